"""Git for tests that build repositories: a fixed author, no signing, whatever the user's config."""

from __future__ import annotations

import subprocess
from pathlib import Path

IDENTITY = ("-c", "user.name=geomcheck", "-c", "user.email=ci@example.invalid", "-c", "commit.gpgsign=false")


def git(repo: Path, *args: str) -> str:
    """Runs ``git args`` in ``repo``; its standard output, stripped."""
    done = subprocess.run(["git", *IDENTITY, *args], cwd=repo, check=True, capture_output=True, text=True)
    return done.stdout.strip()
