"""A guarded evaluator for xacro expressions.

xacro evaluates ``${...}`` and ``$(eval ...)`` with Python's ``eval``. Every expression is
rewritten before it runs so that the arithmetic that can exhaust memory or time (``**``,
``*``, ``<<``, ``range``, ``math.factorial``/``comb``/``perm``/``prod``/``lcm``) is bounded
(:func:`compile_budgeted`, trusted descriptions too). For uploads (confined bundles) it is also
checked (:func:`compile_guarded`): no ``__`` anywhere, no attribute that starts with ``_`` or
reaches frames, code or ``str.format`` (the classic sandbox escapes), no builtins. Every
expression of one expansion draws on one work budget: each item a ``range`` holds and each
step of a comprehension or generator expression costs one unit, so nested loops over large
ranges are refused at once instead of running until a time limit. Violations raise
:class:`SandboxViolation` / :class:`LimitExceeded`.
"""

from __future__ import annotations

import ast
import builtins
import functools
import math
import re
import string
from collections.abc import Callable, Iterable, Iterator, Mapping
from typing import Any

from geomcheck.errors import LimitExceeded, SandboxViolation

GUARD_NAME = "__geomcheck_binop__"
MAX_INT_BITS = 100_000  # integers beyond this many bits are refused [bits]
MAX_RANGE = 1_000_000  # longest range() an expression may build [items]
DEFAULT_WORK = (
    1_000_000  # range items and comprehension steps of one expansion (LoadLimits.max_expression_work) [count]
)

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


_PLAIN = (int, float, bool)


def _bits(value: int) -> int:
    return abs(value).bit_length()


def _sized(value: Any) -> bool:
    return isinstance(value, str | bytes | list | tuple)


def _guarded_pow(left: Any, right: Any, max_bytes: int) -> Any:
    exact = isinstance(left, int) and isinstance(right, int) and right > 0 and abs(left) > 1
    if exact and right * math.log2(abs(left)) > MAX_INT_BITS:
        raise LimitExceeded(f"xacro expression {left}**{right} is too large")
    return left**right


def _guarded_mul(left: Any, right: Any, max_bytes: int) -> Any:
    if type(left) in _PLAIN and type(right) in _PLAIN:  # the common case, kept cheap
        if type(left) is int and type(right) is int and _bits(left) + _bits(right) > MAX_INT_BITS:
            raise LimitExceeded("xacro expression builds a too large integer")
        return left * right
    for seq, count in ((left, right), (right, left)):
        weight = 1 if isinstance(seq, str | bytes) else 8  # a list holds a pointer per item [bytes]
        if _sized(seq) and isinstance(count, int) and len(seq) * count * weight > max_bytes:
            raise LimitExceeded(f"xacro expression builds a sequence of {len(seq) * count} items")
    if isinstance(left, int) and isinstance(right, int) and _bits(left) + _bits(right) > MAX_INT_BITS:
        raise LimitExceeded("xacro expression builds a too large integer")
    return left * right


def _guarded_add(left: Any, right: Any, max_bytes: int) -> Any:
    if _sized(left) and _sized(right) and len(left) + len(right) > max_bytes:
        raise LimitExceeded(f"xacro expression builds a sequence of {len(left) + len(right)} items")
    return left + right


def _guarded_mod(left: Any, right: Any, max_bytes: int) -> Any:
    if isinstance(left, str | bytes):
        check_printf(left, right, max_bytes)
    return left % right


def _guarded_lshift(left: Any, right: Any, max_bytes: int) -> Any:
    if isinstance(right, int) and right > MAX_INT_BITS:
        raise LimitExceeded(f"xacro expression shifts by {right} bits")
    return left << right


# the operators the rewritten expressions route through the guard, each with its check
_GUARDED_BINOPS: Mapping[str, Callable[[Any, Any, int], Any]] = {
    "pow": _guarded_pow,
    "mul": _guarded_mul,
    "add": _guarded_add,
    "mod": _guarded_mod,
    "lshift": _guarded_lshift,
}


def guarded_binop(op: str, left: Any, right: Any, max_bytes: int) -> Any:
    """``left <op> right`` after checking that the result stays small (any other ``op`` is ``<<``)."""
    return _GUARDED_BINOPS.get(op, _guarded_lshift)(left, right, max_bytes)


