"""What pycollada and trimesh read of a COLLADA document besides its geometry and scene: the
images, effects, materials, cameras and lights, and the libraries the reader leaves to them.

None of it changes a vertex, but pycollada loads all of it and trimesh builds a material of
every ``<material>``, and either may fail on it (a color with no text, a negative emission, a
texture without its sampler) or drop an effect, which drops the material made of it and every
geometry instance bound to that material. :func:`material_ids` accepts a document only where
the structure is one that loads whole, checked against pycollada's and trimesh's code, and
raises :class:`~geomcheck.load.collada_xml.Unsupported` otherwise: the file is then read
through trimesh, which fails or drops exactly as it does.
"""

from __future__ import annotations

from lxml import etree

from geomcheck.load.collada_xml import Dae, Unsupported

SHADERS = ("phong", "lambert", "blinn", "constant")  # pycollada's order of preference
NUMBER_PARAMETERS = ("float", "float2", "float3", "float4")  # pycollada's order of preference
COLOR_PROPERTIES = ("emission", "ambient", "diffuse", "specular", "reflective", "transparent")
FLOAT_PROPERTIES = ("shininess", "reflectivity", "transparency", "index_of_refraction")
MAX_COLOR_VALUES = 4  # RGBA: trimesh refuses a longer base color
# trimesh's roughness is sqrt(2 / (2 + shininess)): this shininess divides by zero [dimensionless]
SINGULAR_SHININESS = -2.0
# elements under a light whose text pycollada reads as a number, failing on a missing text
LIGHT_NUMBERS = (
    "constant_attenuation",
    "linear_attenuation",
    "quadratic_attenuation",
    "zfar",
    "falloff_angle",
    "falloff_exponent",
)
# libraries whose entries pycollada loads by code the reader does not mirror (sources of
# animations, skins and morphs, nodes instanced by reference)
UNMIRRORED_LIBRARIES = (
    ("library_animations", "animation"),
    ("library_controllers", "controller"),
    ("library_nodes", "node"),
)


def _first(dae: Dae, node: etree._Element, names: tuple[str, ...]) -> etree._Element | None:
    """The first child of ``node`` named the first of ``names`` that ``node`` has, or ``None``."""
    return next((found for name in names if (found := dae.find(node, name)) is not None), None)


def _floats(text: str | None) -> list[float]:
    """The numbers of a color or float as pycollada reads them (Python's ``float``)."""
    if text is None:
        raise Unsupported("a number without text")
    try:
        return [float(value) for value in text.split()]
    except ValueError:
        raise Unsupported("a malformed number") from None


def _float(text: str | None) -> float:
    """The number of a ``<float>`` as pycollada reads it (Python's ``float`` of the whole text)."""
    try:
        return float(text)  # type: ignore[arg-type]  # None fails as in pycollada
    except (TypeError, ValueError):
        raise Unsupported("a malformed float") from None


def image_ids(dae: Dae) -> set[str | None]:
    """Ids of the ``<image>`` elements pycollada loads (those with an ``<init_from>``)."""
    return {
        image.get("id")
        for image in dae.findall(dae.root, "library_images/image")
        if dae.find(image, "init_from") is not None
    }


Scope = dict[str | None, tuple[str, str | None]]  # an effect's parameters by sid: kind, image id


def _parameters(dae: Dae, parent: etree._Element, scope: Scope, images: set[str | None]) -> None:
    """Check the ``<newparam>`` of an effect's profile or technique as pycollada loads them,
    recording each under its sid: its kind (``surface``, ``sampler`` or ``float``) and the id
    of the image a surface or sampler shows."""
    for param in dae.findall(parent, "newparam"):
        surface = dae.find(param, "surface")
        sampler = dae.find(param, "sampler2D")
        if surface is not None:
            source = dae.find(surface, "init_from")
            if surface.get("type") != "2D" or source is None:
                raise Unsupported("a surface pycollada drops")
            if source.text in scope or source.text not in images:
                raise Unsupported("a surface of an image that is not loaded")
            scope[param.get("sid")] = ("surface", source.text)
        elif sampler is not None:
            source = dae.find(sampler, "source")
            found = scope.get(source.text) if source is not None else None
            if found is None or found[0] != "surface":
                raise Unsupported("a sampler of a surface that is not loaded")
            scope[param.get("sid")] = ("sampler", found[1])
        else:
            number = _first(dae, param, NUMBER_PARAMETERS)
            sid = param.get("sid")
            if number is not None and sid and number.text is not None:
                _floats(number.text)
                scope[sid] = ("float", None)


def _check_texture(texture: str | None, scope: Scope, images: set[str | None]) -> None:
    """Check a ``<texture>`` finds its sampler as pycollada finds it: by sid, else the sampler
    of the image of that id, else (exporters that write no sampler) a sampler pycollada makes
    for the image of that id."""
    found = scope.get(texture)
    if found is not None:
        if found[0] != "sampler":
            raise Unsupported("a texture naming a parameter that is no sampler")
    elif texture is None:
        raise Unsupported("a texture without sampler")
    elif not any(kind == "sampler" and image == texture for kind, image in scope.values()):
        if texture not in images:
            raise Unsupported("a texture without its sampler")
        scope[texture] = ("sampler", texture)
        scope[f"{texture}-surface"] = ("surface", texture)


