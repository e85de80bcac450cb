"""Candidate root files of an upload, ranked by what each file does, and the root a person means.

A description's root makes the robot: URDF links and joints, or xacro macro calls, at its top
level (MJCF bodies in its ``<worldbody>``, an SDFormat model with links or included models), or
through files it includes that do (a xacro including one variant or another). A file that only
defines macros, properties or materials is a library, never a root, and a file another
description includes is a part, unless that other file only wraps it: a MuJoCo scene including
its robot and adding a floor and lights makes no robot of its own, and the robot is the root.
Among the files left, the root is the one that pulls in the others: one whose includes
(directly or through them) hold everything another's do and more is the whole robot, the other
a sub-assembly (the PR2's ``pr2_base.urdf.xacro`` against ``pr2.urdf.xacro``). Then what the
rest of the upload says about them: a file named by the package's other files (launch files, a
README, a model.config for the SDFormat version Gazebo loads, an SRDF written for the robot it
names) is the root the package itself loads; a plain URDF with the robot name of a xacro is
that xacro's generated copy, and the source is the root; a ``robots/`` folder is where ROS
keeps roots. Last, of robots equally likely by all that, one pulling in at least twice the
files of every other is the robot and the others smaller models beside it.

:func:`root_candidates` ranks every candidate; :func:`choose` is the service's choice when a
request names no root: the first candidate when one of these signals puts it ahead of every
other (:class:`RootChoice` says which, and lists the alternatives), else ``None``: several
robots are equally likely (``create_1`` and ``create_2``, a multi-robot package) and the person
must say which. Nothing here runs xacro: the files are only parsed, within
:data:`MAX_SCANNED_BYTES` each and :data:`MAX_REFERENCE_FILES` read for references.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path, PurePosixPath
from typing import Any

from lxml import etree

from api.uploads.completeness import missing_files
from api.uploads.xml_elements import is_xacro, local_name, parsed_root

# the first element after the prolog (declaration, comments, processing instructions, doctype)
_PROLOG = re.compile(rb"\A(?:\s+|<\?.*?\?>|<!--.*?-->|<!DOCTYPE[^>]*>)*", re.DOTALL)
_FIRST_TAG = re.compile(rb"<(?:[\w.-]+:)?([\w.-]+)")
ROOT_TAGS = (b"robot", b"mujoco", b"sdf")  # URDF and xacro, MJCF, SDFormat
# the name a description gives its robot: <robot name>, <mujoco model>, SDFormat's <model name>
_ROBOT_NAME = re.compile(rb"""<(?:robot|mujoco|model)\b[^>]*?\b(?:name|model)\s*=\s*["']([^"']*)["']""", re.DOTALL)
# includes by file (xacro filename=, MJCF file=) and SDFormat's model:// folder
_INCLUDE = re.compile(rb"""<(?:xacro:)?include\b[^>]*?\b(?:file|filename)\s*=\s*["']([^"']+)["']""", re.DOTALL)
# an SDFormat <include> of a model folder (not a mesh's <uri>model://NAME/meshes/...)
_MODEL_URI = re.compile(rb"<include\b[^>]*>(?:(?!</include>).)*?<uri>\s*model://([^/<\s]+)", re.DOTALL)
# a substitution in an include's path: $(find pkg), $(arg name), ${property}
_SUBSTITUTION = re.compile(r"\$\([^)]*\)|\$\{[^}]*\}")
_PACKAGE_PREFIX = re.compile(r"^.*\$\((?:find|find-pkg-share|dirname|cwd)\b[^)]*\)/?")
MIN_SIZE_RATIO = 2  # a robot pulling in this many times the files of every other equally likely one is the root
MIN_PATTERN_LITERALS = 4  # letters an include with substitutions must keep to match files by it [count]
ROOT_FOLDERS = ("robots", "robot")  # where ROS description packages keep their root files
DESCRIPTION_SUFFIXES = (".urdf", ".xacro", ".sdf", ".xml")  # .xml: MJCF, SDFormat and URDF alike
SRDF_SUFFIXES = (".srdf", ".srdf.xacro")  # a MoveIt configuration: <robot> too, but never a description
MAX_SCANNED_BYTES = 4 * 1024 * 1024  # of one file, when looking for package references or includes [bytes]
PROLOG_BYTES = 64 * 1024  # read of an .xml file to find its root element (licence comments come first) [bytes]
# files that may name the root a package loads: launch files, documentation, build and test
# files, configurations (an SRDF names its robot, a model.config the SDFormat file of each version)
REFERENCE_SUFFIXES = (".launch", ".py", ".xml", ".md", ".rst", ".txt", ".yaml", ".yml", ".config", *SRDF_SUFFIXES)
MAX_REFERENCE_FILES = 2000  # files read for references in one upload [count]
REFERENCE_BYTES = 256 * 1024  # read of one such file [bytes]

XACRO_DEFINITIONS = frozenset({"macro", "property", "arg", "include", "insert_block", "element", "attribute"})
XACRO_BRANCHES = frozenset({"if", "unless"})
LEGACY_DEFINITIONS = {"property": "name", "include": "filename", "macro": "name", "arg": "name"}
# what a robot is made of, and URDF elements that make no robot part on their own
URDF_PARTS = frozenset({"link", "joint"})
URDF_EXTRAS = frozenset({"material", "gazebo", "transmission", "ros2_control", "sensor", "plugin", "version"})


def root_tag(head: bytes) -> bytes | None:
    """Local name of the first element of an XML text's head, ``None`` when there is none."""
    found = _FIRST_TAG.match(head, _PROLOG.match(head).end())  # type: ignore[union-attr]
    return found.group(1) if found else None


