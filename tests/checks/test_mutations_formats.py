"""Mutation suite for MJCF and SDFormat: defects injected into the corpus models must be found,
benign rewrites must not be.

The method is tests/checks/test_mutations.py's, in each format's own syntax. The models are
those of the corpus's ``robots.toml`` with ``format = "mjcf"`` or ``"sdf"``
(tests/corpus_robots.py). Each model's folder is copied into a temporary folder (MJCF meshes
resolve through ``<compiler meshdir>`` beside the root file, SDFormat's ``model://NAME`` through
the robot's packages, the copied folder standing for the model's own); mutated root files are
written there, the corpus is never written. The clean check of the copy is the reference.

Every defect kind is applied to every eligible element or link of each model, in as many
mutated copies as it takes: each copy changes at most ``MAX_TARGETS_PER_BATCH`` targets, chosen
in an order hashed from their names, one per link and never two on joined links, so that one
link's defect can neither hide nor reveal another's. A defect counts as found when a finding of
one of the kind's rules names its link (and element) where the clean check had none. Two MJCF
defects are refused by MuJoCo's compiler itself, so no check runs and no finding can name them:
a mesh file that is not there and moments that break the triangle inequality. Those kinds
mutate one target per copy, and a target counts as found when the check refuses the copy
(:class:`InputError`) with a message naming its file or its body.

Kinds (MJCF / SDFormat): a link's collision geoms shrunk to half their size (a primitive's
``size``, ``fromto`` / ``<box><size>``, ``<radius>``, ``<length>``; a mesh through an asset of its
own at half the scale / ``<mesh><scale>``), moved by one and a half times the link's size
(``pos``, ``fromto`` / ``<pose>``), a mesh in millimetres (``<mesh scale>`` x1000 /
``<mesh><scale>``), a missing mesh file (the asset's ``file`` / ``<uri>``), moments breaking the
triangle inequality (``diaginertia``, replacing ``fullinertia`` / ``<inertia>``), moments
impossible for the geometry (a radius of gyration three times the link's reach, triangle kept)
and every collision geom of a link removed (the geoms MuJoCo collides, ``contype`` or
``conaffinity`` non-zero / ``<collision>``). A shrunk or moved collision mesh is GC306's, a
primitive GC301/GC303/GC304's. Eligibility is the URDF suite's: collision geometry that alone
covers its link's visual (:func:`covered_alone`: all the link's collision elements are
mutated together), a mesh the clean check loaded, a link whose clean check is silent on the
kind's rules; MJCF geoms that MuJoCo merges (``fusestatic``) and SDFormat links of included
models (other files) are not mutated.

Benign rewrites: sibling elements of different tags interleaved otherwise (the order of one
tag's elements kept: it names the n-th geom, the canonical link), MJCF attributes in another
order, numbers spelt otherwise, a comment, other indentation. They must add or change no finding.
The figures are printed per format, with the models' count and the time taken. ``pytest -m
campaign`` mutates every eligible target of every model (about six minutes on a busy two-core
machine); the default run takes the first model of each format and one copy per kind (its
first ``MAX_TARGETS_PER_BATCH`` targets), about twenty seconds.
"""

from __future__ import annotations

import random
import shutil
import time
import zlib
from collections.abc import Callable, Iterator, Mapping
from copy import deepcopy
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from lxml import etree

from geomcheck.cache import using_store
from geomcheck.cache.store import open_store
from geomcheck.errors import InputError
from geomcheck.load import make_bundle
from geomcheck.load.xmlsafe import late_declaration_removed
from geomcheck.pipeline import run_check
from geomcheck.report.model import Report
from tests.checks.test_mutations import (
    FIT,
    MAX_TARGETS_PER_BATCH,
    MESH_PROBLEMS,
    MIN_RECALL,
    OPTIONS,
    Tally,
    extent,
    fitted,
)
from tests.corpus_robots import CorpusRobot, corpus_robots

pytestmark = [pytest.mark.corpus, pytest.mark.long]

FORMATS = ("mjcf", "sdf")
SCALE = ("GC205", "GC206")
PLACEMENT = (*FIT, "GC306")  # a primitive's fit, or a collision mesh that does not match the visual
Apply = Callable[[], None]


@dataclass(frozen=True)
class Target:
    """What one mutation changes: a link, the element labels a finding may name (none: the link
    itself), and for a defect the compiler refuses, the text its refusal must name."""

    link: str
    abouts: tuple[str, ...] = ()
    refusal: str = ""


@dataclass(frozen=True)
class Kind:
    codes: tuple[str, ...]
    one_per_copy: bool = False  # the compiler refuses the defect: one target per mutated copy


KINDS: dict[str, Kind] = {
    "shrunk collision geom": Kind(PLACEMENT),
    "offset collision geom": Kind(PLACEMENT),
    "mesh in millimetres": Kind(SCALE),
    "missing mesh": Kind(("GC201",)),
    "triangle inequality": Kind(("GC504",)),
    "inertia impossible for the geometry": Kind(("GC505",)),
    "collision geom removed": Kind(("GC305",)),
}
# what MuJoCo's compiler refuses: no check runs, the refusal names the defect
MJCF_REFUSED = ("missing mesh", "triangle inequality")


