"""A printout of the 1967 program read into its records, whatever its page layout.

A **record** is what one of the listing's FORMATs prints: a labelled value (``THE VALUE OF
label IS`` and its Fw.d field, named by the label printed on the paper) or a message (``THE
POST HAS ...``), found by its text wherever it stands: carriage control, a rendered page,
``pdftotext`` output with or without ``-layout`` (a label that ends its line takes the lone
field of the next non-blank line), re-spaced fields, two records on a line.  A compile
listing's FORMAT statements are not records.  What the FORMATs print is read from the listing
only (``printer.VALUE_FIELDS``, ``printer.VALUE_TEXT``, ``listing_writes.MESSAGES``).  A
**block** is the values one page prints, up to ``TIME``: each value carries its block's TIME.
A record read through a scan's confusions (:data:`OCR_CONFUSIONS`) is **damaged** and says
why; one that does not read even so is **unreadable** (README, "compare").
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from functools import lru_cache

from deck_emulator.legacy.printer import VALUE_FIELDS, VALUE_TEXT, printout_lines
from deck_emulator.vocabulary.listing_writes import MESSAGES

__all__ = ["LABELS", "MESSAGE", "OCR_CONFUSIONS", "UNKNOWN", "Record", "read_records",
           "read_value"]

#: The one table of a scan's confusions: a character read where a digit was printed.
OCR_CONFUSIONS = {"O": "0", "o": "0", "l": "1", "I": "1", "|": "1", "S": "5", "B": "8"}
_REPAIR = str.maketrans(OCR_CONFUSIONS)

#: The ``name`` of a message record.
MESSAGE = "message"
#: The ``name`` of a record whose label cannot be read (or a line that looks like a record).
UNKNOWN = "?"

#: How a record was read.
NUMBER, OVERFLOW, DAMAGED, UNREADABLE, TEXT = ("number", "overflow", "damaged",
                                               "unreadable", "text")


@dataclass(frozen=True)
class Record:
    """One record: the ``line`` of the text it stands on (1-based; a value on a line of its
    own after its label's: the label's), its ``name`` (the label printed on the paper,
    :data:`MESSAGE`, or :data:`UNKNOWN`), what was ``printed`` (the value's field, or the
    message's words), how it was read (``reading``: number, overflow, damaged, unreadable or
    text), the ``value`` read (None for a message, an overflow or an unreadable record) and
    the text it was read as (``read_as``; None where unreadable), the TIME of its block (a
    message: the block's before it; None where the block's TIME is not printed or not
    readable), the ``text`` of its line(s) as they stand, and ``why``: what was read through
    damage, or why it is unreadable."""

    line: int
    name: str
    printed: str
    reading: str
    value: float | None = None
    read_as: str | None = None
    time_s: float | None = None
    text: str = ""
    why: tuple[str, ...] = ()

    @property
    def is_message(self) -> bool:
        return self.name == MESSAGE

    @property
    def readable(self) -> bool:
        return self.reading != UNREADABLE


# ------------------------------------------------------- what the listing's FORMATs print

#: Every label the listing prints (FORMAT 207's ``ZXCMA`` as printed).
LABELS = frozenset(f.name for f in VALUE_FIELDS)
_MESSAGES = frozenset(" ".join(t.split()) for t in MESSAGES.values())
_BEFORE, _AFTER = VALUE_TEXT.split("{name}")
_MESSAGE_START = os.path.commonprefix(sorted(_MESSAGES)).rsplit(" ", 1)[0] + " "
_PAGE_STARTS = {f.name for f in VALUE_FIELDS if f.label == f.page}
_PAGE_ENDS = {f.name for f, after in zip(VALUE_FIELDS, VALUE_FIELDS[1:] + (None,))
              if after is None or after.page != f.page}
#: (page, label) -> (width, decimals) of the label's Fw.d field on that page
_FIELD: dict[tuple[int, str], tuple[int, int]] = {
    (f.page, f.name): (f.width, f.decimals) for f in VALUE_FIELDS}
_PAGES_OF: dict[str, set[int]] = {}
for _f in VALUE_FIELDS:
    _PAGES_OF.setdefault(_f.name, set()).add(_f.page)


# ----------------------------------------------------------------- a scan's confusions

_DIGIT_READ_AS: dict[str, set[str]] = {}  # a digit -> what a scan reads for it, itself too
for _c, _d in OCR_CONFUSIONS.items():
    _DIGIT_READ_AS.setdefault(_d, {_d}).add(_c)


def _read_for(c: str) -> frozenset[str]:
    """What a scan may read where ``c`` was printed: itself (either case), and for a letter
    or digit of :data:`OCR_CONFUSIONS` every character confused with the same digit."""
    out = {c, c.lower(), c.upper()}
    for group in _DIGIT_READ_AS.values():
        if out & group:
            out |= group
    return frozenset(out)


def _damaged_word(word: str) -> str:
    """A regular expression for ``word`` as a scan may read it."""
    return "".join("[" + re.escape("".join(sorted(_read_for(c)))) + "]" for c in word)


def _words(text: str) -> str:
    return r"\s+".join(_damaged_word(w) for w in text.split())


def _reads_as(seen: str, printed: str) -> bool:
    """Whether ``seen`` may be what a scan read where ``printed`` was printed."""
    return len(seen) == len(printed) and all(s in _read_for(p) for s, p in zip(seen, printed))


_START = f"(?<!\\dH)(?:{_words(_BEFORE)}|{_words(_MESSAGE_START)})"
_RECORD = re.compile(
    rf"(?<!\dH)(?:(?P<before>{_words(_BEFORE)})\s*(?P<label>\S+)\s+"
    rf"(?P<after>{_words(_AFTER)})\s*(?P<field>\S*?)(?={_START}|\s|$)"
    rf"|(?P<message>{_words(_MESSAGE_START)}.*?)\s*(?={_START}|$))")
_STARTS_LINE = re.compile(rf"\s*{_START}")
_F_FIELD = re.compile(r"-?(?:[0-9]+\.([0-9]*)|\.([0-9]+))")  # what Fw.d prints
#: a lone field on a line of its own (damaged or not): a digit, a point or a star in it
_LONE_FIELD = re.compile(r".*[0-9.*].*")
#: a lone field no label claimed, read as a record that cannot be read: a number with a
#: point (read through a scan's confusions), or the stars of an overflowed field
_STRAY_FIELD = re.compile(r"-?(?:[0-9]+\.[0-9]*|\.[0-9]+)|\*{1,%d}"
                          % max(f.width for f in VALUE_FIELDS))
_LOOKS_LIKE = [" ".join(_BEFORE.split()), " ".join(_MESSAGE_START.split())]


@lru_cache(maxsize=256)
def _read_words(seen: str, printed: str) -> str | None:
    """Why the words ``seen`` are read as ``printed`` (None: they are the same words)."""
    seen, printed = " ".join(seen.split()), " ".join(printed.split())
    return None if seen == printed else f"words {seen!r} read as {printed!r}"


@lru_cache(maxsize=1024)
def _known(kind: str, seen: str) -> tuple[str | None, str | None]:
    """(the ``kind`` -- label or message -- that ``seen`` stands for or None, why: None when
    read as printed)."""
    known = LABELS if kind == "label" else _MESSAGES
    if seen in known:
        return seen, None
    could = sorted(k for k in known if _reads_as(seen, k))
    if len(could) == 1:
        said = could[0] if kind == "label" else repr(could[0])
        return could[0], f"{kind} {seen!r} read as {said}"
    if could:
        return None, f"{kind} {seen!r} could be any of {', '.join(could)}"
    return None, f"{kind} {seen!r} is none of the listing's"


def _places(field: str) -> int:
    m = _F_FIELD.fullmatch(field)
    return len(m.group(1) if m.group(1) is not None else m.group(2))


def read_value(printed: str, decimals: int | None, width: int | None = None
               ) -> tuple[str, float | None, str | None, str | None]:
    """(reading, value, read as, why) of a printed field whose FORMAT is F``width``.``decimals``
    (None: not known; then a lost or doubled point is not put back and no count of decimals
    or width is checked).  ``why`` says what was read through damage, or why the field is
    unreadable; None for a field read as printed."""
    shape = "its FORMAT" if decimals is None else f"F{width}.{decimals}"
    if not printed:
        return UNREADABLE, None, None, "no value printed"
    if set(printed) == {"*"}:
        return OVERFLOW, None, printed, None
    repaired, why = printed, None
    if not _F_FIELD.fullmatch(printed):
        repaired = printed.translate(_REPAIR)
        sign, digits = ("-", repaired[1:]) if repaired.startswith("-") else ("", repaired)
        if digits.count(".") != 1 and decimals is not None:
            bare = digits.replace(".", "")
            if re.fullmatch(r"[0-9]+", bare) and len(bare) >= decimals:
                digits = bare[:len(bare) - decimals] + "." + bare[len(bare) - decimals:]
        repaired = sign + digits
        if not _F_FIELD.fullmatch(repaired):
            return UNREADABLE, None, None, f"value {printed!r} is not a number {shape} prints"
        why = f"value {printed!r} read as {repaired}"
    if decimals is not None and _places(repaired) != decimals:
        return (UNREADABLE, None, None, f"value {printed!r} has {_places(repaired)} "
                f"decimal(s) where {shape} prints {decimals}")
    if width is not None and len(repaired) > width:
        return UNREADABLE, None, None, f"value {printed!r} is wider than {shape} prints"
    return (NUMBER if why is None else DAMAGED), float(repaired), repaired, why


@dataclass
class _Found:
    """A record found in the text, before its value is read."""

    line: int
    name: str  # a label of LABELS, MESSAGE or UNKNOWN
    printed: str
    text: str
    why: list[str]
    unreadable: bool = False  # its label or words cannot be read
    message: str | None = None  # the listing's message it stands for


def _find(lines: list[str]) -> list[_Found]:
    """The records of the text's lines, in order (values not yet read)."""
    found: list[_Found] = []
    taken: set[int] = set()  # lines that hold a record or a record's value
    for k, line in enumerate(lines):
        if k in taken or not line.strip():
            continue
        for m in _RECORD.finditer(line):
            taken.add(k)
            why: list[str] = []
            if m.group("message") is not None:
                seen = " ".join(m.group("message").split())
                text, why_message = _known("message", seen)
                if why_message:
                    why.append(why_message)
                found.append(_Found(k + 1, MESSAGE, seen, line, why, text is None, text))
                continue
            for part, printed in ((m.group("before"), _BEFORE), (m.group("after"), _AFTER)):
                why_words = _read_words(part, printed)
                if why_words:
                    why.append(why_words)
            name, why_label = _known("label", m.group("label"))
            if why_label:
                why.append(why_label)
            field, text = m.group("field") or "", line
            if not field and not line[m.end():].strip():  # its value on a line of its own?
                j = next((j for j in range(k + 1, len(lines)) if lines[j].strip()), None)
                if j is not None and _lone_field(lines[j]):
                    field, text = lines[j].strip(), f"{line}\n{lines[j]}"
                    taken.add(j)
            found.append(_Found(k + 1, name or UNKNOWN, field, text, why, name is None))
        if k not in taken and _looks_like_a_record(line):
            found.append(_Found(k + 1, UNKNOWN, line.strip(), line,
                                ["not read as a record of the listing"], True))
    return found


