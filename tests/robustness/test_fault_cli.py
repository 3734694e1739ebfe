"""The fault campaign's reproducers that end at the command line: each ends with its documented
exit status (0 computed, 2 bad input and nothing written, 3 a run that could not end), one
line, no traceback. The package-level ones are in test_assembly_inputs, test_scene,
test_deck, test_extract, test_sensitivity, test_store_lock, test_output_sets."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[2]
STEEL40 = str(ROOT / "decks" / "steel40.dat")


def _deck(tmp_path: Path, name: str, **changes) -> str:
    from deck_emulator.engine.assemblies import to_deck_text
    from deck_emulator.legacy.deck import read_deck

    path = tmp_path / f"{name}.dat"
    path.write_text(to_deck_text(dict(read_deck(STEEL40).with_values(**changes).values)))
    return str(path)


def _one_line(err: str) -> str:
    assert "Traceback" not in err, err
    lines = [x for x in err.splitlines() if x.startswith("deck-emulator: error:")]
    assert len(lines) == 1, err
    return lines[0]


@pytest.mark.parametrize("argv, status, says", [
    (["run", "steel40", "--max-ed-iterations", "1", "--out", "{tmp}/p.txt"], 3,
     "did not converge in 1 iterations"),
    (["core", "steel40", "--atol", "1e-300"], 2, "--atol: must be from 1e-14"),
    (["sweep", "--speeds", "inf", "--angles", "0", "--out", "{tmp}/sw"], 2, "not finite"),
    (["sweep", "--speeds", "20:40:1e-300", "--angles", "0", "--out", "{tmp}/sw"], 2,
     "more than 10000"),
    (["sweep", "--speeds", "1:100000000:1", "--angles", "0", "--out", "{tmp}/sw"], 2,
     "more than 10000"),
    (["diff", "steel40", "--max-k", "12"], 2, "--max-k: at most 8"),
    (["run", "steel40", "--out", "{tmp}/same", "--pages", "{tmp}/same"], 2, "pages are a PDF"),
    (["run", "steel40", "--out", "{tmp}/same.pdf", "--pages", "{tmp}/same.pdf"], 2,
     "same file"),
])
def test_bounded_and_named(argv, status, says, tmp_path, capsys):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(argv) == status
    assert says in _one_line(capsys.readouterr().err)
    assert not (tmp_path / "sw").exists() and not (tmp_path / "same.pdf").exists()


def test_a_negative_number_in_exponent_form_is_a_value(capsys):
    assert main(["summary", "steel40", "--tha-start", "-1e-5", "--quiet"]) == 0


def test_a_negative_number_is_the_value_of_the_option_before_it_in_any_spelling():
    """Any negative number (exponent form or not) after an option that takes a value is that
    value, also after an abbreviation of the option or written with '='; after an option that
    takes none it is left to argparse, which refuses it."""
    from hypothesis import HealthCheck, given, settings, strategies as st

    from deck_emulator.cli import build_parser

    parser = build_parser("summary")
    number = st.from_regex(r"-([1-9][0-9]{0,3}(\.[0-9]{0,3})?|\.[0-9]{1,3}[1-9])"
                           r"([eE][-+]?[0-9]{1,2})?", fullmatch=True)

    @settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])  # (a loaded machine)
    @given(text=number, spelling=st.sampled_from(["--tha-start", "--tha-st", "--tha-start="]))
    def check(text, spelling):
        argv = ["summary", "steel40", *([spelling + text] if spelling.endswith("=")
                                        else [spelling, text])]
        assert parser.parse_args(argv).tha_start == text

    check()
    with pytest.raises(SystemExit):
        parser.parse_args(["summary", "steel40", "--quiet", "-1e-5"])


@pytest.mark.parametrize("command", [["diff"], ["study", "error"]])
def test_a_deck_the_core_refuses_is_bad_input_for_both_engines(command, tmp_path, capsys):
    w0 = _deck(tmp_path, "w0", W=0.0)
    extra = ["--quick", "--out", str(tmp_path / "st")] if command[0] == "study" else []
    assert main([*command, w0, *extra]) == 2
    assert "post mass must be positive" in _one_line(capsys.readouterr().err)
    assert not (tmp_path / "st").exists()


def test_a_printed_value_that_overflows_its_field_is_named_not_a_traceback(tmp_path, capsys):
    """XRO = 10,000 ft: the listing prints R's final coordinates as ********** (the field is
    too narrow), as the compiled listing does; summary says so and names the field."""
    deck = _deck(tmp_path, "xro", XRO=10000.0)
    assert main(["summary", deck, "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "XRFA overflowed its printed field" in out
    assert "**********" in out  # R's unknown coordinate, in the table at the hit


def test_a_users_crash_test_is_the_one_that_runs(tmp_path, capsys):
    text = (ROOT / "src" / "deck_emulator" / "assemblies" / "crash_test.toml").read_text()
    assert "vehicle_speed_ft_s = 40.0" in text
    mine = tmp_path / "crash.toml"
    mine.write_text(text.replace("vehicle_speed_ft_s = 40.0", "vehicle_speed_ft_s = 60.0"))
    assert main(["assembly", "crash_test", "scene"]) == 0
    shipped = capsys.readouterr().out
    assert main(["assembly", str(mine), "scene"]) == 0
    theirs = capsys.readouterr().out
    assert "initial_velocity_ft_s = -40.0" in shipped
    assert "initial_velocity_ft_s = -60.0" in theirs
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("post_weight_lb = ", "post_weight_lb = -5 #"))
    assert main(["assembly", str(bad), "core"]) == 2
    assert "post_weight_lb" in _one_line(capsys.readouterr().err)
    empty = tmp_path / "e.toml"
    empty.write_text("")
    assert main(["assembly", str(empty), "core"]) == 2
    _one_line(capsys.readouterr().err)


def test_a_cluster_without_workers_ends_a_sweep_within_worker_wait(tmp_path, capsys):
    """A scheduler no worker ever joins: the sweep ends with exit 3 after --worker-wait, names
    the scheduler, and leaves no folder (it stored nothing)."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster:
        argv = ["sweep", "--speeds", "20", "--angles", "0", "--quiet", "--out",
                str(tmp_path / "sw"), "--scheduler", cluster.scheduler_address,
                "--worker-wait", "1"]
        assert main(argv) == 3
    line = _one_line(capsys.readouterr().err)
    assert "has no worker: none joined in 1 s" in line and cluster.scheduler_address in line
    assert not (tmp_path / "sw").exists()


