"""Running checks: a check's options, its job, the sandboxed process it runs in and the service that queues it.

:mod:`api.checks.options` reads a request's options into a configuration;
:mod:`api.checks.job` is one check as it runs in its process (:mod:`api.checks.sandbox`, warm
from :mod:`api.checks.preload`), reporting its stages through :mod:`api.checks.progress`;
:mod:`api.checks.service` queues checks and writes their outcomes to the store;
:mod:`api.checks.submission` is what ``POST /v1/checks`` does with a request;
:mod:`api.checks.blobs` packs an arranged upload for a remote worker.
"""

__all__ = ["blobs", "job", "options", "preload", "progress", "sandbox", "service", "submission"]
