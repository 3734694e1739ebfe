"""The 1967 engine (the listing through the FORTRAN front end, legacy/fortran) against the
printouts of the compiled listing (golden/, made by gfortran), and its guards.

The goldens are the independent source: they come from compiling legacy/luminaire.f, never
from this package. Records are compared as text, numeric fields as numbers.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.fortran import run_deck
from deck_emulator.legacy.stops import EmulatorError, Limits

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = ROOT / "golden"
NUMBER = re.compile(r"-?\d+\.\d+")


def golden_runs(precision: str):
    """(deck name, errata, golden path) for every golden of one precision."""
    out = []
    for path in sorted(GOLDEN.glob(f"*.{precision}.txt")):
        parts = path.name.split(".")
        errata = tuple(parts[1:-2])
        out.append(pytest.param(parts[0], errata, path, id=path.name))
    return out


def compare_records(ours: list[str], theirs: list[str]):
    """Share of identical numeric fields, largest relative difference, and text mismatches."""
    assert len(ours) == len(theirs), f"{len(ours)} records, golden has {len(theirs)}"
    fields = same = 0
    worst = 0.0
    text_diffs = []
    for n, (a, b) in enumerate(zip(ours, theirs), start=1):
        if NUMBER.sub("#", a) != NUMBER.sub("#", b):
            text_diffs.append((n, a, b))
            continue
        for x, y in zip(NUMBER.findall(a), NUMBER.findall(b)):
            fields += 1
            if x == y:
                same += 1
            else:
                worst = max(worst, abs(float(x) - float(y)) / max(abs(float(y)), 1e-5))
    return fields, same, worst, text_diffs


@pytest.mark.parametrize("deck_name, errata, golden", golden_runs("r8"))
def test_double_reproduces_r8_golden(deck_name, errata, golden):
    run = run_deck(read_deck(ROOT / "decks" / f"{deck_name}.dat"), "double", errata=errata)
    theirs = golden.read_text().splitlines()
    fields, same, worst, text_diffs = compare_records(run.records, theirs)
    assert not text_diffs, f"records whose text differs: {text_diffs[:3]}"
    assert fields > 1000
    # Measured: every field identical on every deck (binary64 and the C library's sin/cos on
    # both sides). The floor is 99.9 % identical, every field within 1e-6 relative.
    assert same == fields, f"{same}/{fields} fields identical, largest relative difference {worst:.3g}"
    assert run.text() == golden.read_text()


@pytest.mark.parametrize("deck_name, errata, golden", golden_runs("r4"))
def test_single_stops_where_gfortran_traps(deck_name, errata, golden):
    trap = golden.with_suffix("").with_suffix(".r4.trap").read_text()
    statement = re.search(r"statement:\n\s+(\w+)=", trap).group(1)
    with pytest.raises(EmulatorError) as info:
        run_deck(read_deck(ROOT / "decks" / f"{deck_name}.dat"), "single", errata=errata)
    err = info.value
    assert err.run.records == golden.read_text().splitlines()  # the same records up to the trap
    assert err.variable == statement  # gfortran's trap line: PHIA=... after label 44
    assert err.label == 44 and err.step == 2
    assert err.time == pytest.approx(0.0004, rel=1e-6)
    assert "division by zero" in str(err) or "divide by zero" in str(err)


def test_angle_deck_as_printed_stops_at_ed_guard():
    """As printed, ED walks away from its root on the 15 degree deck: the guard ends it."""
    deck = read_deck(ROOT / "decks" / "steel40_a15.dat")
    with pytest.raises(EmulatorError) as info:
        run_deck(deck, limits=Limits(ed_iterations=5000))
    err = info.value
    assert err.guard == "ed_iterations"
    assert str(err.label).startswith("ED 1")  # the branch ROOT GOES NEGATIVE TO POSITIVE
    assert "ED's root search did not converge in 5000 iterations (D = " in str(err)
    assert err.step > 1 and 0 < err.time < 0.01
    # what the goldens' command saw before it cut the compiled program off
    assert err.run.records[-1].strip().startswith("THE VALUE OF TIME IS")


def test_halving_guard_fires_on_a_deck_whose_contact_never_closes():
    # the mass centre punched 1 ft off its start: DIFF > 0.01 at any step size, so label 108
    # halves H for ever. (THB, THDB, W2B are punched with the start-up values of label 123:
    # with the deck's THB = 0, the first halving would send ED a zero SIN(THB) to divide by.)
    deck = read_deck(ROOT / "decks" / "steel40.dat").with_values(
        XCMB=1.0, THB=0.000022, THDB=0.0545, W2B=0.0545)
    with pytest.raises(EmulatorError) as info:
        run_deck(deck, limits=Limits(halvings=12))
    err = info.value
    assert err.guard == "halvings" and err.label == 108
    assert "halved 12 times in a row at label 108" in str(err)
    assert "DIFF = 1" in str(err)


def test_time_guard_fires_on_a_post_that_never_lands():
    deck = read_deck(ROOT / "decks" / "steel40.dat").with_values(HEIGHT=5000.0)
    with pytest.raises(EmulatorError) as info:
        run_deck(deck, limits=Limits(time_s=1.5), trace=False)
    err = info.value
    assert err.guard == "time_s" and err.label == 59
    assert "the post has not landed" in str(err)
    assert err.time == pytest.approx(1.5, abs=0.001)
    assert any("LOST CONTACT WITH THE VEHICLE" in r for r in err.run.records)


def test_first_step_halving_divides_by_zero_in_ed():
    # the same deck with the original THB = 0: ED's DF divides by SIN(THB + ...) = 0
    deck = read_deck(ROOT / "decks" / "steel40.dat").with_values(XCMB=1.0)
    with pytest.raises(EmulatorError) as info:
        run_deck(deck)
    assert info.value.label == "ED 21" and info.value.variable == "DF"
    assert "division by zero" in str(info.value)


def test_non_finite_value_names_the_statement():
    deck = read_deck(ROOT / "decks" / "steel40.dat").with_values(W=0.0)  # a massless post
    with pytest.raises(EmulatorError) as info:
        run_deck(deck)
    err = info.value
    assert err.variable == "V1A" and err.label == 124  # V1A=H*((F1B/W)+...
    assert err.step == 1 and "division by zero" in str(err)


def test_trace_and_events_follow_the_printout():
    from deck_emulator.vocabulary.events import EventKind, Surface
    from deck_emulator.legacy.printer import event_message

    run = run_deck(read_deck(ROOT / "decks" / "steel40.dat"))
    # each event's text is the message the line printer wrote, in the printout's order
    printed = [r.strip() for r in run.records if "THE POST HAS" in r]
    assert [event_message(e) for e in run.events] == printed == [
        "THE POST HAS LOST CONTACT WITH FIRST SPRING",
        "THE POST HAS LOST CONTACT WITH THE VEHICLE",
        "THE POST HAS HIT THE GROUND WITH POINT R",
    ]
    assert [e.label for e in run.events] == [355, 100, 110]  # the FORMATs that printed them
    hit = run.events[-1]
    assert hit.kind is EventKind.HIT and hit.surface is Surface.GROUND and hit.point == "R"
    printed_times = [float(x) for x in re.findall(r"TIME IS\s+(\S+)", run.text())]
    assert hit.time_s == pytest.approx(printed_times[-1], abs=5e-6)
    assert run.trace[-1]["t"] == pytest.approx(hit.time_s)
    assert [r["phase"] for r in run.trace].count("contact") > 100


@pytest.mark.parametrize("precision", ["double", "single", "ibm7094"])
def test_variables_read_before_assignment_are_zero(precision):
    """As on the 7094 (and gfortran -fno-automatic -finit-local-zero): a variable the program
    reads before any statement assigns it is zero, INTEGER for I-N (the listing's first
    printout after a start-up step reads THAD, which only label 44 sets)."""
    from deck_emulator.legacy.fortran import Program

    program = Program(["      LL=LL+1", "      X=LL/2", "      WRITE(6,1)THAD,DIFFB,X",
                       "    1 FORMAT(1H ,3F8.3)", "      STOP", "      END"])
    run = program.runner(read_deck(ROOT / "decks" / "steel40.dat"), precision).run()
    assert run.records == ["    0.000   0.000   0.000"]  # LL/2 = 1/2: INTEGER division


def test_overflow_in_a_block_is_named_by_the_replay():
    """An infinity made by an overflowing product (no Python exception in binary64) is found
    when its block ends and named by the replay in the checking mode."""
    deck = read_deck(ROOT / "decks" / "steel40.dat").with_values(WV=1e-308)  # (H/WV)*FSB overflows
    with pytest.raises(EmulatorError) as info:
        run_deck(deck)
    err = info.value
    assert err.variable == "VVA" and err.label == 124 and err.step == 1
    assert "non-finite" in str(err)


@pytest.mark.parametrize("name, surface, height", [
    ("hit_top", "TOP", "HTV"), ("hit_trunk", "TRUNK", "HTRV")])
def test_a_car_hit_names_the_point_that_met_the_surface(name, surface, height):
    """The listing's car messages do not name the point; the event does, from the check the
    program was in. Checked by geometry: at the hit the named point lies in the listing's
    0.1 ft band about that surface's height (decks made for these labels, tests/decks)."""
    from deck_emulator.vocabulary.events import Surface

    deck = read_deck(ROOT / "tests" / "decks" / f"{name}.dat")
    run = run_deck(deck, errata=("ed-direction",))
    hit = run.events[-1]
    assert hit.surface is Surface[surface] and hit.point in ("P", "R", "C")
    z = run.trace[-1][f"ZZ{hit.point}"]
    assert abs(z - deck[height]) <= 0.1
