"""What the listing writes to the line printer, read from the listing itself.

The package's copy of ``legacy/luminaire.f`` is the one source of the printout's words: each
``WRITE(6,n) list``, the ``FORMAT`` it names and the variables it prints are read from it here,
once, at import (FORMAT and WRITE statements only, in the fixed form the listing is punched
in).  The printer lays its records out from :data:`FORMATS`, the printout readers find its
labels and messages here, and both paths word their events from :data:`MESSAGES`
(:mod:`deck_emulator.vocabulary.events`).  The FORTRAN front end reads the same FORMATs with
its own, checked reader; a test holds the two equal.  Nothing of the package is imported: the
listing is read as a data file.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass

#: The listing as shipped (a byte-for-byte copy of the repository's ``legacy/luminaire.f``).
LISTING_FILE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                            "legacy", "luminaire.f")


def listing_lines() -> list[str]:
    """The lines of the listing (the package's ``legacy/luminaire.f``)."""
    with open(LISTING_FILE, encoding="ascii") as fh:
        return fh.read().splitlines()


def is_comment(line: str) -> bool:
    """A fixed-form card that holds no statement: blank, a comment (C or * in column 1), or
    a control card ($ in column 1)."""
    return not line[:72].strip() or line[:1] in ("C", "c", "*") or line.startswith("$")


def is_continuation(line: str) -> bool:
    """A statement card continuing the one before (column 6 neither blank nor zero)."""
    return not is_comment(line) and len(line) > 5 and line[5] not in (" ", "0")


@dataclass(frozen=True)
class Write:
    """One ``WRITE(6,label) variables`` of the listing and its FORMAT: ``format`` its text
    with blanks dropped outside the Hollerith texts (``(/,5X,20HTHE VALUE OF SVA IS ,F15.5)``),
    ``variables`` what the WRITE prints, in order; ``card``: the WRITE's line."""

    label: int
    format: str
    variables: tuple[str, ...]
    card: int


_COUNT = re.compile(r"([0-9][0-9 ]*)H")  # a Hollerith count (blanks in it ignored)


def _format_text(body: str) -> str:
    """A FORMAT statement's ``(...)`` from its columns 7-72 (continuations joined): blanks
    dropped, except the ``n`` characters after each ``nH``."""
    body = body[re.match(r" *" + " *".join("FORMAT"), body).end():]
    out, i = [], 0
    while i < len(body):
        m = _COUNT.match(body, i) if out and out[-1] in "(,/" else None
        if m:
            n = int(m.group(1).replace(" ", ""))
            out.append(f"{n}H{body[m.end():m.end() + n]}")
            i = m.end() + n
            continue
        if body[i] != " ":
            out.append(body[i])
        i += 1
    return "".join(out)


def _writes(lines: list[str]) -> tuple[Write, ...]:
    """The listing's WRITE statements with their FORMATs, in the order of the listing."""
    statements: list[list] = []  # [label, columns 7-72 joined, first line]
    for number, raw in enumerate(lines, start=1):
        if is_comment(raw):
            continue
        card = raw[:72].ljust(72)
        if is_continuation(raw) and statements:
            statements[-1][1] += card[6:]
        else:
            statements.append([card[:5].strip(), card[6:], number])
    formats, writes = {}, []
    for label, body, number in statements:
        compact = body.replace(" ", "")
        if compact.startswith("FORMAT(") and label:
            formats[int(label)] = _format_text(body)
        elif compact.startswith("WRITE("):
            m = re.fullmatch(r"WRITE\(6,(\d+)\)([A-Z0-9,]*)", compact)
            writes.append((int(m.group(1)), tuple(filter(None, m.group(2).split(","))), number))
    writes = [Write(label, formats[label], names, number) for label, names, number in writes]
    return tuple(writes)


#: Every WRITE of the listing to the line printer, by its FORMAT's label, in the listing's
#: order (the order it prints them: a page is a ``1H1`` FORMAT and the value FORMATs after it;
#: the listing writes each FORMAT from one WRITE).
WRITES: dict[int, Write] = {w.label: w for w in _writes(listing_lines())}

#: The FORMATs the listing writes with, by label, in the listing's order.
FORMATS: dict[int, str] = {label: w.format for label, w in WRITES.items()}

#: The FORMATs that print a message and no value, by label: the message (their one Hollerith
#: text after the carriage control, blanks and ``nX``), as the listing spells it.
MESSAGES: dict[int, str] = {label: re.fullmatch(r"\([/,0-9X]*[0-9]+H(.*)\)", w.format)[1]
                            for label, w in WRITES.items() if not w.variables}
