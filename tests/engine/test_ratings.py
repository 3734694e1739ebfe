"""The verdicts of a run (engine.ratings) on hand-made runs whose geometry fixes the answer:
a post lying over the steel decks' car, coming down into its hood, its trunk or its roof, or
staying above it.

The car (decks/steel40.dat, its scene; the numbers below are its deck's, checked by the
fixture): the hood from the bumper SV - HLEN = -5 ft to SV = 0 at HHV = -16.27 ft (road axes,
from the post's mass centre), the occupant compartment (roof box) from 0 to TLEN = 7 ft up to
HTV = -15.27 ft, the trunk from 7 to 13 ft at HTRV = -16.77 ft, between the fenders YLFEN =
-1.47 and YRFEN = 4.53 ft; the car stands still at SV = 0 here, approach angle 0 (XV = XX).

The criterion (MASH, its occupant compartment; docs/safety.md): the compartment is the roof,
windshield and side glass; the hood and the trunk are not part of it. OIV and ORA are read
from the contact pulse, whatever strikes the car later."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from deck_emulator import decks
from deck_emulator.engine.outcome import Outcome
from deck_emulator.engine.ratings import ratings
from deck_emulator.engine.safety import CRITERIA, VERDICTS, rate
from deck_emulator.engine.sources import read_deck
from deck_emulator.vocabulary.events import Event, EventKind, Surface
from deck_emulator.vocabulary.scene import Scene

HOOD_FT = -16.27  # HHV of the steel decks' car
TOP_FT = -15.27  # HTV
TRUNK_FT = -16.77  # HTRV
HOOD_X, ROOF_X, TRUNK_X = (-5.0, 0.0), (0.0, 7.0), (7.0, 13.0)
T = np.array([0.0, 0.1, 0.2, 0.3])


@pytest.fixture(scope="module")
def scene():
    s = Scene.from_deck(read_deck(decks.path("steel40")), name="steel40", checked=False)
    body = s.vehicle.body
    assert (body.hood_height_ft, body.hood_length_ft) == (HOOD_FT, 5.0)
    assert (body.top_height_ft, body.top_length_ft) == (TOP_FT, 7.0)
    assert (body.trunk_height_ft, body.trunk_length_ft) == (TRUNK_FT, 6.0)
    assert (body.left_fender_ft, body.right_fender_ft) == (-1.47, 4.53)
    assert s.vehicle.approach_angle_rad == 0.0
    return s


def run(scene, heights, *, hit=Event(EventKind.HIT, 0.3, Surface.GROUND, "C"),
        contact_test="points", error=None, xs=(-4.0, -2.0, -1.0), ys=(1.0, 1.0, 1.0)):
    """The post lying along XX (Q, P, R at ``xs``, default over the hood; at ``ys``, each a
    number or one per instant of T), at ``heights`` (ft) at the instants T; the car lets go of
    it at 0.1 s, having lost 1.66 ft/s (an OIV of about 0.5 m/s: within every limit)."""
    z = np.asarray(heights, float)
    pts = {}
    for k, x, y in zip("QPR", xs, ys):
        x = np.broadcast_to(np.asarray(x, float), (4,))
        y = np.broadcast_to(np.asarray(y, float), (4,))
        pts[k] = np.column_stack([x, y, z])
    return Outcome("emulator", "hand", scene, t=T, points=pts, sv=np.zeros(4),
                   vv=np.array([-58.66, -57.0, -57.0, -57.0]),
                   free=np.array([False, True, True, True]),
                   events=[Event(EventKind.LOST_VEHICLE, 0.1), hit], error=error,
                   contact_test=contact_test)


def assert_pulse_rated(rated):
    """OIV and ORA are read against every cited limit, whatever the compartment says."""
    for name in ("oiv_m_s", "ora_g"):
        r = rated[name]
        limits = {k for k, c in CRITERIA.items() if c.quantity == name}
        assert set(r["verdicts"]) == limits, name
        assert set(r["verdicts"].values()) <= {"preferred", "acceptable", "exceeds"}
        assert r["reason"] == ""


ABOVE = [HOOD_FT + 1.0] * 4
INTO = [HOOD_FT + 1.0, HOOD_FT + 1.0, HOOD_FT + 0.5, HOOD_FT - 0.5]


def test_a_post_that_comes_down_into_the_hood_strikes_outside_the_compartment(scene):
    r = ratings(run(scene, INTO))["occupant_compartment"]
    assert r["part"] == "the shaft Q-P" and r["surface"] == "hood"
    assert r["in_compartment"] is False and r["car_part"] == "hood"
    assert r["time_s"] == 0.3  # the first instant the line is inside the outline
    assert r["depth_ft"] == pytest.approx(0.5, abs=1e-9)  # 0.5 ft below HHV
    # the points-only model runs on through the hood: nothing after the strike is judged
    assert r["verdict"] == "not judged"
    assert "outside the occupant compartment" in r["reason"]
    assert "only the points P, R and C" in r["reason"]


@pytest.mark.parametrize("test", ["points", "segments"])
def test_a_strike_on_the_hood_leaves_oiv_and_ora_rated(scene, test):
    assert_pulse_rated(ratings(run(scene, INTO, contact_test=test)))


def test_a_post_above_the_car_is_not_judged_by_a_model_that_tests_only_points(scene):
    r = ratings(run(scene, ABOVE))["occupant_compartment"]
    assert r["verdict"] == "not judged"
    assert r["clearance_ft"] == pytest.approx(1.0, abs=1e-9)
    assert r["part"] is None and r["depth_ft"] is None


def test_a_post_above_the_car_passes_when_the_whole_post_was_tested(scene):
    rated = ratings(run(scene, ABOVE, contact_test="segments"))
    assert rated["occupant_compartment"]["verdict"] == "passes"
    # the OIV (about 0.5 m/s) is within both cited limits: rated, not withheld
    oiv = rated["oiv_m_s"]
    assert oiv["value"] < CRITERIA["mash_oiv"].maximum
    assert oiv["verdicts"] == {"nchrp350_oiv": "preferred", "mash_oiv": "acceptable"}


def test_a_run_that_ends_on_the_hood_is_a_strike_outside_the_compartment(scene):
    """The shaft comes down on the hood and the run ends there, at depth 0 (the model's own
    test stops it at the surface): the hood is not the occupant compartment, so this is no
    failure of it; nor a pass, since the post, left lying on the car beside the compartment,
    is not followed."""
    strike = Event(EventKind.HIT, 0.3, Surface.HOOD, "Q-P", fraction=0.5)
    rated = ratings(run(scene, ABOVE[:3] + [HOOD_FT], hit=strike, contact_test="segments"))
    r = rated["occupant_compartment"]
    assert (r["part"], r["surface"], r["in_compartment"], r["time_s"]) == (
        "the shaft Q-P", "hood", False, 0.3)
    assert r["verdict"] == "not judged" and "no pass" in r["reason"]
    assert r["depth_ft"] == 0.0  # the model ends the run at the strike
    assert r["roof_clearance_before_ft"] is None  # the post lies over the hood only
    assert "the shaft Q-P strikes the hood at 300.0 ms" in r["reason"]
    assert_pulse_rated(rated)


def test_a_strike_on_the_roof_is_not_judged_and_never_passes(scene):
    """The post lying over the roof comes down on it and the run ends there: MASH judges that
    by the deformation it causes, which a rigid car does not compute."""
    strike = Event(EventKind.HIT, 0.3, Surface.TOP, "Q-P", fraction=0.5)
    rated = ratings(run(scene, [TOP_FT + 1.0] * 3 + [TOP_FT], hit=strike,
                        contact_test="segments", xs=(1.0, 3.0, 6.0)))
    r = rated["occupant_compartment"]
    assert (r["surface"], r["in_compartment"], r["verdict"]) == ("roof", True, "not judged")
    assert "Section 5.2.2 and Appendix E" in r["reason"] and "not re-checked" in r["reason"]
    assert "no pass" in r["reason"]
    assert_pulse_rated(rated)


def test_the_windshield_and_the_side_glass_are_the_compartment_entered_through_them(scene):
    """Below the roof line and above the hood, the post's end R moves back into the roof box
    through its front face (the windshield); at the roof box's height it moves in from beside
    the car through a flank (the side glass). A points model: its line check finds them."""
    z = [TOP_FT - 0.5] * 4
    through_front = run(scene, z, xs=(-4.0, -3.0, np.array([-2.0, -1.0, -0.5, 0.5])))
    r = ratings(through_front)["occupant_compartment"]
    assert (r["surface"], r["in_compartment"], r["time_s"]) == ("windshield", True, 0.3)
    beside = np.array([-4.0, -3.0, -2.0, -1.0])  # left of YLFEN = -1.47, then inside
    r = ratings(run(scene, z, xs=(2.0, 3.0, 4.0), ys=(beside, beside, beside)))[
        "occupant_compartment"]
    assert (r["surface"], r["in_compartment"], r["time_s"]) == ("side glass", True, 0.3)
    assert r["verdict"] == "not judged"


# ------------------------------------------------------------ properties at the boundaries

#: a depth below a part's top: exactly at it, at round-off, or well inside (ft)
DEPTHS = st.one_of(st.just(0.0), st.sampled_from([1e-15, 1e-12, 1e-9, 1e-6]),
                   st.floats(1e-6, 2.0))


@st.composite
def post_over(draw, x_range):
    """Three x positions of Q, P, R inside ``x_range`` (a post lying over that part only)."""
    lo, hi = x_range
    xs = sorted(draw(st.lists(st.floats(lo + 0.01, hi - 0.01), min_size=3, max_size=3,
                              unique=True)))
    return tuple(xs)


@settings(max_examples=60, deadline=None)
@given(part=st.sampled_from(["hood", "trunk"]), depth=DEPTHS, data=st.data(),
       test=st.sampled_from(["points", "segments"]), ends_on_it=st.booleans())
def test_no_strike_outside_the_compartment_fails_it_or_withholds_the_pulse(
        scene, part, depth, data, test, ends_on_it):
    """Any strike on the hood or the trunk, at any depth from exactly the surface through
    round-off to 2 ft inside, by either model, ending the run there or not: the verdict
    names it as outside the occupant compartment, is never a failure of it, and OIV and ORA
    are rated against every limit."""
    top, x_range, surface = {"hood": (HOOD_FT, HOOD_X, Surface.HOOD),
                             "trunk": (TRUNK_FT, TRUNK_X, Surface.TRUNK)}[part]
    xs = data.draw(post_over(x_range))
    heights = [top + 1.0, top + 1.0, top + 0.5, top - depth]
    hit = (Event(EventKind.HIT, 0.3, surface, "Q-P", fraction=0.5) if ends_on_it
           else Event(EventKind.HIT, 0.3, Surface.GROUND, "C"))
    rated = ratings(run(scene, heights, hit=hit, contact_test=test, xs=xs))
    r = rated["occupant_compartment"]
    assert r["verdict"] in {"passes", "not judged"}
    if r["part"] is not None:  # a touch at round-off depth may be no strike at all
        assert r["in_compartment"] is False and r["surface"] == part
        assert "outside the occupant compartment" in r["reason"]
        assert r["verdict"] == "not judged"  # the post is not followed past its strike
    else:  # the line exactly on the surface (a depth lost in the height's round-off too)
        assert top - depth == top and not ends_on_it
    assert_pulse_rated(rated)


@settings(max_examples=40, deadline=None)
@given(depth=DEPTHS, data=st.data(), test=st.sampled_from(["points", "segments"]),
       ends_on_it=st.booleans())
def test_no_strike_on_the_compartment_passes_it(scene, depth, data, test, ends_on_it):
    """Any strike on the roof, from exactly its surface to 2 ft in: never a pass (a rigid car
    gives no deformation to read against MASH's limits), and OIV and ORA still rated."""
    xs = data.draw(post_over(ROOF_X))
    heights = [TOP_FT + 1.0, TOP_FT + 1.0, TOP_FT + 0.5, TOP_FT - depth]
    hit = (Event(EventKind.HIT, 0.3, Surface.TOP, "Q-P", fraction=0.5) if ends_on_it
           else Event(EventKind.HIT, 0.3, Surface.GROUND, "C"))
    rated = ratings(run(scene, heights, hit=hit, contact_test=test, xs=xs))
    r = rated["occupant_compartment"]
    if ends_on_it or TOP_FT - depth < TOP_FT:  # the run's strike, or the line inside
        assert r["verdict"] == "not judged" and r["in_compartment"] is True
        assert r["surface"] == "roof"
    else:  # the line exactly on the roof, and the run ends on the ground: no strike found
        assert r["part"] is None
    assert_pulse_rated(rated)


@pytest.mark.parametrize("key", ["nchrp350_oiv", "mash_oiv", "nchrp350_ora"])
def test_a_value_exactly_on_a_limit_is_within_it(key):
    """'at most' (the criteria's words, docs/safety.md): the maximum itself is within it, the
    next float above it exceeds it; the preferred value itself is preferred."""
    c = CRITERIA[key]
    assert rate(c.maximum, c) in {"preferred", "acceptable"}
    assert rate(math.nextafter(c.maximum, math.inf), c) == "exceeds"
    if c.preferred is not None:
        assert rate(c.preferred, c) == "preferred"
        assert rate(math.nextafter(c.preferred, math.inf), c) == "acceptable"


@settings(max_examples=200, deadline=None)
@given(key=st.sampled_from(["nchrp350_oiv", "mash_oiv", "nchrp350_ora"]),
       value=st.floats(0.0, 100.0))
def test_a_rating_is_on_the_side_of_the_limit_the_value_is(key, value):
    c = CRITERIA[key]
    word = rate(value, c)
    assert (word == "exceeds") == (value > c.maximum)
    if c.preferred is not None:
        assert (word == "preferred") == (value <= c.preferred)


def test_a_run_that_stopped_is_rated_nothing(scene):
    assert ratings(run(scene, INTO, error="stopped on purpose")) is None


def test_every_verdict_word_is_in_the_one_table(scene):
    for heights, test in ((INTO, "points"), (INTO, "segments"), (ABOVE, "points"),
                          (ABOVE, "segments")):
        rated = ratings(run(scene, heights, contact_test=test))
        assert rated["occupant_compartment"]["verdict"] in VERDICTS
        for name in ("oiv_m_s", "ora_g"):
            assert set(rated[name]["verdicts"].values()) <= set(VERDICTS)


def test_the_safety_page_gives_the_verdict_words_of_the_one_table():
    from pathlib import Path

    page = (Path(__file__).resolve().parents[2] / "docs" / "safety.md").read_text()
    table = page.split("| word | what it says |\n|---|---|\n", 1)[1].split("\n\n", 1)[0]
    rows = dict(line.strip("|").split(" | ", 1) for line in table.splitlines())
    assert {w.strip(): m.strip(" |") for w, m in rows.items()} == dict(VERDICTS)
