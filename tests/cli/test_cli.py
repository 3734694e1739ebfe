"""The command line: run, summary, core, scene; files written whole or not at all."""

import json
import subprocess
import sys
from pathlib import Path

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_run_writes_the_golden_to_a_file(tmp_path, capsys):
    out = tmp_path / "steel40.txt"
    assert main(["run", "decks/steel40.dat", "--out", str(out)]) == 0
    assert out.read_text() == (ROOT / "golden" / "steel40.r8.txt").read_text()
    err = capsys.readouterr().err
    assert "arithmetic double" in err and "errata: none" in err


def test_run_single_writes_up_to_the_trap_and_fails(tmp_path, capsys):
    out = tmp_path / "x.txt"
    assert main(["run", "decks/steel40.dat", "--precision", "single", "--out", str(out)]) == 3
    assert out.read_text() == ""  # gfortran's r4 run printed nothing before its trap either
    assert "assigning PHIA" in capsys.readouterr().err
    assert not list(tmp_path.glob(".x.txt*"))  # no temporary left behind


def test_failed_write_leaves_no_file(tmp_path, capsys):
    target = tmp_path / "missing-dir" / "out.txt"
    assert main(["run", "decks/steel40.dat", "--out", str(target)]) == 2
    assert not target.exists()
    assert "error" in capsys.readouterr().err


def test_render_turns_carriage_control_into_page_layout(capsys):
    assert main(["run", "decks/steel40.dat", "--render"]) == 0
    text = capsys.readouterr().out
    assert text.startswith("\f\n    THE VALUE OF VVA IS")  # 1H1 is a record of its own
    assert text.count("\f") == (ROOT / "golden" / "steel40.r8.txt").read_text().splitlines().count("1")


def test_summary_json_names_the_errata_and_outcomes(capsys):
    assert main(["summary", "decks/steel40_a15.dat", "--erratum", "ed-direction", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["errata"] == ["ed-direction"]
    # the events as objects, in time order; the hit agrees with the printed message
    assert [e["kind"] for e in data["events"]] == ["lost_first_spring", "lost_vehicle", "hit"]
    assert data["events"][-1]["surface"] == "ground" and data["events"][-1]["point"] == "R"
    assert data["events"][0]["sentence"].startswith("post lost contact with the first spring at")
    # two ΔVs, two names: the report's (crush-pulse end) is reached before contact ends
    q = data["quantities"]
    assert 0 < q["delta_v_crush_mph"] < q["delta_v_contact_mph"]


def test_summary_without_needed_erratum_fails_with_a_hint(capsys):
    assert main(["summary", "decks/steel40_a30.dat", "--max-ed-iterations", "2000"]) == 3
    err = capsys.readouterr().err
    assert "ED's root search did not converge" in err and "--erratum ed-direction" in err


def test_scene_toml_round_trips_through_core(tmp_path, capsys):
    toml = tmp_path / "steel40.toml"
    assert main(["scene", "decks/steel40.dat", "--out", str(toml)]) == 0
    assert main(["core", str(toml), "--json"]) == 0
    from_toml = json.loads(capsys.readouterr().out)
    assert main(["core", "decks/steel40.dat", "--json"]) == 0
    from_deck = json.loads(capsys.readouterr().out)
    assert from_toml["events"][-1] == from_deck["events"][-1]
    assert from_toml["quantities"]["hit_time_s"] == from_deck["quantities"]["hit_time_s"]


def test_module_entry_point():
    proc = subprocess.run([sys.executable, "-m", "deck_emulator", "parse", "decks/steel40.dat", "--json"],
                          capture_output=True, text=True, cwd=ROOT, check=True)
    assert json.loads(proc.stdout)["values"]["FCONST"] == 1200.0


def test_ibm7094_run_ends_and_names_its_assumptions(capsys):
    """The archival run: the original deck as printed, in the 1967 machine's arithmetic."""
    assert main(["summary", "decks/steel40.dat", "--precision", "ibm7094", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    s = data["settings"]
    assert s["assumptions"] == {"sincos": "chop", "decimal": "chop", "output": "nearest"}
    assert s["arithmetic"].startswith("ibm7094 (sincos=chop")
    assert data["events"][-1]["sentence"].startswith("post hit the ground with the luminaire end R")
    assert data["errata"] == []


def test_machine_assumptions_belong_to_ibm7094(capsys):
    assert main(["run", "decks/steel40.dat", "--sincos", "round"]) == 2
    assert "assumptions of --precision ibm7094" in capsys.readouterr().err


def test_summary_flags_a_listing_hit_with_a_point_under_the_ground(tmp_path, capsys):
    """The post thrown down at 50 ft/s: the listing reports 'hit the ground with point P'
    while Q is far below the ground (it tests Q only in a 0.01 ft band). The printout stays
    the listing's; the summary says what is odd, with the printed depth."""
    from deck_emulator.legacy.deck import read_deck

    deck = tmp_path / "thrown_down.dat"
    deck.write_text(read_deck(ROOT / "decks" / "steel40.dat").with_values(V3B=-50.0).to_text())
    assert main(["summary", str(deck), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    zql = data["terminal_xl_yl_zl_ft"]["Q"][2]
    hit = data["events"][-1]
    assert (hit["surface"], hit["point"]) == ("ground", "P") and zql < -1.0
    assert any(f"Q {-zql:.3g} ft below the ground" in f for f in data["notes"]), data["notes"]
