"""The web page's server side: the page and its option form, static files, root candidates,
and the SARIF and JUnit downloads it offers (the page in a real browser: test_web_browser.py)."""

from __future__ import annotations

import base64
import copy
import hashlib
import json
import re
from collections.abc import Callable
from pathlib import Path

import pytest
from apitools import EXAMPLE, EXAMPLE_ROOT, TWO_LINKS, post_xml, post_zip, zip_bytes, zip_folder
from fastapi.testclient import TestClient
from junitparser import JUnitXml

from api.checks.options import OPTION_NAMES
from api.http.app import create_app
from api.routers.web import MAX_INSPECTING
from api.settings import Settings
from api.uploads.roots import root_candidates
from api.web.forms import option_defaults, option_fields
from tests.packagetools import MESH_PACKAGE_ROOT, mesh_package

PAGE_BUDGET = 200 * 1024  # the page with its script and style sheet, without a report [bytes]


def _option_inputs(html: str) -> dict[str, str]:
    """``data-option`` name -> the tag of its input, from the page."""
    return {m.group(1): m.group(0) for m in re.finditer(r'<[^>]*data-option="([a-z0-9_]+)"[^>]*>', html)}


def test_page_has_one_field_per_api_option_with_its_default(client: TestClient) -> None:
    page = client.get("/")
    assert page.status_code == 200
    assert page.headers["content-type"].startswith("text/html")
    assert '<form id="check-form"' in page.text
    inputs = _option_inputs(page.text)
    assert sorted(inputs) == sorted(OPTION_NAMES)
    assert (
        'type="number"' in inputs["samples"] and 'value="10000"' in inputs["samples"] and 'min="1"' in inputs["samples"]
    )
    assert 'value="0"' in inputs["seed"] and 'min="0"' in inputs["seed"]
    assert "checked" in inputs["sweep"] and "checked" not in inputs["matrix"]
    assert inputs["backend"].startswith("<select") and 'data-default="coal"' in inputs["backend"]
    assert re.search(r'data-option="backend".*?<option selected>coal</option><option>fcl</option>', page.text, re.S)
    assert re.search(
        r'data-option="fail_on".*?<option selected>error</option><option>warning</option>', page.text, re.S
    )
    assert inputs["args"].startswith("<textarea")
    # every control is labelled
    for name in OPTION_NAMES:
        assert f'<label for="opt-{name}">' in page.text


def test_option_fields_follow_the_openapi_document() -> None:
    app = create_app(Settings(data_dir=Path("/nonexistent-geomcheck-data")))
    fields = {f.name: f for f in option_fields(app.openapi(), option_defaults(200_000))}
    assert [f.name for f in fields.values()] == [
        "args", "env", "srdf", "samples", "seed", "backend", "semantics", "fail_on",
        "matrix", "sweep", "pose", "pose_name", "select", "ignore", "extend_select", "view_3d",
    ]  # fmt: skip
    assert (fields["matrix"].kind, fields["matrix"].default) == ("boolean", "false")
    assert (fields["sweep"].kind, fields["sweep"].default) == ("boolean", "true")
    assert (fields["samples"].kind, fields["samples"].minimum, fields["samples"].default) == ("integer", 1, "10000")
    assert (fields["semantics"].kind, fields["semantics"].choices) == ("choice", ("moveit", "pinocchio"))
    assert (fields["fail_on"].choices, fields["fail_on"].default) == (("error", "warning", "info"), "error")
    assert (fields["select"].kind, fields["select"].default, fields["select"].advanced) == ("list", "ALL", True)
    assert (fields["pose_name"].kind, fields["pose_name"].default) == ("text", "")
    assert fields["args"].description == "xacro argument NAME=VALUE (repeatable)"


