"""The HTML report in a real browser: headless Chromium (Debian's package) driven by Playwright.

Each page is loaded from a file:// URL with every request routed: anything but the page
itself is refused and fails the test. Console errors fail it too. Screenshots go to the
test's tmp_path, and to test-output/ at the repo root when GEOMCHECK_SCREENSHOTS is set.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from geomcheck.report import render
from geomcheck.report.model import Report

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
REPO = Path(__file__).resolve().parents[2]

pytestmark = [
    pytest.mark.long,
    pytest.mark.browser,
    pytest.mark.skipif(not CHROMIUM.exists(), reason="headless Chromium not found at /usr/bin/chromium"),
]


@dataclass
class Visit:
    page: Any
    url: str
    console: list[str] = field(default_factory=list)
    refused: list[str] = field(default_factory=list)

    def check_clean(self) -> None:
        assert self.refused == [], f"the page made network requests: {self.refused}"
        assert self.console == [], f"console errors: {self.console}"


@contextmanager
def browser_page(path: Path, javascript: bool = True) -> Iterator[Visit]:
    """``path`` opened in headless Chromium at 1280 px wide; requests other than the page are refused."""
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900}, java_script_enabled=javascript)
            visit = Visit(page=page, url=path.resolve().as_uri())

            def route(request_route: Any) -> None:
                if request_route.request.url.split("#")[0] == visit.url:
                    request_route.continue_()
                else:
                    visit.refused.append(request_route.request.url)
                    request_route.abort()

            page.route("**/*", route)
            page.on("console", lambda m: visit.console.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: visit.console.append(str(e)))
            page.goto(visit.url)
            yield visit
        finally:
            browser.close()


def save_screenshot(visit: Visit, tmp_path: Path, name: str, **options: Any) -> Path:
    shot = tmp_path / name
    visit.page.screenshot(path=str(shot), **options)
    if os.environ.get("GEOMCHECK_SCREENSHOTS"):
        out = REPO / "test-output"
        out.mkdir(exist_ok=True)
        (out / name).write_bytes(shot.read_bytes())
    assert shot.stat().st_size > 10_000
    return shot


@pytest.fixture(scope="module")
def sample_page(html_samples: ModuleType, tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("demo")
    report = html_samples.sample_report(folder)
    path = folder / "report.html"
    path.write_text(render(report, "html"), encoding="utf-8")
    return path


def test_sample_report_in_chromium(sample_page: Path, tmp_path: Path) -> None:
    with browser_page(sample_page) as visit:
        page = visit.page
        save_screenshot(visit, tmp_path, "html-report-sample.png", full_page=True)
        assert page.title() == "demo_base: geomcheck report"
        figure = page.locator("#link-base_link svg.views")
        assert figure.is_visible()
        box = figure.bounding_box()
        assert box is not None and box["width"] > 300
        assert page.locator("#sweeps svg.polar").count() == 2
        assert page.locator("svg.matrix rect").count() == 10
        page.locator("svg.matrix rect.m-witness").hover()
        assert "witness" in page.locator("#matrix-readout").inner_text()
        # the script's conveniences
        assert page.locator("details.link[open]").count() == 2
        page.get_by_role("button", name="collapse all").click()
        assert page.locator("details.link[open]").count() == 0
        page.get_by_role("button", name="expand all").click()
        assert page.locator("details.link[open]").count() == 6
        page.goto(visit.url + "#link-laser_ring_link")
        assert page.locator("#link-laser_ring_link").get_attribute("open") is not None
        visit.check_clean()


def test_sample_report_without_script_and_in_print(sample_page: Path, tmp_path: Path) -> None:
    with browser_page(sample_page, javascript=False) as visit:
        page = visit.page
        assert page.locator("#findings article").count() == 5
        assert page.locator("#link-base_link svg.views").is_visible()
        assert not page.get_by_role("button", name="expand all").is_visible()  # needs the script
        closed = page.locator("#link-laser_ring_link .link-body")
        assert not closed.is_visible()
        page.emulate_media(media="print")
        assert closed.is_visible()  # print expands collapsed sections without the script
        assert not page.locator("nav.toc").is_visible()
        save_screenshot(visit, tmp_path, "html-report-sample-print.png", full_page=True)
        visit.check_clean()


@pytest.mark.corpus
def test_full_pr2_report_in_chromium(pr2_root: Path, tmp_path: Path) -> None:
    from geomcheck.load import make_bundle
    from geomcheck.options import CheckOptions
    from geomcheck.pipeline import run_check

    bundle = make_bundle(pr2_root / "pr2_description/robots/pr2.urdf.xacro", search=[pr2_root])
    report = run_check(bundle, CheckOptions(matrix=True, samples=300))
    path = tmp_path / "pr2.html"
    text = render(report, "html")
    path.write_text(text, encoding="utf-8")
    assert render(Report.from_dict(report.to_dict()), "html") == text
    with browser_page(path) as visit:
        page = visit.page
        base = page.locator("#link-base_link")
        assert base.get_attribute("open") is not None
        save_screenshot(visit, tmp_path, "html-report-pr2-base.png", clip=base.bounding_box(), full_page=True)
        # the thin collision slab is drawn far smaller than the base mesh, in the front view
        heights = page.evaluate(
            """() => {
                const svg = document.querySelector('#link-base_link svg.views');
                const h = (sel) => svg.querySelector(sel).getBBox().height;
                return [h('path.mesh'), h('path.collision')];
            }"""
        )
        assert heights[1] < 0.1 * heights[0], heights
        wheel = page.locator("#findings article", has_text="link bl_caster_l_wheel_link").filter(  # the 8 wheels as one
            has_text="radius of gyration"
        )
        assert wheel.count() >= 1 and wheel.first.is_visible()
        assert page.locator("#sweep-fl_caster_rotation_joint svg.polar").count() >= 2
        if "matrix" in report.sections:
            assert page.locator("svg.matrix").is_visible()
        page.get_by_role("button", name="collapse all").click()
        save_screenshot(visit, tmp_path, "html-report-pr2.png", full_page=True)
        visit.check_clean()
