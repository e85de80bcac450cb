"""Fixtures of the service tests: apps over a temporary data folder, PostgreSQL when it answers."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
import sqlalchemy as sa
from fastapi.testclient import TestClient

from api.http.app import create_app
from api.settings import Settings

# the helpers next to this file (apitools) are plain modules; pytest's importlib mode does not put them on sys.path
sys.path.insert(0, str(Path(__file__).resolve().parent))

POSTGRES_URL = "postgresql+psycopg://{user}@127.0.0.1:5432/test"


def postgres_url() -> str | None:
    """URL of the local PostgreSQL test database, or None when no server answers."""
    for user in ("postgres", "root"):
        url = POSTGRES_URL.format(user=user)
        engine = sa.create_engine(url, connect_args={"connect_timeout": 2})
        try:
            with engine.connect() as conn:
                conn.execute(sa.text("SELECT 1"))
            return url
        except sa.exc.SQLAlchemyError:
            continue
        finally:
            engine.dispose()
    return None


@pytest.fixture(scope="session")
def pg_url() -> str:
    url = postgres_url()
    if url is None:
        pytest.skip("PostgreSQL not reachable at 127.0.0.1:5432 (database 'test', trust auth): storage tests skipped")
    return url


@pytest.fixture
def make_settings(tmp_path: Path) -> Callable[..., Settings]:
    """Settings over ``tmp_path/data`` with ``overrides``."""

    def make(**overrides: Any) -> Settings:
        return Settings(data_dir=tmp_path / "data", **overrides)

    return make


@pytest.fixture
def make_client(make_settings: Callable[..., Settings]) -> Iterator[Callable[..., TestClient]]:
    """Started clients (lifespan run) of apps with the given settings; all stopped at the end."""
    clients: list[TestClient] = []

    def make(settings: Settings | None = None, **overrides: Any) -> TestClient:
        client = TestClient(create_app(settings or make_settings(**overrides)))
        client.__enter__()
        clients.append(client)
        return client

    yield make
    for client in reversed(clients):
        client.__exit__(None, None, None)


@pytest.fixture
def client(make_client: Callable[..., TestClient]) -> TestClient:
    return make_client()
