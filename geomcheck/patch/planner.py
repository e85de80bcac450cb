"""One finding's fix planned: its :class:`SuggestedFix` turned into edits of the source files.

The element a finding points at is found in its source file by line and tag. In xacro
sources a value written literally is changed in place, and so is an expression written in
the attribute (``${a - b/2}``: the text at that place); a value that is a bare property
(``${name}``) is changed at the property's definition when nothing else uses the property,
and otherwise the fix is refused naming both places. Every fix together, and the elements
written once for several links, are :mod:`geomcheck.patch.plan`'s.
"""

from __future__ import annotations

import functools
import os
import re
from collections import defaultdict
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from xml.sax.saxutils import escape

from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import InputError
from geomcheck.fixes.model import (
    Change,
    Edit,
    ModerniseXacro,
    PlannedFix,
    Refused,
    RemoveAttribute,
    RenameAttribute,
    RenameElement,
    ReplaceElement,
    SetAttribute,
    SetText,
    SuggestedFix,
    place,
)
from geomcheck.load import LoadedDescription
from geomcheck.patch.modernise import modernising_edits
from geomcheck.patch.plan_formats import adapt, as_written, refusal
from geomcheck.patch.xacro_values import REFERENCE, XacroSources, macro_parameter, same_number, tokens
from geomcheck.patch.xmltext import Attribute, Element, SourceText

COMMENT = re.compile(r"<!--.*?-->", re.DOTALL)
BLOCK_TAGS = ("insert_block", "xacro:insert_block", "xacro:call")
INDENT_STEP = "  "


def _attribute_text(value: str) -> str:
    return escape(value, {'"': "&quot;"})


@dataclass
class _PropertyToken:
    """A component written as ``${name}``: changed at the definition if nothing else uses it."""

    name: str
    value: str
    file: str
    start: int
    end: int
    element: Element


