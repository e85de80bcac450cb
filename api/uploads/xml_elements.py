"""Elements of an uploaded description as the root choice reads them: parsed without trusting the
upload, named without namespace or prefix, xacro's told apart."""

from __future__ import annotations

from lxml import etree

XACRO_URIS = frozenset(
    {"http://www.ros.org/wiki/xacro", "http://ros.org/wiki/xacro", "http://wiki.ros.org/xacro", "xacro"}
)


def parsed_root(text: bytes) -> etree._Element | None:
    """The document's root element, parsed without entities, network or DTD (a hostile upload);
    ``None`` when it cannot be. Undeclared prefixes (legacy xacro) are recovered."""
    parser = etree.XMLParser(
        resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False, recover=True, remove_comments=True
    )
    try:
        root = etree.fromstring(text, parser)
    except (etree.XMLSyntaxError, ValueError):
        return None
    return root if root is not None and isinstance(root.tag, str) else None


def local_name(element: etree._Element) -> str:
    """The element's name without namespace or prefix (a recovered ``xacro:NAME`` whose prefix
    was never declared keeps it in its tag)."""
    tag = element.tag
    if not isinstance(tag, str):
        return ""
    return tag.rsplit("}", 1)[-1].rsplit(":", 1)[-1]


def is_xacro(element: etree._Element) -> bool:
    tag = element.tag
    namespace = tag[1:].split("}", 1)[0] if isinstance(tag, str) and tag.startswith("{") else None
    return (
        element.prefix == "xacro"
        or (isinstance(tag, str) and tag.startswith("xacro:"))
        or (namespace is not None and namespace in XACRO_URIS)
    )
