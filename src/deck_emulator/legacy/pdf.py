"""A small PDF writer for pages of monospaced text and a few filled or stroked shapes: what a
line printer's forms need, written directly (one text object a page, one string a printed
line) rather than through a plotting library's figure a page.

The face is one TrueType font, embedded as a CIDFontType2 (``Identity-H``, the character
codes are the glyph numbers of the embedded subset) with a ``ToUnicode`` map, so that a
reader extracts the text as it was printed.  The subset holds only the characters the
document uses and is made once a document with fontTools' subsetter.

The bytes depend on nothing but the arguments: no date unless the caller passes one, no
random font tag (it is derived from the characters used), objects numbered in a fixed order.
"""

from __future__ import annotations

import hashlib
import io
import math
import re
import zlib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

__all__ = ["Face", "Rect", "Ellipse", "TextLine", "write_document", "pdf_text_string"]

#: the unit circle as eight cubic Bezier arcs of 45 degrees from its lowest point,
#: anticlockwise: each arc's control points 4/3 tan(45/4 degrees) of the radius along the
#: tangents (within 0.0003 % of the radius of the circle)
_ARC = 4 / 3 * math.tan(math.radians(45 / 4))


def _ellipse_path(cx: float, cy: float, rx: float, ry: float) -> str:
    """A closed, stroked ellipse (axes along x and y) as PDF path operators."""
    points = []
    for k in range(9):
        a = math.radians(-90 + 45 * k)
        points.append((math.cos(a), math.sin(a)))
    ops = [f"{_num(cx)} {_num(cy - ry)} m"]
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        c = [(x0 - _ARC * y0, y0 + _ARC * x0), (x1 + _ARC * y1, y1 - _ARC * x1), (x1, y1)]
        ops.append(" ".join(f"{_num(cx + rx * u)} {_num(cy + ry * v)}" for u, v in c) + " c")
    return " ".join(ops) + " s"


@dataclass(frozen=True)
class Rect:
    """A filled rectangle, in points from the page's lower left corner."""

    x: float
    y: float
    width: float
    height: float
    rgb: tuple[float, float, float]


@dataclass(frozen=True)
class Ellipse:
    """A stroked ellipse: centre, radii and line width in points."""

    cx: float
    cy: float
    rx: float
    ry: float
    rgb: tuple[float, float, float]
    line_width: float


@dataclass(frozen=True)
class TextLine:
    """A string whose first character's origin (on the baseline) is at (x, y) points."""

    x: float
    y: float
    text: str


def _num(value: float, decimals: int = 6) -> str:
    """A PDF number: at most ``decimals`` decimals, no exponent, no trailing zeros."""
    text = f"{value:.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def pdf_text_string(text: str) -> bytes:
    """A PDF text string: printable ASCII as a literal (with ``\\``, ``(`` and ``)``
    escaped), anything else as UTF-16BE with its byte order mark, in hex."""
    if all(" " <= c <= "~" for c in text):
        return b"(" + re.sub(rb"([\\()])", rb"\\\1", text.encode("ascii")) + b")"
    return b"<feff" + text.encode("utf-16-be").hex().encode("ascii") + b">"


_NAME = re.compile(r"[A-Za-z][A-Za-z0-9]*")


