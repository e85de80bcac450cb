"""Service settings, read from the environment (prefix ``GEOMCHECK_``) by pydantic-settings.

Sizes are [bytes], times [s]. Every limit that protects the service from hostile uploads
lives here, next to the worker-process limits.
"""

from __future__ import annotations

import functools
import hashlib
import re
from dataclasses import dataclass
from pathlib import Path

from pydantic import Field, field_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

MiB = 1024 * 1024
GiB = 1024 * MiB


@dataclass(frozen=True)
class ApiToken:
    """One accepted bearer token and the client it identifies: ``name`` owns the checks
    submitted with it; an ``admin`` token sees every client's checks."""

    name: str
    token: str
    admin: bool = False


TOKEN_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.@\-]{0,63}")


@functools.lru_cache(maxsize=8)
def parse_tokens(text: str) -> tuple[ApiToken, ...]:
    """``GEOMCHECK_API_TOKENS``: comma-separated ``NAME=TOKEN`` entries, ``NAME=TOKEN:admin`` for an
    admin; a bare ``TOKEN`` (the format before names) is a client of its own, named
    ``token-`` and the first 8 hex digits of the token's SHA-256. :class:`ValueError` for a bad
    name, an empty token, or a name or token given twice."""
    entries: list[ApiToken] = []
    for item in (part.strip() for part in text.split(",")):
        if not item:
            continue
        name, sep, token = item.partition("=")
        if not sep:
            name, token = "token-" + hashlib.sha256(item.encode()).hexdigest()[:8], item
        token, marked, flag = token.strip().rpartition(":") if token.strip().endswith(":admin") else (token, "", "")
        name, token = name.strip(), token.strip()
        if not TOKEN_NAME.fullmatch(name):
            raise ValueError(f"api_tokens: bad client name {name!r} (letters, digits, _ . @ -, at most 64)")
        if not token:
            raise ValueError(f"api_tokens: client {name} has an empty token")
        entries.append(ApiToken(name, token, admin=bool(marked and flag == "admin")))
    for attribute in ("name", "token"):
        values = [getattr(e, attribute) for e in entries]
        if len(set(values)) != len(values):
            raise ValueError(f"api_tokens: a client {attribute} is given twice")
    return tuple(entries)