def is_srdf(name: str) -> bool:
    return name.lower().endswith(SRDF_SUFFIXES)


def description_candidates(folder: Path) -> list[str]:
    """Relative paths of the files under ``folder`` that may be descriptions, sorted: URDF,
    xacro and SDFormat files by suffix, ``.xml`` files only when their root element is a
    description's (``package.xml`` and launch files are not); SRDF files are not."""
    found = []
    for path in folder.rglob("*"):
        name = path.name.lower()
        if not path.is_file() or not name.endswith(DESCRIPTION_SUFFIXES) or is_srdf(name):
            continue
        if name.endswith(".xml") and root_tag(_head(path, PROLOG_BYTES)) not in ROOT_TAGS:
            continue
        found.append(path.relative_to(folder).as_posix())
    return sorted(found)


@dataclass(frozen=True)
class Candidate:
    """A file of the upload that holds a ``<robot>``, ``<mujoco>`` or ``<sdf>``: its path
    relative to the upload root, the robot's ``name`` (None when absent), whether another
    description includes it, how many description files it pulls in (directly or through
    them), whether it makes a robot (``instantiates``: at its top level, or through a file it
    includes; False: a library of macros, properties or materials, never a root), whether it
    is a sub-assembly of another candidate (``dominated``, :func:`_sub_assembly`), whether it
    is the ``generated`` copy of a xacro (a plain URDF with a xacro's robot name), how many
    other files of the upload name it (``referenced``) and which files of the upload's own
    packages it names that the upload lacks (``missing``, :mod:`api.uploads.completeness`)."""

    path: str
    robot: str | None
    included: bool
    pulls_in: int = 0
    instantiates: bool = True
    dominated: bool = False
    generated: bool = False
    referenced: int = 0
    wraps: str | None = None  # the one robot this file includes and adds no link to (a MuJoCo scene's)
    missing: tuple[str, ...] = ()  # files of the upload's own packages it names and the upload lacks

    @property
    def in_root_folder(self) -> bool:
        return any(part in ROOT_FOLDERS for part in PurePosixPath(self.path).parts[:-1])

    def signals(self) -> tuple[bool, bool, bool, bool, bool, bool, bool]:
        """What decides between candidates, most telling first (lower is likelier). Whether
        other files name a candidate counts, not how many: variants each with a launch file
        (``create_1``, ``create_2``) stay equally likely. A robot whose own package's files
        are missing from the upload comes after one the upload holds whole, even when it
        includes that one: the person uploaded the files of the robot they meant."""
        return (
            not self.instantiates,
            self.included,
            bool(self.missing),
            self.dominated,
            self.generated,
            self.referenced == 0,
            not self.in_root_folder,
        )

    def rank(self) -> tuple[Any, ...]:
        return (*self.signals(), -self.pulls_in, self.robot is None, self.path.count("/"), self.path)

    def to_dict(self) -> dict[str, Any]:
        return {
            "path": self.path,
            "robot": self.robot,
            "included": self.included,
            "pulls_in": self.pulls_in,
            "instantiates": self.instantiates,
            "referenced": self.referenced,
            "missing": len(self.missing),
        }


