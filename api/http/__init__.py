"""The HTTP side of the service: the FastAPI application, its server, and what every request passes through.

:mod:`api.http.app` wires the application (``create_app``), :mod:`api.http.server` runs it under
uvicorn; :mod:`api.http.deps` gives the handlers the check service (``ServiceDep``);
:mod:`api.http.auth` (bearer tokens), :mod:`api.http.bodylimit` (body size and time),
:mod:`api.http.security` (headers, documentation pages, cross-origin refusals) and
:mod:`api.http.handlers` (errors as one line) wrap every request; :mod:`api.http.openapi` and
:mod:`api.http.schemas` make the OpenAPI document; :mod:`api.http.metrics` exports Prometheus metrics.
"""

__all__ = ["app", "auth", "bodylimit", "deps", "handlers", "metrics", "openapi", "schemas", "security", "server"]
