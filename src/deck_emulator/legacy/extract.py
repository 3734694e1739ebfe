"""The outcomes the report tabulates, read back from a line-printer printout of the 1967 program.

Works on any printout of ``legacy/luminaire.f``: a gfortran golden (``golden/*.txt``) or the
emulator's ``Run.records`` -- text, a list of records, or an object with ``.records``. Only what
is printed is used; nothing is recomputed from the model.

How the printout is laid out (labels of ``legacy/luminaire.f``)
----------------------------------------------------------------
* A **block** is one page: a ``1`` record (the ``1H1`` page eject of FORMAT 15 or 60) followed by
  ``THE VALUE OF name IS value`` lines. Contact blocks (label 88) start with VVA and end with
  ``TIME`` = Q; free-flight blocks (label 98) start with THFA and end with ``TIME`` = T. Values
  are stored under the *variable* each WRITE prints, not the Hollerith label
  (:data:`LABEL_VARIABLE`). A field that overflowed its width (all ``*``) reads as ``None``.
* Contact blocks are printed when the counter E reaches 0.0016 (label 87: every 4th step of
  0.0004 s in binary64, every 5th under the 7094's chopped E counter), and also when the step
  that loses contact is found (labels 56 and 353 set M or N and ``GO TO 88``). A contact block
  is printed *before* the step is judged, so one printed by the counter can be a trial step
  that label 108 then rejects (halving H); such blocks are kept, as printed.
* **Loss of contact.** When DIFF (then DIFFT) first lies in (0, 0.01], label 56 (353) prints that
  step's block through ``GO TO 88``, and only then does control reach 354 (42), which writes
  ``THE POST HAS LOST CONTACT WITH FIRST SPRING`` (``... THE VEHICLE``). So **the block just
  before a loss-of-contact message is the step at which contact was lost**, and the event's
  time is that block's TIME. (If the step counter printed the same step as well, the block
  appears twice in a row, as in steel40 at 0.1184 s.) Only if DIFF or DIFFT were exactly 0.0
  would 354/42 be reached without that forced print; the time is then the last printed block's.
* **The hit.** The ground and vehicle checks (labels 81-462) write ``THE POST HAS HIT ...`` and
  then ``GO TO 98``, which prints the block of that same step, then STOP. So **the block just
  after the hit message is the terminal state**: its TIME is the hit time, the last TIME of the
  printout, and its coordinates are the terminal coordinates.

Definitions
-----------
* ``final_time_s``: the last TIME printed.
* ``max_decel_g``: max of the printed FSA over the contact blocks, divided by WV*G (FSA, the
  spring force, in lb; WV, the vehicle mass, in slug; G in ft/s^2). It is over the *printed*
  records only, not over every step, so a peak between two prints is missed.
* ``delta_v_candidates_mph``: the decrease of the vehicle's speed, |VVB| - |VV|, with VVB the
  deck's initial value, in mph (1 mph = 88/60 ft/s), at four instants (:data:`DELTA_V_CANDIDATES`):

  - ``crush_pulse_end``: VVA of the first contact block whose printed FSA equals FCONST after a
    block with FSA > FCONST, i.e. where the first spring's crush pulse has been cut to the
    FCONST cap (label 504). This is the one reported as ``delta_v_crush_mph``: of the four it alone
    comes near the report's figures (docs/comparison.md);
  - ``first_spring_lost``: VVA of the block before ``LOST CONTACT WITH FIRST SPRING``;
  - ``vehicle_contact_lost``: VVA of the block before ``LOST CONTACT WITH THE VEHICLE``;
  - ``end_of_run``: the vehicle's speed over the free flight, (SVFA_last - SVFA_first) /
    (TIME_last - TIME_first) of the free-flight blocks. VVFA is never changed in free flight
    (``VVFA=VVFB``) and is not printed, so this recovers it from the printed displacement; it
    equals ``vehicle_contact_lost`` to print precision.
* Terminal coordinates of P, Q, R and C in the report's XL, YL, ZL axes ("origin at the base
  of the support ... translating the XX, YY, ZZ coordinate system"): the printout's XX, YY, ZZ
  have their origin at the post's initial mass centre and the ground is ZZ = -HEIGHT (the
  listing's ground test), so ``XL = XX - XQO``, ``YL = YY - YYQO``, ``ZL = ZZ + HEIGHT``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

from deck_emulator.legacy.printer import VALUE_FIELDS, printout_lines
from deck_emulator.vocabulary.events import LOST_MESSAGES, EventKind
from deck_emulator.vocabulary.units import force_in_g, speed_lost_mph

__all__ = [
    "DELTA_V_CANDIDATES",
    "DELTA_V_DEFINITION",
    "LABEL_VARIABLE",
    "Block",
    "Event",
    "ExtractError",
    "Message",
    "Outcome",
    "PointL",
    "extract",
    "parse_printout",
]

#: The candidate definitions of the report's "DECREASE IN VEHICLE VELOCITY", in order.
DELTA_V_CANDIDATES = ("crush_pulse_end", "first_spring_lost", "vehicle_contact_lost",
                      "end_of_run")

#: The candidate reported as ``Outcome.delta_v_crush_mph`` (see the module docstring).
DELTA_V_DEFINITION = "crush_pulse_end"

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
    record: int  # index of its ``1`` record in the printout
    #: index of the record each value is printed on
    value_records: Mapping[str, int] = field(default_factory=dict, compare=False, repr=False)

    @property
    def time(self) -> float | None:
        return self.values.get("TIME")

    def __getitem__(self, name: str) -> float | None:
        return self.values[name]


@dataclass(frozen=True)
class Message:
    """One ``THE POST HAS ...`` line."""

    text: str
    record: int


@dataclass(frozen=True)
class Event:
    """A message with the TIME the printout gives it (see the module docstring)."""

    message: str
    time_s: float | None
    record: int


@dataclass(frozen=True)
class PointL:
    """A point in the report's XL, YL, ZL axes (ft)."""

    XL: float | None
    YL: float | None
    ZL: float | None

    def as_dict(self, ndigits: int | None = None) -> dict:
        """The coordinates; ``ndigits`` rounds them (the printout has 5 decimals)."""
        def r(v):
            return v if v is None or ndigits is None else round(v, ndigits)
        return {"XL": r(self.XL), "YL": r(self.YL), "ZL": r(self.ZL)}


