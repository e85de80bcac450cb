"""Read the bundle's root file, recognise its format and load it: the one entry point of loading."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import TYPE_CHECKING

from geomcheck.diagnostics import Diagnostic
from geomcheck.errors import InputError
from geomcheck.load.bundle import Bundle
from geomcheck.load.description import ExpandedDocument, LoadedDescription
from geomcheck.load.formats import InputFormat, detect, register
from geomcheck.load.legacy import uses_xacro
from geomcheck.load.locations import LocationResolver
from geomcheck.load.urdf import parse_urdf
from geomcheck.load.xacro_cache import cached_expand
from geomcheck.load.xmlsafe import (
    as_tinyxml_reads,
    decode_text,
    parse_bytes,
    read_file_bytes,
    unsupported_version,
)
from geomcheck.model import SourceLocation
from geomcheck.rules.structure import NON_CONFORMING_XML, XML_VERSION
from geomcheck.thresholds import LoadLimits

if TYPE_CHECKING:
    from lxml import etree


def load(bundle: Bundle, args: Mapping[str, str], limits: LoadLimits) -> LoadedDescription:
    """The description of ``bundle``: document, robot model and load-time findings.

    The root file is read with the hardened parser and handed to the loader of its format
    (:func:`geomcheck.load.formats.detect`: by root element, then suffix). Raises
    :class:`geomcheck.errors.InputError` (GC101 malformed XML, GC102 xacro failure, missing
    files, a model MuJoCo's compiler rejects), :class:`LimitExceeded` and
    :class:`SandboxViolation`.
    """
    path = bundle.check_access(bundle.root_file)
    display = bundle.display(bundle.root_file)
    data = read_file_bytes(path, display, limits)
    issues: tuple[str, ...] = ()
    try:
        root = parse_bytes(data, display, limits)
    except InputError as err:
        if "Namespace prefix xacro" in str(err):
            root = None  # xacro tags without the namespace: the expansion declares it in memory
        else:
            data, root, issues = read_as_tinyxml(data, display, limits, err)
    loaded = detect(root, path.name).load(bundle, args, limits, data, root)
    said = [d for d in (_version_said(data, display), _conformance_said(loaded, issues, display)) if d is not None]
    return replace(loaded, diagnostics=(*said, *loaded.diagnostics)) if said else loaded


def _version_said(data: bytes, display: str) -> Diagnostic | None:
    version = unsupported_version(data)
    if version is None:
        return None
    return XML_VERSION.diagnose(
        f'{display} declares XML version "{version}", which XML does not have: ROS, Gazebo, MuJoCo and PyBullet '
        "read it as XML 1.0, libxml2 and the readers built on it (lxml: yourdfpy, urdfpy) refuse the file",
        help='Declare <?xml version="1.0"?>: every reader reads it.',
        location=SourceLocation(display, 1, 1),
        data={"file": display, "version": version},
    )


_ISSUE_TEXT = {
    "late-declaration": "its <?xml ...?> declaration stands after blank lines or a comment",
    "trailing-nul": "NUL bytes follow its last element",
}
_ISSUE_FIX = {
    "late-declaration": "put the <?xml ...?> declaration on the first line, or delete it",
    "trailing-nul": "delete the NUL bytes at the end of the file",
}


def _conformance_said(loaded: LoadedDescription, issues: tuple[str, ...], display: str) -> Diagnostic | None:
    """GC132 for a URDF read as TinyXML2 reads it; an SDFormat or MJCF file's only readers read it so."""
    if not issues or loaded.format != "urdf":
        return None
    what = " and ".join(_ISSUE_TEXT[i] for i in issues)
    return NON_CONFORMING_XML.diagnose(
        f"{display} is XML only as TinyXML2 reads it: {what}. urdfdom (ROS, MoveIt, Gazebo), MuJoCo and PyBullet "
        "read the file, xacro and Python's expat and libxml2 readers (lxml: yourdfpy, urdfpy) refuse it",
        help=_sentence(" and ".join(_ISSUE_FIX[i] for i in issues)) + ": every reader then reads it.",
        location=SourceLocation(display, 1, 1),
        data={"file": display, "issues": list(issues)},
    )


def _sentence(text: str) -> str:
    return text[:1].upper() + text[1:]


def read_as_tinyxml(
    data: bytes, display: str, limits: LoadLimits, err: InputError
) -> tuple[bytes, etree._Element, tuple[str, ...]]:
    """A root file that XML refuses and TinyXML2 reads (:func:`as_tinyxml_reads`: a declaration
    after a comment or blank lines, NUL bytes at the end), as TinyXML2 reads it, with what that
    took; ``err`` raised again for any other file."""
    repaired, issues = as_tinyxml_reads(data)
    if not issues:
        raise err
    try:
        root = parse_bytes(repaired, display, limits)
    except InputError:
        raise err from None
    return repaired, root, issues


def load_urdf(
    bundle: Bundle, args: Mapping[str, str], limits: LoadLimits, data: bytes, root: etree._Element | None
) -> LoadedDescription:
    """URDF as it is; xacro (a ``.xacro`` name, the xacro namespace or any xacro or legacy
    tag) expanded with the real xacro first."""
    display = bundle.display(bundle.root_file)
    if root is not None and not uses_xacro(root, bundle.root_file.name):
        text = decode_text(data)
        resolver = LocationResolver(display, {display: text}, None)
        robot, found = parse_urdf(root, resolver)
        document = ExpandedDocument(text=text, root=display, sources={display: text}, is_xacro=False)
        return LoadedDescription(bundle, robot, document, tuple(found))
    expansion = cached_expand(bundle, args, limits)  # expanded anew when no cache store is active
    expanded_limits = LoadLimits(
        max_file_bytes=limits.max_expanded_bytes,
        max_xml_depth=limits.max_xml_depth,
    )
    expanded = parse_bytes(expansion.text.encode("utf-8"), f"{display} (expanded)", expanded_limits)
    resolver = LocationResolver(display, expansion.sources, expansion.origins)
    robot, found = parse_urdf(expanded, resolver)
    document = ExpandedDocument(text=expansion.text, root=display, sources=expansion.sources, is_xacro=True)
    return LoadedDescription(bundle, robot, document, (*expansion.diagnostics, *found))


def load_mjcf(
    bundle: Bundle, args: Mapping[str, str], limits: LoadLimits, data: bytes, root: etree._Element | None
) -> LoadedDescription:
    """MJCF compiled by MuJoCo (imported only when an MJCF file is checked)."""
    from geomcheck.load.mjcf import load_mjcf as load_compiled

    return load_compiled(bundle, limits, data)


def load_sdf(
    bundle: Bundle, args: Mapping[str, str], limits: LoadLimits, data: bytes, root: etree._Element | None
) -> LoadedDescription:
    """SDFormat (Gazebo) with its nested and included models, SDFormat's frame semantics applied."""
    from geomcheck.load.sdf import load_sdf as load_model

    return load_model(bundle, limits, data)


URDF = register(InputFormat("urdf", "URDF, or xacro expanded to URDF", ("robot",), (".urdf", ".xacro"), load_urdf))
MJCF = register(InputFormat("mjcf", "MuJoCo MJCF, compiled by MuJoCo", ("mujoco",), (".mjcf",), load_mjcf))
SDF = register(InputFormat("sdf", "SDFormat (Gazebo) model, 1.4 to 1.11", ("sdf",), (".sdf",), load_sdf))
