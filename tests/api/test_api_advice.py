"""Service answers speak of the upload, not of command-line flags an HTTP user cannot pass."""

from __future__ import annotations

from pathlib import Path

import pytest
from apitools import post_xml, post_zip, zip_bytes
from fastapi.testclient import TestClient

from geomcheck.cli import main

MISSING_PACKAGE = b"""<?xml version="1.0"?>
<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find gripper_description)/urdf/gripper.xacro"/>
  <link name="base"/>
</robot>
"""

MESH_IN_MISSING_PACKAGE = b"""<?xml version="1.0"?>
<robot name="r">
  <link name="base">
    <visual><geometry><mesh filename="package://gripper_description/meshes/base.stl"/></geometry></visual>
  </link>
</robot>
"""


def test_an_unknown_package_in_an_upload_asks_for_it_in_the_upload(client: TestClient) -> None:
    answer = post_zip(client, zip_bytes({"robot.urdf.xacro": MISSING_PACKAGE}), root="robot.urdf.xacro")
    assert answer.status_code == 422, answer.text
    detail = answer.json()["detail"]
    assert "package 'gripper_description' not found" in detail
    assert "add the package to the upload" in detail and "<name>gripper_description</name>" in detail
    assert "--package" not in detail and "--search" not in detail


def test_a_mesh_of_an_unknown_package_in_an_upload_says_the_same(client: TestClient) -> None:
    answer = post_xml(client, MESH_IN_MISSING_PACKAGE)
    assert answer.status_code == 201, answer.text
    (finding,) = [d for d in answer.json()["report"]["diagnostics"] if d["code"] == "GC202"]
    assert finding["help"].startswith("Add the package to the upload: a folder holding its package.xml")
    assert "--package" not in finding["help"] and "--search" not in finding["help"]


def test_the_cli_keeps_its_flags(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "robot.urdf.xacro").write_bytes(MISSING_PACKAGE)
    assert main(["check", str(tmp_path / "robot.urdf.xacro"), "--format", "concise"]) == 2
    assert "pass --package gripper_description=DIR or --search DIR" in capsys.readouterr().err


TWO_LINKS_URDF = (
    b'<robot name="two"><link name="a"/><link name="b"/>'
    b'<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>'
)


def test_a_zip_sent_as_xml_is_read_as_a_zip(client: TestClient) -> None:
    body = zip_bytes({"robots/two.urdf": TWO_LINKS_URDF})
    answer = client.post("/v1/checks", content=body, headers={"content-type": "application/xml"})
    assert answer.status_code == 201, answer.text
    assert answer.json()["report"]["robot"]["name"] == "two"


def test_xml_sent_as_a_zip_is_read_as_xml(client: TestClient) -> None:
    answer = client.post("/v1/checks", content=TWO_LINKS_URDF, headers={"content-type": "application/zip"})
    assert answer.status_code == 201, answer.text
    assert answer.json()["report"]["robot"]["links"] == 2


def test_a_zip_of_meshes_only_says_the_description_is_missing(client: TestClient) -> None:
    answer = post_zip(client, zip_bytes({"meshes/base.stl": b"solid x\nendsolid x\n", "meshes/arm.stl": b""}))
    assert answer.status_code == 400, answer.text
    detail = answer.json()["detail"]
    assert detail.startswith(
        "the upload holds no robot description (URDF or xacro .urdf/.xacro, MJCF .xml, SDFormat .sdf): add it"
    )
    assert "meshes/arm.stl, meshes/base.stl" in detail and "root" not in detail


@pytest.mark.parametrize("content_type", ["application/xml", "application/zip"])
def test_an_empty_body_names_no_file_the_user_never_sent(client: TestClient, content_type: str) -> None:
    answer = client.post("/v1/checks", content=b"", headers={"content-type": content_type})
    assert answer.status_code in (400, 422), answer.text
    detail = answer.json()["detail"]
    assert detail.startswith("empty request body; send a URDF or xacro document")
    assert "robot.urdf" not in detail


def test_a_check_links_every_download_the_docs_list(client: TestClient) -> None:
    body = post_xml(client, TWO_LINKS_URDF).json()
    links = body["links"]
    expected = {"report.json", "report.html", "report.sarif", "report.junit.xml", "fixes.patch"}
    assert {link.rsplit("/", 1)[1] for key, link in links.items() if key not in ("self", "collision_matrix_srdf")} == (
        expected
    )
    for key, link in links.items():
        if link is not None:
            assert client.get(link).status_code == 200, key


SDF_BOX = b"""<?xml version="1.0"?>
<sdf version="1.7"><model name="cart">
  <link name="body"><inertial><mass>2</mass><inertia><ixx>0.02</ixx><iyy>0.02</iyy><izz>0.02</izz></inertia></inertial>
    <collision name="c"><geometry><box><size>0.2 0.2 0.2</size></box></geometry></collision>
    <visual name="v"><geometry><box><size>0.2 0.2 0.2</size></box></geometry></visual></link>
  <include><uri>model://wheel</uri><pose>0 0.15 0 0 0 0</pose></include>
  <joint name="axle" type="revolute"><parent>body</parent><child>wheel::rim</child><axis><xyz>0 1 0</xyz></axis></joint>
</model></sdf>"""
SDF_WHEEL = b"""<sdf version="1.7"><model name="wheel"><link name="rim">
  <inertial><mass>0.5</mass><inertia><ixx>0.001</ixx><iyy>0.001</iyy><izz>0.001</izz></inertia></inertial>
  <collision name="c"><geometry><sphere><radius>0.05</radius></sphere></geometry></collision></link></model></sdf>"""


def test_an_sdformat_model_folder_is_checked_from_its_evident_root(client: TestClient) -> None:
    files = {"cart/model.sdf": SDF_BOX, "cart/model.config": b"<model/>", "wheel/model.sdf": SDF_WHEEL}
    answer = post_zip(client, zip_bytes(files))
    assert answer.status_code == 201, answer.text
    robot = answer.json()["report"]["robot"]
    assert (robot["name"], robot["links"], robot["joints"]) == ("cart", 2, 1)
    assert robot["source"].endswith("cart/model.sdf")
