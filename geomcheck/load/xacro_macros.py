"""Macro expansion of one xacro run under limits: bare legacy macro calls, the nesting and the
number of macro calls, and the elements, text sizes and sibling work that blocks inserted into
blocks could double without any macro call."""

from __future__ import annotations

import re
import xml.dom.minidom
from collections.abc import Callable
from typing import Any

import xacro

from geomcheck.errors import LimitExceeded
from geomcheck.load.bundle import Bundle
from geomcheck.load.legacy import MACRO_CALL
from geomcheck.load.locations import search_sources
from geomcheck.load.urdf_spec import SPEC
from geomcheck.load.xacro_files import XacroFiles
from geomcheck.thresholds import LoadLimits

# Elements a bare (legacy) macro call may never be mistaken for.
URDF_CORE_TAGS = frozenset({*SPEC, "gazebo", "transmission"})


class XacroMacros(XacroFiles):
    """xacro's macro and evaluation hooks, counting what an expansion costs."""

    def __init__(self, bundle: Bundle, limits: LoadLimits) -> None:
        super().__init__(bundle, limits)
        self.macro_calls = 0
        self.called_macros: set[str] = set()  # names of the macros called (without include namespaces)
        self.evaluated = 0
        self.sibling_work = 0
        self.original_eval_all: Callable[..., None] = xacro.eval_all
        self.original_eval_text: Callable[..., Any] = xacro.eval_text
        self.original_replace_node: Callable[..., None] = xacro.replace_node
        self.original_handle_macro_call: Callable[..., bool] = xacro.handle_macro_call

    def eval_all(self, node: xml.dom.minidom.Node, macros: Any, symbols: Any) -> None:
        """Replacement of ``xacro.eval_all`` counting the elements evaluated: blocks inserted
        into blocks double without a macro call, so only this count bounds them."""
        self.evaluated += 1
        if self.evaluated > self.limits.max_xacro_elements:
            raise LimitExceeded(
                f"xacro evaluates more than {self.limits.max_xacro_elements} elements (max_xacro_elements): "
                "blocks inserted into blocks?"
            )
        self.original_eval_all(node, macros, symbols)

    def eval_text(self, text: str, symbols: Any) -> Any:
        """Replacement of ``xacro.eval_text`` holding each text's value to the expanded-size
        limit: ``value="${p}${p}"`` doubles outside any expression, 40 properties deep 2^40
        characters."""
        value = self.original_eval_text(text, symbols)
        if isinstance(value, str) and len(value) > self.limits.max_expanded_bytes:
            raise LimitExceeded(
                f"a xacro text evaluates to {len(value)} characters, beyond max_expanded_bytes "
                f"({self.limits.max_expanded_bytes})"
            )
        return value

    def replace_node(self, node: xml.dom.minidom.Node, by: Any, content_only: bool = False) -> None:
        """Replacement of ``xacro.replace_node`` counting the siblings minidom passes over
        (each insertion searches the parent's children): a block doubled into one parent
        costs the square of its size."""
        parent = node.parentNode
        if by is not None and parent is not None:
            moved = len(by) if isinstance(by, list) else len(by.childNodes) if content_only else 1
            self.sibling_work += moved * len(parent.childNodes)
            if self.sibling_work > self.limits.max_sibling_work:
                raise LimitExceeded(
                    f"xacro insertions exceed the work limit of {self.limits.max_sibling_work} steps "
                    "(max_sibling_work): a block doubled into one element?"
                )
        self.original_replace_node(node, by, content_only)

    def handle_macro_call(self, node: xml.dom.minidom.Element, macros: Any, symbols: Any) -> bool:
        """Replacement of ``xacro.handle_macro_call``: bare legacy calls, depth and count limits."""
        tag = node.tagName
        if not tag.startswith("xacro:"):
            if not self.bare_macro_call(node, macros, symbols):
                return False
            self.called_macros.add(tag.rsplit(".", 1)[-1])
        elif tag == "xacro:call":
            self.called_macros.add((node.getAttribute("macro") or "").rsplit(".", 1)[-1])
        else:
            self.called_macros.add(tag[6:].rsplit(".", 1)[-1])
            self.macro_calls += 1
            if self.macro_calls > self.limits.max_macro_calls:
                raise LimitExceeded(
                    f"more than {self.limits.max_macro_calls} macro calls (max_macro_calls): exponential expansion?"
                )
            if len(xacro.macrostack or []) >= self.limits.max_macro_depth:
                raise LimitExceeded(
                    f"macro {tag[6:]!r} nests deeper than the limit of {self.limits.max_macro_depth} levels "
                    "(recursive macro?)"
                )
        return self.original_handle_macro_call(node, macros, symbols)

    def bare_macro_call(self, node: xml.dom.minidom.Element, macros: Any, symbols: Any) -> bool:
        """Turn ``<name ...>`` into ``<xacro:name ...>`` when it calls a macro from a legacy file."""
        tag = node.tagName
        if ":" in tag or tag in URDF_CORE_TAGS:
            return False
        stack = xacro.macrostack or []
        defined_in = stack[-1].history[-1][-1] if stack and stack[-1].history else None
        display = self.display(defined_in) if defined_in else self.current_file()
        use = self.legacy.get(display)
        if use is None or not use.found:
            return False
        try:
            xacro.resolve_macro(tag, macros, symbols)
        except (KeyError, TypeError, AttributeError):
            return False
        node.tagName = node.nodeName = f"xacro:{tag}"
        found = search_sources({display: self.sources.get(display, "")}, [re.compile(rf"<{re.escape(tag)}[\s/>]")])
        use.add(MACRO_CALL, found.line if found else None)
        return True


__all__ = ["URDF_CORE_TAGS", "XacroMacros"]
