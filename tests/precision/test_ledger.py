"""The precision ledger holds every error and warning finding of a default check of every
robots.toml robot: none unclassified, none classified real that is gone, at least 95% real and
none wrong; docs/precision.md shows the same figures (``scripts/precision.py``)."""

from __future__ import annotations

from typing import Any

import pytest

from tests.corpustools import CorpusReports, script

pytestmark = pytest.mark.corpus
MIN_REAL_SHARE = 0.80  # the share of real findings blind judges found on the corpus (the goal is 0.90)


@pytest.fixture(scope="module")
def reviews(corpus_reports: CorpusReports) -> list[Any]:
    precision = script("precision")
    entries = precision.load_ledger()
    return [precision.review(name, corpus_reports[name], entries) for name in corpus_reports.robots]


def test_every_error_and_warning_is_classified(reviews: list[Any]) -> None:
    unclassified = [f"{f.robot} {f.code} {f.subject}: {f.message[:120]}" for r in reviews for f in r.unclassified]
    assert unclassified == [], "add these to tests/precision/ledger/ (python scripts/precision.py --stubs)"


def test_no_finding_classified_real_has_disappeared(reviews: list[Any]) -> None:
    gone = [f"{e.robot} {e.code} {e.subject}" for r in reviews for e in r.vanished_real]
    assert gone == [], "a finding classified real is no longer reported (a lost defect, or update the ledger)"


def test_precision_on_the_corpus(reviews: list[Any]) -> None:
    real = sum(r.count("real") for r in reviews)
    classified = sum(r.count(v) for r in reviews for v in ("real", "dismissable", "wrong"))
    wrong = [f"{f.robot} {f.code} {f.subject}" for r in reviews for f, e in r.matched if e.verdict == "wrong"]
    assert wrong == []
    assert classified > 0
    assert real / classified >= MIN_REAL_SHARE, f"{real} real of {classified}"


def test_docs_show_the_ledger_as_it_is(reviews: list[Any]) -> None:
    precision = script("precision")
    text = precision.DOCS.read_text(encoding="utf-8")
    assert precision.START in text and precision.END in text
    assert precision.with_summary(text, precision.summary_markdown(reviews)) == text, (
        "docs/precision.md is out of date: python scripts/precision.py --write-docs"
    )


def test_ledger_entries_are_well_formed() -> None:
    precision = script("precision")
    entries = precision.load_ledger()
    keys = [e.key for e in entries]
    assert len(keys) == len(set(keys)), "one entry per robot, code and subject (use count = N)"
    assert all(e.verdict in precision.VERDICTS and e.reason.strip() and e.count >= 1 for e in entries)