def test_option_fields_follow_schemas_given_by_reference() -> None:
    app = create_app(Settings(data_dir=Path("/nonexistent-geomcheck-data")))
    direct = option_fields(app.openapi(), option_defaults(200_000))
    spec = copy.deepcopy(app.openapi())
    content = spec["paths"]["/v1/checks"]["post"]["requestBody"]["content"]["multipart/form-data"]
    form = content["schema"]
    form["properties"]["backend"] = {"$ref": "#/components/schemas/Backend"}
    spec.setdefault("components", {}).setdefault("schemas", {}).update(
        {"CheckForm": form, "Backend": {"type": "string", "enum": ["coal", "fcl"]}}
    )
    content["schema"] = {"$ref": "#/components/schemas/CheckForm"}
    assert option_fields(spec, option_defaults(200_000)) == direct


def test_shared_link_serves_the_page_for_that_check(client: TestClient) -> None:
    page = client.get("/checks/abcDEF123")
    assert page.status_code == 200
    assert 'data-check-id="abcDEF123"' in page.text


def test_page_weight_and_no_external_url(client: TestClient) -> None:
    page = client.get("/").text
    assets = re.findall(r'(?:href|src)="(/web/static/[^"?]+)', page)
    assert sorted(assets) == ["/web/static/app.css", "/web/static/app.js", "/web/static/archive.js"]
    bodies = [page] + [client.get(a).text for a in assets]
    assert client.get("/web/static/app.js").headers["content-type"].startswith("text/javascript")
    total = sum(len(b.encode()) for b in bodies)
    assert total < PAGE_BUDGET, f"page weight {total} bytes"
    for text in bodies:
        assert re.findall(r"https?://", text) == []


def test_static_files_are_a_closed_set(client: TestClient) -> None:
    assert client.get("/web/static/app.js").status_code == 200
    assert client.get("/web/static/../routers/web.py").status_code == 404
    assert client.get("/web/static/index.html").json() == {"detail": "no static file 'index.html'"}


def test_root_candidates_rank_the_including_file_first() -> None:
    found = root_candidates(EXAMPLE)
    assert [c.path for c in found] == [
        EXAMPLE_ROOT,
        "urdf/common.xacro",
        "urdf/laser.urdf.xacro",
        "urdf/materials.urdf.xacro",
        "urdf/base.urdf.xacro",
    ]
    assert (found[0].robot, found[0].included, found[0].instantiates) == ("pr2_base_example", False, True)
    # the others define macros, properties and materials, and the root includes them
    assert all(c.included and not c.instantiates and c.robot is None for c in found[1:])


def test_root_candidates_skip_files_without_a_robot(tmp_path: Path) -> None:
    (tmp_path / "launch").mkdir()
    (tmp_path / "launch" / "view.xacro").write_text("<launch/>")
    (tmp_path / "deep" / "er").mkdir(parents=True)
    (tmp_path / "deep" / "er" / "a.urdf").write_text('<robot name="a"/>')
    (tmp_path / "b.urdf").write_text('<robot name="b"/>')
    (tmp_path / "parts.xacro").write_text("<robot xmlns:xacro='http://ros.org/wiki/xacro'/>")
    assert [(c.path, c.robot) for c in root_candidates(tmp_path)] == [
        ("b.urdf", "b"),
        ("deep/er/a.urdf", "a"),
        ("parts.xacro", None),
    ]


def test_root_candidates_endpoint_reads_archives_and_forms(client: TestClient) -> None:
    zipped = client.post(
        "/v1/root-candidates", content=zip_folder(EXAMPLE, "pr2_base/"), headers={"content-type": "application/zip"}
    )
    assert zipped.status_code == 200, zipped.text
    assert zipped.json()["candidates"][0] == {
        "path": f"pr2_base/{EXAMPLE_ROOT}",
        "robot": "pr2_base_example",
        "included": False,
        "pulls_in": 4,
        "instantiates": True,
        "referenced": 1,  # the example's README names it
        "missing": 0,
    }
    chosen = zipped.json()["chosen"]
    assert chosen["path"] == f"pr2_base/{EXAMPLE_ROOT}" and chosen["given"] is False
    assert (
        chosen["reason"] == "the only file that makes a robot at its top level; the others define macros or materials"
    )
    form = client.post(
        "/v1/root-candidates",
        files=[("files", ("robots/two.urdf", TWO_LINKS)), ("files", ("urdf/empty.xacro", b"<robot/>"))],
    )
    assert form.json() == {
        "candidates": [
            {
                "path": "robots/two.urdf",
                "robot": "two_links",
                "included": False,
                "pulls_in": 0,
                "instantiates": True,
                "referenced": 0,
                "missing": 0,
            },
            {
                "path": "urdf/empty.xacro",
                "robot": None,
                "included": False,
                "pulls_in": 0,
                "instantiates": False,
                "referenced": 0,
                "missing": 0,
            },
        ],
        "chosen": {
            "path": "robots/two.urdf",
            "given": False,
            "reason": "the only file that makes a robot at its top level; the others define macros or materials",
            "alternatives": ["urdf/empty.xacro"],
        },
        "why": None,
    }
    leftovers = [p.name for p in client.app.state.settings.work_dir.iterdir()]
    assert not [n for n in leftovers if n.startswith("candidates-")]


