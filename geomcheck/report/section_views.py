"""The ``views`` report section as typed data: per link, its front, side and top outlines.

Written by the views family (geomcheck/checks/views.py) as JSON-ready dicts, documented in
docs/report-schema.md; readers parse it here and use named fields. ``from_dict`` tolerates
the keys an older or hand-written report leaves out; ``to_dict`` writes the keys, in the
order, the family writes them, so a parsed entry serialises back to the same JSON.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

# A view's outlines: rings of (u, v) points [m] in the view's axes, as the JSON lists.
Rings = Sequence[Sequence[Sequence[float]]]


@dataclass(frozen=True)
class View:
    """One orthographic view: its (right, up) axis names, the bounds (umin, vmin, umax, vmax)
    [m] of everything drawn (``None`` when nothing is), the visual silhouette (``mesh``), the
    collision outlines and the suggested primitives' outlines."""

    axes: tuple[str, str] = ("u", "v")
    bounds: tuple[float, float, float, float] | None = None
    mesh: Rings = ()
    collision: Rings = ()
    suggested: Rings = ()

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> View:
        axes = data.get("axes") or ("u", "v")
        bounds = data.get("bounds")
        return cls(
            axes=(str(axes[0]), str(axes[1])),
            bounds=None if not bounds else (float(bounds[0]), float(bounds[1]), float(bounds[2]), float(bounds[3])),
            mesh=data.get("mesh") or (),
            collision=data.get("collision") or (),
            suggested=data.get("suggested") or (),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "axes": list(self.axes),
            "bounds": None if self.bounds is None else list(self.bounds),
            "mesh": _rings(self.mesh),
            "collision": _rings(self.collision),
            "suggested": _rings(self.suggested),
        }


@dataclass(frozen=True)
class LinkViews:
    """One ``views`` entry: a link's three views, the largest extent of its geometry
    ``scale_m`` [m], and why some of its meshes could not be drawn (``unavailable``)."""

    link: str
    scale_m: float | None = None
    front: View | None = None
    side: View | None = None
    top: View | None = None
    unavailable: tuple[str, ...] = ()

    def views(self) -> Iterator[tuple[str, View | None]]:
        """(name, view) in figure order: front, side, top."""
        yield from (("front", self.front), ("side", self.side), ("top", self.top))

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> LinkViews:
        scale = data.get("scale_m")
        return cls(
            link=str(data.get("link", "")),
            scale_m=None if scale is None else float(scale),
            front=_view(data.get("front")),
            side=_view(data.get("side")),
            top=_view(data.get("top")),
            unavailable=tuple(str(u) for u in data.get("unavailable") or ()),
        )

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"link": self.link, "scale_m": self.scale_m}
        out |= {name: view.to_dict() for name, view in self.views() if view is not None}
        if self.unavailable:
            out["unavailable"] = list(self.unavailable)
        return out


def _view(data: Mapping[str, Any] | None) -> View | None:
    return None if data is None else View.from_dict(data)


def _rings(rings: Rings) -> list[list[list[float]]]:
    return [[list(point) for point in ring] for ring in rings]


def views_section(sections: Mapping[str, Any]) -> tuple[LinkViews, ...]:
    """The report's ``views`` section, parsed; empty when the family did not run."""
    return tuple(LinkViews.from_dict(entry) for entry in sections.get("views") or ())
