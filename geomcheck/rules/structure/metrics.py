"""The data keys several GC1xx rules' findings share."""

from __future__ import annotations

from geomcheck.diagnostics import Metric

ALSO = Metric(
    "also",
    "text",
    description="The other subjects the same source line wrote, when a macro wrote it for several.",
    optional=True,
)
ELEMENT = Metric("element", "text", description="The URDF element.")
ATTRIBUTE = Metric("attribute", "text", description="The attribute.")
SUGGESTION = Metric("suggestion", "text", description="The closest known name, or null.")
FIRST = Metric("first", "text", description="Where the name was first used.")
JOINTS = Metric("joints", "text", description="The joints concerned.")
ACCEPTED_BY = Metric(
    "accepted_by",
    "text",
    description=(
        "The format's own parser that loads the file as written (urdfdom, libsdformat): the finding is "
        "geomcheck's judgement of what a consumer does with it, not a refusal of the file."
    ),
    optional=True,
)
AXIS: tuple[Metric, ...] = (
    Metric("axis", "1", description="The axis as written."),
    Metric("norm", "1", description="Its length."),
)
