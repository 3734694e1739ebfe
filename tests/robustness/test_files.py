"""The one writer: a file is written whole or not at all, and what is not ours (a
device, a FIFO, the file behind a link, other files of a folder) is never replaced."""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from procs import sigint_as_on_a_terminal

from deck_emulator.files import OutputError, OutputSet, check_output_dir, check_output_file, write_file

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src"
GOLDEN = (ROOT / "golden" / "steel40.r8.txt").read_bytes()


def env():
    e = dict(os.environ)
    e["PYTHONPATH"] = str(SRC) + os.pathsep + e.get("PYTHONPATH", "")
    return e


def leftovers(folder: Path) -> list[str]:
    """Temporary names of ours left in ``folder``."""
    return sorted(p.name for p in folder.iterdir() if ".~" in p.name)


def umask() -> int:
    m = os.umask(0o022)
    os.umask(m)
    return m


# ----------------------------------------------------------------------- regular files


def test_new_file_whole_with_open_permissions(tmp_path):
    write_file(tmp_path / "a.txt", "é\n")
    assert (tmp_path / "a.txt").read_bytes() == "é\n".encode()
    assert stat.S_IMODE(os.stat(tmp_path / "a.txt").st_mode) == 0o666 & ~umask()
    assert leftovers(tmp_path) == []


def test_existing_file_keeps_its_mode(tmp_path):
    p = tmp_path / "a.bin"
    p.write_bytes(b"old")
    os.chmod(p, 0o640)
    write_file(p, b"new")
    assert p.read_bytes() == b"new"
    assert stat.S_IMODE(os.stat(p).st_mode) == 0o640


def test_folder_as_target_is_refused(tmp_path):
    with pytest.raises(OutputError, match="is a folder|it is a folder"):
        write_file(tmp_path, "x")
    with pytest.raises(OutputError):
        check_output_file(tmp_path)
    assert tmp_path.is_dir()


def test_missing_folder_names_the_users_path(tmp_path):
    target = tmp_path / "missing" / "out.txt"
    with pytest.raises(OutputError) as err:
        check_output_file(target)
    assert str(target) in str(err.value) and ".~" not in str(err.value)
    with pytest.raises(OutputError) as err:
        write_file(target, "x")
    assert str(target) in str(err.value) and ".part" not in str(err.value)
    assert not (tmp_path / "missing").exists()


def test_stale_temporaries_of_dead_writers_are_removed(tmp_path):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = tmp_path / f".a.txt.~{dead.pid}.abc123.part"
    stale.write_text("half")
    mine = tmp_path / f".a.txt.~{os.getpid()}.abc123.part"  # a live writer's: kept
    mine.write_text("busy")
    other = tmp_path / ".a.txt.something"  # not our pattern: kept
    other.write_text("not ours")
    write_file(tmp_path / "a.txt", "x")
    assert not stale.exists() and mine.exists() and other.exists()


# ----------------------------------------------------------------------- special files


def test_dev_null_is_written_not_replaced():
    before = os.stat("/dev/null")
    check_output_file("/dev/null")
    write_file("/dev/null", "bytes\n")
    after = os.stat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and after.st_rdev == before.st_rdev


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this system")
def test_dev_full_fails_and_stays_a_device():
    with pytest.raises(OutputError) as err:
        write_file("/dev/full", "x" * 10)
    assert "/dev/full" in str(err.value) and ".part" not in str(err.value)
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode)


def _fifo_reader(path: Path, got: list):
    def read():
        with open(path, "rb") as fh:
            got.append(fh.read())

    t = threading.Thread(target=read, daemon=True)
    t.start()
    return t


def test_fifo_receives_the_bytes_and_stays_a_fifo(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    check_output_file(fifo)
    got: list = []
    t = _fifo_reader(fifo, got)
    write_file(fifo, b"through the pipe")
    t.join(10)
    assert got == [b"through the pipe"]
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)


def test_run_out_dev_null_and_fifo(tmp_path):
    """The command itself: ``run --out /dev/null`` and ``--out FIFO``."""
    cmd = [sys.executable, "-m", "deck_emulator", "run", "decks/steel40.dat", "--out"]
    before = os.stat("/dev/null")
    r = subprocess.run(cmd + ["/dev/null"], cwd=ROOT, env=env(), capture_output=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode) and os.stat("/dev/null").st_rdev == before.st_rdev
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got: list = []
    t = _fifo_reader(fifo, got)
    r = subprocess.run(cmd + [str(fifo)], cwd=ROOT, env=env(), capture_output=True, timeout=300)
    t.join(10)
    assert r.returncode == 0, r.stderr
    assert got == [GOLDEN]
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert leftovers(tmp_path) == []


