"""The 1967 path's commands: ``parse``, ``run``, ``punch``, ``compare``, ``corrections``."""

from __future__ import annotations

from dataclasses import dataclass

from deck_emulator.errors import UsageError

from . import Answer, command
from . import common
from .options import CARD_FORMATS, KEYPUNCH_CODES, Answering, Common, Emulator, Source, option
from .options import nonnegative_float, positive_int

# ------------------------------------------------------------------------------------ parse


@dataclass(frozen=True, kw_only=True)
class ParseOptions(Source):
    json: bool = option(False, help="print one JSON object: values (name -> value, READ "
                        "order) and the cards' fields with their columns and units "
                        "(docs/json.md)")


@command("parse", ParseOptions, help="read a card deck and print its 64 values",
         description="Read a $DATA card deck (8 cards, FORMAT(8F10.5)) with the 1967 input "
         "rules and print the values under their READ-list names.")
def parse(o: ParseOptions) -> Answer:
    from deck_emulator.present.answers import parse_result, render_parse

    src = common.load(o, "parse", kinds=("deck",))
    deck = src.deck("parse")
    result = parse_result(deck)
    answer = Answer("parse", str(deck.path), result=result, json=o.json, said=list(src.notes))
    answer.text = render_parse(answer.document())
    return answer


# -------------------------------------------------------------------------------------- run


@dataclass(frozen=True, kw_only=True)
class RunOptions(Emulator):
    out: str | None = option(None, metavar="FILE", help="write the printout to FILE")
    pages: str | None = option(None, metavar="FILE.pdf",
                               help="lay the printout out as the line printer's pages, as PDF "
                               "(the text goes to --out if given, and not to the terminal)")
    paper: str = option("plain", choices=("plain", "striped"),
                        help="the fan-fold paper of --pages (default plain)")
    listing: bool = option(False, help="with --pages: the program's FORTRAN source as a "
                           "compile listing (cards, sequence columns, statement numbers) "
                           "before the output: a job deck's own cards, with its control "
                           "cards, when it carries them, the shipped transcription otherwise "
                           "(the banner page says which)")
    quiet: bool = option(False, help="no progress display on stderr (shown only on a terminal)")
    render: bool = option(False, help="render ASA carriage control (1 = form feed, 0 = blank "
                          "line, + = overprint) as the POSIX asa utility does, instead of the "
                          "raw records")
    json: bool = option(False, help="print the printout's records, per $DATA section, as one "
                        "JSON object (docs/json.md)")
    trajectory: str | None = option(None, metavar="FILE.csv|FILE.parquet",
                                    help="also write the run's trajectory: time, every named "
                                    "point (road and report axes), the shaft's tilt and heading, "
                                    "the car (pandas reads it)")


def _describe(run) -> str:
    from deck_emulator.engine import errata

    scale = f"; step literals / 2**{run.step_scale_k}" if run.step_scale_k else ""
    return f"arithmetic {run.arithmetic}; errata: {errata.describe(run.errata)}{scale}"


@command("run", RunOptions,
         help="run the 1967 program on a deck and write its line-printer output",
         description="Run the emulated 1967 program on a deck. The printout goes to stdout (or "
         "--out FILE, written whole or not at all); what was run (arithmetic, its assumptions, "
         "errata) is said on stderr. If the run stops early (a trap or a guard), the records "
         "printed until then are written and the exit status is 3.")
