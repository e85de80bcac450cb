"""The untrusted CLI mode: confinement as in the service, CPU, memory and wall-clock limits,
one line and exit 2 when a limit or the confinement stops a command."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from geomcheck.cli import main
from geomcheck.untrusted import UntrustedLimits, untrusted_requested

XACRO = '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n  {body}\n</robot>\n'


def write(folder: Path, name: str, body: str) -> Path:
    path = folder / name
    path.write_text(XACRO.format(body=body), encoding="utf-8")
    return path


def run(argv: list[str], capfd: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    status = main(argv)
    out, err = capfd.readouterr()
    return status, out, err


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "repo"
    folder.mkdir()
    monkeypatch.chdir(folder)
    return folder


def test_untrusted_refuses_env_home_with_one_line_and_exit_2(repo: Path, capfd: pytest.CaptureFixture[str]) -> None:
    write(repo, "r.urdf.xacro", '<link name="$(env HOME)"/>')
    status, out, err = run(["check", "--untrusted", "r.urdf.xacro", "--format", "json"], capfd)
    assert status == 2
    assert out == ""
    assert err.count("\n") == 1
    assert err.startswith("geomcheck: error: r.urdf.xacro:3:")
    assert "GC102 xacro-error: $(env HOME) is refused in untrusted descriptions" in err


def test_untrusted_stops_power_tower_at_once(repo: Path, capfd: pytest.CaptureFixture[str]) -> None:
    write(repo, "r.urdf.xacro", '<link name="l${10**10**10}"/>')
    started = time.monotonic()
    status, out, err = run(["check", "--untrusted", "--time-limit", "60", "r.urdf.xacro"], capfd)
    assert out == ""
    elapsed = time.monotonic() - started
    assert status == 2
    assert err.count("\n") == 1
    assert "xacro expression 10**10000000000 is too large" in err
    assert elapsed < UntrustedLimits().wall_s and elapsed < 30


def test_allowed_variable_is_read(
    repo: Path, capfd: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("GC_TEST_LINK", "from_env")
    write(repo, "r.urdf.xacro", '<link name="$(env GC_TEST_LINK)"/>')
    argv = ["check", "--untrusted", "--allow-env", "GC_TEST_LINK", "r.urdf.xacro", "--format", "json"]
    status, out, err = run(argv, capfd)
    assert (status, err) == (0, "")
    assert [entry["link"] for entry in json.loads(out)["sections"]["links"]] == ["from_env"]


def test_untrusted_expands_optenv_as_a_fresh_machine_and_takes_given_values(
    repo: Path, capfd: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """``$(optenv NAME default)`` is the default (the runner's variable is not read), ``$(env
    NAME)`` and ``$(optenv NAME)`` take what ``--env`` gives."""
    monkeypatch.setenv("GC_TEST_LINK", "from_runner")
    write(repo, "r.urdf.xacro", '<link name="$(optenv GC_TEST_LINK default)"/><link name="a$(optenv GC_TEST_NONE)"/>')
    status, out, err = run(["check", "--untrusted", "r.urdf.xacro", "--format", "json"], capfd)
    assert status in (0, 1) and err == ""  # two root links: GC115
    assert [entry["link"] for entry in json.loads(out)["sections"]["links"]] == ["default", "a"]
    write(repo, "r.urdf.xacro", '<link name="$(env GC_TEST_LINK)"/><link name="$(optenv GC_TEST_OTHER x)"/>')
    argv = ["check", "--untrusted", "--env", "GC_TEST_LINK=given", "--env", "GC_TEST_OTHER=y", "r.urdf.xacro"]
    status, out, err = run([*argv, "--format", "json"], capfd)
    assert status in (0, 1) and err == ""  # two root links: GC115
    assert [entry["link"] for entry in json.loads(out)["sections"]["links"]] == ["given", "y"]
    assert json.loads(out)["options"]["env"] == {"GC_TEST_LINK": "given", "GC_TEST_OTHER": "y"}


def test_untrusted_refuses_includes_outside_the_repository(
    repo: Path, tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    write(tmp_path, "outside.xacro", '<link name="outside"/>')
    write(repo, "r.urdf.xacro", f'<xacro:include filename="{tmp_path / "outside.xacro"}"/>')
    status, _, err = run(["check", "--untrusted", "r.urdf.xacro"], capfd)
    assert status == 2
    assert "access outside the uploaded bundle refused" in err
    trusted, out, _ = run(["check", "--no-untrusted", "r.urdf.xacro", "--format", "json"], capfd)
    assert trusted == 0
    assert [entry["link"] for entry in json.loads(out)["sections"]["links"]] == ["outside"]


def test_wall_clock_limit_kills_the_command(repo: Path, capfd: pytest.CaptureFixture[str]) -> None:
    write(repo, "r.urdf.xacro", '<link name="a"/>')
    status, out, err = run(["check", "--untrusted", "--time-limit", "0.05", "r.urdf.xacro"], capfd)
    assert (status, out) == (2, "")
    assert err == "geomcheck: error: wall-clock limit of 0.05 s exceeded (--time-limit)\n"


def test_memory_limit_is_one_line(repo: Path, capfd: pytest.CaptureFixture[str]) -> None:
    write(repo, "r.urdf.xacro", '<link name="a"/>')
    status, out, err = run(["check", "--untrusted", "--memory-limit", "150", "r.urdf.xacro"], capfd)
    assert (status, out) == (2, "")
    assert err.count("\n") == 1
    assert "150 MiB" in err and "--memory-limit" in err


def test_child_does_not_import_modules_from_the_repository(repo: Path, capfd: pytest.CaptureFixture[str]) -> None:
    marker = repo / "imported"
    (repo / "xacro.py").write_text(f"open({str(marker)!r}, 'w').close()\n", encoding="utf-8")
    write(repo, "r.urdf.xacro", '<link name="a${1+1}"/>')
    status, out, err = run(["check", "--untrusted", "r.urdf.xacro", "--format", "concise"], capfd)
    assert (status, err) == (0, "")
    assert "1 link" in out
    assert not marker.exists()


def test_ci_true_makes_untrusted_the_default(
    repo: Path, capfd: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("GEOMCHECK_UNTRUSTED")
    monkeypatch.setenv("CI", "true")
    write(repo, "r.urdf.xacro", '<link name="$(env HOME)"/>')
    status, _, err = run(["check", "r.urdf.xacro"], capfd)
    assert status == 2 and "$(env HOME) is refused" in err
    status, out, err = run(["check", "--no-untrusted", "r.urdf.xacro", "--format", "concise"], capfd)
    assert (status, err) == (0, "")
    assert "1 link" in out


@pytest.mark.parametrize(
    ("flag", "environ", "expected"),
    [
        (None, {}, False),
        (None, {"CI": "true"}, True),
        (None, {"CI": "true", "GEOMCHECK_UNTRUSTED": "0"}, False),
        (None, {"GEOMCHECK_UNTRUSTED": "1"}, True),
        (False, {"CI": "true"}, False),
        (True, {}, True),
    ],
)
def test_untrusted_requested(flag: bool | None, environ: dict[str, str], expected: bool) -> None:
    assert untrusted_requested(flag, environ) is expected


def test_bad_switch_value_is_a_usage_error(
    repo: Path, capfd: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("GEOMCHECK_UNTRUSTED", "maybe")
    write(repo, "r.urdf.xacro", '<link name="a"/>')
    status, _, err = run(["check", "r.urdf.xacro"], capfd)
    assert status == 2
    assert err == "geomcheck: error: invalid GEOMCHECK_UNTRUSTED 'maybe'; valid choices: 1, 0, true, false\n"


def test_the_confined_child_dies_with_a_killed_parent() -> None:
    """The child runs in a session of its own (killed as a group at a limit): a CI job's
    SIGKILL of geomcheck must still end it."""
    script = (
        "import subprocess, sys\n"
        "from geomcheck.untrusted import UntrustedLimits, child_preparation\n"
        "command = [sys.executable, '-c', 'import time; time.sleep(60)']\n"
        "child = subprocess.Popen(command, start_new_session=True, preexec_fn=child_preparation(UntrustedLimits()))\n"
        "print(child.pid, flush=True)\n"
        "child.wait()\n"
    )
    parent = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert parent.stdout is not None
    pid = int(parent.stdout.readline())
    parent.send_signal(signal.SIGKILL)
    parent.wait()
    deadline = time.monotonic() + 10
    state = "?"
    while time.monotonic() < deadline:
        state = subprocess.run(["ps", "-o", "stat=", "-p", str(pid)], capture_output=True, text=True).stdout.strip()
        if not state or state.startswith("Z"):
            break
        time.sleep(0.05)
    assert not state or state.startswith("Z"), f"the child {pid} outlived its parent ({state})"


PASSWD_READER = '<xacro:property name="p" value="${xacro.load_yaml(\'$(find etc)/passwd\')}"/><link name="${p}"/>'


@pytest.mark.parametrize(
    ("config", "key"),
    [
        ('[packages]\netc = "/etc"\n', "packages.etc"),
        ('search = ["/"]\n', "search"),
        ('[packages]\netc = "etc_link"\n', "packages.etc"),  # a link in the repository to /etc
        ('srdf = "/etc/passwd"\n', "srdf"),
        ("[thresholds.limits]\nmax_expression_work = 1000000000000\n", "thresholds.limits.max_expression_work"),
    ],
)
@pytest.mark.parametrize("file_name", ["geomcheck.toml", "pyproject.toml"])
def test_a_repository_configuration_cannot_widen_untrusted_mode(
    repo: Path,
    capfd: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    config: str,
    key: str,
    file_name: str,
) -> None:
    (repo / "etc_link").symlink_to("/etc")
    in_pyproject = "[tool.geomcheck]\n" + re.sub(r"^\[", "[tool.geomcheck.", config, flags=re.M)
    text = config if file_name == "geomcheck.toml" else in_pyproject
    (repo / file_name).write_text(text, encoding="utf-8")
    (repo / "package.xml").write_text("<package><name>r</name></package>", encoding="utf-8")
    write(repo, "r.urdf.xacro", PASSWD_READER)
    monkeypatch.setenv("CI", "true")  # untrusted by default, as a pull request's CI job
    monkeypatch.delenv("GEOMCHECK_UNTRUSTED", raising=False)
    status, out, err = run(["check", "r.urdf.xacro", "--format", "github"], capfd)
    assert status == 2
    assert out == ""
    assert err.count("\n") == 1
    assert f"{file_name}: {key} " in err and "untrusted mode" in err
    assert "root:" not in out + err


def test_the_command_line_still_grants_a_package_in_untrusted_mode(
    repo: Path, tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    shared = tmp_path / "shared"
    shared.mkdir()
    (shared / "part.xacro").write_text(XACRO.format(body='<link name="granted"/>'), encoding="utf-8")
    (repo / "geomcheck.toml").write_text('ignore = ["GC126"]\n', encoding="utf-8")  # narrowing is fine
    write(repo, "r.urdf.xacro", '<xacro:include filename="$(find shared)/part.xacro"/>')
    argv = ["check", "--untrusted", "--package", f"shared={shared}", "r.urdf.xacro", "--format", "json"]
    status, out, err = run(argv, capfd)
    assert (status, err) == (0, "")
    assert [entry["link"] for entry in json.loads(out)["sections"]["links"]] == ["granted"]


def test_a_hard_address_space_limit_below_the_memory_limit_is_honoured(repo: Path) -> None:
    """``ulimit -v`` (hard) under the 4096 MiB default: setrlimit could not raise it in the
    child's preexec_fn, and the command ended with a traceback and exit 1."""
    (repo / "ok.urdf").write_text('<robot name="r"><link name="a"/></robot>\n', encoding="utf-8")
    write(repo, "big.urdf.xacro", "<link name=\"l${len('x' * 60000000 + 'y' * 60000000)}\"/>")
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    env.pop("CI", None)
    script = "ulimit -v 1500000 && {python} -m geomcheck check --untrusted {name} --format concise"
    for name, status, line in (
        ("ok.urdf", 0, "r: 1 link"),
        ("big.urdf.xacro", 2, "geomcheck: error:"),
    ):
        command = script.format(python=sys.executable, name=name)
        done = subprocess.run(["bash", "-c", command], cwd=repo, env=env, capture_output=True, text=True, timeout=120)
        assert done.returncode == status, done.stderr
        assert "Traceback" not in done.stderr
        assert line in done.stdout + done.stderr


