"""The HTTP API over small inline descriptions: submitting, reading, listing, auth, OpenAPI."""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path

from apitools import TWO_LINKS, burn_cpu, post_xml, sleep_long, zip_bytes
from fastapi.testclient import TestClient

from api.http.schemas import CheckOut, CheckPage, HealthOut, RuleOut
from geomcheck.report import Report, render
from geomcheck.rules import all_rules

MISSING_MESH = b"""<robot name="meshy">
  <link name="base_link">
    <visual><geometry><mesh filename="package://meshy_description/meshes/base.stl"/></geometry></visual>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
  </link>
</robot>
"""


def test_bare_urdf_answers_201_with_the_report_and_a_location(client: TestClient) -> None:
    response = post_xml(client, TWO_LINKS, root="two_links.urdf")
    assert response.status_code == 201, response.text
    body = response.json()
    check = CheckOut.model_validate(body)
    assert response.headers["location"] == f"/v1/checks/{check.id}"
    assert len(check.id) >= 22  # secrets.token_urlsafe(16): 128 random bits
    assert (check.status, check.robot, check.source) == ("succeeded", "two_links", "two_links.urdf")
    report = body["report"]
    assert report["schema"] == "geomcheck.report/1"
    assert report["robot"] == {
        "name": "two_links",
        "source": "two_links.urdf",
        "links": 2,
        "joints": 1,
        "meshes_total": 0,
        "meshes_loaded": 0,
    }
    assert check.summary is not None and check.summary.model_dump() == report["summary"]
    assert check.verdict == report["verdict"]


def test_absent_meshes_are_findings_not_failures(client: TestClient) -> None:
    body = post_xml(client, MISSING_MESH).json()
    report = body["report"]
    assert report["robot"]["meshes_total"] == 1 and report["robot"]["meshes_loaded"] == 0
    mesh = [d for d in report["diagnostics"] if d["code"].startswith("GC2")]
    assert [(d["code"], d["about"], d["location"]["file"], d["location"]["line"]) for d in mesh] == [
        ("GC202", "package:meshy_description", "robot.urdf", 3)
    ]
    assert [(r["link"], r["about"]) for r in mesh[0]["data"]["references"]] == [("base_link", "visual[0]")]
    assert "meshy_description" in mesh[0]["message"]
    assert any(s["check"] == "fit" and s["subject"] == "base_link" for s in report["skipped"])


def test_the_stored_check_and_its_downloads(client: TestClient) -> None:
    created = post_xml(client, TWO_LINKS, root="robots/two_links.urdf").json()
    check_id = created["id"]
    again = client.get(f"/v1/checks/{check_id}")
    assert again.status_code == 200
    assert again.json() == created

    as_json = client.get(f"/v1/checks/{check_id}/report.json")
    assert as_json.status_code == 200
    assert as_json.headers["content-type"] == "application/json"
    stored = Report.from_dict(json.loads(as_json.text))
    assert as_json.text == render(stored, "json")  # the bytes the CLI writes for the same report
    assert json.loads(as_json.text) == created["report"]

    page = client.get(f"/v1/checks/{check_id}/report.html")
    assert page.status_code == 200
    assert page.headers["content-type"] == "text/html; charset=utf-8"
    assert page.headers["content-disposition"] == 'attachment; filename="two_links-geomcheck.html"'
    assert page.text.lstrip().lower().startswith("<!doctype html>")
    assert "two_links" in page.text


def test_unknown_ids_and_missing_matrix(client: TestClient) -> None:
    missing = client.get("/v1/checks/nope")
    assert missing.status_code == 404 and missing.json() == {"detail": "no check with id 'nope'"}
    check_id = post_xml(client, TWO_LINKS).json()["id"]
    srdf = client.get(f"/v1/checks/{check_id}/collision-matrix.srdf")
    assert srdf.status_code == 404
    assert srdf.json()["detail"] == f"check {check_id} computed no collision matrix; submit it with matrix=true"


