"""The second fault campaign's items (issue 44), each ending with exit 0, 2 or 3 (or 130 / 143
for a signal) in one line, within 10 s, nothing left behind:

* a Ctrl-C to a sweep's process group while its worker pool's server starts: no
  ``KeyboardInterrupt`` traceback of the server's (it starts with SIGINT ignored);
* a SIGINT or SIGTERM while a library's compiled code runs (scipy's, as SALib builds a Sobol'
  sample) is held to the end of that code (``signals.held``), never raised inside it;
* ``run --pages`` under a small address space: refused or failed in one line, no ``.part``;
* under any ``ulimit -v``, an I/O error is said as what it is, not as a library that could
  not load;
* a command killed with SIGKILL leaves multiprocessing's ``pymp-*`` folder in a folder of its
  own, which the next command removes.

Process-level: marked ``slow``, as the suite does (the README's test command runs them)."""

from __future__ import annotations

import errno
import os
import resource
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from procs import group, sigint_as_on_a_terminal

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src"
BOUND_S = 10  # what each item must end within (the bound), not a speed measure
HANG_S = 300  # the longest wait for a command under test: a guard against a hang


@pytest.fixture
def tmp_path(tmp_path_factory):
    """A short folder (a Unix socket's path in a temporary folder below it must stay within
    108 bytes; pytest's own are long), removed after the test."""
    import shutil
    import tempfile

    folder = Path(tempfile.mkdtemp(prefix="de-"))
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


def _env(tmp_path: Path, **extra) -> dict:
    return dict(os.environ, PYTHONPATH=str(SRC), TMPDIR=str(tmp_path / "tmp"), **extra)


def _errors(err: str) -> list[str]:
    """stderr's lines but the notes a command prints as it starts (its arithmetic)."""
    return [line for line in err.splitlines() if "arithmetic" not in line]


# ------------------------------------------------------------------------- I/O under a limit


def test_an_io_error_is_not_a_library_that_could_not_load():
    """cli hands an OSError to the out-of-memory wording only for ENOMEM or a loader's error
    (no errno), never for a full disk, a closed pipe or a missing file."""
    from deck_emulator.cli import _could_not_load
    from deck_emulator.files import OutputError

    assert _could_not_load(OSError(errno.ENOMEM, "Cannot allocate memory"))
    assert _could_not_load(OSError("libx.so: failed to map segment from shared object"))
    for code in (errno.ENOSPC, errno.EPIPE, errno.EIO, errno.ENOENT, errno.EACCES):
        assert not _could_not_load(OSError(code, os.strerror(code)))
    assert not _could_not_load(OutputError("x.txt", "no space left", errno.ENOSPC))
    assert not _could_not_load(OutputError("x.txt", "whatever"))


def _limited(mb: int):
    def preexec():
        resource.setrlimit(resource.RLIMIT_AS, (mb << 20, mb << 20))
    return preexec


@pytest.mark.slow
@pytest.mark.parametrize("limit_mb", [None, 1000])
def test_run_to_a_full_disk_says_so_under_any_limit(tmp_path, limit_mb):
    """deck-emulator run steel40 > /dev/full (under ulimit -v or not): exit 2, one line that
    names standard output and the full disk."""
    (tmp_path / "tmp").mkdir()
    with open("/dev/full", "wb") as full:
        p = subprocess.run([sys.executable, "-m", "deck_emulator", "run", "steel40"],
                           stdout=full, stderr=subprocess.PIPE, text=True, env=_env(tmp_path),
                           timeout=HANG_S, preexec_fn=_limited(limit_mb) if limit_mb else None)
    assert p.returncode == 2, p.stderr
    assert _errors(p.stderr) == ["deck-emulator: error: cannot write standard output: "
                                 f"{os.strerror(errno.ENOSPC)}"]


# --------------------------------------------------------------------- --pages under a limit


