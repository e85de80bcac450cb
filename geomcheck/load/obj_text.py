"""Wavefront OBJ text read as trimesh's loader reads it: lines, keywords and numbers, with numpy.

The first half of :mod:`geomcheck.load.obj`: the file's bytes decoded and split into lines of
the kinds trimesh looks for (:func:`split_lines`), the numbers of ``v``, ``vt``, ``vn`` and
``f`` lines read with the same numpy calls trimesh makes (:func:`parse_numbers`,
:func:`vertex_positions`), and the byte classes the face references are checked with.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

# beyond this the positions and counts below could overflow; the mesh store refuses files
# far smaller (LoadLimits.max_mesh_bytes)
MAX_OBJ_BYTES = 1 << 30  # [bytes]
# usemtl lines read one by one (their names decide the meshes), and materials (one mesh each,
# each built apart); a file with more is left to trimesh
MAX_MATERIAL_LINES = 100_000
MAX_MATERIALS = 1_000
# trimesh's scene root: a mesh named after it would hang under itself in the scene graph
SCENE_ROOT = "world"
# magnitude from which a face integer is refused: numpy saturates what overflows int64 where
# Python's int (trimesh's reader of mixed polygons) raises; no file indexes this far [count]
INDEX_LIMIT = 1 << 31
POSITION = 3  # numbers of a vertex's position, the first on its v line (w or colours may follow)
TEXTURE_WIDTHS = (2, 3)  # numbers on a vt line: u v, u v w
NORMAL_WIDTHS = (3,)  # numbers on a vn line
# a material whose indices are fewer than the vertices over this is re-indexed by sorting
SPARSE_GROUP = 16  # [vertices per index]

# line kinds, by the bytes a line starts with: what trimesh searches its text for ("\nv ",
# "\nf ", "\nusemtl " ...); it passes over every other line (comments, blank or indented
# lines, mtllib, l, p, vp, curves ...), and so does this reader
VERTEX, TEXTURE, NORMAL, FACE, MATERIAL, OBJECT, GROUP, SMOOTH, OTHER = range(9)
KEYWORD, LONGER, UNKNOWN = range(9, 12)  # keyword bytes; lines whose kind is not told yet, or refused
KEYWORDS = {
    VERTEX: b"v ",
    TEXTURE: b"vt ",
    NORMAL: b"vn ",
    FACE: b"f ",  # trimesh cuts face lines at "^f": "f" then anything but a space is refused
    MATERIAL: b"usemtl ",
    OBJECT: b"o ",
    GROUP: b"g ",
    SMOOTH: b"s ",
}
STARTERS = (MATERIAL, OBJECT, FACE, GROUP, SMOOTH)  # the statements trimesh's face chunk starts at
NEWLINE, SPACE, TAB = ord("\n"), ord(" "), ord("\t")
SIGNS = np.frombuffer(b"+-", dtype=np.uint8)

# byte classes of number text
INVALID, SEPARATOR, DIGIT, DOT, SIGN, EXPONENT, SLASH = range(7)
# face reference forms and the integers each holds
FORM_V, FORM_V_VT, FORM_V_VT_VN, FORM_V_VN = range(4)
FORM_WIDTH = {FORM_V: 1, FORM_V_VT: 2, FORM_V_VT_VN: 3, FORM_V_VN: 2}

Arrays = tuple[np.ndarray, np.ndarray]  # vertices (n, 3) float64, faces (m, 3) int64
Polygons = tuple[np.ndarray, list[np.ndarray], bool]  # vertex indices, texture/normal indices, one corner count


def _class_table(signs: bytes, extra: dict[int, int]) -> np.ndarray:
    """A (256,) uint8 table of byte classes: space, tab and newline separate, digits,
    ``signs`` and ``extra``; any other byte is INVALID."""
    table = np.full(256, INVALID, dtype=np.uint8)
    table[[SPACE, TAB, NEWLINE]] = SEPARATOR
    table[ord("0") : ord("9") + 1] = DIGIT
    table[list(signs)] = SIGN
    for byte, kind in extra.items():
        table[byte] = kind
    return table


FLOAT_CLASSES = _class_table(b"+-", {ord("."): DOT, ord("e"): EXPONENT, ord("E"): EXPONENT})
INDEX_CLASSES = _class_table(b"-", {ord("/"): SLASH})


def decoded_text(data: bytes) -> np.ndarray | None:
    """The file's text as trimesh sees it, as a (b,) uint8 array: decoded as UTF-8, stripped,
    CRLF made LF, continuations joined, one newline before and after; ``None`` when it is not
    UTF-8 (trimesh guesses an encoding then) or holds control characters other than tab and
    newline (a lone CR included: trimesh only turns CRLF into LF)."""
    if data.isascii():  # bytes and str strip alike here (the controls str also strips are refused)
        raw = data.strip()
        raw = b"\n" + (raw.replace(b"\r\n", b"\n") if b"\r" in raw else raw) + b"\n"
    else:
        try:
            raw = ("\n" + data.decode("utf-8").strip().replace("\r\n", "\n") + "\n").encode("utf-8")
        except UnicodeDecodeError:  # trimesh asks charset_normalizer: its guess is not modelled
            return None
    if b"\\" in raw:
        raw = raw.replace(b"\\\n", b"")
    return None if b"\x7f" in raw else np.frombuffer(raw, dtype=np.uint8)


def _pair_kinds() -> np.ndarray:
    """A (65536,) uint8 table of line kinds by a line's first two bytes (``first << 8 | second``):
    LONGER where a longer keyword could start, UNKNOWN for "f" then anything but a space."""
    table = np.full(1 << 16, OTHER, dtype=np.uint8)
    face = ord("f") << 8
    table[face : face + 256] = UNKNOWN
    for kind, keyword in KEYWORDS.items():
        table[keyword[0] << 8 | keyword[1]] = kind if len(keyword) == 2 else LONGER
    return table


PAIR_KINDS = _pair_kinds()


@dataclass(frozen=True)
class Lines:
    """The text's lines: ``buf`` (b,) uint8 the text; ``starts``, ``ends`` (k,) the offsets
    of each line's first byte and of its newline; ``kinds`` (k,) each line's kind."""

    buf: np.ndarray
    starts: np.ndarray
    ends: np.ndarray
    kinds: np.ndarray

    @functools.cached_property
    def byte_kinds(self) -> np.ndarray:
        """(b,) the kind of the line each byte belongs to, KEYWORD on the keywords of vertex and face lines."""
        lengths = np.diff(self.ends, prepend=0)  # each line with its newline; the text's first byte is a newline
        byte_kinds = np.repeat(np.concatenate([[OTHER], self.kinds]).astype(np.uint8), np.concatenate([[1], lengths]))
        for kind in (VERTEX, TEXTURE, NORMAL, FACE):
            chosen = self.starts[self.kinds == kind]
            for i in range(len(KEYWORDS[kind])):
                byte_kinds[chosen + i] = KEYWORD
        return byte_kinds

    def body(self, kind: int) -> np.ndarray:
        """The bytes of the ``kind`` lines, keywords blanked or left out, each line with its newline."""
        rows = np.flatnonzero(self.kinds == kind)
        if not len(rows):
            return self.buf[:0]
        if rows[-1] - rows[0] + 1 == len(rows):  # one block of lines: one slice
            first = self.starts[rows[0]]
            text = self.buf[first : self.ends[rows[-1]] + 1].copy()
            for i in range(len(KEYWORDS[kind])):
                text[self.starts[rows] - first + i] = SPACE
            return text
        return self.buf[self.byte_kinds == kind]

    def offsets(self, kind: int) -> np.ndarray:
        """(k,) where each ``kind`` line starts in :meth:`body`."""
        rows = np.flatnonzero(self.kinds == kind)
        if len(rows) and rows[-1] - rows[0] + 1 == len(rows):
            return self.starts[rows] - self.starts[rows[0]]
        lengths = self.ends[rows] - self.starts[rows] + 1 - len(KEYWORDS[kind])
        return np.cumsum(lengths) - lengths

    def text(self, line: int) -> str:
        """Line number ``line``, without its newline."""
        return self.buf[self.starts[line] : self.ends[line]].tobytes().decode("utf-8")


def split_lines(buf: np.ndarray) -> Lines | None:
    """The lines of ``buf`` and their kinds; ``None`` when a line is of no kind modelled here."""
    newlines = np.flatnonzero(buf == NEWLINE)
    controls = np.count_nonzero(buf < SPACE) - len(newlines)
    if controls and controls != buf.tobytes().count(b"\t"):
        return None  # the bytes below a space other than newlines and tabs
    starts, ends = newlines[:-1] + 1, newlines[1:]
    # the text ends with a newline: a line's second byte is always inside it
    kinds = PAIR_KINDS[(buf[starts].astype(np.uint16) << 8) | buf[np.minimum(starts + 1, len(buf) - 1)]]
    for kind, keyword in KEYWORDS.items():
        if len(keyword) > 2:
            rows = np.flatnonzero(kinds == LONGER)
            rows = rows[(buf[starts[rows]] == keyword[0]) & (buf[starts[rows] + 1] == keyword[1])]
            match = np.ones(len(rows), dtype=bool)
            for i, byte in enumerate(keyword[2:], start=2):  # a line's newline ends any match
                match &= buf[np.minimum(starts[rows] + i, len(buf) - 1)] == byte
            kinds[rows[match]] = kind
    kinds[kinds == LONGER] = OTHER  # "vt\t", "usemtl\n": not what trimesh looks for
    return None if (kinds == UNKNOWN).any() else Lines(buf, starts, ends, kinds)


def parse_numbers(text: bytes, dtype: type) -> np.ndarray | None:
    """The whitespace-separated numbers of ``text`` read as trimesh reads them, with
    ``np.fromstring`` (floats correctly rounded); ``None`` where numpy fails to read it all."""
    try:
        values: np.ndarray = np.fromstring(text, sep=" ", dtype=dtype)
    except (ValueError, DeprecationWarning):
        # numpy >= 2.3 raises on text it cannot read to its end (so does trimesh then); older
        # numpy warns and stops, an error where warnings are errors
        return None
    return values


def _first_count(body: np.ndarray) -> int:
    """Tokens on the first line of ``body``: the row width trimesh takes for a kind of line."""
    return len(body[: int(np.argmax(body == NEWLINE))].tobytes().split())


def neighbours(classes: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(previous, current, next)`` byte classes of ``classes`` (n,), a separator beyond each end."""
    padded = np.concatenate([[SEPARATOR], classes, [SEPARATOR]]).astype(np.uint8)
    return padded[:-2], padded[1:-1], padded[2:]


