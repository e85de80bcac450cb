"""The HTML report (geomcheck/report/html.py and its view model, drawings and templates)."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from lxml import html as lxml_html

from geomcheck.report import FORMATS, render
from geomcheck.report.html import asset
from geomcheck.report.model import Report


@pytest.fixture(scope="module")
def sample_dict(html_samples: ModuleType, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    return html_samples.sample_report_dict(tmp_path_factory.mktemp("demo"))


@pytest.fixture(scope="module")
def page(sample_dict: dict[str, Any]) -> str:
    return render(Report.from_dict(sample_dict), "html")


@pytest.fixture(scope="module")
def tree(page: str) -> Any:
    return lxml_html.fromstring(page)


def words(element: Any) -> str:
    """The element's text, its pieces joined by single spaces."""
    return " ".join(" ".join(element.itertext()).split())


def minimal_report(**changes: Any) -> Report:
    data: dict[str, Any] = {
        "schema": "geomcheck.report/1",
        "tool": {"name": "geomcheck", "version": "0.1.0"},
        "created": "2026-01-01T00:00:00Z",
        "robot": {"name": "empty", "source": "empty.urdf", "links": 1, "joints": 0},
        "diagnostics": [],
        "sections": {},
    }
    data.update(changes)
    return Report.from_dict(data)


def test_html_is_a_registered_format(sample_dict: dict[str, Any]) -> None:
    assert FORMATS["html"] == "html"
    text = render(Report.from_dict(sample_dict), "html")
    assert text.startswith('<!DOCTYPE html>\n<html lang="en">')
    assert text.endswith("</html>\n")


def test_one_self_contained_file(page: str, tree: Any) -> None:
    assert not tree.xpath("//link | //img | //iframe | //object | //embed | //script[@src] | //*[@srcset]")
    for element in tree.xpath("//*[@href]"):
        assert element.get("href").startswith("#"), element.get("href")
    styles = "".join(tree.xpath("//style/text()"))
    assert "url(" not in styles and "@import" not in styles
    # the only URLs in the page: the SVG namespace, XHTML's (three.js makes its canvas in it),
    # and text that quotes one (xacro's namespace); no script can fetch anything
    namespaces = ("http://www.w3.org/2000/svg", "http://www.w3.org/1999/xhtml", "http://www.ros.org/wiki/xacro")
    for url in re.findall(r"https?://[^\s\"'<>&]+", page):
        assert url in namespaces, url
    scripts = "".join(tree.xpath("//script[not(@type)]/text()"))
    for call in ("fetch(", "XMLHttpRequest", "import(", "Worker(", "WebSocket", "sendBeacon", ".src="):
        assert call not in scripts, call
    assert tree.xpath("//script[@type='application/json']/@id") == ["v3d-data"]
    three = str(asset("three.min.js"))
    assert three in page and len(page) - len(three) < 300_000


def test_header_states_robot_verdict_and_counts(tree: Any) -> None:
    header = tree.xpath("//header[@class='top']")[0]
    assert header.xpath(".//h1/text()") == ["demo_base"]
    assert header.xpath(".//span[contains(@class, 'verdict')]/@class") == ["verdict fail"]
    text = header.text_content()
    assert "robots/demo.urdf.xacro" in text and "2026-01-01T00:00:00Z" in text and "0.1.0" in text
    counts = [words(a) for a in header.xpath(".//a[contains(@class, 'count')]")]
    assert counts == ["2 errors", "3 warnings", "0 info"]


def test_findings_are_grouped_by_rule_errors_first(tree: Any) -> None:
    groups = tree.xpath("//section[@id='findings']/div[contains(@class, 'group')]")
    heads = [(g.get("class"), g.xpath(".//a[@class='code']/text()")[0]) for g in groups]
    assert heads == [
        ("group error", "GC401"),
        ("group error", "GC505"),
        ("group warning", "GC103"),
        ("group warning", "GC301"),
        ("group warning", "GC507"),
    ]
    first = groups[0].xpath(".//article")[0]
    assert first.get("id") == "finding-1"
    assert "links base_link / fl_caster_l_wheel_link" in first.text_content()


