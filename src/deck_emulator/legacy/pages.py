"""The printout as the line printer laid it on paper: pages, as PDF.

The 7094's printer (an IBM 1403 on the 1401 or the 7094's own channel; facts from the IBM
1403 manuals as summarised in the project's reference notes):

* 132 print positions at 10 characters an inch, 6 lines an inch;
* an 11-inch form holds 66 lines; channel 1 of the carriage-control tape marks the form's
  first line, here line 1 (the top of the form); fan-fold paper 14 7/8 inches wide;
* FORTRAN carriage control, column 1 of each record, is obeyed before the line prints:
  blank = space one line, ``0`` = two (one blank line), ``-`` = three (two blank lines; not
  every installation had it, it is followed here), ``1`` = skip to channel 1 (a new form),
  ``+`` = no spacing (print over the line before).  Any other character spaces one line.
* There is no overflow control: nothing in the listing tests channel 12, so a line past the
  66th prints on the next form, across the perforation, as the paper simply moves on.
* A ``1`` before anything is printed leaves the printer on the first form (as POSIX ``asa``
  does); whether an operator's first skip fed one blank form is not known.
* Print positions beyond 132 are not printed.  The listing printed no page numbers and none
  are added.

Each printed line's baseline sits 1/6 inch below the previous one; line ``n`` of a form
(1-based) has its baseline ``BASELINE_DROP`` above the bottom of its 1/6-inch band.  The face
is DejaVu Sans Mono, embedded in the PDF (the subset of it the pages use), at the size whose
advance is exactly 1/10 inch.  It comes with matplotlib (its ``mpl-data/fonts/ttf``, licence
``LICENSE_DEJAVU`` there: Bitstream Vera's, a free licence that allows embedding and
redistribution, with DejaVu's changes in the public domain); PDF's standard Courier, used
before, is not embedded, so every viewer drew the pages in a face of its own choosing.
``striped`` paper has green bars three lines (half an inch) deep, starting with a bar on
lines 1-3.

The same records give the same bytes: the PDF carries no creation date (or the one
``SOURCE_DATE_EPOCH`` gives, as reproducible builds set it) and names its producer by
version; its metadata are the facts the caller passes (the provenance of the run).
"""

from __future__ import annotations

import os
import zlib

from deck_emulator.files import OutputError, OutputSet
from deck_emulator.parallel import progress_bar

__all__ = ["LINES_PER_FORM", "PRINT_POSITIONS", "PAGE_WIDTH_IN", "PAGE_HEIGHT_IN",
           "LEFT_MARGIN_IN", "layout", "baseline_in", "column_x_in", "form_figure", "write_pdf",
           "stop_facts", "closing_records"]

LINES_PER_FORM = 66
LINES_PER_INCH = 6
CHARS_PER_INCH = 10
PRINT_POSITIONS = 132
PAGE_WIDTH_IN = 14.875
PAGE_HEIGHT_IN = LINES_PER_FORM / LINES_PER_INCH  # 11
LEFT_MARGIN_IN = (PAGE_WIDTH_IN - PRINT_POSITIONS / CHARS_PER_INCH) / 2
BASELINE_DROP = 0.04  # inch, baseline above the bottom of the line's band
# DejaVu Sans Mono: every glyph advances 1233 of its 2048 units to the em (the font's hmtx
# table; a test reads it from the file matplotlib ships), so at 11.96 points 7.2 points,
# 1/10 inch -- the 1403's pitch.
_FONT = "DejaVu Sans Mono"
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


def closing_records(facts: dict[str, str], width: int = 131) -> list[str]:
    """The closing page of a run that stopped, as printer records on a form of its own: what
    :func:`stop_facts` says, after the printout, which stays exactly as printed."""
    import textwrap

    rule = "=" * width
    records = ["1" + rule, " ", " DECK_EMULATOR  --  THE RUN STOPPED", " ", " " + rule, "0"]
    label = max(len(k) for k in facts) + 2
    for key, text in facts.items():
        lines = textwrap.wrap(text, width - label - 1) or [""]
        records.append(" " + f"{key.upper():<{label}}" + lines[0])
        records += [" " + " " * label + more for more in lines[1:]]
    return records + ["0", " " + rule]