def test_root_candidates_endpoint_refuses_what_checks_refuse(make_client: Callable[..., TestClient]) -> None:
    client = make_client(max_files=3)
    escaping = client.post(
        "/v1/root-candidates", content=zip_bytes({"../x.urdf": TWO_LINKS}), headers={"content-type": "application/zip"}
    )
    assert escaping.status_code == 400 and "escapes the bundle" in escaping.json()["detail"]
    many = client.post(
        "/v1/root-candidates",
        content=zip_bytes({f"f{i}.urdf": TWO_LINKS for i in range(5)}),
        headers={"content-type": "application/zip"},
    )
    assert (many.status_code, many.json()["detail"]) == (413, "zip archive has more than 3 entries")
    text = client.post("/v1/root-candidates", content=b"x", headers={"content-type": "text/plain"})
    assert text.status_code == 415


def test_root_candidates_endpoint_bounds_uploads_at_once(client: TestClient) -> None:
    body = zip_bytes({"a.urdf": TWO_LINKS})
    client.app.state.inspecting = MAX_INSPECTING  # as while that many are being unpacked
    busy = client.post("/v1/root-candidates", content=body, headers={"content-type": "application/zip"})
    assert (busy.status_code, busy.headers["retry-after"]) == (503, "5")
    assert busy.json()["detail"] == "4 uploads are being inspected, the most at once; retry later"
    client.app.state.inspecting = MAX_INSPECTING - 1
    free = client.post("/v1/root-candidates", content=body, headers={"content-type": "application/zip"})
    assert free.status_code == 200 and client.app.state.inspecting == MAX_INSPECTING - 1


def test_root_candidates_endpoint_needs_the_token(make_client: Callable[..., TestClient]) -> None:
    client = make_client(api_tokens="s3cret")
    body = zip_bytes({"a.urdf": TWO_LINKS})
    refused = client.post("/v1/root-candidates", content=body, headers={"content-type": "application/zip"})
    assert refused.status_code == 401
    allowed = client.post(
        "/v1/root-candidates",
        content=body,
        headers={"content-type": "application/zip", "authorization": "Bearer s3cret"},
    )
    assert [(c["path"], c["robot"]) for c in allowed.json()["candidates"]] == [("a.urdf", "two_links")]
    assert client.get("/").status_code == 200  # the page itself asks for the token


@pytest.fixture(scope="module")
def package_check(tmp_path_factory: pytest.TempPathFactory) -> tuple[TestClient, dict[str, object]]:
    """A check of a small package with meshes and two errors (:func:`apitools.mesh_package`)."""
    settings = Settings(data_dir=tmp_path_factory.mktemp("web") / "data")
    with TestClient(create_app(settings)) as client:
        created = post_zip(client, zip_bytes(mesh_package()), root=MESH_PACKAGE_ROOT)
        assert created.status_code == 201, created.text
        yield client, created.json()