def test_every_rule_code_links_to_its_documentation(tree: Any) -> None:
    targets = {a.get("href")[1:] for a in tree.xpath("//a[@class='code']")}
    assert targets == {"rule-GC103", "rule-GC301", "rule-GC401", "rule-GC505", "rule-GC507"}
    docs = tree.xpath("//section[@id='rules']/article")
    assert {d.get("id") for d in docs} == targets  # only the rules that occur
    known = tree.xpath("//article[@id='rule-GC505']")[0].text_content()
    assert "What it does" in known and "inertia-exceeds-geometry" in known


def test_findings_show_help_location_and_excerpt(tree: Any) -> None:
    legacy = tree.xpath("//div[@id='group-GC103-warning']")[0]
    assert legacy.xpath("./p[@class='help']")[0].text_content().startswith("Fix: Prefix them with xacro:")
    source = legacy.xpath(".//details[@class='src']")[0]
    assert source.get("open") is not None  # few findings: excerpts open
    assert source.xpath("./summary/text()") == ["urdf/base.urdf.xacro:2:3"]
    here = source.xpath(".//span[@class='line here']")[0]
    assert here.xpath("./span[@class='ln']/text()") == ["2"]
    assert "caster_offset_x" in here.text_content()


def test_text_from_the_report_is_escaped(page: str) -> None:
    assert "<&>" not in page and "&lt;&amp;&gt; &#39;quoted&#39;" in page
    report = minimal_report(
        diagnostics=[
            {
                "code": "GC105",
                "name": "unknown-urdf-element",
                "severity": "warning",
                "message": "<script>alert(1)</script>",
                "help": 'use <origin> "here"',
                "link": "<b>bold</b>",
            }
        ]
    )
    text = render(report, "html")
    assert "<script>alert(1)</script>" not in text and "&lt;script&gt;alert(1)&lt;/script&gt;" in text
    assert "<b>bold</b>" not in text and "link &lt;b&gt;bold&lt;/b&gt;" in text


def test_links_with_findings_come_first_and_open(tree: Any) -> None:
    links = tree.xpath("//section[@id='links']/details")
    names = [d.xpath("./summary/span[@class='name']/text()")[0] for d in links]
    opened = [d.get("open") is not None for d in links]
    assert names[:2] == ["base_link", "fl_caster_l_wheel_link"]
    assert opened == [True, True, False, False, False, False]
    assert set(names) == {
        "base_link",
        "fl_caster_l_wheel_link",
        "fl_caster_rotation_link",
        "fl_caster_r_wheel_link",
        "laser_ring_link",
        "lost_link",
    }


def test_link_picture_and_fit_metrics(tree: Any) -> None:
    base = tree.xpath("//details[@id='link-base_link']")[0]
    figure = base.xpath(".//svg[@class='views']")[0]
    classes = [p.get("class") for p in figure.xpath(".//*[local-name()='path']")]
    assert classes.count("mesh") == 3 and classes.count("collision") == 3 and classes.count("suggested") == 3
    labels = figure.xpath(".//*[local-name()='text']/text()")
    assert {"front, from +x", "side, from −y", "top, from +z", "20 cm"} <= set(labels)
    card = base.xpath(".//div[@class='collision-card']")[0]
    assert "box 0.650 × 0.650 × 0.040 m" in card.text_content()
    assert card.xpath(".//div[@class='metric bad']")  # coverage flagged: GC301 on collision[0]
    assert '<box size="0.66 0.66 0.9"/>' in card.xpath(".//div[@class='suggest']/pre/text()")[0]
    chips = base.xpath(".//div[@class='chips']/a/text()")
    assert chips == ["GC401", "GC301"]
    lost = tree.xpath("//details[@id='link-lost_link']")[0].text_content()
    assert "visual[0]: mesh file not found" in lost


