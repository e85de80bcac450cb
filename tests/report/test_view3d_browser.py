"""The HTML report's 3D view in a real browser: Debian's Chromium driven by Playwright, WebGL
through SwiftShader (Chromium's software renderer), on the bundled example and the 2009 PR2.

Every request is routed: anything but the page itself is refused and fails the test, and so
do console errors. The canvas is read back (the view keeps its drawing buffer) and its pixels
classified: the grey of the visual mesh and the red of an erroneous collision box must be
there. Screenshots at 1280 and 375 px go to the test's tmp_path, and to test-output/view3d/
at the repo root when GEOMCHECK_SCREENSHOTS is set.
"""

from __future__ import annotations

import base64
import io
import json
import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from PIL import Image

from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report import render

CHROMIUM = Path("/usr/bin/chromium")
# WebGL without a GPU: ANGLE on SwiftShader
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--use-gl=angle",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "pr2_base" / "robots" / "pr2_base.urdf.xacro"
READY_MS = 60_000  # first frame; SwiftShader on a loaded CI machine is slow
NO_WEBGL = """(() => {
  const original = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {
    return /webgl/i.test(kind) ? null : original.call(this, kind, ...rest);
  };
})();"""

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
def viewing(path: Path, width: int = 1280, webgl: bool = True) -> Iterator[Visit]:
    """``path`` in headless Chromium, ``width`` px wide; requests other than the page are refused."""
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": width, "height": 900})
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
            if not webgl:
                page.add_init_script(NO_WEBGL)
            page.goto(visit.url)
            yield visit
        finally:
            browser.close()


def save(visit: Visit, tmp_path: Path, name: str, element: str | None = None) -> Path:
    """A screenshot of the viewport, or of ``element``."""
    shot = tmp_path / name
    if element is None:
        visit.page.screenshot(path=str(shot))
    else:
        visit.page.locator(element).screenshot(path=str(shot))
    if os.environ.get("GEOMCHECK_SCREENSHOTS"):
        out = REPO / "test-output" / "view3d"
        out.mkdir(parents=True, exist_ok=True)
        (out / name).write_bytes(shot.read_bytes())
    assert shot.stat().st_size > 10_000
    return shot


def canvas_pixels(visit: Visit) -> np.ndarray:
    """The 3D view's canvas as RGB pixels (h, w, 3), read from its drawing buffer."""
    visit.page.wait_for_function("() => new Promise((done) => requestAnimationFrame(() => done(true)))")
    url = visit.page.evaluate("() => document.querySelector('.v3d-canvas').toDataURL('image/png')")
    data = base64.b64decode(url.split(",", 1)[1])
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"), dtype=np.int16)


def shares(pixels: np.ndarray) -> dict[str, float]:
    """Fractions of the canvas that are background, the visual mesh's grey, a red (error)
    collision element and the suggested primitive's green."""
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    background = (r > 240) & (g > 240) & (b > 240)
    grey = (np.abs(r - g) < 12) & (np.abs(g - b) < 18) & (r > 50) & (r < 215)
    red = (r > g + 30) & (r > b + 25)
    green = (g > r + 30) & (g > b + 5)
    classes = {"background": background, "grey": grey, "red": red, "green": green}
    return {name: float(mask.sum()) / r.size for name, mask in classes.items()}


def ready(visit: Visit) -> int:
    """Waits for the first frame; its time from opening the page [ms]."""
    visit.page.wait_for_selector("[data-v3d][data-ready]", timeout=READY_MS)
    return int(visit.page.get_attribute("[data-v3d]", "data-first-frame-ms") or 0)


def focus_gc301(visit: Visit, link: str) -> set[str]:
    """Chooses the GC301 finding on ``link``'s collision[0]; what the view then shows."""
    page = visit.page
    button = page.locator(".v3d-item", has_text="GC301").filter(has_text=f"link {link} collision[0]")
    finding = button.first.get_attribute("data-key")
    button.first.click()
    page.wait_for_function(f"() => document.querySelector('[data-v3d]').dataset.focus === {finding!r}")
    return set(json.loads(page.get_attribute("[data-v3d]", "data-shown") or "[]"))


