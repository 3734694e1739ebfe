"""Commands killed while they write: SIGKILL of a command that replaces existing
outputs leaves every file whole, old or new, never a truncated one; SIGINT and SIGTERM leave no
temporary file and no worker process, and end with 130 and 143.

Every signal lands at a known point of the writing, whatever the machine's speed: the command
runs under :data:`HOOK` (test code, nothing in the package), which patches
:mod:`deck_emulator.files` (or the parallel map, or the scene store) so that, when the command
reaches the point named in ``KILL_POINT``, it writes the marker file named in ``KILL_MARKER``
(with what it was doing there, as JSON) and waits.  The test waits for the marker
(:data:`HANG_S` only guards against a hang), sends the signal, and asserts what must hold at
that point.  The points:

* ``file-staged``: :func:`~deck_emulator.files.write_file` has written and fsynced its
  temporary and not yet renamed it;
* ``renaming`` / ``renamed``: just before / just after the ``KILL_NTH``-th rename made by
  :mod:`deck_emulator.files` (a file over its target, or a new folder's staging folder to its
  name); these are inside the commit, where SIGINT/SIGTERM are held;
* ``set-staged``: an :class:`~deck_emulator.files.OutputSet` has every file staged and nothing
  renamed (the start of its commit);
* ``runs``: the first run's result is back from the workers, the others are still out;
* ``stored``: the sweep's scene store holds its first batch (one Dask task's scenes), the others are still
  out.

The commands that take tens of seconds are marked ``slow_corpus``."""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from procs import group, sigint_as_on_a_terminal

#: process-level or document tests: the README's test command runs them, a bare pytest not
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = (ROOT / "golden" / "steel40.r8.txt").read_bytes()
CLI = [sys.executable, "-m", "deck_emulator"]
HANG_S = 300  # the longest wait for a point or an exit: a guard against a hang, never a measure

# The CLI as its main() will be wrapped (SIGTERM as an exception, exit 130 / 143; the handlers
# first, then the imports), stopping at the point KILL_POINT.
HOOK = r'''
import json, os, signal, sys, time
from deck_emulator import signals
signals.install_signal_handlers()

POINT, MARKER = os.environ["KILL_POINT"], os.environ["KILL_MARKER"]
NTH = int(os.environ.get("KILL_NTH", "1"))
CATCHABLE = {signal.SIGINT, signal.SIGTERM}
counts = {}


def nth(what):
    """Whether this is the NTH time the command passes ``what``."""
    counts[what] = counts.get(what, 0) + 1
    return counts[what] == NTH


def reached(**info):
    """Write the marker (aside, then renamed: the test reads it whole) and wait for the test's
    signal.  SIGKILL ends us here.  SIGINT/SIGTERM: we wait until our handler has run (or the
    signal is pending, blocked): a handler that raises (KeyboardInterrupt, Terminated) raises
    here; one that holds the signal (inside a commit) lets us go on, and the signal is
    delivered when the hold ends."""
    with open(MARKER + ".tmp", "w") as fh:
        json.dump(dict(point=POINT, pid=os.getpid(), **info), fh)
    os.rename(MARKER + ".tmp", MARKER)
    seen, handlers = [], {}
    for sig in CATCHABLE:
        handler = signal.getsignal(sig)
        if callable(handler):
            handlers[sig] = handler
            signal.signal(sig, lambda n, frame, handler=handler: (seen.append(n), handler(n, frame)))
    try:
        end = time.monotonic() + 900
        while time.monotonic() < end:
            if seen or CATCHABLE & signal.sigpending():
                return
            time.sleep(0.01)
    finally:
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
    sys.stderr.write(f"the point {POINT} was reached and no signal came\n")
    os._exit(97)


from deck_emulator import files, parallel

if POINT == "file-staged":
    _mode_as_open = files._mode_as_open

    def mode_as_open(tmp, existing):
        _mode_as_open(tmp, existing)
        if nth("file-staged"):
            reached(temporary=str(tmp))

    files._mode_as_open = mode_as_open
elif POINT == "set-staged":
    _commit = files.OutputSet._commit

    def commit(self):
        if nth("set-staged"):
            reached(staged=[str(s) for s in self._order],
                    targets=[str(self._staged[s][0]) for s in self._order])
        _commit(self)

    files.OutputSet._commit = commit
elif POINT in ("renaming", "renamed"):
    class Os:
        """``os`` for deck_emulator.files alone, its renames watched."""

        def __getattr__(self, name):
            return getattr(os, name)

        def _move(self, move, src, dst):
            hit = nth("rename")
            if hit and POINT == "renaming":
                reached(src=str(src), dst=str(dst))
            move(src, dst)
            if hit and POINT == "renamed":
                reached(src=str(src), dst=str(dst))

        def replace(self, src, dst):
            self._move(os.replace, src, dst)

        def rename(self, src, dst):
            self._move(os.rename, src, dst)

    files.os = Os()
elif POINT == "runs":
    _progress_bar = parallel.progress_bar

    def progress_bar(*a, **k):
        bar = _progress_bar(*a, **k)
        update = bar.update

        def counted(n=1):
            got = update(n)
            if nth("runs"):
                reached()
            return got

        bar.update = counted
        return bar

    parallel.progress_bar = progress_bar
elif POINT == "stored":
    from deck_emulator.studies import distributed

    _run_scenes, _write_batch = distributed.run_scenes, distributed.SceneStore.write_batch

    def run_scenes(*a, **k):
        k["flush_s"] = 0.0  # a file per finished Dask task: the first holds its scenes alone
        return _run_scenes(*a, **k)

    def write_batch(self, rows):
        path = _write_batch(self, rows)
        if path is not None and nth("stored"):
            reached(batch=str(path), rows=len(rows))
        return path

    distributed.run_scenes = run_scenes
    distributed.SceneStore.write_batch = write_batch
else:
    sys.exit(f"unknown KILL_POINT {POINT}")

sys.exit(signals.run(lambda: __import__("deck_emulator.cli").cli.main(sys.argv[1:])))
'''