def baseline_in(line: int) -> float:
    """Height of line ``line``'s baseline above the bottom of the form, in inches."""
    return PAGE_HEIGHT_IN - line / LINES_PER_INCH + BASELINE_DROP


def column_x_in(position: int) -> float:
    """Left edge of print position ``position`` (1-based), in inches from the form's left."""
    return LEFT_MARGIN_IN + (position - 1) / CHARS_PER_INCH


def _paper(fig, paper: str) -> None:
    from matplotlib.patches import Circle, Rectangle

    w, h = PAGE_WIDTH_IN, PAGE_HEIGHT_IN
    if paper == "striped":
        for first in range(1, LINES_PER_FORM + 1, 6):
            top = h - (first - 1) / LINES_PER_INCH
            fig.add_artist(Rectangle(((LEFT_MARGIN_IN - 0.2) / w, (top - 0.5) / h),
                                     (PRINT_POSITIONS / CHARS_PER_INCH + 0.4) / w, 0.5 / h,
                                     transform=fig.transFigure, color="#d8ecd8", lw=0))
    for k in range(22):  # tractor holes, every half inch, a quarter inch from each edge
        y = (k + 0.5) / 2
        for x in (0.25, w - 0.25):
            fig.add_artist(Circle((x / w, y / h), 0.08 / w, transform=fig.transFigure,
                                  fill=False, color="#b0b0b0", lw=0.6))


# TrueType embedded as such (type 42): the glyphs are the font's own outlines
_RC = {"pdf.fonttype": 42, "font.family": "monospace", "font.monospace": [_FONT]}


def form_figure(form: list[tuple[int, str]], paper: str = "plain"):
    """One form as a matplotlib Figure, 14 7/8 by 11 inches."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(PAGE_WIDTH_IN, PAGE_HEIGHT_IN))
    _paper(fig, paper)
    for line, text in form:
        stripped = text.lstrip(" ")
        if not stripped.strip():
            continue
        first = len(text) - len(stripped) + 1
        fig.text(column_x_in(first) / PAGE_WIDTH_IN, baseline_in(line) / PAGE_HEIGHT_IN,
                 stripped.rstrip(" "), family="monospace", size=FONT_SIZE_PT,
                 ha="left", va="baseline")
    return fig


def write_pdf(records: list[str], path: str | os.PathLike, paper: str = "plain", *,
              outputs=None, metadata: dict[str, str] | None = None,
              progress: str | None = None) -> int:
    """Write the printout's forms to ``path`` as PDF, through the one writer; return the
    number of pages.

    ``outputs``: an open :class:`~deck_emulator.files.OutputSet` to stage the PDF in, so that
    it is committed with the set's other files (the printout itself: both or neither);
    without it the PDF is committed alone.  ``metadata``: the PDF's document information
    (Title, Subject, Keywords, Creator ...), strings.  ``progress``: the words of the page
    count shown while the forms are drawn (about a tenth of a second each: 120 forms for
    steel40) on the package's progress display; None shows none.  Either way a kill leaves the old file or the new
    one whole, and a PDF that cannot be made (a full disk: ``zlib.error`` or ``OSError`` from
    the PDF backend) is an :class:`~deck_emulator.files.OutputError` naming ``path``, with
    nothing left behind."""

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


def _render_pdf(records: list[str], path, paper: str, metadata: dict[str, str],
                progress: str | None) -> int:
    from matplotlib import rc_context
    from matplotlib.backends.backend_pdf import PdfPages

    info = dict(metadata)
    if not os.environ.get("SOURCE_DATE_EPOCH"):
        info["CreationDate"] = None  # none at all (matplotlib reads SOURCE_DATE_EPOCH itself)
    forms = layout(records)
    with (rc_context(_RC), PdfPages(path, metadata=info) as pdf,
          progress_bar(len(forms), desc=progress or "", unit="page",
                       quiet=progress is None) as bar):
        for form in forms:
            pdf.savefig(form_figure(form, paper))
            bar.update()
    return len(forms)
