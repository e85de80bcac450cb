"""scripts/precision.py matches findings with ledger entries by robot, code and subject."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.corpustools import script


def finding(code: str, severity: str, **subject: object) -> dict[str, object]:
    return {"code": code, "severity": severity, "message": f"{code} message", **subject}


DOCUMENT = {
    "diagnostics": [
        finding("GC301", "warning", link="arm", about="collision[0]"),
        finding("GC301", "warning", link="arm", about="collision[0]"),
        finding("GC403", "error", links=["a", "b"]),
        finding("GC124", "info", link="base"),
        finding("GC113", "warning", joint="world_joint"),
        finding("GC505", "warning", link="l_wheel", data={"also": ["r_wheel"]}),
    ]
}


def test_entries_answer_for_their_count_and_the_rest_is_unclassified() -> None:
    precision = script("precision")
    entries = [
        precision.Entry("r", "GC301", "arm collision[0]", "real", "box too short", count=2),
        precision.Entry("r", "GC403", "a, b", "dismissable", "designed overlap"),
        precision.Entry("r", "GC505", "hand", "real", "gone"),
        precision.Entry("other", "GC113", "world_joint", "real", "another robot"),
        precision.Entry("r", "GC505", "l_wheel", "real", "copied tensor"),
        precision.Entry("r", "GC505", "r_wheel", "real", "the same macro line"),
    ]
    result = precision.review("r", DOCUMENT, entries)
    assert [f.subject for f in result.findings] == [
        "arm collision[0]",
        "arm collision[0]",
        "a, b",
        "world_joint",
        "l_wheel",
    ]
    assert (result.count("real"), result.count("dismissable"), result.count("wrong")) == (3, 1, 0)
    assert [(f.code, f.subject) for f in result.unclassified] == [("GC113", "world_joint")]
    assert [e.subject for e in result.vanished_real] == ["hand"]  # r_wheel's is answered by l_wheel's
    assert (result.severity("error"), result.severity("warning")) == (1, 4)


def test_the_ledger_refuses_an_unknown_verdict(tmp_path: Path) -> None:
    precision = script("precision")
    (tmp_path / "GC1.toml").write_text(
        '[[finding]]\nrobot = "r"\ncode = "GC101"\nsubject = "-"\nverdict = "maybe"\nreason = "x"\n', encoding="utf-8"
    )
    with pytest.raises(ValueError, match="verdict 'maybe'"):
        precision.load_ledger(tmp_path)


def test_the_summary_replaces_only_the_part_between_the_markers() -> None:
    precision = script("precision")
    result = precision.review("r", DOCUMENT, [precision.Entry("r", "GC403", "a, b", "real", "collides")])
    summary = precision.summary_markdown([result])
    assert "| r | 1 | 4 | 1 | 0 | 0 | 4 |" in summary
    assert "Real: **100.0%** of 1 classified findings." in summary
    text = f"intro\n{precision.START}\nold\n{precision.END}\noutro\n"
    assert precision.with_summary(text, summary) == f"intro\n{summary}\noutro\n"
