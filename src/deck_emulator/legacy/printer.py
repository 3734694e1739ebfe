"""The line printer: every WRITE/FORMAT of the 1967 listing, as records with ASA carriage
control in column 1 (exactly the lines gfortran writes to unit 6).

Records are laid out from the FORMAT texts below, copied from ``legacy/luminaire.f`` with
their labels; they use only Hollerith text, ``nX``, ``/`` and ``Fw.d``, which are laid out here
directly (tests/legacy/test_printer.py checks the layout against fortranformat's, and the goldens
against gfortran's). The digits are decided from the exact value (see ``rounded_digits``):
gfortran rounds exact ties to even, where fortranformat rounds them away from zero and
misrounds some values next to a tie; an arithmetic may also choose to truncate
(``format_rounding``).
"""

from __future__ import annotations

import numbers
import re
from dataclasses import dataclass

from deck_emulator.vocabulary.events import Event, EventKind, Surface

#: FORMAT statements of the listing, by label, as they stand in legacy/luminaire.f.
FORMATS: dict[int, str] = {
    # contact phase, every 4 steps
    15: "(1H1/5X,20HTHE VALUE OF VVA IS ,F15.5)",
    19: "(/,5X,20HTHE VALUE OF SVA IS ,F15.5)",
    120: "(/,5X,20HTHE VALUE OF THA IS ,F15.5)",
    121: "(/,5X,21HTHE VALUE OF PHIA IS ,F15.5)",
    122: "(/,5X,21HTHE VALUE OF PSIA IS ,F15.5)",
    20: "(/,5X,21HTHE VALUE OF XCMA IS ,F15.5)",
    27: "(/,5X,20HTHE VALUE OF XPA IS ,F15.5)",
    33: "(/,5X,20HTHE VALUE OF XSA IS ,F15.5)",
    30: "(/,5X,20HTHE VALUE OF XQA IS ,F15.5)",
    206: "(/,5X,22HTHE VALUE OF YYCMA IS ,F15.5)",
    200: "(/,5X,21HTHE VALUE OF YYPA IS ,F15.5,30X,20HTHE VALUE OF XRA IS ,F15.5)",
    202: "(/,5X,21HTHE VALUE OF YYSA IS ,F15.5,30X,21HTHE VALUE OF YYRA IS ,F15.5)",
    204: "(/,5X,21HTHE VALUE OF YYQA IS ,F15.5,30X,21HTHE VALUE OF ZZRA IS ,F15.5)",
    207: "(/,5X,22HTHE VALUE OF ZXCMA IS ,F15.5)",
    201: "(/,5X,21HTHE VALUE OF ZZPA IS ,F15.5)",
    203: "(/,5X,21HTHE VALUE OF ZZSA IS ,F15.5)",
    205: "(/,5X,21HTHE VALUE OF ZZQA IS ,F15.5)",
    39: "(/,5X,20HTHE VALUE OF FSA IS ,F15.5)",
    53: "(/,5X,21HTHE VALUE OF DIFF IS ,F15.5)",
    40: "(/,5X,21HTHE VALUE OF TIME IS ,F10.6)",
    # loss of contact
    355: "(//,5X,43HTHE POST HAS LOST CONTACT WITH FIRST SPRING)",
    100: "(//,5X,42HTHE POST HAS LOST CONTACT WITH THE VEHICLE)",
    # free flight, every 40 steps
    60: "(1H1/5X,21HTHE VALUE OF THFA IS ,F10.5)",
    61: "(/,5X,22HTHE VALUE OF PHIFA IS ,F10.5)",
    62: "(/,5X,22HTHE VALUE OF PSIFA IS ,F10.5)",
    63: "(/,5X,22HTHE VALUE OF XCMFA IS ,F10.5)",
    64: "(/,5X,21HTHE VALUE OF XPFA IS ,F10.5)",
    66: "(/,5X,21HTHE VALUE OF XQFA IS ,F10.5)",
    113: "(/,5X,21HTHE VALUE OF XRFA IS ,F10.5)",
    131: "(/,5X,21HTHE VALUE OF XCFA IS ,F15.5)",
    208: "(/,5X,23HTHE VALUE OF YYCMFA IS ,F15.5)",
    210: "(/,5X,22HTHE VALUE OF YYPFA IS ,F15.5)",
    212: "(/,5X,22HTHE VALUE OF YYQFA IS ,F15.5)",
    216: "(/,5X,22HTHE VALUE OF YYRFA IS ,F15.5)",
    132: "(/,5X,22HTHE VALUE OF YYCFA IS ,F15.5)",
    209: "(/,5X,23HTHE VALUE OF ZZCMFA IS ,F15.5)",
    211: "(/,5X,22HTHE VALUE OF ZZPFA IS ,F15.5)",
    213: "(/,5X,22HTHE VALUE OF ZZQFA IS ,F15.5)",
    217: "(/,5X,22HTHE VALUE OF ZZRFA IS ,F15.5)",
    133: "(/,5X,22HTHE VALUE OF ZYCFA IS ,F15.5)",
    75: "(/,5X,21HTHE VALUE OF SVFA IS ,F10.5)",
    76: "(/,5X,21HTHE VALUE OF TIME IS ,F10.5)",
    # the end
    134: "(/,5X,40HTHE POST HAS HIT THE GROUND WITH POINT C)",
    97: "(//,5X,40HTHE POST HAS HIT THE GROUND WITH POINT Q)",
    99: "(//,5X,40HTHE POST HAS HIT THE GROUND WITH POINT P)",
    110: "(//,5X,40HTHE POST HAS HIT THE GROUND WITH POINT R)",
    237: "(//,5X,40HTHE POST HAS HIT THE HOOD OF THE VEHICLE)",
    239: "(//,5X,46HTHE POST HAS HIT THE WINDSHIELD OF THE VEHICLE)",
    242: "(//,5X,39HTHE POST HAS HIT THE TOP OF THE VEHICLE)",
    248: "(//,5X,41HTHE POST HAS HIT THE TRUNK OF THE VEHICLE)",
}

