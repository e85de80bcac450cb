"""The rule registry.

A :class:`Rule` is declared once, with its documentation, in a module of this package named
after its family (``structure`` GC1xx, ``meshes`` GC2xx, ``fit`` GC3xx, ``selfcollision``
GC4xx, ``inertia`` GC5xx); every module here is imported when the registry is read.
Checks create diagnostics through :meth:`Rule.diagnose`. A rule declares the metrics its
findings carry in ``data`` (:class:`~geomcheck.diagnostics.Metric`: unit, which way is
better; ``geomcheck diff`` reads them) and may own its message templates (``messages``,
filled by :meth:`Rule.message`).
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

from geomcheck.diagnostics import Diagnostic, Metric, Severity
from geomcheck.errors import UsageError
from geomcheck.model import SourceLocation

FAMILIES: Mapping[str, str] = {
    "GC1": "structure",
    "GC2": "meshes",
    "GC3": "fit",
    "GC4": "selfcollision",
    "GC5": "inertia",
}
SEVERITY_POLICY = (
    "error: a consumer (urdfdom, xacro, MoveIt, Gazebo, MuJoCo, pinocchio) misbehaves or refuses "
    "the robot, or a file it needs is missing; warning: a maintainer would change it when shown; "
    "info: worth knowing, nothing to change. A finding that a rule's own conditions make harmless "
    "is lowered and says why."
)
"""The policy every rule's severities follow; each rule says in ``severity_reason`` how it applies it."""

FAMILY_TITLES: Mapping[str, str] = {
    "GC1": "Syntax and structure",
    "GC2": "Meshes and files",
    "GC3": "Collision-vs-visual fit",
    "GC4": "Self-collision",
    "GC5": "Inertia and mass",
}


@dataclass(frozen=True)
class Rule:
    """A stable rule: ``code`` (``GC301``), kebab-case ``name`` of the defect, default
    ``severity`` (chosen by :data:`SEVERITY_POLICY`, explained in ``severity_reason``),
    one-line ``summary``, documentation (``what``, ``why``, ``example``) and
    the default ``fix`` used as the diagnostic's ``help``; ``metrics``, every key its findings
    may carry in ``data``; ``messages``, the format strings of its messages by variant (``""``
    for the main one), for the checks to fill with :meth:`message`."""

    code: str
    name: str
    severity: Severity
    summary: str
    what: str
    why: str
    example: str
    fix: str
    metrics: tuple[Metric, ...] = ()
    messages: Mapping[str, str] = field(default_factory=dict, hash=False)
    severity_reason: str = ""
    """How :data:`SEVERITY_POLICY` applies to this rule: why its default severity, and when a
    finding is reported lower."""

    @property
    def family(self) -> str:
        return self.code[:3]

    def metric(self, name: str) -> Metric | None:
        """The declared metric ``name`` of this rule's ``data``, if any (``also``, the
        subjects a grouped finding stands for, belongs to every rule)."""
        return next((m for m in self.metrics if m.name == name), ALSO if name == ALSO.name else None)

    def message(self, variant: str = "", /, **values: Any) -> str:
        """The message template ``variant`` filled with ``values`` (``str.format``)."""
        return self.messages[variant].format(**values)

    def diagnose(
        self,
        message: str,
        *,
        help: str | None = None,
        link: str | None = None,
        joint: str | None = None,
        links: tuple[str, str] | None = None,
        about: str = "",
        location: SourceLocation | None = None,
        data: Mapping[str, Any] | None = None,
        severity: Severity | None = None,
    ) -> Diagnostic:
        """A finding of this rule; ``links`` is stored sorted."""
        pair = tuple(sorted(links)) if links is not None else None
        return Diagnostic(
            code=self.code,
            name=self.name,
            severity=severity or self.severity,
            message=message,
            help=help or self.fix,
            link=link,
            joint=joint,
            links=pair,  # type: ignore[arg-type]
            about=about,
            location=location,
            data=dict(data or {}),
        )


def optional(metrics: tuple[Metric, ...], when: str) -> tuple[Metric, ...]:
    """``metrics`` marked optional, their description saying ``when`` they are present."""
    return tuple(replace(m, optional=True, description=f"{m.description} Only {when}.") for m in metrics)


ALSO = Metric(
    "also",
    "text",
    description="The other links or joints the same source line wrote alike, when a macro wrote it for several.",
    optional=True,
)
"""Every rule's findings may carry it (:mod:`geomcheck.repeats`)."""

_REGISTRY: dict[str, Rule] = {}


def register(rule: Rule) -> Rule:
    """Add ``rule`` to the registry; codes and names are unique."""
    if rule.code in _REGISTRY:
        raise ValueError(f"duplicate rule code {rule.code}")
    if any(r.name == rule.name for r in _REGISTRY.values()):
        raise ValueError(f"duplicate rule name {rule.name}")
    names = [m.name for m in rule.metrics]
    if len(set(names)) != len(names):
        raise ValueError(f"{rule.code} declares a metric twice: {names}")
    _REGISTRY[rule.code] = rule
    return rule


def _load_families() -> None:
    for info in pkgutil.iter_modules(__path__):
        importlib.import_module(f"geomcheck.rules.{info.name}")


def all_rules() -> tuple[Rule, ...]:
    """Every registered rule, sorted by code."""
    _load_families()
    return tuple(_REGISTRY[c] for c in sorted(_REGISTRY))


def get_rule(code_or_name: str) -> Rule:
    """The rule with this code (``GC301``) or name; :class:`UsageError` naming the codes otherwise."""
    _load_families()
    key = code_or_name.strip()
    if key.upper() in _REGISTRY:
        return _REGISTRY[key.upper()]
    for rule in _REGISTRY.values():
        if rule.name == key:
            return rule
    raise UsageError.bad_choice("rule", code_or_name, sorted(_REGISTRY))


def find_rule(code: str) -> Rule | None:
    """The rule with this code, or ``None`` (a code of another version, in a stored report)."""
    _load_families()
    return _REGISTRY.get(code)


def matches(code: str, selector: str) -> bool:
    """Whether ``code`` is selected by ``selector``: a code, a prefix (``GC3``, ``GC30``) or ``ALL``."""
    sel = selector.upper()
    return sel == "ALL" or code.startswith(sel)


def validate_selector(selector: str) -> str:
    """``selector`` upper-cased if it names at least one rule, else a :class:`UsageError`."""
    codes = [r.code for r in all_rules()]
    if not any(matches(c, selector) for c in codes):
        raise UsageError.bad_choice("rule selector", selector, ["ALL", *FAMILIES, *codes])
    return selector.upper()
