"""Mutation suite: defects injected into the corpus robots must be found, benign rewrites must not be.

The robots are those of the corpus's ``robots.toml`` in URDF or xacro (tests/corpus_robots.py:
a robot added there is mutated too). Each is expanded once (xacro, with its args) into a URDF
written in a temporary folder, mesh filenames relative to its root file made absolute; the
corpus is never written. The clean check of that copy is the reference.

Every defect kind is applied to eligible elements or links of each robot, all in one mutated
copy per robot and kind: at most ``MAX_TARGETS_PER_BATCH`` targets, chosen in an order hashed
from their names (deterministic, spread over the tree), one per link and never two on joined
links, so one link's defect can neither hide nor reveal another's. A defect counts as found
when a finding of one of the kind's rules names its link (and element), where the clean check
had none of them. Eligible means the defect changes something checkable there: a box that is
there to shrink, a cylinder longer or shorter than wide to turn, a collision element that alone
covers its link's visual (no other element, no joined link's geometry reaching it: see
``sole_cover``), a mesh the clean check could load, a link whose clean check is silent on those
rules. Recall per kind must be at least 98% and the benign rewrites (order, number spellings,
comments, whitespace) must add or change no finding. The figures are printed, with the robots'
count and the time taken.

The self-collision family does not run (no mutation here targets it), and meshes are read
through a cache store of the test's own, so each file is parsed once: 13 checks per robot (the
clean copy, one per defect kind, two benign rewrites), about three minutes for the 36 robots of
the corpus on an idle two-core machine. The default run takes the first robot of each kind
(``tests.corpus_robots.sample``); ``pytest -m campaign`` takes every robot.
"""

from __future__ import annotations

import math
import random
import time
import zlib
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
from lxml import etree
from scipy.spatial.transform import Rotation

from geomcheck.cache import using_store
from geomcheck.cache.store import open_store
from geomcheck.diagnostics import Diagnostic
from geomcheck.load import make_bundle
from geomcheck.options import CheckOptions, Selection
from geomcheck.pipeline import run_check
from geomcheck.report.model import Report
from tests.corpus_robots import corpus_robots, expanded_urdf, sample

pytestmark = [pytest.mark.corpus, pytest.mark.long]

MIN_RECALL = 0.98
MAX_TARGETS_PER_BATCH = 12  # targets one mutated copy of a robot changes, per defect kind [count]
OPTIONS = CheckOptions(sweep=False, selection=Selection(ignore=("GC4",)))
FIT = ("GC301", "GC303", "GC304")


@dataclass(frozen=True)
class Target:
    """What one mutation changes: a link, and the element label (``collision[0]``) or ``""``."""

    link: str
    about: str = ""


@dataclass
class Tally:
    found: int = 0
    eligible: int = 0
    missed: list[str] = field(default_factory=list)


Packages = Mapping[str, Path]


def check(path: Path, packages: Packages) -> Report:
    return run_check(make_bundle(path, packages=packages), OPTIONS)


def parse(source: bytes) -> etree._Element:
    return etree.fromstring(source, etree.XMLParser(remove_comments=True))


def links(root: etree._Element) -> dict[str, etree._Element]:
    return {e.get("name"): e for e in root.findall("link")}


def floats(text: str | None, default: str) -> list[float]:
    return [float(v) for v in (text or default).split()]


def fmt(values: list[float]) -> str:
    return " ".join(repr(float(v)) for v in values)


def elements(link: etree._Element, tag: str) -> Iterator[tuple[int, etree._Element]]:
    yield from enumerate(link.findall(tag))


def origin_of(element: etree._Element) -> etree._Element:
    origin = element.find("origin")
    if origin is None:
        origin = etree.SubElement(element, "origin")
        element.insert(0, origin)
    return origin


def inertia_of(link: etree._Element) -> tuple[etree._Element, etree._Element] | None:
    inertial = link.find("inertial")
    if inertial is None or inertial.find("mass") is None or inertial.find("inertia") is None:
        return None
    return inertial.find("mass"), inertial.find("inertia")


# --- the defect kinds: each yields its targets and mutates one of them in place ---------------------


def fitted(entry: dict | None) -> bool:
    """Whether the clean check fitted the link (visual geometry present and no placeholder)."""
    return entry is not None and entry.get("union") is not None


def sole_cover(link: etree._Element, entry: dict | None) -> bool:
    """Whether the link's one collision element is all that covers its visual: fitted, no other
    collision element, and no joined link's collision geometry reaching its visual (the clean
    fit borrowed none). Elsewhere the other geometry may keep the visual covered when one
    element shrinks, moves or turns (the PR2's camera frames sit inside their parents' boxes,
    a capsule's spheres outlast its cylinder), and whether the change is a defect depends on it."""
    return fitted(entry) and len(link.findall("collision")) == 1 and not (entry or {}).get("borrowed")


