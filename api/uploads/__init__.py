"""Uploads: a ``POST /v1/checks`` body read into a folder of its own, and the root file found in it.

:mod:`api.uploads.body` reads the three kinds of body (an XML document, a multipart form, an
archive) into an :class:`api.uploads.tree.UploadTree`, one checked path at a time;
:mod:`api.uploads.archives` unpacks zip and tar archives safely into it;
:mod:`api.uploads.layout` arranges the unpacked tree (the root file, the package folders, the
SRDF) and :mod:`api.uploads.roots` ranks the files that could be the root.
"""

__all__ = ["archives", "body", "layout", "roots", "tree"]
