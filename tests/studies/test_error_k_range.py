"""The error study's whole k range runs: every step size it shows, H = 0.0004/2**k for
k = 0..6 (2,054 to 131,297 steps of the 1967 scheme), ends with the post's hit under the
study's own statement budget (slow: about half a minute of the emulator)."""

import pytest

from deck_emulator.legacy.deck import read_deck
from deck_emulator.studies.common import run_emulator
from deck_emulator.studies.diff import ed_tolerance
from deck_emulator.studies.error import emulator_limits, plan

pytestmark = pytest.mark.slow


def test_every_k_of_the_study_ends_with_a_hit():
    deck = read_deck("decks/steel40.dat")
    ks = list(plan(quick=False)["ks"])
    assert ks == list(range(7))
    for k in ks:
        for tol in (".0001", ed_tolerance(k)):
            out = run_emulator(deck, k=k, ed_tolerance=tol, limits=emulator_limits(k))
            assert out["status"] == "hit", (k, tol, out["error"])
            t, _ = out["outcome"].accepted_steps()
            # a fixed step H0/2**k (label 108 halves one now and then) over the run's time
            h = 0.0004 / 2**k
            assert t.size >= 0.9 * t[-1] / h, (k, tol, t.size)
