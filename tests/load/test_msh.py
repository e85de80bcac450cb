"""MuJoCo's legacy binary mesh format: read for an MJCF model, as MuJoCo reads it; a format
only MuJoCo reads is still unsupported under a URDF."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from geomcheck.load import load_description, make_bundle, mesh_formats
from geomcheck.load.meshes import MeshProblem, MeshStore
from geomcheck.load.msh import read_msh
from geomcheck.model import Mesh

mujoco = pytest.importorskip("mujoco")

# a tetrahedron of 10 cm legs, faces wound outward
VERTICES = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]], dtype="<f4")
FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype="<i4")


def msh_bytes(
    vertices: np.ndarray = VERTICES, faces: np.ndarray = FACES, normals: int = 4, texcoords: int = 0
) -> bytes:
    counts = np.array([len(vertices), normals, texcoords, len(faces)], dtype="<i4")
    return b"".join(
        (
            counts.tobytes(),
            vertices.astype("<f4").tobytes(),
            np.zeros((normals, 3), dtype="<f4").tobytes(),
            np.zeros((texcoords, 2), dtype="<f4").tobytes(),
            faces.astype("<i4").tobytes(),
        )
    )


def test_a_msh_file_gives_its_vertices_and_faces() -> None:
    read = read_msh(msh_bytes(texcoords=4))
    assert read is not None
    vertices, faces = read
    assert vertices.dtype == np.float64 and faces.dtype == np.int64
    assert np.array_equal(vertices, VERTICES.astype(np.float64)) and np.array_equal(faces, FACES)


@pytest.mark.parametrize(
    "data",
    [
        msh_bytes()[:-1],  # a byte short of its counts
        msh_bytes() + b"\0",  # a byte past them
        msh_bytes(faces=np.array([[0, 1, 4]])),  # a face on a fifth vertex of four
        np.array([-1, 0, 0, 0], dtype="<i4").tobytes(),  # a negative count
        b"\0" * 12,  # shorter than the counts
    ],
    ids=["short", "long", "face-out-of-range", "negative", "no-header"],
)
def test_a_malformed_msh_is_refused(data: bytes) -> None:
    assert read_msh(data) is None


MODEL = """<mujoco><compiler meshdir="meshes"/>
  <asset><mesh name="tip" file="tip.msh"/></asset>
  <worldbody><body name="b"><geom type="mesh" mesh="tip"/></body></worldbody>
</mujoco>"""


def test_an_mjcf_model_reads_its_msh_meshes_as_mujoco_does(tmp_path: Path) -> None:
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "tip.msh").write_bytes(msh_bytes())
    root = tmp_path / "m.xml"
    root.write_text(MODEL, encoding="utf-8")
    loaded = load_description(make_bundle(root, display_root=tmp_path))
    (shape,) = loaded.robot.link_map["b"].collisions
    assert isinstance(shape.geometry, Mesh) and shape.geometry.filename == "meshes/tip.msh"
    mesh = MeshStore(loaded.bundle, formats=mesh_formats(loaded.format)).get(shape.geometry)
    assert not isinstance(mesh, MeshProblem)
    assert np.array_equal(mesh.vertices, VERTICES.astype(np.float64)) and len(mesh.faces) == 4
    model = mujoco.MjModel.from_xml_path(str(root))
    assert int(model.mesh_vertnum[0]) == 4 and int(model.mesh_facenum[0]) == 4  # MuJoCo's own count


def test_a_urdf_mesh_in_the_msh_format_is_unsupported(tmp_path: Path) -> None:
    """ROS's and Gazebo's mesh loaders do not know MuJoCo's format: GC203 says so."""
    from geomcheck.options import CheckOptions
    from geomcheck.pipeline import run_check

    (tmp_path / "tip.msh").write_bytes(msh_bytes())
    root = tmp_path / "robot.urdf"
    root.write_text(
        '<robot name="r"><link name="b"><visual><geometry><mesh filename="tip.msh"/></geometry></visual>'
        "</link></robot>",
        encoding="utf-8",
    )
    report = run_check(make_bundle(root, display_root=tmp_path), CheckOptions(workers=1))
    (finding,) = [d for d in report.diagnostics if d.code == "GC203"]
    assert (finding.link, finding.data["kind"]) == ("b", "unsupported-format")
    assert "unsupported mesh format '.msh'" in finding.message
