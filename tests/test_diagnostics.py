from __future__ import annotations

from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.model import SourceLocation
from geomcheck.options import Selection
from geomcheck.pipeline import apply_selection


def diag(
    code: str, link: str = "base_link", line: int = 3, about: str = "", sev: Severity = Severity.ERROR
) -> Diagnostic:
    return Diagnostic(
        code=code,
        name="x",
        severity=sev,
        message=f"message at {line}",
        help="h",
        link=link,
        about=about,
        location=SourceLocation("robot.urdf", line),
    )


def test_fingerprint_ignores_location_and_message() -> None:
    assert diag("GC301", line=3).fingerprint == diag("GC301", line=40).fingerprint


def test_fingerprint_separates_rule_subject_and_about() -> None:
    prints = {
        diag("GC301").fingerprint,
        diag("GC302").fingerprint,
        diag("GC301", link="wheel").fingerprint,
        diag("GC301", about="collision[1]").fingerprint,
    }
    assert len(prints) == 4


def test_sort_key_puts_errors_first() -> None:
    items = [diag("GC101", sev=Severity.INFO), diag("GC301"), diag("GC201", sev=Severity.WARNING)]
    assert [d.code for d in sorted(items, key=Diagnostic.sort_key)] == ["GC301", "GC201", "GC101"]


def test_selection_select_ignore_and_per_link() -> None:
    items = [diag("GC101"), diag("GC301"), diag("GC302", link="wheel"), diag("GC501")]
    sel = Selection(select=("GC3", "GC5"), ignore=("GC501",), per_link_ignore={"wheel": ("GC30",)})
    assert [d.code for d in apply_selection(items, sel)] == ["GC301"]


def test_severity_override_longest_selector_wins() -> None:
    sel = Selection(severity={"GC3": Severity.INFO, "GC301": Severity.WARNING})
    out = apply_selection([diag("GC301"), diag("GC302")], sel)
    assert [(d.code, d.severity) for d in out] == [("GC301", Severity.WARNING), ("GC302", Severity.INFO)]