class Planner:
    """Plans fixes against one loaded description's sources."""

    def __init__(self, loaded: LoadedDescription) -> None:
        self.loaded = loaded
        self.sources: dict[str, str] = dict(loaded.document.sources)  # and other files fixes edit (an SRDF)
        if loaded.format != "urdf":
            self.sources.update(as_written(loaded))
        self._texts: dict[str, SourceText] = {}
        self._expanded: SourceText | None = None
        self.xacro = XacroSources(_LazyTexts(self))

    def text(self, file: str) -> SourceText:
        if file not in self._texts:
            self._texts[file] = SourceText(self.sources[file])
        return self._texts[file]

    def readable(self, file: str) -> bool:
        """Whether ``file`` (display path) is a source, or a file of the bundle read now (an SRDF)."""
        if file not in self.sources:
            bundle = self.loaded.bundle
            try:
                path = bundle.check_access(Path(os.path.normpath(bundle.display_root / file)))
                self.sources[file] = path.read_bytes().decode("utf-8", errors="replace")
            except (InputError, OSError):
                return False
        return True

    def expanded(self) -> SourceText:
        if self._expanded is None:
            self._expanded = SourceText(self.loaded.document.text)
        return self._expanded

    # one finding -----------------------------------------------------------------------

    def plan_one(self, d: Diagnostic, fix: SuggestedFix) -> PlannedFix:
        planned = PlannedFix(d.code, d.subject, d.fingerprint, fix)
        modernise = [c for c in fix.changes if isinstance(c, ModerniseXacro)]
        if modernise:
            return self.plan_modernise(planned, modernise[0].file)
        if (blocked := refusal(self.loaded, d, fix)) is not None:
            return planned.refused(blocked.reason, *blocked.locations)
        loc = d.location
        if loc is None or loc.line is None or not self.readable(loc.file):
            return planned.refused("the element's source line is unknown")
        if "\ufffd" in self.sources[loc.file]:
            return planned.refused("the file is not valid UTF-8", loc.file)
        element = self.text(loc.file).at_line(loc.line, fix.element)
        if element is None:
            return planned.refused(
                f"no <{fix.element}> element at {place(loc.file, loc.line)}", place(loc.file, loc.line)
            )
        expanded_line = loc.expanded_line

        def expanded() -> Element | None:  # scanned only when a value is not written literally
            if expanded_line is None or not self.loaded.document.is_xacro:
                return None
            return self.expanded().at_line(expanded_line, fix.element)

        try:
            changes = fix.changes if fix.syntax == "urdf" else adapt(self.loaded, self.text, d, fix, loc.file, element)
            edits = self.edits(loc.file, element, expanded, changes)
        except Refused as refused:
            return planned.refused(refused.reason, *refused.locations)
        return PlannedFix(d.code, d.subject, d.fingerprint, fix, tuple(edits))

    def plan_modernise(self, planned: PlannedFix, file: str) -> PlannedFix:
        """GC103's fix: the whole file written in today's xacro syntax."""
        if not self.readable(file):
            return planned.refused(f"{file} cannot be read", file)
        if "\ufffd" in self.sources[file]:
            return planned.refused("the file is not valid UTF-8", file)
        edits = modernising_edits(file, self.sources[file], self.sources)
        if not edits:
            return planned.refused(f"nothing to rewrite in {file}", file)
        return replace(planned, edits=tuple(edits))

    def edits(
        self, file: str, element: Element, expanded: Callable[[], Element | None], changes: Sequence[Change]
    ) -> list[Edit]:
        """The edits of ``changes`` to ``element`` of ``file``; ``expanded`` gives its expanded counterpart."""
        direct: list[Edit] = []
        deferred: list[_PropertyToken] = []
        by_path: dict[tuple[str, ...], list[SetAttribute]] = defaultdict(list)
        for change in changes:
            if isinstance(change, SetAttribute):
                by_path[change.path].append(change)
            elif isinstance(change, RenameAttribute):
                direct.append(self.rename_attribute(file, self.reach(file, element, change.path), change))
            elif isinstance(change, RenameElement):
                direct.extend(self.rename_element(file, self.reach(file, element, change.path), change))
            elif isinstance(change, ReplaceElement):
                target = self.reach(file, element, change.path)
                indent = self.text(file).indentation(target.start)
                # comments inside the replaced element are kept, before what replaces it
                kept = "".join(f"{c}\n{indent}" for c in COMMENT.findall(self.sources[file][target.start : target.end]))
                direct.append(Edit(file, target.start, target.end, kept + change.xml.replace("\n", "\n" + indent)))
            elif isinstance(change, RemoveAttribute):
                direct.extend(self.remove_attribute(file, self.follow(element, change.path), change.attribute))
            elif isinstance(change, SetText):
                continue  # together below: values of one missing element are written in one
            else:  # a format's change the format's planning turns into these (plan_formats.adapt)
                raise Refused(f"{change.describe()}: not written in {file}'s syntax", file)
        for path, settings in by_path.items():
            target = self.reach(file, element, path, create=True)
            if target is None:
                inserted = self.insert_element(file, element, path, settings)
                direct.extend([inserted] if inserted is not None else [])
                continue
            counterpart = functools.partial(lambda p: self.follow(expanded(), p), path)
            for setting in settings:
                direct.extend(self.set_attribute(file, target, counterpart, setting, deferred))
        direct.extend(self.set_texts(file, element, [c for c in changes if isinstance(c, SetText)]))
        direct.extend(self.property_edits(deferred, direct))
        return _joined_insertions(direct)

    # navigation ------------------------------------------------------------------------

    def reach(self, file: str, element: Element, path: tuple[str, ...], create: bool = False) -> Element:
        """The element at ``path`` below ``element``; with ``create``, a missing last step gives ``None``."""
        node = element
        for depth, step in enumerate(path):
            child = _child(node, step)
            if child is None:
                line = place(file, node.first_line)
                if any(c.name in BLOCK_TAGS or c.name.startswith("xacro:") for c in node.children):
                    raise Refused(f"<{step}> of the <{node.name}> at {line} comes from a xacro block or macro", line)
                if create and depth == len(path) - 1 and node.end_name is not None:
                    return None  # type: ignore[return-value]  # the caller inserts it
                raise Refused(f"the <{node.name}> at {line} has no <{step}>", line)
            node = child
        return node

    @staticmethod
    def follow(element: Element | None, path: tuple[str, ...]) -> Element | None:
        node = element
        for step in path:
            if node is None:
                return None
            node = _child(node, step)
        return node

    def remove_attribute(self, file: str, target: Element | None, name: str) -> list[Edit]:
        """The attribute and the white space before it removed, when it is written."""
        attribute = target.attribute(name) if target is not None else None
        if attribute is None:
            return []
        text = self.sources[file]
        start = attribute.start
        while start > 0 and text[start - 1] in " \t\r\n":
            start -= 1
        return [Edit(file, start, attribute.end, "")]

    def set_texts(self, file: str, element: Element, changes: Sequence[SetText]) -> list[Edit]:
        """The text of each element at a change's path set; the missing elements of the paths
        created, those below one missing element together, as the last children of the
        deepest element found (an SDFormat ``<inertia>`` with its six values)."""
        source, text = self.text(file), self.sources[file]
        out: list[Edit] = []
        missing: dict[tuple[int, str], tuple[Element, list[tuple[tuple[str, ...], str]]]] = {}
        for change in changes:
            node, depth = element, 0
            while depth < len(change.path) and (child := _child(node, change.path[depth])) is not None:
                node, depth = child, depth + 1
            if depth == len(change.path):
                out.extend(self.set_text(file, node, change))
                continue
            if node.end_name is None:
                line = place(file, node.first_line)
                step = change.path[depth]
                raise Refused(f"the <{node.name}> at {line} is empty (<{node.name}/>): it has no <{step}>", line)
            missing.setdefault((node.start, change.path[depth]), (node, []))[1].append(
                (change.path[depth:], change.text)
            )
        for node, entries in missing.values():
            xml = _nested(entries)
            assert node.end_name is not None
            end_tag = text.rfind("<", 0, node.end_name[0])
            line_start = text.rfind("\n", 0, end_tag) + 1
            indent = (
                source.indentation(node.children[-1].start)
                if node.children
                else source.indentation(node.start) + INDENT_STEP
            )
            if text[line_start:end_tag].strip():
                out.append(Edit(file, end_tag, end_tag, xml))
            else:
                out.append(Edit(file, line_start, line_start, f"{indent}{xml}\n"))
        return out

    def set_text(self, file: str, node: Element, change: SetText) -> list[Edit]:
        """The text of ``node``, the element at ``change.path``, set to ``change.text``."""
        text = self.sources[file]
        here = place(file, node.first_line)
        if node.children:
            raise Refused(f"the <{node.name}> at {here} holds elements, not a value", here)
        if node.end_name is None:  # <pose/>: written out with its text
            slash = text.rfind("/", node.start, node.open_end)
            return [Edit(file, slash, node.open_end, f">{_attribute_text(change.text)}</{node.name}>")]
        start, end = node.open_end, text.rfind("<", 0, node.end_name[0])
        content = text[start:end]
        written = content.split()
        if change.keep_leading:
            if len(written) < change.keep_leading:
                raise Refused(f"the <{node.name}> at {here} has fewer than {change.keep_leading} values", here)
            wanted = [*written[: change.keep_leading], *change.text.split()]
        else:
            wanted = change.text.split()
        if written == wanted or _all_same(written, wanted):
            return []
        lead = content[: len(content) - len(content.lstrip())]
        trail = content[len(content.rstrip()) :]
        return [Edit(file, start, end, lead + _attribute_text(" ".join(wanted)) + trail)]

    # changes ---------------------------------------------------------------------------

    def insert_element(
        self, file: str, element: Element, path: tuple[str, ...], settings: list[SetAttribute]
    ) -> Edit | None:
        """The missing element at ``path`` with the attributes that differ from URDF's defaults."""
        parent = self.reach(file, element, path[:-1])
        source = self.text(file)
        indent = (
            source.indentation(parent.children[0].start)
            if parent.children
            else source.indentation(parent.start) + INDENT_STEP
        )
        written = [s for s in settings if not _is_default(path[-1], s)]
        if not written:
            return None
        attributes = " ".join(f'{s.attribute}="{_attribute_text(s.value)}"' for s in written)
        return Edit(file, parent.open_end, parent.open_end, f"\n{indent}<{path[-1]} {attributes}/>")

    def rename_attribute(self, file: str, target: Element, change: RenameAttribute) -> Edit:
        attribute = target.attribute(change.old)
        line = place(file, target.first_line)
        if attribute is None:
            raise Refused(f"the <{target.name}> at {line} has no attribute {change.old}", line)
        if target.attribute(change.new) is not None:
            raise Refused(f"the <{target.name}> at {line} has both {change.old} and {change.new}", line)
        return Edit(file, attribute.start, attribute.start + len(change.old), change.new)

    def rename_element(self, file: str, target: Element, change: RenameElement) -> list[Edit]:
        out = [Edit(file, target.name_start, target.name_start + len(target.name), change.new)]
        if target.end_name is not None:
            out.append(Edit(file, target.end_name[0], target.end_name[1], change.new))
        return out

    def set_attribute(
        self,
        file: str,
        target: Element,
        counterpart: Callable[[], Element | None],
        setting: SetAttribute,
        deferred: list[_PropertyToken],
    ) -> list[Edit]:
        attribute = target.attribute(setting.attribute)
        if attribute is None:
            if _is_default(target.name, setting):
                return []
            end = target.attributes[-1].end if target.attributes else target.name_start + len(target.name)
            return [Edit(file, end, end, f' {setting.attribute}="{_attribute_text(setting.value)}"')]
        written = attribute.value
        if "$" not in written:
            if written.split() == setting.value.split() or _all_same(written.split(), setting.value.split()):
                return []
            return [Edit(file, attribute.value_start, attribute.value_end, _attribute_text(setting.value))]
        return self.set_components(file, target, attribute, counterpart, setting, deferred)

    def set_components(
        self,
        file: str,
        target: Element,
        attribute: Attribute,
        counterpart: Callable[[], Element | None],
        setting: SetAttribute,
        deferred: list[_PropertyToken],
    ) -> list[Edit]:
        """Component by component: each changed one where its value is written."""
        line = place(file, self.text(file).line_of(attribute.start))
        spans = tokens(attribute.value)
        wanted = setting.value.split()
        expanded = counterpart()
        evaluated_attribute = expanded.attribute(setting.attribute) if expanded is not None else None
        evaluated = evaluated_attribute.value.split() if evaluated_attribute is not None else []
        if len(spans) != len(wanted) or len(evaluated) != len(wanted):
            raise Refused(
                f'{setting.attribute}="{attribute.value}" at {line} is not written component by component', line
            )
        out = []
        for (lo, hi), old, new in zip(spans, evaluated, wanted, strict=True):
            if same_number(old, new):
                continue
            start, end = attribute.value_start + lo, attribute.value_start + hi
            part = attribute.value[lo:hi]
            if "$(" in part:
                raise Refused(
                    f"{part} at {line} comes from a substitution (an argument): set it where it is given", line
                )
            reference = REFERENCE.match(part)
            if reference is None:  # a literal, or an expression written here: its text is this place's
                out.append(Edit(file, start, end, _attribute_text(new)))
                continue
            name = reference.group(1)
            macro = macro_parameter(target, name)
            if macro is not None:
                where = place(file, macro.first_line)
                raise Refused(f"{part} at {line} is a parameter of the macro at {where}", line, where)
            deferred.append(_PropertyToken(name, new, file, start, end, target))
        return out

    def property_edits(self, deferred: Iterable[_PropertyToken], direct: Sequence[Edit]) -> list[Edit]:
        """Each property a changed component names (``${name}``) changed at its one definition,
        when nothing but ``direct``'s replaced text uses it; :class:`Refused` otherwise."""
        replaced = [(e.file, e.start, e.end) for e in direct]
        return [self.property_edit(token, replaced) for token in deferred]

    def property_edit(self, token: _PropertyToken, replaced: Sequence[tuple[str, int, int]]) -> Edit:
        here = place(token.file, self.text(token.file).line_of(token.start))
        definitions = self.xacro.definitions(token.name)
        if len(definitions) != 1:
            what = "defined in no file of the description" if not definitions else "defined several times"
            places = [place(d.file, d.line) for d in definitions]
            raise Refused(f"property {token.name} used at {here} is {what}", here, *places)
        definition = definitions[0]
        there = place(definition.file, definition.line)
        value = definition.element.attribute("value")
        if value is None or "$" in value.value:
            raise Refused(f"property {token.name} used at {here} is computed at {there}", here, there)
        others = [
            u
            for u in self.xacro.uses(token.name)
            if not (u.file == token.file and u.start <= token.start and token.end <= u.end)
            and not any(f == u.file and s <= u.start and u.end <= e for f, s, e in replaced)
        ]
        if others:
            also = [place(u.file, u.line) for u in others]
            raise Refused(
                f"property {token.name} (defined at {there}) is also used at {', '.join(also)}", here, there, *also
            )
        return Edit(definition.file, value.value_start, value.value_end, _attribute_text(token.value))