@dataclass(frozen=True)
class RootChoice:
    """The root a check reads: ``path`` in the upload, ``given`` by the request or chosen by the
    service, why (``reason``), and the other candidates, likeliest first (``alternatives``)."""

    path: str
    given: bool
    reason: str
    alternatives: tuple[str, ...] = field(default_factory=tuple)

    def to_dict(self) -> dict[str, Any]:
        return {"path": self.path, "given": self.given, "reason": self.reason, "alternatives": list(self.alternatives)}


def _head(path: Path, size: int = MAX_SCANNED_BYTES) -> bytes:
    with path.open("rb") as fp:
        return fp.read(size)


def _legacy_definition(element: etree._Element) -> bool:
    required = LEGACY_DEFINITIONS.get(local_name(element))
    return element.prefix is None and required is not None and element.get(required) is not None


def _instantiates_urdf(parent: etree._Element, legacy: bool) -> bool:
    """Whether a ``<robot>`` (or a top-level ``xacro:if`` in it) makes robot parts: a link or a
    joint, a macro call (``xacro:NAME``, and in a legacy file a bare ``<NAME>`` that is neither
    URDF nor a xacro definition)."""
    for child in parent:
        if not isinstance(child.tag, str):
            continue
        name = local_name(child)
        if is_xacro(child) or _legacy_definition(child):
            if name in XACRO_BRANCHES and _instantiates_urdf(child, legacy):
                return True
            if name not in XACRO_DEFINITIONS and name not in XACRO_BRANCHES:
                return True  # xacro:NAME or xacro:call: a macro instantiated
        elif name in URDF_PARTS:
            return True
        elif legacy and name not in URDF_EXTRAS and name not in LEGACY_DEFINITIONS:
            return True  # a bare legacy macro call (<pr2_base_v0 name="base">)
    return False


def _instantiates(root: etree._Element | None) -> bool:
    """Whether the parsed description makes a robot at its top level; a file that cannot be
    parsed is given the benefit of the doubt (the check says what is wrong with it)."""
    if root is None:
        return True
    kind = local_name(root)
    if kind == "robot":
        legacy = any(_legacy_definition(e) for e in root.iter() if isinstance(e.tag, str))
        return _instantiates_urdf(root, legacy)
    if kind == "mujoco":
        return any(local_name(b) == "body" for w in root if local_name(w) == "worldbody" for b in w)
    if kind == "sdf":
        holders = [m for m in root if local_name(m) == "model"]
        holders += [m for w in root if local_name(w) == "world" for m in w if local_name(m) in ("model", "include")]
        return any(
            local_name(m) == "include" or any(local_name(p) in ("link", "include", "model") for p in m) for m in holders
        )
    return True