@dataclass(frozen=True)
class Outcome:
    """What the report tabulates, as read from one printout."""

    events: tuple[Event, ...]  # the LOST CONTACT messages, in order, with their times
    hit: str | None  # the final THE POST HAS HIT ... message, None if the printout has none
    hit_time_s: float | None  # TIME of the block printed after the hit message
    final_time_s: float | None  # last TIME printed
    delta_v_crush_mph: float | None  # the candidate named by delta_v_definition
    crush_pulse_end_s: float | None  # TIME of the block that candidate is read at
    delta_v_definition: str
    delta_v_candidates_mph: Mapping[str, float | None]
    max_decel_g: float | None  # over the printed contact blocks
    max_decel_time_s: float | None
    max_fsa_lb: float | None
    terminal: Mapping[str, PointL]  # "P", "Q", "R", "C" in XL, YL, ZL
    terminal_time_s: float | None  # TIME of the block the terminal coordinates come from
    contact_blocks: int
    free_blocks: int
    notes: tuple[str, ...] = field(default=())

    def summary_dict(self) -> dict:
        """Plain JSON-able dict (floats as read, None where the printout has nothing)."""
        return {
            "events": [{"message": e.message, "time_s": e.time_s} for e in self.events],
            "hit": self.hit,
            "hit_time_s": self.hit_time_s,
            "final_time_s": self.final_time_s,
            "delta_v_crush_mph": self.delta_v_crush_mph,
            "delta_v_definition": self.delta_v_definition,
            "delta_v_candidates_mph": dict(self.delta_v_candidates_mph),
            "max_decel_g": self.max_decel_g,
            "max_decel_time_s": self.max_decel_time_s,
            "max_decel_basis": "max printed FSA over the contact blocks / (WV*G)",
            "max_fsa_lb": self.max_fsa_lb,
            "terminal_time_s": self.terminal_time_s,
            "terminal_axes": "XL = XX - XQO, YL = YY - YYQO, ZL = ZZ + HEIGHT",
            "terminal": {k: p.as_dict(5) for k, p in self.terminal.items()},  # as printed: 5 dp
            "contact_blocks": self.contact_blocks,
            "free_blocks": self.free_blocks,
            "notes": list(self.notes),
        }


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


