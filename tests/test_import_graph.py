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


# The layers of docs/architecture.md, lowest first: a module imports only modules of its own
# layer or below. The most specific prefix names a module's layer.
LAYERS: tuple[tuple[str, ...], ...] = (
    (  # foundations: findings, rules, the model, thresholds, what a fix is
        "geomcheck.version",
        "geomcheck.errors",
        "geomcheck.thresholds",
        "geomcheck.model",
        "geomcheck.diagnostics",
        "geomcheck.rules",
        "geomcheck.options",
        "geomcheck.progress",
        "geomcheck.repeats",
        "geomcheck.gitrev",
        "geomcheck.fixes",
    ),
    ("geomcheck.cache",),  # the content-addressed store: knows no stage
    ("geomcheck.load",),  # LOAD: bundle, xacro, URDF, MJCF, SDFormat (sdf*), meshes (and their stage caches)
    ("geomcheck.geometry", "geomcheck.kinematics", "geomcheck.collision"),  # computations
    ("geomcheck.selfcollision",),
    ("geomcheck.checks",),  # CHECKS: the rule families and their shared analyses
    ("geomcheck.report",),  # REPORT: one model, every format
    ("geomcheck.patch",),  # a fix as text: planned against the loaded sources, applied, diffed
    (  # running checks: the pipeline, configuration, verified fixes, diffs, baselines, untrusted runs
        "geomcheck.pipeline",
        "geomcheck.check_cache",
        "geomcheck.option_spec",
        "geomcheck.config",
        "geomcheck.fix",
        "geomcheck.baseline",
        "geomcheck.diff",
        "geomcheck.diff_cache",
        "geomcheck.untrusted",
    ),
    ("geomcheck.facade", "geomcheck.cli", "geomcheck.__main__", "geomcheck"),  # the surfaces
)


def layer_of(module: str) -> int:
    """The layer of ``module``: that of the longest prefix naming it (a package or a module)."""
    best, found = -1, -1
    for index, prefixes in enumerate(LAYERS):
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > best:
                best, found = len(prefix), index
    return found


def test_every_module_has_a_layer() -> None:
    assert [m for m in import_graph() if layer_of(m) < 0] == []


def test_no_import_circle_anywhere() -> None:
    graph = import_graph()
    circles = sorted(m for m in graph if m in reachable(graph, m))
    assert circles == []


def test_layers_import_only_downwards() -> None:
    graph = import_graph()
    upward = sorted(
        f"{a} ({layer_of(a)}) -> {b} ({layer_of(b)})"
        for a, targets in graph.items()
        for b in targets
        if layer_of(b) > layer_of(a)
    )
    assert upward == []


def test_the_service_is_above_the_library() -> None:
    """api/ imports geomcheck; geomcheck imports api/ only where it starts the service
    (``geomcheck serve``, ``worker``: the CLI's service module, lazily)."""
    importers = sorted(
        name
        for name, path in ((module_name(p), p) for p in PACKAGE.rglob("*.py"))
        if any(
            isinstance(n, ast.ImportFrom) and n.module and n.module.split(".")[0] == "api"
            for n in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
        )
    )
    assert importers == ["geomcheck.cli.service"]