@pytest.mark.parametrize("argv, says", [
    (["run", "steel40", "--out", ""], "--out: an empty path"),
    (["run", "steel40", "--pages", ""], "--pages: an empty path"),
    (["sweep", "--speeds", "20", "--angles", "0", "--out", "{tmp}/sw", "--worker-wait", "5"],
     "--worker-wait: only with --scheduler"),
    (["sensitivity", "--quick", "--out", "{tmp}/a/missing/d"], "does not exist"),
])
def test_refused_before_any_work(argv, says, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(argv) == 2
    assert says in _one_line(capsys.readouterr().err)
    assert list(tmp_path.iterdir()) == []


def test_the_cores_bounds_are_options(tmp_path, capsys):
    """core's --max-wall and --max-time bound one run (the library's bounds, named): a wall
    time too short for the run is a named stop (3); so is a simulated time bound reached
    with the post still in the air (the emulator's 'the post has not landed'), whose
    trajectory ends there and is written."""
    # a nanosecond: no machine runs a scene in it, so the outcome does not hang on its speed
    assert main(["core", "steel40", "--max-wall", "1e-9", "--quiet"]) == 3
    assert "max_wall_s = 1e-09 s of wall time" in _one_line(capsys.readouterr().err)
    csv = tmp_path / "t.csv"
    assert main(["core", "steel40", "--max-time", "0.05", "--quiet", "--trajectory",
                 str(csv)]) == 3
    assert "0.05 s (--max-time) with no hit" in _one_line(capsys.readouterr().err)
    import pandas as pd

    assert pd.read_csv(csv)["t_s"].max() <= 0.05
    assert main(["core", "steel40", "--max-time", "0.05", "--json"]) == 3
    assert json.loads(capsys.readouterr().out)["status"] == "stopped"