def check(path: Path, packages: Mapping[str, Path]) -> Report:
    return run_check(make_bundle(path, packages=packages), OPTIONS)


def parse(source: bytes) -> etree._Element:
    """The document, comments dropped (a licence comment above the declaration with them)."""
    return etree.fromstring(late_declaration_removed(source) or source, etree.XMLParser(remove_comments=True))


def fmt(values: Any) -> str:
    return " ".join(repr(float(v)) for v in values)


def covered_alone(entry: dict | None, count: int) -> bool:
    """Whether the link's ``count`` collision elements (all the clean check measured) are all that
    covers its visual: fitted and no joined link's geometry reaching it (test_mutations.py's
    ``sole_cover``, the link's elements mutated together where it has several)."""
    return fitted(entry) and len((entry or {}).get("collisions") or []) == count and not (entry or {}).get("borrowed")


def offset_distance(entry: dict | None, size: float) -> float:
    """One and a half times the larger of the link's visual meshes and the element itself [m]."""
    return 1.5 * max(extent(entry), size)


def spread(target: Target) -> int:
    """A deterministic order of targets that does not follow the tree (names hashed)."""
    return zlib.crc32(f"{target.link}\0{' '.join(target.abouts)}".encode())


def choose(targets: list[Target], joined: Mapping[str, set[str]]) -> list[Target]:
    """At most ``MAX_TARGETS_PER_BATCH`` targets in hashed order, one per link, no two on joined links."""
    chosen: list[Target] = []
    blocked: set[str] = set()
    for target in sorted(targets, key=spread):
        if len(chosen) == MAX_TARGETS_PER_BATCH:
            break
        if target.link not in blocked:
            chosen.append(target)
            blocked |= {target.link, *joined.get(target.link, ())}
    return chosen


def batches(targets: list[Target], joined: Mapping[str, set[str]], one_per_copy: bool) -> Iterator[list[Target]]:
    """Every target, in mutated copies chosen by :func:`choose` until none is left (one per
    copy where the compiler refuses the defect: its refusal names the first it meets)."""
    left = sorted(targets, key=spread)
    while left:
        batch = left[:1] if one_per_copy else choose(left, joined)
        yield batch
        left = [t for t in left if t not in batch]


def unloadable(clean: Report) -> set[tuple[str, str]]:
    """(link, element) of the meshes the clean check could not load."""
    out = set()
    for d in clean.diagnostics:
        if d.code in MESH_PROBLEMS and d.link:
            out.add((d.link, d.about))
        for row in (d.data or {}).get("references", []) if d.code == "GC202" else []:
            out.add((row["link"], row["about"]))
    return out


@dataclass
class Context:
    """What the clean check says of a model, for choosing targets."""

    clean: Report
    links: dict[str, dict] = field(default_factory=dict)
    inertia: dict[str, dict] = field(default_factory=dict)
    broken: set[tuple[str, str]] = field(default_factory=set)

    @classmethod
    def of(cls, clean: Report) -> Context:
        return cls(
            clean,
            {e["link"]: e for e in clean.sections.get("links", [])},
            {e["link"]: e for e in clean.sections.get("inertia", [])},
            unloadable(clean),
        )

    def silent(self, target: Target, codes: tuple[str, ...]) -> bool:
        """Whether the clean check has no finding of ``codes`` on the target."""
        return not any(d.code in codes and named(d, target) for d in self.clean.diagnostics)

    def impossible_moment(self, link: str, mass: float) -> float | None:
        """A moment whose radius of gyration is three times the link's reach, or ``None``."""
        reach = [r for r in (self.inertia.get(link) or {}).get("reach") or [] if r is not None]
        return mass * (3.0 * max(reach)) ** 2 if reach and max(reach) > 0.0 and mass > 0.0 else None


def named(d: Any, target: Target) -> bool:
    return d.link == target.link and (not target.abouts or d.about in target.abouts)


# ---------------------------------------------------------------------------------------------
# MJCF: the geoms, meshes and inertials of the XML matched to MuJoCo's compiled model


@dataclass
class MjcfGeom:
    element: etree._Element
    link: str
    label: str  # visual[i] / collision[i], as geomcheck numbers the body's shapes
    kind: int  # mjtGeom
    size: np.ndarray  # MuJoCo's half sizes
    mesh: int  # the mesh asset's id, -1 for a primitive


@dataclass
class MjcfModel:
    root: etree._Element
    geoms: list[MjcfGeom]
    bodies: dict[str, tuple[etree._Element, int]]  # link -> (body element, compiled id)
    meshes: dict[int, etree._Element]  # mesh id -> <mesh> asset
    joined: dict[str, set[str]]
    model: Any


def mjcf_geoms_of(element: etree._Element) -> Iterator[etree._Element]:
    """A body's geoms in document order, those of its ``<frame>``s included."""
    for child in element:
        if child.tag == "geom":
            yield child
        elif child.tag == "frame":
            yield from mjcf_geoms_of(child)


def mjcf_bodies_of(element: etree._Element) -> Iterator[etree._Element]:
    for child in element:
        if child.tag == "body":
            yield child
            yield from mjcf_bodies_of(child)
        elif child.tag == "frame":
            yield from mjcf_bodies_of(child)


