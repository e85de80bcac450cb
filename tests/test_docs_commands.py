"""Every geomcheck command the README and the docs show in a code block parses as the CLI
reads it (flags, choices, sub-commands), and the pre-commit and install examples work when
copied: a user copies them as they are."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
import yaml

from geomcheck.cli import build_parser

REPO = Path(__file__).resolve().parents[1]
PAGES = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
FENCE = re.compile(r"```[a-z]*\n(.*?)```", re.S)
COMMAND = re.compile(r"(?:^|[\s|;&(])(geomcheck (?:check|fix|diff|render|matrix|rules|rule|serve|worker)\b[^\n#|]*)")


def shown_commands() -> list[tuple[str, str]]:
    """(page, command) for every geomcheck command in a code block, shell variables and
    GitHub expressions replaced by a word, redirections and trailing `|| ...` dropped."""
    out = []
    for page in PAGES:
        for block in FENCE.findall(page.read_text(encoding="utf-8")):
            block = block.replace("\\\n", " ")
            for match in COMMAND.finditer(block):
                text = re.sub(r"\$\{\{[^}]*\}\}|\"?\$\{?[A-Za-z_][A-Za-z_0-9]*\}?\"?", "VALUE", match.group(1))
                text = re.split(r"\s(?:\|\||&&|>|2>|&$)", text)[0].strip()
                out.append((page.name, text))
    return out


COMMANDS = shown_commands()


def test_the_docs_show_commands() -> None:
    assert len(COMMANDS) >= 20
    assert {c.split()[1] for _, c in COMMANDS} >= {"check", "diff", "fix", "matrix", "serve", "render"}


@pytest.mark.parametrize(("page", "command"), COMMANDS, ids=[f"{p}:{c[:60]}" for p, c in COMMANDS])
def test_a_documented_command_parses(page: str, command: str) -> None:
    argv = shlex.split(command)[1:]
    try:
        build_parser().parse_args(argv)
    except SystemExit as exit:
        pytest.fail(f"{page}: `{command}` does not parse (exit {exit.code})")


def test_no_page_installs_geomcheck_from_an_index_it_is_not_on() -> None:
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        assert not re.search(r"pip install (-q )?geomcheck\b(?![ \"]*@)", text), page.name


def test_the_pre_commit_example_keeps_the_hooks_format() -> None:
    hooks = {h["id"]: h for h in yaml.safe_load((REPO / ".pre-commit-hooks.yaml").read_text(encoding="utf-8"))}
    text = (REPO / "docs" / "ci.md").read_text(encoding="utf-8")
    (config,) = [b for b in FENCE.findall(text) if "repos:" in b and "geomcheck-diff" in b]
    for hook in yaml.safe_load(config)["repos"][0]["hooks"]:
        if "args" in hook:  # args replace the hook's own: its format must be given again
            assert hook["args"][: len(hooks[hook["id"]]["args"])] == hooks[hook["id"]]["args"], hook["id"]


ZIPPED = re.compile(r"\(?cd (\S+) && zip -qr (\S+\.zip) ([^\s)]+)")
POSTED = re.compile(r"root=([^\s&'\"]+)[^\n]*\\?\n?[^\n]*--data-binary @(\S+\.zip)")


def test_the_documented_archives_hold_the_root_they_are_posted_with() -> None:
    """README and docs/api.md zip the example into the same archive name: in one layout, so
    that following one after the other still posts a root the archive holds (they once zipped
    the folder and its contents into one file, and the API doc's example got a 400)."""
    layouts: dict[str, set[str]] = {}
    for page in PAGES:
        for block in FENCE.findall(page.read_text(encoding="utf-8")):
            for folder, archive, what in ZIPPED.findall(block):
                if not (REPO / folder).is_dir():  # the shared corpus, outside the repository
                    continue
                start = REPO / folder / what
                entries = {p.relative_to(REPO / folder).as_posix() for p in start.rglob("*") if p.is_file()}
                assert layouts.setdefault(archive, entries) == entries, f"{page.name}: {archive} zipped otherwise"
    assert "/tmp/pr2_base.zip" in layouts
    posted = 0
    for page in PAGES:
        for block in FENCE.findall(page.read_text(encoding="utf-8")):
            for root, archive in POSTED.findall(block.replace("\\\n", " ")):
                if archive in layouts:
                    held = {p.removeprefix("./") for p in layouts[archive]}
                    assert root in held, f"{page.name}: {root} not in {archive}"
                    posted += 1
    assert posted >= 3


def test_the_first_line_and_the_help_name_every_format() -> None:
    first = (REPO / "README.md").read_text(encoding="utf-8").splitlines()[2]
    assert first.endswith("(URDF and xacro, MJCF, SDFormat).")
    assert build_parser().description.endswith("URDF and xacro, MJCF, SDFormat.")


def test_ci_doc_places_the_diff_where_the_report_has_it() -> None:
    from geomcheck.diff import diff_report
    from geomcheck.report.model import Report, RobotSummary

    head = Report(RobotSummary("r", "r.urdf", 1, 0), (), tool_version="0", created="2024-01-01T00:00:00Z")
    report = diff_report((), head, "HEAD").to_dict()
    assert "diff" in report["sections"] and "diff" not in report
    text = (REPO / "docs" / "ci.md").read_text(encoding="utf-8")
    assert "`sections.diff`" in text and "has a `diff` section" not in text
