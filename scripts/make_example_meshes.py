"""Generate the STL meshes of the bundled example package ``examples/pr2_base/meshes``.

The shapes are written anew for geomcheck, modelled on the 2009 PR2 mobile base: a base
shell with a 0.66 x 0.66 m footprint, caster wells in its corners and the rear spine housing
up to 0.90 m, a caster housing, a wheel of the uncompressed radius 0.079 m and width 0.034 m,
and a small scanning laser. Every mesh is in its link's frame, in metres (the frames of
``urdf/base.urdf.xacro``). The output is deterministic: the same trimesh and numpy give the
same bytes, and tests/test_example.py regenerates the files and compares them.

Usage: ``python scripts/make_example_meshes.py [--output DIR]``
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
import trimesh

DEFAULT_OUTPUT = Path(__file__).resolve().parent.parent / "examples" / "pr2_base" / "meshes"
STL_HEADER_BYTES = 80

# Base link frame: centre of the footprint, z = 0 at the bottom of the chassis (0.051 m above the floor).
BASE_HALF_WIDTH = 0.33  # half the footprint's side [m]
BASE_CHAMFER = 0.06  # corner chamfer of the footprint, along each side [m]
BASE_DECK_BOTTOM = 0.20  # underside of the deck, above the casters' tops (0.196 m) [m]
BASE_DECK_TOP = 0.23  # top surface of the base (base_size_z in the URDF) [m]
BASE_ARM_HALF_WIDTH = 0.095  # the chassis between the caster wells: a cross of two arms [m]
SPINE_X = (-0.325, -0.185)  # rear spine housing, front and back faces [m]
SPINE_HALF_WIDTH = 0.19  # [m]
SPINE_TOP = 0.90  # [m]

# Caster rotation link frame: on the swivel axis at wheel axle height.
CASTER_HUB = ((-0.05, -0.025, -0.025), (0.05, 0.025, 0.063))  # block between the wheels, min/max corner [m]
CASTER_PLATE = ((-0.0935, -0.075, 0.063), (0.0935, 0.075, 0.077))  # [m]
CASTER_COLUMN_RADIUS = 0.045  # swivel column [m]
CASTER_COLUMN_Z = (0.077, 0.168)  # [m]

# Wheel link frame: wheel centre, axis along y. Profile (radius, position along the axis) [m]:
# hub recessed into a tyre with rounded shoulders.
WHEEL_RADIUS = 0.079  # uncompressed tyre [m]
WHEEL_HALF_WIDTH = 0.017  # [m]
WHEEL_PROFILE = (
    (0.0, -0.012),
    (0.030, -0.012),
    (0.035, -WHEEL_HALF_WIDTH),
    (0.072, -WHEEL_HALF_WIDTH),
    (WHEEL_RADIUS, -0.010),
    (WHEEL_RADIUS, 0.010),
    (0.072, WHEEL_HALF_WIDTH),
    (0.035, WHEEL_HALF_WIDTH),
    (0.030, 0.012),
    (0.0, 0.012),
)
WHEEL_SECTIONS = 48

# Laser link frame: the scan plane, in the optical head; the body below it rests on the base's deck.
LASER_BODY = ((-0.025, -0.025, -0.022), (0.025, 0.025, -0.004))  # [m]
LASER_HEAD_RADIUS = 0.02  # [m]
LASER_HEAD_Z = (-0.004, 0.010)  # [m]

CYLINDER_SECTIONS = 48


def union(parts: Sequence[trimesh.Trimesh]) -> trimesh.Trimesh:
    """The parts as one mesh (closed bodies side by side; no boolean operation)."""
    merged = trimesh.util.concatenate(list(parts))
    assert isinstance(merged, trimesh.Trimesh)
    return merged


def box(lower: Sequence[float], upper: Sequence[float]) -> trimesh.Trimesh:
    """Axis-aligned box between two corners [m]."""
    lo, hi = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    return trimesh.creation.box(extents=hi - lo, transform=trimesh.transformations.translation_matrix((lo + hi) / 2))


def z_cylinder(radius: float, z_range: tuple[float, float]) -> trimesh.Trimesh:
    """Cylinder on the z axis between two heights [m]."""
    z0, z1 = z_range
    return trimesh.creation.cylinder(
        radius=radius,
        height=z1 - z0,
        sections=CYLINDER_SECTIONS,
        transform=trimesh.transformations.translation_matrix((0.0, 0.0, (z0 + z1) / 2)),
    )


def octagon_prism(half_width: float, chamfer: float, z_range: tuple[float, float]) -> trimesh.Trimesh:
    """Square of side ``2 * half_width`` with chamfered corners, extruded between two heights [m]."""
    h, c = half_width, chamfer
    corners = [(h, -h + c), (h, h - c), (h - c, h), (-h + c, h), (-h, h - c), (-h, -h + c), (-h + c, -h), (h - c, -h)]
    outline = np.array(corners, dtype=float)
    fan = np.array([(0, i, i + 1) for i in range(1, len(corners) - 1)])
    z0, z1 = z_range
    return trimesh.creation.extrude_triangulation(
        outline, fan, height=z1 - z0, transform=trimesh.transformations.translation_matrix((0.0, 0.0, z0))
    )


def base_mesh() -> trimesh.Trimesh:
    """Base shell: a deck over a cross-shaped chassis (caster wells in the four corners) and the
    rear spine housing; 0.66 x 0.66 x 0.90 m."""
    h, a = BASE_HALF_WIDTH, BASE_ARM_HALF_WIDTH
    parts = [
        box((-h, -a, 0.0), (h, a, BASE_DECK_BOTTOM)),
        box((-a, -h, 0.0), (a, h, BASE_DECK_BOTTOM)),
        octagon_prism(h, BASE_CHAMFER, (BASE_DECK_BOTTOM, BASE_DECK_TOP)),
        box((SPINE_X[0], -SPINE_HALF_WIDTH, BASE_DECK_TOP), (SPINE_X[1], SPINE_HALF_WIDTH, SPINE_TOP)),
    ]
    return union(parts)


def caster_mesh() -> trimesh.Trimesh:
    """Caster housing: the block between the two wheels, the top plate and the swivel column."""
    return union([box(*CASTER_HUB), box(*CASTER_PLATE), z_cylinder(CASTER_COLUMN_RADIUS, CASTER_COLUMN_Z)])


def wheel_mesh() -> trimesh.Trimesh:
    """Wheel of radius 0.079 m and width 0.034 m; revolved about z, then turned so its axis is y."""
    revolved = trimesh.creation.revolve(np.array(WHEEL_PROFILE, dtype=float), sections=WHEEL_SECTIONS)
    revolved.apply_transform(trimesh.transformations.rotation_matrix(-np.pi / 2, (1.0, 0.0, 0.0)))
    return revolved


def laser_mesh() -> trimesh.Trimesh:
    """Small scanning laser: body and optical head."""
    return union([box(*LASER_BODY), z_cylinder(LASER_HEAD_RADIUS, LASER_HEAD_Z)])


MESHES: dict[str, Callable[[], trimesh.Trimesh]] = {
    "base.stl": base_mesh,
    "caster.stl": caster_mesh,
    "wheel.stl": wheel_mesh,
    "laser.stl": laser_mesh,
}


def stl_bytes(name: str, mesh: trimesh.Trimesh) -> bytes:
    """Binary STL of ``mesh`` with a header naming the file and its generator."""
    body = trimesh.exchange.stl.export_stl(mesh)
    header = f"pr2_base_example {name}: scripts/make_example_meshes.py".encode("ascii")
    return header.ljust(STL_HEADER_BYTES, b" ")[:STL_HEADER_BYTES] + body[STL_HEADER_BYTES:]


def write_meshes(directory: Path) -> dict[str, Path]:
    """Write every mesh into ``directory`` (created if needed); returns the paths by file name."""
    directory.mkdir(parents=True, exist_ok=True)
    out = {}
    for name, build in MESHES.items():
        path = directory / name
        path.write_bytes(stl_bytes(name, build()))
        out[name] = path
    return out


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--output", type=Path, default=DEFAULT_OUTPUT, help="directory to write the STL files to")
    ns = parser.parse_args(argv)
    for path in write_meshes(ns.output).values():
        mesh = trimesh.load_mesh(path)
        extents = " x ".join(f"{e:.3f}" for e in mesh.extents)
        sys.stdout.write(f"{path}: {len(mesh.faces)} triangles, {extents} m\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
