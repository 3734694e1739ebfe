"""Two printouts of the 1967 program, lined up by their records (issues 26, 33).

Each printout is read into its records (:func:`~deck_emulator.legacy.records.read_records`:
labelled values and messages, whatever the page layout), and the two sequences are lined up
by their content as a diff lines up lines: a value by its variable and its block's TIME, a
message by its words.  A stretch where the two do not line up so (a block whose TIME differs
or was lost) is lined up again by the variables' names alone.  So one record lost or added, or
a page mark, costs one finding, not every record after it.

Three kinds of finding, counted apart:

* a **difference**: two values lined up that differ by more than ``tolerance`` (0: exactly as
  printed), or where one field overflowed (``*``) and the other did not; two messages lined
  up whose words differ;
* a **damaged** value: read only through a scan's confusions, or not at all (unreadable);
  reported with what was printed and what it was read as, and compared as read (an unreadable
  value is compared with nothing);
* a **missing** record: one printout's record that lines up with none of the other's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from difflib import SequenceMatcher

from deck_emulator.legacy.records import DAMAGED, MESSAGE, OVERFLOW, UNREADABLE, Record, \
    read_records

__all__ = ["Comparison", "Damage", "Difference", "Missing", "compare", "compare_records"]


def _when(time_s: float | None) -> str:
    return "" if time_s is None else f" (TIME {time_s:g})"


@dataclass(frozen=True)
class Difference:
    """Two records lined up that disagree: each printout's record (its line, 1-based), the
    block's TIME, the variable (or ``message``), the two as read, and the size (``None`` where
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
    """A value of one printout (``printout``: ``"A"`` or ``"B"``) read through a scan's
    confusions (``reading`` ``damaged``: ``read_as`` what it was read as) or not readable
    (``unreadable``: ``read_as`` None)."""

    printout: str
    record: int
    time_s: float | None
    what: str
    printed: str
    reading: str
    read_as: str | None

    def line(self) -> str:
        read = (f"read as {self.read_as}" if self.read_as is not None
                else "unreadable: compared with nothing")
        return (f"damaged: record {self.record} of {self.printout}{_when(self.time_s)}: "
                f"{self.what}: printed {self.printed!r}, {read}")


@dataclass(frozen=True)
class Missing:
    """A record of one printout (``printout``) that lines up with none of the other's."""

    printout: str
    record: int
    time_s: float | None
    what: str
    printed: str

    def line(self) -> str:
        other = "B" if self.printout == "A" else "A"
        return (f"missing: record {self.record} of {self.printout}{_when(self.time_s)}: "
                f"{self.what} {self.printed} is not in {other}")


@dataclass(frozen=True)
class Comparison:
    """What comparing two printouts found, each kind in printed order."""

    differences: list[Difference] = field(default_factory=list)
    damaged: list[Damage] = field(default_factory=list)
    missing: list[Missing] = field(default_factory=list)

    @property
    def agree(self) -> bool:
        """No value differs and no record is missing (damage alone does not count)."""
        return not self.differences and not self.missing


def _key(r: Record) -> tuple:
    return (MESSAGE, r.printed) if r.is_message else (r.name, r.time_s)


def _pairs(a: list[Record], b: list[Record]) -> list[tuple[int | None, int | None]]:
    """The two sequences lined up: (index in a, index in b), None on the side that lacks it."""
    out: list[tuple[int | None, int | None]] = []

    def matched(keys_a, keys_b, offset_a, offset_b, again):
        sm = SequenceMatcher(None, keys_a, keys_b, autojunk=False)
        for tag, i1, i2, j1, j2 in sm.get_opcodes():
            if tag == "equal":
                out.extend(zip(range(offset_a + i1, offset_a + i2),
                               range(offset_b + j1, offset_b + j2)))
            elif tag == "replace" and again:  # lined up again by the names alone
                matched([r.name for r in a[offset_a + i1:offset_a + i2]],
                        [r.name for r in b[offset_b + j1:offset_b + j2]],
                        offset_a + i1, offset_b + j1, False)
            else:
                out.extend((i, None) for i in range(offset_a + i1, offset_a + i2))
                out.extend((None, j) for j in range(offset_b + j1, offset_b + j2))

    matched([_key(r) for r in a], [_key(r) for r in b], 0, 0, True)
    return out


def _shown(r: Record) -> str:
    return r.read_as if r.read_as is not None else repr(r.printed)


def _difference(x: Record, y: Record, tolerance: float) -> Difference | None:
    time = x.time_s if x.time_s is not None else y.time_s
    if x.is_message or y.is_message:
        if x.printed == y.printed:
            return None
        return Difference(x.line, y.line, time, MESSAGE, repr(x.printed), repr(y.printed), None)
    if UNREADABLE in (x.reading, y.reading):
        return None  # reported as damage: nothing to compare with
    if OVERFLOW in (x.reading, y.reading):
        if x.reading == y.reading:
            return None
        return Difference(x.line, y.line, time, x.name, _shown(x), _shown(y), None)
    size = abs(x.value - y.value)
    if size <= tolerance:
        return None
    return Difference(x.line, y.line, time, x.name, _shown(x), _shown(y), size)


def compare_records(a: list[Record], b: list[Record], tolerance: float = 0.0) -> Comparison:
    """The findings between two printouts' records (see the module docstring)."""
    if not (tolerance >= 0.0 and math.isfinite(tolerance)):
        raise ValueError(f"tolerance must be finite and >= 0, got {tolerance}")
    found = Comparison()
    for side, records in (("A", a), ("B", b)):
        found.damaged.extend(Damage(side, r.line, r.time_s, r.name, r.printed, r.reading,
                                    r.read_as if r.reading == DAMAGED else None)
                             for r in records if r.reading in (DAMAGED, UNREADABLE))
    for i, j in _pairs(a, b):
        if i is None or j is None:
            side, r = ("A", a[i]) if j is None else ("B", b[j])
            found.missing.append(Missing(side, r.line, r.time_s, r.name, r.printed))
            continue
        difference = _difference(a[i], b[j], tolerance)
        if difference is not None:
            found.differences.append(difference)
    return found


def compare(a, b, tolerance: float = 0.0) -> Comparison:
    """The findings between printouts ``a`` and ``b`` (text, a list of lines, or an object
    with ``.records``)."""
    return compare_records(read_records(a), read_records(b), tolerance)
