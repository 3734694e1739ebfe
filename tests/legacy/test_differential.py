"""The compiled listing as a standing oracle (the checkout's oracle/): seeded random decks,
run through the compiled legacy/luminaire.f (REAL*8) and through the emulator in binary64,
printouts compared byte for byte, and how each run ended compared too.

20 decks run by default; the 500-deck corpus runs with ``pytest -m slow_corpus``."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SMALL, SMALL_SEED = 20, 2026
LARGE, LARGE_SEED = 500, 1

pytestmark = pytest.mark.skipif(shutil.which("gfortran") is None,
                                reason="gfortran is not installed: the compiled listing is the oracle")


def _differential():
    import oracle

    return oracle


@pytest.fixture(scope="module")
def oracle():
    diff = _differential()
    o = diff.Oracle(timeout_s=2.0)
    yield diff, o
    o.close()


@pytest.mark.parametrize("index", range(SMALL))
def test_random_deck_prints_as_the_compiled_listing(oracle, index):
    diff, o = oracle
    deck = diff.corpus(SMALL, SMALL_SEED)[index]
    outcome = o.compare(deck)
    assert outcome.agree, outcome.why
    if outcome.ending_compiled == "normal":
        assert outcome.records > 100  # a whole printout, compared byte for byte


#: Hand-made decks for the lines of MAIN the random corpus does not reach (docs/oracle.md), and
#: the message the compiled program ends with on each.
HAND_MADE = {
    "hit_top.dat": "THE POST HAS HIT THE TOP OF THE VEHICLE",  # labels 240, 242
    "hit_trunk.dat": "THE POST HAS HIT THE TRUNK OF THE VEHICLE",  # labels 247, 248
    "ground_q.dat": "THE POST HAS HIT THE GROUND WITH POINT Q",  # labels 96, 97; 253
    "c_past_roof.dat": "THE POST HAS HIT THE GROUND WITH POINT R",  # point C: labels 459-461
}


@pytest.mark.parametrize("name", sorted(HAND_MADE))
def test_hand_made_deck_prints_as_the_compiled_listing(oracle, name):
    from deck_emulator.legacy.deck import read_deck

    diff, o = oracle
    outcome = o.compare(read_deck(ROOT / "tests" / "decks" / name))
    assert outcome.ending_compiled == "normal" and outcome.agree, outcome.why
    messages = [r.strip() for r in outcome.compiled_text.splitlines() if "THE POST HAS" in r]
    assert messages[-1] == HAND_MADE[name]  # then the last printout (label 98) and STOP


def test_small_corpus_reaches_normal_ends_and_stops():
    diff = _differential()
    decks = diff.corpus(SMALL, SMALL_SEED)
    assert len({d.to_text() for d in decks}) == SMALL  # all different
    assert any(d["ALPHA"] != 0 for d in decks) and any(d["ALPHA"] == 0 for d in decks)


@pytest.mark.slow_corpus
def test_large_corpus_prints_as_the_compiled_listing(oracle):
    diff, o = oracle
    bad = []
    endings = set()
    for i, deck in enumerate(diff.corpus(LARGE, LARGE_SEED)):
        outcome = o.compare(deck)
        endings.add((outcome.ending_compiled, outcome.ending_emulator))
        if not outcome.agree:
            bad.append((i, outcome.why))
    assert not bad, f"{len(bad)} of {LARGE} decks disagree, first: {bad[:3]}"
    assert ("normal", "normal") in endings
