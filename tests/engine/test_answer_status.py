"""An answer knows its status: a run that stopped has no quantity that depends on its end,
nothing is rated for it, and every answer (Python, JSON, CSV, the tables) says why."""

from __future__ import annotations

import csv
import io
import json

import pytest

import deck_emulator
from deck_emulator.engine import quantities
from deck_emulator.cli import main

#: steel40_a15 as printed: SUBROUTINE ED walks away from its root at step 16 (6 ms), long
#: before the car lets go of the post (legacy/CORRECTIONS.md; README, "Errata")
STOPPED = "steel40_a15"


@pytest.fixture
def run_cli(capsys):
    def run(*argv):
        code = main(list(argv))
        captured = capsys.readouterr()
        return code, captured.out, captured.err

    return run


@pytest.fixture(scope="module")
def stopped():
    out = deck_emulator.run(STOPPED)
    assert out.error is not None and not out.ended
    return out


def _end_dependent():
    return [q.name for q in quantities.QUANTITIES.values() if q.needs is not None]


def test_a_stopped_run_has_no_end_dependent_quantity(stopped):
    assert stopped.vehicle_contact_lost_s is None  # it stopped in contact with the car
    values = quantities.values(stopped, _end_dependent())
    assert values and set(values.values()) == {None}
    why = quantities.unavailable(stopped, _end_dependent())
    assert set(why) == set(values)
    assert all("the run stopped" in w for w in why.values())
    assert "before the car let go of the post" in why["oiv_m_s"]
    assert quantities.pulse(stopped) is None and quantities.clearance(stopped) is None


def test_a_run_that_ended_has_them_all_within_reach():
    out = deck_emulator.run("steel40")
    assert out.ended
    assert quantities.unavailable(out, quantities.names()) == {}
    assert quantities.value("oiv_m_s", out) is not None


def test_summary_json_of_a_stopped_run_says_null_and_why(run_cli):
    code, stdout, stderr = run_cli("summary", STOPPED, "--json")
    assert code == 3
    answer = json.loads(stdout)
    assert answer["status"] == "stopped"
    assert set(answer["quantities"].values()) == {None}
    assert answer["occupant_risk"] is None and answer["criteria"] is None
    assert answer["ratings"] is None
    assert {"oiv_m_s", "ora_g", "max_decel_g", "delta_v_contact_mph"} <= set(answer["unavailable"])
    assert stderr.count("error:") == 1


def test_summary_table_of_a_stopped_run_rates_nothing(run_cli):
    code, stdout, _ = run_cli("summary", STOPPED)
    assert code == 3
    assert "no value (-) and no rating:" in stdout
    assert "limits, with their sources" not in stdout


def test_a_sweep_row_of_a_stopped_run_has_empty_cells(stopped):
    from deck_emulator.studies.sweep import result_row, write_csv

    row = result_row(stopped, 40.0, 15.0)
    (cells,) = csv.DictReader(io.StringIO(write_csv([row])))
    for name in ("max_decel_g", "oiv_m_s", "ora_g", "occupant_strike_time_s",
                 "delta_v_contact_mph", "body_clearance_ft", "XPL"):
        assert cells[name] == "", name
    ratings = [k for k in cells if k.endswith("_rating") or k == "compartment_verdict"]
    assert {"nchrp350_oiv_rating", "mash_oiv_rating", "compartment_verdict"} <= set(ratings)
    assert all(cells[k] == "" for k in ratings)
    assert cells["error"].startswith("ED's root search did not converge")



@pytest.mark.parametrize("engine", ["emulator", "core"])
def test_an_outcome_is_made_once(engine):
    """Once its engine has made it, no field of an outcome can be assigned: every reader sees
    the same answer (what the registry computes from it is kept aside, in its cache)."""
    import dataclasses

    out = deck_emulator.run("steel40", engine=engine)
    for name in ("error", "t", "events", "delta_v_crush_mph"):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(out, name, None)
    assert quantities.value("hit_time_s", out) == out.hit_time_s is not None
