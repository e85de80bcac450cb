"""What a check run is asked to do, independent of where the request came from (CLI, API, config).

Each user-facing option is declared once in :mod:`geomcheck.option_spec` (its flag, key,
request name, default, bounds and help); this is what a check runs with once they are read.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from geomcheck.diagnostics import Severity
from geomcheck.thresholds import Thresholds

BACKENDS = ("coal", "fcl")
SEMANTICS = ("moveit", "pinocchio")  # which link pairs exist (geomcheck.collision.topology)


@dataclass(frozen=True)
class Selection:
    """Which rules report, ruff-style: ``select``/``ignore`` by code or prefix, severity
    overrides by code, and per-subject ignores (``{link or joint name: (codes...)}``)."""

    select: tuple[str, ...] = ("ALL",)
    ignore: tuple[str, ...] = ()
    severity: Mapping[str, Severity] = field(default_factory=dict)
    per_link_ignore: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    per_joint_ignore: Mapping[str, tuple[str, ...]] = field(default_factory=dict)


@dataclass(frozen=True)
class CheckOptions:
    """Options of one check run.

    ``pose`` gives joint values ([rad] or [m]) of the default pose; ``pose_name`` names an
    SRDF ``group_state`` instead. ``matrix`` asks for the full collision matrix (slow);
    ``sweep`` for the continuous-joint sweep (on by default); ``view_3d`` for
    the ``scene`` section the HTML report's 3D view draws (on by default). ``semantics`` says which link
    pairs exist: ``moveit`` (every two links with geometry) or ``pinocchio`` (links joined
    only by fixed joints are one body, never checked against each other).
    """

    args: Mapping[str, str] = field(default_factory=dict)
    env: Mapping[str, str] = field(default_factory=dict)  # values of the variables $(env)/$(optenv) read
    srdf: Path | None = None
    pose: Mapping[str, float] = field(default_factory=dict)
    pose_name: str | None = None
    backend: str = "coal"
    semantics: str = "moveit"
    matrix: bool = False
    sweep: bool = True
    view_3d: bool = True  # the scene section (the HTML report's 3D view)
    # the drawn sections (views, 3D scene): off when the output never shows them (text, CI
    # formats), so a check does not draw what nobody reads
    drawings: bool = True
    samples: int | None = None  # overrides thresholds.self_collision.samples
    seed: int | None = None  # overrides thresholds.self_collision.seed
    fail_on: Severity = Severity.ERROR
    thresholds: Thresholds = field(default_factory=Thresholds)
    selection: Selection = field(default_factory=Selection)
    workers: int = 2  # processes for the heavy checks
