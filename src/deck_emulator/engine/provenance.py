"""What produced a printout, said once: the facts the banner page prints, the PDF's metadata
carry and ``run --json`` answers (issue 26).

An operator's job separator page came out of the printer before each job's output; the banner
page here is that page, carrying what an archive needs to trust the pages that follow: the
deck (its name, its cards, the SHA-256 of its file), the program (the listing's checksum, and
what a job deck's own FORTRAN is), the arithmetic, the errata, this tool's version, and the
statement that the pages are a reconstruction.
"""

from __future__ import annotations

import hashlib
from importlib import resources
from pathlib import Path

from deck_emulator import __version__


#: Said on every banner page and in every answer: nothing printed in 1967 survives.
RECONSTRUCTION = ("a reconstruction: Report 75-9 prints no output pages; these are what the "
                  "transcribed listing prints for this deck, laid out as the line printer "
                  "printed")


def listing_sha256() -> str:
    """SHA-256 of the listing the emulator follows (the package's ``luminaire.f``)."""
    data = resources.files("deck_emulator.legacy").joinpath("luminaire.f").read_bytes()
    return hashlib.sha256(data).hexdigest()


def facts(source, settings: list[str], listing: bool = False) -> dict[str, str]:
    """The provenance of a run of ``source`` (an :class:`~deck_emulator.engine.sources.Source`
    of kind deck) with the emulator settings ``settings`` (one line per $DATA section run, as
    the command says them: arithmetic and errata), as ordered name -> text; ``listing``: the
    pages print a compile listing, and the facts say which source it lists."""

    sha = source.fortran.sha256 if source.fortran is not None else listing_sha256()
    program = f"the listing of Report 75-9's appendix, transcribed (luminaire.f, sha256 {sha})"
    if source.fortran is not None:
        program = (f"the job deck's own FORTRAN, run by the FORTRAN front end (sha256 {sha} "
                   f"of its {len(source.program_cards)} cards before $DATA): {source.program}")
    elif source.program:
        program += f"; the job deck's own FORTRAN: {source.program}"
    sections = len(source.decks)
    return {
        "deck": source.name,
        "deck file": source.given if Path(source.given).is_file()
        else f"{source.name}, shipped with the tool",
        "deck sha256": source.sha256,
        "cards": f"{source.cards} in the file ({source.card_format or 'text'}); "
                 f"{sections} $DATA section{'s' if sections != 1 else ''} run",
        "program": program,
        "program sha256": sha,
        "run": "; ".join(dict.fromkeys(settings)) or "not run",
        **({"listing": listed(source)} if listing else {}),
        "tool": f"deck_emulator {__version__}",
        "note": RECONSTRUCTION,
    }


def listed(source) -> str:
    """Which source the compile listing of the pages lists: the job deck's own cards when it
    carries them, the shipped transcription otherwise."""
    if source.program_cards:
        return (f"the job deck's own cards, as punched: {len(source.program_cards)} control "
                "and FORTRAN cards before its first $DATA section")
    return "the transcribed listing shipped with the tool (luminaire.f): the deck carries no " \
           "FORTRAN of its own"


def separator_records(run: int, runs: int, deck: str, settings: str, width: int = 131
                      ) -> list[str]:
    """The separator page before run ``run`` of ``runs`` (a job deck's $DATA sections, each
    run in turn), as printer records: a form of its own, the next record starting a new one."""
    from deck_emulator.legacy.pages import fact_page

    return fact_page(f"RUN {run} OF {runs}", {"deck": deck, "run": settings}, "-", width, 7)


def banner_records(provenance: dict[str, str], width: int = 131) -> list[str]:
    """The banner page as printer records (carriage control in column 1): a form of its own,
    the facts wrapped to the print line, the next record starting a new form."""
    from deck_emulator.legacy.pages import fact_page

    return fact_page("DECK_EMULATOR  --  JOB SEPARATOR", provenance, "*", width)


def pdf_metadata(provenance: dict[str, str]) -> dict[str, str]:
    """The PDF's document information: the same facts, for an archive's catalogue."""
    return {
        "Title": f"{provenance['deck']}: line printer output of the Report 75-9 program",
        "Subject": provenance["note"],
        "Keywords": "; ".join(f"{k}: {v}" for k, v in provenance.items() if k != "note"),
        "Creator": provenance["tool"],
    }