MATRIX_SECTION = {
    "samples": 200,
    "seed": 0,
    "backend": "coal",
    "always_fraction": 0.95,
    "links": ["base_link", "arm", "gripper"],
    "counts": {"adjacent": 2, "default": 0, "always": 0, "never": 1, "enabled": 0, "certified": 1},
    "pairs": [
        {
            "links": ["arm", "base_link"],
            "class": "adjacent",
            "fraction": None,
            "tested": 0,
            "min_distance": None,
            "certified": False,
            "clearance_bound": None,
            "witness": None,
        },
        {
            "links": ["arm", "gripper"],
            "class": "adjacent",
            "fraction": None,
            "tested": 0,
            "min_distance": None,
            "certified": False,
            "clearance_bound": None,
            "witness": None,
        },
        {
            "links": ["base_link", "gripper"],
            "class": "never",
            "fraction": 0.0,
            "tested": 0,
            "min_distance": 0.31,
            "certified": True,
            "clearance_bound": 0.25,
            "witness": None,
        },
    ],
}


def test_collision_matrix_srdf_download(client: TestClient) -> None:
    created = post_xml(client, TWO_LINKS).json()
    store = client.app.state.service.store  # type: ignore[attr-defined]
    report = {**created["report"], "sections": {**created["report"]["sections"], "matrix": MATRIX_SECTION}}
    store.create("with-matrix", "two_links.urdf", {})
    store.finish_ok("with-matrix", json.dumps(report), "two_links", "pass", report["summary"], True, 0.1)
    body = client.get("/v1/checks/with-matrix").json()
    assert body["links"]["collision_matrix_srdf"] == "/v1/checks/with-matrix/collision-matrix.srdf"
    srdf = client.get(body["links"]["collision_matrix_srdf"])
    assert srdf.status_code == 200
    assert srdf.headers["content-disposition"] == 'attachment; filename="two_links.srdf"'
    lines = srdf.text.splitlines()
    assert lines[0] == '<?xml version="1.0" encoding="UTF-8"?>'
    assert '<robot name="two_links">' in lines
    assert '    <disable_collisions link1="arm" link2="base_link" reason="Adjacent"/>' in lines
    assert (
        '    <disable_collisions link1="base_link" link2="gripper" reason="Never"/>'
        " <!-- certified: clearance >= 0.2500 m -->"
    ) in lines


def test_matrix_option_reaches_the_check(client: TestClient) -> None:
    body = post_xml(client, TWO_LINKS, matrix="true", samples="200").json()
    assert body["report"]["options"]["matrix"] is True and body["report"]["options"]["samples"] == 200
    if "matrix" in body["report"]["sections"]:
        assert client.get(body["links"]["collision_matrix_srdf"]).status_code == 200


def test_pinocchio_semantics_reaches_the_matrix(client: TestClient) -> None:
    # a camera box fixed inside the base: one rigid body for Pinocchio, Default for MoveIt
    body_text = TWO_LINKS.replace(
        b"</robot>",
        b'<link name="camera"><collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>'
        b'<joint name="camera_mount" type="fixed"><parent link="base_link"/><child link="camera"/></joint></robot>',
    )
    for semantics, pairs in (("moveit", [["base_link", "camera"]]), ("pinocchio", [])):
        body = post_xml(client, body_text, matrix="true", samples="50", semantics=semantics).json()
        assert body["report"]["options"]["semantics"] == semantics
        section = body["report"]["sections"]["matrix"]
        assert section["semantics"] == semantics and [p["links"] for p in section["pairs"]] == pairs
        srdf = client.get(body["links"]["collision_matrix_srdf"]).text
        assert ("Pinocchio semantics" in srdf) is (semantics == "pinocchio")


def test_wait_false_answers_202_and_the_check_finishes_in_the_background(client: TestClient) -> None:
    response = post_xml(client, TWO_LINKS, wait="false")
    assert response.status_code == 202
    body = response.json()
    assert body["status"] in ("queued", "running") and body["report"] is None
    assert response.headers["location"] == body["links"]["self"]
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        status = client.get(response.headers["location"]).json()
        if status["status"] == "succeeded":
            break
        time.sleep(0.05)
    assert status["status"] == "succeeded" and status["report"]["robot"]["name"] == "two_links"
    unfinished = client.get("/v1/checks", params={"status": "queued"}).json()["items"]
    assert body["id"] not in [c["id"] for c in unfinished]


