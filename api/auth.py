"""Optional bearer-token authentication of the ``/v1`` endpoints (``GEOMCHECK_API_TOKENS``)."""

from __future__ import annotations

import secrets

from fastapi import Depends, HTTPException, Request
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

bearer = HTTPBearer(
    auto_error=False,
    description="Required when the service is started with GEOMCHECK_API_TOKENS (comma-separated tokens).",
)


async def require_token(request: Request, credentials: HTTPAuthorizationCredentials | None = Depends(bearer)) -> None:
    """Pass when authentication is off or the request carries one of the configured tokens.

    A coroutine: FastAPI runs a plain function dependency in its thread pool, a hand-off
    costing more than the comparison (every request to /v1 passes here)."""
    tokens: tuple[str, ...] = request.app.state.settings.tokens
    if not tokens:
        return
    given = credentials.credentials.encode() if credentials is not None else b""
    # compare against every token, always, so the time taken says nothing about which one nearly matched
    matched = [secrets.compare_digest(given, token.encode()) for token in tokens]
    if not any(matched):
        raise HTTPException(401, "missing or invalid bearer token", headers={"WWW-Authenticate": "Bearer"})
