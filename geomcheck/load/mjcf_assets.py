"""Every file MuJoCo reads of an MJCF model, read by geomcheck and handed to MuJoCo in memory.

MuJoCo's compiler opens the files a model names itself, from C, where neither the bundle's
sandbox nor Python's audit hooks see it: ``<include>``, the sub-models of ``<asset><model>``
(attached with ``<attach>``, with their own includes, assets and sub-models) and the files of
``<mesh>``, ``<skin>``, ``<hfield>``, ``<texture>`` (and its six cube faces) and
``<flexcomp>``. A hostile model could have it read any file of the server, learn which paths
exist from its messages, or block it on a FIFO. So geomcheck walks the model first
(:func:`stage_model`): it resolves every such file as MuJoCo 4 does, passes it through
:meth:`Bundle.check_access` (the sandbox, and the whole-check cache's record), reads it as a
regular file within the limits, and gives MuJoCo a copy of each XML file in which every file
name is replaced by the name of those bytes in MuJoCo's virtual file system (VFS). MuJoCo then
compiles from the VFS alone (:func:`compile_staged`).

Resolution, as MuJoCo 4 does it (``tests/load/test_mjcf_assets.py`` holds it to MuJoCo's own
reading of the disk): an ``<include>`` and a ``<model file>`` are relative to the folder of the
model file being read (the root file, or the sub-model's file; an included file brings no
folder of its own); a mesh, skin, height field or flexcomp file to that folder joined with the
compiler's ``meshdir``, a texture to it joined with ``texturedir`` (``assetdir`` sets both; a
later ``<compiler>`` overrides an earlier one; ``strippath`` keeps the file's name alone); an
absolute name or folder stands for itself. Each sub-model has its own compiler settings.

The VFS names all lie in :data:`VFS_ROOT`, a folder of ``/proc`` where no file can be created:
were MuJoCo to miss a name in the VFS and fall back on the disk, it would find nothing there.
The copies keep every line and column of the files (only attribute values change), so
MuJoCo's messages point at the lines the author wrote; the VFS names in them are put back as
the files' display paths (:meth:`StagedModel.named`).

The work MuJoCo would do is counted before it is done (:meth:`Stager.expanded`): the elements
nested ``<replicate>``s multiply, sub-models attached, and the points of flexcomp grids; a
model beyond ``max_mjcf_elements`` is refused naming the construct, and so is an asset MuJoCo
would generate beyond the limits (:meth:`Stager.refuse_generated`: texture pixels, height
field points, builtin mesh vertices, keyframes and user numbers per object).
"""

from __future__ import annotations

import math
import re
import struct
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import quoteattr

from lxml import etree

from geomcheck.errors import InputError, LimitExceeded
from geomcheck.load.regular import read_regular_file
from geomcheck.load.xmlsafe import parse_bytes

if TYPE_CHECKING:
    from geomcheck.load.bundle import Bundle
    from geomcheck.thresholds import LoadLimits

VFS_ROOT = "/proc/geomcheck-vfs/"  # no file can be created under /proc: a name MuJoCo misses names nothing
MESH_DIR, TEXTURE_DIR = "meshdir", "texturedir"
# the elements whose attributes name a file MuJoCo opens, with the compiler folder it is relative to
# (<include> and <model> are relative to the model file's folder); with those two, every attribute
# of MJCF 4's schema that names a file is here
ASSET_FILES: dict[str, tuple[tuple[str, ...], str]] = {
    "mesh": (("file",), MESH_DIR),
    "skin": (("file",), MESH_DIR),
    "hfield": (("file",), MESH_DIR),
    "flexcomp": (("file",), MESH_DIR),
    "texture": (("file", "fileleft", "fileright", "fileup", "filedown", "filefront", "fileback"), TEXTURE_DIR),
}
COMPILER_FOLDERS = ("assetdir", MESH_DIR, TEXTURE_DIR)
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_ATTRIBUTE = re.compile(rb"""([^\s=/>]+)\s*=\s*("[^"]*"|'[^']*')""")
_START_TAG = re.compile(rb"""<[^\s/>]+(?:\s+[^\s=/>]+\s*=\s*(?:"[^"]*"|'[^']*'))*\s*/?>""")