_PRINTF_WIDTH = re.compile(rb"%(?:\([^)]*\))?[-#0 +]*(\*|\d+)?(?:\.(\*|\d+))?")
_SPEC_NUMBER = re.compile(r"\d+")


def _too_wide(width: int, max_bytes: int) -> None:
    if width > max_bytes:
        raise LimitExceeded(f"xacro expression pads a value to {width} characters")


def check_printf(text: str | bytes, args: Any, max_bytes: int) -> None:
    """Refuse ``text % args`` when a ``%`` field's width or precision (written, or ``*`` taken
    from ``args``) exceeds ``max_bytes``: ``'%999999999d' % 1`` allocates a gigabyte in C."""
    raw = text.encode("utf-8", "replace") if isinstance(text, str) else text
    values = args if isinstance(args, tuple) else (args,)
    for match in _PRINTF_WIDTH.finditer(raw):
        for group in match.groups():
            if group is None:
                continue
            if group == b"*":
                _too_wide(max((abs(v) for v in values if type(v) is int), default=0), max_bytes)
            else:
                _too_wide(int(group), max_bytes)


def check_format_spec(spec: Any, max_bytes: int) -> Any:
    """``spec`` (a ``format()``/f-string spec) after refusing a width or precision beyond ``max_bytes``."""
    if isinstance(spec, str):
        for number in _SPEC_NUMBER.findall(spec):
            _too_wide(int(number), max_bytes)
    return spec


def check_format_string(text: str, max_bytes: int) -> None:
    """Refuse a ``str.format`` template whose fields pad beyond ``max_bytes``."""
    try:
        fields = list(string.Formatter().parse(text))
    except ValueError:
        return  # str.format raises the same error itself
    for _, _, spec, _ in fields:
        check_format_spec(spec, max_bytes)


_PADDING = frozenset({"center", "ljust", "rjust", "zfill"})


def check_text_method(name: str, text: str | bytes, args: tuple[Any, ...], max_bytes: int) -> None:
    """Refuse a ``str``/``bytes`` method call whose result would exceed ``max_bytes``."""
    if name in _PADDING and args and type(args[0]) is int:
        _too_wide(args[0], max_bytes)
    elif name == "expandtabs":
        size = args[0] if args and type(args[0]) is int else 8
        tabs = text.count("\t") if isinstance(text, str) else text.count(b"\t")
        _too_wide(tabs * max(size, 0) + len(text), max_bytes)
    elif name == "replace" and len(args) >= 2 and _sized(args[0]) and _sized(args[1]):
        old, new = args[0], args[1]
        if len(new) > len(old):
            count = text.count(old) if len(old) else len(text) + 1  # type: ignore[arg-type]
            _too_wide(len(text) + count * (len(new) - len(old)), max_bytes)
    elif name in ("format", "format_map") and isinstance(text, str):
        check_format_string(text, max_bytes)


def bounded_range(*args: int) -> range:
    """``range(*args)`` refused beyond :data:`MAX_RANGE` items."""
    result = range(*args)
    if len(result) > MAX_RANGE:
        raise LimitExceeded(f"xacro expression builds a range of {len(result)} items")
    return result


_BINOPS: Mapping[type[ast.operator], str] = {
    ast.Pow: "pow",
    ast.Mult: "mul",
    ast.LShift: "lshift",
    ast.Add: "add",
    ast.Mod: "mod",
}


def _int_arg(value: Any) -> int:
    return abs(value) if isinstance(value, int) else 0


def _check_factorial(args: tuple[Any, ...]) -> None:
    n = _int_arg(args[0]) if args else 0
    if n > 1 and n * math.log2(n) > MAX_INT_BITS:
        raise LimitExceeded(f"xacro expression factorial({n}) is too large")


def _check_choose(args: tuple[Any, ...]) -> None:
    n = _int_arg(args[0]) if args else 0
    k = _int_arg(args[1]) if len(args) > 1 else n
    if n > 1 and min(k, max(n - k, 0)) * math.log2(n) > MAX_INT_BITS:
        raise LimitExceeded(f"xacro expression comb/perm({n}, {k}) is too large")


