"""Helpers of the service tests: small descriptions, archives made in memory, posting them.

It imports nothing of ``tests.``: the service's check processes import it by name (the
``check_slowly``-style targets) with only its folder on their path."""

from __future__ import annotations

import copy
import io
import secrets
import tarfile
import time
import zipfile
from pathlib import Path
from typing import Any

from fastapi.testclient import TestClient

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "pr2_base"
EXAMPLE_ROOT = "robots/pr2_base.urdf.xacro"

TWO_LINKS = b"""<?xml version="1.0"?>
<robot name="two_links">
  <link name="base_link">
    <inertial><mass value="1.0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="arm"/><origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""

XACRO = b'<robot name="evil" xmlns:xacro="http://www.ros.org/wiki/xacro">%s</robot>'
# every level calls the next one twice: 2^40 expansions, none of them producing output
EXPONENTIAL = XACRO % (
    b"".join(b'<xacro:macro name="m%d"><xacro:m%d/><xacro:m%d/></xacro:macro>' % (i, i + 1, i + 1) for i in range(40))
    + b'<xacro:macro name="m40"><xacro:property name="p" value="1"/></xacro:macro><xacro:m0/><link name="a"/>'
)


def zip_bytes(files: dict[str, bytes], compression: int = zipfile.ZIP_DEFLATED) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression) as archive:
        for name, data in files.items():
            archive.writestr(name, data)
    return buf.getvalue()


def zip_folder(folder: Path, prefix: str = "") -> bytes:
    """``folder``'s files zipped, each named ``prefix`` + its path in the folder."""
    paths = sorted(p for p in folder.rglob("*") if p.is_file())
    return zip_bytes({prefix + p.relative_to(folder).as_posix(): p.read_bytes() for p in paths})


def tar_gz_bytes(members: list[tuple[tarfile.TarInfo, bytes | None]]) -> bytes:
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w:gz") as archive:
        for info, data in members:
            if data is not None:
                info.size = len(data)
            archive.addfile(info, io.BytesIO(data) if data is not None else None)
    return buf.getvalue()


def post_xml(client: TestClient, body: bytes, **params: Any) -> Any:
    return client.post("/v1/checks", content=body, headers={"content-type": "application/xml"}, params=params)


def post_zip(client: TestClient, body: bytes, **params: Any) -> Any:
    return client.post("/v1/checks", content=body, headers={"content-type": "application/zip"}, params=params)


def unique_prefix() -> str:
    """A table prefix no other test run uses."""
    return f"t{secrets.token_hex(4)}_"


def burn_cpu(job: object) -> None:
    """A check process target that computes until its CPU-time limit stops it."""
    sum(range(10**13))


def sleep_long(job: object) -> None:
    """A check process target that waits until its wall-clock limit stops it."""
    time.sleep(3600)


def check_slowly(job: Any) -> Any:
    """A check process target that waits two seconds, then checks as the service does."""
    from api.checks.job import run_job

    time.sleep(2.0)
    return run_job(job)


def report_then_hang(job: Any) -> Any:
    """A check process target that checks as the service does, hands over its report, and then
    verifies its fixes for ever (until its wall-clock limit stops it)."""
    import api.checks.job

    api.checks.job.verified_fixes = lambda *args: time.sleep(3600)  # type: ignore[assignment]
    return api.checks.job.run_job(job)


def assert_same_report(service: dict[str, Any], cli: dict[str, Any]) -> None:
    assert service["robot"] == cli["robot"]
    service, cli = copy.deepcopy(service), copy.deepcopy(cli)
    # how to make a package known: the upload's folder for the service, flags for the CLI
    for ours, theirs in zip(service["diagnostics"], cli["diagnostics"], strict=False):
        if ours["code"] == theirs["code"] == "GC202":
            assert ours.pop("help").startswith("Add the package to the upload")
            assert theirs.pop("help").startswith("Pass --package")
    assert service["diagnostics"] == cli["diagnostics"]
    assert service["skipped"] == cli["skipped"]
    # the fixes the service offers are verified (as `geomcheck fix` verifies them), the CLI
    # report's are planned: the same fixes, and patches that may differ
    offered, planned = service["sections"].pop("fixes", None), cli["sections"].pop("fixes", None)
    assert (offered is None) == (planned is None)
    if offered is not None and offered["verified"] is False:  # the report, answered before the verification
        assert {k: v for k, v in offered.items() if k != "verified"} == planned
    elif offered is not None:
        assert offered["verified"] is True
        assert [f["fingerprint"] for f in offered["fixes"]] == [f["fingerprint"] for f in planned["fixes"]]
        # a fix verification refitted (boxes clear of other links) is offered as applied, its
        # title saying why; every other offered fix is the planned one
        for mine, theirs in zip(offered["fixes"], planned["fixes"], strict=True):
            assert mine == theirs or mine["fingerprint"] in offered["applied"], (mine, theirs)
    assert service == cli  # options, the other sections, summary, verdict: the whole document


