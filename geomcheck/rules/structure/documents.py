"""GC101-GC104, GC131, GC132: the document as XML and as xacro."""

from __future__ import annotations

from geomcheck.diagnostics import Metric, Severity
from geomcheck.rules import Rule, register

XACRO_NS = "http://www.ros.org/wiki/xacro"

MALFORMED_XML = register(
    Rule(
        code="GC101",
        name="malformed-xml",
        severity=Severity.ERROR,
        summary="A file of the description is not well-formed XML, or is refused by the hardened parser.",
        what=(
            "Reports a file that cannot be parsed: a syntax error (unclosed tag, bad attribute quoting, "
            "undeclared namespace prefix), a DOCTYPE that declares entities, nesting deeper than the "
            "configured limit. The check stops: nothing else can be said about the robot."
        ),
        why=(
            "ROS tools (xacro, robot_state_publisher, MoveIt) refuse the same file. Entity declarations "
            "are refused because they are how XML bombs (billion laughs) and external-entity reads work."
        ),
        example='<link name="base_link">\n  <visual>\n</link>   <!-- GC101: mismatched tag -->',
        fix="Fix the XML at the given line and column; remove any <!DOCTYPE> with <!ENTITY> declarations.",
        severity_reason=(
            "Error: xacro, urdfdom and every ROS tool refuse a file that is not well-formed XML; geomcheck cannot "
            "go on either. Never lowered."
        ),
    )
)

XACRO_ERROR = register(
    Rule(
        code="GC102",
        name="xacro-error",
        severity=Severity.ERROR,
        summary="xacro failed to expand the description (undefined property, unknown macro, bad include).",
        what=(
            "Runs the real xacro expander (in process, no ROS install) and reports its error message with "
            "the file and line where the failing expression, macro call or include was found."
        ),
        why="The description cannot be turned into URDF, so no ROS tool can load it.",
        example='<xacro:property name="r" value="0.1"/>\n<cylinder radius="${radius}" length="1"/>  <!-- GC102 -->',
        fix="Define the property, macro or argument, or fix the include path; pass arguments with --arg NAME=VALUE.",
        metrics=(Metric("macros", "text", description="The macro calls being expanded, outermost first."),),
        severity_reason=("Error: xacro stops and produces no URDF, so no consumer can load the robot. Never lowered."),
    )
)

LEGACY_XACRO = register(
    Rule(
        code="GC103",
        name="legacy-xacro-syntax",
        severity=Severity.WARNING,
        summary="A file uses pre-2013 xacro syntax: bare <property>, <include>, <macro>, <insert_block>...",
        what=(
            "Reports, once per file, the xacro tags written without the xacro: prefix (<property>, "
            "<include>, <macro>, <insert_block>, <arg>, <if>, <unless>, <call>, bare macro calls) and a "
            "missing or wrong xmlns:xacro declaration. geomcheck rewrites them in memory and goes on. Severity by what "
            "xacro does with the file: see severity_reason."
        ),
        why=(
            "ROS 2 xacro no longer understands the bare tags (ROS 1 xacro accepted them with a deprecation "
            "warning): it copies them into the URDF unexpanded, so the robot silently loses its includes and macros."
        ),
        example=(
            '<robot name="pr2">\n  <include filename="$(find pr2_description)/urdf/common.xacro"/>\n'
            '  <property name="M_PI" value="3.1415926535897931"/>'
        ),
        fix=f'Prefix the tags with xacro: and declare xmlns:xacro="{XACRO_NS}" on the root element.',
        metrics=(
            Metric("file", "text", description="The file using the legacy syntax."),
            Metric("tags", "object", description="Each legacy tag used, and how many times."),
            Metric("namespace", "text", description="What the file declares as the xacro namespace, or null."),
        ),
        severity_reason=(
            "By what xacro does with the file (it matches its instructions by the xacro: prefix of the tag name, "
            "never by the namespace URI): a xacro: prefix without its xmlns:xacro declaration makes xacro's "
            "namespace-aware XML parser refuse the file (error); bare <property>/<include>/<macro>/<insert_block> "
            "tags were accepted by ROS 1 xacro with a deprecation warning and are copied unexpanded by ROS 2 "
            "xacro, which a maintainer modernises (warning), unless they all lie in macros this robot never calls "
            "(they cannot reach its URDF: info); a wrong or old namespace URI on a file that expands as it is is "
            "dead markup (info)."
        ),
    )
)