def test_untrusted_mjcf_cannot_have_mujoco_read_outside_the_repository(
    repo: Path, tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "outside.stl").write_bytes(b"\0" * 84)
    os.mkfifo(tmp_path / "fifo.stl")  # was: the CLI hung on it until the time limit (900 s)
    attached = '<mujoco><asset><mesh name="m" file="../outside.stl"/></asset><worldbody><body name="p">'
    attached += '<geom type="mesh" mesh="m"/></body></worldbody></mujoco>'
    (repo / "sub.xml").write_text(attached)
    (repo / "attach.xml").write_text(
        '<mujoco><asset><model name="s" file="sub.xml"/></asset><worldbody><body name="b">'
        '<attach model="s" body="p" prefix="s_"/></body></worldbody></mujoco>'
    )
    (repo / "fifo.xml").write_text(
        '<mujoco><compiler meshdir=".."/><worldbody><flexcomp name="f" type="mesh" file="fifo.stl" dim="2"/>'
        "</worldbody></mujoco>"
    )
    started = time.monotonic()
    status, out, err = run(["check", "--untrusted", "attach.xml"], capfd)
    assert (status, out) == (2, "")
    assert err == "geomcheck: error: access outside the uploaded bundle refused: ../outside.stl\n"
    status, out, err = run(["check", "--untrusted", "fifo.xml"], capfd)
    assert (status, out, err) == (2, "", "geomcheck: error: access outside the uploaded bundle refused: ../fifo.stl\n")
    # trusted, the FIFO is in reach, and refused as no regular file: never opened
    status, out, err = run(["check", "--no-untrusted", "fifo.xml"], capfd)
    assert (status, out) == (2, "")
    assert err.endswith("not a regular file: ../fifo.stl\n")
    assert time.monotonic() - started < 60


def test_untrusted_include_patterns_list_no_folder_outside_the_repository(
    repo: Path, tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "secret_name.xacro").write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"/>')
    (repo / "sub").mkdir()
    (repo / "sub" / "out").symlink_to(tmp_path)
    answers = []
    for pattern in (f"{tmp_path}/secret*", f"{tmp_path}/nothing*", "sub/*/secret*", "sub/*/../../secret*"):
        write(repo, "r.urdf.xacro", f'<xacro:include filename="{pattern}"/><link name="a"/>')
        status, _, err = run(["check", "--untrusted", "r.urdf.xacro", "--format", "concise"], capfd)
        answers.append((status, err.strip()))
    # was: '/secret*' refused naming secret_name.xacro, '/nothing*' matched no files: a listing of any folder
    refused = (
        f"geomcheck: error: r.urdf.xacro: GC102 xacro-error: access outside the uploaded bundle refused: {tmp_path}"
    )
    assert answers[0] == answers[1] == (2, refused)
    assert answers[2][0] == 0 and "secret_name" not in answers[2][1]  # the match through the link is left out
    assert answers[3][0] == 2 and "'..' after a wildcard is refused" in answers[3][1]
