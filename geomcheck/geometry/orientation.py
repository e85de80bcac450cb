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

from geomcheck.geometry.hull_mesh import signed_volume


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


def sorted_runs(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct values of the sorted 1-D ``values`` and how often each occurs: what
    ``np.unique(values, return_counts=True)`` gives, without sorting again."""
    if len(values) == 0:
        return values, np.zeros(0, dtype=np.int64)
    starts = np.flatnonzero(np.concatenate(([True], values[1:] != values[:-1])))
    return values[starts], np.diff(np.append(starts, len(values)))


def sorted_members(values: np.ndarray, sorted_set: np.ndarray) -> np.ndarray:
    """Whether each of ``values`` is in the sorted, distinct 1-D ``sorted_set`` (``np.isin``)."""
    if len(values) == 0 or len(sorted_set) == 0:
        return np.zeros(len(values), dtype=bool)
    at = np.minimum(np.searchsorted(sorted_set, values), len(sorted_set) - 1)
    return np.asarray(sorted_set[at] == values)


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
    # edges used by exactly two faces (the keys are sorted: runs are counted, not hashed, as
    # numpy's unique and isin now do, several times slower on a mesh's millions of edges)
    keys, counts = sorted_runs(undirected)
    shared = keys[counts == 2]
    # a directed edge repeated: two faces run along it the same way
    repeated = directed[1:][directed[1:] == directed[:-1]]
    lo, hi = repeated // n, repeated % n
    turned, _ = sorted_runs(np.sort(np.minimum(lo, hi) * n + np.maximum(lo, hi)))
    inconsistent = int(np.count_nonzero(sorted_members(turned, shared)))
    return Winding(len(shared), inconsistent, bool((counts == 2).all()), signed_volume(vertices, f))


__all__ = ["Winding", "sorted_members", "sorted_runs", "winding"]
