"""``GET /v1/checks/{id}/fixes.patch``: the fixes of a check's findings as a unified diff
against the uploaded files, safe ones by default, all of them with ``unsafe=true``."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from apitools import EXAMPLE, EXAMPLE_ROOT, post_xml, post_zip, verified_check, zip_folder
from fastapi.testclient import TestClient

import geomcheck

TYPO = b"""<robot name="typo">
  <link name="base"/>
  <link name="arm"/>
  <joint name="j" type="fixed"><origin xzy="0 0 1"/><parent link="base"/><child link="arm"/></joint>
</robot>
"""


def test_the_safe_patch_of_a_bare_urdf(client: TestClient) -> None:
    created = post_xml(client, TYPO, root="typo.urdf").json()
    response = client.get(f"/v1/checks/{created['id']}/fixes.patch")
    assert response.status_code == 200
    assert response.headers["content-type"] == "text/x-diff; charset=utf-8"
    assert response.headers["content-disposition"] == 'attachment; filename="typo-fixes.patch"'
    assert response.text == (
        "--- a/typo.urdf\n+++ b/typo.urdf\n@@ -1,5 +1,5 @@\n"
        ' <robot name="typo">\n   <link name="base"/>\n   <link name="arm"/>\n'
        '-  <joint name="j" type="fixed"><origin xzy="0 0 1"/><parent link="base"/><child link="arm"/></joint>\n'
        '+  <joint name="j" type="fixed"><origin xyz="0 0 1"/><parent link="base"/><child link="arm"/></joint>\n'
        " </robot>\n"
    )
    (fix,) = created["report"]["sections"]["fixes"]["fixes"]
    assert (fix["code"], fix["applicability"], fix["applicable"]) == ("GC106", "safe", True)


def test_the_examples_patches_add_no_finding(client: TestClient, tmp_path: Path) -> None:
    answered = post_zip(client, zip_folder(EXAMPLE), root=EXAMPLE_ROOT).json()
    # the report first, offering the planned patches; the verified ones follow
    assert answered["report"]["sections"]["fixes"]["verified"] is False
    assert answered["fixes"]["status"] in ("verifying", "verified")
    safe = client.get(f"/v1/checks/{answered['id']}/fixes.patch")  # waits for the verification
    assert safe.status_code == 200 and safe.headers["geomcheck-fixes"] == "verified"
    created = verified_check(client, answered["id"])
    assert created["fixes"] == {"status": "verified", "reason": None}
    assert created["report"]["sections"]["fixes"]["verified"] is True
    assert created["progress"] is None
    # the safe fixes: the four legacy xacro files in today's syntax
    assert [line for line in safe.text.splitlines() if line.startswith("+++ ")] == [
        "+++ b/robots/pr2_base.urdf.xacro",
        "+++ b/urdf/base.urdf.xacro",
        "+++ b/urdf/common.xacro",
        "+++ b/urdf/laser.urdf.xacro",
    ]
    assert '+  <xacro:include filename="$(find pr2_base_example)/urdf/common.xacro" />' in safe.text.splitlines()
    unsafe_response = client.get(f"/v1/checks/{created['id']}/fixes.patch", params={"unsafe": "true"})
    # safe and unsafe patches download under names of their own (curl -O -J keeps both)
    assert unsafe_response.headers["content-disposition"] == (
        'attachment; filename="pr2_base_example-unsafe-fixes.patch"'
    )
    unsafe = unsafe_response.text
    assert [line for line in unsafe.splitlines() if line.startswith("+++ ")] == [
        "+++ b/robots/pr2_base.urdf.xacro",
        "+++ b/urdf/base.urdf.xacro",
        "+++ b/urdf/common.xacro",
        "+++ b/urdf/laser.urdf.xacro",
    ]
    # the base is refitted as boxes clear of the casters, not one 0.9 m box through them
    assert '+  <xacro:property name="base_collision_size_z" value="0.9" />' not in unsafe.splitlines()
    assert sum(line.startswith("+      <collision>") for line in unsafe.splitlines()) >= 2
    # ... and the section lists that fix as applied, saying why it is not the help's one box
    (base,) = [f for f in created["report"]["sections"]["fixes"]["fixes"] if f["subject"] == "link base_link"]
    assert base["title"].startswith("replace the box by ")
    assert "the fitted box would overlap them by up to" in base["title"]
    assert '+        <inertia ixx="0.00071258" ixy="0" ixz="0"' in unsafe.splitlines()
    # applied with git, the patch leaves fewer findings and adds none
    copy = tmp_path / "pr2_base"
    shutil.copytree(EXAMPLE, copy)
    subprocess.run(["git", "apply", "-p1", "-"], cwd=copy, input=unsafe.encode(), check=True)
    before = {d["fingerprint"] for d in created["report"]["diagnostics"]}
    after = {d.fingerprint for d in geomcheck.check(copy / EXAMPLE_ROOT, use_config=False).diagnostics}
    assert after < before


def test_verification_turned_off_offers_the_planned_patches_marked_so(client: TestClient) -> None:
    created = post_xml(client, TYPO, root="typo.urdf", verify_fixes="false").json()
    assert created["fixes"] == {"status": "unverified", "reason": None}
    assert created["report"]["sections"]["fixes"]["verified"] is False
    response = client.get(f"/v1/checks/{created['id']}/fixes.patch")
    assert response.headers["geomcheck-fixes"] == "unverified"
    assert '+  <joint name="j" type="fixed"><origin xyz="0 0 1"/>' in response.text
    # the same request with verification on is not answered from that report
    again = post_xml(client, TYPO, root="typo.urdf").json()
    assert again["cached"] is False and again["fixes"]["status"] in ("verifying", "verified")


def test_an_unknown_check_has_no_patch(client: TestClient) -> None:
    response = client.get("/v1/checks/nosuchcheck/fixes.patch")
    assert response.status_code == 404
    assert "nosuchcheck" in response.json()["detail"]