def parse_printout(printout) -> list[Block | Message]:
    """The printout as a list of blocks and messages, in printed order."""
    items: list[Block | Message] = []
    cur: dict | None = None
    lines: dict[str, int] = {}
    start = 0

    def close():
        nonlocal cur, lines
        if cur:
            kind = "contact" if "VVA" in cur else "free" if "THFAD" in cur else "unknown"
            items.append(Block(kind, MappingProxyType(cur), start, MappingProxyType(lines)))
        cur, lines = None, {}

    for i, rec in enumerate(printout_lines(printout, _split)):
        if rec[:1] == "1" and rec[1:].strip() == "":  # ASA page eject: a new block
            close()
            cur, start = {}, i
            continue
        m = _MESSAGE.search(rec)
        if m and "THE VALUE OF" not in rec:
            close()
            items.append(Message(m.group(0), i))
            continue
        found = _VALUE.findall(rec)
        if found:
            if cur is None:  # values without a page eject before them (a cut printout)
                cur, start = {}, i
            for label, text in found:
                name = LABEL_VARIABLE.get(label, label)
                cur[name] = _number(text, label, i)
                lines[name] = i
    close()
    return items


# ------------------------------------------------------------------------------------ extract


def _deck_values(deck) -> Mapping[str, float]:
    values = deck if isinstance(deck, Mapping) else getattr(deck, "values", None)
    if not isinstance(values, Mapping):
        raise TypeError("deck must be a Deck or a mapping of READ-list names to values")
    return values


def _decrease_mph(vv0: float, vv: float | None) -> float | None:
    return None if vv is None else speed_lost_mph(vv0, vv)


def extract(printout, deck) -> Outcome:
    """Read the report's outcomes from a printout; ``deck`` is the Deck it was run on (or its
    ``.values``): VVB, WV, G, FCONST, XQO, YYQO, HEIGHT are used."""
    d = _deck_values(deck)
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
        if "LOST CONTACT" in x.text:
            events.append(Event(x.text, last_block.time if last_block else None, x.record))
            if last_block is not None and last_block.kind == "contact":
                before.setdefault(x.text, last_block)
        elif "HAS HIT" in x.text:
            hit = x.text
            after = next((y for y in items[j + 1:] if isinstance(y, Block)), None)
            if after is not None:
                hit_block, hit_time = after, after.time
            else:
                notes.append("no block printed after the hit message (printout cut short)")
        else:
            notes.append(f"unrecognised message: {x.text}")
    times = [b.time for b in blocks if b.time is not None]
    final_time = times[-1] if times else None

    # maximum deceleration over the printed contact blocks
    fsa = [(b["FSA"], b.time) for b in contact if b.values.get("FSA") is not None]
    if fsa:
        max_fsa, max_t = max(fsa, key=lambda p: p[0])
        max_decel = force_in_g(max_fsa, d["WV"], d["G"])
    else:
        max_fsa = max_t = max_decel = None

    # delta-V candidates
    vv0, fconst = d["VVB"], d["FCONST"]
    cands: dict[str, float | None] = dict.fromkeys(DELTA_V_CANDIDATES)
    above = False
    crush_end_s = None
    for b in contact:
        f = b.values.get("FSA")
        if f is None:
            continue
        if f > fconst * (1 + _PRINT_EPS):
            above = True
        elif above and abs(f - fconst) <= fconst * _PRINT_EPS:
            cands["crush_pulse_end"] = _decrease_mph(vv0, b.values.get("VVA"))
            crush_end_s = b.time
            break
    if LOST_FIRST_SPRING in before:
        cands["first_spring_lost"] = _decrease_mph(vv0, before[LOST_FIRST_SPRING].values.get("VVA"))
    if LOST_VEHICLE in before:
        cands["vehicle_contact_lost"] = _decrease_mph(vv0, before[LOST_VEHICLE].values.get("VVA"))
    sv = [(b.time, b.values.get("SVFA")) for b in free
          if b.time is not None and b.values.get("SVFA") is not None]
    if len(sv) >= 2 and sv[-1][0] != sv[0][0]:
        (t0, s0), (t1, s1) = sv[0], sv[-1]
        cands["end_of_run"] = _decrease_mph(vv0, (s1 - s0) / (t1 - t0))

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
        delta_v_crush_mph=cands[DELTA_V_DEFINITION], crush_pulse_end_s=crush_end_s,
        delta_v_definition=DELTA_V_DEFINITION,
        delta_v_candidates_mph=MappingProxyType(cands),
        max_decel_g=max_decel, max_decel_time_s=max_t, max_fsa_lb=max_fsa,
        terminal=MappingProxyType(terminal),
        terminal_time_s=None if term is None else term.time,
        contact_blocks=len(contact), free_blocks=len(free), notes=tuple(notes),
    )