def run(o: RunOptions) -> Answer:
    from deck_emulator.legacy.printer import render_asa

    src = common.load(o, "run", kinds=("deck",))
    common.check_out(o.out)
    common.check_trajectory(o.trajectory)
    if o.trajectory and len(src.decks) != 1:
        raise UsageError(f"--trajectory writes one run's trajectory and {src.name} holds "
                         f"{len(src.decks)} $DATA sections: choose one with --section N")
    if o.pages:
        from deck_emulator.files import check_distinct

        common.require("plot")  # the pages are drawn with matplotlib
        if not o.pages.lower().endswith(".pdf"):
            raise UsageError(f"--pages {o.pages}: the pages are a PDF; name a .pdf file")
        check_distinct(o.out, o.pages)  # --out X --pages X: refused before any work
        common.check_out(o.pages)
    elif o.paper != "plain" or o.listing:
        which = ("--paper is the paper of --pages" if o.paper != "plain"
                 else "--listing is printed on the pages of --pages")
        raise UsageError(f"{which}: give --pages FILE.pdf")
    engine = common.emulator(o, trace=bool(o.trajectory))
    answer = Answer("run", src.name, settings={"precision": o.precision,
                                               "errata": list(o.erratum)},
                    notes=list(src.notes), json=o.json, out=None if o.pages else o.out,
                    said=list(src.notes))
    printed_by_run, text, sections = [], "", []
    for deck in src.decks:  # a job deck's $DATA sections, in turn (or --section's)
        done = common.with_progress(o.quiet, engine, deck, execute=True)
        run_ = done.run
        # the Outcome only where it is used (a trajectory, a stopped run's reasons): a plain
        # run prints the program's records and loads no numpy
        out = engine.outcome_of(done, deck) if o.trajectory or done.stopped else None
        printed_by_run.append(list(run_.records))
        text += render_asa(run_.records) if o.render else run_.text()
        answer.said.append(f"{deck.path}: {_describe(run_)}")
        sections.append({"deck": str(deck.path), "settings": _describe(run_),
                         "records": list(run_.records), "stopped": out and out.error})
        written = common.write_trajectory(o.trajectory, out) if out is not None else None
        if written:
            answer.said.append(written)
        if done.stopped:
            answer.status, answer.error = "stopped", common.failed(out, deck.path)
            break
    # what produced the printout: for the JSON answer and the pages (the version costs an
    # importlib.metadata read, and the module importlib.resources, so a plain run asks neither)
    facts = None
    if o.json or o.pages:
        from deck_emulator.engine import provenance

        facts = provenance.facts(src, [s["settings"] for s in sections], listing=o.listing)
    answer.result = {"provenance": facts, "sections": sections}
    answer.text = text
    if o.pages:  # the printout (if asked for) and its pages: one set, both written or neither
        from deck_emulator.files import OutputSet
        from deck_emulator.legacy.pages import write_pdf

        with OutputSet() as outputs:
            if o.out:
                outputs.write(o.out, answer.printed())
            # the banner page (the job separator) first, the compile listing if asked for
            # (the deck's own cards, or the shipped transcription), then the output as
            # printed, each of several runs after a separator page of its own
            pages = provenance.banner_records(facts)
            if o.listing:
                from deck_emulator.legacy.listing import listing_records

                pages += listing_records(list(src.program_cards) or None)
            for k, (section, printed) in enumerate(zip(sections, printed_by_run), start=1):
                if len(src.decks) > 1:
                    pages += provenance.separator_records(k, len(src.decks), section["deck"],
                                                          section["settings"])
                pages += printed
            write_pdf(pages, o.pages, paper=o.paper, outputs=outputs,
                      metadata=provenance.pdf_metadata(facts))
        answer.said.append(f"wrote the line printer's pages to {o.pages}")
        if o.out or not o.json:
            answer.text, answer.json = None, False  # written, or not for the terminal
    return answer


# ------------------------------------------------------------------------------------ punch


@dataclass(frozen=True, kw_only=True)
class PunchOptions(Source):
    source: str = option(positional=True, metavar="SOURCE",
                         help="a shipped deck's name (steel40), a deck file (text or card "
                         "images), or a job deck; a scene file is refused (`scene` and `core` "
                         "take scenes)")
    to: str = option("text", choices=CARD_FORMATS, help="card format to punch")
    code: str = option("026", choices=KEYPUNCH_CODES,
                       help="keypunch code of the punched holes (default 026)")
    job: bool = option(False, help="punch a whole IBSYS job deck")
    out: str | None = option(None, metavar="FILE", help="write to FILE (default: stdout)")
    json: bool = option(False, help="print the punched cards' texts as one JSON object "
                        "(docs/json.md)")


