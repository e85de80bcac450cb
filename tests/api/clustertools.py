"""Helpers of the distributed-mode tests: real brokers and PostgreSQL, real `geomcheck serve` and `geomcheck worker`.

A server that does not answer skips the test with its name, except under ``CI=true``,
where the test fails: CI starts them (.ci/run).
"""

from __future__ import annotations

import contextlib
import os
import secrets
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx
import pytest
from servertools import free_port

REDIS = ("127.0.0.1", 6379)
RABBITMQ = ("127.0.0.1", 5672)
START_TIMEOUT_S = 90.0


def answers(address: tuple[str, int]) -> bool:
    try:
        with socket.create_connection(address, timeout=2):
            return True
    except OSError:
        return False


def require(what: str, ok: bool) -> None:
    """Skip naming ``what`` when it is missing; fail under CI=true, where it must be there."""
    if ok:
        return
    message = f"{what} not reachable: distributed-mode tests need it"
    if os.environ.get("CI") == "true":
        pytest.fail(f"{message} (CI=true: .ci/run starts it)")
    pytest.skip(message)


def database_url() -> str:
    """The local PostgreSQL test database (trust auth, database ``test``)."""
    import sqlalchemy as sa

    for user in ("postgres", "root"):
        engine = sa.create_engine(
            f"postgresql+psycopg://{user}@127.0.0.1:5432/test", connect_args={"connect_timeout": 2}
        )
        try:
            with engine.connect() as conn:
                conn.execute(sa.text("SELECT 1"))
            return engine.url.render_as_string(hide_password=False)
        except sa.exc.SQLAlchemyError:
            continue
        finally:
            engine.dispose()
    require("PostgreSQL at 127.0.0.1:5432 (database 'test', trust auth)", False)
    raise AssertionError("unreachable")


def redis_url() -> str:
    require("Redis at 127.0.0.1:6379", answers(REDIS))
    return "redis://127.0.0.1:6379/0"


def rabbitmq_url() -> str:
    require("RabbitMQ at 127.0.0.1:5672 (guest/guest)", answers(RABBITMQ))
    return "amqp://guest:guest@127.0.0.1:5672//"


def unique_queue() -> str:
    return f"gc-test-{secrets.token_hex(4)}"


def delete_queue(broker: str, queue: str) -> None:
    """Remove the test run's queue from the broker (its name is unique: leftovers would be harmless)."""
    from kombu import Connection

    with Connection(broker, connect_timeout=5) as conn:
        if broker.startswith("redis"):
            client = conn.default_channel.client
            client.delete(queue, f"_kombu.binding.{queue}", f"_kombu.binding_permanent.{queue}")
        else:
            conn.default_channel.queue_delete(queue)


@dataclass
class Cluster:
    """API replicas and workers of one test run (processes started here, stopped by their pids)."""

    env: dict[str, str]
    root: Path
    apis: dict[str, tuple[int, subprocess.Popen[bytes]]] = field(default_factory=dict)
    workers: dict[str, subprocess.Popen[bytes]] = field(default_factory=dict)

    def _log(self, name: str) -> Any:
        return (self.root / f"{name}.log").open("ab")

    def spawn_api(self, name: str, port: int | None = None) -> str:
        """Start ``geomcheck serve`` (not waiting for it); returns its base URL."""
        port = port or free_port()
        env = {**self.env, "GEOMCHECK_DATA_DIR": str(self.root / name)}
        command = [sys.executable, "-m", "geomcheck", "serve", "--host", "127.0.0.1", "--port", str(port)]
        process = subprocess.Popen(command, env=env, stdout=self._log(name), stderr=subprocess.STDOUT)
        self.apis[name] = (port, process)
        return self.base(name)

    def wait_api_ready(self, name: str) -> str:
        """Wait (bounded) until the API answers /readyz with 200; returns its base URL."""
        process = self.apis[name][1]
        base = self.base(name)
        deadline = time.monotonic() + START_TIMEOUT_S
        while True:
            assert process.poll() is None, f"API {name} exited: {self.log(name)[-2000:]}"
            try:
                if httpx.get(f"{base}/readyz", timeout=2).status_code == 200:
                    return base
            except httpx.HTTPError:
                pass
            assert time.monotonic() < deadline, f"API {name} not ready within {START_TIMEOUT_S:g} s"
            time.sleep(0.1)

    def start_api(self, name: str, port: int | None = None) -> str:
        self.spawn_api(name, port)
        return self.wait_api_ready(name)

    def base(self, name: str) -> str:
        return f"http://127.0.0.1:{self.apis[name][0]}"

    def start_worker(self, name: str, concurrency: int = 1, *flags: str) -> subprocess.Popen[bytes]:
        env = {**self.env, "GEOMCHECK_DATA_DIR": str(self.root / name)}
        command = [sys.executable, "-m", "geomcheck", "worker", "--concurrency", str(concurrency), *flags]
        process = subprocess.Popen(command, env=env, stdout=self._log(name), stderr=subprocess.STDOUT)
        self.workers[name] = process
        return process

    def wait_worker_ready(self, name: str) -> None:
        deadline = time.monotonic() + START_TIMEOUT_S
        while " ready." not in self.log(name):
            assert self.workers[name].poll() is None, f"worker {name} exited: {self.log(name)[-2000:]}"
            assert time.monotonic() < deadline, f"worker {name} not ready within {START_TIMEOUT_S:g} s"
            time.sleep(0.2)

    def log(self, name: str) -> str:
        path = self.root / f"{name}.log"
        return path.read_text(errors="replace") if path.exists() else ""

    def stop_api(self, name: str) -> int:
        port, process = self.apis.pop(name)
        stop(process)
        return port

    def stop_all(self) -> None:
        for _, process in self.apis.values():
            stop(process)
        for process in self.workers.values():
            stop(process)


def stop(process: subprocess.Popen[bytes]) -> None:
    """SIGTERM, then SIGKILL after a bounded wait."""
    if process.poll() is None:
        process.send_signal(signal.SIGTERM)
        try:
            process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=10)


@contextmanager
def cluster(tmp_path: Path, broker: str, database: str, prefix: str, **settings: str) -> Iterator[Cluster]:
    """Environment of one cluster test run: its own table prefix and queue; every process stopped at the end."""
    queue = unique_queue()
    env = {
        **os.environ,
        "GEOMCHECK_BROKER_URL": broker,
        "GEOMCHECK_DATABASE_URL": database,
        "GEOMCHECK_TABLE_PREFIX": prefix,
        "GEOMCHECK_QUEUE": queue,
        **{f"GEOMCHECK_{k.upper()}": v for k, v in settings.items()},
    }
    env.pop("GEOMCHECK_API_TOKENS", None)
    running = Cluster(env, tmp_path)
    try:
        yield running
    finally:
        running.stop_all()
        with contextlib.suppress(Exception):  # the broker is gone: nothing to clean
            delete_queue(broker, queue)