XACRO_WARNING = register(
    Rule(
        code="GC104",
        name="xacro-warning",
        severity=Severity.WARNING,
        summary="xacro warned while expanding (unknown attribute on a xacro tag, redefined symbol...).",
        what="Reports the warnings that the xacro expander prints, with the file being processed.",
        why="xacro warnings usually point at a typo or at a construct that newer xacro versions reject.",
        example='<xacro:include filename="arm.xacro" nss="arm"/>   <!-- GC104: unknown attribute(s): nss -->',
        fix="Fix what the xacro message names.",
        metrics=(Metric("file", "text", description="The file xacro warned about."),),
        severity_reason=(
            "Warning: xacro expanded the file but printed a warning, which names a construct the maintainer would "
            "fix (a typo, an attribute newer xacro rejects)."
        ),
    )
)

XML_VERSION = register(
    Rule(
        code="GC131",
        name="unsupported-xml-version",
        severity=Severity.WARNING,
        summary='The root file\'s XML declaration names a version XML does not have (version="0.0").',
        what=(
            "Reads the version of the root file's <?xml ...?> declaration. XML has versions 1.0 and 1.1 only; "
            "a file declaring another (old exporters wrote 0.0) is read as XML 1.0, as TinyXML2 (urdfdom, "
            "Gazebo, MuJoCo) and expat (xacro) read it, and checked in full."
        ),
        why=(
            "libxml2 refuses the file outright ('Unsupported version'), and with it every reader built on it: "
            "lxml, and so Python URDF loaders such as yourdfpy and urdfpy, and XML linters in CI."
        ),
        example='<?xml version="0.0" ?>   <!-- GC131 -->\n<robot name="minitaur">',
        fix='Declare <?xml version="1.0"?>.',
        metrics=(
            Metric("file", "text", description="The file with the declaration."),
            Metric("version", "text", description="The version it declares."),
        ),
        severity_reason=(
            "Warning: ROS (xacro, urdfdom), Gazebo, MuJoCo and PyBullet read the file, libxml2-based readers "
            "refuse it; the maintainer changes one attribute."
        ),
    )
)

NON_CONFORMING_XML = register(
    Rule(
        code="GC132",
        name="non-conforming-xml",
        severity=Severity.WARNING,
        summary="The root URDF is XML only as TinyXML2 reads it: blank lines or a comment before its <?xml?> "
        "declaration, or NUL bytes after its last element.",
        what=(
            "When the root file does not parse as XML, reads it as TinyXML2 does (urdfdom, Gazebo, MuJoCo, "
            "PyBullet): an <?xml ...?> declaration after blank space or comments is accepted, and reading stops "
            "at the first NUL byte, so NULs after the last element end the text. A URDF that parses so is "
            "checked in full and this finding says what libxml2 and expat refuse. An SDFormat or MJCF file read "
            "so gets no finding: Gazebo and MuJoCo, its only readers, read it with TinyXML2."
        ),
        why=(
            "XML allows nothing before the declaration and no NUL character anywhere. expat (xacro, Python's "
            "xml.dom) and libxml2 (lxml: yourdfpy, urdfpy, XML linters in CI) refuse the file: the URDF loads "
            "in ROS and PyBullet and fails in those tools."
        ),
        example='\n\n\n<?xml version="1.0"?>   <!-- GC132: three blank lines before the declaration -->\n'
        '<robot name="balance">',
        fix="Put the declaration on the first line (or delete it) and delete the NUL bytes at the end of the file.",
        metrics=(
            Metric("file", "text", description="The root file."),
            Metric("issues", "text", description="What XML refuses: late-declaration, trailing-nul."),
        ),
        severity_reason=(
            "Warning: ROS's C++ readers, Gazebo and PyBullet read the file, xacro and libxml2-based readers "
            "refuse it; the maintainer deletes a few bytes."
        ),
    )
)
