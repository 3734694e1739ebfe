"""The verdicts of a run (engine.ratings) on hand-made runs whose geometry fixes the answer:
a post lying over the steel decks' car, coming down into its hood or staying above it.

The car (decks/steel40.dat, its scene): the hood from the bumper SV - HLEN to SV at
HHV = -16.27 ft (road axes, from the post's mass centre), between the fenders YLFEN = -1.47
and YRFEN = 4.53 ft; the car stands still at SV = 0 here, approach angle 0 (XV = XX)."""

from __future__ import annotations

import numpy as np
import pytest

from deck_emulator import decks
from deck_emulator.engine.outcome import Outcome
from deck_emulator.engine.ratings import ratings
from deck_emulator.engine.safety import CRITERIA, VERDICTS
from deck_emulator.engine.sources import read_deck
from deck_emulator.vocabulary.events import Event, EventKind, Surface
from deck_emulator.vocabulary.scene import Scene

HOOD_FT = -16.27  # HHV of the steel decks' car
T = np.array([0.0, 0.1, 0.2, 0.3])


@pytest.fixture(scope="module")
def scene():
    s = Scene.from_deck(read_deck(decks.path("steel40")), name="steel40", checked=False)
    body = s.vehicle.body
    assert (body.hood_height_ft, body.hood_length_ft) == (HOOD_FT, 5.0)
    return s


def run(scene, heights, *, hit=Event(EventKind.HIT, 0.3, Surface.GROUND, "C"),
        contact_test="points", error=None):
    """The post lying along XX over the hood (Q at XV -4, P at -2, R at -1 ft; YY 1 ft), at
    ``heights`` (ft) at the instants T; the car lets go of it at 0.1 s, having lost 1.66
    ft/s (an OIV of about 0.5 m/s: within every limit)."""
    z = np.asarray(heights, float)
    pts = {k: np.column_stack([np.full(4, x), np.full(4, 1.0), z])
           for k, x in (("Q", -4.0), ("P", -2.0), ("R", -1.0))}
    return Outcome("emulator", "hand", scene, t=T, points=pts, sv=np.zeros(4),
                   vv=np.array([-58.66, -57.0, -57.0, -57.0]),
                   free=np.array([False, True, True, True]),
                   events=[Event(EventKind.LOST_VEHICLE, 0.1), hit], error=error,
                   contact_test=contact_test)


ABOVE = [HOOD_FT + 1.0] * 4
INTO = [HOOD_FT + 1.0, HOOD_FT + 1.0, HOOD_FT + 0.5, HOOD_FT - 0.5]


def test_a_post_that_comes_down_into_the_hood_fails_there(scene):
    r = ratings(run(scene, INTO))["occupant_compartment"]
    assert r["verdict"] == "fails"
    assert r["part"] == "the shaft Q-P" and r["surface"] == "hood"
    assert r["time_s"] == 0.3  # the first instant the line is inside the outline
    assert r["depth_ft"] == pytest.approx(0.5, abs=1e-9)  # 0.5 ft below HHV
    assert "only the points P, R and C" in r["reason"]


@pytest.mark.parametrize("test", ["points", "segments"])
def test_no_pass_beside_a_failure(scene, test):
    rated = ratings(run(scene, INTO, contact_test=test))
    for name in ("oiv_m_s", "ora_g"):
        words = set(rated[name]["verdicts"].values())
        assert words == {"not rated"}, name
        assert rated[name]["reason"] == "the occupant compartment fails"


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


def test_a_run_that_ends_on_the_car_fails_with_the_part_that_struck_it(scene):
    strike = Event(EventKind.HIT, 0.2, Surface.HOOD, "Q-P")
    r = ratings(run(scene, ABOVE[:3] + [HOOD_FT], hit=strike,
                    contact_test="segments"))["occupant_compartment"]
    assert (r["verdict"], r["part"], r["surface"], r["time_s"]) == (
        "fails", "the shaft Q-P", "hood", 0.2)
    assert r["depth_ft"] == 0.0  # the model ends the run at the strike


def test_a_run_that_stopped_is_rated_nothing(scene):
    assert ratings(run(scene, INTO, error="stopped on purpose")) is None


def test_every_verdict_word_is_in_the_one_table(scene):
    for heights, test in ((INTO, "points"), (ABOVE, "points"), (ABOVE, "segments")):
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
