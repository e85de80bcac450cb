"""The Clearpath robots read dozens of ``$(optenv NAME default)`` variables (the husky 84):
untrusted, where no environment variable is read, they expand to their defaults, as on a fresh
machine. Checked by the service (uploaded as a zip of the package tree, no options) and by
``CI=true geomcheck check`` with no flag but the packages, they give the findings of a trusted
run with the defaults."""

from __future__ import annotations

import io
import json
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

import geomcheck
from tests.corpus_robots import corpus_robot

CLEARPATH = ("husky", "jackal", "dingo")
VARIABLE = re.compile(r"\$\((?:optenv|env)\s+([A-Za-z_][A-Za-z0-9_]*)")
REPO = Path(__file__).resolve().parents[2]


def tree_of(robot: Any) -> Path:
    return Path(os.path.commonpath([str(p) for p in robot.packages.values()] + [str(robot.root.parent)]))


def variables(tree: Path) -> set[str]:
    return {m for path in tree.rglob("*.xacro") for m in VARIABLE.findall(path.read_text(errors="replace"))}


def findings(report: dict[str, Any]) -> list[tuple[str, str, str]]:
    return sorted((d["code"], d["severity"], d["fingerprint"]) for d in report["diagnostics"])


@pytest.fixture(scope="module")
def service(tmp_path_factory: pytest.TempPathFactory) -> Any:
    from api.http.app import create_app
    from api.settings import Settings

    with TestClient(create_app(Settings(data_dir=tmp_path_factory.mktemp("clearpath") / "data"))) as client:
        yield client


@pytest.mark.corpus
@pytest.mark.parametrize("name", CLEARPATH)
def test_untrusted_runs_expand_optenv_as_a_fresh_machine(
    service: TestClient, corpus: Path, name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    robot = corpus_robot(corpus, name)
    tree = tree_of(robot)
    read = variables(tree)
    assert len(read) >= 20  # dozens of $(optenv) variables
    for variable in read:  # the trusted run on a fresh machine: none of them set
        monkeypatch.delenv(variable, raising=False)
    trusted = geomcheck.check(robot.root, packages=robot.packages, args=dict(robot.args), use_config=False).to_dict()

    archive = io.BytesIO()
    with zipfile.ZipFile(archive, "w") as zipped:
        for path in sorted(tree.rglob("*")):
            if path.is_file():
                zipped.write(path, path.relative_to(tree).as_posix())
    response = service.post("/v1/checks", content=archive.getvalue(), headers={"content-type": "application/zip"})
    assert response.status_code == 201, response.text
    answered = response.json()
    assert answered["source"] == robot.root.relative_to(tree).as_posix() and answered["root"]["given"] is False
    assert findings(answered["report"]) == findings(trusted)

    flags = [f"--package={package}={folder}" for package, folder in robot.packages.items()]
    environment = {**os.environ, "CI": "true", "PYTHONPATH": str(REPO)}
    environment.pop("GEOMCHECK_UNTRUSTED", None)
    for variable in read:
        environment.pop(variable, None)
    ci = subprocess.run(
        [sys.executable, "-m", "geomcheck", "check", str(robot.root), *flags, "--format", "json", "--no-cache"],
        cwd=tree,
        env=environment,
        capture_output=True,
        timeout=600,
    )
    assert ci.returncode in (0, 1), ci.stderr.decode()
    assert findings(json.loads(ci.stdout)) == findings(trusted)
