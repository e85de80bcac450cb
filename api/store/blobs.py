"""Uploads stored by content (SHA-256), readable by every worker of the distributed mode."""

from __future__ import annotations

import hashlib

import sqlalchemy as sa

from api.store.database import Database
from api.store.schema import utcnow


def digest_of(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


class Blobs(Database):
    """``put_blob`` stores an upload once under its digest; ``get_blob`` reads it back."""

    def put_blob(self, data: bytes) -> str:
        """Store ``data`` once under its SHA-256 digest (hex), which is returned."""
        digest = digest_of(data)
        try:
            with self._begin() as conn:
                conn.execute(self.blobs.insert().values(digest=digest, size=len(data), created_at=utcnow(), data=data))
        except sa.exc.IntegrityError:  # stored before: refresh its age so retention keeps it
            with self._begin() as conn:
                conn.execute(self.blobs.update().where(self.blobs.c.digest == digest).values(created_at=utcnow()))
        return digest

    def get_blob(self, digest: str) -> bytes | None:
        with self.engine.connect() as conn:
            data = conn.execute(sa.select(self.blobs.c.data).where(self.blobs.c.digest == digest)).scalar()
        return bytes(data) if data is not None else None
