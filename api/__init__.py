"""The geomcheck HTTP service (FastAPI): imports the library, never the reverse.

One package per job: :mod:`api.uploads` (request bodies into upload folders),
:mod:`api.checks` (options, jobs, the sandbox and the check service), :mod:`api.results`
(the result cache and the report's forms), :mod:`api.store` (the database),
:mod:`api.distributed` (the Celery workers), :mod:`api.http` (the application and what wraps
every request), :mod:`api.routers` (the endpoints) and :mod:`api.web` (the web page).
:mod:`api.settings` and :mod:`api.errors` are what all of them share.
"""

__all__ = ["checks", "distributed", "errors", "http", "results", "routers", "settings", "store", "uploads", "web"]
