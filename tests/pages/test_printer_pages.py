"""The printer's pages written directly (legacy/pdf.py) look as they did when matplotlib drew
them: every page of both renderings at 60 dots an inch (poppler's pdftoppm), pixel by pixel.

The writer puts every character exactly 1/10 inch after the one before (the 1403's pitch);
matplotlib's layout put each a little further right (its PDF adds a kern of 0.5627/1000 em
to the rounded width of 602/1000 em), 0.7 point at the 132nd position, 0.6 pixel at 60 dpi;
and the rasteriser places a glyph at a quarter of a pixel, so a glyph whose position differs
by a hair may fall on the next quarter and its anti-aliased edges differ in single pixels.
The check therefore compares the renderings seen as a reader's eye sees them at arm's length:
each averaged over 3 x 3 pixels (1/20 inch), the largest difference of those averages within
a tolerance; a negative control shows that one changed character exceeds it.  Run as a
script on two PDFs it prints the largest pixel difference (raw and averaged) and the share of
pixels that differ:  python tests/pages/test_printer_pages.py OLD.pdf NEW.pdf
"""

from __future__ import annotations

import io
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

DPI = 60
#: the largest difference of 3 x 3 averages (8-bit grey levels) that glyphs placed a fraction
#: of a pixel apart give (measured: 43 over every page of steel40's, plain and striped)
TOLERANCE = 56


def render(pdf: Path, folder: Path, first: int | None = None, last: int | None = None
           ) -> list[np.ndarray]:
    """Every page (or first..last) of ``pdf`` as an RGB array at DPI dots an inch."""
    folder.mkdir(parents=True, exist_ok=True)
    span = [*(["-f", str(first)] if first else []), *(["-l", str(last)] if last else [])]
    subprocess.run(["pdftoppm", "-r", str(DPI), *span, str(pdf), str(folder / "p")],
                   check=True, capture_output=True)
    pages = []
    for ppm in sorted(folder.glob("p-*.ppm"), key=lambda p: int(p.stem.split("-")[-1])):
        magic, width, height, _, data = ppm.read_bytes().split(maxsplit=4)
        assert magic == b"P6"
        pages.append(np.frombuffer(data, np.uint8).reshape(int(height), int(width), 3))
    return pages


def _averaged(page: np.ndarray) -> np.ndarray:
    """The page's grey level averaged over each pixel's 3 x 3 neighbourhood."""
    grey = page.astype(float).mean(axis=2)
    padded = np.pad(grey, 1, mode="edge")
    h, w = grey.shape
    return sum(padded[i : i + h, j : j + w] for i in range(3) for j in range(3)) / 9


def compare(old: list[np.ndarray], new: list[np.ndarray]) -> dict[str, float]:
    """The largest pixel difference (8-bit levels, any colour) and its page (1-based), the
    share of pixels that differ at all, and the largest difference of the 3 x 3 averages."""
    assert len(old) == len(new), (len(old), len(new))
    largest, page, differing, total, averaged = 0, 0, 0, 0, 0.0
    for k, (a, b) in enumerate(zip(old, new), start=1):
        assert a.shape == b.shape, (k, a.shape, b.shape)
        diff = np.abs(a.astype(int) - b.astype(int)).max(axis=2)
        if diff.max() > largest:
            largest, page = int(diff.max()), k
        differing += int((diff > 0).sum())
        total += diff.size
        averaged = max(averaged, float(np.abs(_averaged(a) - _averaged(b)).max()))
    return {"pages": len(old), "largest difference": largest, "on page": page,
            "share of pixels differing": round(differing / total, 5),
            "largest difference averaged 3x3": round(averaged, 1)}


