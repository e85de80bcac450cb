"""Left and right counterparts: links named alike but for their side, placed as mirror images.

A description's left and right legs, arms, wheels and fingers are written by one macro or copied
from each other, and a fix made on one side is forgotten on the other. Two links are
counterparts when their names differ only by a side word (``left``/``right``, ``l``/``r``,
``FL``/``FR``, ``lf``/``rf``, ...) and, at the default pose, their frames are mirror images
across the robot's sagittal plane (the root frame's xz plane, ROS's convention: x forward, y
left): each one's origin is the other's with y negated, to within ``tolerance``.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass

import numpy as np

MIRROR = np.diag([1.0, -1.0, 1.0])  # reflection across the root frame's xz plane
# side words, replaced whole (at a boundary of the name: start, end, _, -, /, . or :)
SIDE_TOKENS = (
    ("l", "r"),
    ("lf", "rf"),
    ("lh", "rh"),
    ("lb", "rb"),
    ("lm", "rm"),
    ("fl", "fr"),
    ("rl", "rr"),
    ("hl", "hr"),
    ("bl", "br"),
    ("ml", "mr"),
)
SIDE_WORDS = (("left", "right"),)  # replaced anywhere in the name (panda_leftfinger)
BOUNDARY = r"(^|[_\-/.:])"


@dataclass(frozen=True)
class Counterparts:
    """Links ``left`` and ``right`` named alike but for their side and mirrored at the default pose."""

    left: str
    right: str


def _swaps(name: str) -> Iterator[str]:
    """Every name ``name`` becomes with one side word swapped for the other side's."""
    for a, b in SIDE_TOKENS:
        for x, y in ((a, b), (b, a)):
            for case in (str.lower, str.upper):
                pattern = BOUNDARY + re.escape(case(x)) + r"(?=$|[_\-/.:])"
                if re.search(pattern, name):
                    yield re.sub(pattern, r"\g<1>" + case(y), name)
    for a, b in SIDE_WORDS:
        for x, y in ((a, b), (b, a)):
            for variant in (x, x.capitalize(), x.upper()):
                if variant in name:
                    target = y if variant == x else (y.capitalize() if variant == x.capitalize() else y.upper())
                    yield name.replace(variant, target)


def named_pairs(names: Iterable[str]) -> list[tuple[str, str]]:
    """Pairs of ``names`` that differ only by a side word, each pair once and sorted, in name
    order (whatever the order of the file)."""
    known = list(dict.fromkeys(names))
    present = set(known)
    out: list[tuple[str, str]] = []
    seen: set[frozenset[str]] = set()
    for name in known:
        for other in _swaps(name):
            key = frozenset((name, other))
            if other != name and other in present and key not in seen:
                seen.add(key)
                first, second = sorted((name, other))
                out.append((first, second))
    return sorted(out)


def mirrored(origins: Mapping[str, np.ndarray], a: str, b: str, tolerance: float) -> bool:
    """Whether the world origins (3,) of ``a`` and ``b`` are mirror images across the xz plane,
    apart from each other (not both on the plane), within ``tolerance`` [m]."""
    pa, pb = origins[a], origins[b]
    return bool(np.linalg.norm(MIRROR @ pa - pb) <= tolerance < np.linalg.norm(pa - pb))


def counterparts(names: Iterable[str], origins: Mapping[str, np.ndarray], tolerance: float) -> list[Counterparts]:
    """The counterpart pairs among ``names`` whose ``origins`` (world, default pose) are mirrored."""
    return [
        Counterparts(a, b)
        for a, b in named_pairs(n for n in names if n in origins)
        if mirrored(origins, a, b, tolerance)
    ]


def mirror_tensor(tensor: np.ndarray) -> np.ndarray:
    """A world-frame inertia tensor (3, 3) of a part reflected across the xz plane."""
    return MIRROR @ tensor @ MIRROR


__all__ = ["MIRROR", "Counterparts", "counterparts", "mirror_tensor", "mirrored", "named_pairs"]
