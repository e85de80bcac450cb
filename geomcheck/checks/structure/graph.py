"""Every graph-level GC1xx finding of a robot in a stable order, those one source line wrote for
several subjects as one, and the family's ``run``."""

from __future__ import annotations

from dataclasses import replace

from geomcheck.checks import CheckContext, FamilyResult
from geomcheck.checks.model_section import MODEL_SECTION, model_section
from geomcheck.checks.structure.joints import joint_definitions, mimic_ranges, mimics
from geomcheck.checks.structure.tree import cycles, duplicate_names, joint_links, tree_shape
from geomcheck.diagnostics import Diagnostic
from geomcheck.model import Robot
from geomcheck.thresholds import StructureThresholds


def check_robot(robot: Robot, thresholds: StructureThresholds | None = None, fmt: str = "urdf") -> list[Diagnostic]:
    """Every graph-level GC1xx finding of ``robot``, a description in format ``fmt`` (``urdf``,
    ``sdf``, ``mjcf``), in a stable order."""
    thresholds = thresholds or StructureThresholds()
    out: list[Diagnostic] = []
    out.extend(duplicate_names(robot))
    out.extend(joint_links(robot))
    out.extend(tree_shape(robot, fmt))
    out.extend(cycles(robot, fmt))
    out.extend(joint_definitions(robot, thresholds, fmt))
    out.extend(mimics(robot))
    out.extend(mimic_ranges(robot, thresholds))
    return group_by_source_line(out)


MAX_ALSO_NAMED = 5  # other subjects a grouped finding names in its message [count]


def group_by_source_line(found: list[Diagnostic]) -> list[Diagnostic]:
    """``found`` with the findings one source line wrote for several subjects (a xacro macro
    expanded for the left and the right side) merged into the one with the first subject name,
    which names the others:
    the author fixes one line."""
    first: dict[tuple[str, str, int, str, str], int] = {}
    others: dict[int, list[Diagnostic]] = {}
    kept: list[Diagnostic] = []
    for d in found:
        loc = d.location
        # only an expanded document writes several elements from one source line (a plain
        # file minified onto one line holds distinct elements: they stay distinct findings)
        expanded = loc is not None and loc.expanded_line is not None and loc.expanded_line != loc.line
        if loc is None or loc.line is None or not expanded or not (d.joint or d.link):
            kept.append(d)
            continue
        key = (d.code, loc.file, loc.line, d.about, d.message)
        if key in first:
            others.setdefault(first[key], []).append(d)
            continue
        first[key] = len(kept)
        kept.append(d)
    for index, group in others.items():
        # the member named first stands for the group, whatever the order of the file
        d = min([kept[index], *group], key=lambda m: m.joint or m.link or "")
        names = sorted({m.joint or m.link or "" for m in [kept[index], *group] if m is not d})
        listed = ", ".join(names[:MAX_ALSO_NAMED])
        if len(names) > MAX_ALSO_NAMED:
            listed += f" and {len(names) - MAX_ALSO_NAMED} more"
        kept[index] = replace(d, message=f"{d.message} (also in {listed})", data={**d.data, "also": names})
    return kept


def run(ctx: CheckContext) -> FamilyResult:
    fmt = ctx.loaded.format
    return FamilyResult(
        diagnostics=check_robot(ctx.robot, ctx.thresholds.structure, fmt),
        sections={MODEL_SECTION: model_section(ctx.robot)},
    )
