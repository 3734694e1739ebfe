"""Installed = checked out: the wheel, installed into a fresh virtual environment, runs the
README's commands from a directory outside the checkout."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def _run(argv, cwd, timeout=300):
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    return subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """A fresh venv with this checkout installed as ``pip install .`` does (a built wheel, not
    editable). The venv sees this interpreter's site-packages for the dependencies (numpy,
    scipy ...) so the test needs no network; the package itself comes from the wheel."""
    base = tmp_path_factory.mktemp("install")
    env_dir = base / "venv"
    venv.EnvBuilder(system_site_packages=True, with_pip=True).create(env_dir)
    python = env_dir / "bin" / "python"
    inst = _run([str(python), "-m", "pip", "install", "--no-deps", str(ROOT)], cwd=base)
    assert inst.returncode == 0, inst.stdout + inst.stderr
    where = _run([str(python), "-c", "import deck_emulator; print(deck_emulator.__file__)"],
                 cwd=base)
    assert str(env_dir) in where.stdout, where.stdout + where.stderr  # the wheel, not the checkout
    work = base / "elsewhere"
    work.mkdir()
    return env_dir / "bin" / "deck-emulator", work


def test_run_and_summary_on_an_absolute_deck_path(installed):
    exe, work = installed
    deck = str(ROOT / "decks" / "steel40.dat")
    run = _run([str(exe), "run", deck], cwd=work)
    assert run.returncode == 0, run.stderr
    assert run.stdout == (ROOT / "golden" / "steel40.r8.txt").read_text()
    summary = _run([str(exe), "summary", deck, "--json"], cwd=work)
    assert summary.returncode == 0, summary.stderr
    hit = json.loads(summary.stdout)["events"][-1]
    assert (hit["kind"], hit["surface"], hit["point"]) == ("hit", "ground", "R")


@pytest.mark.parametrize("argv, made", [
    (["parse", "{deck}", "--json"], None),
    (["run", "{deck}", "--precision", "ibm7094", "--out", "r.txt"], "r.txt"),
    (["plot", "{deck}", "--out", "side.png"], "side.png"),
    (["diff", "{deck}", "--erratum", "ed-direction", "--max-k", "0"], None),
    (["core", "{deck}"], None),
    (["scene", "{deck}", "--out", "s.toml"], "s.toml"),
    (["core", "s.toml"], None),
    (["punch", "{deck}", "--to", "cbn", "--job", "--out", "j.cbn"], "j.cbn"),
    (["run", "j.cbn", "--pages", "j.pdf"], "j.pdf"),
    (["assembly", "aluminium", "deck"], None),
    (["study", "error", "{deck}", "--quick", "--jobs", "2", "--out", "err"], "err/README.md"),
])
def test_every_readme_command_runs_installed(installed, argv, made):
    """Each command of the README, as a user types it, from outside the checkout (in order:
    the scene and the punched job deck of earlier rows are inputs of later ones)."""
    exe, work = installed
    deck = str(ROOT / "decks" / "steel40.dat")
    proc = _run([str(exe)] + [a.format(deck=deck) for a in argv], cwd=work, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    if made:
        assert (work / made).stat().st_size > 0
    else:
        assert proc.stdout.strip()


def test_sweep_and_study_need_no_base_deck_path(installed):
    exe, work = installed
    sweep = _run([str(exe), "sweep", "--speeds", "40", "--angles", "0", "--jobs", "1",
                  "--out", "sweep"], cwd=work)
    assert sweep.returncode == 0, sweep.stderr
    assert "POST HITS GROUND WITH POINT R" in (work / "sweep" / "sweep.md").read_text()
    study = _run([str(exe), "study", "stability", "--quick", "--jobs", "2", "--out", "stab"],
                 cwd=work, timeout=600)
    assert study.returncode == 0, study.stderr
    assert (work / "stab" / "README.md").is_file()


def test_the_listing_ships_with_the_package(installed):
    """Job decks carrying the program's source are compared with the listing: the installed
    package holds it (the checkout's file, through a link in the package's folder)."""
    exe, work = installed
    python = exe.parent / "python"
    code = ("import importlib.resources as r; "
            "print(r.files('deck_emulator.legacy').joinpath('luminaire.f').read_text(), end='')")
    proc = _run([str(python), "-c", code], cwd=work)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == (ROOT / "legacy" / "luminaire.f").read_text()