# ----------------------------------------------------------------------- links


def test_symlink_is_written_through(tmp_path):
    real = tmp_path / "run-42.txt"
    real.write_text("old")
    os.chmod(real, 0o600)
    link = tmp_path / "latest.txt"
    link.symlink_to(real.name)
    check_output_file(link)
    write_file(link, "new")
    assert link.is_symlink() and os.readlink(link) == real.name
    assert real.read_text() == "new"
    assert stat.S_IMODE(os.stat(real).st_mode) == 0o600
    assert leftovers(tmp_path) == []


def test_symlink_in_another_folder_is_written_there(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    real = tmp_path / "b" / "x.txt"
    real.write_text("old")
    (tmp_path / "a" / "x.txt").symlink_to(real)
    with OutputSet() as out:
        out.write(tmp_path / "a" / "x.txt", "new")
    assert (tmp_path / "a" / "x.txt").is_symlink() and real.read_text() == "new"
    assert leftovers(tmp_path / "a") == [] and leftovers(tmp_path / "b") == []


# ----------------------------------------------------------------------- read-only folders


RO_CHECK = """
import sys
from pathlib import Path
from deck_emulator.files import OutputError, OutputSet, check_output_dir, check_output_file, write_file
ro = Path(sys.argv[1])
for call in (lambda: check_output_file(ro / "x.txt"), lambda: check_output_dir(ro),
             lambda: check_output_dir(ro / "new"), lambda: write_file(ro / "old.txt", "new"),
             lambda: OutputSet(directory=ro / "new").__enter__(),
             lambda: OutputSet().path(ro / "x.png")):
    try:
        call()
        print("no error")
    except OutputError as exc:
        print(exc)
    except RuntimeError as exc:
        print(exc)
"""


def _read_only_mount(ro: Path, argv: list[str]) -> subprocess.CompletedProcess:
    """Run ``argv`` with ``ro`` bind-mounted read-only in a private mount namespace (so that
    even root cannot write there, and nothing outlives the child)."""
    import shlex
    import shutil

    if os.geteuid() != 0 or not shutil.which("unshare"):
        pytest.skip("needs root and unshare(1) for a private read-only bind mount")
    script = (f"mount --bind {shlex.quote(str(ro))} {shlex.quote(str(ro))} && "
              f"mount -o remount,bind,ro {shlex.quote(str(ro))} && exec {shlex.join(argv)}")
    probe = subprocess.run(["unshare", "-m", "sh", "-c", f"mount --bind {shlex.quote(str(ro))} "
                            f"{shlex.quote(str(ro))} && mount -o remount,bind,ro {shlex.quote(str(ro))}"],
                           capture_output=True, text=True)
    if probe.returncode:
        pytest.skip(f"this machine does not allow a read-only bind mount: {probe.stderr.strip()}")
    return subprocess.run(["unshare", "-m", "sh", "-c", script], env=env(), capture_output=True,
                          text=True, timeout=300, cwd=ROOT)


def test_read_only_folder_fails_before_any_work(tmp_path):
    """As root a folder of mode 0555 is still writable, so the folder is a read-only bind
    mount (EROFS, which access(2) reports even for root), private to a child process."""
    ro = tmp_path / "ro"
    ro.mkdir()
    (ro / "old.txt").write_text("old")
    r = _read_only_mount(ro, [sys.executable, "-c", RO_CHECK, str(ro)])
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert len(lines) == 6, lines
    for line in lines[:5]:
        assert line.startswith(f"cannot write {ro}") and ".~" not in line, line
    assert lines[5] == "OutputSet.path() outside its with block"  # a misuse, said as such
    assert (ro / "old.txt").read_text() == "old" and sorted(os.listdir(ro)) == ["old.txt"]


# The CLI with the points where the work starts replaced by a marker and an exit: the plot's
# engine run (EmulatorEngine.run, CoreEngine.run) and the studies' scene runner.
NO_ENGINE = """
import os, sys
from deck_emulator.engine import core_engine, engines
from deck_emulator.studies import distributed

def started(*args, **kwargs):
    print("ENGINE STARTED", flush=True)
    os._exit(99)

engines.EmulatorEngine.run = core_engine.CoreEngine.run = core_engine.CoreEngine.run_batch = started
distributed.run_scenes = started
from deck_emulator.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_commands_fail_on_a_read_only_folder_before_running(tmp_path):
    """``plot`` and ``study`` (ours) stop at once on a read-only folder: exit status 2, the
    user's path in one line, and the engine never starts: run with the engine replaced by a
    marker, the marker is absent (and present when the same command may write: the
    replacement is on the command's way)."""
    ro, rw = tmp_path / "ro", tmp_path / "rw"
    ro.mkdir()
    rw.mkdir()
    m = [sys.executable, "-c", NO_ENGINE]
    for args in (lambda d: ["plot", "decks/steel40.dat", "--out", str(d / "p.png")],
                 lambda d: ["study", "error", "decks/steel40.dat", "--quick", "--jobs", "1",
                            "--out", str(d / "s")],
                 lambda d: ["study", "stability", "--quick", "--jobs", "1", "--out", str(d)]):
        r = subprocess.run(m + args(rw), env=env(), capture_output=True, text=True,
                           timeout=300, cwd=ROOT)
        assert (r.returncode, r.stdout) == (99, "ENGINE STARTED\n"), (args(rw), r.stderr)
        r = _read_only_mount(ro, m + args(ro))
        assert "ENGINE STARTED" not in r.stdout, (args(ro), r.stderr)
        assert r.returncode == 2, (args(ro), r.stderr)
        assert r.stderr.count("\n") == 1 and f"cannot write {ro}" in r.stderr, r.stderr
    assert sorted(os.listdir(ro)) == [] and sorted(os.listdir(rw)) == []


def test_plot_checks_its_outputs_before_the_run(tmp_path, monkeypatch):
    from deck_emulator.cli import main
    from deck_emulator.present import plot

    def no_run(*a, **k):
        raise AssertionError("the engine ran before the output was checked")

    monkeypatch.setattr(plot, "engine_for", no_run)
    assert main(["plot", "decks/steel40.dat", "--out", str(tmp_path / "p.png"),
                 "--animate", str(tmp_path / "missing" / "a.gif")]) == 2
    assert main(["plot", "decks/steel40.dat", "--out", str(tmp_path / "p.png"),
                 "--animate", str(tmp_path / "a.png")]) == 2
    assert sorted(os.listdir(tmp_path)) == []


def test_studies_check_their_folder_before_the_runs(tmp_path, monkeypatch):
    from deck_emulator.studies import error, stability

    def no_run(*a, **k):
        raise AssertionError("runs started before the folder was checked")

    monkeypatch.setattr(error, "run_longest_first", no_run)
    monkeypatch.setattr(stability, "run_longest_first", no_run)
    (tmp_path / "file").write_text("x")
    for out in (tmp_path / "missing" / "out", tmp_path / "file"):
        with pytest.raises(OutputError):
            error.error_study(ROOT / "decks" / "steel40.dat", out, quick=True, jobs=1)
        with pytest.raises(OutputError):
            stability.stability_study(out, quick=True, jobs=1)
    assert sorted(os.listdir(tmp_path)) == ["file"]


# ----------------------------------------------------------------------- sets of files


def test_set_commits_together_and_keeps_suffixes(tmp_path):
    (tmp_path / "b.gif").write_bytes(b"old gif")
    with OutputSet() as out:
        p = out.path(tmp_path / "a.png")
        assert p.suffix == ".png" and p.parent == tmp_path
        p.write_bytes(b"png")
        out.write(tmp_path / "b.gif", b"gif")
        assert not (tmp_path / "a.png").exists() and (tmp_path / "b.gif").read_bytes() == b"old gif"
    assert (tmp_path / "a.png").read_bytes() == b"png" and (tmp_path / "b.gif").read_bytes() == b"gif"
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("exc", [RuntimeError, KeyboardInterrupt])
def test_set_moves_nothing_on_an_exception(tmp_path, exc):
    (tmp_path / "a.png").write_bytes(b"old")
    with pytest.raises(exc):
        with OutputSet() as out:
            out.write(tmp_path / "a.png", b"new")
            out.write(tmp_path / "b.gif", b"new")
            raise exc()
    assert (tmp_path / "a.png").read_bytes() == b"old" and not (tmp_path / "b.gif").exists()
    assert leftovers(tmp_path) == []


def test_set_with_a_staged_file_never_written_fails_whole(tmp_path):
    (tmp_path / "a.txt").write_text("old")
    with pytest.raises(OutputError, match="nothing was written"):
        with OutputSet() as out:
            out.write(tmp_path / "a.txt", "new")
            out.path(tmp_path / "b.png").unlink()  # a library that failed to write
    assert (tmp_path / "a.txt").read_text() == "old" and leftovers(tmp_path) == []


def test_new_directory_appears_only_with_its_contents(tmp_path):
    d = tmp_path / "study"
    with pytest.raises(KeyboardInterrupt):
        with OutputSet(directory=d) as out:
            out.write("a.csv", "1\n")
            assert not d.exists()
            raise KeyboardInterrupt
    assert sorted(os.listdir(tmp_path)) == []
    with OutputSet(directory=d) as out:
        out.write("a.csv", "1\n")
        out.path("fig/b.png").write_bytes(b"png")
        assert not d.exists()
    assert sorted(os.listdir(tmp_path)) == ["study"]
    assert (d / "a.csv").read_text() == "1\n" and (d / "fig" / "b.png").read_bytes() == b"png"
    assert stat.S_IMODE(os.stat(d).st_mode) == 0o777 & ~umask()


def test_existing_directory_keeps_other_files(tmp_path):
    (tmp_path / "a.csv").write_text("old")
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(RuntimeError):
        with OutputSet(directory=tmp_path) as out:
            out.write("a.csv", "new")
            out.write("README.md", "new")
            raise RuntimeError
    assert sorted(os.listdir(tmp_path)) == ["a.csv", "notes.txt"]
    assert (tmp_path / "a.csv").read_text() == "old"
    with OutputSet(directory=tmp_path) as out:
        out.write("a.csv", "new")
        out.write(tmp_path / "README.md", "new")  # absolute inside the folder is fine
        with pytest.raises(ValueError):
            out.path("../escape.txt")
    assert sorted(os.listdir(tmp_path)) == ["README.md", "a.csv", "notes.txt"]
    assert (tmp_path / "notes.txt").read_text() == "mine" and (tmp_path / "a.csv").read_text() == "new"


def test_set_into_a_device(tmp_path):
    with OutputSet() as out:
        out.write("/dev/null", "x")
        out.write(tmp_path / "a.txt", "y")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode) and (tmp_path / "a.txt").read_text() == "y"


# ----------------------------------------------------------------------- signals


SIGNALLED = """
import sys, time
from pathlib import Path
from deck_emulator import signals
from deck_emulator.files import OutputSet

def main():
    d = Path(sys.argv[1])
    with OutputSet() as out:
        out.write(d / "a.txt", "new")
        with OutputSet(directory=d / "new") as inner:
            inner.write("b.txt", "new")
            print("ready", flush=True)
            time.sleep(60)
    return 0

sys.exit(signals.run(main))
"""


HELD = """
import signal, sys, threading, time
from deck_emulator import signals

# a second thread, which does not hold the signals: the kernel may give a signal to it
threading.Thread(target=time.sleep, args=(600,), daemon=True).start()
CATCHABLE = {signal.SIGINT, signal.SIGTERM}


def main():
    with signals.held():
        seen, handlers = [], {s: signal.getsignal(s) for s in CATCHABLE}
        for s, h in handlers.items():  # note when the signal reaches its handler
            signal.signal(s, lambda n, f, h=h: (seen.append(n), h(n, f)))
        print("ready", flush=True)
        while not (seen or CATCHABLE & signal.sigpending()):
            time.sleep(0.01)
        for s, h in handlers.items():
            signal.signal(s, h)
        print("the window ran to its end", flush=True)
    print("not reached: the signal is raised as the window ends", flush=True)
    return 0

sys.exit(signals.run(main))
"""


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signal_is_held_over_a_commit_in_a_process_with_threads(sig, code):
    """A SIGINT/SIGTERM that arrives inside a commit's window is delivered as the window ends,
    even when the process has another thread (numpy's OpenBLAS starts some): the window runs
    to its end, then the status."""
    p = subprocess.Popen([sys.executable, "-c", HELD], env=env(), stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, preexec_fn=sigint_as_on_a_terminal)
    assert p.stdout.readline() == "ready\n"
    p.send_signal(sig)
    out, err = p.communicate(timeout=300)
    assert out == "the window ran to its end\n", err
    assert p.returncode == code, err


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signal_removes_temporaries_and_sets_the_status(tmp_path, sig, code):
    (tmp_path / "a.txt").write_text("old")
    p = subprocess.Popen([sys.executable, "-c", SIGNALLED, str(tmp_path)], env=env(),
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=sigint_as_on_a_terminal)
    assert p.stdout.readline() == "ready\n"
    assert leftovers(tmp_path)  # the staged files exist while it runs
    p.send_signal(sig)
    out, err = p.communicate(timeout=30)
    assert p.returncode == code, err
    assert "Traceback" not in err
    assert sorted(os.listdir(tmp_path)) == ["a.txt"] and (tmp_path / "a.txt").read_text() == "old"


def test_an_empty_path_is_refused_not_taken_for_the_current_folder(tmp_path, monkeypatch):
    from deck_emulator.files import OutputError, check_output_file

    monkeypatch.chdir(tmp_path)
    for check in (check_output_dir, check_output_file):
        with pytest.raises(OutputError, match="empty path"):
            check("")
    assert list(tmp_path.iterdir()) == []