@dataclass
class StagedModel:
    """What MuJoCo compiles: the VFS name of the root model, the VFS's files, and what each
    name stands for (the file on disk, and how messages name it)."""

    root: str
    files: dict[str, bytes] = field(default_factory=dict)
    paths: dict[str, Path] = field(default_factory=dict)  # VFS name -> the file it holds
    displays: dict[str, str] = field(default_factory=dict)  # VFS name -> display path
    elements: int = 0  # the elements MuJoCo's parse makes, replicated and attached ones included

    def named(self, text: str) -> str:
        """``text`` (a MuJoCo message) with every VFS name put back as the display path of its file."""
        if VFS_ROOT not in text or not self.displays:
            return text
        names = sorted(self.displays, key=len, reverse=True)
        return re.sub("|".join(map(re.escape, names)), lambda m: self.displays[m.group(0)], text)


# ---------------------------------------------------------------------------------------------
# Attribute values rewritten in place: every line and column of the file kept


def start_tags(data: bytes) -> Iterator[tuple[int, int]]:
    """The spans of the start tags of ``data`` (a well-formed document: the hardened parser read
    it), in document order: comments, CDATA sections, processing instructions, the document
    type and end tags skipped."""
    position = 0
    while (position := data.find(b"<", position)) >= 0:
        if data.startswith(b"<!--", position):
            end, skip = data.find(b"-->", position + 4), 3
        elif data.startswith(b"<![CDATA[", position):
            end, skip = data.find(b"]]>", position), 3
        elif data.startswith(b"<?", position):
            end, skip = data.find(b"?>", position), 2
        elif data.startswith(b"<!", position):  # <!DOCTYPE ...>, with an internal subset in [...]
            close, bracket = data.find(b">", position), data.find(b"[", position)
            if 0 <= bracket < close:
                close = data.find(b">", data.find(b"]", bracket))
            end, skip = close, 1
        elif data.startswith(b"</", position):
            end, skip = data.find(b">", position), 1
        else:
            tag = _START_TAG.match(data, position)
            end = tag.end() if tag is not None else _tag_end(data, position)
            yield position, end
            position = end
            continue
        if end < 0:
            return
        position = end + skip


def _tag_end(data: bytes, position: int) -> int:
    """The end of the start tag at ``position`` found byte by byte (quoted ``>`` skipped), for
    a tag :data:`_START_TAG` does not match."""
    end, quote = position + 1, 0
    while end < len(data):
        byte = data[end]
        if quote:
            quote = 0 if byte == quote else quote
        elif byte in b"\"'":
            quote = byte
        elif byte == ord(">"):
            break
        end += 1
    return end + 1


class Patches:
    """New values for attributes of the elements of one file, written into its bytes."""

    def __init__(self, data: bytes, root: etree._Element, display: str) -> None:
        self.data = data
        elements = [e for e in root.iter() if isinstance(e.tag, str)]
        spans = list(start_tags(data))
        names = [re.match(rb"<([^\s/>]+)", data[s:e]) for s, e in spans]
        found = [m.group(1).split(b":")[-1].decode("utf-8", "replace") if m else "" for m in names]
        if found != [etree.QName(e).localname for e in elements]:
            raise InputError(f"{display}: the file's elements cannot be told apart to read the files it names")
        self.elements = elements  # held: lxml keeps an element's proxy (and its id) while it lives
        self.span = {id(e): s for e, s in zip(elements, spans, strict=True)}
        self.new: list[tuple[int, int, bytes]] = []

    def set(self, element: etree._Element, attribute: str, value: str) -> None:
        start, end = self.span[id(element)]
        for match in _ATTRIBUTE.finditer(self.data, start, end):
            if match.group(1).split(b":")[-1] == attribute.encode():
                self.new.append((match.start(2), match.end(2), quoteattr(value).encode("utf-8")))
                return
        raise InputError(f"<{element.tag}> has no {attribute} attribute to rewrite")  # pragma: no cover

    def applied(self) -> bytes:
        out, last = [], 0
        for start, end, value in sorted(self.new):
            out += [self.data[last:start], value]
            last = end
        return b"".join([*out, self.data[last:]])


# ---------------------------------------------------------------------------------------------
# The model files


@dataclass
class ModelFile:
    """One XML file of a model (its root file or an included one), parsed."""

    path: Path  # as the model names it (links not resolved: display paths follow the author)
    resolved: Path
    display: str
    data: bytes
    root: etree._Element
    patches: Patches