def test_sarif_download_holds_every_finding(package_check: tuple[TestClient, dict[str, object]]) -> None:
    client, check = package_check
    report = check["report"]
    assert isinstance(report, dict)
    response = client.get(f"/v1/checks/{check['id']}/report.sarif")
    assert response.status_code == 200
    assert response.headers["content-type"] == "application/sarif+json"
    assert response.headers["content-disposition"] == 'attachment; filename="boxed-geomcheck.sarif"'
    results = json.loads(response.text)["runs"][0]["results"]
    assert sorted(r["ruleId"] for r in results) == sorted(d["code"] for d in report["diagnostics"])


def test_junit_download_holds_every_failure(
    package_check: tuple[TestClient, dict[str, object]], tmp_path: Path
) -> None:
    client, check = package_check
    report = check["report"]
    assert isinstance(report, dict)
    response = client.get(f"/v1/checks/{check['id']}/report.junit.xml")
    assert response.status_code == 200
    assert response.headers["content-disposition"] == 'attachment; filename="boxed-geomcheck.junit.xml"'
    path = tmp_path / "junit.xml"
    path.write_bytes(response.content)
    suites = JUnitXml.fromfile(str(path))
    assert suites.failures + suites.errors > 0
    assert report["summary"]["error"] > 0  # type: ignore[index]
    assert client.get("/v1/checks/nope/report.sarif").status_code == 404


def test_docs_load_no_script_from_elsewhere(client: TestClient) -> None:
    for path in ("/docs", "/redoc"):
        page = client.get(path)
        assert page.status_code == 200
        sources = re.findall(r'(?:src|href)="([^"]+)"', page.text)
        assert sources and all(s.startswith("/docs-static/") or s == "/openapi.json" for s in sources), sources
        assert "fonts.googleapis" not in page.text and "cdn.jsdelivr" not in page.text
        assert "script-src 'self' 'unsafe-inline'" in page.headers["content-security-policy"]
        assert page.headers["x-frame-options"] == "DENY"
    script = client.get("/docs-static/swagger-ui-bundle.js")
    assert script.status_code == 200 and len(script.content) > 100_000
    assert client.get("/docs-static/../../etc/passwd").status_code == 404


def test_pages_and_reports_carry_security_headers(client: TestClient) -> None:
    page = client.get("/")
    assert page.headers["content-security-policy"].startswith("default-src 'self'; script-src 'self' 'sha256-")
    assert "frame-ancestors 'none'" in page.headers["content-security-policy"]
    assert (page.headers["x-frame-options"], page.headers["x-content-type-options"]) == ("DENY", "nosniff")
    check_id = post_xml(client, TWO_LINKS).json()["id"]
    report = client.get(f"/v1/checks/{check_id}/report.html")
    policy = report.headers["content-security-policy"]
    assert policy.startswith("default-src 'none'; script-src 'sha256-") and "'unsafe-inline'; img-src" in policy
    # the scripts the report runs (its own; three.js and the 3D view's) are allowed by their hashes
    scripts = re.findall(r"<script>(.*?)</script>", report.text, re.S)
    assert len(scripts) == 3
    for script in scripts:
        digest = base64.b64encode(hashlib.sha256(script.encode()).digest()).decode()
        assert f"'sha256-{digest}'" in policy.split(";")[1]
    assert (report.headers["x-frame-options"], report.headers["x-content-type-options"]) == ("SAMEORIGIN", "nosniff")
    assert client.get(f"/v1/checks/{check_id}/report.json").headers["x-content-type-options"] == "nosniff"


def test_a_cross_origin_form_post_is_refused_without_tokens(client: TestClient) -> None:
    form = {"description": ("robot.urdf", TWO_LINKS, "application/xml")}
    for headers in ({"Origin": "https://evil.example"}, {"Origin": "null"}, {"Sec-Fetch-Site": "cross-site"}):
        answer = client.post("/v1/checks", files=form, headers=headers)
        assert answer.status_code == 403, headers
        assert answer.json() == {"detail": "cross-origin request refused: submit from this service's own page"}
    assert client.get("/v1/checks").json()["items"] == []  # nothing was checked
    same = client.post("/v1/checks", files=form, headers={"Origin": "http://testserver"})
    assert same.status_code == 201
    assert client.post("/v1/checks", files=form).status_code == 201  # curl, CI: no Origin