class Face:
    """A TrueType face subset to the characters of one document.

    ``path``: the font file (a path or an importlib.resources file); ``characters``: every
    character the document draws (one subset a document).  A character the face has no
    glyph for is drawn as the face's ``.notdef`` glyph (an empty box) and extracts as
    nothing."""

    def __init__(self, path, characters: Iterable[str]):
        from fontTools import subset

        used = "".join(sorted(set(characters)))
        options = subset.Options()
        options.layout_features = []   # no shaping in a PDF's text: GSUB/GPOS unused
        options.notdef_outline = True  # the box drawn for a character the face lacks
        options.recommended_glyphs = True
        options.drop_tables += ["FFTM", "GSUB", "GPOS", "GDEF"]  # FFTM: FontForge's timestamp
        # read whole (a package resource need not be a file); recalc_timestamp is False
        # by default, so the subset keeps the font's own dates: nothing of today's
        font = subset.load_font(io.BytesIO(path.read_bytes()), options)
        subsetter = subset.Subsetter(options=options)
        subsetter.populate(text=used)
        subsetter.subset(font)
        out = io.BytesIO()
        font.save(out)
        self.file = out.getvalue()
        order = font.getGlyphOrder()
        cmap = font.getBestCmap()
        self.gid = {c: order.index(cmap[ord(c)]) for c in used if ord(c) in cmap}
        self._codes = {c: f"{g:04x}" for c, g in self.gid.items()}
        head, hhea, hmtx = font["head"], font["hhea"], font["hmtx"]
        scale = 1000 / head.unitsPerEm
        self.widths = [hmtx[name][0] * scale for name in order]  # per glyph, 1/1000 em
        self.bbox = [round(v * scale) for v in (head.xMin, head.yMin, head.xMax, head.yMax)]
        self.ascent, self.descent = round(hhea.ascent * scale), round(hhea.descent * scale)
        os2 = font["OS/2"]
        self.cap_height = round(getattr(os2, "sCapHeight", 0) * scale) or self.ascent
        self.fixed_pitch = bool(font["post"].isFixedPitch)
        family = font["name"].getDebugName(6) or "Embedded"
        self.name = re.sub(r"[^A-Za-z0-9-]", "", family)
        # the subset's tag (six capitals, ISO 32000 9.6.4): from the characters, not chance
        digest = hashlib.sha256(used.encode("utf-8", "surrogatepass")).digest()
        self.tag = "".join(chr(65 + b % 26) for b in digest[:6])

    def encode(self, text: str) -> bytes:
        """The text as a hex string of two-byte glyph numbers (0, .notdef, if missing)."""
        codes = self._codes
        return b"<" + "".join([codes.get(c, "0000") for c in text]).encode("ascii") + b">"

    def to_unicode(self) -> bytes:
        """The ToUnicode CMap: each glyph number back to its character (the first, where
        the face draws several characters with one glyph)."""
        back: dict[int, str] = {}
        for char, gid in sorted(self.gid.items()):
            back.setdefault(gid, char)
        pairs = sorted(back.items())
        lines = [b"/CIDInit /ProcSet findresource begin", b"12 dict begin", b"begincmap",
                 b"/CIDSystemInfo << /Registry (Adobe) /Ordering (UCS) /Supplement 0 >> def",
                 b"/CMapName /Adobe-Identity-UCS def", b"/CMapType 2 def",
                 b"1 begincodespacerange", b"<0000> <ffff>", b"endcodespacerange"]
        for at in range(0, len(pairs), 100):
            chunk = pairs[at : at + 100]
            lines.append(f"{len(chunk)} beginbfchar".encode())
            for gid, char in chunk:
                lines.append(f"<{gid:04x}> <{char.encode('utf-16-be').hex()}>".encode())
            lines.append(b"endbfchar")
        lines += [b"endcmap", b"CMapName currentdict /CMap defineresource pop", b"end", b"end"]
        return b"\n".join(lines) + b"\n"


def shapes_content(shapes: Sequence[Rect | Ellipse]) -> bytes:
    """Operators drawing the shapes in order (what every page has in common, written once a
    document as a form XObject: see :func:`write_document`)."""
    ops: list[str] = []
    fill = stroke = None
    for shape in shapes:
        rgb = " ".join(_num(v) for v in shape.rgb)
        if isinstance(shape, Rect):
            if fill != rgb:
                ops.append(f"{rgb} rg")
                fill = rgb
            ops.append(f"{_num(shape.x)} {_num(shape.y)} {_num(shape.width)} "
                       f"{_num(shape.height)} re f")
        else:
            if stroke != (rgb, shape.line_width):
                ops.append(f"{rgb} RG {_num(shape.line_width)} w")
                stroke = (rgb, shape.line_width)
            ops.append(_ellipse_path(shape.cx, shape.cy, shape.rx, shape.ry))
    return "\n".join(ops).encode("ascii")


def page_content(lines: Sequence[TextLine], face: Face, size_pt: float,
                 background: bool = False) -> bytes:
    """One page's content stream: the background (the document's form XObject), then the
    text, one string a line."""
    out = [b"/Bg Do"] if background else []
    if lines:
        out += [b"BT", f"/F1 {_num(size_pt, 10)} Tf 0 g".encode()]
        for line in lines:
            out.append(f"1 0 0 1 {_num(line.x)} {_num(line.y)} Tm ".encode()
                       + face.encode(line.text) + b" Tj")
        out.append(b"ET")
    return b"\n".join(out)


