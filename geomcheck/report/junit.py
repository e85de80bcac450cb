"""JUnit XML (GitLab CI, Jenkins, Azure): a test suite per rule family, a test case per
checked subject in it.

Findings at or above the failing severity make their test case fail (one ``<failure>``
listing them all); lower ones go to its ``<system-out>``, so the test verdicts agree with
the exit status. Subjects are the robot, the links and joints the report names (links from
the per-link sections, joints from the sweeps, and every subject with a finding) and the
link pairs with a finding; each family lists the subject kinds it checks.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import defaultdict
from collections.abc import Iterable

from geomcheck.diagnostics import Diagnostic
from geomcheck.report.model import Report
from geomcheck.report.section_inertia import inertia_section
from geomcheck.report.section_links import links_section
from geomcheck.report.section_sweeps import sweeps_section
from geomcheck.report.section_views import views_section
from geomcheck.report.summary import location_label, skipped_lines, summary_line
from geomcheck.rules import FAMILIES, FAMILY_TITLES

# family prefix -> subject kinds it checks ("robot", "link", "joint"; pairs come from findings)
FAMILY_SUBJECTS: dict[str, tuple[str, ...]] = {
    "GC1": ("robot", "link", "joint"),
    "GC2": ("link",),
    "GC3": ("link",),
    "GC4": ("robot", "joint"),
    "GC5": ("link",),
}


def _unique(names: Iterable[str]) -> list[str]:
    return list(dict.fromkeys(names))


def known_subjects(report: Report) -> dict[str, list[str]]:
    """Subject names by kind, in first-seen order: sections first, then findings."""
    sections = report.sections
    links = [e.link for e in links_section(sections)] + [e.link for e in inertia_section(sections)]
    links = [name for name in [*links, *(v.link for v in views_section(sections))] if name]
    joints = [s.joint for s in sweeps_section(sections) if s.joint]
    links += [d.link for d in report.diagnostics if d.link and not d.links]
    joints += [d.joint for d in report.diagnostics if d.joint and not d.links]
    return {"robot": ["robot"], "link": _unique(links), "joint": _unique(joints)}


def _subject_key(d: Diagnostic) -> str:
    return d.subject


def _failure_text(findings: list[Diagnostic], report: Report) -> str:
    return "\n".join(
        f"{location_label(d, report)}: {d.code} [{d.severity.value}] {d.name}: {d.message}\n  help: {d.help}"
        for d in findings
    )


def testcase(parent: ET.Element, classname: str, name: str, findings: list[Diagnostic], report: Report) -> bool:
    """Append a test case; ``True`` when it fails."""
    case = ET.SubElement(parent, "testcase", {"classname": classname, "name": name, "time": "0"})
    if findings and findings[0].location is not None:
        case.set("file", findings[0].location.file)
    failing = [d for d in findings if d.severity.rank >= report.fail_on.rank]
    passing = [d for d in findings if d.severity.rank < report.fail_on.rank]
    if failing:
        codes = ", ".join(sorted({d.code for d in failing}))
        failure = ET.SubElement(
            case, "failure", {"message": f"{len(failing)} finding(s): {codes}", "type": failing[0].code}
        )
        failure.text = _failure_text(failing, report)
    if passing:
        ET.SubElement(case, "system-out").text = _failure_text(passing, report)
    return bool(failing)


def render(report: Report) -> str:
    subjects = known_subjects(report)
    by_family: dict[str, dict[str, list[Diagnostic]]] = defaultdict(lambda: defaultdict(list))
    for d in report.diagnostics:
        by_family[d.code[:3]][_subject_key(d)].append(d)
    root = ET.Element("testsuites", {"name": f"geomcheck {report.robot.name}"})
    total = failed_total = 0
    for prefix, family in FAMILIES.items():
        found = by_family.get(prefix, {})
        names = [
            "robot" if kind == "robot" else f"{kind} {n}" for kind in FAMILY_SUBJECTS[prefix] for n in subjects[kind]
        ]
        names = _unique([*names, *found])
        suite = ET.SubElement(
            root,
            "testsuite",
            {"name": f"{prefix}xx {FAMILY_TITLES[prefix]}", "timestamp": report.created.removesuffix("Z")},
        )
        classname = f"geomcheck.{family}"
        failures = sum(testcase(suite, classname, name, found.get(name, []), report) for name in names)
        suite.attrib.update(
            {"tests": str(len(names)), "failures": str(failures), "errors": "0", "skipped": "0", "time": "0"}
        )
        if prefix == "GC1":
            ET.SubElement(suite, "system-out").text = "\n".join([*skipped_lines(report), summary_line(report)])
        total += len(names)
        failed_total += failures
    root.attrib.update({"tests": str(total), "failures": str(failed_total), "errors": "0", "time": "0"})
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