def test_sweep_charts_mark_contact(tree: Any) -> None:
    sweep = tree.xpath("//div[@id='sweep-fl_caster_rotation_joint']")[0]
    assert "sweep hit" in sweep.get("class")
    charts = sweep.xpath(".//svg[@class='polar']")
    assert len(charts) == 2
    first, second = charts
    assert first.xpath(".//*[@class='contact']") and first.xpath(".//*[@class='contact-arc']")
    assert not second.xpath(".//*[@class='contact']")
    rows = [[words(td) for td in r.xpath("./td")] for r in sweep.xpath(".//tbody/tr")]
    assert rows[0] == ["base_link / fl_caster_l_wheel_link", "-10.0 mm", "217°", "172°–268°", "10.0 mm"]
    assert rows[1] == ["base_link / fl_caster_r_wheel_link", "18.0 mm", "133°", "none", "–"]


def test_matrix_grid_classes_legend_and_hover(tree: Any, sample_dict: dict[str, Any]) -> None:
    grid = tree.xpath("//svg[@class='matrix']")[0]
    cells = grid.xpath(".//*[local-name()='rect']")
    assert len(cells) == len(sample_dict["sections"]["matrix"]["pairs"]) == 10
    classes = sorted(c.get("class") for c in cells)
    assert classes.count("m-adjacent") == 3 and classes.count("m-certified") == 2 and classes.count("m-witness") == 1
    tips = [c.xpath("./*[local-name()='title']/text()")[0] for c in cells]
    witness = next(t for t in tips if "witness" in t)
    assert "fl_caster_r_wheel_link / laser_ring_link" in witness and "depth 3.0 mm" in witness
    legend = [words(li) for li in tree.xpath("//ul[@class='legend-list']/li")]
    assert legend[0] == "adjacent (parent and child) 3"
    assert len(legend) == 7


def test_matrix_under_pinocchio_semantics_says_so_and_counts_the_missing_pairs(sample_dict: dict[str, Any]) -> None:
    matrix = json.loads(json.dumps(sample_dict["sections"]["matrix"]))
    links = len(matrix["links"])
    matrix["semantics"] = "pinocchio"
    matrix["pairs"] = matrix["pairs"][1:]  # one pair left out: a rigid body
    data = {**sample_dict, "sections": {**sample_dict["sections"], "matrix": matrix}}
    pinocchio = lxml_html.fromstring(render(Report.from_dict(data), "html"))
    head = words(pinocchio.xpath("//section[@id='matrix']//div[@class='section-head']/p")[0])
    assert "Pinocchio semantics (links joined only by fixed joints make no pair)" in head
    legend = [words(li) for li in pinocchio.xpath("//ul[@class='legend-list']/li")]
    assert legend[-1] == f"one rigid body: no pair {links * (links - 1) // 2 - len(matrix['pairs'])}"
    assert len(legend) == 8


def test_inertia_table_flags_the_impossible_wheel_first(tree: Any) -> None:
    rows = tree.xpath("//table[@class='inertia']/tbody/tr")
    first = rows[0]
    assert first.get("class") == "flagged"
    assert first.xpath("./td[1]/a/text()") == ["fl_caster_l_wheel_link"]
    assert "needs mass outside the geometry" in first.text_content()
    assert first.xpath(".//*[@class='bar over']")
    assert rows[1].get("class") is None and "base_link" in rows[1].text_content()


def test_same_report_same_bytes_also_after_storing(sample_dict: dict[str, Any], page: str) -> None:
    report = Report.from_dict(sample_dict)
    assert render(report, "html") == page
    assert render(Report.from_dict(report.to_dict()), "html") == page
    stored = json.loads(json.dumps(report.to_dict(), allow_nan=False))
    assert render(Report.from_dict(stored), "html") == page


