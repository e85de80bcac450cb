"""Numbers of a compiled MJCF model held to the load limits, as the URDF and SDFormat loaders
hold theirs: a size, position, mass, inertia or mesh scale beyond them (``size="1e308 1 1"``,
or the infinite mass MuJoCo infers from such a box) is refused at load naming its element,
before any check multiplies it into infinities (it used to end in an internal error: "Out of
range float values are not JSON compliant"). MuJoCo compiles such numbers without complaint;
what it computed from them is read from the compiled model, so a number an included file or a
default class wrote is caught as well as one written on the element.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np

from geomcheck.errors import InputError

if TYPE_CHECKING:
    from geomcheck.model import SourceLocation
    from geomcheck.thresholds import LoadLimits

# geom types of mjtGeom, and how many of geom_size's entries each one's shape reads
_SIZES_READ = {2: 1, 3: 2, 4: 3, 5: 2, 6: 3}  # sphere, capsule, ellipsoid, cylinder, box
_SLIDE = 2  # mjtJoint


def _beyond(values: np.ndarray, bound: float) -> float | None:
    """The first of ``values`` whose magnitude is beyond ``bound`` (or not a number), else None."""
    flat = np.asarray(values, dtype=float).ravel()
    bad = ~(np.abs(flat) <= bound)
    return float(flat[np.argmax(bad)]) if bad.any() else None


def _below(values: np.ndarray, floor: float) -> float | None:
    """The first nonzero of ``values`` whose magnitude is below ``floor``, else None."""
    flat = np.abs(np.asarray(values, dtype=float).ravel())
    tiny = (flat > 0.0) & (flat < floor)
    return float(flat[np.argmax(tiny)]) if tiny.any() else None


def _refuse(where: SourceLocation | str, element: str, what: str, value: float, limit: float, name: str) -> InputError:
    side = "below the smallest size of" if abs(value) < limit else "beyond the limit of"
    return InputError(f"{where}: {element} {what} {value:g} is {side} {limit:g} ({name})")


def check_magnitudes(model: Any, mapper: Any, limits: LoadLimits) -> None:
    """:class:`InputError` naming the first geom, joint, mesh or body of ``model`` whose compiled
    numbers are beyond ``limits`` (or below their floor, for sizes and scales); ``mapper`` (a
    :class:`geomcheck.load.mjcf.Mapper`) locates them."""
    length, mass, inertia = limits.max_length_m, limits.max_mass_kg, limits.max_inertia_kg_m2
    for b, g, found in _geoms(model, mapper):
        where = mapper.location(*found) if found else mapper.body_location(b)
        geom = mapper.name(mapper.mujoco.mjtObj.mjOBJ_GEOM, g)
        element = f"<geom name='{geom}'>" if geom else f"<geom> of body '{mapper.body_name(b)}'"
        sizes = model.geom_size[g][: _SIZES_READ.get(int(model.geom_type[g]), 0)]
        for what, values, bound, name in (
            ("size", sizes, length, "max_length_m"),
            ("pos", model.geom_pos[g], length, "max_length_m"),
        ):
            if (value := _beyond(values, bound)) is not None:
                raise _refuse(where, element, what, value, bound, name)
        if (value := _below(sizes, limits.min_size_m)) is not None:
            raise _refuse(where, element, "size", value, limits.min_size_m, "min_size_m")
    for j in range(int(model.njnt)):
        b = int(model.jnt_bodyid[j])
        joint = mapper.name(mapper.mujoco.mjtObj.mjOBJ_JOINT, j)
        element = f"<joint name='{joint}'>" if joint else f"<joint> of body '{mapper.body_name(b)}'"
        checked = [("pos", model.jnt_pos[j])]
        if int(model.jnt_type[j]) == _SLIDE and bool(model.jnt_limited[j]):
            checked.append(("range", model.jnt_range[j]))
        for what, values in checked:
            if (value := _beyond(values, length)) is not None:
                raise _refuse(mapper.body_location(b), element, what, value, length, "max_length_m")
    for m in range(int(model.nmesh)):
        element = f"<mesh name='{mapper.name(mapper.mujoco.mjtObj.mjOBJ_MESH, m) or m}'>"
        scale, shown = model.mesh_scale[m], mapper.root_display
        if (value := _beyond(scale, limits.max_mesh_scale)) is not None:
            raise _refuse(shown, element, "scale", value, limits.max_mesh_scale, "max_mesh_scale")
        if (value := _below(scale, limits.min_mesh_scale)) is not None:
            raise _refuse(shown, element, "scale", value, limits.min_mesh_scale, "min_mesh_scale")

    # last: a body's mass and inertia are often what MuJoCo inferred from a geom named above
    for b in range(1, int(model.nbody)):
        where, element = mapper.body_location(b), f"<body name='{mapper.body_name(b)}'>"
        for what, values, bound, name in (
            ("pos", model.body_pos[b], length, "max_length_m"),
            ("inertial pos", model.body_ipos[b], length, "max_length_m"),
            ("mass", model.body_mass[b : b + 1], mass, "max_mass_kg"),
            ("inertia", model.body_inertia[b], inertia, "max_inertia_kg_m2"),
        ):
            if (value := _beyond(values, bound)) is not None:
                raise _refuse(where, element, what, value, bound, name)


def _geoms(model: Any, mapper: Any) -> Iterable[tuple[int, int, Any]]:
    """Every geom with its body and its element (or None), matched as the mapping matches them."""
    for b in range(int(model.nbody)):
        first, count = int(model.body_geomadr[b]), int(model.body_geomnum[b])
        geoms = range(first, first + count) if first >= 0 else range(0)
        entry = mapper.body_xml[b]
        names = [mapper.name(mapper.mujoco.mjtObj.mjOBJ_GEOM, g) for g in geoms]
        elements = mapper.matched(entry.geoms if entry else [], len(geoms), names)
        yield from ((b, g, found) for g, found in zip(geoms, elements, strict=True))
