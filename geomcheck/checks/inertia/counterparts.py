"""GC510: left and right counterparts whose inertials are not mirror images of each other.

Counterparts (:mod:`geomcheck.geometry.counterparts`) whose geometry is mirrored too (their
shapes' extents in the world frame at the default pose agree, mirrored, within
`counterpart_geometry_fraction`) must carry mirrored inertials: the same mass, the centre of mass
reflected across the sagittal plane, the tensor reflected. A description fixed on one side and
not the other, or copied without mirroring (a right leg carrying the left's centre of mass),
breaks that.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from geomcheck.diagnostics import Diagnostic
from geomcheck.geometry.counterparts import MIRROR, Counterparts, counterparts, mirror_tensor
from geomcheck.geometry.inertia import MassProperties, mass_properties
from geomcheck.kinematics import Kinematics
from geomcheck.model import Mesh, Robot
from geomcheck.rules.inertia import COUNTERPART_INERTIA
from geomcheck.thresholds import InertiaThresholds


def world_origins(kin: Kinematics) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Each link's world transform (4, 4) and origin (3,) at the default pose (0 or mid-range)."""
    frames = kin.link_transforms(kin.default_configuration()[None])[0]
    transforms = {name: frames[i] for i, name in enumerate(kin.link_names)}
    return transforms, {name: t[:3, 3] for name, t in transforms.items()}