def test_input_errors_are_4xx_and_recorded_failed(client: TestClient) -> None:
    response = post_xml(client, b"<robot name='x'><link name='a'></robot>", root="bad.urdf")
    assert response.status_code == 422
    detail = response.json()["detail"]
    assert detail.startswith("bad.urdf:1:") and "GC101" in detail and "\n" not in detail
    failed = client.get("/v1/checks", params={"status": "failed"}).json()["items"]
    assert failed[0]["reason"] == detail and failed[0]["http_status"] == 422
    assert client.get(f"/v1/checks/{failed[0]['id']}/report.json").status_code == 409


def test_options_are_validated_before_the_body_is_read(client: TestClient) -> None:
    cases = {
        "samples=0": "samples must be between 1 and 200000, got 0",
        "samples=abc": "samples must be an integer, got 'abc'",
        "samples=300000": "samples must be between 1 and 200000, got 300000",
        "backend=bullet": "backend: invalid value 'bullet'",
        "semantics=drake": "semantics: invalid value 'drake'",
        "fail_on=fatal": "fail-on: invalid value 'fatal'",
        "sampels=10": "unknown option 'sampels' in query (did you mean 'samples'?); valid names: args,",
        "select=GC999": "unknown rule code or family 'GC999'",
        "args=novalue": "args must be NAME=VALUE, got 'novalue'",
        "matrix=maybe": "invalid matrix 'maybe'; valid choices: true, false",
    }
    for query, expected in cases.items():
        response = client.post(f"/v1/checks?{query}", content=TWO_LINKS, headers={"content-type": "application/xml"})
        assert response.status_code == 400, (query, response.text)
        assert expected in response.json()["detail"], (query, response.json())
    same_twice = client.post("/v1/checks?seed=1&seed=2", content=TWO_LINKS, headers={"content-type": "application/xml"})
    assert same_twice.status_code == 400
    assert same_twice.json()["detail"] == "option seed given twice with different values ('1', '2')"


def test_every_unknown_option_is_reported_at_once_with_the_name_meant(client: TestClient) -> None:
    response = client.post(
        "/v1/checks?sampels=10&sede=3&colour=red", content=TWO_LINKS, headers={"content-type": "application/xml"}
    )
    assert response.status_code == 400
    detail = response.json()["detail"]
    problems, _, valid = detail.partition("; valid names: ")
    assert problems.split("; ") == [
        "unknown option 'sampels' in query (did you mean 'samples'?)",
        "unknown option 'sede' in query (did you mean 'seed'?)",
        "unknown option 'colour' in query",
    ]
    assert {"samples", "seed", "root", "wait", "cache"} <= set(valid.split(", "))


def test_unsupported_media_type_is_415(client: TestClient) -> None:
    response = client.post("/v1/checks", content=b"hello", headers={"content-type": "text/plain"})
    assert response.status_code == 415
    assert response.json()["detail"].startswith("unsupported Content-Type 'text/plain'; use one of application/xml")


def test_rule_selection_and_failing_severity(client: TestClient) -> None:
    everything = post_xml(client, MISSING_MESH).json()["report"]
    assert any(d["code"].startswith("GC2") for d in everything["diagnostics"])
    only_structure = post_xml(client, MISSING_MESH, select="GC1").json()["report"]
    assert all(d["code"].startswith("GC1") for d in only_structure["diagnostics"])
    strict = post_xml(client, MISSING_MESH, fail_on="info", ignore="GC2").json()
    assert strict["report"]["fail_on"] == "info"
    assert not any(d["code"].startswith("GC2") for d in strict["report"]["diagnostics"])


