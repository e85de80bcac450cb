"""Sphere covers of links: the broad phase of the collision matrix and the certificates.

Every collision shape is covered by a few spheres that together contain its whole volume
(:attr:`geomcheck.collision.scene.SceneShape.cover`: the convex hull of the shape's support
points grown by their pad, so the cover holds whether a backend treats a mesh as a surface
or as a convex solid).
A link's *bound* is one sphere around all of its cover spheres. Two links whose covers do not
overlap cannot collide, and the gap between covers is a lower bound of their distance.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from geomcheck.collision.scene import CollisionScene

ABSENT = -np.inf  # radius of padding slots: a gap to them is +inf
SINGLE_PRECISION_SLACK_M = 1e-5  # added to cover radii tested in float32 (rounding of ~1 m coordinates) [m]


@dataclass(frozen=True)
class LinkSpheres:
    """Sphere covers of links, in each link's frame.

    ``centres`` (n_links, k, 3) [m] and ``radii`` (n_links, k) [m], padded with
    :data:`ABSENT` radii; ``bound_centres`` (n_links, 3) and ``bound_radii`` (n_links,) [m]
    enclose each link's cover.
    """

    links: tuple[str, ...]
    centres: np.ndarray
    radii: np.ndarray
    bound_centres: np.ndarray
    bound_radii: np.ndarray

    def cover(self, row: int) -> tuple[np.ndarray, np.ndarray]:
        """The cover of the link in ``row``: centres (k, 3) and radii (k,) [m], padding dropped."""
        keep = np.isfinite(self.radii[row])
        return self.centres[row][keep], self.radii[row][keep]

    @functools.cached_property
    def width_class(self) -> np.ndarray:
        """Per link, the number of cover slots worth testing: its sphere count (covers are
        stored first, padding after), shape (n_links,)."""
        return np.maximum(np.isfinite(self.radii).sum(axis=1), 1)

    @functools.cached_property
    def bound_radii32(self) -> np.ndarray:
        """``bound_radii`` in single precision, grown by :data:`SINGLE_PRECISION_SLACK_M`."""
        return (self.bound_radii + SINGLE_PRECISION_SLACK_M).astype(np.float32)

    @functools.cached_property
    def radii32(self) -> np.ndarray:
        """``radii`` in single precision, grown by :data:`SINGLE_PRECISION_SLACK_M`."""
        return (self.radii + SINGLE_PRECISION_SLACK_M).astype(np.float32)


def link_spheres(scene: CollisionScene, links: Sequence[str] | None = None) -> LinkSpheres:
    """Covers of the collision shapes of ``links`` (default: every scene link), one row per
    link in that order, from the scene's support points (hull vertices, box corners, rim
    points) grown by their pad."""
    names = tuple(scene.links if links is None else links)
    covers = []
    for name in names:
        covers.append([ball for shape in scene.scene_shapes(name) for ball in shape.cover])
    width = max((len(c) for c in covers), default=1) or 1
    n = len(names)
    centres = np.zeros((n, width, 3))
    radii = np.full((n, width), ABSENT)
    bound_centres = np.zeros((n, 3))
    bound_radii = np.zeros(n)
    for i, cover in enumerate(covers):
        if not cover:
            continue
        c = np.array([b[0] for b in cover])
        r = np.array([b[1] for b in cover])
        centres[i, : len(cover)] = c
        radii[i, : len(cover)] = r
        mid = 0.5 * ((c - r[:, None]).min(axis=0) + (c + r[:, None]).max(axis=0))
        bound_centres[i] = mid
        bound_radii[i] = float((np.linalg.norm(c - mid, axis=1) + r).max())
    return LinkSpheres(names, centres, radii, bound_centres, bound_radii)


def world_bounds(transforms: np.ndarray, spheres: LinkSpheres) -> np.ndarray:
    """Bounding sphere centres (b, n_links, 3) in the world [m] for link ``transforms`` (b, n_links, 4, 4)."""
    rot, shift = transforms[:, :, :3, :3], transforms[:, :, :3, 3]
    return np.asarray(np.matmul(rot, spheres.bound_centres[:, :, None])[..., 0] + shift)


def bound_gaps(bounds: np.ndarray, spheres: LinkSpheres, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Gap [m] between the bounding spheres of link pairs (``first``, ``second``: (P,) link
    rows) given their world centres ``bounds`` (b, n_links, 3): shape (b, P), single
    precision (radii grown by :data:`SINGLE_PRECISION_SLACK_M`); <= 0 overlap."""
    # link-major: gathering whole (b, 3) blocks per pair is much cheaper than along axis 1
    centres = np.ascontiguousarray(bounds.astype(np.float32).transpose(1, 0, 2))
    d = centres[first] - centres[second]
    radii = spheres.bound_radii32
    gaps = np.sqrt(np.einsum("pbi,pbi->pb", d, d)) - (radii[first] + radii[second])[:, None]
    return np.ascontiguousarray(gaps.T)