@command("punch", PunchOptions,
         help="punch a deck's data cards (or a whole job deck) in a card image format",
         description="Read a deck (any card format) and punch its data cards, in the report's "
         "layout (8F10.5, a $DATA card first), as text, binary, column binary (cbn) or BCD "
         "card images, in the 026 or 029 keypunch code.  --job punches a whole IBSYS job "
         "deck: control cards, the listing's FORTRAN source and the data.")
def punch(o: PunchOptions) -> Answer:
    from deck_emulator.legacy.cardimage import write_images
    from deck_emulator.legacy.deck import DeckError
    from deck_emulator.legacy.jobdeck import data_deck_texts, job_deck_texts

    src = common.load(o, "punch", kinds=("deck",))
    common.check_out(o.out)
    texts = job_deck_texts(list(src.decks)) if o.job else data_deck_texts(list(src.decks))
    try:
        data = write_images(texts, o.to, o.code)
    except DeckError as err:
        raise DeckError(f"cannot punch in the {o.code} code: {err}") from None
    # the JSON: the punched cards as text, whatever the format they were punched in
    return Answer("punch", src.name, settings={"to": o.to, "code": o.code, "job": o.job},
                  notes=list(src.notes), said=list(src.notes),
                  result={"cards": texts, "bytes": len(data)}, text=data, json=o.json,
                  out=o.out)


# ---------------------------------------------------------------------------------- compare


@dataclass(frozen=True, kw_only=True)
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


# ------------------------------------------------------------------------------ corrections


@dataclass(frozen=True, kw_only=True)
class CorrectionsOptions(Common, Answering):
    key: str | None = option(None, positional=True, metavar="KEY",
                             help="show one entry in full: a departure's number (8), an "
                             "erratum's name (ed-direction) or a note's key")
    all: bool = option(False, help="the whole record and every patch")


def _corrections_list(entries) -> str:
    import textwrap

    kinds = {"departure": "Departures of luminaire.f from the scanned listing",
             "kept": "Kept as printed, although an equation differs",
             "section": "Notes", "erratum": "Errata (applied only with --erratum NAME)"}
    lines = []
    for kind, heading in kinds.items():
        chosen = [e for e in entries if e.kind == kind]
        if chosen:
            lines += ["", heading]
            width = max(len(e.key) for e in chosen)
            lines += [f"  {e.key:<{width}}  "
                      + textwrap.shorten(e.title.replace("**", ""), 100 - width,
                                         placeholder=" ...")
                      for e in chosen]
    lines += ["", "deck-emulator corrections KEY shows one in full; --all the whole record."]
    return "\n".join(lines[1:]) + "\n"


@command("corrections", CorrectionsOptions,
         help="the corrections to the scanned listing and the named errata",
         description="Every place where the transcribed listing (luminaire.f) departs from the "
         "report's scanned listing, with its reason; what is kept as printed; the named errata "
         "and their patches. Read from the installed package.")
def corrections(o: CorrectionsOptions) -> Answer:
    from deck_emulator.legacy import corrections as record

    if o.all and o.key:
        raise UsageError("corrections: give an entry's KEY or --all, not both")
    entries = record.entries()
    if o.key:
        try:
            entries = [record.find(o.key)]
        except KeyError:
            keys = ", ".join(e.key for e in entries)
            raise UsageError(f"corrections {o.key}: no such entry (there are: {keys})") from None
    listed = not (o.key or o.all)  # the list: keys and titles, not the full texts
    result = {"entries": [{k: v for k, v in vars(e).items() if not (listed and k == "text")}
                          for e in entries]}
    if o.all:
        text = record.document() + "".join(
            f"\n## errata/{n}.patch\n\n{record.patch(n)}" for n in record.ERRATA)
    elif o.key:
        text = entries[0].text.rstrip("\n") + "\n"
    else:
        text = _corrections_list(entries)
    return Answer("corrections", "luminaire.f", result=result, text=text, json=o.json, out=o.out)