@dataclass
class Model:
    """One model: the root model or a sub-model of ``<asset><model>``; its files in the order
    MuJoCo splices them, and the compiler's sections over all of them."""

    folder: Path
    files: list[ModelFile] = field(default_factory=list)
    compilers: list[etree._Element] = field(default_factory=list)
    included: dict[int, ModelFile] = field(default_factory=dict)  # id of an <include> -> its file
    attached: dict[str, Model] = field(default_factory=dict)  # <model name> -> the sub-model
    name: str = ""  # its VFS name
    size: int | None = None  # the elements of its worldbody once expanded

    def folders(self) -> tuple[str, str, bool]:
        """``meshdir``, ``texturedir`` and ``strippath`` as the compiler sections set them."""
        meshdir = texturedir = ""
        strip = False
        for compiler in self.compilers:
            if compiler.get("assetdir") is not None:
                meshdir = texturedir = compiler.get("assetdir", "")
            meshdir = compiler.get(MESH_DIR, meshdir)
            texturedir = compiler.get(TEXTURE_DIR, texturedir)
            if compiler.get("strippath") is not None:
                strip = compiler.get("strippath", "").strip().lower() == "true"
        return meshdir, texturedir, strip


class Stager:
    """Walks a model's files through the bundle's sandbox and limits, staging them for the VFS."""

    def __init__(self, bundle: Bundle, limits: LoadLimits) -> None:
        self.bundle = bundle
        self.limits = limits
        self.staged = StagedModel(root="")
        self.by_path: dict[tuple[int, Path], str] = {}  # (id of the model, resolved file) -> VFS name
        self.reading: list[Path] = []  # the sub-model files being read (a loop is refused)
        self.count = 0

    def vfs_name(self, path: Path) -> str:
        """A new VFS name for the file ``path``, in a folder of its own: its name kept, as MuJoCo
        names an unnamed asset after it and picks a decoder by its suffix."""
        self.count += 1
        if self.count > self.limits.max_model_files:
            raise LimitExceeded(
                f"{self.bundle.display(path)}: the model names more than {self.limits.max_model_files} files "
                "(max_model_files)"
            )
        return f"{VFS_ROOT}{self.count}/{path.name}"

    def parse(self, path: Path, resolved: Path, data: bytes | None = None) -> ModelFile:
        display = self.bundle.display(path)
        if data is None:
            data = read_regular_file(resolved, display, self.limits.max_file_bytes, "max_file_bytes")
        root = parse_bytes(data, display, self.limits)
        return ModelFile(path, resolved, display, data, root, Patches(data, root, display))

    def stage(self, name: str, data: bytes, path: Path, resolved: Path) -> None:
        self.staged.files[name] = data
        self.staged.paths[name] = resolved
        self.staged.displays.setdefault(name, self.bundle.display(path))

    # -- one model ------------------------------------------------------------------------------

    def model(self, path: Path, where: str, data: bytes | None = None) -> Model:
        """The model of the file ``path`` with its includes spliced and every file it names staged."""
        resolved = self.bundle.check_access(path)
        if resolved in self.reading:
            raise InputError(f"{where}: <model> of {self.bundle.shown(path)} attaches itself (a loop of sub-models)")
        if len(self.reading) > self.limits.max_include_depth:
            raise LimitExceeded(
                f"{where}: <model> files nested deeper than {self.limits.max_include_depth} (max_include_depth)"
            )
        self.reading.append(resolved)
        model = Model(path.parent)
        first = self.parse(path, resolved, data)
        model.files.append(first)
        self.splice(model, first, True, [resolved])
        meshdir, texturedir, strip = model.folders()
        for file in model.files:
            self.stage_files(model, file, {MESH_DIR: meshdir, TEXTURE_DIR: texturedir}, strip)
        model.name = self.vfs_name(path)
        self.stage(model.name, first.patches.applied(), path, resolved)
        for file in model.files[1:]:
            self.stage(self.by_path[(id(model), file.resolved)], file.patches.applied(), file.path, file.resolved)
        self.reading.pop()
        return model

    def splice(self, model: Model, file: ModelFile, top: bool, including: list[Path]) -> None:
        """Read ``file``'s includes (relative to the model's folder, as MuJoCo reads them) into
        ``model.files`` in document order, with the compiler sections at the model's top level."""
        for element in file.root.iter():
            if not isinstance(element.tag, str):
                continue
            at_top = top and element.getparent() is file.root
            if element.tag == "compiler" and at_top:
                model.compilers.append(element)
            elif element.tag == "include" and element.get("file") is not None:
                where = f"{file.display}:{element.sourceline}"
                path = model.folder / element.get("file", "")
                resolved = self.bundle.check_access(path)
                if resolved in including:
                    raise InputError(f"{where}: <include> of {element.get('file')} includes itself")
                if len(including) > self.limits.max_include_depth:
                    raise LimitExceeded(
                        f"{where}: <include> nested deeper than {self.limits.max_include_depth} files "
                        "(max_include_depth)"
                    )
                key = (id(model), resolved)
                if key not in self.by_path:
                    self.by_path[key] = self.vfs_name(path)
                included = self.parse(path, resolved)
                model.files.append(included)
                model.included[id(element)] = included
                file.patches.set(element, "file", self.by_path[key])
                self.splice(model, included, at_top, [*including, resolved])

    def stage_files(self, model: Model, file: ModelFile, folders: dict[str, str], strip: bool) -> None:
        """Stage the files ``file``'s elements name and write their VFS names in its copy."""
        for element in file.root.iter():
            if not isinstance(element.tag, str) or element.tag == "include":
                continue  # <include>: staged by splice
            tag, where = element.tag, f"{file.display}:{element.sourceline}"
            if tag == "compiler":  # the copies name every file absolutely: no folder to prepend
                for attribute in COMPILER_FOLDERS:
                    if element.get(attribute) is not None:
                        file.patches.set(element, attribute, "")
                if element.get("strippath") is not None:
                    file.patches.set(element, "strippath", "false")
            elif tag == "model" and element.get("file") is not None:
                sub = self.model(model.folder / element.get("file", ""), where)
                model.attached[element.get("name", "")] = sub
                file.patches.set(element, "file", sub.name)
            else:
                self.refuse_generated(element, where)
                attributes, kind = ASSET_FILES.get(tag, ((), MESH_DIR))
                for attribute in element.attrib:
                    if attribute in attributes:
                        self.asset(model, file, element, attribute, folders[kind], strip)
                    elif str(attribute).startswith("file"):
                        raise InputError(
                            f"{where}: <{tag} {attribute}>: MJCF names no file there (MuJoCo's schema refuses it); "
                            "geomcheck does not let MuJoCo open it"
                        )

    def asset(
        self, model: Model, file: ModelFile, element: etree._Element, attribute: str, folder: str, strip: bool
    ) -> None:
        """Stage the file ``element``'s ``attribute`` names (an empty name is MuJoCo's to judge)."""
        written = element.get(attribute, "")
        if not written:
            return
        name = re.split(r"[/\\]", written)[-1] if strip else written
        path = Path(name)
        if not path.is_absolute():
            path = Path(folder) / path if Path(folder).is_absolute() else model.folder / folder / path
        resolved = self.bundle.check_access(path)
        key = (id(model), resolved)
        if key not in self.by_path:
            vfs = self.vfs_name(path)
            self.by_path[key] = vfs
            self.staged.displays[vfs] = self.bundle.display(path)
            if resolved.exists() or resolved.is_symlink():
                display = self.bundle.display(path)
                data = read_regular_file(resolved, display, self.limits.max_mesh_bytes, "max_mesh_bytes")
                self.refuse_huge_image(data, f"{file.display}:{element.sourceline}", element.tag)
                self.stage(vfs, data, path, resolved)
            # a missing file stays out of the VFS: MuJoCo says whether it matters ("Error opening file")
        file.patches.set(element, attribute, self.by_path[key])

    def refuse_huge_image(self, data: bytes, where: str, tag: str) -> None:
        """:class:`LimitExceeded` for a PNG whose pixels would not fit the limit once decoded
        (a small file may declare gigapixels: MuJoCo would allocate them)."""
        if not data.startswith(PNG_SIGNATURE) or len(data) < 24:
            return
        width, height = struct.unpack(">II", data[16:24])
        if width * height > self.limits.max_image_pixels:
            raise LimitExceeded(
                f"{where}: <{tag}> image of {width} x {height} pixels exceeds the limit of "
                f"{self.limits.max_image_pixels} pixels (max_image_pixels)"
            )

    # -- the work of MuJoCo's parse -----------------------------------------------------------

    def refuse_generated(self, element: etree._Element, where: str) -> None:
        """:class:`LimitExceeded` for an asset MuJoCo generates beyond the limits from a few
        bytes: a texture of ``width`` x ``height`` pixels (six faces for a cube or skybox), a
        height field of ``nrow`` x ``ncol`` points, a builtin mesh of a given resolution
        (a 200-byte ``<texture builtin="checker" width="20000" height="20000">`` took 2.3 GiB;
        ``<mesh builtin="plate" params="3000 3000">`` 9 million vertices and 73 s)."""
        tag, limits = element.tag, self.limits
        if tag == "texture":
            faces = 6 if (element.get("type") or "").strip() in ("cube", "skybox") else 1
            size = faces * _integer(element.get("width")) * _integer(element.get("height"))
            what, bound, name = "pixels", limits.max_image_pixels, "max_image_pixels"
        elif tag == "hfield":
            size = _integer(element.get("nrow")) * _integer(element.get("ncol"))
            what, bound, name = "points", limits.max_image_pixels, "max_image_pixels"
        elif tag == "size":  # per-object numbers MuJoCo allocates for every object: ``nuser_geom="100000"``
            counts = {
                a: _integer(v) for a, v in element.attrib.items() if str(a) == "nkey" or str(a).startswith("nuser")
            }
            size = max(counts.values(), default=0)
            what, bound, name = "entries per object", limits.max_mjcf_elements, "max_mjcf_elements"
        elif tag == "mesh" and element.get("builtin") is not None:
            first, second = ([_integer(p) for p in (element.get("params") or "").split()[:2]] + [1, 1])[:2]
            size = first * (second if element.get("builtin", "").strip() == "plate" else first)  # a grid of them
            what, bound, name = "vertices", limits.max_builtin_mesh_vertices, "max_builtin_mesh_vertices"
        else:
            return
        if size > bound:
            raise LimitExceeded(
                f"{where}: <{tag}> makes {size} {what}, beyond the limit of {bound} ({name}); MuJoCo would build them"
            )

    def expansion(self, model: Model) -> int:
        """The elements ``model``'s worldbody makes once replicated and attached (memoised)."""
        if model.size is None:
            model.size = 0  # a loop of attachments counts nothing more (MuJoCo refuses it)
            first = model.files[0]
            model.size = sum(self.expanded(model, e, first.display) for e in first.root if e.tag == "worldbody")
        return model.size

    def expanded(self, model: Model, element: etree._Element, file: str) -> int:
        """The elements ``element`` makes once its ``<include>``s are spliced, its ``<replicate>``s
        repeated, its ``<attach>``es attached and its flexcomp grids laid out; :class:`LimitExceeded`
        naming the element as soon as that is beyond ``max_mjcf_elements``."""
        if not isinstance(element.tag, str):
            return 0
        tag = element.tag
        if tag == "include" and id(element) in model.included:
            included = model.included[id(element)]
            return sum(self.expanded(model, c, included.display) for c in included.root)
        inner = sum(self.expanded(model, child, file) for child in element)
        total = 1 + inner
        if tag == "replicate":
            total = 1 + inner * max(1, _integer(element.get("count")))
        elif tag == "attach" and element.get("model") in model.attached:
            total += self.expansion(model.attached[element.get("model", "")])
        elif tag == "flexcomp":
            counts = [max(1, _integer(c)) for c in (element.get("count") or "").split()[:3]]
            total += int(math.prod(counts)) if counts else 0
        budget = self.limits.max_mjcf_elements
        if total > budget:
            construct = {"replicate": "<replicate>s", "attach": "<attach>ed models", "flexcomp": "<flexcomp> points"}
            raise LimitExceeded(
                f"{file}:{element.sourceline}: <{tag}> expands to {total} elements "
                f"({construct.get(tag, 'the elements it holds')}), beyond the limit of {budget} (max_mjcf_elements)"
            )
        return total


def _integer(text: str | None) -> int:
    """An integer attribute as MuJoCo reads it; 1 for what it would refuse (its error follows)."""
    try:
        return int((text or "").split()[0])
    except (ValueError, IndexError):
        return 1


def stage_model(bundle: Bundle, limits: LoadLimits, data: bytes) -> StagedModel:
    """The root file of ``bundle`` (holding ``data``) and every file MuJoCo would read for it,
    staged for MuJoCo's VFS (see the module docstring); the work its parse would do counted
    first and refused beyond ``limits.max_mjcf_elements`` (:class:`LimitExceeded`)."""
    stager = Stager(bundle, limits)
    model = stager.model(bundle.root_file, bundle.display(bundle.root_file), data)
    stager.staged.root = model.name
    stager.staged.elements = stager.expansion(model)
    return stager.staged


def compile_staged(staged: StagedModel) -> Any:
    """MuJoCo's model of ``staged``, compiled from the VFS alone (raises MuJoCo's ``ValueError``)."""
    import mujoco

    with mujoco.MjVfs() as vfs:
        for name, data in staged.files.items():
            vfs[name] = data
        return mujoco.MjModel.from_xml_path(staged.root, vfs=vfs)