def _norms(d: np.ndarray) -> np.ndarray:
    return np.sqrt(np.einsum("...i,...i->...", d, d))


def world_covers(
    transforms: np.ndarray, bounds: np.ndarray, spheres: LinkSpheres, links: np.ndarray | None = None
) -> np.ndarray:
    """Cover sphere centres (b, n_links, k, 3) in the world [m], single precision, for link
    ``transforms`` (b, n_links, 4, 4) and world bounding-sphere centres ``bounds`` (b,
    n_links, 3); only for the link rows ``links`` when given (the others are left unset).
    Only the first ``width_class`` slots of a link are filled: a one-sphere cover is its
    bounding sphere, and the padding is never read."""
    n_samples, n_links = transforms.shape[:2]
    out = np.empty((n_samples, n_links, spheres.centres.shape[1], 3), dtype=np.float32)
    wanted = np.zeros(n_links, dtype=bool)
    wanted[np.arange(n_links) if links is None else links] = True
    widths = spheres.width_class
    single = wanted & (widths == 1)
    out[:, single, 0] = bounds[:, single]
    for k in np.unique(widths[wanted & (widths > 1)]).tolist():
        rows = np.nonzero(wanted & (widths == k))[0]
        placed_links = transforms[:, rows]
        rot, shift = placed_links[..., :3, :3], placed_links[..., :3, 3]
        placed = np.matmul(rot, np.swapaxes(spheres.centres[rows, :k], 1, 2)).swapaxes(2, 3) + shift[:, :, None, :]
        out[:, rows, :k] = placed
    return out


def cover_gaps(
    covers: np.ndarray,
    bounds: np.ndarray,
    spheres: LinkSpheres,
    samples: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
) -> np.ndarray:
    """Gap [m] between the covers of links ``first[i]`` and ``second[i]`` in configuration
    ``samples[i]`` (all (M,)), a lower bound of the links' distance; <= 0 when some cover
    spheres overlap. ``covers`` (b, n_links, k, 3) and ``bounds`` (b, n_links, 3) are the
    world centres of the cover and bounding spheres (:func:`world_covers`, :func:`world_bounds`).
    Each cover is first tested against the other
    link's bounding sphere (2 k tests), the k x k sphere pairs only where that does not
    separate them; rows are grouped by cover size so that small covers skip the padding,
    and two one-sphere covers are their bounding spheres."""
    bound_r = spheres.bound_radii + SINGLE_PRECISION_SLACK_M
    d = bounds[samples, first] - bounds[samples, second]
    out = _norms(d) - spheres.bound_radii[first] - spheres.bound_radii[second]
    bounds32 = bounds.astype(np.float32)
    wa, wb = spheres.width_class[first], spheres.width_class[second]
    for ka, kb in sorted(set(zip(wa.tolist(), wb.tolist(), strict=True))):
        if ka == 1 and kb == 1:
            continue
        rows = np.nonzero((wa == ka) & (wb == kb))[0]
        s, a, b = samples[rows], first[rows], second[rows]
        ra, rb = spheres.radii32[a, :ka], spheres.radii32[b, :kb]
        ca, cb = covers[s, a, :ka], covers[s, b, :kb]
        to_b = (_norms(ca - bounds32[s, b][:, None, :]) - ra).min(axis=1) - bound_r[b]
        to_a = (_norms(cb - bounds32[s, a][:, None, :]) - rb).min(axis=1) - bound_r[a]
        gap = np.maximum(to_b, to_a)
        need = np.nonzero(gap <= 0)[0]
        for lo in range(0, len(need), 65536):  # bounded memory: rows x ka x kb distances
            sub = need[lo : lo + 65536]
            pair_gaps = _norms(ca[sub][:, :, None, :] - cb[sub][:, None, :, :])
            pair_gaps = pair_gaps - ra[sub][:, :, None] - rb[sub][:, None, :]
            gap[sub] = pair_gaps.reshape(len(sub), -1).min(axis=1)
        out[rows] = gap
    return out