# Attributes URDF gives a value when they are absent: a fix leaves them absent when it wants that value.
DEFAULTS = {("origin", "xyz"): "0 0 0", ("origin", "rpy"): "0 0 0"}


def _is_default(tag: str, setting: SetAttribute) -> bool:
    default = DEFAULTS.get((tag, setting.attribute))
    return default is not None and _all_same(default.split(), setting.value.split())


def _nested(entries: Sequence[tuple[tuple[str, ...], str]]) -> str:
    """Elements holding each ``(path, text)``, paths with a first tag in common in one element."""
    groups: dict[str, list[tuple[tuple[str, ...], str]]] = {}
    for path, value in entries:
        groups.setdefault(path[0], []).append((path[1:], value))
    out = []
    for tag, rest in groups.items():
        inner = "".join(_attribute_text(value) for path, value in rest if not path) + _nested(
            [(path, value) for path, value in rest if path]
        )
        out.append(f"<{tag}>{inner}</{tag}>")
    return "".join(out)


def _joined_insertions(edits: list[Edit]) -> list[Edit]:
    """Insertions of one fix at one place made one edit, in the order the fix lists them
    (attributes added to an MJCF geom read ``type size pos quat``, not the reverse)."""
    out: list[Edit] = []
    at: dict[tuple[str, int], int] = {}
    for e in edits:
        key = (e.file, e.start)
        if e.start == e.end and key in at:
            first = out[at[key]]
            out[at[key]] = replace(first, replacement=first.replacement + e.replacement)
            continue
        if e.start == e.end:
            at[key] = len(out)
        out.append(e)
    return out


ANY_CHILD = "*"  # a path step that takes the first child element, whatever its tag


def _child(node: Element, step: str) -> Element | None:
    if step == ANY_CHILD:
        return node.children[0] if node.children else None
    return node.child(step)


def _all_same(written: list[str], wanted: list[str]) -> bool:
    return len(written) == len(wanted) and all(same_number(a, b) for a, b in zip(written, wanted, strict=True))


class _LazyTexts(Mapping[str, SourceText]):
    """Every source of the planner, scanned on first access."""

    def __init__(self, planner: Planner) -> None:
        self.planner = planner

    def __getitem__(self, key: str) -> SourceText:
        return self.planner.text(key)

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self.planner.sources)

    def __len__(self) -> int:
        return len(self.planner.sources)
