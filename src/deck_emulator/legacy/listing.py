"""The program's source as a compile listing, for the printed pages (``run --pages --listing``).

A job's printout in 1967 held the compiler's listing of the FORTRAN source before the program's
output.  IBFTC's own listing format is not in the report, and nothing of it is claimed here:
this is a reconstruction in the usual shape of such listings -- each source card as punched
(columns 1-72, and its sequence columns 73-80, blank in the transcription as in the scan), an
internal statement number (ISN) before the first card of each statement (comments and
continuation cards get none), each ``$IBFTC`` routine starting a new form, with a heading line
on every form.  The source is the package's ``luminaire.f`` (the transcribed listing; the
``C$`` comment cards stand for the job's control cards, which are printed as such), or the
cards a job deck carries, its own control cards (``$`` in column 1) and FORTRAN, as punched.
"""

from __future__ import annotations

from deck_emulator.legacy import listing_lines
from deck_emulator.legacy.jobdeck import is_comment, is_continuation

__all__ = ["listing_records", "LINES_PER_PAGE", "SHIPPED", "DECKS_OWN"]

#: source cards on a form: a heading, a blank line, then the cards (66 lines a form)
LINES_PER_PAGE = 60


#: what a listing lists, as its heading says it: the shipped transcription, a deck's cards
SHIPPED = "THE TRANSCRIBED SOURCE"
DECKS_OWN = "THE JOB DECK'S OWN CARDS"


def _heading(routine: str, page: int, source: str) -> str:
    title = f"$IBFTC {routine}    COMPILE LISTING (A RECONSTRUCTION: {source})"
    return "1" + f"{title:<120}PAGE {page:>3}"


def listing_records(lines: list[str] | None = None) -> list[str]:
    """The compile listing of ``lines`` as printer records, carriage control in column 1:
    a job deck's own cards (control cards and FORTRAN), or by default the package's
    luminaire.f, whose ``C$`` comment lines stand for the control cards."""

    source = DECKS_OWN if lines is not None else SHIPPED
    if lines is None:
        lines = listing_lines()
    records: list[str] = []
    routine, page, on_page, isn = "MAIN", 0, 0, 0
    for card in lines:
        card = card.rstrip("\n")
        control = (card[1:] if card.startswith("C$") and source == SHIPPED
                   else card if card.startswith("$") else None)  # a job control card
        new_routine = control is not None and control.startswith("$IBFTC") and isn > 0
        if control is not None and control.startswith("$IBFTC") and len(control.split()) > 1:
            routine = control.split()[1]
        if page == 0 or new_routine or on_page >= LINES_PER_PAGE:
            page += 1
            records += [_heading(routine, page, source), " "]
            on_page = 0
        on_page += 1
        if control is not None:
            records.append(" " + " " * 8 + control)
            continue
        number = ""
        if not is_comment(card) and not is_continuation(card):  # a statement's first card
            isn += 1
            number = f"{isn:>5}"
        records.append(" " + f"{number:>5}   " + card[:72].ljust(72) + card[72:80].ljust(8))
    return records