def world_extent(points: np.ndarray, transform: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper corners (3,) of link-frame ``points`` (n, 3) moved to the world."""
    world = points @ transform[:3, :3].T + transform[:3, 3]
    return world.min(axis=0), world.max(axis=0)


def mirrored_geometry(a: np.ndarray, b: np.ndarray, ta: np.ndarray, tb: np.ndarray, share: float) -> bool:
    """Whether link-frame point sets ``a`` and ``b`` occupy mirror-image boxes in the world."""
    lo_a, hi_a = world_extent(a, ta)
    lo_a, hi_a = np.minimum(MIRROR @ lo_a, MIRROR @ hi_a), np.maximum(MIRROR @ lo_a, MIRROR @ hi_a)
    lo_b, hi_b = world_extent(b, tb)
    size = float(max(np.ptp([lo_a, hi_a], axis=0).max(), np.ptp([lo_b, hi_b], axis=0).max()))
    return size > 0.0 and bool(np.abs(lo_a - lo_b).max() <= share * size and np.abs(hi_a - hi_b).max() <= share * size)


def mirror_images(a: np.ndarray, b: np.ndarray, ta: np.ndarray, tb: np.ndarray, share: float) -> bool:
    """Whether link-frame point sets ``a`` and ``b`` are mirror images in the world, point by point:
    95% of each within ``share`` of their size of the other reflected. One part mounted unmirrored
    on both sides is its own mirror image when it is symmetric (a thigh symmetric about its plane of
    motion): then mirrored inertials fit it as well as identical ones."""
    from scipy.spatial import cKDTree  # only for parts drawn alike on both sides

    wa = (a @ ta[:3, :3].T + ta[:3, 3]) @ MIRROR.T
    wb = b @ tb[:3, :3].T + tb[:3, 3]
    size = float(max(np.ptp(wa, axis=0).max(), np.ptp(wb, axis=0).max()))
    apart = max(np.percentile(cKDTree(wb).query(wa)[0], 95), np.percentile(cKDTree(wa).query(wb)[0], 95))
    return size > 0.0 and float(apart) <= share * size


def check_counterparts(
    robot: Robot,
    kin: Kinematics,
    points_of: Callable[[str], np.ndarray | str],
    th: InertiaThresholds,
) -> Iterator[Diagnostic]:
    """GC510 for every counterpart pair with geometry mirrored and inertials that are not."""
    transforms, origins = world_origins(kin)
    for pair in counterparts([link.name for link in robot.links], origins, th.counterpart_origin_tolerance_m):
        found = _compare(robot, pair, transforms, points_of, th)
        if found is not None:
            yield found


def part_kinds(robot: Robot, pair: Counterparts) -> tuple[str, ...]:
    """How the two sides' parts relate, by their visual meshes: ``("identical",)`` when both draw
    the same mesh files at the same scales and places in their link frames (one part, mounted
    on both sides: a PR2's arms), ``("mirrored",)`` when they draw different files or scales (a
    left and a right part); both readings when they draw the same meshes placed differently (a
    mesh turned half a turn to serve the other side) or only primitives (a box is its own mirror
    image)."""
    drawn = [
        sorted(
            (s.geometry.filename, s.geometry.scale, s.origin.xyz, s.origin.rpy)
            for s in robot.link_map[name].visuals
            if isinstance(s.geometry, Mesh)
        )
        for name in (pair.left, pair.right)
    ]
    if drawn[0] == drawn[1]:
        return ("identical",) if drawn[0] else ("identical", "mirrored")
    files = [sorted((d[0], d[1]) for d in side) for side in drawn]
    return ("identical", "mirrored") if files[0] == files[1] else ("mirrored",)


@dataclass(frozen=True)
class Difference:
    """How far two inertials are apart under one reading of the parts (identical or mirrored)."""

    kind: str
    mass: float  # [fraction of the larger]
    com: float  # [m]
    tensor: float  # [fraction of the largest value per unit mass]

    def within(self, com_allowed: float, th: InertiaThresholds) -> bool:
        return (
            self.mass <= th.counterpart_mass_fraction
            and self.com <= com_allowed
            and self.tensor <= th.counterpart_tensor_fraction
        )


def part_frame(robot: Robot, link: str) -> tuple[np.ndarray, np.ndarray]:
    """The frame ``(rotation, translation)`` in the link frame that the link's first visual (or,
    without one, its first collision element) is drawn in: where an identical part sits."""
    shapes = robot.link_map[link].visuals or robot.link_map[link].collisions
    if not shapes:
        return np.eye(3), np.zeros(3)
    origin = shapes[0].origin
    return origin.rotation(), np.asarray(origin.xyz, dtype=float)


def difference(
    kind: str,
    a: MassProperties,
    b: MassProperties,
    ta: np.ndarray,
    tb: np.ndarray,
    frames: tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]],
) -> Difference:
    """The inertials' difference: for identical parts in the frames their geometry is drawn in
    (``frames``, one per side), for mirrored ones in the world with ``a`` reflected across the xz plane."""
    if kind == "identical":
        (ra, pa), (rb, pb) = frames
        com_a, com_b = ra.T @ (a.com - pa), rb.T @ (b.com - pb)
        tensor_a, tensor_b = ra.T @ a.tensor @ ra, rb.T @ b.tensor @ rb
    else:
        com_a = MIRROR @ (ta[:3, :3] @ a.com + ta[:3, 3])
        com_b = tb[:3, :3] @ b.com + tb[:3, 3]
        tensor_a = mirror_tensor(ta[:3, :3] @ a.tensor @ ta[:3, :3].T)
        tensor_b = tb[:3, :3] @ b.tensor @ tb[:3, :3].T
    # the tensors compared at the same mass: a mass difference is reported as such
    scale = max(float(np.abs(tensor_a).max()) / a.mass, float(np.abs(tensor_b).max()) / b.mass, 1e-300)
    return Difference(
        kind,
        abs(a.mass - b.mass) / max(a.mass, b.mass),
        float(np.linalg.norm(com_a - com_b)),
        float(np.abs(tensor_a / a.mass - tensor_b / b.mass).max()) / scale,
    )


def _compare(
    robot: Robot,
    pair: Counterparts,
    transforms: dict[str, np.ndarray],
    points_of: Callable[[str], np.ndarray | str],
    th: InertiaThresholds,
) -> Diagnostic | None:
    left, right = robot.link_map[pair.left], robot.link_map[pair.right]
    if left.inertial is None or right.inertial is None:
        return None
    pa, pb = points_of(left.name), points_of(right.name)
    ta, tb = transforms[left.name], transforms[right.name]
    if isinstance(pa, str) or isinstance(pb, str):
        return None
    if not mirrored_geometry(pa, pb, ta, tb, th.counterpart_geometry_fraction):
        return None
    a, b = mass_properties(left.inertial), mass_properties(right.inertial)
    if not (a.mass > 0.0 and b.mass > 0.0 and np.isfinite(a.tensor).all() and np.isfinite(b.tensor).all()):
        return None
    size = float(max(np.ptp(pa, axis=0).max(), np.ptp(pb, axis=0).max()))
    com_allowed = max(th.counterpart_com_m, th.counterpart_com_fraction * size)
    frames = (part_frame(robot, left.name), part_frame(robot, right.name))
    kinds = part_kinds(robot, pair)
    if kinds == ("identical",) and mirror_images(pa, pb, ta, tb, th.counterpart_geometry_fraction):
        kinds = ("identical", "mirrored")
    found = [difference(kind, a, b, ta, tb, frames) for kind in kinds]
    if any(d.within(com_allowed, th) for d in found):
        return None
    worst = min(found, key=lambda d: (d.mass > th.counterpart_mass_fraction) + d.com / com_allowed + d.tensor)
    reasons = []
    if worst.mass > th.counterpart_mass_fraction:
        reasons.append(COUNTERPART_INERTIA.message("mass", left=left.name, right=right.name, a=a.mass, b=b.mass))
    if worst.com > com_allowed:
        variant = {"identical": "com_identical", "mirrored": "com_mirrored"}[worst.kind]
        reasons.append(COUNTERPART_INERTIA.message(variant, right=right.name, left=left.name, distance=worst.com * 1e3))
    if worst.tensor > th.counterpart_tensor_fraction:
        variant = {"identical": "tensor_identical", "mirrored": "tensor_mirrored"}[worst.kind]
        reasons.append(COUNTERPART_INERTIA.message(variant, share=worst.tensor))
    location = right.inertial.location or right.location
    return COUNTERPART_INERTIA.diagnose(
        COUNTERPART_INERTIA.message(
            left=left.name,
            right=right.name,
            parts=COUNTERPART_INERTIA.message({"identical": "identical", "mirrored": "mirrored"}[worst.kind])
            if len(kinds) == 1
            else COUNTERPART_INERTIA.message("either"),
            reasons="; ".join(reasons),
        ),
        links=(left.name, right.name),
        about="inertia",
        location=location,
        data={
            "parts": worst.kind,
            "mass_difference": round(worst.mass, 4),
            "com_distance_mm": round(worst.com * 1000, 3),
            "com_allowed_mm": round(com_allowed * 1000, 3),
            "tensor_difference": round(worst.tensor, 4),
        },
    )