def _includes(texts: dict[str, bytes]) -> dict[str, set[str]]:
    """Per file, the description files it includes; an include names a file by a path of
    its own (``$(find pkg)/urdf/x.xacro``, ``../x.xacro``): its base name is enough. An
    SDFormat ``model://NAME`` names a folder: every description under a folder NAME."""
    by_name: dict[str, set[str]] = {}
    by_folder: dict[str, set[str]] = {}
    for rel in texts:
        path = PurePosixPath(rel)
        by_name.setdefault(path.name, set()).add(rel)
        for folder in path.parts[:-1]:
            by_folder.setdefault(folder, set()).add(rel)

    def found(pattern: re.Pattern[bytes], text: bytes, files: Callable[[str], set[str]]) -> set[str]:
        return {f for m in pattern.finditer(text) for f in files(m.group(1).decode(errors="replace"))}

    def by_base_name(path: str) -> set[str]:
        if _SUBSTITUTION.search(path) is None:
            return by_name.get(PurePosixPath(path).name, set())
        return by_pattern(path)

    def by_pattern(path: str) -> set[str]:
        """The files an include whose path holds substitutions may name, whatever their values
        (``$(find pkg)/urdf/arms/$(arg arm_model).urdf.xacro``: every file of an arms/ folder
        ending so); none when too little of the path is literal to say."""
        tail = _PACKAGE_PREFIX.sub("", path)
        pieces = _SUBSTITUTION.split(tail)
        if sum(ch.isalnum() for piece in pieces for ch in piece) < MIN_PATTERN_LITERALS:
            return set()
        pattern = re.compile(r"(?:^|/)" + "[^/]*".join(re.escape(piece) for piece in pieces) + "$")
        return {rel for rel in texts if pattern.search(rel)}

    def in_folder(name: str) -> set[str]:
        return by_folder.get(name, set())

    return {
        rel: (found(_INCLUDE, text, by_base_name) | found(_MODEL_URI, text, in_folder)) - {rel}
        for rel, text in texts.items()
    }


def _sub_assembly(part: set[str], whole: set[str]) -> bool:
    """Whether a robot pulling in ``part`` is a sub-assembly of one pulling in ``whole``: the
    whole holds everything the part does and more, or most of it (a test file's own helper
    aside) and at least twice as much (the PR2's caster test file against pr2.urdf.xacro)."""
    if not part:
        return False
    return part < whole or (len(whole) >= 2 * len(part) and 2 * len(part & whole) > len(part))


def _reachable(start: str, includes: dict[str, set[str]]) -> set[str]:
    seen: set[str] = set()
    todo = list(includes.get(start, ()))
    while todo:
        rel = todo.pop()
        if rel not in seen:
            seen.add(rel)
            todo.extend(includes.get(rel, ()))
    seen.discard(start)
    return seen


_MACRO_DEFINITION = re.compile(rb"<xacro:macro\b")
_SDF_ENTRY = re.compile(rb"""<sdf\b[^>]*\bversion\s*=\s*["']([\d.]+)["'][^>]*>\s*([^<\s]+)\s*</sdf>""")
_SRDF_ROBOT = re.compile(rb"""<robot\b[^>]*?\bname\s*=\s*["']([^"']+)["']""")


def _version(text: bytes) -> tuple[int, ...]:
    return tuple(int(p) for p in text.split(b".") if p.isdigit())


def references(folder: Path, candidates: Iterable[str], robots: dict[str, str | None]) -> dict[str, int]:
    """How many files of the upload, descriptions aside, name each candidate: by its file name
    (a launch file, a README, a test), as the SDFormat file a ``model.config`` gives for its
    newest version (the one Gazebo loads), or as the robot an SRDF is written for."""
    wanted = set(candidates)
    if not wanted:
        return {}
    by_name: dict[str, set[str]] = {}
    for rel in wanted:
        by_name.setdefault(PurePosixPath(rel).name, set()).add(rel)
    alternatives = b"|".join(re.escape(n.encode()) for n in sorted(by_name, key=len, reverse=True))
    names = re.compile(rb"(?<![\w.-])(" + alternatives + rb")(?![\w.-])")
    counts = dict.fromkeys(wanted, 0)
    scanned = 0
    for path in sorted(folder.rglob("*")):
        rel = path.relative_to(folder).as_posix()
        name = path.name.lower()
        if rel in wanted or not name.endswith(REFERENCE_SUFFIXES) or name == "package.xml" or not path.is_file():
            continue
        if scanned >= MAX_REFERENCE_FILES:
            break
        scanned += 1
        text = _head(path, REFERENCE_BYTES)
        named: set[str] = set()
        if name == "model.config":  # Gazebo loads the file of the newest version it lists
            entries = sorted(_SDF_ENTRY.findall(text), key=lambda e: _version(e[0]))
            if entries:
                target = (PurePosixPath(rel).parent / entries[-1][1].decode(errors="replace")).as_posix()
                named |= {target} & wanted
        elif is_srdf(name):  # written for the robot it names
            found = _SRDF_ROBOT.search(text)
            robot = found.group(1).decode(errors="replace") if found else None
            named |= {c for c, r in robots.items() if robot is not None and r == robot}
        else:
            named |= {c for m in names.finditer(text) for c in by_name.get(m.group(1).decode(), ())}
        for c in named:
            counts[c] += 1
    return counts


