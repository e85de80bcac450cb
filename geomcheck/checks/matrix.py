"""The collision matrix (``--matrix``) and the SRDF audit (``--srdf``, GC410-GC416).

The matrix is the run's ``ctx.analyses.matrix`` (:func:`collision_matrix`), computed once
from the kinematics, collision scene and default pose the self-collision family shares.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.selfcollision import (
    adjacency,
    collision_scene,
    default_configuration,
    kinematics,
    not_pairs,
    rigidly_attached,
    srdf,
)
from geomcheck.load import Bundle, LoadedDescription, MeshStore, load_description, mesh_formats
from geomcheck.options import CheckOptions
from geomcheck.selfcollision.audit import audit_srdf
from geomcheck.selfcollision.default_pose import contacts_at
from geomcheck.selfcollision.matrix import CollisionMatrix

PROXY_MARGIN_M = 0.005  # a proxy's geometry may leave this much of the part it stands for out [m]


def collision_matrix(ctx: CheckContext) -> CollisionMatrix:
    """The run's :class:`CollisionMatrix` (computed once, with a progress bar when asked)."""
    return ctx.analyses.matrix


def run(ctx: CheckContext) -> FamilyResult:
    result = FamilyResult()
    if not (ctx.options.matrix or ctx.options.srdf is not None) or not ctx.robot.links:
        return result
    matrix = collision_matrix(ctx)
    result.sections["matrix"] = matrix.to_section()
    # the audit is of a --srdf: the description's own collision filter (MJCF) is MuJoCo's rule, not a list to audit
    document = srdf(ctx) if ctx.options.srdf is not None else None
    if document is not None:
        adjacent = adjacency(ctx)  # without the pairs the semantics does not check
        kin, scene, skip = kinematics(ctx), collision_scene(ctx), not_pairs(ctx)

        def audited(a: str, b: str) -> bool:  # adjacent, or rigidly attached (GC403 leaves these to the audit)
            pair = (min(a, b), max(a, b))
            return pair in adjacent or (pair not in skip and rigidly_attached(ctx, a, b))

        base = default_configuration(ctx)
        touching = contacts_at(kin, scene, base, keep=audited)
        contacts = {c.links: c.depth for c in touching}

        def collides(pair: tuple[str, str], values: Mapping[str, float]) -> bool:
            q = base.copy()
            variables = {j.name: i for i, j in enumerate(kin.joints)}
            for name, value in values.items():
                if name in variables:  # a mimic joint follows its leader's value
                    q[variables[name]] = value
            frames = kin.link_transforms(q[None], pair)[0]
            return bool(scene.pair_collide(pair[0], frames[0], pair[1], frames[1])[0])

        result.diagnostics += audit_srdf(document, matrix, ctx.robot, contacts, collides, stands_for(ctx))
    return result


def stands_for(ctx: CheckContext) -> Callable[[str, str], bool]:
    """Whether a link's collision geometry holds another's, rigidly attached to it: a proxy (Franka's
    capsule ``*_sc`` links) standing for the part in the SRDF's enabled pairs. Held: the other's
    surface points (primitives' tessellation, meshes' hull vertices) within ``PROXY_MARGIN_M`` of
    the proxy's elements, over ``min_coverage`` of them."""
    from geomcheck.checks.fit import link_elements
    from geomcheck.geometry.reach import element_corners
    from geomcheck.geometry.shapes import primitive_mesh

    kin = kinematics(ctx)
    frames = dict(zip(kin.link_names, kin.link_transforms(kin.default_configuration()[None])[0], strict=True))

    def surface(link: str) -> np.ndarray:
        elements = link_elements(ctx, ctx.robot.link_map[link])
        if isinstance(elements, str):
            return np.zeros((0, 3))
        points = [
            primitive_mesh(e.primitive).vertices @ np.asarray(e.rotation).T + np.asarray(e.translation)
            if e.primitive is not None
            else element_corners(e)
            for e in elements
        ]
        return np.concatenate(points) if points else np.zeros((0, 3))

    def holds(proxy: str, link: str) -> bool:
        elements = link_elements(ctx, ctx.robot.link_map[proxy])
        points = surface(link)
        if isinstance(elements, str) or not elements or not len(points) or proxy not in frames or link not in frames:
            return False
        relative = np.linalg.inv(frames[proxy]) @ frames[link]
        local = points @ relative[:3, :3].T + relative[:3, 3]
        distance = np.min([e.signed_distance(local) for e in elements], axis=0)
        return bool(np.mean(distance <= PROXY_MARGIN_M) >= ctx.thresholds.fit.min_coverage)

    return holds


def matrix_of(loaded: LoadedDescription, options: CheckOptions) -> CollisionMatrix:
    """The collision matrix of an already loaded description (``geomcheck matrix``)."""
    meshes = MeshStore(loaded.bundle, options.thresholds.limits, mesh_formats(loaded.format))
    ctx = CheckContext(loaded=loaded, meshes=meshes, options=options)
    return collision_matrix(ctx)


def load_and_compute(bundle: Bundle, options: CheckOptions) -> tuple[LoadedDescription, CollisionMatrix]:
    """Load ``bundle`` and compute its collision matrix."""
    loaded = load_description(bundle, options.args, options.thresholds.limits)
    return loaded, matrix_of(loaded, options)
