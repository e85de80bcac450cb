"""The web page in a real browser: Debian's Chromium driven by Playwright, against a real
``geomcheck serve`` on loopback (embedded mode), and once against an API and a worker on
Redis and PostgreSQL (distributed mode).

Every request the page makes is watched: anything not to the service fails the test, and
so do console errors. Screenshots of each state go to the test's tmp_path, and to
test-output/web/ at the repo root when GEOMCHECK_SCREENSHOTS is set.
"""

from __future__ import annotations

import io
import json
import math
import os
import tarfile
import time
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx
import pytest
from apitools import EXAMPLE, EXAMPLE_ROOT, TWO_LINKS, long_chain, unique_prefix, verified_check
from clustertools import cluster, database_url, redis_url
from servertools import serving

from api.store import Store
from tests.packagetools import MESH_PACKAGE_ROOT, mesh_package, write_package

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--no-first-run"]
REPO = Path(__file__).resolve().parents[3]
CHECK_TIMEOUT_MS = 180_000  # the bundled example takes a few seconds; CI machines are slower
MALFORMED = b'<?xml version="1.0"?>\n<robot name="bad">\n  <link name="a">\n  </lnk>\n</robot>\n'

pytestmark = [
    pytest.mark.long,
    pytest.mark.browser,
    pytest.mark.skipif(not CHROMIUM.exists(), reason="headless Chromium not found at /usr/bin/chromium"),
]


def wait_true(page: Any, expression: str, timeout: float = 30_000) -> None:
    """Wait until ``expression`` is true in the page, polling from here: Playwright's
    ``wait_for_function`` evaluates its text with ``new Function``, which the page's
    Content-Security-Policy (no 'unsafe-eval') refuses, as it should."""
    deadline = time.monotonic() + timeout / 1000
    while not page.evaluate(expression):
        assert time.monotonic() < deadline, f"not true within {timeout / 1000:g} s: {expression}"
        time.sleep(0.1)


@dataclass
class Visit:
    page: Any
    base: str
    shots: Path
    console: list[str] = field(default_factory=list)
    outside: list[str] = field(default_factory=list)

    def check_clean(self, allowed_console: tuple[str, ...] = ()) -> None:
        assert self.outside == [], f"the page reached outside the service: {self.outside}"
        errors = [m for m in self.console if not any(a in m for a in allowed_console)]
        assert errors == [], f"console errors: {errors}"

    def shot(self, name: str, element: str | None = None) -> Path:
        path = self.shots / name
        if element:
            self.page.locator(element).screenshot(path=str(path))
        else:
            self.page.screenshot(path=str(path), full_page=True)
        if os.environ.get("GEOMCHECK_SCREENSHOTS"):
            out = REPO / "test-output" / "web"
            out.mkdir(parents=True, exist_ok=True)
            (out / name).write_bytes(path.read_bytes())
        print(f"screenshot: {path}")
        assert path.stat().st_size > 10_000
        return path


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    sync_api = pytest.importorskip("playwright.sync_api", reason="Playwright for Python is not installed")
    with sync_api.sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        yield launched
        launched.close()


