"""A Ctrl-C while the embedded Dask cluster starts (3 of 65 such sweeps once hung, the main
process asleep for ever after "Exception ignored in GCDiagnosis._gc_callback ...
KeyboardInterrupt"; an interrupted start also printed Dask's "AssertionError: Status.init" from
its exit hook).  SIGINT goes to the whole process group, as a terminal sends it, at moments
spread over the cluster's start; each sweep must end (130; or 0, or killed by the SIGINT
itself, when it had finished first) within a bound far above its run time, with none of those
messages, and leave no process.

Not asserted: that no worker prints a KeyboardInterrupt traceback.  A spawned worker ignores
SIGINT from its first import of the package (deck_emulator/__init__.py), but a Ctrl-C in the
few milliseconds before, while its interpreter starts, still reaches it (1 of 16 such
Ctrl-Cs printed one; 4 of 16 before the package's early word)."""

from __future__ import annotations

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

SRC = Path(__file__).resolve().parents[2] / "src"
SWEEP = ["sweep", "--speeds", "20,40", "--angles", "0,15", "--erratum", "ed-direction",
         "--quiet", "--jobs", "2"]


def _interrupt_at(delay_s: float, out: Path) -> tuple[int | str, str]:
    env = dict(os.environ, PYTHONPATH=str(SRC))
    p = subprocess.Popen([sys.executable, "-m", "deck_emulator", *SWEEP, "--out", str(out)],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env,
                         start_new_session=True, preexec_fn=sigint_as_on_a_terminal)
    time.sleep(delay_s)
    try:
        os.killpg(p.pid, signal.SIGINT)
    except ProcessLookupError:
        pass
    try:
        _, err = p.communicate(timeout=90)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return "hung", ""
    deadline = time.monotonic() + 15  # the cluster's processes end as it closes
    while group(p.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not group(p.pid), f"processes left after a Ctrl-C at {delay_s} s"
    return p.returncode, err


def _check(delay_s: float, tmp_path: Path) -> None:
    status, err = _interrupt_at(delay_s, tmp_path / f"sw{delay_s}")
    assert status != "hung", f"a Ctrl-C at {delay_s} s: the sweep did not end in 90 s"
    # Where the Ctrl-C lands depends on the machine's speed, so every honest ending passes:
    # 130 (interrupted, said in one line), 0 (the sweep had finished), or death by SIGINT
    # itself (-2: it came after the command had returned, as the interpreter exited; a shell
    # reports 130).  What must never happen does not depend on the moment.
    assert status in (130, 0, -signal.SIGINT), (delay_s, status, err)
    assert "Exception ignored" not in err and "Status.init" not in err, err
    if status == 130:
        assert "deck-emulator: interrupted" in err


@pytest.mark.parametrize("delay_s", [0.4, 1.0, 1.8])
def test_a_ctrl_c_while_the_cluster_starts_ends_the_sweep(delay_s, tmp_path):
    _check(delay_s, tmp_path)


@pytest.mark.slow_corpus
@pytest.mark.parametrize("delay_s", [round(0.2 + 0.1 * k, 1) for k in range(30)])
def test_a_ctrl_c_at_every_moment_of_the_start(delay_s, tmp_path):
    _check(delay_s, tmp_path)