def shrunk_box(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    for i, c in elements(link, "collision"):
        box = c.find("geometry/box")
        if box is not None and sole_cover(link, entry):

            def apply(box: etree._Element = box) -> None:
                box.set("size", fmt([0.5 * v for v in floats(box.get("size"), "0 0 0")]))

            yield Target(link.get("name"), f"collision[{i}]"), apply


def extent(entry: dict | None) -> float:
    meshes = [m["extents"] for m in (entry or {}).get("visual_meshes", []) if m.get("extents")]
    return max((max(e) for e in meshes), default=0.0)


def offset_collision(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    size = extent(entry)
    for i, c in elements(link, "collision"):
        if c.find("geometry/mesh") is None and sole_cover(link, entry) and size > 0.0:

            def apply(c: etree._Element = c) -> None:
                origin = origin_of(c)
                xyz = floats(origin.get("xyz"), "0 0 0")
                origin.set("xyz", fmt([xyz[0] + 1.5 * size, xyz[1], xyz[2]]))

            yield Target(link.get("name"), f"collision[{i}]"), apply


def cylinder_axis(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    for i, c in elements(link, "collision"):
        cyl = c.find("geometry/cylinder")
        if cyl is None or not sole_cover(link, entry):
            continue
        radius, length = float(cyl.get("radius")), float(cyl.get("length"))
        # a cylinder as long as it is wide looks the same turned: nothing to find
        if abs(length - 2.0 * radius) < 0.3 * max(length, 2.0 * radius):
            continue

        def apply(c: etree._Element = c) -> None:
            origin = origin_of(c)
            rpy = floats(origin.get("rpy"), "0 0 0")
            turned = Rotation.from_euler("xyz", rpy) * Rotation.from_euler("x", math.pi / 2)
            origin.set("rpy", fmt(list(turned.as_euler("xyz"))))

        yield Target(link.get("name"), f"collision[{i}]"), apply


def mesh_elements(link: etree._Element) -> Iterator[tuple[str, etree._Element]]:
    for tag in ("visual", "collision"):
        for i, e in elements(link, tag):
            mesh = e.find("geometry/mesh")
            if mesh is not None:
                yield f"{tag}[{i}]", mesh


def mesh_in_millimetres(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    for about, mesh in mesh_elements(link):
        if about.startswith("visual"):

            def apply(mesh: etree._Element = mesh) -> None:
                mesh.set("scale", fmt([1000.0 * v for v in floats(mesh.get("scale"), "1 1 1")]))

            yield Target(link.get("name"), about), apply


def missing_mesh(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    for about, mesh in mesh_elements(link):

        def apply(mesh: etree._Element = mesh) -> None:
            head, _, tail = mesh.get("filename").rpartition("/")
            mesh.set("filename", f"{head}/gone_{tail}" if head else f"gone_{tail}")

        yield Target(link.get("name"), about), apply


def wrong_case(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    for about, mesh in mesh_elements(link):
        head, _, tail = mesh.get("filename").rpartition("/")
        stem, dot, suffix = tail.rpartition(".")
        if stem.swapcase() == stem:
            continue

        def apply(mesh: etree._Element = mesh, head: str = head, name: str = stem.swapcase() + dot + suffix) -> None:
            mesh.set("filename", f"{head}/{name}" if head else name)

        yield Target(link.get("name"), about), apply


def massive(link: etree._Element) -> tuple[etree._Element, etree._Element] | None:
    found = inertia_of(link)
    return found if found is not None and float(found[0].get("value")) > 0.0 else None


def triangle_inequality(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    found = massive(link)
    if found is not None:
        inertia = found[1]

        def apply() -> None:
            diagonal = [abs(float(inertia.get(k))) for k in ("ixx", "iyy", "izz")]
            moment = max(float(np.mean(diagonal)), 1e-9)
            for key, value in (("ixx", moment), ("iyy", moment), ("izz", 3.0 * moment)):
                inertia.set(key, repr(value))
            for key in ("ixy", "ixz", "iyz"):
                inertia.set(key, "0")

        yield Target(link.get("name")), apply


def negative_mass(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    found = massive(link)
    if found is not None:
        mass = found[0]

        def apply() -> None:
            mass.set("value", repr(-float(mass.get("value"))))

        yield Target(link.get("name")), apply


def impossible_inertia(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    """``entry`` is the clean check's ``inertia`` section entry: a radius of gyration three times
    the farthest the link's geometry reaches from its centre of mass is impossible by construction."""
    found = massive(link)
    reach = [r for r in (entry or {}).get("reach") or [] if r is not None]
    if found is not None and reach and max(reach) > 0.0:
        mass, inertia = found
        moment = float(mass.get("value")) * (3.0 * max(reach)) ** 2

        def apply() -> None:
            for key in ("ixx", "iyy", "izz"):
                inertia.set(key, repr(moment))
            for key in ("ixy", "ixz", "iyz"):
                inertia.set(key, "0")

        yield Target(link.get("name")), apply


def collision_removed(link: etree._Element, entry: dict | None) -> Iterator[tuple[Target, Callable[[], None]]]:
    if link.find("collision") is not None and fitted(entry):

        def apply() -> None:
            for c in link.findall("collision"):
                link.remove(c)

        yield Target(link.get("name")), apply


# kind: (targets, rules that find it, whether a finding must name the element)
KINDS: dict[str, tuple[Callable[..., Iterator[tuple[Target, Callable[[], None]]]], tuple[str, ...]]] = {
    "shrunk box": (shrunk_box, FIT),
    "offset collision": (offset_collision, FIT),
    "cylinder on the wrong axis": (cylinder_axis, FIT),
    "mesh in millimetres": (mesh_in_millimetres, ("GC205", "GC206")),
    "missing mesh": (missing_mesh, ("GC201",)),
    "wrong file-name case": (wrong_case, ("GC201",)),
    "triangle inequality": (triangle_inequality, ("GC504",)),
    "negative mass": (negative_mass, ("GC502",)),
    "inertia impossible for the geometry": (impossible_inertia, ("GC505",)),
    "collision element removed": (collision_removed, ("GC305",)),
}


def names(d: Diagnostic, target: Target) -> bool:
    return d.link == target.link and (not target.about or d.about == target.about)


def spread(target: Target) -> int:
    """A deterministic order of targets that does not follow the tree (names hashed)."""
    return zlib.crc32(f"{target.link}\0{target.about}".encode())


def neighbours(root: etree._Element) -> dict[str, set[str]]:
    """The links joined to each link."""
    out: dict[str, set[str]] = {}
    for joint in root.findall("joint"):
        child, parent = joint.find("child"), joint.find("parent")
        if child is not None and parent is not None:
            out.setdefault(child.get("link"), set()).add(parent.get("link"))
            out.setdefault(parent.get("link"), set()).add(child.get("link"))
    return out


MESH_PROBLEMS = ("GC201", "GC202", "GC203", "GC204", "GC207")


def unloadable(clean: Report) -> set[Target]:
    """The mesh elements the clean check could not load (a missing file or package, an
    unreadable file): renaming or rescaling them changes nothing checkable."""
    out = set()
    for d in clean.diagnostics:
        if d.code in MESH_PROBLEMS and d.link:
            out.add(Target(d.link, d.about))
        for row in (d.data or {}).get("references", []) if d.code == "GC202" else []:
            out.add(Target(row["link"], row["about"]))
    return out


def choose(candidates: list[tuple[Target, Callable[[], None]]], joined: dict[str, set[str]]) -> list:
    """At most ``MAX_TARGETS_PER_BATCH`` candidates in hashed order, one per link, no two on
    joined links: one link's defect can neither hide nor reveal another's."""
    chosen: list[tuple[Target, Callable[[], None]]] = []
    blocked: set[str] = set()
    for target, apply in sorted(candidates, key=lambda c: spread(c[0])):
        if len(chosen) == MAX_TARGETS_PER_BATCH:
            break
        if target.link not in blocked:
            chosen.append((target, apply))
            blocked |= {target.link, *joined.get(target.link, ())}
    return chosen


MESH_KINDS = ("mesh in millimetres", "missing mesh", "wrong file-name case")


def mutate_robot(
    name: str, source: bytes, packages: Packages, clean: Report, folder: Path, tallies: dict[str, Tally]
) -> None:
    entries = {e["link"]: e for e in clean.sections.get("links", [])}
    inertia_entries = {e["link"]: e for e in clean.sections.get("inertia", [])}
    joined = neighbours(parse(source))
    broken = unloadable(clean)
    for kind, (targets_of, codes) in KINDS.items():
        tally = tallies.setdefault(kind, Tally())
        root = parse(source)
        candidates: list[tuple[Target, Callable[[], None]]] = []
        section = inertia_entries if kind == "inertia impossible for the geometry" else entries
        for link in root.findall("link"):
            for target, apply in targets_of(link, section.get(link.get("name"))):
                # already reported by the kind's rules when clean: nothing to find
                if any(d.code in codes and names(d, target) for d in clean.diagnostics):
                    continue
                if kind in MESH_KINDS and target in broken:
                    continue
                candidates.append((target, apply))
        chosen = choose(candidates, joined)
        if not chosen:
            continue
        for _, apply in chosen:
            apply()
        path = folder / f"{kind.replace(' ', '_')}_{name}.urdf"
        path.write_bytes(etree.tostring(root, xml_declaration=True, encoding="utf-8"))
        report = check(path, packages)
        for target, _ in chosen:
            tally.eligible += 1
            if any(d.code in codes and names(d, target) for d in report.diagnostics):
                tally.found += 1
            else:
                tally.missed.append(f"{name}: {target.link} {target.about}".strip())


def benign(source: bytes, seed: int) -> bytes:
    """Links and joints permuted, numbers spelt otherwise, a comment and other indentation."""
    rng = random.Random(seed)
    root = parse(source)
    top = list(root)
    rng.shuffle(top)
    for child in top:
        root.remove(child)
        root.append(child)
    for element in root.iter():
        for key in ("xyz", "rpy", "size", "radius", "length", "value", "ixx", "iyy", "izz", "scale"):
            text = element.get(key)
            if text is None:
                continue
            try:
                values = [float(v) for v in text.split()]
            except ValueError:
                continue
            element.set(
                key,
                " ".join(
                    rng.choice((repr(v), f"{v:.17e}", f"{v!r}0" if "e" not in repr(v) else repr(v))) for v in values
                ),
            )
    root.insert(0, etree.Comment(" benign rewrite "))
    etree.indent(root, space="   ")
    return etree.tostring(root, xml_declaration=True, encoding="utf-8")


Results = tuple[dict[str, Tally], dict[str, list[str]], dict[str, float]]  # tallies, false alarms, seconds per robot


@pytest.fixture(
    scope="module",
    params=[pytest.param("sample", id="sample"), pytest.param("corpus", id="corpus", marks=pytest.mark.campaign)],
)
def results(corpus: Path, tmp_path_factory: pytest.TempPathFactory, request: pytest.FixtureRequest) -> Results:
    """The campaign over the first robot of each kind (default run) or over every robot."""
    tallies: dict[str, Tally] = {}
    false_alarms: dict[str, list[str]] = {}
    seconds: dict[str, float] = {}
    robots = list(corpus_robots(corpus))
    with using_store(open_store(tmp_path_factory.mktemp("store"))):
        for robot in sample(robots) if request.param == "sample" else robots:
            started = time.monotonic()
            folder = tmp_path_factory.mktemp("mutated")
            source = expanded_urdf(robot)
            path = folder / f"clean_{robot.name}.urdf"
            path.write_bytes(source)
            clean = check(path, robot.packages)
            mutate_robot(robot.name, source, robot.packages, clean, folder, tallies)
            expected = {(d.fingerprint, d.message) for d in clean.diagnostics}
            for seed in (0, 1):
                path = folder / f"benign_{seed}_{robot.name}.urdf"
                path.write_bytes(benign(source, seed))
                got = {(d.fingerprint, d.message) for d in check(path, robot.packages).diagnostics}
                false_alarms.setdefault(robot.name, []).extend(sorted(m for _, m in got - expected))
            seconds[robot.name] = time.monotonic() - started
    return tallies, false_alarms, seconds


def test_recall_per_kind(results: Results, capsys: pytest.CaptureFixture[str]) -> None:
    tallies, _, seconds = results
    with capsys.disabled():
        slowest = sorted(seconds, key=seconds.__getitem__, reverse=True)[:3]
        print(f"\nmutation suite: {len(seconds)} robots in {sum(seconds.values()):.0f} s (slowest: ", end="")
        print(", ".join(f"{n} {seconds[n]:.0f} s" for n in slowest) + ")")
        print("mutation recall per kind (found / eligible):")
        for kind, t in tallies.items():
            print(f"  {kind:38s} {t.found:4d} / {t.eligible:4d}  {t.found / max(t.eligible, 1):7.1%}")
            for missed in t.missed:
                print(f"      missed {missed}")
    for kind, t in tallies.items():
        assert t.eligible > 0, f"{kind}: no eligible target in the corpus"
        assert t.found / t.eligible >= MIN_RECALL, f"{kind}: missed {t.missed}"
    assert set(tallies) == set(KINDS)
    assert len(seconds) >= 6


def test_no_false_alarm_on_benign_rewrites(results: Results, capsys: pytest.CaptureFixture[str]) -> None:
    _, false_alarms, seconds = results
    with capsys.disabled():
        total = sum(len(v) for v in false_alarms.values())
        print(f"\nfalse alarms on benign rewrites: {total} over {len(false_alarms)} robots x 2 rewrites")
    assert false_alarms == {name: [] for name in seconds}
