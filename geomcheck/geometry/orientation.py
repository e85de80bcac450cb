"""How a triangle mesh's faces are wound: consistently with their neighbours, and outward.

Two triangles sharing an edge are wound alike when they run along it in opposite directions; a
mesh whose faces disagree with their neighbours has normals pointing in and out at random (a
viewer culling back faces shows holes; a simulator computing the mesh's volume and inertia from
its faces gets them wrong). A closed mesh wound alike everywhere but with a negative signed
volume is inside out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Winding:
    """``shared`` edges used by exactly two faces, ``inconsistent`` ones of them run the same way
    by both; ``closed`` when every edge is shared by two faces; ``volume`` the signed volume [m^3]
    the faces enclose (negative: wound inward)."""

    shared: int
    inconsistent: int
    closed: bool
    volume: float

    @property
    def inconsistent_share(self) -> float:
        return self.inconsistent / self.shared if self.shared else 0.0

    @property
    def inside_out(self) -> bool:
        return self.closed and self.inconsistent == 0 and self.volume < 0.0


def winding(vertices: np.ndarray, faces: np.ndarray) -> Winding:
    """The winding of ``faces`` (m, 3) over ``vertices`` (n, 3), vertices already welded (a
    mesh as read: equal positions share one index)."""
    f = np.asarray(faces, dtype=np.int64)
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
    if len(f) == 0:
        return Winding(0, 0, False, 0.0)
    n = int(f.max()) + 1
    start = f.reshape(-1)
    end = f[:, [1, 2, 0]].reshape(-1)
    directed = np.sort(start * n + end)
    undirected = np.sort(np.minimum(start, end) * n + np.maximum(start, end))
    # edges used by exactly two faces
    keys, counts = np.unique(undirected, return_counts=True)
    shared = keys[counts == 2]
    # a directed edge repeated: two faces run along it the same way
    repeated = directed[1:][directed[1:] == directed[:-1]]
    lo, hi = repeated // n, repeated % n
    inconsistent = int(np.isin(np.unique(np.minimum(lo, hi) * n + np.maximum(lo, hi)), shared).sum())
    v = np.asarray(vertices, dtype=float)
    tri = v[f]
    volume = float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0)
    return Winding(len(shared), inconsistent, bool((counts == 2).all()), volume)


__all__ = ["Winding", "winding"]