@pytest.fixture(scope="module")
def service(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    # two checks a page, so that a few checks are enough to page the recent list
    with serving(tmp_path_factory.mktemp("web-browser") / "data", page_size="2") as base:
        yield base


TOKEN = "s3cret-token"
MAX_FILES = 5  # of the token-protected service: fewer than the bundled example's 11 files


@pytest.fixture(scope="module")
def guarded(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """A service that needs a token and takes at most MAX_FILES files an upload."""
    data = tmp_path_factory.mktemp("web-guarded") / "data"
    with serving(data, api_tokens=TOKEN, max_files=str(MAX_FILES)) as base:
        yield base


@contextmanager
def visit(
    browser: Any, base: str, shots: Path, path: str = "/", token: str | None = None, width: int = 1280
) -> Iterator[Visit]:
    context = browser.new_context(viewport={"width": width, "height": 900}, accept_downloads=True)
    if token:  # as if given earlier in this browser tab
        script = f"if (window === window.top) sessionStorage.setItem('geomcheck.token', {json.dumps(token)})"
        context.add_init_script(script)  # not in the report's sandboxed frame, which has no storage
    page = context.new_page()
    seen = Visit(page=page, base=base, shots=shots)

    def watch(route: Any) -> None:
        url = route.request.url
        if url.startswith(base) or url.startswith(("blob:", "data:", "about:")):
            route.continue_()
        else:
            seen.outside.append(url)
            route.abort()

    page.route("**/*", watch)
    page.on("console", lambda m: seen.console.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: seen.console.append(str(e)))
    page.set_default_timeout(30_000)
    try:
        page.goto(base + path)
        yield seen
    finally:
        context.close()


def wait_finished(page: Any) -> str:
    wait_true(
        page,
        "['succeeded', 'failed'].includes(document.getElementById('status').textContent)",
        timeout=CHECK_TIMEOUT_MS,
    )
    return str(page.text_content("#status"))


def api_paths(base: str) -> set[str]:
    return set(httpx.get(f"{base}/openapi.json").json()["paths"])


def downloaded(page: Any, button: str) -> tuple[str, bytes]:
    with page.expect_download() as info:
        page.click(f"#downloads button:text-is('{button}')")
    download = info.value
    return download.suggested_filename, Path(download.path()).read_bytes()


def test_example_folder_end_to_end(browser: Any, service: str, tmp_path: Path) -> None:
    with visit(browser, service, tmp_path) as seen:
        page = seen.page
        seen.shot("web-1-empty.png")
        page.set_input_files("#pick-folder", str(EXAMPLE))
        page.wait_for_selector("#root:not([disabled])")
        assert page.input_value("#root") == f"pr2_base/{EXAMPLE_ROOT}"
        options = page.eval_on_selector_all("#root option", "os => os.map(o => o.value)")
        assert options[0] == f"pr2_base/{EXAMPLE_ROOT}" and "pr2_base/urdf/base.urdf.xacro" in options
        assert "folder pr2_base" in str(page.text_content("#picked"))
        seen.shot("web-2-chosen.png")
        page.click("#submit")
        page.wait_for_selector("#progress:not([hidden])")
        seen.shot("web-3-progress.png")
        assert wait_finished(page) == "succeeded"
        page.wait_for_selector("#result:not([hidden])")
        check_id = str(page.text_content("#check-id"))
        assert page.url == f"{service}/checks/{check_id}"

        # the report once its fixes are verified: verification rewrites the fixes section when it ends,
        # and the downloads below are compared with the report as it is then
        with httpx.Client(base_url=service) as client:
            api = verified_check(client, check_id)
        report = api["report"]
        assert api["source"] == f"pr2_base/{EXAMPLE_ROOT}" and report["robot"]["name"] == "pr2_base_example"
        assert page.text_content("#verdict") == report["verdict"] == "fail"
        summary = report["summary"]

        def counted(n: int, word: str) -> str:
            return f"{n} {word}" if n == 1 else f"{n} {word}s"

        assert page.text_content("#counts") == (
            f"{counted(summary['error'], 'error')}, {counted(summary['warning'], 'warning')}, {summary['info']} info"
        )
        rows_expected = [d["code"] for d in report["diagnostics"]]
        fixable = sum(1 for d in report["diagnostics"] if d["fix"])
        assert page.text_content("#fixable") == f"({fixable} with a suggested fix)"
        page.click("#findings-box summary")
        assert page.is_visible("#findings tbody tr") and page.text_content("#findings-count") == str(len(rows_expected))
        rows = page.eval_on_selector_all(
            "#findings tbody tr", "rows => rows.map(r => r.cells[0].textContent.slice(0, 5))"
        )
        assert rows == rows_expected
        frame = page.frame_locator("#report")
        frame.locator("h1").first.wait_for()
        assert "pr2_base_example" in str(frame.locator("h1").first.text_content())
        seen.shot("web-4-report.png", element="#report")  # before any full-page shot: those blank the frame
        # the report's 3D view runs in the frame (its scripts allowed by hash): a finding focuses its link
        frame.locator("[data-v3d][data-ready]").wait_for(timeout=60_000)
        frame.locator(".v3d-item", has_text="GC301").first.click()
        frame.locator("[data-v3d][data-focus='finding-1']").wait_for()
        assert "base_link/suggested:collision[0]" in str(frame.locator("[data-v3d]").get_attribute("data-shown"))
        frame.locator("#view3d").scroll_into_view_if_needed()
        seen.shot("web-4-report-3d.png", element="#report")
        seen.shot("web-4-result.png")

        name, html = downloaded(page, "HTML")
        assert name == "pr2_base_example-geomcheck.html"
        assert html == httpx.get(f"{service}/v1/checks/{check_id}/report.html").content
        name, raw = downloaded(page, "JSON")
        assert name == "pr2_base_example-geomcheck.json"
        assert raw == httpx.get(f"{service}/v1/checks/{check_id}/report.json").content
        assert json.loads(raw) == report
        name, sarif = downloaded(page, "SARIF")
        assert name == "pr2_base_example-geomcheck.sarif"
        assert len(json.loads(sarif)["runs"][0]["results"]) == len(report["diagnostics"])
        assert page.is_hidden("#downloads button:text-is('SRDF')")  # no matrix was asked for
        # the report came first; its fixes are verified after it, and the page shows that
        wait_true(
            page, "document.getElementById('fixes-text').textContent.startsWith('The offered fixes are verified')"
        )
        fixes = httpx.get(f"{service}/v1/checks/{check_id}").json()["report"]["sections"].get("fixes") or {}
        assert fixes["verified"] is True
        assert page.is_hidden("#downloads button:text-is('Safe fixes (patch)')") == (not fixes.get("safe_patch"))
        assert page.is_hidden("#downloads button:text-is('All fixes (patch)')") == (not fixes.get("unsafe_patch"))
        if fixes.get("unsafe_patch") and "/v1/checks/{check_id}/fixes.patch" in api_paths(service):
            name, patch = downloaded(page, "All fixes (patch)")
            assert name == "pr2_base_example-unsafe-fixes.patch"  # not the safe patch's name: both are kept
            assert patch == httpx.get(f"{service}/v1/checks/{check_id}/fixes.patch?unsafe=true").content
            assert patch.decode() == fixes["unsafe_patch"]

        recent = page.eval_on_selector_all("#recent-table tbody tr", "rows => rows.map(r => r.cells[0].textContent)")
        assert "pr2_base_example" in recent
        seen.check_clean()

    # the shared link shows the same check in a fresh page
    with visit(browser, service, tmp_path, f"/checks/{check_id}") as seen:
        assert wait_finished(seen.page) == "succeeded"
        seen.page.wait_for_selector("#result:not([hidden])")
        assert seen.page.text_content("#robot") == "pr2_base_example"
        seen.check_clean()


def test_malformed_urdf_shows_file_line_and_code(browser: Any, service: str, tmp_path: Path) -> None:
    bad = tmp_path / "bad.urdf"
    bad.write_bytes(MALFORMED)
    with visit(browser, service, tmp_path) as seen:
        page = seen.page
        # dropped on the page, as from a file manager
        page.evaluate(
            """([name, text]) => {
                const files = new DataTransfer();
                files.items.add(new File([text], name, {type: "application/xml"}));
                const event = new DragEvent("drop", {dataTransfer: files, bubbles: true, cancelable: true});
                document.getElementById("drop").dispatchEvent(event);
            }""",
            [bad.name, MALFORMED.decode()],
        )
        page.wait_for_selector("#root:not([disabled])")
        assert page.input_value("#root") == "bad.urdf"
        assert page.text_content("#picked") == "Chosen: file bad.urdf, 77 bytes."
        page.click("#submit")
        assert wait_finished(page) == "failed"
        page.wait_for_selector("#error:not([hidden])")
        assert page.text_content("#error-file") == "bad.urdf"
        assert page.text_content("#error-line") == "4, column 9"
        assert "GC101 malformed-xml" in str(page.text_content("#error-message"))
        page.wait_for_selector("#error-frame:not([hidden])")
        frame = str(page.text_content("#error-frame")).splitlines()
        assert frame[2:4] == ['  3 |   <link name="a">', "> 4 |   </lnk>"]
        assert frame[-1] == "  5 | </robot>"
        assert page.is_hidden("#result")
        seen.shot("web-5-malformed.png")
        seen.check_clean()


INCLUDING = (
    b'<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
    b'  <xacro:include filename="../urdf/broken.xacro"/>\n  <link name="base"/>\n</robot>\n'
)


@pytest.mark.parametrize("kind", ["zip", "tar.gz"])
def test_malformed_file_inside_an_archive_shows_its_lines(
    browser: Any, service: str, tmp_path: Path, kind: str
) -> None:
    """The lines come out of the archive the person chose, read by the page itself."""
    files = {"pkg/robots/robot.urdf.xacro": INCLUDING, "pkg/urdf/broken.xacro": MALFORMED}
    archive = tmp_path / f"pkg.{kind}"
    if kind == "zip":
        with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as zipped:
            for name, data in files.items():
                zipped.writestr(name, data)
    else:
        with tarfile.open(archive, "w:gz") as tarred:
            for name, data in files.items():
                info = tarfile.TarInfo(name)
                info.size = len(data)
                tarred.addfile(info, io.BytesIO(data))
    with visit(browser, service, tmp_path) as seen:
        page = seen.page
        page.set_input_files("#pick-file", str(archive))
        page.wait_for_selector("#root:not([disabled])")
        assert page.input_value("#root") == "pkg/robots/robot.urdf.xacro"
        page.click("#submit")
        assert wait_finished(page) == "failed"
        page.wait_for_selector("#error-frame:not([hidden])")
        assert page.text_content("#error-file") == "pkg/urdf/broken.xacro"
        frame = str(page.text_content("#error-frame")).splitlines()
        assert frame[2:4] == ['  3 |   <link name="a">', "> 4 |   </lnk>"]
        if kind == "zip":
            seen.shot("web-5-malformed-in-zip.png")
        seen.check_clean()


def _zip_example(path: Path) -> None:
    with zipfile.ZipFile(path, "w") as archive:
        for file in sorted(EXAMPLE.rglob("*")):
            if file.is_file():
                archive.write(file, file.relative_to(EXAMPLE).as_posix())


def _tab_to(page: Any, element_id: str, limit: int = 40) -> None:
    for _ in range(limit):
        page.keyboard.press("Tab")
        if page.evaluate("document.activeElement && document.activeElement.id") == element_id:
            return
    raise AssertionError(f"#{element_id} cannot be reached with the Tab key")


def test_keyboard_only_upload_of_an_archive_with_a_matrix(browser: Any, service: str, tmp_path: Path) -> None:
    archive = tmp_path / "pr2_base.zip"
    _zip_example(archive)
    with visit(browser, service, tmp_path) as seen:
        page = seen.page
        unlabelled = page.eval_on_selector_all(
            "input, select, textarea",
            "els => els.filter(e => e.labels.length === 0 && !e.getAttribute('aria-label')).map(e => e.id)",
        )
        assert unlabelled == []
        # A standing listener turns Chromium's file-chooser interception on now: one made by
        # expect_file_chooser races the key press and loses when the machine is busy.
        choosers: list[Any] = []
        page.on("filechooser", lambda chooser: choosers.append(chooser))
        _tab_to(page, "pick-file")
        seen.shot("web-6-keyboard-focus.png")
        page.keyboard.press("Space")
        for _ in range(300):  # events reach the listener while Playwright waits
            if choosers:
                break
            page.wait_for_timeout(100)
        assert len(choosers) == 1
        choosers[0].set_files(str(archive))
        page.wait_for_selector("#root:not([disabled])")
        assert page.input_value("#root") == EXAMPLE_ROOT
        _tab_to(page, "root")
        _tab_to(page, "opt-args")
        page.keyboard.type("web_test=1")  # a xacro argument the description does not use: xacro ignores it
        _tab_to(page, "opt-samples")
        page.keyboard.press("Control+A")
        page.keyboard.type("200")  # a small matrix: enough for an SRDF to download
        _tab_to(page, "opt-matrix")
        page.keyboard.press("Space")
        _tab_to(page, "opt-sweep")
        page.keyboard.press("Space")  # skip the sweep: sent as sweep=false
        assert page.is_checked("#opt-matrix") and not page.is_checked("#opt-sweep")
        seen.shot("web-6-keyboard.png")
        _tab_to(page, "submit")
        page.keyboard.press("Enter")
        assert wait_finished(page) == "succeeded"
        page.wait_for_selector("#result:not([hidden])")
        assert page.evaluate("document.activeElement.id") == "result-title"
        check_id = str(page.text_content("#check-id"))
        check = httpx.get(f"{service}/v1/checks/{check_id}").json()
        assert check["source"] == EXAMPLE_ROOT and check["options"]["sweep"] is False
        assert check["options"]["args"] == {"web_test": "1"}
        assert (check["options"]["matrix"], check["options"]["samples"]) == (True, 200)
        assert "sweep" not in check["report"]["sections"] and "matrix" in check["report"]["sections"]
        _tab_to(page, "download-srdf")
        with page.expect_download() as info:
            page.keyboard.press("Enter")
        srdf = Path(info.value.path()).read_bytes()
        assert info.value.suggested_filename == "pr2_base_example.srdf"
        assert srdf == httpx.get(f"{service}/v1/checks/{check_id}/collision-matrix.srdf").content
        assert b"<disable_collisions" in srdf
        seen.check_clean()


def test_token_is_asked_and_kept_for_the_session(browser: Any, guarded: str, tmp_path: Path) -> None:
    with visit(browser, guarded, tmp_path) as seen:
        page = seen.page
        page.wait_for_selector("#auth:not([hidden])")
        assert page.evaluate("document.activeElement.id") == "token"
        seen.shot("web-7-token.png")
        page.keyboard.type("wrong")
        page.keyboard.press("Enter")
        wait_true(page, "document.getElementById('auth-why').textContent.includes('not accepted')")
        page.fill("#token", TOKEN)
        page.keyboard.press("Enter")
        page.wait_for_selector("#recent-empty:not([hidden])")
        assert page.is_hidden("#auth")
        assert page.evaluate("sessionStorage.getItem('geomcheck.token')") == TOKEN
        assert page.evaluate("localStorage.length") == 0
        two = tmp_path / "two_links.urdf"
        two.write_bytes(TWO_LINKS)
        page.set_input_files("#pick-file", str(two))
        page.wait_for_selector("#root:not([disabled])")
        page.click("#submit")
        assert wait_finished(page) == "succeeded"
        name, raw = downloaded(page, "JSON")
        assert name == "two_links-geomcheck.json" and json.loads(raw)["robot"]["name"] == "two_links"
        seen.check_clean(allowed_console=("status of 401",))


def test_limits_are_named_with_their_value(browser: Any, guarded: str, tmp_path: Path) -> None:
    archive = tmp_path / "pr2_base.zip"
    _zip_example(archive)
    with visit(browser, guarded, tmp_path, token=TOKEN) as seen:
        page = seen.page
        page.set_input_files("#pick-folder", str(EXAMPLE))  # counted in the browser: nothing is sent
        page.wait_for_selector("#error:not([hidden])")
        assert page.text_content("#error-message") == (
            f"The folder holds 11 files; the service accepts at most {MAX_FILES} (GEOMCHECK_MAX_FILES)."
        )
        assert page.text_content("#error-title") == "A limit was exceeded" and page.is_disabled("#submit")
        page.set_input_files("#pick-file", str(archive))  # counted by the service while it unpacks
        message = f"zip archive has more than {MAX_FILES} entries"
        wait_true(page, f"document.getElementById('error-message').textContent === {json.dumps(message)}")
        assert page.text_content("#error-title") == "A limit was exceeded" and page.is_disabled("#submit")
        seen.shot("web-11-limit.png")
        seen.check_clean(allowed_console=("status of 413",))


def test_recent_checks_page_on(browser: Any, service: str, tmp_path: Path) -> None:
    summaries = {}
    for name in ("first", "second", "third"):
        body = TWO_LINKS.replace(b'name="two_links"', f'name="{name}"'.encode())
        created = httpx.post(
            f"{service}/v1/checks",
            params={"root": f"{name}.urdf", "sweep": "false"},
            content=body,
            headers={"content-type": "application/xml"},
            timeout=120,
        )
        assert created.status_code == 201, created.text
        summaries[name] = created.json()
    with visit(browser, service, tmp_path) as seen:
        page = seen.page
        names = "rows => rows.map(r => r.cells[0].textContent)"
        # the cell is null until the list arrives: a predicate that throws ends the wait at once
        first_cell = "document.querySelector('#recent-table tbody td')?.textContent === '%s'"
        wait_true(page, first_cell % "third")
        assert page.eval_on_selector_all("#recent-table tbody tr", names) == ["third", "second"]
        assert page.is_disabled("#newer") and page.is_enabled("#older")
        page.click("#older")
        wait_true(page, first_cell % "first")
        assert page.is_enabled("#newer")
        row = page.eval_on_selector_all(
            "#recent-table tbody tr", "rows => Array.from(rows[0].cells).map(c => c.textContent)"
        )
        first = summaries["first"]
        counts = [str(first["summary"][k]) for k in ("error", "warning", "info")]
        shown = {"pass": "pass", "fail": "fail: findings"}[first["verdict"]]
        assert row[:5] == ["first", shown, *counts]
        seen.shot("web-8-recent.png")
        page.click("#newer")
        wait_true(page, first_cell % "third")
        page.click("#recent-table tbody a")  # a recent check opens in the page, at its shared link
        page.wait_for_selector("#result:not([hidden])")
        assert page.text_content("#robot") == "third" and page.url.endswith(
            "/checks/" + str(page.text_content("#check-id"))
        )
        seen.check_clean()


def test_a_long_check_shows_its_stage_and_a_progress_bar(browser: Any, service: str, tmp_path: Path) -> None:
    """The stage and the fraction of a running check, on a wide screen and on a phone."""
    robot = tmp_path / "long_chain.urdf"
    robot.write_bytes(long_chain(8))  # seconds of continuous-joint sweeps (3.5 s alone on this machine)
    with visit(browser, service, tmp_path) as seen:
        page = seen.page
        page.set_input_files("#pick-file", str(robot))
        page.wait_for_selector("#root:not([disabled])")
        page.click("#submit")
        page.wait_for_selector("#stage-box:not([hidden])", timeout=CHECK_TIMEOUT_MS)
        wait_true(page, "document.getElementById('stage').textContent.includes('selfcollision')", CHECK_TIMEOUT_MS)
        first = float(page.eval_on_selector("#stage-bar", "bar => bar.value"))
        wait_true(page, f"document.getElementById('stage-bar').value > {first}", CHECK_TIMEOUT_MS)
        # read together, in one turn of the page's loop: the check goes on between two reads
        stage, bar, percent = page.evaluate(
            "() => ['stage', 'stage-bar', 'stage-percent'].map(id => { const e = document.getElementById(id);"
            " return id === 'stage-bar' ? e.value : e.textContent; })"
        )
        fraction = float(bar)
        assert stage.startswith("Stage ") and " of " in stage and ("selfcollision" in stage or "fix " in stage)
        assert 0.0 < fraction < 1.0
        assert percent == f"{math.floor(fraction * 100 + 0.5)} %"  # the page's Math.round: halves up
        check_id = str(page.text_content("#check-id"))
        seen.shot("web-progress-1280.png")
        with visit(browser, service, tmp_path, path=f"/checks/{check_id}", width=375) as phone:
            phone.page.wait_for_selector("#stage-box:not([hidden])")
            phone.shot("web-progress-375.png")
            assert wait_finished(phone.page) == "succeeded"
            phone.page.wait_for_selector("#result:not([hidden])")
            assert phone.page.is_hidden("#stage-box")
            phone.shot("web-done-375.png")
            phone.check_clean()
        assert wait_finished(page) == "succeeded"
        page.wait_for_selector("#result:not([hidden])")
        assert page.is_hidden("#stage-box")  # a finished check has no stage
        seen.shot("web-done-1280.png")
        seen.check_clean()


def test_cancel_a_running_check(browser: Any, service: str, tmp_path: Path) -> None:
    check_path = httpx.get(f"{service}/openapi.json").json()["paths"].get("/v1/checks/{check_id}", {})
    if "delete" not in check_path:
        pytest.skip("this service has no DELETE /v1/checks/{check_id} (cancel) yet")
    archive = tmp_path / "pr2_base.zip"
    _zip_example(archive)
    with visit(browser, service, tmp_path) as seen:
        page = seen.page
        page.set_input_files("#pick-file", str(archive))
        page.wait_for_selector("#root:not([disabled])")
        page.check("#opt-matrix")  # the matrix keeps the check running long enough to cancel it
        page.fill("#opt-samples", "200000")
        page.click("#submit")
        wait_true(page, "document.getElementById('status').textContent === 'running'")
        page.click("#cancel")
        wait_true(page, "!['queued', 'running', 'submitted'].includes(document.getElementById('status').textContent)")
        assert page.text_content("#status") == "cancelled"
        assert page.is_hidden("#cancel") and page.is_hidden("#result") and page.is_hidden("#error")
        check_id = str(page.text_content("#check-id"))
        assert httpx.get(f"{service}/v1/checks/{check_id}").json()["status"] == "cancelled"
        seen.shot("web-9-cancelled.png")


def _check_package_folder(seen: Visit, folder: Path) -> str:
    """Upload the package ``folder`` (:func:`apitools.mesh_package`) with the page, wait for
    its check; the check's id."""
    write_package(folder, mesh_package())
    page = seen.page
    page.set_input_files("#pick-folder", str(folder))
    page.wait_for_selector("#root:not([disabled])")
    assert page.input_value("#root") == f"{folder.name}/{MESH_PACKAGE_ROOT}"
    page.click("#submit")
    assert wait_finished(page) == "succeeded"
    page.wait_for_selector("#result:not([hidden])")
    return str(page.text_content("#check-id"))


def test_distributed_mode_same_page(browser: Any, tmp_path: Path) -> None:
    broker, database = redis_url(), database_url()
    prefix = unique_prefix()
    store = Store(database, prefix)
    try:
        with cluster(tmp_path, broker, database, prefix) as nodes:
            base = nodes.start_api("api")
            nodes.start_worker("worker")
            nodes.wait_worker_ready("worker")
            with visit(browser, base, tmp_path) as seen:
                check_id = _check_package_folder(seen, tmp_path / "boxed")  # a package with meshes
                with httpx.Client(base_url=base) as client:  # the download and the read after it alike
                    verified_check(client, check_id)
                _, raw = downloaded(seen.page, "JSON")
                assert raw == httpx.get(f"{base}/v1/checks/{check_id}/report.json").content
                assert json.loads(raw)["robot"]["name"] == "boxed"
                assert json.loads(raw)["robot"]["meshes_loaded"] == 2
                seen.shot("web-10-distributed.png")
                seen.check_clean()
    finally:
        store.drop_schema()
        store.dispose()


def test_a_phone_sees_the_shared_check_with_its_options_and_failed_is_not_fail(
    browser: Any, service: str, tmp_path: Path
) -> None:
    broken = httpx.post(
        f"{service}/v1/checks",
        params={"root": "broken.urdf"},
        content=MALFORMED,
        headers={"content-type": "application/xml"},
        timeout=120,
    )
    assert broken.status_code == 422, broken.text
    failed = httpx.get(f"{service}/v1/checks", params={"status": "failed"}, timeout=30).json()["items"][0]
    asked = {"root": "asked.urdf", "samples": "500", "matrix": "true", "sweep": "false", "seed": "7"}
    body = TWO_LINKS.replace(b'name="two_links"', b'name="asked"')
    shared = httpx.post(
        f"{service}/v1/checks", params=asked, content=body, headers={"content-type": "application/xml"}, timeout=120
    )
    assert shared.status_code == 201, shared.text
    with visit(browser, service, tmp_path, path=f"/checks/{shared.json()['id']}", width=375) as seen:
        page = seen.page
        page.wait_for_selector("#result:not([hidden])")
        # the shared page shows the options the check ran with, not the defaults
        assert page.input_value("#opt-samples") == "500" and page.input_value("#opt-seed") == "7"
        assert page.is_checked("#opt-matrix") and not page.is_checked("#opt-sweep")
        assert page.is_visible("#options-of")
        page.wait_for_function("document.querySelectorAll('#recent-table tbody tr').length === 2")
        badges = page.eval_on_selector_all("#recent-table tbody .badge", "bs => bs.map(b => b.textContent)")
        assert badges == ["fail: findings" if shared.json()["verdict"] == "fail" else "pass", "could not run"]
        reason = page.text_content("#recent-table tbody tr:nth-child(2) .reason")
        assert reason == failed["reason"] and "GC101" in reason
        # nothing is wider than the phone's screen
        assert page.evaluate("document.documentElement.scrollWidth") <= 375
        # the recent checks fit too: no column hidden behind a scroll bar
        assert page.evaluate("(r => r.scrollWidth <= r.clientWidth)(document.querySelector('#recent'))")
        seen.shot("web-10-phone.png")
        seen.check_clean()


@pytest.mark.parametrize("width", [375, 1280])
def test_root_fixes_and_tables_at_every_width(browser: Any, service: str, tmp_path: Path, width: int) -> None:
    """The chosen root is shown whole with why; the progress is in sight once Check is pressed
    (1280 x 900 too); the report answers first and the fixes' verification follows as a state
    of its own; nothing is wider than the screen: the page, its findings and recent-checks
    tables, and the HTML report in its frame."""
    with visit(browser, service, tmp_path, width=width) as seen:
        page = seen.page
        assert ".sdf" in str(page.get_attribute("#pick-file", "accept")).split(",")  # as the drop zone says
        page.set_input_files("#pick-folder", str(EXAMPLE))
        page.wait_for_selector("#root:not([disabled])")
        root = f"pr2_base/{EXAMPLE_ROOT}"
        assert page.input_value("#root") == root and page.text_content("#root-path") == root
        box = page.locator("#root-path").bounding_box()
        assert box is not None and box["x"] >= 0 and box["x"] + box["width"] <= width  # whole, never cut
        assert str(page.text_content("#root-why")).startswith("Chosen because it is the only file that makes a robot")
        seen.shot(f"web-root-{width}.png")
        page.click("#submit")
        page.wait_for_selector("#progress:not([hidden])")
        top = page.evaluate("document.getElementById('progress').getBoundingClientRect().top")
        assert 0 <= top < 900  # in sight, not below the fold
        assert wait_finished(page) == "succeeded"
        page.wait_for_selector("#fixes-state:not([hidden])")
        first = str(page.text_content("#fixes-text"))
        assert first.startswith(("Verifying the offered fixes", "The offered fixes are verified"))
        wait_true(
            page, "document.getElementById('fixes-text').textContent.startsWith('The offered fixes are verified')"
        )
        assert not page.is_disabled("#downloads button:text-is('Safe fixes (patch)')")
        name, _ = downloaded(page, "Safe fixes (patch)")
        assert name == "pr2_base_example-fixes.patch"
        page.click("#findings-box summary")
        wait_true(page, "document.querySelectorAll('#recent-table tbody tr').length > 0")
        widths = page.evaluate(
            """() => {
              const $ = (id) => document.getElementById(id);
              return [[document.documentElement.scrollWidth, innerWidth],
                      [$('findings').scrollWidth, $('findings-box').clientWidth],
                      [$('recent-table').scrollWidth, $('recent').clientWidth]];
            }"""
        )
        assert all(inside <= box for inside, box in widths), widths
        frame = next(f for f in page.frames if f != page.main_frame)
        wait_true(page, "document.getElementById('report').srcdoc.length > 0")
        frame.wait_for_selector("h1")
        assert frame.evaluate("document.documentElement.scrollWidth <= innerWidth")
        seen.shot(f"web-fixes-{width}.png")
        seen.check_clean()


def test_several_equally_likely_robots_are_not_preselected(browser: Any, service: str, tmp_path: Path) -> None:
    archive = tmp_path / "two.zip"
    with zipfile.ZipFile(archive, "w") as zipped:
        zipped.writestr("robots/a.urdf", TWO_LINKS)
        zipped.writestr("robots/b.urdf", TWO_LINKS.replace(b"two_links", b"other"))
    with visit(browser, service, tmp_path, width=375) as seen:
        page = seen.page
        page.set_input_files("#pick-file", str(archive))
        page.wait_for_selector("#root:not([disabled])")
        assert page.input_value("#root") == "" and page.is_disabled("#submit")
        assert str(page.text_content("#root-why")).startswith("Choose it: 2 files could each be the robot")
        page.select_option("#root", "robots/b.urdf")
        assert not page.is_disabled("#submit") and page.text_content("#root-why") == "Chosen by you."
        seen.check_clean()


def test_a_tree_trimmed_to_the_arm_preselects_the_arm(browser: Any, service: str, tmp_path: Path) -> None:
    """Spot's package trimmed to its arm: the full robot's xacro names body meshes the upload lacks,
    so the arm is preselected and the full robot's option says what it lacks."""
    ns = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'

    def mesh(name: str) -> str:
        return f'<visual><geometry><mesh filename="package://arm_description/meshes/{name}"/></geometry></visual>'

    arm = f'<robot {ns}><xacro:macro name="arm"><link name="arm">{mesh("arm.stl")}</link></xacro:macro></robot>'
    include = '<xacro:include filename="$(find arm_description)/urdf/arm_macro.xacro"/>'
    full = f'<robot name="full" {ns}>{include}<link name="body">{mesh("body.stl")}</link><xacro:arm/></robot>'
    alone = f'<robot name="alone" {ns}>{include}<xacro:arm/></robot>'
    archive = tmp_path / "arm.zip"
    with zipfile.ZipFile(archive, "w") as zipped:
        zipped.writestr("package.xml", "<package><name>arm_description</name></package>")
        zipped.writestr("urdf/arm_macro.xacro", arm)
        zipped.writestr("urdf/full.urdf.xacro", full)
        zipped.writestr("urdf/standalone_arm.urdf.xacro", alone)
        zipped.writestr("meshes/arm.stl", "solid arm\nendsolid arm\n")
    with visit(browser, service, tmp_path) as seen:
        page = seen.page
        page.set_input_files("#pick-file", str(archive))
        page.wait_for_selector("#root:not([disabled])")
        assert page.input_value("#root") == "urdf/standalone_arm.urdf.xacro"
        texts = page.eval_on_selector_all("#root option", "os => os.map(o => o.textContent)")
        assert "urdf/full.urdf.xacro (robot full, includes 1 file, lacks 1 file of its own package)" in texts
        seen.shot("web-trimmed-arm.png")
        seen.check_clean()