def verified_check(client: Any, check_id: str, timeout_s: float = 300.0) -> dict[str, Any]:
    """The check once the verification of its fixes ended (``GET /v1/checks/{id}``, polled)."""
    deadline = time.monotonic() + timeout_s
    while True:
        body: dict[str, Any] = client.get(f"/v1/checks/{check_id}").json()
        if (body.get("fixes") or {}).get("status") != "verifying" or time.monotonic() > deadline:
            return body
        time.sleep(0.1)


def long_chain(joints: int) -> bytes:
    """A chain of ``joints`` continuous joints, each link a cylinder folding back near the
    others: its continuous-joint sweeps (the ``selfcollision`` stage) take seconds per joint
    on a busy machine, a real slow input whose progress can be watched."""
    inertia = '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>'
    inertial = f'<inertial><mass value="1"/>{inertia}</inertial>'
    shape = '<geometry><cylinder radius="0.03" length="0.1"/></geometry>'
    links = [
        f'<link name="l{i}">{inertial}<visual>{shape}</visual><collision>{shape}</collision></link>'
        for i in range(joints + 1)
    ]
    chain = [
        f'<joint name="j{i}" type="continuous"><parent link="l{i}"/><child link="l{i + 1}"/>'
        f'<origin xyz="0 0.07 0.05" rpy="0.3 0 0"/><axis xyz="1 0 0"/></joint>'
        for i in range(joints)
    ]
    return "\n".join(['<?xml version="1.0"?>', '<robot name="long_chain">', *links, *chain, "</robot>", ""]).encode()


def watch_progress(get: Any, check_id: str, timeout_s: float = 300.0) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """Every distinct ``progress`` seen by polling ``get(path)`` for ``check_id`` a few times a
    second while it runs, and the finished check."""
    seen: list[dict[str, Any]] = []
    deadline = time.monotonic() + timeout_s
    while True:
        check = get(f"/v1/checks/{check_id}").json()
        if check["status"] not in ("queued", "running"):
            return seen, check
        if check["progress"] is not None and (not seen or seen[-1] != check["progress"]):
            seen.append(check["progress"])
        assert time.monotonic() < deadline, f"check {check_id} still {check['status']} after {timeout_s} s"
        time.sleep(0.2)


def database_at_version(url: str, prefix: str, version: int) -> dict[str, Any]:
    """A database whose tables (named with ``prefix``) are the store's own schema ``version``:
    its revisions run up to that one, then Alembic's record removed, as a service of that
    version left it before Alembic. Its tables, reflected, by name without the prefix."""
    import sqlalchemy as sa
    from alembic import command

    from api.store.migrate import alembic_config, revision_of

    engine = sa.create_engine(url)
    try:
        with engine.begin() as conn:
            command.upgrade(alembic_config(conn, prefix), revision_of(version))
            conn.execute(sa.text(f"DROP TABLE {prefix}alembic_version"))
        metadata = sa.MetaData()
        metadata.reflect(engine, only=lambda name, _: name.startswith(prefix))
    finally:
        engine.dispose()
    return {name.removeprefix(prefix): table for name, table in metadata.tables.items()}


def assert_progress_of_a_run(seen: list[dict[str, Any]]) -> None:
    """What every client watching a long check sees: stages in order, fractions in [0, 1]."""
    assert seen, "no progress seen while the check ran"
    for p in seen:
        assert set(p) == {"stage", "stage_index", "stages", "stage_fraction", "fraction", "phase"}
        assert p["phase"] == "check"
        assert 0.0 <= p["fraction"] <= 1.0 and 0.0 <= p["stage_fraction"] <= 1.0
        assert 0 <= p["stage_index"] < p["stages"]
    stages = [p["stage"] for p in seen]
    assert "selfcollision" in stages  # the long stage: the chain's sweeps
    sweep = [p["stage_fraction"] for p in seen if p["stage"] == "selfcollision"]
    assert len(set(sweep)) >= 2 and sweep == sorted(sweep)  # it advanced while watched
    check_pass = [p["fraction"] for p in seen]
    assert check_pass == sorted(check_pass) and check_pass[-1] < 1.0


def drop_store(url: str, prefix: str) -> None:
    """Drop a test's tables under ``prefix`` (Alembic's version table with them) and close the
    store's connections: a pooled connection left to the garbage collector is reported later,
    against whichever test runs then."""
    from api.store import Store

    store = Store(url, prefix)
    try:
        store.drop_schema()
    finally:
        store.dispose()
