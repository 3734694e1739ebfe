"""The one process-pool map (issue 17): results in order, and no worker outlives the map or
its parent, however the parent ends."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from procs import children, group

from deck_emulator.parallel import parallel_map

ROOT = Path(__file__).resolve().parent.parent


def env():
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + e.get("PYTHONPATH", "")
    return e


def _square(x):
    return x * x


def _fail_on_three(x):
    if x == 3:
        raise ValueError("three")
    time.sleep(0.05)
    return x






needs_proc = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")


def test_results_in_input_order():
    assert parallel_map(_square, range(12), jobs=2, desc="t") == [x * x for x in range(12)]
    assert parallel_map(_square, [3], jobs=4, desc="t") == [9]
    assert parallel_map(_square, [], jobs=2, desc="t") == []
    assert parallel_map(_square, range(5), jobs=1, desc="t") == [0, 1, 4, 9, 16]


@needs_proc
def test_a_worker_error_propagates_and_stops_the_workers():
    before = set(children(os.getpid()))  # e.g. multiprocessing's resource tracker of an
    # earlier test: not this pool's
    with pytest.raises(ValueError, match="three"):
        parallel_map(_fail_on_three, range(40), jobs=2, desc="t")
    assert set(children(os.getpid())) <= before


def test_no_progress_bar_unless_stderr_is_a_terminal(capsys):
    parallel_map(_square, range(4), jobs=2, desc="quietly")
    assert capsys.readouterr().err == ""


SLOW = """
import sys, time
from deck_emulator import parallel, signals

parallel._USE_PDEATHSIG = sys.argv[1] == "pdeathsig"

def slow(x):
    time.sleep(120)
    return x

def main():
    print("ready", flush=True)
    return len(parallel.parallel_map(slow, range(4), jobs=2, desc="slow"))

sys.exit(signals.run(main))
"""


def _start(mode: str):
    p = subprocess.Popen([sys.executable, "-c", SLOW, mode], env=env(), stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, start_new_session=True)
    assert p.stdout.readline() == "ready\n"
    deadline = time.monotonic() + 30
    while len(group(p.pid)) < 3:  # the main process and its two workers
        assert time.monotonic() < deadline, "the workers did not start"
        time.sleep(0.1)
    return p


def _wait_empty(pgid: int, seconds: float) -> list[int]:
    deadline = time.monotonic() + seconds
    while group(pgid) and time.monotonic() < deadline:
        time.sleep(0.1)
    return group(pgid)


@needs_proc
@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_to_the_main_process_stops_its_workers(sig, code):
    p = _start("pdeathsig")
    try:
        p.send_signal(sig)  # to the main process only, not the group: it must stop the workers
        p.wait(timeout=30)
        assert p.returncode == code, p.stderr.read()
        assert _wait_empty(p.pid, 2) == []
    finally:
        for pid in group(p.pid):
            os.kill(pid, signal.SIGKILL)


@needs_proc
@pytest.mark.parametrize("mode", ["pdeathsig", "poll"])
def test_workers_die_with_a_killed_parent(mode):
    """SIGKILL of the main process: no handler runs; the workers notice (prctl death signal,
    or the thread polling getppid() alone) and end within seconds."""
    p = _start(mode)
    try:
        os.kill(p.pid, signal.SIGKILL)
        p.wait(timeout=10)
        assert _wait_empty(p.pid, 5) == []
    finally:
        for pid in group(p.pid):
            os.kill(pid, signal.SIGKILL)
