"""The house's sizes: no module of the library or the service over ``MAX_MODULE_LINES`` lines and
no function or method over ``MAX_FUNCTION_LINES`` (decorators, signature and docstring included),
so that a rule's logic, a loader or a route is read in one sitting. Cyclomatic complexity (at
most 25) is ruff's ``C901`` (pyproject.toml), checked with the rest of the lint."""

from __future__ import annotations

import ast
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PACKAGES = ("geomcheck", "api")
MAX_MODULE_LINES = 600  # [lines]
MAX_FUNCTION_LINES = 60  # [lines]


def function_lengths(source: str) -> dict[str, int]:
    """Each function's and method's length [lines] in ``source``, by qualified name (nested
    ones too: ``Class.method``, ``outer.<locals>.inner``)."""
    lengths: dict[str, int] = {}

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                name = prefix + child.name
                first = min([child.lineno, *(d.lineno for d in child.decorator_list)])
                assert child.end_lineno is not None
                lengths[name] = child.end_lineno - first + 1
                visit(child, name + ".<locals>.")
            elif isinstance(child, ast.ClassDef):
                visit(child, prefix + child.name + ".")
            else:
                visit(child, prefix)

    visit(ast.parse(source), "")
    return lengths


def sources() -> list[Path]:
    return sorted(p for package in PACKAGES for p in (REPO / package).rglob("*.py"))


def test_the_measure_counts_methods_nested_functions_and_decorators() -> None:
    source = "\n".join(
        [
            "class A:",
            "    @property",
            "    def m(self):",
            "        def inner():",
            "            return 1",
            "        return inner()",
            "def f():",
            "    if True:",
            "        async def g():",
            "            pass",
        ]
    )
    assert function_lengths(source) == {"A.m": 5, "A.m.<locals>.inner": 2, "f": 4, "f.<locals>.g": 2}


def test_no_module_is_longer_than_the_limit() -> None:
    long = {str(p.relative_to(REPO)): n for p in sources() if (n := len(p.read_text().splitlines())) > MAX_MODULE_LINES}
    assert len(sources()) > 300
    assert long == {}


def test_no_function_is_longer_than_the_limit() -> None:
    long = {
        f"{p.relative_to(REPO)}:{name}": n
        for p in sources()
        for name, n in function_lengths(p.read_text()).items()
        if n > MAX_FUNCTION_LINES
    }
    assert long == {}
