"""A printout of the 1967 program read into its records, whatever its page layout (issue 33).

A **record** is what one of the listing's FORMATs prints (:mod:`deck_emulator.legacy.printer`
says which): a labelled value, ``THE VALUE OF name IS`` and its Fw.d field (the block's
``TIME`` among them), or a message, ``THE POST HAS ...``.  Records are found by their text
wherever they stand on a line, so the page layout does not matter: carriage control in
column 1 (gfortran's and this tool's printouts), the page as the line printer printed it (form
feeds and blank lines, no control column: ``run --render``), text taken from a PDF of the
forms, blank lines dropped or fields re-spaced by a typist, two records on one line.  The page
marks themselves are not records.  The FORTRAN source of a compile listing, where the same
words stand in FORMAT statements as Hollerith constants (``20HTHE VALUE OF ...``), is not read.

A **block** is the values one page prints: it begins with the value a ``1H1`` FORMAT prints
(VVA in contact, THFA in free flight) or after the block before ends, and ends with ``TIME``;
each value carries its block's TIME, which is how two printouts' records are lined up.

A value is read as the Fw.d field its FORMAT prints (a sign, digits, a point, ``d`` digits).
One that does not read so is read through the usual confusions of a scanned page
(:data:`OCR_CONFUSIONS`: O for 0, l for 1 ...) and, where the FORMAT fixes the point's place,
with a lost or doubled point put back: it is then **damaged**, with what was printed and what
it was read as.  One that does not read even so is **unreadable**.  A field all of ``*``
overflowed its width, as Fw.d prints a value too wide for it.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable
from dataclasses import dataclass

from deck_emulator.legacy.extract import LABEL_VARIABLE
from deck_emulator.legacy.printer import MESSAGE_TEXTS, VALUE_FIELDS, VALUE_TEXT

__all__ = ["MESSAGE", "OCR_CONFUSIONS", "Record", "read_records", "read_value"]

#: The one table of a scan's confusions: a character read where a digit was printed.
OCR_CONFUSIONS = {"O": "0", "o": "0", "l": "1", "I": "1", "|": "1", "S": "5", "B": "8"}
_REPAIR = str.maketrans(OCR_CONFUSIONS)

#: The ``name`` of a message record.
MESSAGE = "message"

#: How a record was read.
NUMBER, OVERFLOW, DAMAGED, UNREADABLE, TEXT = ("number", "overflow", "damaged",
                                               "unreadable", "text")


@dataclass(frozen=True)
class Record:
    """One record: the ``line`` of the text it stands on (1-based), its ``name`` (the variable
    the WRITE prints, or :data:`MESSAGE`), what was ``printed`` (the value's field, or the
    message's words), how it was read (``reading``: number, overflow, damaged, unreadable or
    text), the ``value`` read (None for a message, an overflow or an unreadable field) and the
    text it was read as (``read_as``), and the TIME of its block (a message: the block's before
    it; None where the block's TIME is not printed or not readable)."""

    line: int
    name: str
    printed: str
    reading: str
    value: float | None = None
    read_as: str | None = None
    time_s: float | None = None

    @property
    def is_message(self) -> bool:
        return self.name == MESSAGE


def _words(text: str) -> str:
    return r"\s+".join(re.escape(w) for w in text.split())


_BEFORE, _AFTER = VALUE_TEXT.split("{name}")
_MESSAGE_START = os.path.commonprefix(list(MESSAGE_TEXTS.values())).rsplit(" ", 1)[0] + " "
_STARTS = f"(?:{_words(_BEFORE)}|{_words(_MESSAGE_START)})"
# a record's text, not a Hollerith constant in a FORMAT statement of a compile listing (20HTHE)
_RECORD = re.compile(
    rf"(?<!\dH)(?:{_words(_BEFORE)}\s*(?P<label>\w+)\s+{_words(_AFTER)}\s*(?P<field>\S*?)"
    rf"(?={_STARTS}|\s|$)|(?P<message>{_words(_MESSAGE_START)}.*?)\s*(?=(?<!\dH){_STARTS}|$))")
_FIRST_WORD = _BEFORE.split()[0]
_F_FIELD = re.compile(r"-?(?:[0-9]+\.[0-9]*|\.[0-9]+)")  # what Fw.d prints

_PAGE_STARTS = {f.name for f in VALUE_FIELDS if f.label == f.page}
_PAGE_ENDS = {f.name for f, after in zip(VALUE_FIELDS, VALUE_FIELDS[1:] + (None,))
              if after is None or after.page != f.page}
_DECIMALS: dict[tuple[int, str], int] = {(f.page, f.name): f.decimals for f in VALUE_FIELDS}
_PAGES_OF: dict[str, set[int]] = {}
for _f in VALUE_FIELDS:
    _PAGES_OF.setdefault(_f.name, set()).add(_f.page)


def read_value(printed: str, decimals: int | None) -> tuple[str, float | None, str | None]:
    """(reading, value, read as) of a printed field whose FORMAT has ``decimals`` places
    (None: not known, and a lost or doubled point is not put back)."""
    if printed and set(printed) == {"*"}:
        return OVERFLOW, None, printed
    if _F_FIELD.fullmatch(printed):
        return NUMBER, float(printed), printed
    repaired = printed.translate(_REPAIR)
    sign, digits = ("-", repaired[1:]) if repaired.startswith("-") else ("", repaired)
    if digits.count(".") != 1 and decimals is not None:
        bare = digits.replace(".", "")
        if re.fullmatch(r"[0-9]+", bare) and len(bare) >= decimals:
            digits = bare[:len(bare) - decimals] + "." + bare[len(bare) - decimals:]
    repaired = sign + digits
    if _F_FIELD.fullmatch(repaired):
        return DAMAGED, float(repaired), repaired
    return UNREADABLE, None, None


def _lines(printout) -> list[str]:
    if hasattr(printout, "records"):
        printout = printout.records
    if isinstance(printout, str):
        return printout.split("\n")  # not splitlines: a form feed is not a new line of the text
    if isinstance(printout, Iterable):
        out: list[str] = []
        for r in printout:
            if not isinstance(r, str):
                raise TypeError(f"a printout record must be str, not {type(r).__name__}")
            out.extend(r.split("\n"))
        return out
    raise TypeError(f"cannot read a printout from {type(printout).__name__}")


def read_records(printout) -> list[Record]:
    """The records of a printout (text, a list of lines, or an object with ``.records``), in
    printed order; see the module docstring."""
    found: list[tuple[int, str | None, str]] = []  # (line, label or None for a message, text)
    for number, line in enumerate(_lines(printout), start=1):
        if _FIRST_WORD not in line:
            continue
        for m in _RECORD.finditer(line):
            if m.group("message") is not None:
                found.append((number, None, " ".join(m.group("message").split())))
            else:
                found.append((number, m.group("label"), m.group("field")))

    # blocks: from a page's first value, or the record after a block's end, to TIME
    blocks: list[list[int]] = []  # indexes into found, values only
    open_block = False
    for k, (_, label, _) in enumerate(found):
        if label is None:
            open_block = False
            continue
        if label in _PAGE_STARTS or not open_block:
            blocks.append([])
        blocks[-1].append(k)
        open_block = label not in _PAGE_ENDS

    read: dict[int, Record] = {}
    for block in blocks:
        known = [_PAGES_OF[found[k][1]] for k in block if found[k][1] in _PAGES_OF]
        pages = set.intersection(*known) if known else set()
        page = next(iter(pages)) if len(pages) == 1 else None
        for k in block:
            number, label, field = found[k]
            decimals = _DECIMALS.get((page, label)) if page is not None else None
            if decimals is None:  # the page unknown: the label's places, if it has one
                places = {d for (p, n), d in _DECIMALS.items() if n == label}
                decimals = places.pop() if len(places) == 1 else None
            reading, value, read_as = read_value(field, decimals)
            read[k] = Record(number, LABEL_VARIABLE.get(label, label), field, reading, value,
                             read_as)
        time = next((read[k].value for k in reversed(block)
                     if read[k].name in _PAGE_ENDS), None)
        for k in block:
            read[k] = _with_time(read[k], time)

    records: list[Record] = []
    last_time = None
    for k, (number, label, text) in enumerate(found):
        if label is None:
            records.append(Record(number, MESSAGE, text, TEXT, None, text, last_time))
        else:
            records.append(read[k])
            last_time = read[k].time_s
    return records


def _with_time(record: Record, time: float | None) -> Record:
    return Record(record.line, record.name, record.printed, record.reading, record.value,
                  record.read_as, time)