def form_figure(form: list[tuple[int, str]], paper: str = "plain"):
    """One form as a matplotlib Figure, 14 7/8 by 11 inches, from the pages' own geometry: the
    independent drawing the direct writer is checked against."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, Rectangle

    from deck_emulator.legacy import pages as p

    w, h = p.PAGE_WIDTH_IN, p.PAGE_HEIGHT_IN
    fig = Figure(figsize=(w, h))
    for x, y, width, height in p.paper_bars(paper):
        fig.add_artist(Rectangle((x / w, y / h), width / w, height / h,
                                 transform=fig.transFigure, color=p.BAR_RGB, lw=0))
    for x, y in p.tractor_holes():
        fig.add_artist(Circle((x / w, y / h), p.HOLE_RADIUS_IN / w, transform=fig.transFigure,
                              fill=False, color=p.HOLE_RGB, lw=p.HOLE_LINE_PT))
    for line, first, text in p.printed_lines(form):
        fig.text(p.column_x_in(first) / w, p.baseline_in(line) / h, text,
                 family="DejaVu Sans Mono", size=p.FONT_SIZE_PT, ha="left", va="baseline")
    return fig


def _matplotlib_pdf(records: list[str], path: Path, paper: str) -> None:
    """The pages as they were drawn before: a matplotlib figure a form (form_figure), the
    TrueType face embedded as such (type 42)."""
    from matplotlib import rc_context
    from matplotlib.backends.backend_pdf import PdfPages

    from deck_emulator.legacy.pages import layout

    with rc_context({"pdf.fonttype": 42}), PdfPages(path, metadata={"CreationDate": None}) as pdf:
        for form in layout(records):
            pdf.savefig(form_figure(form, paper))


def _records(listing: bool) -> list[str]:
    """The banner page, the compile listing if asked, and steel40's printout, as `run
    steel40 --pages` prints them."""
    root = Path(__file__).resolve().parents[2]
    records = (root / "golden" / "steel40.r8.txt").read_text().splitlines()
    banner = ["1" + "*" * 131, " STEEL40  (A BANNER LINE ABOVE THE RECORDS)", "0"]
    if listing:
        from deck_emulator.legacy.listing import listing_records

        banner += listing_records(None)
    return banner + records


@pytest.mark.skipif(shutil.which("pdftoppm") is None, reason="needs poppler's pdftoppm")
@pytest.mark.parametrize("paper", ["plain", "striped"])
@pytest.mark.parametrize("forms", [
    pytest.param(14, marks=pytest.mark.slow),                      # banner, listing, output
    pytest.param(None, marks=pytest.mark.slow_corpus)])            # every page
def test_the_pages_look_as_matplotlib_drew_them(tmp_path, paper, forms):
    pytest.importorskip("matplotlib")
    from deck_emulator.legacy.pages import layout, write_pdf

    records = _records(listing=True)
    if forms is not None:  # the records of the first ``forms`` forms
        kept, seen = [], 0
        for record in records:
            seen += record[:1] == "1"
            if seen > forms:
                break
            kept.append(record)
        records = kept
    old, new = tmp_path / "old.pdf", tmp_path / "new.pdf"
    _matplotlib_pdf(records, old, paper)
    assert write_pdf(records, new, paper) == len(layout(records))
    # the text a reader (pypdf, as `compare` reads the pages) extracts: the same, page by page
    pypdf = pytest.importorskip("pypdf")
    assert ([page.extract_text() for page in pypdf.PdfReader(new).pages]
            == [page.extract_text() for page in pypdf.PdfReader(old).pages])
    result = compare(render(old, tmp_path / "old"), render(new, tmp_path / "new"))
    assert result["pages"] == len(layout(records))
    assert result["largest difference averaged 3x3"] <= TOLERANCE, result
    # the negative control: one character changed on the last form ('1' for an '8' of its
    # last printed record, or '#' for that record's last character) stands out of the tolerance
    at = max(k for k, r in enumerate(records) if r[1:].strip())
    line = records[at]
    column = line.find("8") if "8" in line else len(line) - 1
    changed = records[:at] + [line[:column] + ("1" if line[column] == "8" else "#")
                              + line[column + 1:]] + records[at + 1:]
    assert changed != records
    other = tmp_path / "changed.pdf"
    write_pdf(changed, other, paper)
    last = len(layout(records))
    control = compare(render(new, tmp_path / "n1", last, last),
                      render(other, tmp_path / "c1", last, last))
    assert control["largest difference averaged 3x3"] > TOLERANCE, control


# --------------------------------------------------------------- the writer, without rendering

#: what a 1403's chain printed and a listing's cards hold, and a few characters beyond
PRINTABLE = st.sampled_from(list("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 +-*/=().,$'")
                            + list("abcxyz_:;#@&%<>?!\"\\[]{}") + ["\u00e9", "\u03b8"])
RECORDS = st.lists(st.tuples(st.sampled_from(["1", " ", "0", "-", "", "X"]),
                             st.text(PRINTABLE, max_size=140)),
                   min_size=1, max_size=90).map(lambda rs: [c + t for c, t in rs])


def _expected(records: list[str]) -> list[list[str]]:
    """Each form's printed lines, as layout() and printed_lines() say (tested by hand in
    tests/legacy/test_cards.py)."""
    from deck_emulator.legacy.pages import layout, printed_lines

    return [[text for _, _, text in printed_lines(form)] for form in layout(records)]


@settings(max_examples=30, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(records=RECORDS, paper=st.sampled_from(["plain", "striped"]))
def test_each_page_extracts_as_its_records_printed(tmp_path, records, paper):
    """A reader extracts each form's records in the order printed, each with its own spacing:
    the text is one string a printed line, in the embedded face's ToUnicode map."""
    pypdf = pytest.importorskip("pypdf")
    from deck_emulator.legacy.pages import write_pdf

    # a record overprinted ('+') is a second string on its line's baseline, which a reader
    # joins with the line it prints over: its order is not a reader's to give
    assume(not any(record.startswith("+") for record in records))
    pdf = tmp_path / "p.pdf"
    expected = _expected(records)
    assert write_pdf(records, pdf, paper) == len(expected)
    pages = pypdf.PdfReader(pdf).pages
    assert [page.extract_text().splitlines() for page in pages] == expected


@pytest.mark.skipif(shutil.which("pdftotext") is None, reason="needs poppler's pdftotext")
def test_pdftotext_reads_each_record_of_steel40(tmp_path):
    """poppler's reader, in the content's order (-raw), gives each record's words, form by
    form (it reads runs of spaces as one)."""
    from deck_emulator.legacy.pages import write_pdf

    records = _records(listing=False)
    pdf = tmp_path / "s.pdf"
    write_pdf(records, pdf)
    text = subprocess.run(["pdftotext", "-raw", str(pdf), "-"], check=True,
                          capture_output=True, text=True).stdout
    pages = text.split("\f")[:-1]  # a form feed after each page
    expected = _expected(records)
    assert len(pages) == len(expected)
    for page, lines in zip(pages, expected):
        assert ([" ".join(line.split()) for line in page.splitlines() if line.strip()]
                == [" ".join(line.split()) for line in lines])


def test_the_face_is_the_subset_of_the_characters_printed(tmp_path):
    """One embedded TrueType subset, a glyph for each character printed (and .notdef), each
    advancing 1233/2048 em: 1/10 inch at the pages' size; a character the face lacks is
    drawn as .notdef and the others are not disturbed."""
    pypdf = pytest.importorskip("pypdf")
    from fontTools.ttLib import TTFont

    from deck_emulator.legacy.pages import FONT_SIZE_PT, write_pdf

    records = ["1 THE VALUE OF VVA IS       -58.60262", "0 T = 0.0016  \ue000 (unmapped)"]
    pdf = tmp_path / "p.pdf"
    write_pdf(records, pdf)
    reader = pypdf.PdfReader(pdf)
    (font,) = [ref.get_object() for ref in reader.pages[0]["/Resources"]["/Font"].values()]
    descendant = font["/DescendantFonts"][0].get_object()
    data = descendant["/FontDescriptor"].get_object()["/FontFile2"].get_object().get_data()
    face = TTFont(io.BytesIO(data))
    used = {ord(c) for r in records for c in r[1:] if c != "\ue000"}
    assert set(face.getBestCmap()) == used
    assert face.getGlyphOrder()[0] == ".notdef"
    assert {face["hmtx"][name][0] for name in face.getGlyphOrder()} <= {1233, 0}
    widths = descendant["/W"][1]
    assert {float(w) for w in widths} <= {1233 / 2048 * 1000, 0.0}
    assert float(widths[1 if len(widths) > 1 else 0]) * FONT_SIZE_PT / 1000 in (
        pytest.approx(7.2), 0.0)
    lines = reader.pages[0].extract_text().splitlines()
    assert lines[0] == "THE VALUE OF VVA IS       -58.60262"
    assert lines[1].startswith("T = 0.0016") and lines[1].endswith("(unmapped)")


def test_the_information_is_the_callers_text_exactly(tmp_path, monkeypatch):
    """The metadata are data: parentheses, backslashes and non-ASCII text come back as
    given (PDF literal strings escaped, UTF-16 beyond ASCII); no date without
    SOURCE_DATE_EPOCH, its date with it."""
    pypdf = pytest.importorskip("pypdf")
    from deck_emulator.legacy.pages import write_pdf

    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    given = {"Title": "deck (a) \\ b) ) ((", "Subject": "Bahnhofstraße θ — ok",
             "Keywords": "k: v; ", "Creator": "deck_emulator 0.1.0"}
    pdf = tmp_path / "m.pdf"
    write_pdf([" X"], pdf, metadata=given)
    info = pypdf.PdfReader(pdf).metadata
    assert {key: info[f"/{key}"] for key in given} == given
    assert "/CreationDate" not in info and info["/Producer"].startswith("deck_emulator ")
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1000000000")  # 2001-09-09 01:46:40 UTC
    write_pdf([" X"], pdf, metadata=given)
    assert pypdf.PdfReader(pdf).metadata["/CreationDate"] == "D:20010909014640Z"
    with pytest.raises(ValueError, match="not a PDF name"):
        write_pdf([" X"], pdf, metadata={"Bad Key": "x"})


def test_a_banner_line_and_a_closing_page_are_records_like_the_others(tmp_path):
    """Text the tool adds to the printout (a banner line above the records, a closing page of
    plain lines after them, as a stopped run's pages carry) goes through the same path as
    the printer's records: its own forms, the same face, extracted as written."""
    pypdf = pytest.importorskip("pypdf")
    from deck_emulator.legacy.pages import write_pdf

    banner = ["1" + "*" * 131, " DECK_EMULATOR  --  JOB SEPARATOR", " STOPPED at label ED 1"]
    printout = ["1", " THE VALUE OF VVA IS       -58.60262", "0 T = 0.0016"]
    closing = ["1" + "=" * 131, " ", " DECK_EMULATOR  --  THE RUN STOPPED", "0",
               " WHERE   label ED 1; its printout ends with record 3", " WHY     root search"]
    pdf = tmp_path / "p.pdf"
    assert write_pdf(banner + printout + closing, pdf) == 3
    pages = [p.extract_text().splitlines() for p in pypdf.PdfReader(pdf).pages]
    assert pages[0][-1] == "STOPPED at label ED 1"
    assert pages[1] == ["THE VALUE OF VVA IS       -58.60262", "T = 0.0016"]
    assert pages[2] == ["=" * 131, "DECK_EMULATOR  --  THE RUN STOPPED",
                        "WHERE   label ED 1; its printout ends with record 3",
                        "WHY     root search"]


def test_the_pages_need_no_matplotlib(tmp_path):
    """The light install writes the pages: nothing of matplotlib is imported (it is made
    unimportable here), the face is the package's own file, its licence beside it."""
    from deck_emulator.legacy.pages import face_file

    assert (face_file().parent / "LICENSE_DEJAVU").read_text().startswith("Fonts are (c)")
    script = (
        "import sys; sys.modules['matplotlib'] = None\n"
        "from deck_emulator.legacy.pages import write_pdf\n"
        f"print(write_pdf(['1 A', '1 B'], {str(tmp_path / 'p.pdf')!r}, 'striped'))\n"
        "print(sorted(m for m in sys.modules if m.startswith('matplotlib')))\n")
    root = Path(__file__).resolve().parents[2]
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(root / "src")}, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split("\n")[:2] == ["2", "['matplotlib']"]  # only the blocked entry


if __name__ == "__main__":
    old_pdf, new_pdf = map(Path, sys.argv[1:3])
    with tempfile.TemporaryDirectory() as tmp:
        print(compare(render(old_pdf, Path(tmp) / "old"), render(new_pdf, Path(tmp) / "new")))
