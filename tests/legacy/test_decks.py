"""The six decks in decks/: they parse, hold the appendix values, differ only where meant."""

from __future__ import annotations

from pathlib import Path

import pytest

from deck_emulator.legacy.deck import NAMES, read_deck

DECKS = Path(__file__).resolve().parents[2] / "decks"

# name -> (VVB, ALPHA): 40/20 mph, approach angle 0/15/30 degrees in radians
VARIANTS = {
    "steel40": (-58.66, 0.0),
    "steel40_a15": (-58.66, 0.26180),
    "steel40_a30": (-58.66, 0.52360),
    "steel20": (-29.33, 0.0),
    "steel20_a15": (-29.33, 0.26180),
    "steel20_a30": (-29.33, 0.52360),
}

# The appendix $DATA deck, card by card, as printed.
APPENDIX = [
    "0.0 0.0 0.0 -58.66 0.0 0.0 0.0 0.0",
    "0.0 0.0 15.1 100.0 3351.41 3282.6 69.68 32.174",
    "0.0 0.0 0.0 33000.0 0.0 0.0 0.0 20.27",
    "0.0 0.0 0.0 5.0 0.0 1.53 -18.77 485.07",
    "0.0 1.53 16.938 0.0 1.53 -19.77 5.0 0.0",
    "0.0 0.0 0.0 5.0 7.0 0.1463 -1.47 4.53",
    "6.0 -16.77 0.0 -15.27 -16.27 0.0 -8.47 21.938",
    "0.0 1.53 -19.77 0.0 1.53 -17.5 20000.0 1200.0",
]


def test_the_six_decks_are_there():
    assert sorted(p.stem for p in DECKS.glob("*.dat")) == sorted(VARIANTS)


@pytest.mark.parametrize("name", VARIANTS)
def test_deck_parses(name):
    deck = read_deck(DECKS / f"{name}.dat")
    assert list(deck.values) == list(NAMES)


def test_steel40_values():
    deck = read_deck(DECKS / "steel40.dat")
    assert deck["VVB"] == -58.66
    assert deck["CK"] == 33000.0
    assert deck["DELTA"] == 0.1463
    assert deck["FCONST"] == 1200.0
    assert deck["W"] == 15.1
    assert deck["FNA"] == 485.07 and deck["CT"] == 20000.0 and deck["ALPHA"] == 0.0


def test_steel40_is_the_appendix_deck_column_exact():
    lines = (DECKS / "steel40.dat").read_text().split("\n")
    assert lines[0] == "$DATA".ljust(80)
    assert lines[-1] == ""  # one final newline, nothing after
    for line, printed in zip(lines[1:9], APPENDIX, strict=True):
        # each value left-justified in its 10 columns, exactly the printed digits
        assert line == "".join(v.ljust(10) for v in printed.split())
    deck = read_deck(DECKS / "steel40.dat")
    assert [deck[n] for n in NAMES] == [float(v) for c in APPENDIX for v in c.split()]


@pytest.mark.parametrize("name", VARIANTS)
def test_variant_differs_only_in_speed_and_angle(name):
    base = read_deck(DECKS / "steel40.dat")
    deck = read_deck(DECKS / f"{name}.dat")
    vvb, alpha = VARIANTS[name]
    assert deck["VVB"] == vvb and deck["ALPHA"] == alpha
    differing = {n for n in NAMES if deck[n] != base[n]}
    assert differing <= {"VVB", "ALPHA"}
    # and the card images too: only columns 31-40 of card 1 and 71-80 of card 5
    for i, (a, b) in enumerate(zip(base.cards, deck.cards)):
        keep = {0: (30, 40), 4: (70, 80)}.get(i)
        if keep:
            a, b = a[: keep[0]] + a[keep[1] :], b[: keep[0]] + b[keep[1] :]
        assert a == b


@pytest.mark.parametrize("name", VARIANTS)
def test_every_card_line_is_80_columns(name):
    data = (DECKS / f"{name}.dat").read_bytes()
    assert data.isascii() and b"\t" not in data and b"\r" not in data
    assert data.endswith(b"\n")
    lines = data.decode("ascii").split("\n")[:-1]
    assert len(lines) == 9 and lines[0].startswith("$DATA")
    assert all(len(line) == 80 for line in lines)
