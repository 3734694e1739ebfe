"""What the report's authors read off a line-printer printout of the 1967 program: its events,
instants and printed values.

Works on any printout of ``legacy/luminaire.f``: a gfortran golden (``golden/*.txt``) or the
emulator's ``Run.records`` -- text, a list of records, or an object with ``.records``. Only what
is printed is used; nothing is recomputed from the model.

A **block** is one page (a ``1`` record, then ``THE VALUE OF name IS value`` lines): contact
(label 88, VVA to ``TIME`` = Q) or free flight (label 98, THFA to ``TIME`` = T), its values
under the variable each WRITE prints (:data:`LABEL_VARIABLE`), an overflowed field (all ``*``)
as None.  The block just before a LOST CONTACT message is the step contact was lost at (labels
56 and 353 print it through ``GO TO 88``); the block just after the hit message is the
terminal state (``GO TO 98``); terminal points are in the report's XL, YL, ZL axes
(``XL = XX - XQO``, ``YL = YY - YYQO``, ``ZL = ZZ + HEIGHT``).  The layout and each reading
in full: docs/emulator.md, "The emulator's answers read from its printout".
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

from deck_emulator.legacy.printer import VALUE_FIELDS, printout_lines
from deck_emulator.vocabulary.events import LOST_MESSAGES, EventKind

__all__ = [
    "INSTANTS",
    "LABEL_VARIABLE",
    "Block",
    "Event",
    "ExtractError",
    "Outcome",
    "PointL",
    "extract",
    "parse_printout",
]

#: The instants the vehicle's printed speed is read at: the candidate readings of the report's
#: "DECREASE IN VEHICLE VELOCITY", in order (docs/emulator.md).
INSTANTS = ("crush_pulse_end", "first_spring_lost", "vehicle_contact_lost", "end_of_run")

#: Printed Hollerith label -> the variable the WRITE statement prints, where they differ, read
#: from the listing's WRITE lists: THA ... PSIFA print THAD ... PSIFAD (degrees), FORMAT 207
#: says ZXCMA for ZZCMA, FORMAT 133 ZYCFA for ZZCFA (typos of the listing); TIME, which prints
#: Q in contact and T in free flight, keeps its label.
LABEL_VARIABLE = MappingProxyType({
    f.name: f.variable for f in VALUE_FIELDS if f.name != f.variable
    and {g.variable for g in VALUE_FIELDS if g.name == f.name} == {f.variable}})

LOST_FIRST_SPRING = LOST_MESSAGES[EventKind.LOST_FIRST_SPRING]
LOST_VEHICLE = LOST_MESSAGES[EventKind.LOST_VEHICLE]

_VALUE = re.compile(r"THE VALUE OF (\w+) IS +(\S+)")
_MESSAGE = re.compile(r"THE POST HAS .*\S")

#: Relative tolerance for "printed FSA equals FCONST": both are printed to 5 decimals.
_PRINT_EPS = 0.5e-5


class ExtractError(ValueError):
    """The printout lacks what an outcome needs (e.g. no block at all)."""


@dataclass(frozen=True)
class Block:
    """One printed page: ``kind`` is ``"contact"`` (label 88) or ``"free"`` (label 98)."""

    kind: str
    values: Mapping[str, float | None]

    @property
    def time(self) -> float | None:
        return self.values.get("TIME")


@dataclass(frozen=True)
class Event:
    """A message with the TIME the printout gives it (see the module docstring)."""

    message: str
    time_s: float | None


@dataclass(frozen=True)
class PointL:
    """A point in the report's XL, YL, ZL axes (ft)."""

    XL: float | None
    YL: float | None
    ZL: float | None


@dataclass(frozen=True)
class Outcome:
    """The instants, events and printed values of one printout (see the module docstring)."""

    events: tuple[Event, ...]  # the LOST CONTACT messages, in order, with their times
    hit: str | None  # the final THE POST HAS HIT ... message, None if the printout has none
    hit_time_s: float | None  # TIME of the block printed after the hit message
    final_time_s: float | None  # last TIME printed
    crush_pulse_end_s: float | None  # TIME of the block the crush pulse ends at
    vehicle_speed_fps: Mapping[str, float | None]  # VVA at each of INSTANTS
    max_fsa_lb: float | None  # over the printed contact blocks
    terminal: Mapping[str, PointL]  # "P", "Q", "R", "C" in XL, YL, ZL
    terminal_time_s: float | None  # TIME of the block the terminal coordinates come from
    notes: tuple[str, ...] = field(default=())


# ------------------------------------------------------------------------------------ parsing


def _number(text: str, label: str, record: int) -> float | None:
    if set(text) <= {"*"}:
        return None  # field overflow: F10.5 / F15.5 filled with asterisks
    try:
        return float(text)
    except ValueError:
        raise ExtractError(f"record {record + 1}: THE VALUE OF {label} IS {text[:20]!r}: "
                           "not a number (a damaged printout?)") from None


def _split(text: str) -> list[str]:
    return text.splitlines() or [""]


