"""``deck-emulator compare``: compare two printouts of the program, record by record."""

from __future__ import annotations

from deck_emulator.errors import UsageError

from . import Answer, command
from .options import Answering, Common, nonnegative_float, option, options_class, positive_int


@options_class
class CompareOptions(Common, Answering):
    a: str = option(positional=True, metavar="A",
                    help="a printout: text with carriage control in column 1, the page as "
                    "printed (run --render), or text taken from the PDF of run --pages")
    b: str = option(positional=True, metavar="B", help="the printout to compare it with")
    tolerance: float = option(0.0, parse=nonnegative_float, metavar="X",
                              help="values agree when they differ by at most X (default 0: "
                              "exactly)")
    max: int | None = option(None, parse=positive_int, metavar="N",
                             help="show at most N findings of each kind (all are counted)")


#: what a printout holds, said when a file holds none of it
_EXPECTED = "a printout of the program was expected ('THE VALUE OF name IS value' lines, " \
            "'THE POST HAS ...' messages)"


def _printout_records(path: str):
    """The records of the printout in ``path``; an empty file or one with no record of the
    program is refused in one line."""
    from deck_emulator.legacy.deck import read_bytes
    from deck_emulator.legacy.records import read_records

    shown, data = read_bytes(path, limit=1 << 26)  # DeckError naming the file
    if not data.strip():
        raise UsageError(f"{path}: an empty file: {_EXPECTED}")
    records = read_records(data.decode("ascii", errors="replace"))
    if not records:
        what = ("a PDF; compare reads a printout's text (the text taken from the PDF)"
                if data.startswith(b"%PDF") else "not a printout of the program: no record of it")
        raise UsageError(f"{path}: {what}: {_EXPECTED}")
    return records


def _compare_text(o: CompareOptions, found) -> str:
    tol = "exactly as printed" if o.tolerance == 0 else f"within {o.tolerance:g}"
    lines, hidden = [], 0
    for kind in (found.differences, found.damaged, found.missing):
        shown = kind if o.max is None else kind[:o.max]
        lines += [finding.line() for finding in shown]
        hidden += len(kind) - len(shown)
    verdict = ("agree" if found.agree else "differ")
    counts = ("" if found.agree else f": {len(found.differences)} difference(s), "
              f"{len(found.missing)} record(s) in one printout only")
    damaged = f"; {len(found.damaged)} value(s) damaged" if found.damaged else ""
    more = f"; {hidden} finding(s) not shown (--max)" if hidden else ""
    lines.append(f"A {o.a} and B {o.b} {verdict} ({tol}){counts}{damaged}{more}.")
    return "\n".join(lines) + "\n"


@command("compare", CompareOptions,
         help="compare two printouts of the program, record by record",
         description="Read two printouts of the program (this tool's, the compiled listing's, "
         "the page as printed, text taken from a PDF of the pages, or one typed or scanned "
         "from another source), line their records up by content (each value by its variable "
         "and its block's TIME, each message by its words), and print each value that "
         "differs, each value damaged as a scan damages it (O for 0, l for 1 ...: read as the "
         "number and named), and each record in one printout only. Exit status 0 when no "
         "value differs (exactly as printed, or within --tolerance) and no record is missing, "
         "1 otherwise, 2 for input that is not a printout.")
def compare(o: CompareOptions) -> Answer:
    from deck_emulator.legacy.compare import compare_records

    records = [_printout_records(path) for path in (o.a, o.b)]
    found = compare_records(*records, tolerance=o.tolerance)

    def listed(kind):
        return [vars(finding) for finding in (kind if o.max is None else kind[:o.max])]

    return Answer("compare", f"{o.a} {o.b}", status="ok" if found.agree else "differ",
                  settings={"tolerance": o.tolerance},
                  result={"agree": found.agree,
                          "differences": listed(found.differences),
                          "differences_total": len(found.differences),
                          "damaged": listed(found.damaged),
                          "damaged_total": len(found.damaged),
                          "missing": listed(found.missing),
                          "missing_total": len(found.missing)},
                  text=_compare_text(o, found), json=o.json, out=o.out)