@pytest.mark.slow
@pytest.mark.parametrize("limit_mb", [100, 150, 200])
def test_run_pages_under_a_small_address_space_ends_in_one_line(tmp_path, limit_mb):
    (tmp_path / "tmp").mkdir()
    started = time.monotonic()
    p = subprocess.run([sys.executable, "-m", "deck_emulator", "run", "steel40", "--pages",
                        str(tmp_path / "p.pdf"), "--quiet"], cwd=tmp_path,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                       env=_env(tmp_path), timeout=HANG_S, preexec_fn=_limited(limit_mb))
    took = time.monotonic() - started
    assert p.returncode in (0, 2, 3), p.stderr
    lines = _errors(p.stderr)
    if p.returncode:
        assert len(lines) == 1 and lines[0].startswith("deck-emulator: error: "), p.stderr
        assert took < BOUND_S, took
    assert "OpenBLAS" not in p.stderr and "Traceback" not in p.stderr
    left = sorted(x.name for x in tmp_path.iterdir() if x.name != "tmp")
    assert left == (["p.pdf"] if p.returncode == 0 else []), left


# ------------------------------------------------------------------ signals held in a block

HELD = textwrap.dedent(
    """
    import os, signal, sys, time
    from deck_emulator import signals

    def command():
        with signals.held():
            try:
                os.kill(os.getpid(), signal.{sig})
                for _ in range(50):
                    time.sleep(0.01)  # (where the signal would have been raised)
            except BaseException as exc:
                print("raised inside", type(exc).__name__, flush=True)
                raise
            print("the block ran to its end", flush=True)
        print("after the block", flush=True)
        return 0

    sys.exit(signals.run(command))
    """
)


@pytest.mark.slow
@pytest.mark.parametrize("sig, code, said", [("SIGINT", 130, "interrupted"),
                                              ("SIGTERM", 143, "terminated by SIGTERM")])
def test_a_signal_in_a_held_block_is_raised_as_it_ends(tmp_path, sig, code, said):
    script = tmp_path / "held.py"
    script.write_text(HELD.format(sig=sig))
    p = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                       env=_env(tmp_path), timeout=HANG_S, preexec_fn=sigint_as_on_a_terminal)
    assert p.returncode == code, p.stderr
    assert p.stdout.splitlines() == ["the block ran to its end"]
    assert p.stderr.splitlines() == [f"deck-emulator: {said}"]


#: The command line with SALib's Sobol' sample sending ``SIG`` to its process group from
#: inside (test code: as a Ctrl-C or a SIGTERM would arrive while scipy builds it).
IN_SAMPLE = textwrap.dedent(
    """
    import os, signal, sys
    from SALib.sample import sobol

    original = sobol.sample

    def sample(*args, **kwargs):
        os.killpg(0, getattr(signal, os.environ["SIG"]))
        return original(*args, **kwargs)

    sobol.sample = sample
    from deck_emulator.cli import main
    if __name__ == "__main__":  # (not in a worker, which imports this as its main module)
        sys.exit(main(sys.argv[1:]))
    """
)


@pytest.mark.slow
@pytest.mark.parametrize("sig, code", [("SIGINT", 130), ("SIGTERM", 143)])
def test_a_signal_while_the_sobol_sample_is_built_ends_the_study_in_one_line(tmp_path, sig,
                                                                            code):
    (tmp_path / "tmp").mkdir()
    script = tmp_path / "in_sample.py"
    script.write_text(IN_SAMPLE)
    p = subprocess.Popen([sys.executable, str(script), "sensitivity", "--quick", "--out",
                          str(tmp_path / "s")], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, env=_env(tmp_path, SIG=sig),
                         start_new_session=True, preexec_fn=sigint_as_on_a_terminal)
    _, err = p.communicate(timeout=HANG_S)
    assert p.returncode == code, err
    assert [line for line in err.splitlines() if not line.startswith("deck-emulator: sens")] \
        == ["deck-emulator: " + ("interrupted" if sig == "SIGINT" else "terminated by SIGTERM")]
    assert not (tmp_path / "s").exists() and not group(p.pid)


# ------------------------------------------------------------------- the worker pool's start