def assert_robot_and_focus(visit: Visit, tmp_path: Path, name: str) -> None:
    """The robot drawn, then one GC301 finding focused: its link's mesh, the red box, the suggestion."""
    page = visit.page
    assert ready(visit) > 0
    page.locator("#view3d").scroll_into_view_if_needed()
    whole = shares(canvas_pixels(visit))
    assert whole["background"] < 0.95 and whole["grey"] > 0.02, whole
    save(visit, tmp_path, f"{name}-1280.png", "#view3d")
    shown = focus_gc301(visit, "base_link")
    assert shown == {"base_link/visual[0]", "base_link/collision[0]", "base_link/suggested:collision[0]"}
    focused = shares(canvas_pixels(visit))
    # the base's mesh in grey, its thin slab in red, the suggested box's dashes in green
    assert focused["grey"] > 0.03 and focused["red"] > 0.002 and focused["green"] > 0.0005, focused
    assert focused["background"] > whole["background"] - 0.2
    assert "GC301" in page.locator(".v3d-focus").inner_text()
    save(visit, tmp_path, f"{name}-1280-gc301.png", "#view3d")
    page.get_by_role("button", name="show all").click()
    page.wait_for_function("() => document.querySelector('[data-v3d]').dataset.focus === ''")
    visit.check_clean()


def test_the_example_in_3d(tmp_path: Path) -> None:
    path = tmp_path / "example.html"
    path.write_text(render(run_check(make_bundle(EXAMPLE), CheckOptions()), "html"), encoding="utf-8")
    with viewing(path) as visit:
        assert_robot_and_focus(visit, tmp_path, "example")
        # a joint slider turns the caster; the default pose puts it back
        page = visit.page
        page.click(".v3d-joints summary")
        before = canvas_pixels(visit)
        turn = "(e) => { e.value = '1.5'; e.dispatchEvent(new Event('input')); }"
        page.eval_on_selector("input[data-joint='fl_caster_rotation_joint']", turn)
        assert (np.abs(canvas_pixels(visit) - before).sum(axis=2) > 30).mean() > 0.001
        page.get_by_role("button", name="default pose").click()
        assert np.array_equal(canvas_pixels(visit), before)
        # toggles: without visual meshes no grey is left; a sweep shows its closest pose
        visit.page.locator("[data-show='visual']").uncheck()
        assert shares(canvas_pixels(visit))["grey"] < 0.002
        visit.page.locator("[data-sweep]").first.click()
        shown = visit.page.get_attribute("[data-v3d]", "data-shown") or ""
        assert "fl_caster_l_wheel_link/pose:sweep0/collision[0]" in shown
        visit.check_clean()
    with viewing(path, width=375) as visit:
        page = visit.page
        ready(visit)
        canvas, side = page.locator(".v3d-canvas").bounding_box(), page.locator(".v3d-side").bounding_box()
        assert canvas is not None and side is not None
        assert 300 < canvas["width"] <= 375 and side["y"] >= canvas["y"] + canvas["height"]  # the list below
        page.locator("#view3d").scroll_into_view_if_needed()
        assert shares(canvas_pixels(visit))["grey"] > 0.02
        save(visit, tmp_path, "example-375.png")
        visit.check_clean()


@pytest.mark.corpus
def test_the_2009_pr2_in_3d(pr2_root: Path, tmp_path: Path) -> None:
    report = run_check(make_bundle(pr2_root / "pr2_description/robots/pr2.urdf.xacro", search=[pr2_root]))
    path = tmp_path / "pr2.html"
    path.write_text(render(report, "html"), encoding="utf-8")
    assert path.stat().st_size < 6_000_000
    with viewing(path) as visit:
        assert_robot_and_focus(visit, tmp_path, "pr2")
    with viewing(path, width=375) as visit:
        ready(visit)
        visit.page.goto(visit.url + "#view3d")
        # the menu stays one line: the section a link jumps to starts below it, heading shown
        nav, heading = visit.page.locator("nav.toc").bounding_box(), visit.page.locator("#view3d h2").bounding_box()
        assert nav is not None and heading is not None
        assert nav["height"] < 60 and heading["y"] >= nav["y"] + nav["height"], (nav, heading)
        save(visit, tmp_path, "pr2-375.png")
        visit.check_clean()


def test_without_webgl_the_view_points_to_the_orthographic_views(tmp_path: Path) -> None:
    path = tmp_path / "example.html"
    path.write_text(render(run_check(make_bundle(EXAMPLE), CheckOptions(sweep=False)), "html"), encoding="utf-8")
    with viewing(path, webgl=False) as visit:
        page = visit.page
        page.wait_for_load_state("load")
        fallback = page.locator(".v3d-fallback")
        assert fallback.is_visible() and "orthographic views" in fallback.inner_text()
        assert not page.locator(".v3d-stage").is_visible() and not page.locator(".v3d-side").is_visible()
        assert page.get_attribute("[data-v3d]", "data-ready") is None
        assert page.locator("#link-base_link svg.views").is_visible()
        visit.check_clean()
