"""Commands killed while they write (issue 17): SIGKILL at seeded random points of a command
that replaces existing outputs leaves every old file byte-identical or every new file complete,
never a truncated file; SIGINT leaves no temporary file and no worker process.

The kill points are drawn (seed 17) between a fifth of the command's measured duration and a
little past its end, so that some land in the writing.  The commands that take tens of seconds
are marked ``slow_corpus``."""

from __future__ import annotations

import hashlib
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from procs import group

ROOT = Path(__file__).resolve().parent.parent
GOLDEN = (ROOT / "golden" / "steel40.r8.txt").read_bytes()
CLI = [sys.executable, "-m", "deck_emulator"]
# the CLI as its main() will be wrapped: SIGTERM as an exception, exit 130 / 143
# (the handlers first, then the imports: a signal during the imports is handled too)
WRAPPED = [sys.executable, "-c", "import sys; from deck_emulator import signals; "
           "sys.exit(signals.run(lambda: __import__('deck_emulator.cli').cli.main(sys.argv[1:])))"]


def env():
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + e.get("PYTHONPATH", "")
    e["MPLBACKEND"] = "Agg"
    return e


def sha(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


def state(folder: Path) -> dict[str, str]:
    """name -> hash of the visible files of ``folder`` (hidden temporaries left out)."""
    return {p.name: sha(p) for p in sorted(folder.iterdir()) if not p.name.startswith(".")}




def timed(argv, **kw) -> float:
    started = time.monotonic()
    r = subprocess.run(argv, cwd=ROOT, env=env(), capture_output=True, timeout=900, **kw)
    assert r.returncode == 0, r.stderr
    return time.monotonic() - started


def killed_at(argv, delay: float, sig=signal.SIGKILL) -> subprocess.Popen:
    """Start ``argv`` in its own process group, send ``sig`` to its main process after
    ``delay`` s, wait for it; then make sure nothing of the group is left."""
    p = subprocess.Popen(argv, cwd=ROOT, env=env(), stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, start_new_session=True)
    try:
        p.wait(timeout=delay)
    except subprocess.TimeoutExpired:
        p.send_signal(sig)
    p.wait(timeout=120)
    p.leftover = _wait_group_empty(p.pid, 10)
    for pid in p.leftover:
        os.kill(pid, signal.SIGKILL)
    return p


def _wait_group_empty(pgid: int, seconds: float) -> list[int]:
    deadline = time.monotonic() + seconds
    while group(pgid) and time.monotonic() < deadline:
        time.sleep(0.1)
    return group(pgid)


def delays(full_s: float, n: int, seed: int = 17) -> list[float]:
    rng = random.Random(seed)
    return sorted(rng.uniform(0.2 * full_s, 1.1 * full_s) for _ in range(n))


# ----------------------------------------------------------------------------- run --out


def test_run_out_killed_anywhere_leaves_old_or_new(tmp_path):
    out = tmp_path / "steel40.txt"
    old = b"the previous run\n" * 50
    argv = CLI + ["run", "decks/steel40.dat", "--out", str(out)]
    out.write_bytes(old)
    full = timed(argv)
    assert out.read_bytes() == GOLDEN
    seen = set()
    for delay in delays(full, 4):
        out.write_bytes(old)
        killed_at(argv, delay)
        got = out.read_bytes()
        assert got in (old, GOLDEN), (delay, len(got))
        seen.add("new" if got == GOLDEN else "old")
    timed(argv)  # a later run into the same folder removes what the killed ones left
    assert sorted(p.name for p in tmp_path.iterdir()) == ["steel40.txt"], seen


def test_run_out_interrupted_leaves_no_temporary(tmp_path):
    out = tmp_path / "steel40.txt"
    argv = WRAPPED + ["run", "decks/steel40.dat", "--out", str(out)]
    full = timed(argv)
    out.write_bytes(b"old")
    interrupted = 0
    for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
        p = killed_at(argv, 0.5 * full, sig)
        assert sorted(x.name for x in tmp_path.iterdir()) == ["steel40.txt"]
        if p.returncode == 0:  # the run was faster than the signal: then the new file, whole
            assert out.read_bytes() == GOLDEN
            out.write_bytes(b"old")
            continue
        interrupted += 1
        assert p.returncode == code, p.stderr.read()
        assert out.read_bytes() == b"old"
    assert interrupted, "no signal landed inside the run"


# ----------------------------------------------------------------------------- plot


@pytest.mark.slow_corpus
def test_plot_killed_anywhere_leaves_both_old_or_both_new(tmp_path):
    png, gif = tmp_path / "fall.png", tmp_path / "fall.gif"
    argv = CLI + ["plot", "decks/steel40.dat", "--out", str(png), "--animate", str(gif)]
    full = timed(argv)
    new = state(tmp_path)
    assert set(new) == {"fall.png", "fall.gif"}
    old = {"fall.png": b"old png", "fall.gif": b"old gif"}
    for delay in delays(full, 2):
        for name, data in old.items():
            (tmp_path / name).write_bytes(data)
        killed_at(argv, delay)
        got = state(tmp_path)
        assert got in ({n: hashlib.sha256(d).hexdigest() for n, d in old.items()}, new), delay


# ----------------------------------------------------------------------------- studies


def _complete_study(folder: Path, reference: Path) -> None:
    """Every file of the study there and complete: the same names as a reference run, the
    CSV with as many lines, the PNGs whole, the README ending as the reference's does."""
    from PIL import Image

    names = sorted(p.name for p in reference.iterdir() if not p.name.startswith("."))
    assert sorted(p.name for p in folder.iterdir() if not p.name.startswith(".")) == names
    for name in names:
        p, ref = folder / name, reference / name
        if name.endswith(".csv"):
            assert len(p.read_text().splitlines()) == len(ref.read_text().splitlines()), name
        elif name.endswith(".png"):
            with Image.open(p) as im:
                im.load()
        else:
            assert p.read_text().splitlines()[-1:] == ref.read_text().splitlines()[-1:] or \
                len(p.read_bytes()) > 0.9 * len(ref.read_bytes()), name


@pytest.mark.slow_corpus
def test_study_killed_anywhere_leaves_old_or_new(tmp_path):
    ref = tmp_path / "ref"
    argv_ref = CLI + ["study", "stability", "--quick", "--jobs", "2", "--out", str(ref)]
    full = timed(argv_ref)
    out = tmp_path / "out"
    argv = CLI + ["study", "stability", "--quick", "--jobs", "2", "--out", str(out)]
    old_files = {"stability_study.csv": b"old,csv\n", "README.md": b"# old\n",
                 "stability_map.png": b"old", "extreme_scenes.png": b"old"}
    for delay in delays(full, 2, seed=18):
        out.mkdir(exist_ok=True)
        for name, data in old_files.items():
            (out / name).write_bytes(data)
        before = state(out)
        p = killed_at(argv, delay)
        assert p.leftover == [], "workers outlived the killed study"
        if state(out) != before:
            _complete_study(out, ref)
    # a new folder: it appears complete or not at all
    from deck_emulator.files import OutputSet

    fresh = tmp_path / "fresh"
    p = killed_at(argv[:-1] + [str(fresh)], 0.6 * full)
    assert p.leftover == []
    if fresh.exists():
        _complete_study(fresh, ref)
    with OutputSet(directory=tmp_path / "later") as later:  # a later writer into the folder
        later.write("x", "x")  # removes the staging folder the SIGKILL left
    assert sorted(x.name for x in tmp_path.iterdir() if x.name.startswith(".")) == []


@pytest.mark.slow_corpus
def test_study_interrupted_leaves_no_temporary_and_no_worker(tmp_path):
    study = ["study", "error", "decks/steel40.dat", "--quick", "--jobs", "2", "--out"]
    full = timed(CLI + study + [str(tmp_path / "ref")])  # the signal lands half-way through
    work = tmp_path / "work"
    work.mkdir()
    out = work / "new"
    for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
        p = killed_at(WRAPPED + study + [str(out)], 0.5 * full, sig)
        assert p.returncode == code, p.stderr.read()
        assert p.leftover == [], "worker processes outlived the interrupted study"
        assert sorted(x.name for x in work.iterdir()) == []  # no folder, no staging


# ----------------------------------------------------------------------------- sweep


SWEEP = ["sweep", "--speeds", "20,30,40", "--angles", "0,15", "--erratum", "ed-direction",
         "--jobs", "2", "--quiet"]


def test_sweep_killed_anywhere_leaves_old_or_new(tmp_path):
    ref = tmp_path / "ref"
    full = timed(CLI + SWEEP + ["--out", str(ref)])
    expected = {p.name: p.read_bytes() for p in ref.iterdir() if p.is_file()}
    out = tmp_path / "out"
    old = {"sweep.csv": b"old,csv\n", "sweep.md": b"# old\n"}
    for delay in delays(full, 3, seed=19):
        out.mkdir(exist_ok=True)
        for name, data in old.items():
            (out / name).write_bytes(data)
        p = killed_at(CLI + SWEEP + ["--out", str(out)], delay)
        assert p.leftover == [], "sweep workers outlived the killed command"
        now = {q.name: q.read_bytes() for q in out.iterdir() if not q.name.startswith(".")}
        assert p.returncode != 0 or now != old  # (a run that ended wrote the new pair)
        # both old, or both new and whole (run times and the command line may differ)
        assert now == old or (_rows(now["sweep.csv"]) == _rows(expected["sweep.csv"])
                              and now["sweep.md"].replace(str(out).encode(), b"")
                              == expected["sweep.md"].replace(str(ref).encode(), b"")), now


def _rows(csv_bytes: bytes) -> list[dict]:
    import csv
    import io

    rows = list(csv.DictReader(io.StringIO(csv_bytes.decode())))
    for r in rows:
        r.pop("run_s")
    return rows


def test_sweep_interrupted_leaves_no_temporary_and_no_worker(tmp_path):
    out = tmp_path / "new"
    full = timed(CLI + SWEEP + ["--out", str(tmp_path / "ref")])
    for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
        p = killed_at(CLI + SWEEP + ["--out", str(out)], 0.5 * full, sig)
        if p.returncode == 0:  # it finished first on a fast machine: nothing to check
            continue
        assert p.returncode == code, p.stderr.read()
        assert p.leftover == [], "sweep workers outlived the interrupted command"
        # no table, no temporary: only the scene store, kept for --resume
        assert sorted(x.name for x in out.iterdir()) in ([], [".scenes"])
        assert sorted(x.name for x in tmp_path.iterdir() if x.name.startswith(".")) == []


def test_sweep_killed_then_resumed_runs_each_scene_once(tmp_path):
    """SIGKILL of the whole sweep part-way, then --resume: the stored scenes are kept as they
    were (no file changed), only the missing ones run, and the table has every scene once."""
    import csv
    import io

    argv = CLI + ["sweep", "--speeds", "20:45:5", "--angles", "0,15", "--erratum",
                  "ed-direction", "--jobs", "2", "--quiet", "--out", str(tmp_path / "out")]
    ref = timed(CLI + ["sweep", "--speeds", "20", "--angles", "0", "--jobs", "2", "--quiet",
                       "--out", str(tmp_path / "warm")])  # a cluster's start-up, measured
    store = tmp_path / "out" / ".scenes" / "results"
    for delay in (ref + 4.0, ref + 8.0, ref + 16.0):
        p = killed_at(argv, delay)
        assert p.leftover == []
        if p.returncode != 0 and store.is_dir() and list(store.iterdir()):
            break
    files = {q.name: sha(q) for q in store.iterdir()} if store.is_dir() else {}
    done = subprocess.run(argv + ["--resume"], cwd=ROOT, env=env(), capture_output=True,
                          text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    after = {q.name: sha(q) for q in store.iterdir()}
    assert all(after[name] == h for name, h in files.items())  # nothing stored was rewritten
    rows = list(csv.DictReader(io.StringIO((tmp_path / "out" / "sweep.csv").read_text())))
    scenes = [(float(r["speed_mph"]), float(r["angle_deg"])) for r in rows]
    assert sorted(scenes) == sorted({(s, a) for s in range(20, 50, 5) for a in (0, 15)})
    assert all(r["error"] == "" and r["hit"] for r in rows)
