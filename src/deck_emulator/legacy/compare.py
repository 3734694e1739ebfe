"""Two printouts of the 1967 program, lined up by their records.

Each printout is read into its records (:func:`~deck_emulator.legacy.records.read_records`),
and the two sequences are lined up by their content as a diff lines up lines: a value by its
printed label and its block's TIME, a message by its words; a stretch that does not line up
so is lined up again by the labels alone.  Every record of both printouts ends compared
(equal or differing), unreadable or missing, and the verdict is computed from these counts
alone (:attr:`Comparison.verdict`): ``agree`` only when every record was lined up, compared
and equal.  The rules as a user reads them: README, "compare".
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from difflib import SequenceMatcher

from deck_emulator.legacy.records import MESSAGE, OVERFLOW, UNKNOWN, Record, read_records
from deck_emulator.legacy.records import UNREADABLE as UNREADABLE_READING

__all__ = ["AGREE", "DIFFER", "UNREADABLE", "Comparison", "Damage", "Difference", "Missing",
           "compare", "compare_records"]

#: The three verdicts.
AGREE, DIFFER, UNREADABLE = "agree", "differ", "unreadable"


def _when(time_s: float | None) -> str:
    return "" if time_s is None else f" (TIME {time_s:g})"


@dataclass(frozen=True)
class Difference:
    """Two records lined up that disagree: each printout's record (its line, 1-based), the
    block's TIME, the label (or ``message``), the two as read, and the size (``None`` where
    no number measures it)."""

    record_a: int
    record_b: int
    time_s: float | None
    what: str
    a: str
    b: str
    size: float | None

    def line(self) -> str:
        where = (f"record {self.record_a}" if self.record_a == self.record_b
                 else f"record {self.record_a} of A, {self.record_b} of B")
        size = "" if self.size is None else f"  |difference| {self.size:.6g}"
        return f"{where}{_when(self.time_s)}: {self.what}: A {self.a}  B {self.b}{size}"


@dataclass(frozen=True)
class Damage:
    """A record of one printout (``printout``: ``"A"`` or ``"B"``) read through a scan's
    confusions (``reading`` ``damaged``: ``read_as`` what it was read as) or not readable
    (``unreadable``: ``read_as`` None; ``what`` ``?`` where its label cannot be read).
    ``text``: its line(s) as they stand; ``why``: what was read through what, or why it
    cannot be read; ``other``: the other printout's record lined up with it (its line and
    what it prints), or None."""

    printout: str
    record: int
    time_s: float | None
    what: str
    printed: str
    reading: str
    read_as: str | None
    text: str = ""
    why: tuple[str, ...] = ()
    other: str | None = None

    def line(self) -> str:
        kind = "unreadable" if self.reading == UNREADABLE_READING else "damaged"
        other = "" if self.other is None else f"; {self.other}"
        return (f"{kind}: line {self.record} of {self.printout}{_when(self.time_s)}: "
                f"{self.what}: {self.text.strip()!r}: {'; '.join(self.why)}{other}")


@dataclass(frozen=True)
class Missing:
    """A readable record of one printout (``printout``) that lines up with none of the
    other's."""

    printout: str
    record: int
    time_s: float | None
    what: str
    printed: str

    def line(self) -> str:
        other = "B" if self.printout == "A" else "A"
        return (f"missing: record {self.record} of {self.printout}{_when(self.time_s)}: "
                f"{self.what} {self.printed} is not in {other}")


@dataclass
class Comparison:
    """What comparing two printouts found: the counts (``compared``: the pairs of readable
    records lined up, values and messages; ``unreadable``: the records of either printout that
    could not be read), and each kind of finding in printed order (``damaged`` holds the
    records read through damage and the unreadable ones)."""

    records_a: int = 0
    records_b: int = 0
    aligned: int = 0
    compared: int = 0
    messages_compared: int = 0
    equal: int = 0
    unreadable: int = 0
    differences: list[Difference] = field(default_factory=list)
    damaged: list[Damage] = field(default_factory=list)
    missing: list[Missing] = field(default_factory=list)
    #: the two printouts' records lined up, in order: (index in A's records, index in B's),
    #: None on the side that lacks it (what a page shows side by side)
    lined_up: list[tuple[int | None, int | None]] = field(default_factory=list, repr=False)

    @property
    def verdict(self) -> str:
        """``agree``, ``differ`` or ``unreadable`` (see the module docstring): ``agree`` when
        every record of both printouts was lined up, compared (none unreadable, none missing,
        and there were records) and equal."""
        if self.differences or self.missing:
            return DIFFER
        if (self.equal == self.compared == self.aligned == self.records_a == self.records_b > 0
                and not self.unreadable):
            return AGREE
        return UNREADABLE

    @property
    def agree(self) -> bool:
        return self.verdict == AGREE

    def counts(self) -> dict[str, int]:
        return {"records_a": self.records_a, "records_b": self.records_b,
                "aligned": self.aligned, "compared": self.compared,
                "values_compared": self.compared - self.messages_compared,
                "messages_compared": self.messages_compared, "equal": self.equal,
                "differing": len(self.differences), "unreadable": self.unreadable,
                "missing": len(self.missing), "read_through_damage": sum(
                    d.reading != UNREADABLE_READING for d in self.damaged)}