def _check_property(dae: Dae, name: str, node: etree._Element, scope: Scope, images: set[str | None]) -> None:
    """Check one shading property (``<diffuse>``...) loads in pycollada and in trimesh's material."""
    children = list(node)  # pycollada reads the first child, whatever it is
    if not children:
        raise Unsupported(f"an empty <{name}>")
    value = children[0]
    if name in COLOR_PROPERTIES and dae.is_a(value, "color"):
        color = _floats(value.text)
        if len(color) > MAX_COLOR_VALUES:
            raise Unsupported("a color of more than four values")
        if name == "emission" and any(v < 0.0 for v in color[:3]):
            raise Unsupported("a negative emission, which trimesh refuses")
    elif name in COLOR_PROPERTIES and dae.is_a(value, "texture"):
        _check_texture(value.get("texture"), scope, images)
    elif name in FLOAT_PROPERTIES and dae.is_a(value, "float"):
        if name == "shininess" and _float(value.text) == SINGULAR_SHININESS:
            raise Unsupported("a shininess trimesh divides by zero with")
        _float(value.text)
    else:
        raise Unsupported(f"a <{name}> the reader does not check")


def _check_effect(dae: Dae, effect: etree._Element, images: set[str | None]) -> None:
    """Check an ``<effect>`` loads whole in pycollada and makes a material in trimesh."""
    profile = dae.find(effect, "profile_COMMON")
    if profile is None or dae.findall(profile, "image"):
        raise Unsupported("an effect without profile_COMMON, or with images of its own")
    scope: Scope = {}
    _parameters(dae, profile, scope, images)
    technique = dae.find(profile, "technique")
    if technique is None:
        raise Unsupported("an effect without technique")
    _parameters(dae, technique, scope, images)
    shader = _first(dae, technique, SHADERS)
    if shader is None:
        raise Unsupported("an effect without a shader pycollada knows")
    for name in COLOR_PROPERTIES + FLOAT_PROPERTIES:
        node = dae.find(shader, name)
        if node is not None:
            _check_property(dae, name, node, scope, images)
    if effect.find(f".//{dae.tag('extra')}//{dae.tag('texture')}") is not None:
        raise Unsupported("a bump map")


def _check_cameras(dae: Dae) -> None:
    """Check no ``<camera>`` makes pycollada fail (a perspective or orthographic view without
    its clipping planes)."""
    for camera in dae.findall(dae.root, "library_cameras/camera"):
        technique = dae.find(camera, "optics/technique_common")
        if technique is None or len(technique) == 0:
            continue  # dropped by pycollada, instanced by no geometry
        for kind in ("perspective", "orthographic"):
            if dae.is_a(technique[0], kind):
                view = dae.find(camera, f"optics/technique_common/{kind}")
                if view is None or dae.find(view, "znear") is None or dae.find(view, "zfar") is None:
                    raise Unsupported("a camera without clipping planes")


def _check_lights(dae: Dae) -> None:
    """Check no ``<light>`` makes pycollada fail (a color or attenuation without text)."""
    for light in dae.findall(dae.root, "library_lights/light"):
        technique = dae.find(light, "technique_common")
        if technique is None or len(technique) == 0:
            continue
        kind = next((k for k in ("directional", "ambient", "point", "spot") if dae.is_a(technique[0], k)), None)
        if kind is None:
            continue  # dropped by pycollada
        if kind in ("directional", "ambient"):
            color, numbers = dae.find(light, f"technique_common/{kind}/color"), []
        else:
            node = dae.find(light, f"technique_common/{kind}")  # technique[0], found
            assert node is not None
            color, numbers = dae.find(node, "color"), [dae.find(node, name) for name in LIGHT_NUMBERS]
        if any(n is not None and n.text is None for n in [color, *numbers]):
            raise Unsupported("a light color or attenuation without text")


def material_ids(dae: Dae) -> set[str | None]:
    """Ids of the document's materials, once every image, effect, material, camera and light
    is checked to load whole (:class:`Unsupported` otherwise, or where the document has
    animations, controllers or a node library)."""
    for library, entry in UNMIRRORED_LIBRARIES:
        if dae.findall(dae.root, f"{library}/{entry}"):
            raise Unsupported(f"a <{entry}> in <{library}>")
    images = image_ids(dae)
    effects: set[str | None] = set()
    for effect in dae.findall(dae.root, "library_effects/effect"):
        _check_effect(dae, effect, images)
        effects.add(effect.get("id"))
    materials: set[str | None] = set()
    for material in dae.findall(dae.root, "library_materials/material"):
        instance = dae.find(material, "instance_effect")
        url = instance.get("url") if instance is not None else None
        if url is None or not url.startswith("#") or url[1:] not in effects:
            raise Unsupported("a material without its effect")
        materials.add(material.get("id"))
    _check_cameras(dae)
    _check_lights(dae)
    return materials


__all__ = ["material_ids"]
