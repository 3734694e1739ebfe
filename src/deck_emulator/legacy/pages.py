"""The printout as the line printer laid it on paper: pages, as PDF.

The printer is an IBM 1403 (its manuals, as summarised in the reference notes): 132 print
positions at 10 characters and 6 lines an inch, an 11-inch form of 66 lines on fan-fold paper
14 7/8 inches wide, channel 1 at the form's first line.  FORTRAN carriage control (column 1)
is obeyed before the line prints: blank one line, ``0`` two, ``-`` three, ``1`` a new form
(none before anything is printed, as POSIX ``asa``), ``+`` overprint; anything else one line.
Nothing in the listing tests channel 12, so a line past the 66th prints on the next form;
positions past 132 are not printed; no page numbers are added.  ``striped`` paper has green
bars three lines deep, the first on lines 1-3.

The face is DejaVu Sans Mono at the size whose advance is 1/10 inch, shipped with its licence
(``fonts/``) and embedded (the subset the pages use) so every viewer draws the same face.  The
PDF is written directly (legacy/pdf.py): one text object a form, one string a printed line, so
its text extracts line by line in printed order.  It is reproducible: no creation date but
``SOURCE_DATE_EPOCH``'s, the producer by version, the caller's facts as metadata.
"""

from __future__ import annotations

import os
import zlib

from deck_emulator.files import OutputError, OutputSet
from deck_emulator.parallel import progress_bar
from deck_emulator.vocabulary import defaults

__all__ = ["LINES_PER_FORM", "PRINT_POSITIONS", "PAGE_WIDTH_IN", "PAGE_HEIGHT_IN",
           "LEFT_MARGIN_IN", "layout", "baseline_in", "column_x_in", "printed_lines", "paper_bars",
           "tractor_holes", "face_file", "write_pdf", "stop_facts", "fact_page",
           "closing_records"]

LINES_PER_FORM = 66
LINES_PER_INCH = 6
CHARS_PER_INCH = 10
PRINT_POSITIONS = defaults.PRINT_POSITIONS
PAGE_WIDTH_IN = 14.875
PAGE_HEIGHT_IN = LINES_PER_FORM / LINES_PER_INCH  # 11
LEFT_MARGIN_IN = (PAGE_WIDTH_IN - PRINT_POSITIONS / CHARS_PER_INCH) / 2
BASELINE_DROP = 0.04  # inch, baseline above the bottom of the line's band
# DejaVu Sans Mono: every glyph advances 1233 of its 2048 units to the em (the font's hmtx
# table; a test reads it from the file matplotlib ships), so at 11.96 points 7.2 points,
# 1/10 inch -- the 1403's pitch.
_ADVANCE_EM = 1233 / 2048
FONT_SIZE_PT = 72 / CHARS_PER_INCH / _ADVANCE_EM  # 11.959...


def layout(records: list[str]) -> list[list[tuple[int, str]]]:
    """Forms of (line number 1..66, printed text) in the order printed, from records
    with carriage control in column 1."""
    forms: list[list[tuple[int, str]]] = [[]]
    line = 0  # the line last printed on; 0: the form is fresh, at channel 1
    for record in records:
        control, text = (record[:1] or " "), record[1 : 1 + PRINT_POSITIONS]
        if control == "1":
            if line or forms[-1]:
                forms.append([])
            line = 1
        elif control == "+":
            line = max(line, 1)
        else:
            line += {"0": 2, "-": 3}.get(control, 1)
        while line > LINES_PER_FORM:
            forms.append([])
            line -= LINES_PER_FORM
        forms[-1].append((line, text))
    return forms


def stop_facts(error, records: list[str], *, section: str = "", hint: str = "") -> dict[str, str]:
    """Where, when and why a run stopped, in words for its pages (the banner's line and the
    closing page): ``error`` the guard that stopped it (legacy.stops.EmulatorError: its
    ``reason``, ``label``, ``variable``, ``step``, ``time``), ``records`` what it printed
    before (the closing page says after which record), ``section`` which $DATA section of a
    job deck it was ('' for a plain deck), ``hint`` what would let it go on."""
    reason = getattr(error, "reason", None) or str(error)
    label = getattr(error, "label", None)
    variable = getattr(error, "variable", None)
    where = (f"label {label}" + (f", assigning {variable}" if variable else "")
             if label is not None else "not said by the program")
    where += (f"; its printout ends with record {len(records)}"
              + (f", {records[-1][1:].strip()[:60]!r}" if records and records[-1][1:].strip()
                 else "") if records else "; it printed no record")
    step, t = getattr(error, "step", None), getattr(error, "time", None)
    when = ((f"step {step}" if step is not None else "")
            + (f", t = {t:.6f} s" if t is not None else "")).strip(", ") or "not said"
    out = {"stopped": "yes: the program did not reach its end; the pages before this one are "
                      "all it printed"}
    if section:
        out["section"] = section
    out.update(where=where, when=when, why=reason + (f" -- {hint}" if hint else ""))
    return out