class Settings(BaseSettings):
    """Configuration of one service instance (``GEOMCHECK_<NAME>`` environment variables)."""

    model_config = SettingsConfigDict(env_prefix="GEOMCHECK_", extra="ignore", frozen=True)

    database_url: str | None = Field(
        default=None,
        description="SQLAlchemy URL (postgresql+psycopg://user@host/db); default: SQLite file in data_dir",
    )
    data_dir: Path = Field(default=Path("data"), description="database file (SQLite) and per-check work folders")
    table_prefix: str = Field(default="", description="prefix of every table name (several services in one database)")
    api_tokens: str = Field(
        default="",
        description="comma-separated NAME=TOKEN (NAME=TOKEN:admin sees every check); empty: no authentication",
    )

    max_body_bytes: int = Field(default=64 * MiB, gt=0, description="request body [bytes]")
    body_timeout_s: float = Field(
        default=120.0, gt=0, description="longest a request body may take to arrive, from its first byte [s]"
    )
    header_timeout_s: float = Field(
        default=10.0, gt=0, description="longest a connection may take to send a request's headers [s]"
    )
    max_files: int = Field(default=2000, gt=0, description="files in one upload (archive entries, form files)")
    max_unpacked_bytes: int = Field(default=256 * MiB, gt=0, description="all files of one upload, unpacked [bytes]")
    max_ratio: float = Field(default=100.0, gt=1, description="unpacked / compressed size of an archive [ratio]")
    max_path_length: int = Field(default=512, gt=0, description="one path inside an upload [characters]")

    check_timeout_s: float = Field(default=300.0, gt=0, description="wall-clock limit of one check [s]")
    check_cpu_s: int = Field(default=300, gt=0, description="CPU-time limit of one check process [s]")
    check_memory_bytes: int = Field(default=2 * GiB, gt=0, description="address-space limit of one check [bytes]")
    check_file_bytes: int = Field(default=256 * MiB, gt=0, description="largest file a check process may write [bytes]")
    workers: int = Field(default=2, gt=0, description="checks running at once, each in its own process")
    max_queued: int = Field(default=64, gt=0, description="checks waiting for a worker before 503 [count]")
    max_samples: int = Field(default=200_000, gt=0, description="largest matrix sample count a request may ask [count]")

    page_size: int = Field(default=20, gt=0, le=200, description="default page size of GET /v1/checks [items]")
    retention_days: float = Field(
        default=30.0,
        ge=0,
        description="finished checks, reports and uploads older than this are deleted [days]; 0: never",
    )
    retention_interval_s: float = Field(default=3600.0, gt=0, description="how often old checks are deleted [s]")

    # the distributed mode (Celery): set broker_url and a PostgreSQL database_url
    broker_url: str | None = Field(
        default=None, description="Celery broker (redis://host:6379/0 or amqp://user:pass@host//); unset: embedded"
    )
    queue: str = Field(default="geomcheck", description="broker queue of the checks (distributed mode)")
    lease_s: float = Field(
        default=30.0, gt=0, description="a worker renews its lease on a running check every third of this [s]"
    )
    requeue_after_s: float = Field(
        default=600.0, gt=0, description="a check queued this long is published again (lost message) [s]"
    )
    max_attempts: int = Field(default=3, gt=0, description="starts of a check whose worker keeps vanishing [count]")
    stage_cache_dir: Path | None = Field(
        default=None,
        description="a folder where check processes keep the library's stage caches (xacro expansions, mesh "
        "analyses, each pair's sweep) across checks, so a re-check of an edited description recomputes only "
        "what the edit touched; unset: none (every check computes everything)",
    )
    shutdown_timeout_s: float = Field(
        default=10.0,
        gt=0,
        description="on SIGTERM, longest the server waits for open requests (POSTs waiting for their checks) "
        "before closing them and failing the unfinished checks [s]",
    )
    wait_s: float = Field(
        default=900.0,
        gt=0,
        description="longest a POST waits for a check it does not run itself (distributed, or shared) "
        "before answering 202 [s]",
    )
    visibility_timeout_s: float = Field(
        default=3600.0, gt=0, description="Redis broker: an unacknowledged message is delivered again after [s]"
    )

    @field_validator("data_dir")
    @classmethod
    def _absolute_data_dir(cls, value: Path) -> Path:
        # checks run in their own working directory: every path handed to them must be absolute
        return value.expanduser().resolve()

    @field_validator("table_prefix")
    @classmethod
    def _valid_prefix(cls, value: str) -> str:
        if not re.fullmatch(r"[a-z][a-z0-9_]{0,30}|", value):
            raise ValueError("table_prefix must be lower-case letters, digits and _, starting with a letter")
        return value

    @field_validator("api_tokens")
    @classmethod
    def _valid_tokens(cls, value: str) -> str:
        parse_tokens(value)
        return value

    @field_validator("queue")
    @classmethod
    def _valid_queue(cls, value: str) -> str:
        if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.\-]{0,100}", value):
            raise ValueError("queue must be letters, digits, '.', '_' and '-'")
        return value

    @property
    def distributed(self) -> bool:
        """True when a broker is configured: API replicas enqueue, ``geomcheck worker`` processes run checks."""
        return bool(self.broker_url)

    @property
    def tokens(self) -> tuple[ApiToken, ...]:
        """The accepted bearer tokens and their clients; empty when authentication is off."""
        return parse_tokens(self.api_tokens)

    @property
    def database(self) -> str:
        """The SQLAlchemy URL in use: ``database_url`` or ``sqlite:///<data_dir>/geomcheck.db``."""
        if self.database_url:
            return self.database_url
        return f"sqlite:///{(self.data_dir / 'geomcheck.db').resolve()}"

    @property
    def work_dir(self) -> Path:
        """Folder of the per-check upload trees (removed when a check ends)."""
        return self.data_dir / "work"