def _check_lcm(args: tuple[Any, ...]) -> None:
    if sum(_int_arg(a).bit_length() for a in args) > MAX_INT_BITS:
        raise LimitExceeded("xacro expression lcm(...) builds a too large integer")


_CALL_CHECKS: Mapping[Callable[..., Any], Callable[[tuple[Any, ...]], None]] = {
    math.factorial: _check_factorial,
    math.comb: _check_choose,
    math.perm: _check_choose,
    math.lcm: _check_lcm,
}


class WorkBudget:
    """The guard the rewritten expressions of one expansion call: ``**``, ``*`` and ``<<``
    checked by :func:`guarded_binop`; calls, ranges and comprehension steps charged to a
    budget of ``max_work`` units."""

    def __init__(self, max_bytes: int, max_work: int = DEFAULT_WORK) -> None:
        self.max_bytes = max_bytes
        self.max_work = max_work
        self.spent = 0

    def charge(self, units: int) -> None:
        self.spent += units
        if self.spent > self.max_work:
            raise LimitExceeded(
                f"xacro expressions exceed the work budget of {self.max_work} steps (max_expression_work): "
                "loops over large ranges?"
            )

    def iterate(self, iterable: Iterable[Any]) -> Iterator[Any]:
        for item in iterable:
            self.charge(1)
            yield item

    def call(self, function: Any, args: tuple[Any, ...], kwargs: dict[str, Any]) -> Any:
        """``function(*args, **kwargs)`` with what it may build bounded before it runs (C code
        such as ``'a'.center(10**9)`` or ``max(range(10**18))`` cannot be interrupted), and
        every sized result held to ``max_bytes`` after."""
        try:
            check = _CALL_CHECKS.get(function)
        except TypeError:  # an unhashable callable is none of the checked functions
            check = None
        if check is not None:
            check(args)
        elif function is math.prod:
            return self.product(args, kwargs)
        elif function is builtins.pow and len(args) == 2 and not kwargs:
            return guarded_binop("pow", args[0], args[1], self.max_bytes)
        else:
            args = self.checked_arguments(function, args)
        return self.checked_result(function(*args, **kwargs))

    def checked_arguments(self, function: Any, args: tuple[Any, ...]) -> tuple[Any, ...]:
        """The arguments of ``function`` (a builtin or a text method), refused when they ask
        for a result beyond ``max_bytes``."""
        if function is builtins.format and len(args) == 2:
            check_format_spec(args[1], self.max_bytes)
        elif isinstance(function, type) and issubclass(function, bytes | bytearray) and args and type(args[0]) is int:
            _too_wide(args[0], self.max_bytes)
        else:
            owner = getattr(function, "__self__", None)
            name = getattr(function, "__name__", "")
            if isinstance(owner, str | bytes):
                return self.text_arguments(name, owner, args)
            if getattr(function, "__objclass__", None) in (str, bytes) and args and isinstance(args[0], str | bytes):
                return (args[0], *self.text_arguments(name, args[0], args[1:]))
        return args

    def checked_result(self, result: Any) -> Any:
        """``result`` after charging a range to the budget and refusing a sized value beyond ``max_bytes``."""
        if isinstance(result, range):  # range itself, or a wrapper of it (xacro's deprecated top-level range)
            if len(result) > MAX_RANGE:
                raise LimitExceeded(f"xacro expression builds a range of {len(result)} items")
            self.charge(len(result))
        elif _sized(result) and len(result) > self.max_bytes:
            raise LimitExceeded(f"xacro expression builds a value of {len(result)} items")
        return result

    def text_arguments(self, name: str, text: str | bytes, args: tuple[Any, ...]) -> tuple[Any, ...]:
        """The arguments of method ``name`` of ``text``, checked; ``join``'s iterable taken as
        a list (charged to the budget) so the joined length is known before joining."""
        if name == "join" and args:
            items = list(self.iterate(args[0]))
            total = len(text) * max(len(items) - 1, 0) + sum(len(i) for i in items if _sized(i))
            if total > self.max_bytes:
                raise LimitExceeded(f"xacro expression joins {total} characters")
            return (items, *args[1:])
        check_text_method(name, text, args, self.max_bytes)
        return args

    def product(self, args: tuple[Any, ...], kwargs: dict[str, Any]) -> Any:
        total = kwargs.get("start", 1)
        for item in self.iterate(args[0] if args else ()):
            total = guarded_binop("mul", total, item, self.max_bytes)
        return total

    def __call__(self, op: str, left: Any, right: Any, extra: Any = None) -> Any:
        if op == "iter":
            return self.iterate(left)
        if op == "call":
            return self.call(left, right, extra)
        if op == "spec":
            return check_format_spec(left, self.max_bytes)
        return guarded_binop(op, left, right, self.max_bytes)


