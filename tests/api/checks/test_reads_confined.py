"""The service's check of a hostile upload opens no file outside its bundle: every path the
check process touches (strace: every file system call, C libraries' included, MuJoCo's
compiler among them; Python's audit hook: every ``open``) is in the upload, or is the
interpreter's and the libraries' own code, for MJCF, SDFormat and URDF uploads naming files
outside in every way they can."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(REPO / "tests" / "load"))

from test_mjcf_assets import OUTSIDE_PLACES, everything, put, stl  # noqa: E402

STRACE = shutil.which("strace")
MARK = "/geomcheck-trace-start"  # a path the harness stats once the library is imported and warm
# calls that read a path's metadata, not its contents: resolving a path an upload wrote (to
# refuse it when it leads outside) looks at each of its folders, whatever it names
CASE = "/geomcheck-trace-case"  # stat before each case: its upload folder follows
METADATA_CALLS = frozenset(
    {
        "stat",
        "lstat",
        "newfstatat",
        "statx",
        "readlink",
        "readlinkat",
        "access",
        "faccessat",
        "faccessat2",
        "getcwd",
        "chdir",
    }
)

HARNESS = textwrap.dedent(
    """
    import json, os, sys
    from pathlib import Path
    audited = []
    cases = json.loads(sys.argv[1])
    from api.checks.job import CheckJob, run_job
    from geomcheck.config import Config
    import geomcheck.load.loader, geomcheck.load.mjcf, geomcheck.load.sdf, mujoco  # noqa: F401
    def hook(event, args):
        if event == "open" and isinstance(args[0], (str, bytes)):
            audited.append(os.path.abspath(os.fsdecode(args[0])))
    sys.addaudithook(hook)
    os.path.exists({mark!r})
    outcomes = {{}}
    for name, (root, upload) in cases.items():
        os.path.exists({case!r} + upload)
        os.chdir(upload)  # as the sandbox does: the check's folder is the working folder
        job = CheckJob(name, Path(root), Path(upload), Path(upload), Config())
        try:
            result = run_job(job)
            outcomes[name] = "ok " + result.verdict
        except Exception as err:
            outcomes[name] = type(err).__name__ + ": " + str(err)
    os.path.exists({mark!r})
    print(json.dumps({{"outcomes": outcomes, "audited": audited}}))
    """
).format(mark=MARK, case=CASE)

SDF = """<sdf version="1.7"><model name="robot">
  <include><uri>{include}</uri></include>
  <link name="base"><collision name="c"><geometry><mesh><uri>{mesh}</uri></mesh></geometry></collision>
    <visual name="v"><geometry><box><size>0.1 0.1 0.1</size></box></geometry></visual></link>
</model></sdf>
"""
URDF = """<robot name="r"><link name="base">
  <collision><geometry><mesh filename="{a}"/></geometry></collision>
  <collision><geometry><mesh filename="{b}"/></geometry></collision>
  <collision><geometry><mesh filename="{c}"/></geometry></collision>
  <visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link></robot>
