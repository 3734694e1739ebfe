"""The line printer: every WRITE/FORMAT of the 1967 listing, as records with ASA carriage
control in column 1 (exactly the lines gfortran writes to unit 6).

Records are laid out from the FORMAT texts the listing writes with (:data:`FORMATS`, read
from ``legacy/luminaire.f`` itself); they use only Hollerith text, ``nX``, ``/`` and ``Fw.d``,
which are laid out here directly (tests/legacy/test_printer.py checks the layout against
fortranformat's, and the goldens against gfortran's). The digits are decided from the exact
value (see ``rounded_digits``): gfortran rounds exact ties to even, where fortranformat rounds
them away from zero and misrounds some values next to a tie; an arithmetic may also choose to
truncate (``format_rounding``).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterable
from dataclasses import dataclass

from deck_emulator.vocabulary import listing_writes
from deck_emulator.vocabulary.events import EVENT_FORMATS, Event, EventKind

TYPE_CHECKING = False  # (typing.TYPE_CHECKING's value, without importing typing, as engines.py)
if TYPE_CHECKING:  # (numbers only names a type here: a run does not load it)
    import numbers

#: The FORMATs the listing writes with, by label, in the listing's order: read from
#: legacy/luminaire.f (:mod:`deck_emulator.vocabulary.listing_writes`); the FORMATs that report
#: an event and what each reports (kind, surface, point) are read off their messages
#: (:data:`deck_emulator.vocabulary.events.EVENT_FORMATS`).
FORMATS = listing_writes.FORMATS


def event_for(label: int, time_s: float, point: str | None = None) -> Event:
    """The event FORMAT ``label`` reports at ``time_s`` (``point``: the car hit's point)."""
    kind, surface, fixed = EVENT_FORMATS[label]
    if kind is not EventKind.HIT:
        return Event(kind, time_s, None, None, label)
    return Event(kind, time_s, surface, fixed or point, label)


def event_message(event: Event) -> str | None:
    """The line printer's text for ``event`` (None for an event the listing never prints)."""
    for label, (kind, surface, point) in EVENT_FORMATS.items():
        if kind is event.kind and surface is event.surface and (
                point is None or point == event.point):
            return listing_writes.MESSAGES[label]
    return None


@functools.lru_cache(maxsize=None)
def format_layout(fmt: str) -> list[list]:
    """A FORMAT's text (as the front end normalises it) as records, each a list of text
    pieces and ``(w, d)`` F fields: ``nH`` Hollerith text, ``nX``, ``/`` and ``Fw.d``,
    separated by commas; each ``/`` ends a record.  Shared by a process's runs: never changed."""
    body = fmt[1:-1]
    records: list[list] = [[]]
    i = 0
    while i < len(body):
        c = body[i]
        if c == ",":
            i += 1
        elif c == "/":
            records.append([])
            i += 1
        elif c == "F":
            m = re.match(r"F(\d+)\.(\d+)", body[i:])
            records[-1].append((int(m.group(1)), int(m.group(2))))
            i += m.end()
        else:
            m = re.match(r"(\d+)([HX])", body[i:])
            if m is None:
                raise ValueError(f"FORMAT item not handled at {body[i:]!r} in {fmt}")
            n, kind = int(m.group(1)), m.group(2)
            i += m.end()
            if kind == "X":
                records[-1].append(" " * n)
            else:
                records[-1].append(body[i:i + n])
                i += n
    return records


def __getattr__(name: str):
    # VALUE_FIELDS: the listing's, made when first read (a run lays out its own FORMATs)
    if name == "VALUE_FIELDS":
        return _value_fields()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def format_fields(layout: list[list]) -> list[tuple[int, int]]:
    """The ``(w, d)`` F fields of a :func:`format_layout`, in order."""
    return [p for pieces in layout for p in pieces if type(p) is tuple]


@dataclass(frozen=True)
class ValueField:
    """One labelled value the listing prints: ``THE VALUE OF name IS`` and an Fw.d field.

    ``label``: its FORMAT's; ``name``: the Hollerith label as printed (FORMAT 207 says ZXCMA
    for ZZCMA); ``page``: the label of the ``1H1`` FORMAT that starts the page it is printed
    on (15 a contact block, 60 a free-flight block: FORMATS are in the order the program
    prints them, a page being a ``1H1`` FORMAT and the value FORMATs after it);
    ``variable``: what the WRITE prints there (ZZCMA, THAD for THA's degrees, Q or T for TIME)."""

    label: int
    name: str
    width: int
    decimals: int
    page: int
    variable: str


#: The Hollerith text before each printed value (``{name}``: its label).
VALUE_TEXT = "THE VALUE OF {name} IS "


@functools.cache
def _value_fields() -> tuple[ValueField, ...]:
    """VALUE_FIELDS: every labelled value of the listing, in printed order (the name TIME
    closes both pages, F10.6 in contact and F10.5 in free flight)."""
    before, after = VALUE_TEXT.split("{name}")
    shape = re.compile(re.escape(before) + r"(\w+)" + re.escape(after))
    fields: list[ValueField] = []
    page = 0
    for label, text in FORMATS.items():
        records = format_layout(text)
        if records[0] == ["1"]:  # 1H1: a new page
            page = label
        for pieces in records:
            for text, field in zip(pieces, pieces[1:]):
                named = shape.fullmatch(text) if type(text) is str else None
                if named and type(field) is tuple:
                    printed = listing_writes.WRITES[label].variables
                    k = sum(f.label == label for f in fields)
                    fields.append(ValueField(label, named.group(1), *field, page, printed[k]))
    return tuple(fields)


def f_field(digits: str, negative: bool, w: int) -> str:
    """An Fw.d field from the rounded digits ``[-]i.fff`` without sign: right-justified in w
    columns; the leading zero of a number below 1 is dropped when it does not fit, and a
    number that still does not fit prints as w asterisks (gfortran and fortranformat alike)."""
    text = ("-" if negative else "") + digits
    if len(text) > w and digits.startswith("0.") and digits != "0.":
        text = ("-" if negative else "") + digits[1:]
    if len(text) > w:
        return "*" * w
    return text.rjust(w)


def rounded_digits(exact: numbers.Rational, decimals: int, rounding: str = "nearest") -> str:
    """|exact| (a :class:`fractions.Fraction`) rounded to ``decimals`` places as gfortran does
    (ties to even), or chopped."""
    scaled = abs(exact) * 10**decimals
    whole, rest = divmod(scaled, 1)
    if rounding == "nearest":  # rest against one half, exactly, in the rational's own type
        if 2 * rest > 1 or (2 * rest == 1 and whole % 2):
            whole += 1
    elif rounding != "truncate":
        raise ValueError(f"unknown output rounding {rounding!r}")
    s = str(int(whole)).rjust(decimals + 1, "0")
    return s[:len(s) - decimals] + "." + s[len(s) - decimals:]


class Printer:
    """Collects the records one run writes to unit 6.

    ``exact`` gives a value's exact value as a Fraction (default: ``Fraction`` itself) and
    ``rounding`` says how the digits are chosen from it. ``binary=True`` says the values are
    IEEE binary floats (or convert to a binary64 exactly): their digits then come from Python's
    formatting, which is correctly rounded from the exact binary value with exact ties to even,
    as gfortran's; a minus zero prints as ``-0.00000``, as gfortran prints it."""

    def __init__(self, exact=None, rounding: str = "nearest", *, binary: bool = False,
                 formats: dict[int, str] | None = None):
        if exact is None:
            from fractions import Fraction as exact
        self._exact = exact
        self._rounding = rounding
        self._binary = binary and rounding == "nearest"
        self.records: list[str] = []
        self._plans: dict = {}  # (binary) label -> (values, its records' templates): _plan
        # the listing's FORMATs, or a program's own (``formats``: label -> text, as FORMATS)
        formats = FORMATS if formats is None else formats
        self._layouts = {label: format_layout(text) for label, text in formats.items()}
        self._decimals = {label: [d for _, d in format_fields(layout)]
                          for label, layout in self._layouts.items()}

    def _field(self, value, w: int, d: int) -> str:
        if self._binary:
            x = float(value)
            text = f"{x:.{d}f}" + ("." if d == 0 else "")  # (Fw.0: "2.", as gfortran)
            negative = text[0] == "-"
            return f_field(text[1:] if negative else text, negative, w)
        exact = self._exact(value)
        return f_field(rounded_digits(exact, d, self._rounding), exact < 0, w)

    def write(self, label: int, *values) -> None:
        """``WRITE(6,label) values``: append the records that FORMAT ``label`` makes."""
        if self._binary:
            plan = self._plans.get(label) or self._plan(label)
            if len(values) != plan[0]:
                raise ValueError(f"FORMAT {label} takes {plan[0]} values, got {len(values)}")
            i = 0
            for template, n, width, pieces in plan[1]:
                text = template.format(*values[i:i + n])
                # (a field wider than its w, or a value that is no float: as _field says)
                self.records.append(text if len(text) == width else
                                    self._slow(pieces, iter(values[i:i + n])))
                i += n
            return
        layout = self._layouts[label]
        decimals = self._decimals[label]
        if len(values) != len(decimals):
            raise ValueError(f"FORMAT {label} takes {len(decimals)} values, got {len(values)}")
        it = iter(values)
        for pieces in layout:
            self.records.append(self._slow(pieces, it))

    def _slow(self, pieces, it) -> str:
        return "".join(p if type(p) is str else self._field(next(it), *p) for p in pieces)

    def _plan(self, label: int):
        """A binary FORMAT's records as str.format templates: Fw.d is ``{:#w.df}`` (Python's
        correctly rounded digits, as :meth:`_field`; a record with an Fw.0 is always made by
        :meth:`_slow`, which writes its point and NaN as _field does); a record whose
        text is not its layout's width holds a field that did not fit, and is made again by
        :meth:`_slow` (the dropped leading zero, the asterisks)."""
        records = []
        for pieces in self._layouts[label]:
            fields = sum(type(p) is not str for p in pieces)
            if any(type(p) is not str and p[1] == 0 for p in pieces):  # (Fw.0 of NaN: _field)
                records.append(("", fields, -1, pieces))  # (width -1: always field by field)
                continue
            template = "".join(p.replace("{", "{{").replace("}", "}}") if type(p) is str
                               else f"{{:#{p[0]}.{p[1]}f}}" for p in pieces)
            width = sum(len(p) if type(p) is str else p[0] for p in pieces)
            records.append((template, fields, width, pieces))
        self._plans[label] = plan = (len(self._decimals[label]), tuple(records))
        return plan


def render_asa(records: list[str]) -> str:
    """Render records for a screen or a PDF as the POSIX ``asa`` utility does: column 1 is
    carriage control ('1' new page, '0' one blank line first, '+' overprint the previous line,
    anything else a single space) and is not printed."""
    out: list[str] = []
    for rec in records:
        cc, body = (rec[:1] or " "), rec[1:]
        if cc == "1":
            out.append("\f" + body)
        elif cc == "+" and out:
            out[-1] += "\r" + body
        elif cc == "0":
            out.append("\n" + body)
        else:
            out.append(body)
    return "\n".join(out) + "\n"


def printout_lines(printout, split=lambda text: text.split("\n")) -> list[str]:
    """The lines of a printout -- text, a list of records, or an object with ``.records`` --
    each text cut by ``split`` (by default at line ends only: a form feed is no new line)."""
    if hasattr(printout, "records"):
        printout = printout.records
    if isinstance(printout, str):
        return split(printout)
    if isinstance(printout, Iterable):
        out: list[str] = []
        for r in printout:
            if not isinstance(r, str):
                raise TypeError(f"a printout record must be str, not {type(r).__name__}")
            out.extend(split(r))
        return out
    raise TypeError(f"cannot read a printout from {type(printout).__name__}")