def mjcf_model(source: bytes, model: Any) -> MjcfModel:
    """The document ``source`` matched to its compiled ``model`` (``mujoco.MjModel``)."""
    import mujoco

    from geomcheck.load.mjcf import geometry_of

    root = parse(source)

    def body_name(b: int) -> str:
        return "world" if b == 0 else mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}"

    geoms: list[MjcfGeom] = []
    bodies: dict[str, tuple[etree._Element, int]] = {}
    xml_bodies = list(mjcf_bodies_of(root.find("worldbody")))
    ordered = len(xml_bodies) + 1 == model.nbody
    for k, element in enumerate(xml_bodies):
        b = k + 1 if ordered else mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, element.get("name") or "")
        if b < 1:
            continue  # fused into its parent (fusestatic)
        link = body_name(b)
        bodies[link] = (element, b)
        elements = list(mjcf_geoms_of(element))
        first, count = int(model.body_geomadr[b]), int(model.body_geomnum[b])
        if count != len(elements):
            continue  # geoms merged from fused bodies: MuJoCo's order is not the document's
        counters = {"visual": 0, "collision": 0}
        for g, geom in zip(range(first, first + count), elements, strict=True):
            if geometry_of(model, g) is None:
                continue
            role = "collision" if model.geom_contype[g] or model.geom_conaffinity[g] else "visual"
            label = f"{role}[{counters[role]}]"
            counters[role] += 1
            mesh = int(model.geom_dataid[g]) if int(model.geom_type[g]) == mujoco.mjtGeom.mjGEOM_MESH else -1
            geoms.append(MjcfGeom(geom, link, label, int(model.geom_type[g]), np.array(model.geom_size[g]), mesh))
    meshes: dict[int, etree._Element] = {}
    for asset in root.iter("mesh"):
        if asset.getparent() is not None and asset.getparent().tag == "asset" and asset.get("file"):
            name = asset.get("name") or Path(asset.get("file", "")).stem
            m = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_MESH, name)
            if m >= 0:
                meshes[m] = asset
    joined: dict[str, set[str]] = {}
    for b in range(1, model.nbody):
        parent = int(model.body_parentid[b])
        if parent > 0:
            joined.setdefault(body_name(b), set()).add(body_name(parent))
            joined.setdefault(body_name(parent), set()).add(body_name(b))
    return MjcfModel(root, geoms, bodies, meshes, joined, model)


def mjcf_collisions(m: MjcfModel, link: str) -> list[MjcfGeom]:
    return [g for g in m.geoms if g.link == link and g.label.startswith("collision")]


_SPHERE, _CAPSULE, _ELLIPSOID, _CYLINDER, _BOX = 2, 3, 4, 5, 6
_PRIMITIVES = (_SPHERE, _CAPSULE, _ELLIPSOID, _CYLINDER, _BOX)


def mjcf_size_text(g: MjcfGeom, factor: float) -> str:
    count = {_SPHERE: 1, _CAPSULE: 2, _CYLINDER: 2}.get(g.kind, 3)
    return fmt(factor * g.size[:count])


def mjcf_reach(g: MjcfGeom) -> float:
    """The geom's largest dimension [m]."""
    return float(2.0 * max(g.size[:3]))


def mjcf_shrinkable(m: MjcfModel, g: MjcfGeom) -> bool:
    """A primitive with its own size (no mesh fitted; a box or ellipsoid ``fromto`` left alone),
    or a mesh of a file."""
    if g.mesh >= 0:
        return g.mesh in m.meshes
    return (
        g.kind in _PRIMITIVES
        and not g.element.get("mesh")
        and not (g.element.get("fromto") and g.kind in (_BOX, _ELLIPSOID))
    )


def mjcf_shrink(m: MjcfModel, g: MjcfGeom) -> None:
    """Half the geom's size: a primitive's ``size`` (and ``fromto`` about its middle), a mesh
    through an asset of its own at half the scale (MuJoCo centres a mesh: it shrinks in place)."""
    fromto = g.element.get("fromto")
    if g.mesh >= 0:
        asset = m.meshes[g.mesh]
        halved = deepcopy(asset)  # its class and other attributes kept
        halved.set("scale", fmt(0.5 * np.array(m.model.mesh_scale[g.mesh])))
        halved.set("name", f"{g.link}_{g.label}_halved")
        halved.tail = asset.tail
        asset.addnext(halved)
        g.element.set("mesh", halved.get("name", ""))
    elif fromto:  # a capsule or cylinder between two points: half as long about its middle
        ends = np.array([float(v) for v in fromto.split()]).reshape(2, 3)
        middle = ends.mean(axis=0)
        g.element.set("fromto", fmt(np.concatenate([middle + 0.5 * (e - middle) for e in ends])))
        g.element.set("size", fmt([0.5 * g.size[0]]))
    else:
        g.element.set("size", mjcf_size_text(g, 0.5))