#: The command line with a Ctrl-C to its process group as soon as the worker pool's server
#: has either ignored SIGINT or installed the interpreter's handler for it (test code, reading
#: /proc): it lands while the server's interpreter starts, before its preload.
AT_SERVER_START = textwrap.dedent(
    """
    import os, signal, sys, time
    from deck_emulator.cli import main  # (first: as the command's own entry point does)
    from deck_emulator.studies import local_pool

    original = local_pool._start_server

    def sigint_set(pid):
        bit = 1 << (signal.SIGINT - 1)
        try:
            status = open(f"/proc/{pid}/status").read().splitlines()
        except OSError:
            return True
        masks = {l.split(":")[0]: int(l.split()[1], 16) for l in status
                 if l.startswith(("SigIgn", "SigCgt"))}
        return bool((masks["SigIgn"] | masks["SigCgt"]) & bit)

    def start_server():
        before = set(os.listdir("/proc"))
        original()
        server = [p for p in set(os.listdir("/proc")) - before if p.isdigit()
                  and b"forkserver" in open(f"/proc/{p}/cmdline", "rb").read()]
        deadline = time.monotonic() + 60
        while server and not sigint_set(server[0]) and time.monotonic() < deadline:
            time.sleep(0.001)
        os.killpg(0, signal.SIGINT)

    local_pool._start_server = start_server
    if __name__ == "__main__":  # (not in a worker, which imports this as its main module)
        sys.exit(main(sys.argv[1:]))
    """
)


@pytest.mark.slow
def test_a_ctrl_c_while_the_worker_pool_starts_prints_no_traceback(tmp_path):
    (tmp_path / "tmp").mkdir()
    script = tmp_path / "at_start.py"
    script.write_text(AT_SERVER_START)
    p = subprocess.Popen([sys.executable, str(script), "sweep", "--speeds", "20,40",
                          "--angles", "0", "--quiet", "--jobs", "2", "--out",
                          str(tmp_path / "sw")], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, env=_env(tmp_path),
                         start_new_session=True, preexec_fn=sigint_as_on_a_terminal)
    _, err = p.communicate(timeout=HANG_S)
    deadline = time.monotonic() + BOUND_S
    while group(p.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert p.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert err.splitlines()[-1] == "deck-emulator: interrupted"
    assert not group(p.pid)
    assert sorted(os.listdir(tmp_path / "tmp")) == []  # (its own temporary folder removed)


# ------------------------------------------------------------------ SIGKILL and pymp folders


@pytest.mark.slow
def test_a_killed_commands_multiprocessing_folder_is_removed_by_the_next(tmp_path):
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    own = tmp / f"deck_emulator-{os.getuid()}"
    argv = [sys.executable, "-m", "deck_emulator", "sweep", "--speeds", "20,40", "--angles",
            "0,15", "--quiet", "--jobs", "2"]
    p = subprocess.Popen([*argv, "--out", str(tmp_path / "a")], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, env=_env(tmp_path), start_new_session=True)
    deadline = time.monotonic() + HANG_S
    while not list(own.glob(f"{p.pid}/pymp-*")) and p.poll() is None:
        assert time.monotonic() < deadline, "no pool started"
        time.sleep(0.05)
    assert p.poll() is None, "the sweep ended before its pool was seen"
    os.killpg(p.pid, signal.SIGKILL)
    p.wait()
    time.sleep(0.5)
    # multiprocessing's pymp-* in the command's own folder, none beside it (the sweep's store,
    # sweep-*, is removed by a later sweep a minute on: distributed.temporary_store)
    assert [x.name for x in tmp.glob("pymp-*")] == []
    assert [x.name for x in own.iterdir()] == [str(p.pid)]
    q = subprocess.run([*argv[:5], "20", "--angles", "0", "--quiet", "--jobs", "2", "--out",
                        str(tmp_path / "b")], capture_output=True, text=True,
                       env=_env(tmp_path), timeout=HANG_S)
    assert q.returncode == 0, q.stderr
    assert not own.exists()  # the killed one's removed, and its own at its exit
    assert [x.name for x in tmp.glob("pymp-*")] == []