"""
XACRO = '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:include filename="{0}"/></robot>'


def cases(server: Path) -> dict[str, tuple[str, str]]:
    """Uploads (folders of ``server``) naming files of ``server`` outside them every way each
    format can, and a sound one naming a file in every place MuJoCo reads one."""
    found: dict[str, tuple[str, str]] = {}

    def upload(name: str, root: Path) -> None:
        found[name] = (str(root), str(root.parent))

    upload("mjcf sound", everything(server / "mjcf_sound"))
    for place, files in OUTSIDE_PLACES.items():
        folder = server / ("mjcf " + place).replace(" ", "_")
        for name, text in files.items():
            put(folder / name, text.replace("/etc/", f"{server}/"))
        (folder / "link.stl").symlink_to(server / "outside.stl")
        upload("mjcf " + place, folder / "robot.xml")
    sdf = server / "sdf" / "model.sdf"
    put(sdf.parent / "box.stl", stl())
    put(sdf, SDF.format(include=f"file://{server}/secret_model", mesh=f"file://{server}/outside.stl"))
    upload("sdf include outside", sdf)
    sdf_mesh = server / "sdf_mesh" / "model.sdf"
    text = SDF.format(include="", mesh="../outside.stl").replace("  <include><uri></uri></include>\n", "")
    put(sdf_mesh, text)
    upload("sdf mesh outside", sdf_mesh)
    urdf = server / "urdf" / "robot.urdf"
    put(urdf, URDF.format(a=f"{server}/outside.stl", b=f"file://{server}/outside.stl", c="link.stl"))
    (urdf.parent / "link.stl").symlink_to(server / "outside.stl")
    upload("urdf meshes outside", urdf)
    xacro = server / "xacro" / "robot.urdf.xacro"
    put(xacro, XACRO.format(f"{server}/secret.xacro"))
    upload("xacro include outside", xacro)
    return found


@pytest.mark.skipif(STRACE is None, reason="strace is not installed")
def test_a_hostile_uploads_check_opens_nothing_outside_its_bundle(tmp_path: Path) -> None:
    server = tmp_path / "server"  # the uploads' folders and the files beside them no upload may read
    put(server / "outside.stl", stl())
    put(server / "outside.xml", "<mujoco/>")
    put(server / "secret.xacro", '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="x"/></robot>')
    put(server / "secret_model" / "model.sdf", '<sdf version="1.7"><model name="s"><link name="l"/></model></sdf>')
    put(server / "hostname", "server\n")
    put(server / "passwd", "root:x:0:0\n")
    found = cases(server)
    log = tmp_path / "strace.log"
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    env.pop("GEOMCHECK_CACHE_DIR", None)  # the service's checks have no cache unless configured
    command = [STRACE, "-f", "-qq", "-e", "trace=%file", "-o", str(log), sys.executable, "-c", HARNESS]
    done = subprocess.run([*command, json.dumps(found)], capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    result = json.loads(done.stdout.splitlines()[-1])
    outcomes = result["outcomes"]
    assert outcomes["mjcf sound"] == "ok fail", outcomes  # checked whole (its meshes are tetrahedra)
    for place in OUTSIDE_PLACES:
        assert outcomes["mjcf " + place].startswith("SandboxViolation: access outside the uploaded bundle"), outcomes
    assert outcomes["sdf include outside"].startswith("SandboxViolation"), outcomes
    assert outcomes["sdf mesh outside"].startswith("ok"), outcomes  # a mesh outside is a finding (GC201)
    assert outcomes["urdf meshes outside"].startswith("ok"), outcomes
    assert outcomes["xacro include outside"].startswith("SandboxViolation"), outcomes

    traced = log.read_text(errors="replace").splitlines()
    marks = [n for n, line in enumerate(traced) if MARK in line]
    assert len(marks) == 2, "the harness's marks are missing from the trace"
    looked: set[str] = set()  # paths whose metadata was read (resolving a path the upload wrote does)
    opened: dict[str, set[str]] = {}  # upload folder -> paths its check opened, executed or changed
    upload = ""
    for line in traced[marks[0] : marks[1]]:
        call = re.match(r'\d+\s+(\w+)\((?:AT_FDCWD, )?"((?:[^"\\]|\\.)*)"', line)
        if call is None:
            continue
        name, path = call.groups()
        if path.startswith(CASE):
            upload = path[len(CASE) :]
            continue
        path = os.path.normpath(os.path.join(upload or str(server), path))  # relative: the upload is the cwd
        (looked if name in METADATA_CALLS else opened.setdefault(upload, set())).add(path)
    assert set(opened) >= {folder for _, folder in found.values()}
    for folder, paths in opened.items():
        strangers = {p for p in paths if p.startswith(str(server)) and not (p + os.sep).startswith(folder + os.sep)}
        assert strangers == set(), f"the check of {folder} opened files outside it"
    everything_opened = set().union(*opened.values())
    assert not {p for p in looked | everything_opened if p.startswith("/proc/geomcheck-vfs")}, "MuJoCo looked on disk"
    allowed = (
        str(server),
        *{sys.prefix, sys.base_prefix, sys.exec_prefix},
        str(REPO / "geomcheck"),
        str(REPO / "api"),
        "/proc/",
        "/sys/",
        "/dev/",
        "/usr/",
        "/lib",
        "/etc/ld.so",
        "/etc/localtime",
    )
    assert sorted(p for p in everything_opened if not p.startswith(allowed)) == []
    # what Python opened: the same files (the audit hook sees no C library, hence strace above)
    audited = {os.path.normpath(p) for p in result["audited"]}
    sound = server / "mjcf_sound"
    assert {p for p in audited if p.startswith(str(server))} <= {p for p in everything_opened}
    assert {p for p in audited if p.startswith(str(sound))} >= {
        str(sound / "robot.xml"),
        str(sound / "hand" / "hand.xml"),
        str(sound / "hand" / "hand_meshes" / "palm.stl"),
        str(sound / "assets" / "grid.png"),
        str(sound / "meshes" / "cloth.stl"),
    }
