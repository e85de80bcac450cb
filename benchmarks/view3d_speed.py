"""The HTML report's 3D view: report size and the time from opening the file to the first frame.

    python benchmarks/view3d_speed.py [--repeat 3] [ROBOT ...]

Robots are robots.toml table names (default: the bundled example, the 2009 PR2, and the corpus
robots with the most mesh triangles and the most links, unitree_h1 and icub); ``example`` is
the bundled example. For each it prints the HTML report's size with the view and without it
(``view_3d = false``), the scene's triangles (kept / in the files), the time the scene family
takes (its meshes read and decimated, no cache), and the first frame in headless Chromium (WebGL on
SwiftShader: software rendering, a pessimistic figure), the minimum over the repeats, as the
page measures it (``performance.now()`` at its first render: from navigation start, the file
read, parsed and its scripts run). Budget: the 2009 PR2's report at most 6 MB.
Needs the corpus (GEOMCHECK_CORPUS) and /usr/bin/chromium with Playwright.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

from geomcheck.cache import using_store
from geomcheck.checks import CheckContext
from geomcheck.checks import scene as scene_family
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.options import CheckOptions
from geomcheck.pipeline import run_check
from geomcheck.report import render
from geomcheck.report.model import Report

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))
import corpus_robots  # noqa: E402

BUDGET_BYTES = 6_000_000  # the 2009 PR2's report with the view
DEFAULT = ("example", "pr2_2009", "unitree_h1", "icub")
CHROMIUM_ARGS = ["--no-sandbox", "--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]


def first_frame_ms(path: Path, repeat: int) -> int:
    from playwright.sync_api import sync_playwright

    times = []
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path="/usr/bin/chromium", args=CHROMIUM_ARGS)
        try:
            for _ in range(repeat):
                page = browser.new_page(viewport={"width": 1280, "height": 900})
                page.route("**/*", lambda r: r.continue_() if r.request.url.startswith("file:") else r.abort())
                page.goto(path.resolve().as_uri())
                page.wait_for_selector("[data-v3d][data-ready]", timeout=120_000)
                times.append(int(page.get_attribute("[data-v3d]", "data-first-frame-ms") or 0))
                page.close()
        finally:
            browser.close()
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=list(DEFAULT))
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    corpus = corpus_robots.corpus_dir()
    robots = {r.name: r for r in corpus_robots.robots(corpus)} if corpus else {}
    print(f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")
    header = f"{'robot':<16} {'with view':>10} {'without':>9} {'triangles':>17} {'scene s':>8} {'first frame':>12}"
    print(header)
    with tempfile.TemporaryDirectory() as folder:
        for name in args.robots:
            if name == "example":
                root, packages, robot_args = REPO / "examples/pr2_base/robots/pr2_base.urdf.xacro", {}, {}
            elif name in robots:
                r = robots[name]
                root, packages, robot_args = r.root, dict(r.packages), dict(r.args)
            else:
                print(f"{name:<16} not in the corpus")
                continue
            bundle = make_bundle(root, packages=packages)
            with using_store(None):  # cold: the scene decimates every mesh
                loaded = load_description(bundle, robot_args)
                ctx = CheckContext(loaded=loaded, meshes=MeshStore(bundle), options=CheckOptions())
                start = time.perf_counter()
                scene = scene_family.run(ctx).sections.get("scene", {})
                scene_s = time.perf_counter() - start
            report = run_check(bundle, CheckOptions(args=robot_args))
            path = Path(folder) / f"{name}.html"
            path.write_text(render(report, "html"), encoding="utf-8")
            data = report.to_dict()
            data["sections"].pop("scene", None)
            without = len(render(Report.from_dict(data), "html").encode("utf-8"))
            kept = sum(m["triangles"] for m in scene.get("meshes", []))
            source = sum(m["source_triangles"] for m in scene.get("meshes", []))
            frame = first_frame_ms(path, args.repeat)
            size = path.stat().st_size
            flag = "  OVER BUDGET" if name.startswith("pr2_2009") and size > BUDGET_BYTES else ""
            print(
                f"{name:<16} {size / 1e6:>8.2f}MB {without / 1e6:>7.2f}MB {kept:>8,}/{source:<8,} "
                f"{scene_s:>8.2f} {frame:>9} ms{flag}"
            )


if __name__ == "__main__":
    main()
