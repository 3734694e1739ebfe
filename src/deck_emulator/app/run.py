"""``deck-emulator run``: run the 1967 program on a deck and write its line-printer output."""

from __future__ import annotations

from deck_emulator.errors import UsageError

from . import PROG, Answer, command
from . import common
from .options import Emulator, option, options_class, quiet_option, trajectory_option


@options_class
class RunOptions(Emulator):
    """What ``run`` takes beyond the emulator's options: where its printout, pages, JSON,
    trajectory and dossier go, and how they are laid out."""

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
    quiet: bool = quiet_option()
    render: bool = option(False, help="render ASA carriage control (1 = form feed, 0 = blank "
                          "line, + = overprint) as the POSIX asa utility does, instead of the "
                          "raw records")
    json: bool = option(False, help="print the printout's records, per $DATA section, as one "
                        "JSON object (docs/json.md)")
    html: str | None = option(None, metavar="FILE.html", help="also write the run's dossier: "
                              "one self-contained HTML page holding the provenance, the "
                              "events, quantities and ratings, the pictures, and the printout "
                              "beside the listing, each record linked to the WRITE that "
                              "printed it (docs/dossier.md)")
    trajectory: str | None = trajectory_option()


def _describe(run, own: bool = False) -> str:
    from deck_emulator.engine import errata

    if own:
        return f"arithmetic {run.arithmetic}; the job deck's own FORTRAN"
    scale = f"; step literals / 2**{run.step_scale_k}" if run.step_scale_k else ""
    return f"arithmetic {run.arithmetic}; errata: {errata.describe(run.errata)}{scale}"


@command("run", RunOptions,
         help="run the 1967 program on a deck and write its line-printer output",
         description="Run the emulated 1967 program on a deck. The printout goes to stdout (or "
         "--out FILE, written whole or not at all); what was run (arithmetic, its assumptions, "
         "errata) is said on stderr. If the run stops early (a trap or a guard), the records "
         "printed until then are written and the exit status is 3.", core=False)