def _tokens_per_line(text: np.ndarray, token_starts: np.ndarray) -> np.ndarray:
    """Tokens (k,) on each of the k newline-terminated lines of ``text``, given the tokens' starts."""
    return np.diff(np.searchsorted(token_starts, np.flatnonzero(text == NEWLINE)), prepend=0)


def owner(positions: np.ndarray, token_starts: np.ndarray) -> np.ndarray:
    """The token (len(positions),) each of ``positions`` falls in."""
    return np.searchsorted(token_starts, positions, side="right") - 1


def _decimal_tokens(text: np.ndarray) -> np.ndarray | None:
    """Tokens (k,) on each line of ``text`` when every token is a plain decimal number
    (``[+-]digits[.digits][e[+-]digits]``, which numpy and Python's float read alike), else ``None``."""
    previous, current, following = neighbours(FLOAT_CLASSES[text])
    token_starts = np.flatnonzero((current != SEPARATOR) & (previous == SEPARATOR))
    # each rule names a byte that cannot be where it is in a decimal number
    malformed = (
        (current == INVALID)
        | ((current == SIGN) & (previous != SEPARATOR) & (previous != EXPONENT))
        | ((current == SIGN) & (following != DIGIT) & ~((following == DOT) & (previous == SEPARATOR)))
        | ((current == EXPONENT) & (previous != DIGIT) & (previous != DOT))
        | ((current == EXPONENT) & (following != DIGIT) & (following != SIGN))
        | ((current == DOT) & (previous != SEPARATOR) & (previous != SIGN) & (previous != DIGIT))
        | ((current == DOT) & ((previous == SEPARATOR) | (previous == SIGN)) & (following != DIGIT))
    )
    if malformed.any():
        return None
    dots, exponents = np.flatnonzero(current == DOT), np.flatnonzero(current == EXPONENT)
    for marks in (dots, exponents):
        if len(marks) and np.bincount(owner(marks, token_starts)).max() > 1:
            return None
    if len(exponents):
        exponent_at = np.full(len(token_starts), len(text), dtype=np.int64)
        exponent_at[owner(exponents, token_starts)] = exponents
        if (dots > exponent_at[owner(dots, token_starts)]).any():
            return None  # 1e5.5
    return _tokens_per_line(text, token_starts)


