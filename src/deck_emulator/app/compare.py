"""``deck-emulator compare``: compare two printouts of the program, record by record.

A printout is read as people hold it: text (carriage control in column 1, the page as printed,
typed, scanned; ``pdftotext`` of the pages, plain or ``-layout``), or the PDF of ``run --pages``
itself.  A PDF's text is taken with pypdf (the ``[pdf]`` extra), a general reader, not by
decoding our own writer's streams: a PDF people hold has often passed through other hands.
The verdicts and their exit statuses are the command's description's
(:mod:`deck_emulator.legacy.compare` computes them).
"""

from __future__ import annotations

from deck_emulator.errors import UsageError

from . import Answer, command
from .options import Answering, Common, nonnegative_float, option, options_class, positive_int


@options_class
class CompareOptions(Common, Answering):
    a: str = option(positional=True, metavar="A",
                    help="a printout: text with carriage control in column 1, the page as "
                    "printed (run --render), text taken from the PDF of run --pages "
                    "(pdftotext, plain or -layout), or that PDF itself (needs the [pdf] "
                    "extra)")
    b: str = option(positional=True, metavar="B", help="the printout to compare it with")
    tolerance: float = option(0.0, parse=nonnegative_float, metavar="X",
                              help="values agree when they differ by at most X (default 0: "
                              "exactly as printed)")
    max: int | None = option(None, parse=positive_int, metavar="N",
                             help="show at most N findings of each kind (all are counted)")
    html: str | None = option(None, metavar="FILE.html",
                              help="also write the comparison as one self-contained HTML page: "
                              "the counts first, the findings, then the two printouts aligned "
                              "record by record, differences and damage highlighted "
                              "(docs/dossier.md)")


#: what a printout holds, said when a file holds none of it
_EXPECTED = "a printout of the program was expected ('THE VALUE OF name IS value' lines, " \
            "'THE POST HAS ...' messages)"


def _pdf_text(path: str, data: bytes, said: list[str]) -> str:
    """The text of a PDF's pages, one after the other (pypdf: the ``[pdf]`` extra)."""
    import io
    import logging
    import zlib

    import pypdf  # ModuleNotFoundError: the command line names the extra (exit 2)
    from pypdf.errors import PyPdfError

    from deck_emulator.parallel import progress_bar

    log = logging.getLogger("pypdf")  # its warnings on a damaged file: the refusal says why
    level = log.level
    log.setLevel(logging.ERROR)
    try:
        reader = pypdf.PdfReader(io.BytesIO(data))
        pages = []
        with progress_bar(len(reader.pages), desc=f"reading {path}", unit="page") as bar:
            for page in reader.pages:
                pages.append(page.extract_text())
                bar.update()
    except (PyPdfError, ValueError, KeyError, IndexError, zlib.error) as exc:
        raise UsageError(f"{path}: a PDF whose text cannot be read "
                         f"({type(exc).__name__}: {exc}): {_EXPECTED}") from exc
    finally:
        log.setLevel(level)
    said.append(f"{path}: the text of {len(pages)} PDF page(s), taken with pypdf")
    return "\n".join(pages)


def _printout_records(path: str, said: list[str]):
    """The records of the printout in ``path``; an empty file or one with no record of the
    program is refused in one line."""
    from deck_emulator.legacy.deck import read_bytes
    from deck_emulator.legacy.records import read_records

    shown, data = read_bytes(path, limit=1 << 26)  # DeckError naming the file
    if not data.strip():
        raise UsageError(f"{path}: an empty file: {_EXPECTED}")
    is_pdf = data.startswith(b"%PDF")
    text = _pdf_text(path, data, said) if is_pdf else data.decode("ascii", errors="replace")
    records = read_records(text)
    if not records:
        what = "a PDF with no record of the program in its text" if is_pdf else \
            "not a printout of the program: no record of it"
        raise UsageError(f"{path}: {what}: {_EXPECTED}")
    return records


def _counts_line(o: CompareOptions, found) -> str:
    """The first line: the verdict and what it rests on."""
    c = found.counts()
    damage = (f"; {c['read_through_damage']:,} read through a scan's damage"
              if c["read_through_damage"] else "")
    return (f"{found.verdict}: {c['records_a']:,} records in A, {c['records_b']:,} in B; "
            f"{c['aligned']:,} aligned; {c['compared']:,} compared ({c['values_compared']:,} "
            f"values, {c['messages_compared']:,} messages): {c['equal']:,} equal, "
            f"{c['differing']:,} differing; {c['unreadable']:,} unreadable; "
            f"{c['missing']:,} missing{damage}")


