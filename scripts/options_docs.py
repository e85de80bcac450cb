"""The options tables of the docs, generated from the options' declaration.

``docs/ci.md`` (configuration keys, with their flags, defaults and request names) and
``docs/api.md`` (request options) hold tables written from
:data:`geomcheck.option_spec.OPTIONS` between marker comments
(``<!-- options:NAME begin -->`` ... ``<!-- options:NAME end -->``); the rest of each file
is left alone. ``tests/test_options_spec.py`` fails when the committed tables differ.

    python scripts/options_docs.py           # rewrite the tables
    python scripts/options_docs.py --check   # exit 1 when a table is out of date
"""

from __future__ import annotations

import argparse
import inspect
import re
import sys
from collections.abc import Callable
from pathlib import Path

from geomcheck.option_spec import OPTIONS, Option

REPO = Path(__file__).resolve().parents[1]
CI_DOC = REPO / "docs" / "ci.md"
API_DOC = REPO / "docs" / "api.md"


def _code(text: str) -> str:
    return f"`{text}`"


def _either(values: tuple[str, ...]) -> str:
    shown = [_code(v) for v in values]
    return shown[0] if len(shown) == 1 else f"{', '.join(shown[:-1])} or {shown[-1]}"


def type_text(option: Option) -> str:
    """The type column: what a value is in the configuration file."""
    if option.type_text:
        return option.type_text
    if option.kind == "int":
        bound = f"≥ {option.minimum}" if option.maximum is None else f"{option.minimum} … {option.maximum}"
        return f"integer {bound}"
    if option.kind == "choice":
        return _either(option.choice_values())
    if option.kind == "pairs":
        subject = "joint" if option.values == "number" else "name"
        return f"table {subject} → {option.values if option.values != 'text' else 'value'}"
    return {
        "bool": "bool",
        "text": "string",
        "file": "file",
        "path": "file",
        "folders": "list of folders",
        "selectors": "list of selectors",
    }[option.kind]


def flag_text(option: Option) -> str:
    """The flag column: the flag as typed, where else it applies, how it meets the file."""
    if option.flag is None:
        return ""
    if option.kind == "bool":
        flag = f"`{option.flag}`/`--no-{option.flag.lstrip('-')}`"
    elif option.repeatable and option.metavar and option.kind != "selectors":
        flag = _code(f"{option.flag} {option.metavar}")
    else:
        flag = _code(option.flag)
    notes = [n for n in (option.flag_note, "also `matrix`" if option.matrix else "") if n]
    return flag + (f" ({'; '.join(notes)})" if notes else "")


def _meaning(option: Option) -> str:
    return option.help + (f" [{option.unit}]" if option.unit else "")


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def config_table() -> str:
    """Every configuration key: type, default, flag, request name and meaning."""
    rows = ["| key | type | default | flag | API | meaning |", "| --- | --- | --- | --- | --- | --- |"]
    for o in OPTIONS:
        default = _code(o.default_text()) if o.default_text() else ""
        api = _code(o.name) if o.api else ""
        cells = (_code(o.key), type_text(o), default, flag_text(o), api, _meaning(o))
        rows.append("| " + " | ".join(_cell(c) for c in cells) + " |")
    return "\n".join(rows) + "\n"


def api_table() -> str:
    """The request options and the request's own parameters of ``POST /v1/checks``, in the
    order the endpoint declares them."""
    from api.checks.options import API_OPTIONS
    from api.routers.checks import REQUEST_ONLY, create_check

    parameters = inspect.signature(create_check).parameters
    rows = ["| name | value |", "| --- | --- |"]
    for name in REQUEST_ONLY:
        rows.append(f"| {_code(name)} | {_cell(parameters[name].default.description)} |")
    for o in API_OPTIONS:
        rows.append(f"| {_code(o.name)} | {_cell(o.description() + (f'; {o.api_note}' if o.api_note else ''))} |")
    return "\n".join(rows) + "\n"


TABLES: dict[str, tuple[Path, Callable[[], str]]] = {"config": (CI_DOC, config_table), "api": (API_DOC, api_table)}


def updated(text: str, name: str, table: str) -> str:
    """``text`` with the block between the ``name`` markers replaced by ``table``."""
    begin, end = f"<!-- options:{name} begin -->", f"<!-- options:{name} end -->"
    pattern = re.compile(re.escape(begin) + r"\n.*?" + re.escape(end), re.S)
    if not pattern.search(text):
        raise SystemExit(f"options_docs: no {begin} ... {end} block")
    return pattern.sub(lambda _: f"{begin}\n{table}{end}", text, count=1)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", action="store_true", help="exit 1 when a table is out of date; write nothing")
    ns = parser.parse_args(argv)
    stale = []
    for name, (path, make) in TABLES.items():
        text = path.read_text(encoding="utf-8")
        new = updated(text, name, make())
        if new != text:
            stale.append(path.relative_to(REPO).as_posix())
            if not ns.check:
                path.write_text(new, encoding="utf-8")
    if stale:
        sys.stdout.write(f"{'out of date' if ns.check else 'updated'}: {', '.join(stale)}\n")
    return 1 if stale and ns.check else 0


if __name__ == "__main__":
    sys.exit(main())