def mjcf_link_collisions(m: MjcfModel, ctx: Context) -> Iterator[tuple[str, list[MjcfGeom]]]:
    """Each link whose collision geoms alone cover its visual (:func:`covered_alone`), with them."""
    for link in m.bodies:
        geoms = mjcf_collisions(m, link)
        if geoms and covered_alone(ctx.links.get(link), len(geoms)):
            yield link, geoms


def mjcf_shrunk(m: MjcfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link, geoms in mjcf_link_collisions(m, ctx):
        if not all(mjcf_shrinkable(m, g) for g in geoms) or any((link, g.label) in ctx.broken for g in geoms):
            continue

        def apply(geoms: list[MjcfGeom] = geoms) -> None:
            for g in geoms:
                mjcf_shrink(m, g)

        yield Target(link, tuple(g.label for g in geoms)), apply


def mjcf_offset(m: MjcfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link, geoms in mjcf_link_collisions(m, ctx):
        size = max(mjcf_reach(g) if g.mesh < 0 else 0.0 for g in geoms)
        distance = offset_distance(ctx.links.get(link), size)
        if distance <= 0.0:
            continue

        def apply(geoms: list[MjcfGeom] = geoms, d: float = distance) -> None:
            for g in geoms:
                fromto = g.element.get("fromto")
                if fromto:
                    ends = np.array([float(v) for v in fromto.split()])
                    ends[[0, 3]] += d
                    g.element.set("fromto", fmt(ends))
                else:
                    pos = [float(v) for v in (g.element.get("pos") or "0 0 0").split()]
                    g.element.set("pos", fmt([pos[0] + d, pos[1], pos[2]]))

        yield Target(link, tuple(g.label for g in geoms)), apply


def mjcf_mesh_users(m: MjcfModel) -> dict[int, list[MjcfGeom]]:
    users: dict[int, list[MjcfGeom]] = {}
    for g in m.geoms:
        if g.mesh >= 0:
            users.setdefault(g.mesh, []).append(g)
    return users


def mjcf_millimetres(m: MjcfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    """A mesh asset used on one link only, by a visual geom at least, scaled x1000."""
    for mesh, users in mjcf_mesh_users(m).items():
        links = {g.link for g in users}
        if mesh not in m.meshes or len(links) != 1 or not any(g.label.startswith("visual") for g in users):
            continue
        if any((g.link, g.label) in ctx.broken for g in users):
            continue
        asset, scale = m.meshes[mesh], 1000.0 * np.array(m.model.mesh_scale[mesh])

        def apply(asset: etree._Element = asset, scale: np.ndarray = scale) -> None:
            asset.set("scale", fmt(scale))

        yield Target(users[0].link, tuple(dict.fromkeys(g.label for g in users))), apply


def mjcf_missing(m: MjcfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    """A mesh asset's file renamed: MuJoCo's compiler refuses the model, naming the file."""
    for mesh, users in mjcf_mesh_users(m).items():
        if mesh not in m.meshes:
            continue
        asset = m.meshes[mesh]
        head, _, tail = asset.get("file", "").rpartition("/")
        gone = f"gone_{tail}"

        def apply(asset: etree._Element = asset, name: str = f"{head}/{gone}" if head else gone) -> None:
            if asset.get("name") is None:  # MuJoCo names an unnamed mesh after its file: the geoms keep that name
                asset.set("name", Path(asset.get("file", "")).stem)
            asset.set("file", name)

        labels = tuple(dict.fromkeys(g.label for g in users if g.link == users[0].link))
        yield Target(users[0].link, labels, refusal=gone), apply


def mjcf_inertials(m: MjcfModel) -> Iterator[tuple[str, etree._Element, int]]:
    """Bodies with an ``<inertial>`` MuJoCo reads (not replaced by the geoms' inertia)."""
    compiler = m.root.find("compiler")
    options = dict(compiler.attrib) if compiler is not None else {}
    if options.get("inertiafromgeom", "auto") == "true" or options.get("balanceinertia") == "true":
        return
    for link, (body, b) in m.bodies.items():
        inertial = body.find("inertial")
        if inertial is not None and float(m.model.body_mass[b]) > 0.0:
            yield link, inertial, b


def mjcf_triangle(m: MjcfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link, inertial, b in mjcf_inertials(m):
        moment = max(float(np.mean(m.model.body_inertia[b])), 1e-9)

        def apply(inertial: etree._Element = inertial, moment: float = moment) -> None:
            inertial.attrib.pop("fullinertia", None)
            inertial.set("diaginertia", fmt([moment, moment, 3.0 * moment]))

        yield Target(link, refusal=f"'{link}'"), apply


def mjcf_impossible(m: MjcfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link, inertial, b in mjcf_inertials(m):
        moment = ctx.impossible_moment(link, float(m.model.body_mass[b]))
        if moment is None:
            continue

        def apply(inertial: etree._Element = inertial, moment: float = moment) -> None:
            inertial.attrib.pop("fullinertia", None)
            inertial.set("diaginertia", fmt([moment] * 3))

        yield Target(link), apply


def mjcf_removed(m: MjcfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    """Every geom MuJoCo collides on a link removed, its mass and inertia kept (written as an
    ``<inertial>`` when MuJoCo derived them from the geoms): what is missing is the collision
    geometry, not the mass that a massless body would make MuJoCo refuse."""
    referenced = {v for e in m.root.iter() for k, v in e.attrib.items() if k in ("geom", "geom1", "geom2")}
    for link, (body, b) in m.bodies.items():
        geoms = mjcf_collisions(m, link)
        if not geoms or not fitted(ctx.links.get(link)) or any(g.element.get("name") in referenced for g in geoms):
            continue
        if len(geoms) != len((ctx.links.get(link) or {}).get("collisions") or []):
            continue

        def apply(body: etree._Element = body, b: int = b, geoms: list[MjcfGeom] = geoms) -> None:
            if body.find("inertial") is None and float(m.model.body_mass[b]) > 0.0:
                inertial = etree.Element("inertial")
                inertial.set("pos", fmt(m.model.body_ipos[b]))
                inertial.set("quat", fmt(m.model.body_iquat[b]))
                inertial.set("mass", repr(float(m.model.body_mass[b])))
                inertial.set("diaginertia", fmt(m.model.body_inertia[b]))
                body.insert(0, inertial)
            for g in geoms:
                g.element.getparent().remove(g.element)

        yield Target(link), apply


MJCF_KINDS: dict[str, Callable[[MjcfModel, Context], Iterator[tuple[Target, Apply]]]] = {
    "shrunk collision geom": mjcf_shrunk,
    "offset collision geom": mjcf_offset,
    "mesh in millimetres": mjcf_millimetres,
    "missing mesh": mjcf_missing,
    "triangle inequality": mjcf_triangle,
    "inertia impossible for the geometry": mjcf_impossible,
    "collision geom removed": mjcf_removed,
}

# MJCF attributes that hold real numbers (integers such as contype are left as written)
MJCF_REALS_TEXT = (
    "pos quat size fromto euler axisangle xyaxes zaxis mass diaginertia fullinertia scale axis range ref "
    "armature damping frictionloss friction density margin gap stiffness springref refpos refquat"
)
MJCF_REALS = frozenset(MJCF_REALS_TEXT.split())


# ---------------------------------------------------------------------------------------------
# SDFormat: the links of the root file's models (included models are other files: left alone)


@dataclass
class SdfLink:
    element: etree._Element
    name: str  # scoped as geomcheck names it


@dataclass
class SdfModel:
    root: etree._Element
    links: list[SdfLink]
    joined: dict[str, set[str]]


def sdf_model(source: bytes) -> SdfModel:
    root = parse(source)
    links: list[SdfLink] = []
    joined: dict[str, set[str]] = {}

    def visit(model: etree._Element, prefix: str) -> None:
        for link in model.findall("link"):
            links.append(SdfLink(link, prefix + link.get("name", "")))
        for joint in model.findall("joint"):
            parent, child = (joint.findtext("parent") or "").strip(), (joint.findtext("child") or "").strip()
            if parent and child and parent != "world":
                a, b = prefix + parent, prefix + child
                joined.setdefault(a, set()).add(b)
                joined.setdefault(b, set()).add(a)
        for nested in model.findall("model"):
            visit(nested, f"{prefix}{nested.get('name')}::")

    top = root.find("model")
    if top is not None:
        visit(top, "")
    return SdfModel(root, links, joined)


_SDF_SKIPPED = ("plane", "empty")


def sdf_shapes(link: etree._Element, tag: str) -> Iterator[tuple[str, etree._Element]]:
    """The link's ``tag`` elements with geomcheck's labels (planes and empty geometry are no shapes)."""
    index = 0
    for element in link.findall(tag):
        geometry = element.find("geometry")
        if geometry is None or any(geometry.find(s) is not None for s in _SDF_SKIPPED):
            continue
        yield f"{tag}[{index}]", element
        index += 1


def scaled(element: etree._Element, factor: float) -> None:
    element.text = fmt([factor * float(v) for v in (element.text or "").split()])


def sdf_scale(mesh: etree._Element) -> etree._Element:
    """The mesh's ``<scale>``, written as SDFormat's default when absent."""
    scale = mesh.find("scale")
    if scale is None:
        scale = etree.SubElement(mesh, "scale")
        scale.text = "1 1 1"
    return scale


def sdf_primitive(collision: etree._Element) -> tuple[list[etree._Element], float] | None:
    """The size elements of a primitive collision and its largest dimension [m], or ``None``."""
    geometry = collision.find("geometry")
    for shape, tags in (("box", ("size",)), ("sphere", ("radius",)), ("cylinder", ("radius", "length"))):
        found = geometry.find(shape) if geometry is not None else None
        if found is None:
            continue
        sizes = [found.find(t) for t in tags]
        if any(s is None for s in sizes):
            return None
        values = [float(v) for s in sizes for v in (s.text or "").split()]
        largest = max(values) * (2.0 if shape == "sphere" else 1.0)
        if shape == "cylinder":
            largest = max(2.0 * values[0], values[1])
        return [s for s in sizes if s is not None], largest
    return None


def sdf_link_collisions(m: SdfModel, ctx: Context) -> Iterator[tuple[SdfLink, list[tuple[str, etree._Element]]]]:
    """Each link whose collision elements alone cover its visual (:func:`covered_alone`), with them."""
    for link in m.links:
        collisions = list(sdf_shapes(link.element, "collision"))
        if collisions and covered_alone(ctx.links.get(link.name), len(collisions)):
            yield link, collisions


def sdf_shrunk(m: SdfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link, collisions in sdf_link_collisions(m, ctx):
        if any((link.name, label) in ctx.broken for label, _ in collisions):
            continue
        primitives = [sdf_primitive(c) for _, c in collisions]
        meshes = [c.find("geometry/mesh") for _, c in collisions]
        if any(p is None and mesh is None for p, mesh in zip(primitives, meshes, strict=True)):
            continue
        sizes = [size for p in primitives if p is not None for size in p[0]]

        def apply(sizes: list[etree._Element] = sizes, meshes: list[etree._Element | None] = meshes) -> None:
            for size in sizes:
                scaled(size, 0.5)
            for mesh in meshes:  # scaled about the mesh's origin: smaller and moved, a defect either way
                if mesh is not None:
                    scaled(sdf_scale(mesh), 0.5)

        yield Target(link.name, tuple(label for label, _ in collisions)), apply


def sdf_offset(m: SdfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link, collisions in sdf_link_collisions(m, ctx):
        primitives = [sdf_primitive(c) for _, c in collisions]
        distance = offset_distance(ctx.links.get(link.name), max(p[1] if p else 0.0 for p in primitives))
        if distance <= 0.0:
            continue

        def apply(collisions: list[tuple[str, etree._Element]] = collisions, d: float = distance) -> None:
            for _, collision in collisions:
                pose = collision.find("pose")
                if pose is None:
                    pose = etree.Element("pose")
                    pose.text = "0 0 0 0 0 0"
                    collision.insert(0, pose)
                values = (pose.text or "").split()
                values[0] = repr(float(values[0]) + d)
                pose.text = " ".join(values)

        yield Target(link.name, tuple(label for label, _ in collisions)), apply


def sdf_meshes(link: SdfLink, tag: str) -> Iterator[tuple[str, etree._Element]]:
    for label, element in sdf_shapes(link.element, tag):
        mesh = element.find("geometry/mesh")
        if mesh is not None and mesh.find("uri") is not None:
            yield label, mesh


def sdf_millimetres(m: SdfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link in m.links:
        for label, mesh in sdf_meshes(link, "visual"):
            if (link.name, label) in ctx.broken:
                continue

            def apply(mesh: etree._Element = mesh) -> None:
                scaled(sdf_scale(mesh), 1000.0)

            yield Target(link.name, (label,)), apply


def sdf_missing(m: SdfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link in m.links:
        for tag in ("visual", "collision"):
            for label, mesh in sdf_meshes(link, tag):
                if (link.name, label) in ctx.broken:
                    continue

                def apply(uri: etree._Element = mesh.find("uri")) -> None:
                    head, _, tail = (uri.text or "").strip().rpartition("/")
                    uri.text = f"{head}/gone_{tail}" if head else f"gone_{tail}"

                yield Target(link.name, (label,)), apply


MOMENTS, PRODUCTS = ("ixx", "iyy", "izz"), ("ixy", "ixz", "iyz")


def sdf_inertias(m: SdfModel) -> Iterator[tuple[SdfLink, float, etree._Element]]:
    for link in m.links:
        inertia = link.element.find("inertial/inertia")
        mass = float((link.element.findtext("inertial/mass") or "1").strip())
        if inertia is not None and mass > 0.0:
            yield link, mass, inertia


def set_moments(inertia: etree._Element, moments: list[float]) -> None:
    for key, value in zip(MOMENTS + PRODUCTS, [*moments, 0.0, 0.0, 0.0], strict=True):
        element = inertia.find(key)
        if element is None:
            element = etree.SubElement(inertia, key)
        element.text = repr(value)


def sdf_triangle(m: SdfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link, _, inertia in sdf_inertias(m):
        diagonal = [abs(float(inertia.findtext(k) or "1")) for k in MOMENTS]
        moment = max(float(np.mean(diagonal)), 1e-9)

        def apply(inertia: etree._Element = inertia, moment: float = moment) -> None:
            set_moments(inertia, [moment, moment, 3.0 * moment])

        yield Target(link.name), apply


def sdf_impossible(m: SdfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link, mass, inertia in sdf_inertias(m):
        moment = ctx.impossible_moment(link.name, mass)
        if moment is None:
            continue

        def apply(inertia: etree._Element = inertia, moment: float = moment) -> None:
            set_moments(inertia, [moment] * 3)

        yield Target(link.name), apply


def sdf_removed(m: SdfModel, ctx: Context) -> Iterator[tuple[Target, Apply]]:
    for link in m.links:
        if link.element.find("collision") is None or not fitted(ctx.links.get(link.name)):
            continue

        def apply(element: etree._Element = link.element) -> None:
            for collision in element.findall("collision"):
                element.remove(collision)

        yield Target(link.name), apply


SDF_KINDS: dict[str, Callable[[SdfModel, Context], Iterator[tuple[Target, Apply]]]] = {
    "shrunk collision geom": sdf_shrunk,
    "offset collision geom": sdf_offset,
    "mesh in millimetres": sdf_millimetres,
    "missing mesh": sdf_missing,
    "triangle inequality": sdf_triangle,
    "inertia impossible for the geometry": sdf_impossible,
    "collision geom removed": sdf_removed,
}

SDF_REALS_TEXT = (
    "pose size radius length scale mass ixx ixy ixz iyy iyz izz xyz lower upper effort velocity damping friction"
)
SDF_REALS = frozenset(SDF_REALS_TEXT.split())


# ---------------------------------------------------------------------------------------------
# Benign rewrites


def interleave(element: etree._Element, rng: random.Random, together: Mapping[str, str]) -> None:
    """``element``'s children in another order that keeps each group's order (a group is a tag,
    or tags ``together`` maps to one name): the n-th geom stays the n-th."""
    children = [c for c in element if isinstance(c.tag, str)]
    groups: dict[str, list[etree._Element]] = {}
    for child in children:
        groups.setdefault(together.get(child.tag, child.tag), []).append(child)
    slots = [together.get(c.tag, c.tag) for c in children]
    rng.shuffle(slots)
    for child in children:
        element.remove(child)
    for slot in slots:
        element.append(groups[slot].pop(0))


def respelt(text: str, rng: random.Random) -> str | None:
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        return None
    return " ".join(rng.choice((repr(v), f"{v:.17e}", f"{v!r}0" if "e" not in repr(v) else repr(v))) for v in values)


def finish(root: etree._Element) -> bytes:
    root.insert(0, etree.Comment(" benign rewrite "))
    etree.indent(root, space="   ")
    return bytes(etree.tostring(root, xml_declaration=True, encoding="utf-8"))


# MuJoCo numbers bodies, geoms and joints in document order, and a frame holds geoms and bodies
MJCF_TOGETHER = {"body": "tree", "frame": "tree", "geom": "tree", "joint": "joint", "freejoint": "joint"}
# the canonical link is the first link, or else the first model
SDF_TOGETHER = {"link": "part", "model": "part", "include": "part"}


def mjcf_benign(source: bytes, seed: int) -> bytes:
    rng = random.Random(seed)
    root = parse(source)
    for section in ("worldbody", "asset"):
        for top in root.findall(section):
            for element in [top, *top.iter()]:
                if isinstance(element.tag, str):
                    interleave(element, rng, MJCF_TOGETHER)
    for element in root.iter():
        if not isinstance(element.tag, str):
            continue
        attributes = list(element.attrib.items())
        rng.shuffle(attributes)
        element.attrib.clear()
        for key, value in attributes:
            spelt = respelt(value, rng) if key in MJCF_REALS else None
            element.set(key, spelt if spelt is not None else value)
    return finish(root)


def sdf_benign(source: bytes, seed: int) -> bytes:
    rng = random.Random(seed)
    root = parse(source)
    for element in list(root.iter()):
        if isinstance(element.tag, str):
            interleave(element, rng, SDF_TOGETHER)
    for element in root.iter():
        if isinstance(element.tag, str) and element.tag in SDF_REALS and len(element) == 0 and element.text:
            spelt = respelt(element.text, rng)
            if spelt is not None:
                element.text = spelt
    return finish(root)


# ---------------------------------------------------------------------------------------------
# The campaign


@dataclass
class Copy:
    """A model's folder copied for mutation: its root file and the packages that read it."""

    root: Path
    packages: dict[str, Path]
    source: bytes
    mujoco_model: Any = None

    def compiled(self) -> Any:
        """MuJoCo's compiled model of the clean copy (MJCF), compiled once."""
        if self.mujoco_model is None:
            import mujoco

            self.mujoco_model = mujoco.MjModel.from_xml_path(str(self.root))
        return self.mujoco_model

    @classmethod
    def of(cls, robot: CorpusRobot, folder: Path) -> Copy:
        original = robot.root.resolve().parent
        copied = folder / original.name
        shutil.copytree(original, copied, symlinks=True)
        packages = {k: copied if v.resolve() == original else v for k, v in robot.packages.items()}
        root = copied / robot.root.name
        return cls(root, packages, root.read_bytes())

    def write(self, name: str, source: bytes) -> Path:
        path = self.root.with_name(f"{name}{self.root.suffix}")
        path.write_bytes(source)
        return path


def outcome(path: Path, packages: Mapping[str, Path]) -> Report | str:
    """The report of a check, or the refusal's message."""
    try:
        return check(path, packages)
    except InputError as err:
        return str(err)


def found(result: Report | str, target: Target, codes: tuple[str, ...]) -> bool:
    if isinstance(result, str):
        return bool(target.refusal) and target.refusal in result
    return any(d.code in codes and named(d, target) for d in result.diagnostics)


def mutate(robot: CorpusRobot, copy: Copy, clean: Report, tallies: dict[str, Tally], every: bool) -> None:
    """Mutates every eligible target of each kind (``every``), or those of one batch."""
    ctx = Context.of(clean)

    def document() -> MjcfModel | SdfModel:
        """A fresh parse of the clean copy, to mutate."""
        return mjcf_model(copy.source, copy.compiled()) if robot.format == "mjcf" else sdf_model(copy.source)

    for kind_name, kind in KINDS.items():
        tally = tallies.setdefault(kind_name, Tally())
        targets_of: Any = MJCF_KINDS[kind_name] if robot.format == "mjcf" else SDF_KINDS[kind_name]
        one_per_copy = robot.format == "mjcf" and kind_name in MJCF_REFUSED
        model = document()
        targets = [t for t, _ in targets_of(model, ctx) if ctx.silent(t, kind.codes)]
        targets = targets if every else choose(targets, model.joined)
        for n, batch in enumerate(batches(targets, model.joined, one_per_copy)):
            model = document()
            for target, apply in targets_of(model, ctx):
                if target in batch:
                    apply()
            source = etree.tostring(model.root, xml_declaration=True, encoding="utf-8")
            result = outcome(copy.write(f"{kind_name.replace(' ', '_')}_{n}", source), copy.packages)
            for target in batch:
                tally.eligible += 1
                if found(result, target, kind.codes):
                    tally.found += 1
                else:
                    why = result[:160] if isinstance(result, str) else ""
                    tally.missed.append(f"{robot.name}: {target.link} {' '.join(target.abouts)} {why}".strip())


Results = tuple[dict[str, Tally], dict[str, list[str]], dict[str, float]]  # tallies, false alarms, seconds per model


def campaign(robots: list[CorpusRobot], folder: Path, every: bool) -> Results:
    tallies: dict[str, Tally] = {}
    false_alarms: dict[str, list[str]] = {}
    seconds: dict[str, float] = {}
    with using_store(open_store(folder / "store")):
        for robot in robots:
            started = time.monotonic()
            copy = Copy.of(robot, folder / robot.name)
            clean = check(copy.root, copy.packages)
            mutate(robot, copy, clean, tallies, every)
            expected = {(d.fingerprint, d.message) for d in clean.diagnostics}
            rewrite = mjcf_benign if robot.format == "mjcf" else sdf_benign
            for seed in (0, 1):
                path = copy.write(f"benign_{seed}", rewrite(copy.source, seed))
                got = {(d.fingerprint, d.message) for d in check(path, copy.packages).diagnostics}
                false_alarms.setdefault(robot.name, []).extend(sorted(m for _, m in got - expected))
            seconds[robot.name] = time.monotonic() - started
    return tallies, false_alarms, seconds


@dataclass
class Campaign:
    """Per format, the tallies, false alarms and seconds per model; ``whole`` over every model."""

    formats: dict[str, Results]
    whole: bool


@pytest.fixture(
    scope="module",
    params=[pytest.param("sample", id="sample"), pytest.param("corpus", id="corpus", marks=pytest.mark.campaign)],
)
def results(corpus: Path, tmp_path_factory: pytest.TempPathFactory, request: pytest.FixtureRequest) -> Campaign:
    """The campaign over the first model of each format (default run) or over every model."""
    out: dict[str, Results] = {}
    for fmt_name in FORMATS:
        robots = list(corpus_robots(corpus, formats=(fmt_name,)))
        chosen = robots[:1] if request.param == "sample" else robots
        if chosen:
            out[fmt_name] = campaign(chosen, tmp_path_factory.mktemp(fmt_name), every=request.param == "corpus")
    return Campaign(out, whole=request.param == "corpus")


def test_recall_per_kind(results: Campaign, capsys: pytest.CaptureFixture[str]) -> None:
    for fmt_name, (tallies, _, seconds) in results.formats.items():
        with capsys.disabled():
            slowest = sorted(seconds, key=seconds.__getitem__, reverse=True)[:3]
            total = sum(seconds.values())
            print(f"\n{fmt_name} mutation suite: {len(seconds)} models in {total:.0f} s (slowest: ", end="")
            print(", ".join(f"{n} {seconds[n]:.0f} s" for n in slowest) + ")")
            print(f"{fmt_name} mutation recall per kind (found / eligible):")
            for kind, t in tallies.items():
                print(f"  {kind:38s} {t.found:4d} / {t.eligible:4d}  {t.found / max(t.eligible, 1):7.1%}")
                for missed in t.missed:
                    print(f"      missed {missed}")
    assert set(results.formats) == set(FORMATS)
    for fmt_name, (tallies, _, _) in results.formats.items():
        assert set(tallies) == set(KINDS)
        for kind, t in tallies.items():
            # the first model need not have every kind's target (no primitive covering a link
            # alone on ANYmal); the corpus has each kind's in each format
            assert t.eligible > 0 or not results.whole, f"{fmt_name} {kind}: no eligible target in the corpus"
            assert t.found >= MIN_RECALL * t.eligible, f"{fmt_name} {kind}: missed {t.missed}"


def test_no_false_alarm_on_benign_rewrites(results: Campaign, capsys: pytest.CaptureFixture[str]) -> None:
    for fmt_name, (_, false_alarms, seconds) in results.formats.items():
        with capsys.disabled():
            total = sum(len(v) for v in false_alarms.values())
            print(f"\n{fmt_name} false alarms on benign rewrites: {total} over {len(seconds)} models x 2 rewrites")
        assert false_alarms == {name: [] for name in seconds}