def _key(r: Record) -> tuple:
    if r.name == UNKNOWN:
        return (UNKNOWN, id(r))  # lines up with nothing by content
    return (MESSAGE, r.read_as) if r.is_message else (r.name, r.time_s)


def _pairs(a: list[Record], b: list[Record]) -> list[tuple[int | None, int | None]]:
    """The two sequences lined up: (index in a, index in b), None on the side that lacks it."""
    out: list[tuple[int | None, int | None]] = []

    def by_place(i1, i2, j1, j2):
        """A stretch whose labels differ: a record whose label cannot be read lines up with
        the other's record at its place; the rest line up with nothing."""
        for i, j in zip(range(i1, i2), range(j1, j2)):
            if UNKNOWN in (a[i].name, b[j].name):
                out.append((i, j))
            else:
                out.extend(((i, None), (None, j)))
        n = min(i2 - i1, j2 - j1)
        out.extend((i, None) for i in range(i1 + n, i2))
        out.extend((None, j) for j in range(j1 + n, j2))

    def matched(keys_a, keys_b, offset_a, offset_b, again):
        sm = SequenceMatcher(None, keys_a, keys_b, autojunk=False)
        for tag, i1, i2, j1, j2 in sm.get_opcodes():
            i1, i2, j1, j2 = i1 + offset_a, i2 + offset_a, j1 + offset_b, j2 + offset_b
            if tag == "equal":
                out.extend(zip(range(i1, i2), range(j1, j2)))
            elif tag == "replace" and again:  # lined up again by the labels alone
                matched([_name(r) for r in a[i1:i2]], [_name(r) for r in b[j1:j2]],
                        i1, j1, False)
            elif tag == "replace":
                by_place(i1, i2, j1, j2)
            else:
                out.extend((i, None) for i in range(i1, i2))
                out.extend((None, j) for j in range(j1, j2))

    matched([_key(r) for r in a], [_key(r) for r in b], 0, 0, True)
    return out


def _name(r: Record) -> tuple:
    return (UNKNOWN, id(r)) if r.name == UNKNOWN else (r.name,)


def _shown(r: Record) -> str:
    return r.read_as if r.read_as is not None else repr(r.printed)


def _same_printed(x: Record, y: Record) -> bool:
    """Two values read as the same printed number: equal, and of the same sign (a printed
    ``-0.00000`` is not ``0.00000``)."""
    return x.value == y.value and math.copysign(1, x.value) == math.copysign(1, y.value)


def _difference(x: Record, y: Record, tolerance: float) -> Difference | None:
    time = x.time_s if x.time_s is not None else y.time_s
    if x.is_message or y.is_message:
        if x.is_message and y.is_message and x.read_as == y.read_as:
            return None
        return Difference(x.line, y.line, time, MESSAGE, repr(_shown(x)), repr(_shown(y)),
                          None)
    if OVERFLOW in (x.reading, y.reading):
        if x.reading == y.reading:
            return None
        return Difference(x.line, y.line, time, x.name, _shown(x), _shown(y), None)
    size = abs(x.value - y.value)
    if (size <= tolerance) if tolerance > 0 else _same_printed(x, y):
        return None
    return Difference(x.line, y.line, time, x.name, _shown(x), _shown(y), size)


def _other(side: str, r: Record) -> str:
    """The other printout's record lined up with an unreadable one, as a finding shows it."""
    what = "" if r.name == UNKNOWN else f"{r.name} "
    return f"lined up with {side} line {r.line}: {what}{_shown(r)}"


def compare_records(a: list[Record], b: list[Record], tolerance: float = 0.0) -> Comparison:
    """The findings between two printouts' records (see the module docstring)."""
    if not (tolerance >= 0.0 and math.isfinite(tolerance)):
        raise ValueError(f"tolerance must be finite and >= 0, got {tolerance}")
    found = Comparison(records_a=len(a), records_b=len(b))
    partner: dict[tuple[str, int], str] = {}
    found.lined_up = _pairs(a, b)
    for i, j in found.lined_up:
        if i is None or j is None:
            side, r = ("A", a[i]) if j is None else ("B", b[j])
            if r.readable:
                found.missing.append(Missing(side, r.line, r.time_s, r.name, r.printed))
            continue
        found.aligned += 1
        x, y = a[i], b[j]
        if not (x.readable and y.readable):
            partner[("A", i)] = _other("B", y)
            partner[("B", j)] = _other("A", x)
            continue
        found.compared += 1
        found.messages_compared += x.is_message and y.is_message
        difference = _difference(x, y, tolerance)
        if difference is None:
            found.equal += 1
        else:
            found.differences.append(difference)
    for side, records in (("A", a), ("B", b)):
        for k, r in enumerate(records):
            if r.why or not r.readable:
                found.unreadable += not r.readable
                found.damaged.append(Damage(
                    side, r.line, r.time_s, r.name, r.printed, r.reading,
                    r.read_as if r.readable else None, r.text, r.why,
                    partner.get((side, k)) if not r.readable else None))
    return found


def compare(a, b, tolerance: float = 0.0) -> Comparison:
    """The findings between printouts ``a`` and ``b`` (text, a list of lines, or an object
    with ``.records``)."""
    return compare_records(read_records(a), read_records(b), tolerance)