def _robot_name(root: etree._Element | None, text: bytes) -> str | None:
    """The name a description gives its robot: ``<robot name>``, ``<mujoco model>`` or the
    SDFormat model's name, from the parsed file, else from its text."""
    named = None
    if root is not None and local_name(root) == "sdf":
        named = next((m.get("name") for m in root if local_name(m) == "model"), None)
    elif root is not None:
        named = root.get("model" if local_name(root) == "mujoco" else "name")
    if named is None:
        match = _ROBOT_NAME.search(text)
        named = match.group(1).decode(errors="replace") if match else None
    return named


def _robot_files(
    texts: dict[str, bytes], trees: dict[str, etree._Element | None]
) -> dict[str, tuple[str | None, bool]]:
    """The files that hold a robot description (their ``texts`` and parsed ``trees``): each
    one's robot name, and whether it makes a robot at its top level (:func:`_instantiates`)."""
    found: dict[str, tuple[str | None, bool]] = {}
    for rel, text in texts.items():
        if root_tag(text[:PROLOG_BYTES]) not in ROOT_TAGS and not (rel.endswith(".xacro") and b"<robot" in text):
            continue  # a xacro may open with macros before its <robot>; others must start with one
        found[rel] = (_robot_name(trees[rel], text), _instantiates(trees[rel]))
    return found


def _wrapped_robots(
    own: dict[str, bool],
    includes: dict[str, set[str]],
    reach: dict[str, set[str]],
    makers: dict[str, set[str]],
    libraries: set[str],
) -> dict[str, str]:
    """File -> the one robot it wraps: a file making nothing itself and including one robot (a
    MuJoCo scene adding a floor and lights around it) wraps that robot, which is the root, not a
    part of the scene. A file defining macros (``libraries``) wraps nothing: what it includes is
    a part of the robot its macros make (Spot's macro file including its accessories)."""
    wraps: dict[str, str] = {}
    for rel, makes in own.items():
        direct = {other for other in includes[rel] if own.get(other)}
        if not makes and len(direct) == 1 and rel not in libraries:
            (robot,) = direct
            if makers[rel] <= {robot, *reach.get(robot, ())}:
                wraps[rel] = robot
    return wraps


def _compared(candidates: list[Candidate], reach: dict[str, set[str]]) -> list[Candidate]:
    """``candidates`` marked by what sets them below another: a sub-assembly of a robot no
    file includes and whose files the upload holds as far as its own are held (``dominated``),
    or the plain-URDF copy of a xacro's robot (``generated``)."""
    tops = [c.path for c in candidates if c.instantiates and not c.included]  # the roots a person may mean
    xacro_robots = {c.robot for c in candidates if c.path in tops and c.path.endswith(".xacro") and c.robot}
    lacks = {c.path: set(c.missing) for c in candidates}
    return [
        replace(
            c,
            # a robot is no sub-assembly of one whose files the upload lacks and its own are there
            dominated=any(
                _sub_assembly(reach[c.path], reach[other]) and lacks[other] <= lacks[c.path]
                for other in tops
                if other != c.path
            ),
            generated=c.path.endswith(".urdf")
            and not reach[c.path]
            and c.robot is not None
            and c.robot in xacro_robots,
        )
        for c in candidates
    ]


