"""Progress: a check's stage and fraction, heard by a listener (the CLI's bar on a terminal,
the service's check status)."""

from __future__ import annotations

import os
import pty
import subprocess
import sys
from pathlib import Path

import pytest

from geomcheck import progress
from geomcheck.checks import DRAWING_FAMILIES, FAMILY_MODULES
from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from tests.packagetools import MESH_PACKAGE_ROOT, mesh_package, write_package

STAGES = len(FAMILY_MODULES) + 1  # loading, then each rule family in turn
LAST = FAMILY_MODULES[-1]
# an output that shows no drawing (the terminal's, a CI format's) runs no drawing family
UNDRAWN = tuple(name for name in FAMILY_MODULES if name not in DRAWING_FAMILIES)
TEXT_STAGES, TEXT_LAST = len(UNDRAWN) + 1, UNDRAWN[-1]

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "examples" / "pr2_base" / "robots" / "pr2_base.urdf.xacro"


def test_a_check_reports_its_stages_in_order_and_its_fraction_grows() -> None:
    heard: list[progress.StageProgress] = []
    with progress.listening(heard.append):
        run_check(make_bundle(EXAMPLE), CheckOptions())
    names = list(dict.fromkeys(p.name for p in heard))
    assert names[:5] == ["loading", "structure", "meshes", "fit", "inertia"]
    assert "selfcollision" in names
    assert {p.count for p in heard} == {len(names)}
    overall = [p.overall for p in heard]
    assert overall == sorted(overall) and overall[0] == 0.0 and 0.85 < overall[-1] <= 1.0
    # the continuous-joint sweep counts its joints within its stage
    sweep = [p.fraction for p in heard if p.name == "selfcollision"]
    assert sweep[0] == 0.0 and sweep[-1] == 1.0 and len(sweep) > 2
    assert heard[0].to_dict() == {
        "stage": "loading",
        "stage_index": 0,
        "stages": len(names),
        "stage_fraction": 0.0,
        "fraction": 0.0,
    }


def test_without_a_listener_nothing_is_heard() -> None:
    with progress.Progress(10) as bar:
        assert not bar.enabled
        bar.advance()


def on_a_terminal(*args: str) -> tuple[int, str]:
    """``geomcheck ARGS`` with its stderr on a pseudo-terminal: its exit status and what it drew."""
    leader, follower = pty.openpty()
    command = [sys.executable, "-m", "geomcheck", *args]
    process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=follower)
    os.close(follower)
    seen = b""
    while True:
        try:
            chunk = os.read(leader, 4096)
        except OSError:  # the child closed the terminal
            break
        if not chunk:
            break
        seen += chunk
    status = process.wait(timeout=300)
    os.close(leader)
    return status, seen.decode(errors="replace")


def test_the_cli_draws_one_bar_on_a_terminal_also_with_an_output_file(tmp_path: Path) -> None:
    out = tmp_path / "report.json"
    status, text = on_a_terminal("check", str(EXAMPLE), "--format", "json", "-o", str(out))
    assert status == 1
    assert f"geomcheck [1/{STAGES}] loading" in text and f"geomcheck [4/{STAGES}] fit" in text
    assert f"[{STAGES}/{STAGES}] {LAST}" in text
    assert text.endswith("\r\x1b[2K")  # cleared: nothing left in the scrollback
    assert out.stat().st_size > 1000


def test_fix_draws_the_bar_through_its_check_its_verification_rounds_and_the_check_after(tmp_path: Path) -> None:
    root = write_package(tmp_path / "boxed", mesh_package()) / MESH_PACKAGE_ROOT  # two fixes, a swept wheel
    out = tmp_path / "after.txt"
    status, text = on_a_terminal("fix", str(root), "--unsafe-fixes", "-o", str(out))
    assert status in (0, 1)
    drawn = [line for line in text.split("\r\x1b[2K") if line]
    fixed = [i for i, line in enumerate(drawn) if line.startswith("geomcheck: fixed ")]
    assert len(fixed) == 1, drawn  # the outcome line on a line of its own, the bar erased before it
    before, after = drawn[: fixed[0]], drawn[fixed[0] + 1 :]
    assert before[0].startswith(f"geomcheck [1/{TEXT_STAGES}] loading")  # the check whose findings are fixed
    rounds = [line for line in before if line.startswith("geomcheck [1/1] verifying fixes")]
    assert rounds  # the verification rounds: one stage, whose fraction only grows
    percents = [int(line.rstrip("%").rsplit(maxsplit=1)[-1]) for line in rounds]
    assert percents == sorted(percents)
    assert after[0].startswith(f"geomcheck [1/{TEXT_STAGES}] loading")
    assert after[-1].startswith(f"geomcheck [{TEXT_STAGES}/{TEXT_STAGES}] {TEXT_LAST}")
    assert text.endswith("\r\x1b[2K")
    assert "wheel_joint" in out.read_text(encoding="utf-8")  # the report of the fixed files, in -o


