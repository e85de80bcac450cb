"""Browser-facing protections: the API documentation served from this service (no CDN), the
security headers of every answer, and cross-origin requests that change state refused.

* ``/docs`` and ``/redoc`` load Swagger UI and ReDoc from ``/docs-static/`` (files shipped by
  the ``fastapi-offline`` package): they work offline and run no third party's script.
* Every answer is ``X-Content-Type-Options: nosniff``; HTML answers also carry a
  ``Content-Security-Policy`` (the page: its own scripts only; a report: no script at all)
  and ``X-Frame-Options`` (the page and the docs are never framed; a report only by the page).
* A ``POST`` or ``DELETE`` that a browser sends from another origin (``Origin`` naming another
  host, or ``Sec-Fetch-Site: cross-site``) is refused with 403: without tokens any web page
  a user visits could otherwise submit checks (a plain form POST needs no CORS preflight).
"""

from __future__ import annotations

import base64
import functools
import hashlib
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

from fastapi import FastAPI, HTTPException, Request
from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html
from fastapi.responses import FileResponse, HTMLResponse
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from api.http.handlers import error_response

PAGE_POLICY = (
    "default-src 'self'; script-src 'self' {report}; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; "
    "connect-src 'self'; frame-src 'self' about: blob:; object-src 'none'; base-uri 'none'; form-action 'self'; "
    "frame-ancestors 'none'"
)
# a report holds text from the description (escaped), its own style sheet and its own scripts
# (allowed by their hashes: nothing else inline runs; the 3D view's data is JSON, never run);
# the page shows it in a srcdoc frame, which inherits the page's policy, so the page allows
# those scripts too
REPORT_POLICY = (
    "default-src 'none'; script-src {report}; style-src 'unsafe-inline'; img-src data:; base-uri 'none'; "
    "form-action 'none'; frame-ancestors 'self'"
)
# Swagger UI and ReDoc start from an inline script; ReDoc runs a worker from a blob
DOCS_POLICY = (
    "default-src 'self'; script-src 'self' 'unsafe-inline'; style-src 'self' 'unsafe-inline'; "
    "img-src 'self' data:; worker-src 'self' blob:; connect-src 'self'; object-src 'none'; base-uri 'none'; "
    "frame-ancestors 'none'"
)
DOCS_STATIC = {
    "swagger-ui-bundle.js": "text/javascript",
    "swagger-ui.css": "text/css",
    "redoc.standalone.js": "text/javascript",
    "favicon.png": "image/png",
}
UNSAFE_METHODS = frozenset({"POST", "PUT", "PATCH", "DELETE"})


def _docs_folder() -> Path:
    import fastapi_offline

    return Path(fastapi_offline.__file__).resolve().parent / "static"


def install_docs(app: FastAPI) -> None:
    """``/docs``, ``/redoc`` and their files from this service (create the app with
    ``docs_url=None, redoc_url=None``)."""

    def base(request: Request) -> str:
        return str(request.scope.get("root_path", ""))

    @app.get("/docs", include_in_schema=False)
    def swagger(request: Request) -> HTMLResponse:
        root = base(request)
        return get_swagger_ui_html(
            openapi_url=f"{root}/openapi.json",
            title=f"{app.title} - Swagger UI",
            swagger_js_url=f"{root}/docs-static/swagger-ui-bundle.js",
            swagger_css_url=f"{root}/docs-static/swagger-ui.css",
            swagger_favicon_url=f"{root}/docs-static/favicon.png",
        )

    @app.get("/redoc", include_in_schema=False)
    def redoc(request: Request) -> HTMLResponse:
        root = base(request)
        return get_redoc_html(
            openapi_url=f"{root}/openapi.json",
            title=f"{app.title} - ReDoc",
            redoc_js_url=f"{root}/docs-static/redoc.standalone.js",
            redoc_favicon_url=f"{root}/docs-static/favicon.png",
            with_google_fonts=False,
        )

    @app.get("/docs-static/{name}", include_in_schema=False)
    def docs_static(name: str) -> FileResponse:
        if name not in DOCS_STATIC:
            raise HTTPException(404, f"no documentation file {name!r}")
        cache = {"Cache-Control": "max-age=86400"}
        return FileResponse(_docs_folder() / name, media_type=DOCS_STATIC[name], headers=cache)


@functools.cache
def report_script_source() -> str:
    """The CSP sources of the HTML report's inline scripts (its own, and three.js and the 3D
    view's in a report with a 3D view): their SHA-256, as the report template writes them."""
    try:
        from geomcheck.report.html import inline_scripts
    except ImportError:  # no HTML report renderer: the plain page has no script
        return "'none'"
    return " ".join(
        f"'sha256-{base64.b64encode(hashlib.sha256(text.encode('utf-8')).digest()).decode()}'"
        for text in inline_scripts()
    )


def _policy(path: str) -> tuple[str, str]:
    """(Content-Security-Policy, X-Frame-Options) of an HTML answer at ``path``."""
    if path.startswith("/v1/"):
        return REPORT_POLICY.format(report=report_script_source()), "SAMEORIGIN"
    if path in ("/docs", "/redoc"):
        return DOCS_POLICY, "DENY"
    return PAGE_POLICY.format(report=report_script_source()), "DENY"


def _header(scope: Scope, name: bytes) -> str | None:
    for key, value in scope.get("headers", ()):
        if key == name:
            return str(value.decode("latin-1"))
    return None


def cross_origin(scope: Scope) -> bool:
    """Whether a browser sent this request from a page of another origin."""
    if _header(scope, b"sec-fetch-site") == "cross-site":
        return True
    origin = _header(scope, b"origin")
    if origin is None:
        return False  # not a browser's cross-origin request (curl, CI, same-origin GETs)
    host = _header(scope, b"host") or ""
    return origin == "null" or urlsplit(origin).netloc.lower() != host.lower()


class SecurityHeaders:
    """Pure ASGI middleware (no per-request task, unlike BaseHTTPMiddleware): the headers of
    :mod:`api.http.security` on every answer, and cross-origin unsafe requests refused."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        if scope["method"] in UNSAFE_METHODS and cross_origin(scope):
            response = error_response(403, "cross-origin request refused: submit from this service's own page")
            await response(scope, receive, send)
            return
        path = scope.get("path", "")

        async def with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers: list[Any] = list(message.get("headers", []))
                headers.append((b"x-content-type-options", b"nosniff"))
                content_type = next((v for k, v in headers if k.lower() == b"content-type"), b"")
                if content_type.startswith(b"text/html"):
                    policy, frames = _policy(path)
                    headers.append((b"content-security-policy", policy.encode()))
                    headers.append((b"x-frame-options", frames.encode()))
                    headers.append((b"referrer-policy", b"no-referrer"))
                message = {**message, "headers": headers}
            await send(message)

        await self.app(scope, receive, with_headers)
