"""The rules reference (docs/rules.md), rendered from the rule registry.

Regenerate with ``geomcheck rules --format markdown -o docs/rules.md``; a test keeps the
checked-in file equal to this output.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from geomcheck.rules import FAMILIES, FAMILY_TITLES, SEVERITY_POLICY, Rule

REGENERATE = "geomcheck rules --format markdown -o docs/rules.md"
BETTER = {"lower": "lower", "higher": "higher", "none": "—"}  # which way a metric improves
MARKUP = re.compile(r"(?<!`)<[A-Za-z!/?][^<>\n]*>(?!`)")


def prose(text: str) -> str:
    """``text`` with XML markup quoted as code, so Markdown shows ``<origin>`` instead of
    swallowing it as HTML."""
    return MARKUP.sub(lambda m: f"`{m.group(0)}`", text.strip())


def code_block(text: str) -> str:
    """``text`` fenced as XML when it is markup, kept as written when it already has fences."""
    body = text.strip("\n")
    if "```" in body:
        return body
    if body.lstrip().startswith("<"):
        return f"```xml\n{body}\n```"
    return prose(body)


def cell(text: str) -> str:
    """``text`` safe inside a Markdown table cell."""
    return prose(text).replace("|", "\\|").replace("\n", " ")


def anchor(rule: Rule) -> str:
    """The GitHub anchor of the rule's heading."""
    return f"{rule.code.lower()}-{rule.name}"


def rule_body(rule: Rule) -> str:
    """What / why / example / fix (and the automatic fix, if any) as Markdown (also the SARIF rule help)."""
    from geomcheck.fixes.derive import rule_fix_note

    automatic = rule_fix_note(rule.code)
    return (
        f"**What it does.** {prose(rule.what)}\n\n"
        f"**Why it matters.** {prose(rule.why)}\n\n"
        + (f"**Severity.** {prose(rule.severity_reason)}\n\n" if rule.severity_reason else "")
        + f"**Example.**\n\n{code_block(rule.example)}\n\n"
        f"**Fix.** {prose(rule.fix)}\n" + (f"\n**Automatic fix.** {automatic}\n" if automatic else "")
    )


def metrics_table(rule: Rule) -> str:
    """The metrics the rule's findings carry in ``data``, as a Markdown table (``""`` for none)."""
    if not rule.metrics:
        return ""
    rows = [
        f"| `{m.name}` | {cell(m.unit)} | {BETTER[m.better]} | {cell(m.description)}"
        + (" *(optional)* |" if m.optional else " |")
        for m in rule.metrics
    ]
    return "\n".join(
        [
            "**Metrics** (the finding's `data`; lengths in metres unless the key ends in `_mm`).",
            "",
            "| key | unit | better | meaning |",
            "| --- | --- | --- | --- |",
            *rows,
            "",
        ]
    )


def metrics_text(rule: Rule) -> str:
    """The metrics as plain text, for ``geomcheck rule CODE`` (``""`` for none)."""
    if not rule.metrics:
        return ""
    width = max(len(m.name) for m in rule.metrics)
    units = max(len(m.unit) for m in rule.metrics)
    lines = [
        f"  {m.name:<{width}}  [{m.unit}]{'':<{units - len(m.unit)}}  {m.better:<6}  "
        f"{m.description}{' (optional)' if m.optional else ''}"
        for m in rule.metrics
    ]
    return "Metrics (data key, unit, better)\n" + "\n".join(lines) + "\n"


def render(rules: Sequence[Rule]) -> str:
    lines = [
        "# Rules",
        "",
        f"<!-- Generated from the rule registry by `{REGENERATE}`; do not edit by hand. -->",
        "",
        "Every rule has a stable code, a kebab-case name and a default severity; `select`, `ignore`",
        "and `severity` in the configuration (see [ci.md](ci.md)) take codes, prefixes (`GC3`) or",
        "family names (`fit`). `geomcheck rule CODE` prints one rule's documentation.",
        "",
        "Each rule lists the metrics its findings carry in `data`, with their unit and which way is",
        "better: `geomcheck diff` reports a finding present on both sides as a regression when one of",
        "them got worse (numbers marked — describe and are not compared).",
        "",
        f"**Severity policy.** {prose(SEVERITY_POLICY)} Each rule's *Severity* paragraph says how it",
        "applies the policy; [precision.md](precision.md) reviews every error and warning on the corpus.",
        "",
    ]
    for prefix, family in FAMILIES.items():
        members = [r for r in rules if r.family == prefix]
        if not members:
            continue
        lines += [f"## {prefix}xx {FAMILY_TITLES[prefix]} (`{family}`)", ""]
        lines += ["| code | name | severity | summary |", "| --- | --- | --- | --- |"]
        lines += [
            f"| [{r.code}](#{anchor(r)}) | `{r.name}` | {r.severity.value} | {cell(r.summary)} |" for r in members
        ]
        lines.append("")
        for r in members:
            lines += [f"### {r.code} {r.name}", "", f"*{r.severity.value}* — {prose(r.summary)}", "", rule_body(r)]
            if r.metrics:
                lines += [metrics_table(r)]
    return "\n".join(lines).rstrip("\n") + "\n"
