"""Results: stored reports found again, and served in every form.

:mod:`api.results.key` and :mod:`api.results.cache` key a check's result so that an identical
submission is answered from the store; :mod:`api.results.compressed` keeps reports compressed
once for gzip'd answers; :mod:`api.results.html` and :mod:`api.results.srdf` render a stored
report as an HTML page and as a MoveIt SRDF.
"""

__all__ = ["cache", "compressed", "html", "key", "srdf"]
