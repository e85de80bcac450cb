"""The Alembic revisions themselves, ``NNNN_<what>.py``: revision NNNN is schema version NNNN."""

__all__: list[str] = []
