"""Acceptance: the service's report equals the CLI's JSON for the same input.

(a) the bundled example as a zip, (b) the 2009 PR2 package as a zip with
``robots/pr2.urdf.xacro`` as root (and as a zip holding the ``pr2_description/`` folder),
(c) a bare URDF whose meshes are absent. The CLI runs with the working directory at the
same root, so report paths match.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import pytest
from apitools import EXAMPLE, EXAMPLE_ROOT, assert_same_report, post_zip, zip_folder
from fastapi.testclient import TestClient

from geomcheck.cli import main as cli_main

pytestmark = pytest.mark.long


def cli_report(cwd: Path, root: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, *flags: str) -> dict[str, Any]:
    """The JSON report of ``geomcheck check ROOT --format json`` run in ``cwd``."""
    output = tmp_path / "cli.json"
    monkeypatch.chdir(cwd)
    status = cli_main(["check", root, "--format", "json", "--no-config", "-o", str(output), *flags])
    monkeypatch.undo()
    assert status in (0, 1)
    return dict(json.loads(output.read_text()))


@pytest.fixture(scope="module")
def service(tmp_path_factory: pytest.TempPathFactory) -> Any:
    from api.http.app import create_app
    from api.settings import Settings

    with TestClient(create_app(Settings(data_dir=tmp_path_factory.mktemp("accept") / "data"))) as client:
        yield client


def test_bundled_example_as_a_zip(service: TestClient, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if not (EXAMPLE / EXAMPLE_ROOT).is_file():
        pytest.skip("examples/pr2_base is not in this tree")
    response = post_zip(service, zip_folder(EXAMPLE), root=EXAMPLE_ROOT)
    assert response.status_code == 201, response.text
    body = response.json()
    assert body["source"] == EXAMPLE_ROOT
    assert_same_report(body["report"], cli_report(EXAMPLE, EXAMPLE_ROOT, tmp_path, monkeypatch))
    assert body["report"]["robot"]["meshes_loaded"] == body["report"]["robot"]["meshes_total"] > 0

    # the offered fixes are verified after the answer, and their section is rewritten when that
    # ends (here possibly during the CLI run above): the rest is the very report answered
    stored = json.loads(service.get(f"/v1/checks/{body['id']}/report.json").text)
    answered = body["report"]
    assert {**stored, "sections": {}} == {**answered, "sections": {}}
    assert {k: v for k, v in stored["sections"].items() if k != "fixes"} == {
        k: v for k, v in answered["sections"].items() if k != "fixes"
    }
    page = service.get(f"/v1/checks/{body['id']}/report.html")
    assert page.status_code == 200
    assert page.headers["content-disposition"] == f'attachment; filename="{body["robot"]}-geomcheck.html"'
    assert body["robot"] in page.text


@pytest.mark.corpus
def test_pr2_2009_package_as_a_zip(
    service: TestClient, pr2_root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    package = pr2_root / "pr2_description"
    response = post_zip(service, zip_folder(package), root="robots/pr2.urdf.xacro")
    assert response.status_code == 201, response.text
    report = response.json()["report"]
    assert report["robot"]["links"] == 72
    legacy = [d for d in report["diagnostics"] if d["code"] == "GC103"]
    assert legacy and all(not d["location"]["file"].startswith(("/", "..")) for d in legacy)
    assert_same_report(report, cli_report(package, "robots/pr2.urdf.xacro", tmp_path, monkeypatch))


@pytest.mark.corpus
def test_zip_holding_the_package_folder(
    service: TestClient, pr2_root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    root = "pr2_description/robots/pr2_base.urdf.xacro"
    archive = zip_folder(pr2_root / "pr2_description", prefix="pr2_description/")
    response = post_zip(service, archive, root=root)
    assert response.status_code == 201, response.text
    report = response.json()["report"]
    assert report["robot"]["source"] == root and report["robot"]["links"] == 14
    assert_same_report(report, cli_report(pr2_root, root, tmp_path, monkeypatch, "--search", "."))


@pytest.mark.corpus
def test_bare_urdf_with_absent_meshes(
    service: TestClient, erd_root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    source = erd_root / "robots/double_pendulum_description/urdf/double_pendulum.urdf"
    response = service.post(
        "/v1/checks",
        content=source.read_bytes(),
        headers={"content-type": "application/xml"},
        params={"root": source.name},
    )
    assert response.status_code == 201, response.text
    report = response.json()["report"]
    alone = tmp_path / "alone"
    alone.mkdir()
    shutil.copy(source, alone / source.name)
    assert_same_report(report, cli_report(alone, source.name, tmp_path, monkeypatch))

    package = f"example-robot-data={erd_root}"
    with_meshes = cli_report(source.parent, source.name, tmp_path, monkeypatch, "--package", package)
    assert with_meshes["robot"]["meshes_loaded"] == with_meshes["robot"]["meshes_total"] > 0
    assert report["robot"]["meshes_loaded"] == 0
    absent = {
        (r["link"], r["about"]) for d in report["diagnostics"] if d["code"] == "GC202" for r in d["data"]["references"]
    }
    referenced = {
        (link["link"], f"visual[{m['index']}]")
        for link in with_meshes["sections"]["links"]
        for m in link["visual_meshes"]
    }
    assert referenced and referenced <= absent  # every mesh the URDF references is reported missing
    assert any(s["check"] == "fit" for s in report["skipped"])