def write_document(stream, pages: Iterable[bytes], count: int, face: Face,
                   width_pt: float, height_pt: float, info: dict[str, bytes],
                   background: bytes = b"", on_page=None) -> None:
    """Write a PDF of ``count`` pages to the binary file ``stream``: each of ``pages`` a
    content stream (see :func:`page_content`) drawn with ``face`` as font ``/F1`` and
    ``background`` (operators, e.g. from :func:`shapes_content`) as the form XObject
    ``/Bg``; ``info`` the document information (name -> a PDF string, e.g. from
    :func:`pdf_text_string`).  ``on_page`` is called after each page is written."""
    for key in info:
        if not _NAME.fullmatch(key):
            raise ValueError(f"document information key {key!r} is not a PDF name")
    offsets: dict[int, int] = {}
    position = 0

    def put(data: bytes) -> None:
        nonlocal position
        stream.write(data)
        position += len(data)

    def obj(number: int, body: bytes, data: bytes | None = None) -> None:
        offsets[number] = position
        if data is None:
            put(b"%d 0 obj\n%s\nendobj\n" % (number, body))
        else:
            packed = zlib.compress(data, 6)
            put(b"%d 0 obj\n<< %s /Length %d /Filter /FlateDecode >>\nstream\n"
                % (number, body, len(packed)) + packed + b"\nendstream\nendobj\n")

    # 1 catalog, 2 page tree, 3 resources, 4-8 the font, 9 info, 10 the background; then
    # each page and its content
    catalog, tree, resources, font, cid, descriptor, file, unicode, info_at, bg = range(1, 11)
    first = 11
    box = b"[0 0 %s %s]" % (_num(width_pt).encode(), _num(height_pt).encode())
    put(b"%PDF-1.4\n%\xe2\xe3\xcf\xd3\n")
    obj(catalog, b"<< /Type /Catalog /Pages %d 0 R >>" % tree)
    kids = b" ".join(b"%d 0 R" % (first + 2 * k) for k in range(count))
    obj(tree, b"<< /Type /Pages /Kids [%s] /Count %d /MediaBox %s >>" % (kids, count, box))
    obj(resources, b"<< /Font << /F1 %d 0 R >> /XObject << /Bg %d 0 R >> "
        b"/ProcSet [/PDF /Text] >>" % (font, bg))
    obj(bg, b"/Type /XObject /Subtype /Form /BBox %s" % box, background)
    written = 0
    for k, content in enumerate(pages):
        if k >= count:
            raise ValueError(f"more than the {count} pages announced")
        page = first + 2 * k
        obj(page, b"<< /Type /Page /Parent %d 0 R /Resources %d 0 R /Contents %d 0 R >>"
            % (tree, resources, page + 1))
        obj(page + 1, b"", content)
        written += 1
        if on_page is not None:
            on_page()
    if written != count:
        raise ValueError(f"{written} pages written of the {count} announced")
    base = f"/{face.tag}+{face.name}".encode()
    obj(font, b"<< /Type /Font /Subtype /Type0 /BaseFont %s /Encoding /Identity-H "
        b"/DescendantFonts [%d 0 R] /ToUnicode %d 0 R >>" % (base, cid, unicode))
    widths = " ".join(_num(w, 8) for w in face.widths).encode()  # 1233/2048 em exactly
    obj(cid, b"<< /Type /Font /Subtype /CIDFontType2 /BaseFont %s /CIDSystemInfo "
        b"<< /Registry (Adobe) /Ordering (Identity) /Supplement 0 >> /FontDescriptor %d 0 R "
        b"/CIDToGIDMap /Identity /W [0 [%s]] >>" % (base, descriptor, widths))
    flags = (1 if face.fixed_pitch else 0) | 32  # FixedPitch, Nonsymbolic
    obj(descriptor, (b"<< /Type /FontDescriptor /FontName %s /Flags %d /FontBBox [%s] "
                     b"/ItalicAngle 0 /Ascent %d /Descent %d /CapHeight %d /StemV 80 "
                     b"/FontFile2 %d 0 R >>")
        % (base, flags, " ".join(map(str, face.bbox)).encode(), face.ascent, face.descent,
           face.cap_height, file))
    obj(file, b"/Length1 %d" % len(face.file), face.file)
    obj(unicode, b"", face.to_unicode())
    obj(info_at, b"<< " + b" ".join(b"/%s %s" % (k.encode(), v) for k, v in info.items())
        + b" >>")
    last = first + 2 * count
    xref = position
    table = [b"xref\n0 %d\n0000000000 65535 f \n" % last]
    for number in range(1, last):
        table.append(b"%010d 00000 n \n" % offsets[number])
    put(b"".join(table))
    put(b"trailer\n<< /Size %d /Root %d 0 R /Info %d 0 R >>\nstartxref\n%d\n%%%%EOF\n"
        % (last, catalog, info_at, xref))