def test_multipart_upload_with_files_and_option_fields(client: TestClient, tmp_path: Path) -> None:
    import trimesh

    mesh = trimesh.creation.box(extents=(0.2, 0.2, 0.2)).export(file_type="stl")
    description = MISSING_MESH.replace(b"package://meshy_description/meshes/base.stl", b"$(arg mesh)").replace(
        b'<robot name="meshy">', b'<robot name="meshy" xmlns:xacro="http://www.ros.org/wiki/xacro">'
    )
    description = description.replace(b"<link", b'<xacro:arg name="mesh" default="none"/><link', 1)
    response = client.post(
        "/v1/checks",
        files=[
            ("description", ("meshy_description/robots/meshy.urdf.xacro", description, "application/xml")),
            ("files", ("meshy_description/package.xml", b"<package><name>meshy_description</name></package>")),
            ("files", ("meshy_description/meshes/base.stl", mesh, "application/octet-stream")),
        ],
        data={"args": "mesh=package://meshy_description/meshes/base.stl", "options": json.dumps({"sweep": False})},
    )
    assert response.status_code == 201, response.text
    report = response.json()["report"]
    assert report["robot"]["source"] == "meshy_description/robots/meshy.urdf.xacro"
    assert report["robot"]["meshes_loaded"] == 1
    assert report["options"]["args"] == {"mesh": "package://meshy_description/meshes/base.stl"}
    assert report["options"]["sweep"] is False
    assert not any(d["code"].startswith("GC2") for d in report["diagnostics"])


def test_multipart_refuses_unknown_fields(client: TestClient) -> None:
    response = client.post("/v1/checks", files=[("mesh", ("a.stl", b"x"))])
    assert response.status_code == 400
    assert response.json()["detail"].startswith("unknown file field 'mesh'")


def test_zip_upload_with_the_root_named(client: TestClient) -> None:
    archive = zip_bytes({"robots/a.urdf": TWO_LINKS, "robots/b.urdf": TWO_LINKS.replace(b"two_links", b"other")})
    ambiguous = client.post("/v1/checks", content=archive, headers={"content-type": "application/zip"})
    assert ambiguous.status_code == 400
    assert ambiguous.json()["detail"] == (
        "name the root file with the 'root' parameter: 2 files could each be the robot, and nothing in the "
        "upload says which: robots/a.urdf, robots/b.urdf"
    )
    named = client.post(
        "/v1/checks?root=robots/b.urdf", content=archive, headers={"content-type": "application/zip"}
    ).json()
    assert (named["robot"], named["source"]) == ("other", "robots/b.urdf")
    assert named["root"] == {
        "path": "robots/b.urdf",
        "given": True,
        "reason": "named by the request",
        "alternatives": [],
    }
    # a root the files point to is taken, and the answer says which and why
    package = zip_bytes({"robots/a.urdf": TWO_LINKS, "robots/b.urdf": TWO_LINKS, "README.md": b"Load `b.urdf`."})
    chosen = client.post("/v1/checks", content=package, headers={"content-type": "application/zip"}).json()
    assert chosen["root"] == {
        "path": "robots/b.urdf",
        "given": False,
        "reason": "named by 1 other file of the upload (launch files, documentation, configuration)",
        "alternatives": ["robots/a.urdf"],
    }
    listed = client.get("/v1/checks", params={"limit": 1}).json()["items"][0]
    assert listed["id"] == chosen["id"] and listed["root"] == chosen["root"]


def test_listing_is_paginated_newest_first(client: TestClient) -> None:
    ids = [post_xml(client, TWO_LINKS, wait="false").json()["id"] for _ in range(3)]
    first = CheckPage.model_validate(client.get("/v1/checks", params={"limit": 2}).json())
    assert [c.id for c in first.items] == ids[::-1][:2]
    assert all(c.report is None for c in first.items)
    assert first.next_cursor is not None
    second = client.get("/v1/checks", params={"limit": 2, "cursor": first.next_cursor}).json()
    assert [c["id"] for c in second["items"]] == [ids[0]]
    assert second["next_cursor"] is None
    bad = client.get("/v1/checks", params={"cursor": "garbage"})
    assert bad.status_code == 400 and bad.json()["detail"].startswith("invalid cursor 'garbage'")
    assert client.get("/v1/checks", params={"limit": 0}).status_code == 400


