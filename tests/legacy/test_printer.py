"""The printer lays out the listing's FORMATs itself; fortranformat (a separate implementation
of FORTRAN formatted output) is the reference for the layout, and the digits for binary
floats come from two routes that must agree: the exact-value rounding and Python's own."""

from __future__ import annotations

import random
from fractions import Fraction

import fortranformat
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from deck_emulator.legacy.printer import (FORMATS, Printer, format_fields, format_layout,
                                          rounded_digits)


def printable(exact: Fraction, decimals: int) -> float:
    """The float that prints ``exact`` as gfortran would, for a writer that rounds correctly
    (fortranformat rounds exact ties away from zero, and misrounds values just off a tie:
    binary64 5.0000000000000004e-06 as F15.5 gives 0.00000 where gfortran gives 0.00001)."""
    whole = int(rounded_digits(exact, decimals).replace(".", ""))
    sign = -1 if exact < 0 else 1
    if whole == 0:
        return sign * 1e-300  # keeps gfortran's '-0.00000' for a small negative value
    return float(sign * Fraction(whole, 10**decimals))


def values(seed: int, n: int):
    rng = random.Random(seed)
    out = [0.0, 1e-7, -1e-7, 0.5, -0.5, 539.640625, -539.640625, 5.0000000000000004e-06,
           1234567.0, -99999.999996, 123456789.0, -1e12, 0.000005, 9.999995]
    for _ in range(n):
        out.append(rng.choice([-1, 1]) * 10 ** rng.uniform(-7, 9))
    return out


@pytest.mark.parametrize("label", sorted(FORMATS))
def test_layout_matches_fortranformat(label):
    writer = fortranformat.FortranRecordWriter(FORMATS[label])
    decimals = [d for _, d in format_fields(format_layout(FORMATS[label]))]
    n = len(decimals)
    vals = values(label, 200)
    for binary in (True, False):
        printer = Printer(binary=binary)
        expected = []
        for i in range(0, len(vals) - n + 1, max(n, 1)):
            args = vals[i:i + n]
            printer.write(label, *args)
            items = [printable(Fraction(v), d) for v, d in zip(args, decimals)]
            expected.extend(writer.write(items).split("\n"))
            if n == 0:
                break
        assert printer.records == expected


def test_minus_zero_prints_with_its_sign_as_gfortran_does():
    # gfortran 12, REAL*8, F15.5 of -0.0D0 writes '-0.00000' (checked by compiling a WRITE)
    printer = Printer(binary=True)
    printer.write(39, -0.0)
    assert printer.records[-1].endswith("       -0.00000")


def test_the_listings_writes_are_what_the_front_end_reads_in_the_listing():
    """The one table of what the listing prints (its WRITE statements, their FORMATs and
    variables, its messages) is derived from legacy/luminaire.f by the vocabulary's small
    reader; the FORTRAN front end, a separate and checked reader of the same cards, reads the
    same WRITE lists and FORMATs in the same order, and fortranformat prints each message
    FORMAT as the message the table holds."""
    from deck_emulator.legacy import listing_lines
    from deck_emulator.legacy.fortran.parse import parse_units
    from deck_emulator.legacy.jobdeck import statements
    from deck_emulator.vocabulary.listing_writes import MESSAGES, WRITES

    units = parse_units(statements(listing_lines()))
    read = [(s.args[0], tuple(item[1] for item in s.args[1]), u.formats[s.args[0]])
            for u in units for s in u.statements if s.kind == "write"]
    assert read == [(w.label, w.variables, w.format) for w in WRITES.values()]
    assert FORMATS == {label: fmt for label, _, fmt in read}
    printed = {label: fortranformat.FortranRecordWriter(fmt).write([]).split("\n")[-1].strip()
               for label, variables, fmt in read if not variables}
    assert MESSAGES == printed and len(MESSAGES) == 10


def test_the_listings_messages_are_the_vocabularys():
    """Each event FORMAT of the listing prints the message the shared vocabulary's one table
    holds for its event (the core words its events from that table, the printer from the
    FORMATs as the listing writes them): the two agree, row for row."""
    from deck_emulator.legacy.printer import EVENT_FORMATS, event_for, event_message
    from deck_emulator.vocabulary.events import LOST_MESSAGES, EventKind, hit_message

    for label, (kind, surface, point) in EVENT_FORMATS.items():
        printed = event_message(event_for(label, 0.0, point or "P"))
        if kind is EventKind.HIT:
            expected = hit_message(surface.name, point or "P")
        else:
            expected = LOST_MESSAGES[kind]
        assert printed == expected, label


def test_the_value_fields_are_the_pages_the_golden_prints():
    """VALUE_FIELDS (read off the FORMATs) against the golden steel40 printout read here with a
    plain expression: a page is what follows a '1' line; the first contact page and the last
    free-flight page print exactly those labels, in that order, with those field widths."""
    import re
    from pathlib import Path

    from deck_emulator.legacy.printer import VALUE_FIELDS
    from deck_emulator.vocabulary.listing_writes import MESSAGES

    text = (Path(__file__).resolve().parents[2] / "golden" / "steel40.r8.txt").read_text()
    pages = [re.findall(r"THE VALUE OF (\w+) IS ( *\S+)", page) for page in text.split("\n1\n")]
    for page, first in ((pages[0], 15), (pages[-1], 60)):
        fields = [f for f in VALUE_FIELDS if f.page == first]
        assert [name for name, _ in page] == [f.name for f in fields]
        # the field: the text after 'IS ' is the Fw.d field, right-justified
        assert [len(value) for _, value in page] == [f.width for f in fields]
        assert [len(value.split(".")[1]) for _, value in page] == [f.decimals for f in fields]
    messages = set(re.findall(r"THE POST HAS .*\S", text))
    assert messages and messages <= set(MESSAGES.values())


_FORMAT_ITEMS = st.one_of(
    st.tuples(st.integers(1, 20), st.integers(0, 8)).filter(lambda wd: wd[1] < wd[0])
    .map(lambda wd: f"F{wd[0]}.{wd[1]}"),
    st.integers(1, 12).map(lambda n: f"{n}X"),
    st.text(alphabet="ABC XYZ={}.,-0123456789", min_size=1, max_size=12)
    .map(lambda t: f"{len(t)}H{t}"),
    st.just("/"))


@settings(max_examples=300, deadline=None)
@given(items=st.lists(_FORMAT_ITEMS, min_size=1, max_size=8), data=st.data())
def test_a_binary_record_is_written_as_field_by_field(items, data):
    """The binary printer writes a record through one str.format template of its FORMAT
    (Printer._plan); whatever the FORMAT and the values (NaN, infinities, -0.0, values too
    wide for their field, Fw.0, braces in Hollerith text), it writes what the field-by-field
    route (Printer._slow: Python's digits, then f_field) writes."""
    text = "(" + ",".join(items) + ")"
    n = sum(i.startswith("F") for i in items)
    values = data.draw(st.lists(st.floats(allow_nan=True, allow_infinity=True)
                                | st.floats(-1e6, 1e6), min_size=n, max_size=n))
    printer = Printer(binary=True, formats={1: text})
    printer.write(1, *values)
    reference = Printer(binary=True, formats={1: text})
    it = iter(values)
    expected = [reference._slow(pieces, it) for pieces in reference._layouts[1]]
    assert printer.records == expected