def fact_page(title: str, facts: dict[str, str], rule: str, width: int = 131,
              label: int = 0) -> list[str]:
    """A page of facts as printer records on a form of its own (the banner, a job's
    separators, the closing page of a run that stopped): ``title`` between two rules of
    ``rule``, then each fact's name and its text wrapped to the print line.  ``label``: the
    names' column (0: the longest name and two)."""
    import textwrap

    line = rule * width
    records = ["1" + line, " ", " " + title, " ", " " + line, "0"]
    label = label or max(len(k) for k in facts) + 2
    for key, text in facts.items():
        lines = textwrap.wrap(text, width - label - 1) or [""]
        records.append(" " + f"{key.upper():<{label}}" + lines[0])
        records += [" " + " " * label + more for more in lines[1:]]
    return records + ["0", " " + line]


def closing_records(facts: dict[str, str]) -> list[str]:
    """The closing page of a run that stopped: what :func:`stop_facts` says, after the
    printout, which stays exactly as printed."""
    return fact_page("DECK_EMULATOR  --  THE RUN STOPPED", facts, "=")


def baseline_in(line: int) -> float:
    """Height of line ``line``'s baseline above the bottom of the form, in inches."""
    return PAGE_HEIGHT_IN - line / LINES_PER_INCH + BASELINE_DROP


def column_x_in(position: int) -> float:
    """Left edge of print position ``position`` (1-based), in inches from the form's left."""
    return LEFT_MARGIN_IN + (position - 1) / CHARS_PER_INCH


#: the paper's colours: the bars of 'striped' (green-bar) paper, the tractor holes' outline
BAR_RGB = (0xD8 / 255, 0xEC / 255, 0xD8 / 255)  # #d8ecd8
HOLE_RGB = (0xB0 / 255, 0xB0 / 255, 0xB0 / 255)  # #b0b0b0
HOLE_LINE_PT = 0.6
HOLE_RADIUS_IN = 0.08
#: The holes are ellipses: a circle in fractions of the form's width and height.
HOLE_HEIGHT_RADIUS_IN = HOLE_RADIUS_IN * PAGE_HEIGHT_IN / PAGE_WIDTH_IN


def paper_bars(paper: str) -> list[tuple[float, float, float, float]]:
    """The green bars of ``paper`` as (left, bottom, width, height) in inches from the
    form's lower left: three lines (half an inch) deep, a bar on lines 1-3, 7-9, ...,
    0.2 inch wider than the print line on each side; none on plain paper."""
    if paper != "striped":
        return []
    bars = []
    for first in range(1, LINES_PER_FORM + 1, 6):
        top = PAGE_HEIGHT_IN - (first - 1) / LINES_PER_INCH
        bars.append((LEFT_MARGIN_IN - 0.2, top - 0.5, PRINT_POSITIONS / CHARS_PER_INCH + 0.4,
                     0.5))
    return bars


def tractor_holes() -> list[tuple[float, float]]:
    """Centres of the tractor holes, in inches: every half inch, a quarter inch from each
    edge, on either kind of paper."""
    return [(x, (k + 0.5) / 2) for k in range(22) for x in (0.25, PAGE_WIDTH_IN - 0.25)]


def printed_lines(form: list[tuple[int, str]]) -> list[tuple[int, int, str]]:
    """What a form shows, in the order printed: (line, first print position, text) for each
    record that prints anything, the text from its first to its last non-blank character
    (a blank record, or the blank margins of one, prints nothing)."""
    out = []
    for line, text in form:
        stripped = text.lstrip(" ")
        if not stripped.strip():
            continue
        out.append((line, len(text) - len(stripped) + 1, stripped.rstrip(" ")))
    return out


