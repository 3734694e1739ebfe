"""The error study's orders (derived by least squares, with an interval, never from one pair),
the emulator's statement budget scaled with its steps, and the diff's order lines."""

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from deck_emulator.engine import Limits
from deck_emulator.legacy.deck import read_deck
from deck_emulator.studies.diff import diff_deck, format_diff
from deck_emulator.studies.error import emulator_limits
from deck_emulator.studies.orders import QUANTISED, order_fit

H0 = 0.0004


@settings(max_examples=60, deadline=None)
@given(p=st.floats(0.3, 9.0), c=st.floats(1e-6, 1e4), n=st.integers(3, 9))
def test_an_exact_power_law_gives_its_power_with_no_spread(p, c, n):
    # e = C h**p: the slope of log e against log h is p (algebra), the points lie on the line
    # (no scatter, so the interval shrinks to rounding), and each halving gains 2**p
    h = [H0 / 2**k for k in range(n)]
    fit = order_fit(h, [c * x**p for x in h])
    assert fit.n == n
    assert fit.p == pytest.approx(p, abs=1e-9)
    assert fit.half < 1e-6
    assert len(fit.pairwise) == n - 1
    assert all(q == pytest.approx(p, abs=1e-9) for q in fit.pairwise)


@settings(max_examples=60, deadline=None)
@given(p=st.floats(0.5, 4.0), wobble=st.lists(st.floats(-0.5, 0.5), min_size=4, max_size=8))
def test_scatter_about_the_line_widens_the_interval(p, wobble):
    # e = h**p * 2**w: log2 e = p log2 h + w; points off one line leave a positive interval,
    # and a step-by-step order is the difference of neighbours' logs (its definition)
    h = [H0 / 2**k for k in range(len(wobble))]
    err = [x**p * 2.0**w for x, w in zip(h, wobble)]
    fit = order_fit(h, err)
    pairwise = [p + a - b for a, b in zip(wobble, wobble[1:])]
    assert fit.pairwise == pytest.approx(pairwise, abs=1e-9)
    if max(wobble) - min(wobble) > 1e-3:
        assert fit.half > 0


def test_two_step_sizes_give_no_order_only_their_pair():
    fit = order_fit([H0, H0 / 2], [0.078, 0.03])
    assert math.isnan(fit.p) and fit.n == 2
    assert fit.pairwise == pytest.approx([math.log2(0.078 / 0.03)])
    assert fit.text() == "none from 2 step sizes (a fit needs three or more)"


def test_points_that_did_not_run_are_left_out_and_the_order_does_not_matter():
    h = [H0 / 4, H0, H0 / 2, H0 / 8]
    err = [0.25, 1.0, 0.5, math.nan]
    fit = order_fit(h, err)
    assert fit.n == 3 and fit.p == pytest.approx(1.0)
    assert fit.pairwise == pytest.approx([1.0, 1.0])


@pytest.mark.parametrize("k", range(7))
def test_a_run_at_a_halved_step_gets_its_steps_worth_of_statements(k):
    """The listing at H0/2**k takes 2**k times its steps: the front end gives the run 2**k
    times the budget, whoever runs it (the error study, diff, a job deck's own options)."""
    from deck_emulator import decks
    from deck_emulator.legacy.fortran.run import listing_program

    limits = emulator_limits(k)
    assert limits == Limits()
    runner = listing_program(step_scale_k=k).runner(read_deck(decks.path("steel40")), "double",
                                                    limits=limits)
    assert runner.budget == Limits().statements * 2**k


def test_diff_prints_no_order_from_one_pair_nor_for_the_hit_time():
    text = format_diff(diff_deck(read_deck("decks/steel40.dat"), ks=range(2),
                                 errata=("ed-direction",)))
    lines = [line for line in text.splitlines() if "order" in line]
    assert f"order (hit time): none: {QUANTISED}" in lines
    assert not any(line.startswith("observed order (hit time)") for line in lines)
    for label in ("terminal points", "trajectory"):
        (line,) = [x for x in lines if x.startswith(f"observed order ({label})")]
        assert line.endswith(": none from 2 step sizes (a fit needs three or more)")