def _lone_field(line: str) -> bool:
    """Whether ``line`` holds a lone field (plain ``pdftotext``: a value below its label),
    not a page mark (``1``) nor the start of a record."""
    token = line.strip()
    return (len(token.split()) == 1 and line.rstrip() != "1"
            and not _STARTS_LINE.match(line) and _LONE_FIELD.fullmatch(token) is not None)


def _looks_like_a_record(line: str) -> bool:
    """A line no record was read from that looks like one: its start resembles a record's
    words, or it is a lone field that no label claimed."""
    from difflib import SequenceMatcher

    text = " ".join(line.split()).upper()
    if not text or re.search(r"\dH", text):
        return False  # blank, or a FORMAT statement of a compile listing
    if _lone_field(line) and _STRAY_FIELD.fullmatch(text.translate(_REPAIR)):
        return True
    return any(len(text) >= 0.75 * len(start)
               and SequenceMatcher(None, text[:len(start)], start).ratio() >= 0.75
               for start in _LOOKS_LIKE)


def read_records(printout) -> list[Record]:
    """The records of a printout (text, a list of lines, or an object with ``.records``), in
    printed order; see the module docstring."""
    found = _find(printout_lines(printout))

    # blocks: from a page's first value, or the record after a block's end, to TIME
    blocks: list[list[int]] = []  # indexes into found, values of a known label only
    open_block = False
    for k, f in enumerate(found):
        if f.name == MESSAGE:
            open_block = False
            continue
        if f.name == UNKNOWN:
            continue
        if f.name in _PAGE_STARTS or not open_block:
            blocks.append([])
        blocks[-1].append(k)
        open_block = f.name not in _PAGE_ENDS

    read: dict[int, Record] = {}
    for block in blocks:
        pages = set.intersection(*(_PAGES_OF[found[k].name] for k in block))
        page = next(iter(pages)) if len(pages) == 1 else None
        values = []
        for k in block:
            f = found[k]
            shape = _FIELD.get((page, f.name)) if page is not None else None
            if shape is None:  # the page unknown: the label's field, if it has one only
                shapes = {s for (_, n), s in _FIELD.items() if n == f.name}
                shape = shapes.pop() if len(shapes) == 1 else (None, None)
            width, decimals = shape
            reading, value, read_as, why = read_value(f.printed, decimals, width)
            if why:
                f.why.append(why)
            if reading == NUMBER and f.why:  # its words or label read through damage
                reading = DAMAGED
            values.append((reading, value, read_as))
        time = next((value for k, (_, value, _) in zip(reversed(block), reversed(values))
                     if found[k].name in _PAGE_ENDS), None)
        for k, (reading, value, read_as) in zip(block, values):
            f = found[k]
            read[k] = Record(f.line, f.name, f.printed, reading, value, read_as, time, f.text,
                             tuple(f.why))

    records: list[Record] = []
    last_time = None
    for k, f in enumerate(found):
        if k in read:
            records.append(read[k])
            last_time = read[k].time_s
        elif f.name == MESSAGE:
            reading = UNREADABLE if f.unreadable else DAMAGED if f.why else TEXT
            records.append(Record(f.line, MESSAGE, f.printed, reading, None, f.message,
                                  last_time, f.text, tuple(f.why)))
        else:  # a label that cannot be read, or a line that looks like a record
            records.append(Record(f.line, UNKNOWN, f.printed, UNREADABLE, None, None,
                                  last_time, f.text, tuple(f.why)))
    return records