#: The FORMATs that report an event, and what each one reports: label -> (kind, surface, point).
#: The line printer's text comes from FORMATS; the event is this row (never parsed back).
#: The listing's car messages do not name the point: the program knows it from the check it
#: was in (P at labels 500-246, R at 112-262, C at 300-462) and passes it on.
EVENT_FORMATS: dict[int, tuple[EventKind, Surface | None, str | None]] = {
    355: (EventKind.LOST_FIRST_SPRING, None, None),
    100: (EventKind.LOST_VEHICLE, None, None),
    134: (EventKind.HIT, Surface.GROUND, "C"),
    97: (EventKind.HIT, Surface.GROUND, "Q"),
    99: (EventKind.HIT, Surface.GROUND, "P"),
    110: (EventKind.HIT, Surface.GROUND, "R"),
    237: (EventKind.HIT, Surface.HOOD, None),
    239: (EventKind.HIT, Surface.WINDSHIELD, None),
    242: (EventKind.HIT, Surface.TOP, None),
    248: (EventKind.HIT, Surface.TRUNK, None),
}


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
            return re.search(r"\d+H(.*)\)$", FORMATS[label]).group(1)
    return None


_DECIMALS = {label: [int(d) for d in re.findall(r"F\d+\.(\d+)", text)] for label, text in FORMATS.items()}


def _compile(fmt: str) -> list[list]:
    """A FORMAT of the listing as records, each a list of text pieces and ``(w, d)`` F fields.

    Only what the listing's FORMATs use: ``nH`` Hollerith text, ``nX``, ``/`` and ``Fw.d``,
    separated by commas; each ``/`` ends a record."""
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


_LAYOUTS = {label: _compile(text) for label, text in FORMATS.items()}


def _fields(layout: list[list]) -> list[tuple[int, int]]:
    """The ``(w, d)`` F fields of a compiled FORMAT, in order."""
    return [p for pieces in layout for p in pieces if type(p) is tuple]