def run(o: RunOptions) -> Answer:
    from deck_emulator.legacy.printer import render_asa

    src = common.load(o, "run", kinds=("deck",), own_program=True)
    common.check_out(o.out)
    common.check_trajectory(o.trajectory)
    if o.trajectory and src.fortran is not None and not src.fortran.keeps_trace:
        labels = ", ".join(map(str, (src.fortran.watch or {}).get("records", ())))
        raise UsageError(f"--trajectory: {src.name} runs its own FORTRAN, which keeps no "
                         f"trajectory: it is recorded at the listing's labels {labels}, with "
                         "their variables, and this program lacks one (the listing's: "
                         "--listing-program)")
    if o.trajectory and len(src.decks) != 1:
        raise UsageError(f"--trajectory writes one run's trajectory and {src.name} holds "
                         f"{len(src.decks)} $DATA sections: choose one with --section N")
    if o.pages:
        from deck_emulator.files import check_distinct

        if not o.pages.lower().endswith(".pdf"):
            raise UsageError(f"--pages {o.pages}: the pages are a PDF; name a .pdf file")
        check_distinct(o.out, o.pages)  # --out X --pages X: refused before any work
        common.check_out(o.pages)
    elif o.paper != "plain" or o.listing:
        which = ("--paper is the paper of --pages" if o.paper != "plain"
                 else "--listing is printed on the pages of --pages")
        raise UsageError(f"{which}: give --pages FILE.pdf")
    if o.html:
        from .dossier import check_html

        check_html(o.html, o.out, o.pages, o.trajectory)
    engine = common.emulator(o, trace=bool(o.trajectory or o.html), fortran=src.fortran)
    answer = Answer("run", src.name, settings={"precision": o.precision,
                                               "errata": list(o.erratum)},
                    notes=list(src.notes), json=o.json, out=None if o.pages else o.out,
                    said=list(src.notes))
    printed_by_run, text, sections, stop = [], "", [], None
    programs, outcomes, writes = [], [], []  # what --html shows

    def keep(program) -> None:  # the program's run keeps which WRITE printed which record
        program.keep_writes = True
        programs.append(program)

    for deck in src.decks:  # a job deck's $DATA sections, in turn (or --section's)
        done = common.with_progress(o.quiet, engine, deck, execute=True,
                                    watch=keep if o.html else None)
        run_ = done.run
        # the Outcome only where it is used (a trajectory, a stopped run's reasons, the
        # dossier's summary): a plain run prints the program's records and loads no numpy
        out = (engine.outcome_of(done, deck) if o.trajectory or o.html or done.stopped
               else None)
        if o.html:
            outcomes.append(out)
            writes.append(tuple(run_.writes))
        printed_by_run.append(list(run_.records))
        text += render_asa(run_.records) if o.render else run_.text()
        settings = _describe(run_, src.fortran is not None)
        answer.said.append(f"{deck.path}: {settings}")
        sections.append({"deck": str(deck.path), "settings": settings,
                         "records": list(run_.records), "stopped": out and out.error})
        if done.stopped:  # where, when and why, for the banner and the closing page
            from deck_emulator.legacy.pages import stop_facts

            which = (f"{len(sections)} of {len(src.decks)} ($DATA sections after it not run)"
                     if len(src.decks) > 1 else "")
            stop = stop_facts(done.error if done.error is not None else done.defect,
                              list(run_.records), section=which, hint=out.hint)
        written = common.write_trajectory(o.trajectory, out) if out is not None else None
        if written:
            answer.said.append(written)
        if done.stopped:
            answer.status, answer.error = "stopped", common.failed(out, deck.path)
            break
    # what produced the printout: for the JSON answer and the pages (the version costs an
    # importlib.metadata read, and the module importlib.resources, so a plain run asks neither)
    facts = None
    if o.json or o.pages or o.html:
        from deck_emulator.engine import provenance

        facts = provenance.facts(src, [s["settings"] for s in sections], listing=o.listing)
        if stop is not None:  # said on the banner and in the metadata, before the note
            note = facts.pop("note")
            facts["stopped"] = (("section " + stop["section"] + ": " if "section" in stop
                                 else "") + f"at {stop['where'].split(';')[0]}, "
                                f"{stop['when']}: {stop['why']}")
            facts["note"] = note
    answer.result = {"provenance": facts, "sections": sections}
    answer.text = text
    page = _dossier(src, facts, sections, stop, programs, outcomes, writes) if o.html else None
    if page is not None and not o.pages:
        from deck_emulator.files import write_file

        write_file(o.html, page)
        answer.said.append(f"wrote the dossier to {o.html}")
    if o.pages:  # the printout (if asked for) and its pages: one set, both written or neither
        from deck_emulator.files import OutputSet
        from deck_emulator.legacy.pages import write_pdf

        with OutputSet() as outputs:  # (and the dossier, if asked for: all or none)
            if o.out:
                outputs.write(o.out, answer.printed())
            if page is not None:
                outputs.write(o.html, page)
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
            metadata = provenance.pdf_metadata(facts)
            if stop is not None:  # the closing page after the printout, which stays as printed
                from deck_emulator.legacy.pages import closing_records

                pages += closing_records(stop)
                metadata["Title"] += " (the run stopped: see its last page)"
            write_pdf(pages, o.pages, paper=o.paper, outputs=outputs,
                      metadata=metadata,
                      progress=None if o.quiet else f"{PROG}: writing the pages")
        answer.said.append(f"wrote the line printer's pages to {o.pages}")
        if page is not None:
            answer.said.append(f"wrote the dossier to {o.html}")
        if o.out or not o.json:
            answer.text, answer.json = None, False  # written, or not for the terminal
    return answer


def _dossier(src, facts, sections, stop, programs, outcomes, writes) -> str:
    """The page of ``--html``: the provenance (the banner's facts), the stop, the summary's
    answer of the (last) section run, its pictures, and each section's printout beside the
    listing of the program that printed it."""
    from deck_emulator.present import dossier
    from deck_emulator.present.answers import outcome_result

    from .dossier import program_listing

    title = ("the job deck's own cards, as punched before $DATA (card numbers)"
             if src.fortran is not None else
             "luminaire.f, the listing of Report 75-9 as run (line numbers)")
    program = program_listing(programs[-1].program, title)
    printed = [dossier.PrintedSection(s["deck"], s["settings"], tuple(s["records"]), w)
               for s, w in zip(sections, writes)]
    last = outcomes[-1]
    result, note = None, None
    if len(sections) > 1:
        note = (f"the events, quantities, ratings and pictures are those of the last $DATA "
                f"section run ({sections[-1]['deck']}, {len(sections)} of {len(src.decks)})")
    result = outcome_result(last)
    pictures = dossier.pictures(last)
    return dossier.run_page(name=src.name, facts=facts, program=program, sections=printed,
                            stop=stop, result=result, outcome_note=note,
                            made_pictures=pictures)
