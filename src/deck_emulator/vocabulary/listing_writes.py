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
from collections import namedtuple

#: The listing as shipped (a byte-for-byte copy of the repository's ``legacy/luminaire.f``).
LISTING_FILE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                            "legacy", "luminaire.f")


def listing_lines() -> list[str]:
    """The lines of the listing (read as bytes and decoded: every run reads it at import)."""
    with open(LISTING_FILE, "rb") as fh:
        return fh.read().decode("ascii").splitlines()


def is_comment(line: str) -> bool:
    """A fixed-form card that holds no statement: blank, a comment (C or * in column 1), or
    a control card ($ in column 1)."""
    return not line[:72].strip() or line[:1] in ("C", "c", "*") or line.startswith("$")


def is_continuation(line: str) -> bool:
    """A statement card continuing the one before (column 6 neither blank nor zero)."""
    return not is_comment(line) and _continues(line)


def _continues(card: str) -> bool:
    return len(card) > 5 and card[5] not in (" ", "0")


class Write(namedtuple("Write", "label format variables card")):
    """One ``WRITE(6,label) variables`` of the listing and its FORMAT: ``label`` (int) the
    FORMAT's, ``format`` its text with blanks dropped outside the Hollerith texts
    (``(/,5X,20HTHE VALUE OF SVA IS ,F15.5)``), ``variables`` (tuple of str) what the WRITE
    prints, in order; ``card`` (int): the WRITE's line.  A named tuple: every run reads the listing
    at import, where a frozen dataclass would compile its methods and typing's NamedTuple
    import typing (docs/scale.md, "A plain run's start")."""

    __slots__ = ()


#: a Hollerith count after the delimiter before it (blanks in it ignored)
_HOLLERITH = re.compile(r"([(,/])( *)([0-9][0-9 ]*)H")


def _format_text(body: str) -> str:
    """A FORMAT statement's ``(...)`` from its columns 7-72 (continuations joined): blanks
    dropped, except in the ``n`` characters after each ``nH``."""
    out, i = [], body.index("(")
    while (m := _HOLLERITH.search(body, i)) is not None:
        n = int(m[3].replace(" ", ""))
        out += [body[i:m.end(1)].replace(" ", ""), f"{n}H", body[m.end():m.end() + n]]
        i = m.end() + n
    return "".join(out) + body[i:].replace(" ", "")


def _writes(lines: list[str]) -> list[Write]:
    """The listing's WRITE statements with their FORMATs, in the order of the listing."""
    read: list[list] = []  # [label, columns 7-72 joined, first line] of a FORMAT or a WRITE
    current = None  # the one being read: its continuation cards are joined to it
    for number, raw in enumerate(lines, start=1):
        if current is not None:
            if is_comment(raw):
                continue
            if _continues(raw):
                current[1] += raw[:72].ljust(72)[6:]
                continue
            current = None
        # (the keywords as the listing punches them, whole: a test holds this reader equal
        # to the front end's)
        if ("FORMAT" in raw or "WRITE" in raw) and not is_comment(raw) and not _continues(raw):
            card = raw[:72].ljust(72)
            if card[6:].replace(" ", "").startswith(("FORMAT(", "WRITE(")):
                current = [card[:5].strip(), card[6:], number]
                read.append(current)
    formats, writes = {}, []
    for label, body, number in read:
        compact = body.replace(" ", "")
        if compact.startswith("FORMAT("):
            formats[int(label)] = _format_text(body)
        else:
            m = re.fullmatch(r"WRITE\(6,(\d+)\)([A-Z0-9,]*)", compact)
            writes.append((int(m[1]), tuple(filter(None, m[2].split(","))), number))
    return [Write(label, formats[label], names, number) for label, names, number in writes]


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