def test_a_report_without_sections_or_findings() -> None:
    tree = lxml_html.fromstring(render(minimal_report(), "html"))
    assert tree.xpath("//span[contains(@class, 'verdict')]/@class") == ["verdict pass"]
    assert tree.xpath("//section[@id='findings']/p[@class='empty']/text()") == ["No findings."]
    for absent in ("links", "sweeps", "matrix", "inertia", "rules", "skipped"):
        assert not tree.xpath(f"//*[@id='{absent}']"), absent
    assert [a.get("href") for a in tree.xpath("//nav//a")] == ["#findings"]


def test_cli_writes_the_html_report(tmp_path: Path) -> None:
    root = tmp_path / "arm.urdf"
    root.write_text(
        """<robot name="arm">
  <link name="base"><visual><geometry><box size="0.3 0.3 0.1"/></geometry></visual>
    <collision><geometry><box size="0.3 0.3 0.1"/></geometry></collision></link>
</robot>
""",
        encoding="utf-8",
    )
    out = tmp_path / "report.html"
    done = subprocess.run(
        [sys.executable, "-m", "geomcheck", "check", str(root), "--format", "html", "-o", str(out)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    tree = lxml_html.fromstring(out.read_text(encoding="utf-8"))
    assert tree.xpath("//h1/text()") == ["arm"]
    assert tree.xpath("//details[@id='link-base']//svg[@class='views']")


@pytest.mark.corpus
def test_full_pr2_report(pr2_root: Path, tmp_path: Path) -> None:
    from geomcheck.load import make_bundle
    from geomcheck.options import CheckOptions
    from geomcheck.pipeline import run_check

    bundle = make_bundle(pr2_root / "pr2_description/robots/pr2.urdf.xacro", search=[pr2_root])
    report = run_check(bundle, CheckOptions())
    start = time.perf_counter()
    text = render(report, "html")
    elapsed = time.perf_counter() - start
    print(f"\nHTML of the full 2009 PR2: {len(text) / 1e6:.2f} MB, rendered in {elapsed:.2f} s")
    assert len(text) < 5_000_000
    assert render(Report.from_dict(json.loads(json.dumps(report.to_dict()))), "html") == text
    tree = lxml_html.fromstring(text)
    assert tree.xpath("//details[@id='link-base_link']//svg[@class='views']")
    wheel = tree.xpath(
        # one finding for the eight wheels
        "//article[starts-with(@id, 'finding-')][.//span[@class='subject'][.='link bl_caster_l_wheel_link']]"
    )
    assert any("GC505" in a.xpath("ancestor::div[contains(@class, 'group')]//a[@class='code']/text()") for a in wheel)
    assert tree.xpath("//div[@id='sweep-fl_caster_rotation_joint']//svg[@class='polar']")


def test_partial_and_unexpected_section_data_still_renders() -> None:
    report = minimal_report(
        diagnostics=[
            {"code": "GC999", "name": "from-a-newer-version", "severity": "error", "message": "m", "help": "h"}
        ],
        sections={
            "links": [{"link": "a", "collisions": [{"index": 0, "type": "box", "geometry": {}, "fit": None}]}],
            "views": [{"link": "a", "scale_m": 0.0, "front": {"bounds": None, "mesh": []}}],
            "sweeps": [{"joint": "j", "pairs": [{"links": ["a", "b"], "min_clearance": None, "colliding_ranges": []}]}],
            "matrix": {"links": ["a", "b"], "pairs": [{"links": ["a", "zz"], "class": "odd"}]},
            "inertia": [{"link": "a", "mass": 1.0, "principal_moments": [0.1, None, 0.2], "geometry_bound": None}],
        },
    )
    tree = lxml_html.fromstring(render(report, "html"))
    assert tree.xpath("//article[@id='rule-GC999']//p/text()") == ["This rule is not known to geomcheck 0.1.0."]
    assert tree.xpath("//details[@id='link-a']//*[local-name()='text'][@class='none']/text()") == ["no geometry"] * 3
    assert tree.xpath("//div[@id='sweep-j']//tbody/tr")
    assert tree.xpath("//svg[@class='matrix']") and not tree.xpath("//svg[@class='matrix']//*[local-name()='rect']")
