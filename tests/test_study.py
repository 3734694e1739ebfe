"""The two studies of issue 6, run with --quick through their command-line parser."""

from __future__ import annotations

import argparse
import csv
import itertools
from pathlib import Path

import numpy as np
import pytest

from deck_emulator.studies import study_cli as study
from deck_emulator.studies.error import COLUMNS as ERROR_COLUMNS
from deck_emulator.studies.stability import COLUMNS as STABILITY_COLUMNS

DECK = Path(__file__).resolve().parents[1] / "decks" / "steel40.dat"


def _run(argv: list[str]) -> int:
    from deck_emulator.cli import build_parser

    parser = build_parser()
    args = parser.parse_args(argv)
    return args.func(args)


def _rows(path: Path) -> tuple[list[str], list[dict]]:
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        return list(reader.fieldnames or []), list(reader)


def _num(text: str) -> float:
    return float(text) if text not in ("", None) else float("nan")


def _check_png(path: Path) -> None:
    import matplotlib.image as mpimg

    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    img = mpimg.imread(path)
    assert img.ndim == 3 and img.shape[0] > 300 and img.shape[1] > 600
    rgb = img[..., :3]
    assert float(rgb.std()) > 0.05  # not blank
    assert float((rgb.mean(axis=2) < 0.5).mean()) > 0.005  # some dark ink: text, lines


@pytest.fixture(scope="module")
def error_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("error")
    assert _run(["study", "error", str(DECK), "--out", str(out), "--quick", "--jobs", "2"]) == 0
    return out


@pytest.fixture(scope="module")
def stability_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("stability")
    assert _run(["study", "stability", "--out", str(out), "--quick", "--jobs", "2"]) == 0
    return out


def test_error_study_files(error_dir):
    for name in ("error_study.csv", "work_precision.png", "README.md"):
        assert (error_dir / name).is_file(), name
    header, rows = _rows(error_dir / "error_study.csv")
    assert header == ERROR_COLUMNS
    assert "np." not in (error_dir / "error_study.csv").read_text()
    series = {r["series"] for r in rows}
    assert {"legacy, ED as printed (double)", "legacy, ED tightened (double)", "core DOP853",
            "core RK45", "core Radau", "reference check"} <= series


def test_error_decreases_with_h_for_the_legacy_scheme(error_dir):
    _, rows = _rows(error_dir / "error_study.csv")
    tight = sorted((r for r in rows if r["series"] == "legacy, ED tightened (double)"),
                   key=lambda r: int(r["k"]))
    assert len(tight) >= 3 and all(r["status"] == "hit" for r in tight)
    errors = [_num(r["err_traj_ft"]) for r in tight]
    assert all(b < a for a, b in itertools.pairwise(errors)), errors
    # first order: halving H about halves the error
    assert all(0.35 < b / a < 0.65 for a, b in itertools.pairwise(errors)), errors
    hit = [_num(r["err_R_ft"]) for r in tight]
    assert hit[-1] < hit[0]


def test_core_error_at_rtol_1e10_below_a_micro_foot(error_dir):
    _, rows = _rows(error_dir / "error_study.csv")
    core = [r for r in rows if r["engine"] == "core" and r["series"] != "reference check"
            and _num(r["rtol"]) == 1e-10]
    assert {r["method"] for r in core} == {"DOP853", "RK45", "Radau"}
    for r in core:
        assert r["status"] == "hit"
        assert _num(r["err_traj_ft"]) < 1e-6, r
        assert _num(r["err_hit_s"]) < 1e-6, r


def test_reference_error_is_known_and_small(error_dir):
    _, rows = _rows(error_dir / "error_study.csv")
    checks = [r for r in rows if r["series"] == "reference check"]
    assert checks and all(_num(r["err_traj_ft"]) < 1e-8 for r in checks)
    text = (error_dir / "README.md").read_text()
    assert "Its own error" in text


def test_error_report(error_dir):
    text = (error_dir / "README.md").read_text()
    assert "deck-emulator study error" in text and "--quick" in text
    assert "observed order" in text.lower()
    assert "cores" in text and "os.cpu_count()" in text
    assert "times faster" in text
    assert "![work-precision diagram](work_precision.png)" in text
    _check_png(error_dir / "work_precision.png")


def test_stability_study_files(stability_dir):
    for name in ("stability_study.csv", "stability_map.png", "extreme_scenes.png", "README.md"):
        assert (stability_dir / name).is_file(), name
    header, rows = _rows(stability_dir / "stability_study.csv")
    assert header == STABILITY_COLUMNS
    assert "np." not in (stability_dir / "stability_study.csv").read_text()
    scenes = {r["scene"] for r in rows}
    assert {"base", "speed-5", "speed-120", "angle-90", "tha-0.0", "abc-equal",
            "friction-large", "thb-1.5"} <= scenes
    assert any(s.startswith("stiff-") for s in scenes)
    known = {"agrees", "same hit, off", "other hit", "no hit", "crash", "n/a", "hit (core failed)"}
    for r in rows:
        assert r["emulator_class"] in known or r["emulator_class"].startswith("guard: "), r
        assert r["core_status"] in ("hit", "no hit", "error"), r
    base = next(r for r in rows if r["scene"] == "base")
    assert base["emulator_class"] == "agrees"
    # a stiff spring at a large step: the emulator's launch energy is far off
    stiff = [r for r in rows if r["group"] == "stiff"]
    worst = max(stiff, key=lambda r: _num(r["h_omega"]))
    assert _num(worst["launch_ke_rel_diff"]) > 0.1
    # friction is not a deck input: core only
    fric = next(r for r in rows if r["scene"] == "friction-large")
    assert fric["emulator_class"] == "n/a" and fric["core_status"] in ("hit", "no hit", "error")


def test_stability_report(stability_dir):
    text = (stability_dir / "README.md").read_text()
    assert "deck-emulator study stability" in text and "--quick" in text
    assert "cores" in text and "os.cpu_count()" in text
    section = text.split("## Failure modes found", 1)[1].split("##", 1)[0]
    bullets = [line for line in section.splitlines() if line.startswith("* ")]
    assert bullets and all("`" in b for b in bullets)  # each names a scene
    for png in ("stability_map.png", "extreme_scenes.png"):
        assert f"]({png})" in text
        _check_png(stability_dir / png)


def test_jobs_must_be_positive():
    with pytest.raises(SystemExit):
        _run(["study", "stability", "--out", "x", "--jobs", "0"])


def test_energy_helpers_on_a_plain_run():
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.studies.common import energies, run_emulator

    deck = read_deck(DECK)
    out = run_emulator(deck)
    assert out["status"] == "hit"
    e = energies(out)
    assert np.isfinite(e["launch_ke_ftlb"]) and e["launch_ke_ftlb"] > 0
    assert 0 < e["free_drift"] < 0.05  # the explicit scheme gains a little energy in free flight