def _verdict_line(o: CompareOptions, found, hidden: int) -> str:
    """The last line: the verdict, and the counts it is computed from."""
    tol = "exactly as printed" if o.tolerance == 0 else f"within {o.tolerance:g}"
    c = found.counts()
    if found.verdict == "agree":
        said = f"agree ({tol}): all {c['compared']:,} records of each compared and equal"
        if c["read_through_damage"]:
            said += f", {c['read_through_damage']:,} of them as read through a scan's damage"
    elif found.verdict == "differ":
        said = (f"differ ({tol}): {c['differing']:,} difference(s), {c['missing']:,} "
                f"record(s) in one printout only")
    else:
        said = (f"cannot be said to agree ({tol}): {c['unreadable']:,} record(s) unreadable, "
                f"{c['compared']:,} of {max(c['records_a'], c['records_b']):,} compared, no "
                "difference among them")
    more = f"; {hidden} finding(s) not shown (--max)" if hidden else ""
    return f"A {o.a} and B {o.b} {said}{more}."


def _compare_text(o: CompareOptions, found) -> str:
    lines, hidden = [_counts_line(o, found)], 0
    for kind in (found.differences, found.damaged, found.missing):
        shown = kind if o.max is None else kind[:o.max]
        lines += [finding.line() for finding in shown]
        hidden += len(kind) - len(shown)
    lines.append(_verdict_line(o, found, hidden))
    return "\n".join(lines) + "\n"


@command("compare", CompareOptions,
         help="compare two printouts of the program, record by record",
         description="Read two printouts of the program (this tool's, the compiled listing's, "
         "the page as printed, text taken from a PDF of the pages by pdftotext, plain or "
         "-layout, the PDF itself with the [pdf] extra, or one typed or scanned from another "
         "source), line their records up by content (each value by its printed label and its "
         "block's TIME, each message by its words), and print the counts (records aligned, "
         "compared, equal, differing, unreadable, missing) first, then each value that "
         "differs, each record damaged as a scan damages it (O for 0, F5A for FSA ...: read "
         "as what it stands for, shown with its line) or unreadable (shown with its line as it "
         "stands), and each record in one printout only. Exit status 0 when every record of "
         "both was compared and equal (exactly as printed, or within --tolerance), 1 when a "
         "value differs or a record is missing, 4 when nothing differs but some record could "
         "not be read (not all compared: no agreement claimed), 2 for input that is not a "
         "printout.", core=False)
def compare(o: CompareOptions) -> Answer:
    from deck_emulator.legacy.compare import compare_records

    said: list[str] = []
    if o.html:
        from .dossier import check_html

        check_html(o.html, o.out)
    records = [_printout_records(path, said) for path in (o.a, o.b)]
    found = compare_records(*records, tolerance=o.tolerance)
    if o.html:
        from deck_emulator.files import write_file
        from deck_emulator.present.dossier import compare_page

        hidden = 0
        write_file(o.html, compare_page(
            a=o.a, b=o.b, counts_line=_counts_line(o, found),
            verdict_line=_verdict_line(o, found, hidden), found=found, records_a=records[0],
            records_b=records[1], lined_up=found.lined_up))
        said.append(f"wrote the comparison's page to {o.html}")

    def listed(kind):
        return [vars(finding) for finding in (kind if o.max is None else kind[:o.max])]

    return Answer("compare", f"{o.a} {o.b}",
                  status={"agree": "ok"}.get(found.verdict, found.verdict),
                  settings={"tolerance": o.tolerance},
                  result={"verdict": found.verdict,
                          "agree": found.agree,
                          "counts": found.counts(),
                          "differences": listed(found.differences),
                          "differences_total": len(found.differences),
                          "damaged": listed(found.damaged),
                          "damaged_total": len(found.damaged),
                          "missing": listed(found.missing),
                          "missing_total": len(found.missing)},
                  text=_compare_text(o, found), json=o.json, out=o.out, said=said)