@dataclass(frozen=True)
class ValueField:
    """One labelled value the listing prints: ``THE VALUE OF name IS`` and an Fw.d field.

    ``label``: its FORMAT's; ``name``: the Hollerith label as printed (FORMAT 207 says ZXCMA
    for ZZCMA); ``page``: the label of the ``1H1`` FORMAT that starts the page it is printed
    on (15 a contact block, 60 a free-flight block: FORMATS are in the order the program
    prints them, a page being a ``1H1`` FORMAT and the value FORMATs after it)."""

    label: int
    name: str
    width: int
    decimals: int
    page: int


#: The Hollerith text before each printed value (``{name}``: its label).
VALUE_TEXT = "THE VALUE OF {name} IS "


def _value_fields() -> tuple[ValueField, ...]:
    before, after = VALUE_TEXT.split("{name}")
    shape = re.compile(re.escape(before) + r"(\w+)" + re.escape(after))
    fields: list[ValueField] = []
    page = 0
    for label, records in _LAYOUTS.items():
        if records[0] == ["1"]:  # 1H1: a new page
            page = label
        for pieces in records:
            for text, field in zip(pieces, pieces[1:]):
                named = shape.fullmatch(text) if type(text) is str else None
                if named and type(field) is tuple:
                    fields.append(ValueField(label, named.group(1), *field, page))
    return tuple(fields)


#: Every labelled value of the listing, in printed order (a page's values in the order
#: printed; the name TIME closes both pages, F10.6 in contact and F10.5 in free flight).
VALUE_FIELDS = _value_fields()

#: The texts of the FORMATs that print a message (no value), by label.
MESSAGE_TEXTS: dict[int, str] = {
    label: records[-1][-1] for label, records in _LAYOUTS.items()
    if not _DECIMALS[label] and type(records[-1][-1]) is str and records[-1][-1].strip()}


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


def printable(exact: numbers.Rational, decimals: int, rounding: str = "nearest") -> float:
    """The float that prints ``exact`` as gfortran would, for a writer that rounds correctly
    (fortranformat rounds exact ties away from zero, and misrounds values just off a tie:
    binary64 5.0000000000000004e-06 as F15.5 gives 0.00000 where gfortran gives 0.00001)."""
    whole = int(rounded_digits(exact, decimals, rounding).replace(".", ""))
    sign = -1 if exact < 0 else 1
    if whole == 0:
        return sign * 1e-300  # keeps gfortran's '-0.00000' for a small negative value
    from fractions import Fraction

    return float(sign * Fraction(whole, 10**decimals))


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
        self._layouts, self._decimals = _LAYOUTS, _DECIMALS
        if formats is not None:
            self._layouts = {label: _compile(text) for label, text in formats.items()}
            self._decimals = {label: [d for _, d in _fields(layout)]
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
                if n < 0:
                    n = sum(type(p) is not str for p in pieces)
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
        correctly rounded digits, as :meth:`_field`; ``#`` keeps Fw.0's point); a record whose
        text is not its layout's width holds a field that did not fit, and is made again by
        :meth:`_slow` (the dropped leading zero, the asterisks)."""
        records = []
        for pieces in self._layouts[label]:
            if any(type(p) is not str and p[1] == 0 for p in pieces):  # (Fw.0 of NaN: _field)
                records.append(("", -1, -1, pieces))
                continue
            template = "".join(p.replace("{", "{{").replace("}", "}}") if type(p) is str
                               else f"{{:#{p[0]}.{p[1]}f}}" for p in pieces)
            fields = sum(type(p) is not str for p in pieces)
            width = sum(len(p) if type(p) is str else p[0] for p in pieces)
            records.append((template, fields, width, pieces))
        self._plans[label] = plan = (len(self._decimals[label]), tuple(records))
        return plan

    def text(self) -> str:
        return "".join(r + "\n" for r in self.records)


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