def test_in_a_log_a_long_command_writes_its_stages(tmp_path: Path) -> None:
    """``geomcheck fix`` in a pipe (a CI log) with the lines due at once: one line per stage of
    its check, of its verification and of the check after, no bar."""
    root = write_package(tmp_path / "boxed", mesh_package()) / MESH_PACKAGE_ROOT
    command = [sys.executable, "-m", "geomcheck", "fix", str(root), "--unsafe-fixes", "-o", str(tmp_path / "r.txt")]
    env = {**os.environ, "GEOMCHECK_PROGRESS_AFTER_S": "0"}
    done = subprocess.run(command, capture_output=True, timeout=300, env=env)
    lines = done.stderr.decode().splitlines()
    stages = [line.split(" (")[0] for line in lines if line.startswith("geomcheck: [")]
    assert stages[:2] == [f"geomcheck: [1/{TEXT_STAGES}] loading", f"geomcheck: [2/{TEXT_STAGES}] structure"]
    assert (
        "geomcheck: [1/1] verifying fixes" in stages
        and stages[-1] == f"geomcheck: [{TEXT_STAGES}/{TEXT_STAGES}] {TEXT_LAST}"
    )
    assert "\r" not in done.stderr.decode() and "\x1b" not in done.stderr.decode()
    quiet = subprocess.run([*command, "--quiet"], capture_output=True, timeout=300, env=env)
    assert not [line for line in quiet.stderr.decode().splitlines() if line.startswith("geomcheck: [")]


def test_in_a_pipe_the_cli_draws_nothing(tmp_path: Path) -> None:
    command = [
        sys.executable,
        "-m",
        "geomcheck",
        "check",
        str(EXAMPLE),
        "--format",
        "json",
        "-o",
        str(tmp_path / "r.json"),
    ]
    done = subprocess.run(command, capture_output=True, timeout=120)
    assert done.returncode == 1 and done.stderr == b""


def test_in_a_log_each_stage_is_one_line_once_the_run_takes_long() -> None:
    """On a non-terminal stderr (a CI log) a long run writes one line per stage, no bar."""
    import io
    import time

    log = io.StringIO()
    lines = progress.StageLines(log, after_s=0.0)
    with progress.listening(lines):
        run_check(make_bundle(EXAMPLE), CheckOptions())
    lines.close()
    written = log.getvalue().splitlines()
    assert [line.split(" (")[0] for line in written[:4]] == [
        f"geomcheck: [1/{STAGES}] loading",
        f"geomcheck: [2/{STAGES}] structure",
        f"geomcheck: [3/{STAGES}] meshes",
        f"geomcheck: [4/{STAGES}] fit",
    ]
    assert len(written) == STAGES and written[-1].startswith(f"geomcheck: [{STAGES}/{STAGES}] {LAST} (")
    seconds = [float(line.rsplit("(", 1)[1].removesuffix(" s)")) for line in written]
    assert seconds == sorted(seconds)
    assert "\r" not in log.getvalue() and "\x1b" not in log.getvalue()
    # a quick run writes nothing; a stage still running when the run gets long gets its line then
    quiet = io.StringIO()
    late = progress.StageLines(quiet, after_s=0.3)
    late(progress.StageProgress("selfcollision", 5, 8))
    assert quiet.getvalue() == ""
    time.sleep(0.6)
    late(progress.StageProgress("selfcollision", 5, 8, 0.5))  # the same stage again: no second line
    late.close()
    assert quiet.getvalue().startswith("geomcheck: [6/8] selfcollision (0.")
    assert quiet.getvalue().count("\n") == 1


def test_the_cli_writes_stage_lines_in_a_log_and_nothing_with_quiet(monkeypatch: pytest.MonkeyPatch) -> None:
    from geomcheck.cli import build_parser, progress_bar
    from geomcheck.errors import UsageError

    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)
    monkeypatch.delenv(progress.LINES_AFTER_ENV)
    lines = progress_bar(build_parser().parse_args(["check", "r.urdf"]))
    assert isinstance(lines, progress.StageLines) and lines.after_s == progress.LINES_AFTER_S == 5.0
    monkeypatch.setenv(progress.LINES_AFTER_ENV, "0.5")
    lines = progress_bar(build_parser().parse_args(["check", "r.urdf"]))
    assert isinstance(lines, progress.StageLines) and lines.after_s == 0.5
    monkeypatch.setenv(progress.LINES_AFTER_ENV, "soon")
    with pytest.raises(UsageError, match="GEOMCHECK_PROGRESS_AFTER_S must be a number of seconds, got 'soon'"):
        progress_bar(build_parser().parse_args(["check", "r.urdf"]))
    monkeypatch.delenv(progress.LINES_AFTER_ENV)
    for command in (["check", "r.urdf"], ["diff", "a", "b"], ["fix", "r.urdf"], ["matrix", "r.urdf"]):
        lines = progress_bar(build_parser().parse_args(command))
        assert isinstance(lines, progress.StageLines), command
        lines.close()
        assert progress_bar(build_parser().parse_args([*command, "--quiet"])) is None
    assert progress_bar(build_parser().parse_args(["rules"])) is None


def test_fix_verification_rounds_only_move_their_stage_forward() -> None:
    """Each round of fix verification checks the description again: its stages count as the
    round's part of the one stage, 0-50%, 50-75%..., never as a stage list starting over."""
    heard: list[progress.StageProgress] = []
    with progress.listening(heard.append):
        progress.stage("verifying fixes", 0, 1)
        for round_number in (1, 2, 3):
            with progress.nested(1 - 0.5 ** (round_number - 1), 1 - 0.5**round_number):
                run_check(make_bundle(EXAMPLE), CheckOptions(sweep=False))
    assert {(p.name, p.index, p.count) for p in heard} == {("verifying fixes", 0, 1)}
    fractions = [p.fraction for p in heard]
    assert fractions == sorted(fractions) and fractions[0] == 0.0 and fractions[-1] == 0.875
    with progress.listening(heard.append), progress.phase("fixes"):
        progress.stage("verifying safe fixes", 0, 2)
    assert heard[-1].to_dict()["phase"] == "fixes" and "phase" not in heard[0].to_dict()