def write_pdf(records: list[str], path: str | os.PathLike, paper: str = "plain", *,
              outputs=None, metadata: dict[str, str] | None = None,
              progress: str | None = None) -> int:
    """Write the printout's forms to ``path`` as PDF, through the one writer; return the
    number of pages.

    ``outputs``: an open :class:`~deck_emulator.files.OutputSet` to stage the PDF in, so that
    it is committed with the set's other files (the printout itself: both or neither);
    without it the PDF is committed alone.  ``metadata``: the PDF's document information
    (Title, Subject, Keywords, Creator ...), strings (None: left out).  ``progress``: the
    words of the page count shown while the forms are written, on the package's progress
    display; None shows none.  Either way a kill leaves the old file or the new one whole,
    and a PDF that cannot be made (a full disk: ``zlib.error`` or ``OSError`` from the
    writer) is an :class:`~deck_emulator.files.OutputError` naming ``path``, with nothing
    left behind."""

    if paper not in ("plain", "striped"):
        raise ValueError(f"paper must be plain or striped, not {paper!r}")
    epoch = os.environ.get("SOURCE_DATE_EPOCH", "")
    if epoch and not (epoch.isascii() and epoch.isdigit() and int(epoch) <= 253402300799):
        raise OutputError(path, f"SOURCE_DATE_EPOCH={epoch[:40]!r} is not a whole number of "
                          "seconds from 1970 to the year 9999 (reproducible-builds.org)")
    if outputs is None:
        with OutputSet() as own:
            return write_pdf(records, path, paper, outputs=own, metadata=metadata,
                             progress=progress)
    stage = outputs.path(path)
    try:
        return _render_pdf(records, stage, paper, metadata or {}, progress)
    except OutputError:
        raise
    except (OSError, zlib.error, MemoryError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
        raise OutputError(path, f"the PDF could not be written: {reason}",
                          getattr(exc, "errno", None)) from None


def face_file():
    """The printer's face shipped with the package: DejaVu Sans Mono (``fonts/``, with its
    licence, ``LICENSE_DEJAVU``), a path-like resource."""
    from importlib.resources import files

    return files("deck_emulator.legacy") / "fonts" / "DejaVuSansMono.ttf"


def _paper_shapes(paper: str) -> list:
    from deck_emulator.legacy.pdf import Ellipse, Rect

    pt = 72
    shapes: list = [Rect(x * pt, y * pt, w * pt, h * pt, BAR_RGB)
                    for x, y, w, h in paper_bars(paper)]
    shapes += [Ellipse(x * pt, y * pt, HOLE_RADIUS_IN * pt, HOLE_HEIGHT_RADIUS_IN * pt,
                       HOLE_RGB, HOLE_LINE_PT) for x, y in tractor_holes()]
    return shapes


def _info(metadata: dict[str, str]) -> dict[str, bytes]:
    """The document information: the caller's, the producer, and a creation date only as
    ``SOURCE_DATE_EPOCH`` gives it (ISO 32000 7.9.4: D:YYYYMMDDHHmmSSZ)."""
    import time

    from deck_emulator.legacy.pdf import pdf_text_string

    info = {}
    for key, value in metadata.items():
        if value is None:
            continue
        if not isinstance(value, str):
            raise TypeError(f"PDF metadata {key}: a string, not {type(value).__name__}")
        info[key] = pdf_text_string(value)
    if "Producer" not in metadata:  # the writer, by the installed version (pyproject.toml's)
        from importlib.metadata import PackageNotFoundError, version

        try:
            producer = f"deck_emulator {version('deck_emulator')}"
        except PackageNotFoundError:
            producer = "deck_emulator (not installed)"
        info["Producer"] = pdf_text_string(producer)
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch and "CreationDate" not in metadata:
        stamp = time.strftime("D:%Y%m%d%H%M%SZ", time.gmtime(int(epoch)))
        info["CreationDate"] = pdf_text_string(stamp)
    return info


def _render_pdf(records: list[str], path, paper: str, metadata: dict[str, str],
                progress: str | None) -> int:
    from deck_emulator.legacy.pdf import (Face, TextLine, page_content, shapes_content,
                                          write_document)

    forms = [printed_lines(form) for form in layout(records)]
    face = Face(face_file(), (c for form in forms for *_, text in form for c in text))
    pt = 72

    def pages():  # the paper (the same on every form) once, as the pages' background
        for form in forms:
            yield page_content([TextLine(column_x_in(first) * pt, baseline_in(line) * pt, text)
                                for line, first, text in form], face, FONT_SIZE_PT,
                               background=True)

    info = _info(metadata)
    with (open(path, "wb") as stream,
          progress_bar(len(forms), desc=progress or "", unit="page",
                       quiet=progress is None) as bar):
        write_document(stream, pages(), len(forms), face, PAGE_WIDTH_IN * pt,
                       PAGE_HEIGHT_IN * pt, info, background=shapes_content(_paper_shapes(paper)),
                       on_page=bar.update)
    return len(forms)
