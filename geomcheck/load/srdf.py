"""Reading a MoveIt SRDF: the collision entries (``disable_collisions``,
``disable_default_collisions``, ``enable_collisions``) and the named poses (``group_state``).

Everything else in the file (groups, end effectors, virtual joints) is kept out of the way.
The file is parsed with the same hardened parser as the URDF. MoveIt config packages often
ship the SRDF as xacro (``NAME.srdf.xacro``, names written ``$(arg prefix)joint_1``): a file
that is xacro by its name or its content is expanded first, with the expander, packages,
arguments and sandbox of the description.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path

from lxml import etree

from geomcheck.errors import InputError, UsageError
from geomcheck.load.bundle import Bundle, make_bundle, read_package_name
from geomcheck.load.legacy import uses_xacro
from geomcheck.load.xmlsafe import parse_bytes, read_file_bytes
from geomcheck.model import SourceLocation
from geomcheck.thresholds import LoadLimits

# The reasons MoveIt's Setup Assistant writes; any other text is read as "User", as MoveIt does.
SRDF_REASONS = ("Adjacent", "Default", "Always", "Never", "User")

LinkPair = tuple[str, str]


def link_pair(a: str, b: str) -> LinkPair:
    """The unordered pair ``{a, b}`` as a sorted tuple."""
    return (a, b) if a <= b else (b, a)


@dataclass(frozen=True)
class DisabledPair:
    """One ``<disable_collisions link1 link2 reason>`` (``reason`` as written, ``""`` when absent)."""

    link1: str
    link2: str
    reason: str
    location: SourceLocation

    @property
    def pair(self) -> LinkPair:
        return link_pair(self.link1, self.link2)

    @property
    def moveit_reason(self) -> str:
        """``reason`` as MoveIt reads it: one of :data:`SRDF_REASONS`."""
        return self.reason if self.reason in SRDF_REASONS else "User"


@dataclass(frozen=True)
class LinkEntry:
    """A ``<disable_default_collisions link>`` element."""

    link: str
    location: SourceLocation


@dataclass(frozen=True)
class GroupState:
    """A named pose: ``values`` maps joint names to their values ([rad] or [m]; several for
    multi-DOF joints, such as the 7 of a floating joint)."""

    name: str
    group: str
    values: Mapping[str, tuple[float, ...]]
    location: SourceLocation

    def single_values(self) -> dict[str, float]:
        """Values of the one-DOF joints only, as ``{joint: value}``."""
        return {k: v[0] for k, v in self.values.items() if len(v) == 1}


@dataclass(frozen=True)
class Srdf:
    """The parts of an SRDF that matter for collision checking, in document order."""

    robot_name: str
    source: str  # display path
    disabled: tuple[DisabledPair, ...] = ()
    disabled_links: tuple[LinkEntry, ...] = ()  # disable_default_collisions
    enabled: tuple[DisabledPair, ...] = ()  # enable_collisions (``reason`` kept as written)
    group_states: tuple[GroupState, ...] = ()
    virtual_joints: tuple[str, ...] = ()  # names of <virtual_joint> (a mobile base's pose)
    location: SourceLocation = field(default_factory=lambda: SourceLocation(""))

    @functools.cached_property
    def _disabled_pairs(self) -> frozenset[LinkPair]:
        return frozenset(d.pair for d in self.disabled)

    @functools.cached_property
    def _enabled_pairs(self) -> frozenset[LinkPair]:
        return frozenset(e.pair for e in self.enabled)

    @functools.cached_property
    def _default_disabled_links(self) -> frozenset[str]:
        return frozenset(e.link for e in self.disabled_links)

    def is_disabled(self, a: str, b: str) -> bool:
        """Whether MoveIt skips the pair: listed in ``disable_collisions``, or one link is in
        ``disable_default_collisions`` and the pair is not re-enabled by ``enable_collisions``."""
        pair = link_pair(a, b)
        if pair in self._disabled_pairs:
            return True
        if a in self._default_disabled_links or b in self._default_disabled_links:
            return pair not in self._enabled_pairs
        return False

    def entry(self, a: str, b: str) -> DisabledPair | None:
        """The first ``disable_collisions`` element naming the pair, if any."""
        pair = link_pair(a, b)
        return next((d for d in self.disabled if d.pair == pair), None)

    def group_state(self, name: str) -> GroupState:
        """The ``group_state`` called ``name``; :class:`UsageError` naming the valid ones otherwise."""
        for state in self.group_states:
            if state.name == name:
                return state
        raise UsageError.bad_choice(
            f"named pose (group_state in {self.source})", name, [s.name for s in self.group_states]
        )


Origins = Mapping[object, tuple[str, int] | None]
"""Per element of an expanded SRDF, the (display file, line) xacro read it from."""


def _location(display: str, element: object, origins: Origins | None = None) -> SourceLocation:
    if origins is not None:  # an expanded document: where the element was written
        origin = origins.get(element)
        return SourceLocation(*origin) if origin is not None else SourceLocation(display)
    line = getattr(element, "sourceline", None)
    return SourceLocation(display, line if isinstance(line, int) else None)


def _require(element: object, attribute: str, display: str, origins: Origins | None = None) -> str:
    value = element.get(attribute)  # type: ignore[attr-defined]
    if value is None or not value.strip():
        loc = _location(display, element, origins)
        tag = element.tag  # type: ignore[attr-defined]
        raise InputError(f"{loc}: <{tag}> lacks the attribute '{attribute}'")
    return str(value).strip()


def _values(text: str, where: SourceLocation, joint: str) -> tuple[float, ...]:
    try:
        values = tuple(float(v) for v in text.split())
    except ValueError:
        raise InputError(f"{where}: group_state value of joint {joint!r} is not a number: {text!r}") from None
    if not values:
        raise InputError(f"{where}: group_state joint {joint!r} has no value")
    return values


def parse_srdf(data: bytes, display: str, limits: LoadLimits | None = None, origins: Origins | None = None) -> Srdf:
    """An :class:`Srdf` from the file's bytes; ``display`` names the file in messages and
    locations (``origins``, for an expanded xacro, says where each element was written).
    :class:`InputError` when it is not XML or not an SRDF (root not ``<robot>``, an entry
    without its link names, a pose value that is not a number)."""
    root = parse_bytes(data, display, limits)
    return _srdf(root, display, origins)


def _srdf(root: etree._Element, display: str, origins: Origins | None) -> Srdf:
    if root.tag != "robot":
        raise InputError(f"{display}: not an SRDF: the root element is <{root.tag}>, expected <robot>")
    disabled: list[DisabledPair] = []
    enabled: list[DisabledPair] = []
    links: list[LinkEntry] = []
    states: list[GroupState] = []
    virtual: list[str] = []
    for element in root:
        tag = element.tag
        if not isinstance(tag, str):  # comments and processing instructions
            continue
        if tag in ("disable_collisions", "enable_collisions"):
            entry = DisabledPair(
                _require(element, "link1", display, origins),
                _require(element, "link2", display, origins),
                (element.get("reason") or "").strip(),
                _location(display, element, origins),
            )
            (disabled if tag == "disable_collisions" else enabled).append(entry)
        elif tag == "virtual_joint":
            virtual.append(_require(element, "name", display, origins))
        elif tag == "disable_default_collisions":
            links.append(LinkEntry(_require(element, "link", display, origins), _location(display, element, origins)))
        elif tag == "group_state":
            where = _location(display, element, origins)
            values: dict[str, tuple[float, ...]] = {}
            for joint in element.iterfind("joint"):
                name = _require(joint, "name", display, origins)
                values[name] = _values(joint.get("value") or "", _location(display, joint, origins), name)
            states.append(
                GroupState(_require(element, "name", display, origins), element.get("group") or "", values, where)
            )
    return Srdf(
        robot_name=(root.get("name") or "").strip(),
        source=display,
        disabled=tuple(disabled),
        disabled_links=tuple(links),
        enabled=tuple(enabled),
        group_states=tuple(states),
        virtual_joints=tuple(virtual),
        location=_location(display, root, origins),
    )


def read_srdf(
    path: Path,
    display: str | None = None,
    limits: LoadLimits | None = None,
    bundle: Bundle | None = None,
    args: Mapping[str, str] | None = None,
) -> Srdf:
    """Read and parse the SRDF at ``path`` (``display`` names it in messages). A xacro SRDF
    (``.xacro`` name, the xacro namespace, or xacro tags) is expanded first with ``bundle``'s
    packages and sandbox (a bundle of its own folder when none is given) and ``args``.
    :class:`InputError` when it is missing, malformed, fails to expand, or is larger than the
    limits (:class:`LimitExceeded`); :class:`SandboxViolation` outside a confined bundle."""
    shown = display or path.as_posix()
    data = read_file_bytes(path, shown, limits)
    try:
        root = parse_bytes(data, shown, limits)
    except InputError as err:
        if "Namespace prefix xacro" not in str(err):
            raise
        root = None  # xacro tags without the namespace: the expansion declares it
    if root is not None and not uses_xacro(root, path.name):
        return _srdf(root, shown, None)
    return _expanded(path, shown, limits or LoadLimits(), bundle, args or {})


def _expanded(path: Path, display: str, limits: LoadLimits, bundle: Bundle | None, args: Mapping[str, str]) -> Srdf:
    """The SRDF xacro at ``path`` expanded, as the description is (same expander, packages,
    arguments and sandbox), each element located where it was written."""
    from geomcheck.load.xacro_expand import expand

    if bundle is None:
        own = make_bundle(path, display_root=path.parent)
    else:  # the description's packages and sandbox, and the package holding the SRDF (a MoveIt config)
        packages = dict(bundle.packages)
        for parent in path.resolve().parents:
            if (parent / "package.xml").is_file():
                packages.setdefault(read_package_name(parent), parent)
                break
        own = replace(bundle, root_file=path.resolve(), packages=packages)
    expansion = expand(own, args, limits)
    expanded_limits = replace(limits, max_file_bytes=limits.max_expanded_bytes)
    root = parse_bytes(expansion.text.encode("utf-8"), f"{display} (expanded)", expanded_limits)
    elements = [e for e in root.iter() if isinstance(e.tag, str)]
    origins = dict(zip(elements, expansion.origins, strict=False))
    return _srdf(root, display, origins)