class _Budget(ast.NodeTransformer):
    """Rewrites the costly parts of an expression (``**``, ``*``, ``<<``, calls, loops) into
    calls of the work budget."""

    def visit_comprehension(self, node: ast.comprehension) -> ast.AST:
        self.generic_visit(node)
        node.iter = ast.copy_location(_guard_call("iter", node.iter, ast.Constant(None)), node.iter)
        return node

    def visit_Call(self, node: ast.Call) -> ast.AST:
        self.generic_visit(node)
        args = ast.Tuple(elts=list(node.args), ctx=ast.Load())
        keys: list[ast.expr | None] = [ast.Constant(k.arg) if k.arg is not None else None for k in node.keywords]
        kwargs = ast.Dict(keys=keys, values=[k.value for k in node.keywords])
        call = _guard_call("call", node.func, args, kwargs)
        return ast.copy_location(call, node)

    def visit_FormattedValue(self, node: ast.FormattedValue) -> ast.AST:
        """``f"{x:{w}}"``: the spec checked (a width of 10**9 pads in C) before it is applied."""
        self.generic_visit(node)
        if node.format_spec is not None:
            checked = ast.FormattedValue(
                value=_guard_call("spec", node.format_spec, ast.Constant(None)), conversion=-1, format_spec=None
            )
            node.format_spec = ast.copy_location(ast.JoinedStr(values=[checked]), node.format_spec)
        return node

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


class _Guard(_Budget):
    """:class:`_Budget` plus the sandbox: no private attribute, none that reaches frames or code."""

    def visit_Attribute(self, node: ast.Attribute) -> ast.AST:
        if node.attr.startswith("_") or node.attr in _DENIED_ATTRIBUTES:
            raise SandboxViolation(f"xacro expression may not use attribute .{node.attr} in uploaded descriptions")
        return self.generic_visit(node)


def _guard_call(op: str, *args: ast.expr) -> ast.Call:
    return ast.Call(func=ast.Name(id=GUARD_NAME, ctx=ast.Load()), args=[ast.Constant(op), *args], keywords=[])


COMPILED_EXPRESSIONS = 4096  # distinct expression texts whose code objects are kept [count]


@functools.lru_cache(maxsize=COMPILED_EXPRESSIONS)
def compile_guarded(expr: str) -> Any:
    """Code object of ``expr`` (an eval expression) checked and rewritten for confined use;
    compiled once per text (a macro's expressions recur with every call; a refused text is
    refused every time)."""
    text = expr.strip()
    if "__" in text:
        raise SandboxViolation(f"xacro expression may not contain '__' in uploaded descriptions: {text[:80]!r}")
    tree = ast.parse(text, "<expression>", "eval")
    tree = ast.fix_missing_locations(_Guard().visit(tree))
    return compile(tree, "<expression>", "eval")


@functools.lru_cache(maxsize=COMPILED_EXPRESSIONS)
def compile_budgeted(expr: str) -> Any:
    """Code object of ``expr`` (an eval expression) with its arithmetic, calls and loops
    drawing on the work budget, and no other restriction: what trusted descriptions run (a
    ``${10**10**10}`` ends with :class:`LimitExceeded` instead of running for hours);
    compiled once per text."""
    tree = ast.parse(expr.strip(), "<expression>", "eval")
    tree = ast.fix_missing_locations(_Budget().visit(tree))
    return compile(tree, "<expression>", "eval")


def make_guard(max_bytes: int, max_work: int = DEFAULT_WORK) -> WorkBudget:
    """The helper the rewritten expressions of one expansion call (one budget per expansion)."""
    return WorkBudget(max_bytes, max_work)