def root_candidates(folder: Path) -> list[Candidate]:
    """The candidate root files under ``folder``, the likely root first."""
    texts = {rel: _head(folder / rel) for rel in description_candidates(folder)}
    trees = {rel: parsed_root(text) for rel, text in texts.items()}  # each parsed once, for every signal
    includes = _includes(texts)
    found = _robot_files(texts, trees)
    reach = {rel: _reachable(rel, includes) for rel in found}
    own = {rel: makes for rel, (_, makes) in found.items()}
    # a file makes a robot when it instantiates one or includes a file that does (dingo.urdf.xacro
    # choosing dingo-d or dingo-o); libraries do not; a wrapper makes none of its own
    makers = {rel: {other for other in reach[rel] if own.get(other)} for rel in found}
    libraries = {rel for rel in found if _MACRO_DEFINITION.search(texts[rel])}
    wraps = _wrapped_robots(own, includes, reach, makers, libraries)
    found = {rel: (robot, makes or (bool(makers[rel]) and rel not in wraps)) for rel, (robot, makes) in found.items()}
    included = {other for rel, others in includes.items() for other in others if wraps.get(rel) != other}
    referenced = references(folder, found, {rel: robot for rel, (robot, _) in found.items()})
    missing = missing_files(folder, trees, list(found))
    candidates = [
        Candidate(
            path=rel,
            robot=robot,
            included=rel in included,
            pulls_in=len(reach[rel]),
            instantiates=makes,
            referenced=referenced[rel],
            wraps=wraps.get(rel),
            missing=tuple(missing[rel]),
        )
        for rel, (robot, makes) in found.items()
    ]
    candidates = _compared(candidates, reach)
    return sorted(candidates, key=Candidate.rank)


def _why(first: Candidate, second: Candidate) -> str:
    """What puts ``first`` ahead of ``second``: the first signal they differ in."""
    if second.wraps == first.path:
        return f"the robot itself: {second.path} only includes it, and adds no link or body of its own"
    if first.instantiates != second.instantiates:
        return "the only file that makes a robot at its top level; the others define macros or materials"
    if first.included != second.included:
        return "the robot no other file includes; the others are parts of it"
    if bool(first.missing) != bool(second.missing):
        n = len(second.missing)
        return (
            f"the robot the upload holds whole: {second.path} names {n} file{'s' if n != 1 else ''} of the upload's "
            f"own packages that it lacks ({second.missing[0]}{', ...' if n > 1 else ''})"
        )
    if first.dominated != second.dominated:
        return f"the whole robot: it includes what {second.path} includes and more ({first.pulls_in} files)"
    if first.generated != second.generated:
        return f"the source of {second.path}, which holds the same robot ({second.robot}) as plain URDF"
    if (first.referenced == 0) != (second.referenced == 0):
        s = "s" if first.referenced != 1 else ""
        return f"named by {first.referenced} other file{s} of the upload (launch files, documentation, configuration)"
    return "the only candidate in a robots/ folder, where ROS packages keep their roots"


def choose(candidates: list[Candidate]) -> RootChoice | None:
    """The root the service takes when the request names none: the first candidate when a
    signal puts it ahead of every other, with why and the alternatives; ``None`` when two or
    more are equally likely (the request must name one)."""
    if not candidates:
        return None
    first = candidates[0]
    others = tuple(c.path for c in candidates[1:])
    if len(candidates) == 1:
        return RootChoice(first.path, False, "the only robot description in the upload")
    second = candidates[1]
    if first.signals() != second.signals():
        return RootChoice(first.path, False, _why(first, second), others)
    # equally likely by what they are: the one that pulls in far more of the upload is the
    # robot, the others smaller models beside it (a docking station beside the LoCoBot)
    tied = [c for c in candidates if c.signals() == first.signals()]
    if all(first.pulls_in >= MIN_SIZE_RATIO * max(c.pulls_in, 1) for c in tied[1:]):
        reason = (
            f"the largest robot: it pulls in {first.pulls_in} files, at least {MIN_SIZE_RATIO} times as many as any "
            f"other robot of the upload ({second.path}: {second.pulls_in})"
        )
        return RootChoice(first.path, False, reason, others)
    return None


def evident_root(candidates: list[Candidate]) -> Candidate | None:
    """The candidate :func:`choose` takes, or ``None``."""
    chosen = choose(candidates)
    return next((c for c in candidates if c.path == chosen.path), None) if chosen is not None else None