def _floats(body: np.ndarray) -> np.ndarray | None:
    """All numbers of ``v``, ``vt`` or ``vn`` lines' ``body`` read at once as trimesh reads
    them; ``None`` where numpy cannot, or where trimesh reads other text: it deletes the sign
    before every "e" first."""
    before = body[np.flatnonzero(body[1:] == ord("e"))]
    return None if np.isin(before, SIGNS).any() else parse_numbers(body.tobytes(), np.float64)


def vertex_positions(body: np.ndarray, lines: int) -> np.ndarray | None:
    """The vertices (k, 3) float64 trimesh reads from the ``body`` of ``lines`` ``v`` lines:
    all numbers at once, as rows of the first line's count when the total allows, else each
    line clipped to the shortest (read one by one); x y z kept. ``None`` for fewer than 3
    numbers a row."""
    values = _floats(body)
    if values is None:
        return None
    width = _first_count(body)
    if len(values) == lines * width:
        return values.reshape(lines, width)[:, :POSITION] if width >= POSITION else None
    # trimesh's slow path reads each token with Python's float: plain decimals read alike
    counts = _decimal_tokens(body)
    if counts is None or counts.sum() != len(values) or counts.min() < POSITION:
        return None
    first = np.cumsum(counts) - counts
    return values[first[:, None] + np.arange(POSITION)]


def readable(body: np.ndarray, lines: int, widths: tuple[int, ...]) -> bool:
    """Whether trimesh reads the ``body`` of ``lines`` ``vt`` or ``vn`` lines without raising,
    as rows of one of ``widths`` (their values do not reach the geometry)."""
    values = _floats(body)
    width = _first_count(body)
    return values is not None and width in widths and len(values) == lines * width
