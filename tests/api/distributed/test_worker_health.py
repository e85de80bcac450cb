"""``geomcheck worker --ping``, the worker containers' health check (compose.yaml): 1 while no
worker of this host answers through the broker, 0 once one runs, 1 again when it stopped."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from apitools import drop_store, unique_prefix
from clustertools import cluster, database_url, redis_url

pytestmark = pytest.mark.long


def ping(env: dict[str, str]) -> int:
    command = [sys.executable, "-m", "geomcheck", "worker", "--ping"]
    return subprocess.run(command, env=env, capture_output=True, timeout=60).returncode


@pytest.mark.postgres
def test_the_worker_health_check_follows_the_worker(tmp_path: Path) -> None:
    database, prefix, neighbour = database_url(), unique_prefix(), unique_prefix()
    (tmp_path / "ours").mkdir()
    (tmp_path / "neighbour").mkdir()
    try:
        with (
            cluster(tmp_path / "ours", redis_url(), database, prefix) as running,
            cluster(tmp_path / "neighbour", redis_url(), database, neighbour) as other,
        ):
            # another deployment's worker on this host and broker (its own queue) is not ours
            other.start_worker("other")
            other.wait_worker_ready("other")
            assert ping(other.env) == 0
            assert ping(running.env) == 1
            running.start_worker("w1")
            running.wait_worker_ready("w1")
            assert ping(running.env) == 0
            running.stop_all()
            assert ping(running.env) == 1
    finally:
        drop_store(database, prefix)
        drop_store(database, neighbour)


def test_the_compose_file_and_the_image_probe_what_the_docs_say() -> None:
    repo = Path(__file__).resolve().parents[3]
    dockerfile = (repo / "Dockerfile").read_text(encoding="utf-8")
    compose = (repo / "compose.yaml").read_text(encoding="utf-8")
    assert "/readyz" in dockerfile.split("HEALTHCHECK", 1)[1].split('CMD ["geomcheck"', 1)[0]
    assert 'test: ["CMD", "geomcheck", "worker", "--ping"]' in compose
    assert "disable: true" not in compose
