"""The request body of ``POST /v1/checks`` for the OpenAPI document.

The endpoint reads its body itself (raw XML, a multipart form or an archive, streamed under
the size limits), so FastAPI cannot infer it; this declares all three forms.
"""

from __future__ import annotations

from typing import Any

from api.archives import TAR_TYPES, TGZ_TYPES, ZIP_TYPES

_BINARY = {"type": "string", "format": "binary"}
_EXAMPLE_URDF = """<robot name="two_links">
  <link name="base_link"><collision><geometry><box size="0.6 0.6 0.2"/></geometry></collision></link>
  <link name="arm"><collision><geometry><cylinder radius="0.05" length="0.5"/></geometry></collision></link>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="arm"/>
    <origin xyz="0 0 0.35"/><axis xyz="0 0 1"/><limit lower="-1.57" upper="1.57" effort="10" velocity="1"/></joint>
</robot>
"""
_OPTION_FIELDS: dict[str, Any] = {
    "args": {"type": "array", "items": {"type": "string"}, "description": "xacro argument NAME=VALUE"},
    "samples": {"type": "integer", "minimum": 1, "description": "collision-matrix samples"},
    "seed": {"type": "integer", "minimum": 0, "description": "collision-matrix sampling seed"},
    "backend": {"type": "string", "enum": ["coal", "fcl"]},
    "semantics": {"type": "string", "enum": ["moveit", "pinocchio"]},
    "fail_on": {"type": "string", "enum": ["error", "warning", "info"]},
    "matrix": {"type": "boolean"},
    "sweep": {"type": "boolean"},
    "pose": {"type": "array", "items": {"type": "string"}, "description": "JOINT=VALUE, [rad] or [m]"},
    "pose_name": {"type": "string", "description": "SRDF group_state used as the default pose"},
    "select": {"type": "array", "items": {"type": "string"}, "description": "only these rules (GC3, fit, GC301)"},
    "ignore": {"type": "array", "items": {"type": "string"}, "description": "not these rules"},
    "extend_select": {"type": "array", "items": {"type": "string"}, "description": "these rules in addition"},
}

CHECK_REQUEST_BODY: dict[str, Any] = {
    "required": True,
    "description": (
        "One of three forms. (1) A URDF or xacro document (`application/xml` or `text/xml`); the files it "
        "references are absent, so mesh rules report them missing. (2) A multipart form: `description` "
        "(the root file) and any number of `files`, each part's filename being its path in the package tree "
        "(`pr2_description/meshes/base_v0/base.stl`), plus option fields. (3) An archive of the package tree "
        "(zip, gzip'd tar or tar) with `?root=` naming the root file. Options may also be given as query "
        "parameters. Report paths are relative to the upload root (the archive's or form's top level; a "
        "top level that is itself a package is placed in a folder named after it)."
    ),
    "content": {
        "application/xml": {"schema": {"type": "string"}, "example": _EXAMPLE_URDF},
        "text/xml": {"schema": {"type": "string"}},
        "multipart/form-data": {
            "schema": {
                "type": "object",
                "properties": {
                    "description": {**_BINARY, "description": "the root URDF/xacro; its filename is its path"},
                    "files": {
                        "type": "array",
                        "items": _BINARY,
                        "description": "meshes, includes and manifests; each filename is its path in the tree",
                    },
                    "root": {"type": "string", "description": "root file path, when it is one of `files`"},
                    "srdf": {"description": "an SRDF file part, or as a text field its path in the upload"},
                    "options": {
                        "type": "string",
                        "description": 'JSON object of options: {"samples": 500, "args": {"NAME": "VALUE"}}',
                    },
                    **_OPTION_FIELDS,
                },
            },
        },
        **{t: {"schema": _BINARY} for t in sorted(ZIP_TYPES | TGZ_TYPES | TAR_TYPES)},
    },
}
