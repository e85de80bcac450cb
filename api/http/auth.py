"""Optional bearer-token authentication of the ``/v1`` endpoints (``GEOMCHECK_API_TOKENS``),
and the client a token identifies: checks belong to the client that submitted them."""

from __future__ import annotations

import secrets
from dataclasses import dataclass

from fastapi import Depends, HTTPException, Request
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

bearer = HTTPBearer(
    auto_error=False,
    description="Required when the service is started with GEOMCHECK_API_TOKENS (comma-separated NAME=TOKEN).",
)


@dataclass(frozen=True)
class Client:
    """Who sent a request: ``name`` owns the checks it submits; ``admin`` sees every check."""

    name: str
    admin: bool = False

    @property
    def scope(self) -> str | None:
        """The owner whose checks this client sees; None: every check."""
        return None if self.admin else self.name

    def sees(self, owner: str | None) -> bool:
        return self.admin or owner == self.name


# without tokens there is one client, the service's operator, who sees every check
ANONYMOUS = Client("", admin=True)


async def require_token(request: Request, credentials: HTTPAuthorizationCredentials | None = Depends(bearer)) -> Client:
    """The client of the request's token: :data:`ANONYMOUS` when authentication is off, 401
    when the request carries none of the configured tokens.

    A coroutine: FastAPI runs a plain function dependency in its thread pool, a hand-off
    costing more than the comparison (every request to /v1 passes here)."""
    tokens = request.app.state.settings.tokens
    if not tokens:
        return ANONYMOUS
    given = credentials.credentials.encode() if credentials is not None else b""
    # compare against every token, always, so the time taken says nothing about which one nearly matched
    matched = [entry for entry in tokens if secrets.compare_digest(given, entry.token.encode())]
    if not matched:
        raise HTTPException(401, "missing or invalid bearer token", headers={"WWW-Authenticate": "Bearer"})
    return Client(matched[0].name, matched[0].admin)
