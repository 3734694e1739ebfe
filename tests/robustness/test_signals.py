"""No signal swallowed: a SIGTERM or SIGINT whose exception Python drops (raised in
a ``__del__`` or a garbage-collector callback) is raised again shortly after, without Python's
"Exception ignored in ..." traceback, and a command that returns with a signal pending ends with its status."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from procs import sigint_as_on_a_terminal

SRC = Path(__file__).resolve().parents[2] / "src"

SCRIPT = textwrap.dedent(
    """
    import gc, os, signal, sys, time
    from deck_emulator import signals

    class Swallower:
        def __del__(self):
            # the signal arrives while Python runs a finaliser: its exception is dropped
            try:
                os.kill(os.getpid(), signal.{sig})
                for _ in range(1000):
                    sum(range(10))
            finally:
                print("raised in a finaliser", flush=True)

    def command(wait_s):
        Swallower()  # finalised at once (no reference left)
        print("swallowed", flush=True)
        cleaned = False
        try:
            time.sleep(wait_s)  # the program goes on, as if nothing had come
            return 0
        finally:
            cleaned = True
            print("cleanup ran", flush=True)

    sys.exit(signals.run(command, float(sys.argv[1])))
    """
)


@pytest.mark.parametrize("sig, code", [("SIGTERM", 143), ("SIGINT", 130)])
def test_a_swallowed_signal_is_raised_again(tmp_path, sig, code):
    script = tmp_path / "swallow.py"
    script.write_text(SCRIPT.format(sig=sig))
    env = dict(os.environ, PYTHONPATH=str(SRC))
    started = time.monotonic()
    r = subprocess.run([sys.executable, str(script), "30"], capture_output=True, text=True,
                       env=env, timeout=60, preexec_fn=sigint_as_on_a_terminal)
    took = time.monotonic() - started
    assert r.returncode == code, r.stderr
    # the first delivery was dropped (the command went on) and said nothing: no "Exception
    # ignored in ..." with a traceback, only the one line of an interrupted command
    assert r.stdout.splitlines() == ["raised in a finaliser", "swallowed", "cleanup ran"]
    assert "Exception ignored" not in r.stderr and "Traceback" not in r.stderr
    assert len(r.stderr.splitlines()) == 1
    assert took < 20  # raised again, not after the 30 s sleep


def test_a_command_that_returns_with_a_signal_pending_ends_with_its_status(monkeypatch):
    import signal

    from deck_emulator import signals

    monkeypatch.setattr(signals, "REDELIVER_S", 60.0)  # no second delivery in time

    def command():
        try:
            signals._raise(signal.SIGTERM, None)
        except signals.Terminated:
            pass  # swallowed, as a finaliser would
        return 0

    try:
        assert signals.run(command) == 143
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGALRM, signal.SIG_DFL)