def parse_printout(printout) -> list[Block | str]:
    """The printout as a list of blocks and messages (``THE POST HAS ...``), in printed
    order."""
    items: list[Block | str] = []
    cur: dict | None = None

    def close():
        nonlocal cur
        if cur:
            kind = "contact" if "VVA" in cur else "free" if "THFAD" in cur else "unknown"
            items.append(Block(kind, MappingProxyType(cur)))
        cur = None

    for i, rec in enumerate(printout_lines(printout, _split)):
        if rec[:1] == "1" and rec[1:].strip() == "":  # ASA page eject: a new block
            close()
            cur = {}
            continue
        m = _MESSAGE.search(rec)
        if m and "THE VALUE OF" not in rec:
            close()
            items.append(m.group(0))
            continue
        found = _VALUE.findall(rec)
        if found:
            if cur is None:  # values without a page eject before them (a cut printout)
                cur = {}
            for label, text in found:
                name = LABEL_VARIABLE.get(label, label)
                cur[name] = _number(text, label, i)
    close()
    return items


# ------------------------------------------------------------------------------------ extract


def extract(printout, deck) -> Outcome:
    """Read a printout's instants and values; ``deck`` is the Deck it was run on (or its
    ``.values``): FCONST, XQO, YYQO, HEIGHT are used."""
    d = deck if isinstance(deck, Mapping) else deck.values
    items = parse_printout(printout)
    blocks = [x for x in items if isinstance(x, Block)]
    if not blocks:
        raise ExtractError("the printout holds no block of values")
    contact = [b for b in blocks if b.kind == "contact"]
    free = [b for b in blocks if b.kind == "free"]
    notes: list[str] = []

    # events: block before each LOST CONTACT message; hit: block after the HIT message
    events: list[Event] = []
    hit = hit_time = None
    hit_block: Block | None = None
    before: dict[str, Block] = {}
    last_block: Block | None = None
    for j, x in enumerate(items):
        if isinstance(x, Block):
            last_block = x
            continue
        if "LOST CONTACT" in x:
            events.append(Event(x, last_block.time if last_block else None))
            if last_block is not None and last_block.kind == "contact":
                before.setdefault(x, last_block)
        elif "HAS HIT" in x:
            hit = x
            after = next((y for y in items[j + 1:] if isinstance(y, Block)), None)
            if after is not None:
                hit_block, hit_time = after, after.time
            else:
                notes.append("no block printed after the hit message (printout cut short)")
        else:
            notes.append(f"unrecognised message: {x}")
    times = [b.time for b in blocks if b.time is not None]
    final_time = times[-1] if times else None

    # the largest printed spring force
    fsa = [b.values["FSA"] for b in contact if b.values.get("FSA") is not None]

    # the vehicle's speed at each instant
    fconst = d["FCONST"]
    speeds: dict[str, float | None] = dict.fromkeys(INSTANTS)
    above = False
    crush_end_s = None
    for b in contact:
        f = b.values.get("FSA")
        if f is None:
            continue
        if f > fconst * (1 + _PRINT_EPS):
            above = True
        elif above and abs(f - fconst) <= fconst * _PRINT_EPS:
            speeds["crush_pulse_end"], crush_end_s = b.values.get("VVA"), b.time
            break
    if LOST_FIRST_SPRING in before:
        speeds["first_spring_lost"] = before[LOST_FIRST_SPRING].values.get("VVA")
    if LOST_VEHICLE in before:
        speeds["vehicle_contact_lost"] = before[LOST_VEHICLE].values.get("VVA")
    sv = [(b.time, b.values.get("SVFA")) for b in free
          if b.time is not None and b.values.get("SVFA") is not None]
    if len(sv) >= 2 and sv[-1][0] != sv[0][0]:
        (t0, s0), (t1, s1) = sv[0], sv[-1]
        speeds["end_of_run"] = (s1 - s0) / (t1 - t0)

    # terminal coordinates: the hit block, else the last free block
    term = hit_block if hit_block is not None and hit_block.kind == "free" else (free[-1] if free else None)
    if term is not None and hit_block is None:
        notes.append("no hit message: terminal coordinates are from the last free-flight block")
    terminal: dict[str, PointL] = {}
    if term is not None:
        xq0, yq0, h = d["XQO"], d["YYQO"], d["HEIGHT"]

        def conv(v, off, sign=-1):
            return None if v is None else v + sign * off

        for p in ("P", "Q", "R", "C"):
            v = term.values
            terminal[p] = PointL(conv(v.get(f"X{p}FA"), xq0), conv(v.get(f"YY{p}FA"), yq0),
                                 conv(v.get(f"ZZ{p}FA"), h, +1))
            starred = [n for n in (f"X{p}FA", f"YY{p}FA", f"ZZ{p}FA")
                       if n in v and v[n] is None]
            if starred:
                notes.append(f"terminal point {p} unknown: {', '.join(starred)} overflowed "
                             "its printed field (all *)")

    return Outcome(
        events=tuple(events), hit=hit, hit_time_s=hit_time, final_time_s=final_time,
        crush_pulse_end_s=crush_end_s, vehicle_speed_fps=MappingProxyType(speeds),
        max_fsa_lb=max(fsa, default=None), terminal=MappingProxyType(terminal),
        terminal_time_s=None if term is None else term.time, notes=tuple(notes),
    )