def test_rules_come_from_the_registry(client: TestClient) -> None:
    rules = [RuleOut.model_validate(r) for r in client.get("/v1/rules").json()]
    assert [r.code for r in rules] == [r.code for r in all_rules()]
    one = client.get("/v1/rules/GC201").json()
    assert (one["code"], one["name"], one["family"], one["family_title"]) == (
        "GC201",
        "mesh-file-not-found",
        "GC2",
        "Meshes and files",
    )
    assert client.get("/v1/rules/mesh-file-not-found").json()["code"] == "GC201"
    assert client.get("/v1/rules/GC999").status_code == 404


def test_health(client: TestClient) -> None:
    health = HealthOut.model_validate(client.get("/healthz").json())
    assert (health.status, health.database, health.workers) == ("ok", "ok", 2)


def test_bearer_tokens_guard_every_v1_endpoint(make_client: Callable[..., TestClient]) -> None:
    client = make_client(api_tokens="alpha, beta")
    assert client.get("/healthz").status_code == 200
    for method, path in [("get", "/v1/checks"), ("get", "/v1/rules"), ("get", "/v1/checks/x"), ("post", "/v1/checks")]:
        response = getattr(client, method)(path)
        assert response.status_code == 401, path
        assert response.json() == {"detail": "missing or invalid bearer token"}
        assert response.headers["www-authenticate"] == "Bearer"
    wrong = client.get("/v1/rules", headers={"Authorization": "Bearer gamma"})
    assert wrong.status_code == 401
    assert client.get("/v1/rules", headers={"Authorization": "Bearer beta"}).status_code == 200
    posted = client.post(
        "/v1/checks", content=TWO_LINKS, headers={"content-type": "application/xml", "Authorization": "Bearer alpha"}
    )
    assert posted.status_code == 201


def test_openapi_describes_every_endpoint_and_body(client: TestClient) -> None:
    spec = client.get("/openapi.json").json()
    paths = spec["paths"]
    assert set(paths) - {
        "/v1/root-candidates",
        "/v1/checks/{check_id}/report.sarif",
        "/v1/checks/{check_id}/report.junit.xml",
    } == {
        "/healthz",
        "/readyz",
        "/metrics",
        "/v1/rules",
        "/v1/rules/{code}",
        "/v1/checks",
        "/v1/checks/{check_id}",
        "/v1/checks/{check_id}/report.json",
        "/v1/checks/{check_id}/report.html",
        "/v1/checks/{check_id}/collision-matrix.srdf",
        "/v1/checks/{check_id}/fixes.patch",
    }
    post = paths["/v1/checks"]["post"]
    assert set(post["requestBody"]["content"]) == {
        "application/xml",
        "text/xml",
        "multipart/form-data",
        "application/zip",
        "application/x-zip-compressed",
        "application/gzip",
        "application/x-gzip",
        "application/x-tar+gzip",
        "application/x-tgz",
        "application/x-tar",
    }
    assert {"201", "202", "400", "401", "413", "415", "422", "503"} <= set(post["responses"])
    assert post["responses"]["201"]["content"]["application/json"]["schema"] == {
        "$ref": "#/components/schemas/CheckOut"
    }
    params = {p["name"] for p in post["parameters"]}
    assert {
        "root",
        "wait",
        "args",
        "srdf",
        "samples",
        "seed",
        "backend",
        "semantics",
        "fail_on",
        "matrix",
        "sweep",
        "pose",
    } <= params
    report_json = paths["/v1/checks/{check_id}/report.json"]["get"]["responses"]
    assert report_json["200"]["content"]["application/json"]["schema"] == {"$ref": "#/components/schemas/ReportOut"}
    assert "text/html" in paths["/v1/checks/{check_id}/report.html"]["get"]["responses"]["200"]["content"]
    assert "HTTPBearer" in spec["components"]["securitySchemes"]
    assert client.get("/docs").status_code == 200


