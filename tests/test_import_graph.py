"""Import circles: the modules below import in one direction only. Every import of a
geomcheck module counts, also one inside a function or under ``TYPE_CHECKING``."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "geomcheck"
# (module, module) pairs once in a circle: the collision interface and its engines, findings
# and failures, the fit and the mesh comparison, the check families and their shared analyses
ONE_WAY = (
    ("geomcheck.collision.base", "geomcheck.collision.coal_backend"),
    ("geomcheck.collision.base", "geomcheck.collision.fcl_backend"),
    ("geomcheck.collision.base", "geomcheck.collision.backends"),
    ("geomcheck.diagnostics", "geomcheck.errors"),
    ("geomcheck.geometry.fit", "geomcheck.geometry.meshfit"),
    ("geomcheck.geometry.fit", "geomcheck.geometry.elements"),
    ("geomcheck.checks", "geomcheck.checks.analyses"),
    ("geomcheck.checks.meshes", "geomcheck.checks.analyses"),
)


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def import_graph() -> dict[str, set[str]]:
    """Module -> the geomcheck modules it imports anywhere in its text."""
    modules = {module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph: dict[str, set[str]] = {name: set() for name in modules}
    for name, path in modules.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                targets = [node.module, *(f"{node.module}.{alias.name}" for alias in node.names)]
            graph[name].update(t for t in targets if t in modules and t != name)
    return graph


def reachable(graph: dict[str, set[str]], start: str) -> set[str]:
    seen: set[str] = set()
    todo = list(graph[start])
    while todo:
        name = todo.pop()
        if name not in seen:
            seen.add(name)
            todo.extend(graph[name])
    return seen


def test_the_graph_sees_lazy_and_type_checking_imports() -> None:
    graph = import_graph()
    assert "geomcheck.collision.coal_backend" in graph["geomcheck.collision.backends"]  # inside a function
    assert "geomcheck.diagnostics" in graph["geomcheck.errors"]  # under TYPE_CHECKING


def test_named_modules_import_each_other_one_way_only() -> None:
    graph = import_graph()
    reach = {name: reachable(graph, name) for pair in ONE_WAY for name in pair}
    assert [(a, b) for a, b in ONE_WAY if b in reach[a] and a in reach[b]] == []
