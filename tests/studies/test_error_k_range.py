"""The error study's whole k range runs: every step size it shows, H = 0.0004/2**k for
k = 0..6 (2,054 to 131,297 steps of the 1967 scheme), ends with the post's hit under the
study's own statement budget.  k = 5 and 6 hold three quarters of the steps: they run with
-m slow_corpus, the smaller steps in the README's test command."""

import pytest

from deck_emulator.legacy.deck import read_deck
from deck_emulator.studies.common import run_emulator
from deck_emulator.studies.diff import ed_tolerance
from deck_emulator.studies.error import emulator_limits, plan

pytestmark = pytest.mark.slow

#: the ks of the whole study, the two smallest steps on request
KS = [k if k < 5 else pytest.param(k, marks=pytest.mark.slow_corpus) for k in range(7)]


def test_the_study_shows_k_0_to_6():
    assert list(plan(quick=False)["ks"]) == list(range(7))


@pytest.mark.parametrize("k", KS)
def test_every_k_of_the_study_ends_with_a_hit(k):
    deck = read_deck("decks/steel40.dat")
    for tol in (".0001", ed_tolerance(k)):
        out = run_emulator(deck, k=k, ed_tolerance=tol, limits=emulator_limits(k))
        assert out["status"] == "hit", (k, tol, out["error"])
        t, _ = out["outcome"].accepted_steps()
        # a fixed step H0/2**k (label 108 halves one now and then) over the run's time
        h = 0.0004 / 2**k
        assert t.size >= 0.9 * t[-1] / h, (k, tol, t.size)
