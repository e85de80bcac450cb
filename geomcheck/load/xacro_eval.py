"""A guarded evaluator for xacro expressions of uploaded (confined) descriptions.

xacro evaluates ``${...}`` and ``$(eval ...)`` with Python's ``eval``. For uploads the
expression is checked and rewritten before it runs: no ``__`` anywhere, no attribute that
starts with ``_`` or reaches frames, code or ``str.format`` (the classic sandbox escapes), no
builtins, and the arithmetic that can exhaust memory or time (``**``, ``*``, ``<<``,
``range``) is bounded. Violations raise :class:`SandboxViolation` / :class:`LimitExceeded`.
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable, Mapping
from typing import Any

from geomcheck.errors import LimitExceeded, SandboxViolation

GUARD_NAME = "__geomcheck_binop__"
MAX_INT_BITS = 100_000  # integers beyond this many bits are refused [bits]
MAX_RANGE = 1_000_000  # longest range() an expression may build [items]

_DENIED_ATTRIBUTES = frozenset(
    {
        "format",
        "format_map",
        "mro",
        "gi_frame",
        "gi_code",
        "gi_yieldfrom",
        "cr_frame",
        "cr_code",
        "ag_frame",
        "ag_code",
        "f_globals",
        "f_locals",
        "f_builtins",
        "f_back",
        "f_code",
        "tb_frame",
        "tb_next",
        "func_globals",
        "ljust",
        "rjust",
        "center",
        "zfill",
        "expandtabs",
    }
)
# Builtins xacro exposes that let an expression build classes or inspect objects.
DENIED_SYMBOLS = frozenset({"type", "vars", "issubclass", "hash"})


def _bits(value: int) -> int:
    return abs(value).bit_length()


def _sized(value: Any) -> bool:
    return isinstance(value, str | bytes | list | tuple)


def guarded_binop(op: str, left: Any, right: Any, max_bytes: int) -> Any:
    """``left <op> right`` after checking that the result stays small."""
    if op == "pow":
        exact = isinstance(left, int) and isinstance(right, int) and right > 0 and abs(left) > 1
        if exact and right * math.log2(abs(left)) > MAX_INT_BITS:
            raise LimitExceeded(f"xacro expression {left}**{right} is too large")
        return left**right
    if op == "mul":
        for seq, count in ((left, right), (right, left)):
            if _sized(seq) and isinstance(count, int) and len(seq) * count > max_bytes:
                raise LimitExceeded(f"xacro expression builds a sequence of {len(seq) * count} items")
        if isinstance(left, int) and isinstance(right, int) and _bits(left) + _bits(right) > MAX_INT_BITS:
            raise LimitExceeded("xacro expression builds a too large integer")
        return left * right
    if isinstance(right, int) and right > MAX_INT_BITS:
        raise LimitExceeded(f"xacro expression shifts by {right} bits")
    return left << right


def bounded_range(*args: int) -> range:
    """``range(*args)`` refused beyond :data:`MAX_RANGE` items."""
    result = range(*args)
    if len(result) > MAX_RANGE:
        raise LimitExceeded(f"xacro expression builds a range of {len(result)} items")
    return result


_BINOPS: Mapping[type[ast.operator], str] = {ast.Pow: "pow", ast.Mult: "mul", ast.LShift: "lshift"}


class _Guard(ast.NodeTransformer):
    def visit_Attribute(self, node: ast.Attribute) -> ast.AST:
        if node.attr.startswith("_") or node.attr in _DENIED_ATTRIBUTES:
            raise SandboxViolation(f"xacro expression may not use attribute .{node.attr} in uploaded descriptions")
        return self.generic_visit(node)

    def visit_BinOp(self, node: ast.BinOp) -> ast.AST:
        self.generic_visit(node)
        op = _BINOPS.get(type(node.op))
        if op is None:
            return node
        call = ast.Call(
            func=ast.Name(id=GUARD_NAME, ctx=ast.Load()),
            args=[ast.Constant(op), node.left, node.right],
            keywords=[],
        )
        return ast.copy_location(call, node)


def compile_guarded(expr: str) -> Any:
    """Code object of ``expr`` (an eval expression) checked and rewritten for confined use."""
    text = expr.strip()
    if "__" in text:
        raise SandboxViolation(f"xacro expression may not contain '__' in uploaded descriptions: {text[:80]!r}")
    tree = ast.parse(text, "<expression>", "eval")
    tree = ast.fix_missing_locations(_Guard().visit(tree))
    return compile(tree, "<expression>", "eval")


def make_guard(max_bytes: int) -> Callable[[str, Any, Any], Any]:
    """The helper the rewritten expressions call for ``**``, ``*`` and ``<<``."""

    def guard(op: str, left: Any, right: Any) -> Any:
        return guarded_binop(op, left, right, max_bytes)

    return guard
