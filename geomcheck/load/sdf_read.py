"""Reading an SDFormat model: the root file and the models it ``<include>``s, each model's
declarations in document order, before any pose is computed (:mod:`geomcheck.load.sdf_frames`
computes them, :mod:`geomcheck.load.sdf` maps them onto the model).

A ``model://NAME/...`` URI (an ``<include>``'s or a mesh's) is resolved as Gazebo resolves it
on its model path (:func:`model_dir`): the folder of model ``NAME`` is the package ``NAME``
given with ``--package NAME=DIR``, else the folder ``NAME`` in a ``--search`` folder (a Gazebo
model path: the folder that holds model folders), else the root model's own folder when it is
called ``NAME``, else a package found as ROS packages are. An included folder is read through
its ``model.config`` (the ``<sdf>`` file of the highest version). A relative URI is relative to
the folder of the file that writes it, ``file://`` is absolute.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import unquote

from lxml import etree

from geomcheck.errors import InputError, LimitExceeded
from geomcheck.load.xmlsafe import decode_text, late_declaration_removed, parse_bytes, read_file_bytes

if TYPE_CHECKING:
    from geomcheck.load.bundle import Bundle
    from geomcheck.thresholds import LoadLimits

MODEL_SCHEME = "model://"
FILE_SCHEME = "file://"
DEFAULT_MODEL_FILE = "model.sdf"  # what Gazebo reads in a model folder whose model.config names no file
FIRST_FRAME_SEMANTICS = (1, 7)  # the version that brought //pose/@relative_to and //axis/xyz/@expressed_in


@dataclass
class ModelScope:
    """One ``<model>``: the root model, a nested one or an included one.

    ``prefix`` is prepended to the names of its links and joints to make them unique in the
    robot (``""`` for the root model, ``"create::"`` for a model ``create`` in it), as
    libsdformat scopes them; ``pose`` is the ``<pose>`` that places it in its parent model (an
    ``<include>``'s wins over the included model's own) and ``placement`` the frame that pose
    places (``placement_frame``, the model frame when ``None``). ``items`` holds its links and
    nested models in document order.
    """

    name: str
    prefix: str
    element: etree._Element
    file: str
    folder: Path
    version: tuple[int, int]
    pose: etree._Element | None
    placement: str | None
    parent: ModelScope | None = None
    links: list[etree._Element] = field(default_factory=list)
    joints: list[etree._Element] = field(default_factory=list)
    frames: list[etree._Element] = field(default_factory=list)
    models: list[ModelScope] = field(default_factory=list)
    items: list[etree._Element | ModelScope] = field(default_factory=list)

    @property
    def label(self) -> str:
        """How messages name the model: its scoped name, or its name for the root."""
        return self.prefix.removesuffix("::") or self.name

    def where(self, element: etree._Element) -> str:
        return f"{self.file}:{element.sourceline}"


def parse_version(text: str | None, where: str) -> tuple[int, int]:
    """``(major, minor)`` of ``<sdf version="1.6">``; :class:`InputError` when absent or not a version."""
    parts = (text or "").strip().split(".")
    try:
        major, minor = int(parts[0]), int(parts[1]) if len(parts) > 1 else 0
    except ValueError:
        raise InputError(f'{where}: <sdf version="{text or ""}"> is not an SDFormat version such as 1.6') from None
    if major != 1:
        raise InputError(f"{where}: SDFormat version {text} is not read (geomcheck reads SDFormat 1.x)")
    return major, minor


class SdfReader:
    """Reads the root file and its includes through the bundle's sandbox and limits, each file's
    text kept for excerpts (``sources``, display path -> text, root first)."""

    def __init__(self, bundle: Bundle, limits: LoadLimits) -> None:
        self.bundle = bundle
        self.limits = limits
        self.sources: dict[str, str] = {}
        self.including: list[Path] = []

    def parse(self, path: Path, data: bytes | None = None) -> tuple[etree._Element, str]:
        display = self.bundle.display(path)
        resolved = self.bundle.check_access(path)
        if data is None:
            data = read_file_bytes(resolved, display, self.limits)
            data = late_declaration_removed(data) or data
        self.sources.setdefault(display, decode_text(data))
        return parse_bytes(data, display, self.limits), display

    def root_model(self, data: bytes) -> ModelScope:
        """The ``<model>`` of the root file holding ``data`` (its expansion counted first:
        :meth:`expansion`)."""
        root, display = self.parse(self.bundle.root_file, data)
        self.including.append(self.bundle.root_file.resolve())
        if root.tag == "sdf":  # libsdformat reads the version first: a file without one is refused for it
            parse_version(root.get("version"), display)
        model = self.model_of(root, display)
        self.expansion(model, display, self.bundle.root_file.parent, {})
        version = parse_version(root.get("version"), display)
        scope = self.scope(model, display, self.bundle.root_file.parent, version, None, "", None, None)
        self.including.pop()
        return scope

    def expansion(self, model: etree._Element, file: str, folder: Path, sizes: dict[Path, int], depth: int = 0) -> int:
        """The links, joints, frames and models ``model`` makes once every ``<include>`` is
        expanded (an included file counted once, however often it is included: ``sizes``),
        before any is built; :class:`LimitExceeded` naming the ``<include>`` that takes it
        beyond ``max_sdf_elements`` (a 1.6 KB fan-out of includes built 111,111 links)."""
        total = 1
        for child in model:
            if child.tag in ("link", "joint", "frame"):
                total += 1
            elif child.tag == "model":
                total += self.expansion(child, file, folder, sizes, depth)
            elif child.tag == "include":
                uri = (child.findtext("uri") or "").strip()
                where = f"{file}:{child.sourceline}"
                if not uri or depth > self.limits.max_xml_depth:
                    continue  # the build says what is wrong with it
                try:
                    path = self.model_file(self.locate(uri, folder, where), where)
                    resolved = path.resolve()
                    if resolved not in sizes:
                        sizes[resolved] = 0  # an include of itself counts nothing here: the build refuses it
                        root, display = self.parse(path)
                        included = self.model_of(root, display)
                        sizes[resolved] = self.expansion(included, display, path.parent, sizes, depth + 1)
                except LimitExceeded:
                    raise
                except InputError:
                    continue  # the build refuses it with its own message
                total += sizes[resolved]
                if total > self.limits.max_sdf_elements:
                    raise LimitExceeded(
                        f"{where}: <include> of {uri} makes the model {total} links, joints, frames and models "
                        f"once its includes are expanded, beyond the limit of {self.limits.max_sdf_elements} "
                        "(max_sdf_elements)"
                    )
        if total > self.limits.max_sdf_elements:
            raise LimitExceeded(
                f"{file}:{model.sourceline}: <model> makes {total} links, joints, frames and models, beyond the "
                f"limit of {self.limits.max_sdf_elements} (max_sdf_elements)"
            )
        return total

    def model_of(self, root: etree._Element, display: str) -> etree._Element:
        """The one ``<model>`` of an ``<sdf>`` document, or of its one ``<world>`` when that holds one
        model and includes none; :class:`InputError` for any other world, or none."""
        if root.tag != "sdf":
            raise InputError(
                f"{display}:{root.sourceline}: the root element is <{root.tag}>, not <sdf>: this is not an "
                "SDFormat document (libsdformat refuses it)"
            )
        models = [c for c in root if c.tag == "model"]
        worlds = [c for c in root if c.tag == "world"]
        if not models and len(worlds) == 1:
            # a world around one robot and nothing else (PyBullet's kuka_with_gripper2.sdf): that robot
            inside = [c for c in worlds[0] if c.tag in ("model", "include")]
            if len(inside) == 1 and inside[0].tag == "model":
                return inside[0]
        if not models:
            what = "a <world>" if worlds else "no <model>"
            raise InputError(
                f"{display}:{root.sourceline}: the <sdf> holds {what}; geomcheck checks one robot: pass the "
                "model's own file (a <world> includes it with <include><uri>model://NAME</uri>)"
            )
        if len(models) > 1:
            raise InputError(
                f"{display}:{models[1].sourceline}: the <sdf> holds {len(models)} <model>s; "
                "geomcheck checks one robot: pass a file with one model"
            )
        return models[0]

    def scope(
        self,
        model: etree._Element,
        file: str,
        folder: Path,
        version: tuple[int, int],
        parent: ModelScope | None,
        prefix: str,
        pose: etree._Element | None,
        placement: str | None,
        name: str | None = None,
    ) -> ModelScope:
        """The scope of ``model`` with its links, joints, frames and nested models read."""
        own_pose = next((c for c in model if c.tag == "pose"), None)
        scope = ModelScope(
            name=name or model.get("name") or "",
            prefix=prefix,
            element=model,
            file=file,
            folder=folder,
            version=version,
            pose=pose if pose is not None else own_pose,
            placement=placement or model.get("placement_frame") or None,
            parent=parent,
        )
        for child in model:
            if not isinstance(child.tag, str):
                continue
            if child.tag == "link":
                scope.links.append(child)
                scope.items.append(child)
            elif child.tag == "joint":
                scope.joints.append(child)
            elif child.tag == "frame":
                scope.frames.append(child)
            elif child.tag == "model":
                nested_name = child.get("name") or ""
                nested = self.scope(child, file, folder, version, scope, f"{prefix}{nested_name}::", None, None)
                scope.models.append(nested)
                scope.items.append(nested)
            elif child.tag == "include":
                nested = self.include(child, scope)
                scope.models.append(nested)
                scope.items.append(nested)
        return scope

    def include(self, element: etree._Element, parent: ModelScope) -> ModelScope:
        """The model an ``<include>`` brings in, as a nested model of ``parent``."""
        where = parent.where(element)
        if (element.get("merge") or "").strip().lower() in ("true", "1"):
            raise InputError(
                f'{where}: <include merge="true"> is not supported yet; include the model without merge '
                "(its links are then scoped as NAME::link)"
            )
        uri = (element.findtext("uri") or "").strip()
        if not uri:
            raise InputError(f"{where}: <include> has no <uri>")
        path = self.model_file(self.locate(uri, parent.folder, where), where)
        if path.resolve() in self.including:
            raise InputError(f"{where}: <include> of {uri} includes itself")
        if len(self.including) > self.limits.max_xml_depth:
            raise InputError(f"{where}: <include>s nested deeper than {self.limits.max_xml_depth} files")
        root, display = self.parse(path)
        model = self.model_of(root, display)
        version = parse_version(root.get("version"), display)
        name = (element.findtext("name") or "").strip() or model.get("name") or ""
        pose = next((c for c in element if c.tag == "pose"), None)
        placement = (element.findtext("placement_frame") or "").strip() or None
        self.including.append(path.resolve())
        scope = self.scope(
            model, display, path.parent, version, parent, f"{parent.prefix}{name}::", pose, placement, name
        )
        self.including.pop()
        return scope

    def locate(self, uri: str, folder: Path, where: str) -> Path:
        """The file or folder ``uri`` names (model://, file://, absolute or relative to ``folder``)."""
        if uri.startswith(MODEL_SCHEME):
            name, _, rest = uri[len(MODEL_SCHEME) :].partition("/")
            directory = model_dir(self.bundle, name)
            if directory is None:
                raise InputError(
                    f"{where}: {uri}: model '{name}' is not on the model path; {self.bundle.package_advice(name)} "
                    "(a Gazebo model path: the folder that holds the model's folder)"
                )
            return directory / unquote(rest) if rest else directory
        if uri.startswith(FILE_SCHEME):
            return Path(unquote(uri[len(FILE_SCHEME) :]))
        if "://" in uri:
            raise InputError(f"{where}: {uri}: only model://, file:// and file paths are read (no download)")
        path = Path(unquote(uri))
        return path if path.is_absolute() else folder / path

    def model_file(self, path: Path, where: str) -> Path:
        """The SDF file of a model folder (its ``model.config``'s ``<sdf>`` of the highest version),
        or ``path`` itself when it is a file."""
        resolved = self.bundle.check_access(path)
        if resolved.is_file():
            return path
        if not resolved.is_dir():
            raise InputError(f"{where}: <include>: no such file or folder: {self.bundle.shown(path)}")
        config = path / "model.config"
        chosen = DEFAULT_MODEL_FILE
        if self.bundle.check_access(config).is_file():
            root, display = self.parse(config)
            best: tuple[int, int] | None = None
            for entry in root.iter("sdf"):
                if not (entry.text or "").strip():
                    continue
                version = parse_version(entry.get("version") or "1.0", display)
                if best is None or version > best:
                    best, chosen = version, entry.text.strip()
        return path / chosen


def model_dir(bundle: Bundle, name: str) -> Path | None:
    """The folder of model ``name`` on the model path (see the module docstring), ``None``
    when there is none (or, for a confined bundle, none inside the sandbox)."""
    if not name or "/" in name or name in (".", ".."):
        return None
    if name in bundle.packages:
        return bundle.packages[name]
    candidates = [root / name for root in bundle.search_roots]
    if bundle.root_file.parent.name == name:
        candidates.append(bundle.root_file.parent)
    for candidate in candidates:
        if candidate.is_dir() and (
            not bundle.confined or any(candidate.resolve().is_relative_to(r) for r in bundle.allowed_roots)
        ):
            return candidate.resolve()
    return bundle.package_dir(name)


def relative_uri(uri: str, scope: ModelScope, bundle: Bundle) -> str:
    """A mesh ``uri`` as geomcheck's mesh store resolves it: ``model://NAME/x`` becomes
    ``package://NAME/x`` when the model's folder is the package ``NAME`` the store finds, else
    the path of the file relative to the root file's folder, as a relative path written in an
    included file does; others stay as written."""
    text = uri.strip()
    root_folder = bundle.root_file.parent
    if text.startswith(MODEL_SCHEME):
        name, _, rest = text[len(MODEL_SCHEME) :].partition("/")
        directory = model_dir(bundle, name)
        if directory is None or directory == bundle.package_dir(name):
            return "package://" + text[len(MODEL_SCHEME) :]  # an unknown model is the store's GC202
        return Path(os.path.relpath(directory / unquote(rest), root_folder)).as_posix()
    if "://" in text or Path(text).is_absolute():
        return text
    if scope.folder == root_folder:
        return text
    return Path(os.path.relpath(scope.folder / text, root_folder)).as_posix()
