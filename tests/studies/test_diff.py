"""The emulator against the modern core on the original deck (deck-emulator diff)."""

import json

import numpy as np
import pytest

from deck_emulator.cli import main
from deck_emulator.legacy.deck import read_deck
from deck_emulator.studies.diff import diff_deck

DECK = "decks/steel40.dat"
#: as printed, ED walks away from its root on steel40 once the step is halved (k >= 1)
ERRATA = ("ed-direction",)


@pytest.fixture(scope="module")
def tightened():
    return diff_deck(read_deck(DECK), ks=range(4), errata=ERRATA)


def test_difference_shrinks_at_first_order_when_ed_is_solved_with_the_step(tightened):
    rows = tightened["convergence"]
    traj = [r["max_trajectory_diff_ft"] for r in rows]
    term = [r["terminal_points_diff_ft"] for r in rows]
    assert all(a > b for a, b in zip(traj, traj[1:])), traj
    assert all(a > b for a, b in zip(term, term[1:])), term
    # the listing's scheme is first order (Chapter IV: explicit Euler in the velocities):
    # over the four halvings the difference falls as h^p with p = 1, to within a quarter
    # (least squares on log2 of the difference against k)
    slope = np.polyfit([r["k"] for r in rows], np.log2(traj), 1)[0]
    assert -slope == pytest.approx(1.0, abs=0.25), slope
    assert rows[-1]["hit_time_diff_s"] < 2 * rows[-1]["h_s"]  # the hit is found to the step
    assert all(r["same_hit"] for r in rows)


def test_side_by_side_is_the_printed_run(tightened):
    e, c = tightened["emulator"], tightened["core"]
    assert e["hit"] == c["hit"] == "hit ground (R)"  # the golden: ...HIT THE GROUND WITH POINT R
    assert e["hit_time_s"] == pytest.approx(0.8216, abs=1e-9)  # the golden's last TIME
    assert abs(e["hit_time_s"] - c["hit_time_s"]) < 0.005  # s
    assert abs(e["delta_v_contact_mph"] - c["delta_v_contact_mph"]) < 0.05  # mph
    assert 0 < tightened["max_trajectory_diff_as_printed_ft"] < 0.5  # ft, ED's .0001 as printed
    # the k = 0 row runs ED at 1e-6 rad: a different run, a different (smaller) number
    assert tightened["convergence"][0]["ed_tolerance_rad"] == 1e-6
    assert (tightened["convergence"][0]["max_trajectory_diff_ft"]
            != tightened["max_trajectory_diff_as_printed_ft"])


def test_as_printed_ed_tolerance_does_not_converge():
    """ED's .0001 rad does not shrink with the step: the difference does not fall as first
    order would have it (to a quarter after two halvings); it stays above half its first
    value."""
    d = diff_deck(read_deck(DECK), ks=range(3), tighten_ed=False, errata=ERRATA)
    traj = [r["max_trajectory_diff_ft"] for r in d["convergence"]]
    assert traj[2] > 2 * traj[0] / 4, traj


def test_diff_cli_json(capsys):
    assert main(["diff", DECK, "--json", "--max-k", "1", "--erratum", "ed-direction"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["command"] == "diff" and data["source"] == DECK and data["status"] == "ok"
    assert data["settings"]["errata"] == ["ed-direction"]
    for side in ("emulator", "core"):
        assert {"hit", "hit_time_s", "delta_v_contact_mph", "max_decel_every_step_g"} <= set(data[side])
    assert [r["k"] for r in data["convergence"]] == [0, 1]
    assert {"k", "h_s", "hit_time_diff_s", "max_trajectory_diff_ft"} <= set(data["convergence"][0])


def test_diff_as_printed_rows_stop_at_the_first_halved_step_and_name_the_erratum(capsys):
    """The halved steps as printed: k = 0 compares, k = 1 is a row that says the listing as
    printed stops there and which erratum lets it run; a run stopped: exit 3."""
    assert main(["diff", DECK, "--max-k", "1", "--json", "--as-printed-rows"]) == 3
    data = json.loads(capsys.readouterr().out)
    assert data["status"] == "stopped" and data["stopped_from_k"] == 1
    assert data["settings"]["row_errata"] == []
    row = data["convergence"][1]
    assert row["k"] == 1 and "k = 1" in row["stopped"]
    assert "--erratum ed-direction" in row["stopped"]
    assert data["observed_order"]["hit_time_diff_s"] == []  # no two rows that ran


def test_diff_default_ends_on_the_report_deck(capsys):
    """No erratum asked for: the side by side is the listing as printed (the golden's hit at
    0.8216 s), the halved steps run with ed-direction, say so, and every row ends: exit 0."""
    assert main(["diff", DECK, "--max-k", "1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["status"] == "ok" and data["stopped_from_k"] is None
    assert data["settings"]["errata"] == [] and data["settings"]["row_errata"] == ["ed-direction"]
    assert data["emulator"]["hit_time_s"] == pytest.approx(0.8216, abs=1e-9)  # the golden's
    assert all(r["errata"] == ["ed-direction"] for r in data["convergence"])
    assert len(data["observed_order"]["hit_time_diff_s"]) == 1
    assert main(["diff", DECK, "--max-k", "1"]) == 0
    assert "errata: ed-direction, since as printed ED" in capsys.readouterr().out