def test_a_full_queue_answers_503_and_frees_its_places(make_client: Callable[..., TestClient]) -> None:
    client = make_client(workers=1, max_queued=1, check_cpu_s=2, check_timeout_s=20)
    client.app.state.service.target = burn_cpu  # type: ignore[attr-defined]
    # cache=false: identical submissions would otherwise share the first one's run
    slow = [post_xml(client, TWO_LINKS, wait="false", cache="false") for _ in range(2)]
    assert [r.status_code for r in slow] == [202, 202]
    full = post_xml(client, TWO_LINKS, cache="false")
    assert full.status_code == 503
    assert full.json()["detail"] == "2 checks are queued or running; try again shortly"
    assert full.headers["retry-after"] == "5"
    started = time.monotonic()
    assert client.get("/healthz").json()["pending"] == 2
    assert time.monotonic() - started < 1.0  # the service answers while checks compute
    deadline = time.monotonic() + 60
    while client.get("/healthz").json()["pending"] and time.monotonic() < deadline:
        time.sleep(0.1)
    assert client.get("/healthz").json()["pending"] == 0
    for response in slow:
        final = client.get(response.headers["location"]).json()
        assert (final["status"], final["http_status"]) == ("failed", 422)
        assert final["reason"] == "the check exceeded the CPU-time limit of 2 s"


def test_a_check_over_its_wall_clock_limit_is_recorded_failed(make_client: Callable[..., TestClient]) -> None:
    client = make_client(check_timeout_s=1)
    client.app.state.service.target = sleep_long  # type: ignore[attr-defined]
    response = post_xml(client, TWO_LINKS)
    assert response.status_code == 422
    assert response.json() == {"detail": "the check exceeded the wall-clock limit of 1 s"}
    failed = client.get("/v1/checks", params={"status": "failed"}).json()["items"][0]
    assert (failed["http_status"], failed["reason"]) == (422, "the check exceeded the wall-clock limit of 1 s")


def test_plain_html_page_escapes_the_report(client: TestClient) -> None:
    from api.results.html import download_name, plain_page

    report = post_xml(client, MISSING_MESH.replace(b'name="meshy"', b'name="a&lt;script&gt;"')).json()["report"]
    page = plain_page(report)
    assert page.startswith("<!DOCTYPE html>")
    assert "<script>" not in page and "a&lt;script&gt;" in page
    assert "GC202" in page and "mesh-package-unresolved" in page
    assert download_name("a<script>/../x", "-geomcheck.html") == "a_script_.._x-geomcheck.html"
    assert download_name(None, ".srdf") == "robot.srdf"


def test_a_configuration_file_in_the_upload_applies_under_the_request(client: TestClient) -> None:
    archive = zip_bytes({"robot.urdf": MISSING_MESH, "geomcheck.toml": b'ignore = ["GC2"]\nfail-on = "warning"\n'})
    report = client.post(
        "/v1/checks", content=archive, headers={"content-type": "application/zip"}, params={"root": "robot.urdf"}
    ).json()["report"]
    assert not any(d["code"].startswith("GC2") for d in report["diagnostics"])
    assert report["fail_on"] == "warning"
    overridden = client.post(
        "/v1/checks",
        content=archive,
        headers={"content-type": "application/zip"},
        params={"root": "robot.urdf", "fail_on": "error"},
    ).json()["report"]
    assert overridden["fail_on"] == "error"
    bad = zip_bytes({"robot.urdf": TWO_LINKS, "geomcheck.toml": b"selct = []\n"})
    response = client.post("/v1/checks", content=bad, headers={"content-type": "application/zip"})
    assert response.status_code == 400
    assert response.json()["detail"].startswith(
        "geomcheck.toml: unknown configuration key 'selct'; did you mean 'select'?"
    )


def test_an_empty_or_unknown_status_filter_is_refused(client: TestClient) -> None:
    for value in ("", "done", "SUCCEEDED"):
        answer = client.get("/v1/checks", params={"status": value})
        assert answer.status_code == 400, value
        assert answer.json()["detail"].startswith("query parameter 'status': Input should be 'queued'"), answer.json()
    assert client.get("/v1/checks", params={"status": "failed"}).status_code == 200
    parameters = client.get("/openapi.json").json()["paths"]["/v1/checks"]["get"]["parameters"]
    parameter = next(p for p in parameters if p["name"] == "status")
    assert parameter["schema"]["anyOf"][0]["enum"] == ["queued", "running", "succeeded", "failed", "cancelled"]