#: the studies' and the sweep's scene store inside their folder (kept for --resume)
STORE = ".scenes"


def env(**extra) -> dict:
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + e.get("PYTHONPATH", "")
    e["MPLBACKEND"] = "Agg"
    e.update(extra)
    return e


def sha(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


def visible(folder: Path) -> dict[str, bytes]:
    """name -> bytes of the visible files of ``folder`` (hidden temporaries left out)."""
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())
            if p.is_file() and not p.name.startswith(".")}


def hidden(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


def run_ok(argv: list[str]) -> None:
    """A whole run of the command, unhooked."""
    r = subprocess.run(CLI + argv, cwd=ROOT, env=env(), capture_output=True, timeout=900)
    assert r.returncode == 0, r.stderr


_started: list[subprocess.Popen] = []


@pytest.fixture(autouse=True)
def _no_command_left():
    """A test that fails while a command waits at its point leaves nothing running."""
    yield
    while _started:
        p = _started.pop()
        with contextlib.suppress(ProcessLookupError):
            os.killpg(p.pid, signal.SIGKILL)
        with contextlib.suppress(subprocess.TimeoutExpired):
            p.wait(timeout=HANG_S)


def pause_at(tmp_path: Path, point: str, argv: list[str], nth: int = 1) -> subprocess.Popen:
    """Start the command ``argv`` under :data:`HOOK` in its own process group and return when
    it waits at ``point`` (its ``nth`` passage); ``p.info`` is what it wrote in the marker."""
    marks = tmp_path / "marks"
    marks.mkdir(exist_ok=True)
    n = len(list(marks.glob("*.json")))
    marker, err = marks / f"{n}-{point}.json", marks / f"{n}-{point}.stderr"
    with open(err, "wb") as fh:  # a file, not a pipe: a command that says much never blocks
        p = subprocess.Popen([sys.executable, "-c", HOOK] + argv, cwd=ROOT,
                             env=env(KILL_POINT=point, KILL_NTH=str(nth), KILL_MARKER=str(marker)),
                             stdout=subprocess.DEVNULL, stderr=fh, start_new_session=True,
                             preexec_fn=sigint_as_on_a_terminal)
    _started.append(p)
    p.err = err
    deadline = time.monotonic() + HANG_S
    while not marker.exists():
        if p.poll() is not None:
            pytest.fail(f"{argv[0]} ended ({p.returncode}) before reaching {point}: "
                        f"{err.read_text()}")
        if time.monotonic() > deadline:
            stop(p)
            pytest.fail(f"{argv[0]} did not reach {point} in {HANG_S} s")
        time.sleep(0.02)
    p.info = json.loads(marker.read_text())
    assert p.info["pid"] == p.pid and p.info["point"] == point
    return p


def stop(p: subprocess.Popen, sig=signal.SIGKILL) -> subprocess.Popen:
    """Send ``sig`` to the command's main process, wait for it, then for its process group to
    empty (``p.leftover``: what was still there after :data:`HANG_S`, then killed)."""
    p.send_signal(sig)
    p.wait(timeout=HANG_S)
    p.stderr_text = p.err.read_text()
    deadline = time.monotonic() + HANG_S
    while group(p.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    p.leftover = group(p.pid)
    for pid in p.leftover:
        os.kill(pid, signal.SIGKILL)
    return p


def killed(p: subprocess.Popen) -> subprocess.Popen:
    """SIGKILL at the point: the command died there (it did not end by itself)."""
    stop(p)
    assert p.returncode == -signal.SIGKILL, p.stderr_text
    assert p.leftover == [], "processes of the command outlived its SIGKILL"
    return p


def with_workers(p: subprocess.Popen, jobs: int) -> subprocess.Popen:
    """At ``runs`` or ``stored``: the workers are there (so that their end is tested)."""
    assert len(group(p.pid)) >= 1 + jobs, group(p.pid)
    return p


# ----------------------------------------------------------------------------- run --out


@pytest.fixture
def listing_made():
    """The listing's made code kept in the session's cache folder beforehand: a first run
    writes it (through the same writer, so the first passage at a point of the writer would
    be that entry's, not --out's, when these tests run first)."""
    run_ok(["run", "decks/steel40.dat"])


def test_run_out_killed_inside_the_write_leaves_old_or_new(tmp_path, listing_made):
    folder = tmp_path / "out"
    folder.mkdir()
    out = folder / "steel40.txt"
    argv = ["run", "decks/steel40.dat", "--out", str(out)]
    old = b"the previous run\n" * 50

    # killed just after the rename: the new file, whole; no temporary left
    out.write_bytes(old)
    p = killed(pause_at(tmp_path, "renamed", argv))
    assert Path(p.info["dst"]) == out
    assert sorted(os.listdir(folder)) == ["steel40.txt"] and out.read_bytes() == GOLDEN

    # killed with the new text written and fsynced in its temporary, before the rename: the
    # old file intact beside the whole new text (so the kill landed inside the write)
    out.write_bytes(old)
    p = killed(pause_at(tmp_path, "file-staged", argv))
    tmp = Path(p.info["temporary"])
    assert tmp.parent == folder and tmp.name.startswith(".steel40.txt.~")
    assert sorted(os.listdir(folder)) == sorted([tmp.name, "steel40.txt"])
    assert out.read_bytes() == old and tmp.read_bytes() == GOLDEN

    run_ok(argv)  # a later run into the same folder removes what the killed one left
    assert sorted(os.listdir(folder)) == ["steel40.txt"] and out.read_bytes() == GOLDEN


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_run_out_interrupted_leaves_no_temporary(tmp_path, sig, code, listing_made):
    folder = tmp_path / "out"
    folder.mkdir()
    out = folder / "steel40.txt"
    argv = ["run", "decks/steel40.dat", "--out", str(out)]

    # the signal while the new text waits in its temporary: the status, the temporary
    # removed, the old file kept
    out.write_bytes(b"old")
    p = stop(pause_at(tmp_path, "file-staged", argv), sig)
    assert Path(p.info["temporary"]).parent == folder
    assert p.returncode == code, p.stderr_text
    assert "Traceback" not in p.stderr_text and p.leftover == []
    assert sorted(os.listdir(folder)) == ["steel40.txt"] and out.read_bytes() == b"old"

    # the signal inside the commit, just before the rename: it is held until the rename is
    # done, so the new file is whole, then the status; no temporary
    p = stop(pause_at(tmp_path, "renaming", argv), sig)
    assert Path(p.info["dst"]) == out and Path(p.info["src"]).parent == folder
    assert p.returncode == code, p.stderr_text
    assert "Traceback" not in p.stderr_text and p.leftover == []
    assert sorted(os.listdir(folder)) == ["steel40.txt"] and out.read_bytes() == GOLDEN


# ----------------------------------------------------------------------------- plot


@pytest.mark.slow_corpus
def test_plot_killed_inside_the_commit_leaves_each_file_whole(tmp_path):
    """The picture and the animation: killed with both staged, both old; killed between their
    two renames (the window the files module names), each file whole: the picture new, the
    animation old."""
    folder = tmp_path / "out"
    folder.mkdir()
    png, gif = folder / "fall.png", folder / "fall.gif"
    argv = ["plot", "decks/steel40.dat", "--out", str(png), "--animate", str(gif)]
    old = {"fall.gif": b"old gif", "fall.png": b"old png"}

    def put_old():
        for name, data in old.items():
            (folder / name).write_bytes(data)

    put_old()
    p = killed(pause_at(tmp_path, "set-staged", argv))
    assert [Path(t) for t in p.info["targets"]] == [png, gif]
    staged = [Path(s) for s in p.info["staged"]]
    assert [s.parent for s in staged] == [folder, folder]
    assert staged[0].name.startswith(".fall.png.~") and staged[1].name.startswith(".fall.gif.~")
    assert visible(folder) == old
    staged_bytes = [s.read_bytes() for s in staged]

    put_old()
    p = killed(pause_at(tmp_path, "renamed", argv))
    assert Path(p.info["dst"]) == png  # the first of the two renames done, not the second
    mixed = visible(folder)
    assert mixed["fall.gif"] == old["fall.gif"]

    run_ok(argv)  # a later run: removes every temporary the killed ones left
    assert sorted(os.listdir(folder)) == ["fall.gif", "fall.png"]
    new = visible(folder)
    assert mixed["fall.png"] == new["fall.png"]  # the renamed picture was the new one, whole
    assert staged_bytes == [new["fall.png"], new["fall.gif"]]  # the staged files were whole


# ----------------------------------------------------------------------------- studies


STABILITY_OLD = {"stability_study.csv": b"old,csv\n", "README.md": b"# old\n",
                 "stability_map.png": b"old", "extreme_scenes.png": b"old"}


def _whole_new(name: str, data: bytes, ref: Path) -> None:
    """``data`` is a whole file ``name`` of a study, as in the reference folder ``ref``: a PNG
    that decodes to the reference's size; a CSV or a report ending in a newline, with as many
    lines, the report with the same last line, the CSV with the same first column (run times
    and dates differ)."""
    from PIL import Image

    if name.endswith(".png"):
        with Image.open(io.BytesIO(data)) as im, Image.open(ref / name) as im_ref:
            im.load()
            assert im.size == im_ref.size, name
        return
    want = (ref / name).read_bytes()
    lines, ref_lines = data.decode().splitlines(), want.decode().splitlines()
    assert data.endswith(b"\n") and len(lines) == len(ref_lines), name
    if name.endswith(".csv"):
        assert [x.split(",")[0] for x in lines] == [x.split(",")[0] for x in ref_lines], name
    else:
        assert lines[-1] == ref_lines[-1], name


@pytest.mark.slow_corpus
def test_study_killed_while_it_writes_leaves_each_file_whole(tmp_path):
    out, fresh = tmp_path / "out", tmp_path / "fresh"
    argv = ["study", "stability", "--quick", "--jobs", "2", "--out"]

    def put_old():
        out.mkdir(exist_ok=True)
        for name, data in STABILITY_OLD.items():
            (out / name).write_bytes(data)

    # killed in the runs: the workers end with it; the old files intact, nothing staged yet
    # (the runs that finished are in the study's scene store, kept for --resume)
    put_old()
    killed(with_workers(pause_at(tmp_path, "runs", argv + [str(out)]), 2))
    assert visible(out) == STABILITY_OLD and hidden(out) == [STORE]

    # killed with the four files staged (in a hidden folder inside the study's), none renamed:
    # the old files intact
    put_old()
    p = killed(pause_at(tmp_path, "set-staged", argv + [str(out)]))
    stage = Path(p.info["staged"][0]).parent
    assert stage.parent == out and hidden(out) == sorted([STORE, stage.name])
    assert sorted(Path(t).name for t in p.info["targets"]) == sorted(STABILITY_OLD)
    assert sorted(os.listdir(stage)) == sorted(STABILITY_OLD)
    assert visible(out) == STABILITY_OLD
    order = [Path(t).name for t in p.info["targets"]]  # the order of the renames

    # killed between the second and the third of the four renames: each file whole, the first
    # two new, the other two old
    put_old()
    p = killed(pause_at(tmp_path, "renamed", argv + [str(out)], nth=2))
    assert Path(p.info["dst"]) == out / order[1]
    mixed = visible(out)
    assert sorted(mixed) == sorted(STABILITY_OLD)
    assert {n: mixed[n] for n in order[2:]} == {n: STABILITY_OLD[n] for n in order[2:]}

    # a new folder, killed with its files staged: the folder holds the scene store (made
    # before the runs, for --resume) and the complete staging folder, and no file
    p = killed(pause_at(tmp_path, "set-staged", argv + [str(fresh)]))
    stage = Path(p.info["staged"][0]).parent
    assert stage.parent == fresh and visible(fresh) == {}
    assert hidden(fresh) == sorted([STORE, stage.name])
    staged_new = visible(stage)
    assert sorted(staged_new) == sorted(STABILITY_OLD)

    # later writers remove what the SIGKILLs left: a run into the study's folder, and a
    # writer of a new folder beside the one that never appeared
    run_ok(argv + [str(out)])
    assert hidden(out) == [STORE]
    for name in order[:2]:  # the renamed files were the new ones, whole
        _whole_new(name, mixed[name], out)
    for name, data in staged_new.items():  # the new folder was staged complete
        _whole_new(name, data, out)
    from deck_emulator.files import OutputSet

    with OutputSet(directory=tmp_path / "later") as later:  # a new folder beside the other
        later.write("x", "x")
    assert hidden(tmp_path) == []


@pytest.mark.slow_corpus
def test_study_interrupted_leaves_no_temporary_and_no_worker(tmp_path):
    """SIGINT and SIGTERM in the runs (the workers busy) and with the files staged: the
    status, no worker, no staging folder, no file; only the scene store, kept for --resume."""
    new = tmp_path / "work" / "new"
    new.parent.mkdir()
    study = ["study", "error", "decks/steel40.dat", "--quick", "--jobs", "2", "--out", str(new)]
    for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
        p = stop(with_workers(pause_at(tmp_path, "runs", study), 2), sig)
        assert p.returncode == code, p.stderr_text
        assert p.leftover == [], "worker processes outlived the interrupted study"
        assert "Traceback" not in p.stderr_text
        assert sorted(os.listdir(new)) == [STORE]

        p = pause_at(tmp_path, "set-staged", study)
        stage = Path(p.info["staged"][0]).parent
        assert stage.parent == new and sorted(os.listdir(new)) == sorted([STORE, stage.name])
        stop(p, sig)
        assert p.returncode == code, p.stderr_text
        assert p.leftover == [] and "Traceback" not in p.stderr_text
        assert sorted(os.listdir(new)) == [STORE]  # no staging, no file


# ----------------------------------------------------------------------------- sweep


SWEEP = ["sweep", "--speeds", "20,30,40", "--angles", "0,15", "--erratum", "ed-direction",
         "--jobs", "2", "--quiet"]
SWEEP_OLD = {"sweep.csv": b"old,csv\n", "sweep.md": b"# old\n"}


def _rows(csv_bytes: bytes) -> list[dict]:
    import csv

    rows = list(csv.DictReader(io.StringIO(csv_bytes.decode())))
    for r in rows:
        r.pop("run_s")
    return rows


def test_sweep_killed_while_it_writes_leaves_each_file_whole(tmp_path):
    out = tmp_path / "out"
    argv = SWEEP + ["--out", str(out)]

    def put_old():
        out.mkdir(exist_ok=True)
        for name, data in SWEEP_OLD.items():
            (out / name).write_bytes(data)

    # killed in the runs: the workers end with it, the old pair intact
    put_old()
    killed(with_workers(pause_at(tmp_path, "runs", argv), 2))
    assert visible(out) == SWEEP_OLD and hidden(out) == [".scenes"]

    # killed with the pair staged: both old, both new ones staged in a hidden folder
    put_old()
    p = killed(pause_at(tmp_path, "set-staged", argv))
    stage = Path(p.info["staged"][0]).parent
    assert [Path(t) for t in p.info["targets"]] == [out / "sweep.csv", out / "sweep.md"]
    assert stage.parent == out and hidden(out) == sorted([".scenes", stage.name])
    assert sorted(os.listdir(stage)) == ["sweep.csv", "sweep.md"]
    assert visible(out) == SWEEP_OLD

    # killed between the two renames: each file whole, the table new, the report old
    put_old()
    p = killed(pause_at(tmp_path, "renamed", argv))
    assert Path(p.info["dst"]) == out / "sweep.csv"
    mixed = visible(out)
    assert mixed["sweep.md"] == SWEEP_OLD["sweep.md"]

    run_ok(argv)  # a later run removes the staging folders the SIGKILLs left
    assert hidden(out) == [".scenes"] and sorted(visible(out)) == ["sweep.csv", "sweep.md"]
    assert _rows(mixed["sweep.csv"]) == _rows((out / "sweep.csv").read_bytes())
    assert len(_rows(mixed["sweep.csv"])) == 6


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_sweep_interrupted_leaves_no_temporary_and_no_worker(tmp_path, sig, code):
    """In the runs (the workers busy) and with the pair staged: the status, no worker, no
    table, no temporary: only the scene store, kept for --resume."""
    out = tmp_path / "new"
    argv = SWEEP + ["--out", str(out)]
    for point in ("runs", "set-staged"):
        p = pause_at(tmp_path, point, argv)
        if point == "runs":
            with_workers(p, 2)
        else:
            assert hidden(out) == sorted([".scenes", Path(p.info["staged"][0]).parent.name])
        stop(p, sig)
        assert p.returncode == code, p.stderr_text
        assert p.leftover == [], "sweep workers outlived the interrupted command"
        assert "Traceback" not in p.stderr_text
        assert sorted(os.listdir(out)) == [".scenes"]
        assert hidden(tmp_path) == []


def test_sweep_killed_then_resumed_runs_each_scene_once(tmp_path):
    """SIGKILL of the whole sweep once its first batch of scenes is stored (the others still
    running on the workers), then --resume: the stored scenes are kept as they were (no file
    changed), only the missing ones run, and the table has every scene once."""
    import csv

    from deck_emulator.studies.store import SceneStore

    argv = ["sweep", "--speeds", "20:45:5", "--angles", "0,15", "--erratum", "ed-direction",
            "--jobs", "2", "--quiet", "--out", str(tmp_path / "out")]
    p = killed(with_workers(pause_at(tmp_path, "stored", argv), 2))
    store = SceneStore(tmp_path / "out" / ".scenes")
    assert [str(f) for f in store.files()] == [p.info["batch"]]
    files = {f.name: sha(f) for f in store.files()}
    first = [r["scene_id"] for r in store.rows()]
    assert len(first) == p.info["rows"] and 1 <= len(first) < 12

    done = subprocess.run(CLI + argv + ["--resume"], cwd=ROOT, env=env(), capture_output=True,
                          text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    after = {f.name: sha(f) for f in store.files()}
    assert all(after[name] == h for name, h in files.items())  # nothing stored was rewritten
    ids = [r["scene_id"] for r in store.rows()]
    assert len(ids) == 12 and len(set(ids)) == 12 and all(ids.count(f) == 1 for f in first)
    # the others ran once each, the stored ones not again
    rows = list(csv.DictReader(io.StringIO((tmp_path / "out" / "sweep.csv").read_text())))
    scenes = [(float(r["speed_mph"]), float(r["angle_deg"])) for r in rows]
    assert sorted(scenes) == sorted({(s, a) for s in range(20, 50, 5) for a in (0, 15)})
    assert all(r["error"] == "" and r["hit"] for r in rows)
