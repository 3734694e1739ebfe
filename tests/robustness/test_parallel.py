"""The progress display: shown on a terminal only, never on a pipe or a file. (Runs of many
scenes are the scene runner's, tested in test_distributed.py and test_kill.py: no worker
outlives its command.)"""

from __future__ import annotations

import io
import sys

from deck_emulator.parallel import busy, progress_bar


def test_no_progress_bar_unless_stderr_is_a_terminal(capsys):
    bar = progress_bar(4, desc="quietly")
    for _ in range(4):
        bar.update(1)
    bar.close()
    with busy("quietly", every_s=0.01):
        pass
    assert capsys.readouterr().err == ""


def test_a_progress_bar_on_a_terminal(monkeypatch):
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    err = Terminal()
    monkeypatch.setattr(sys, "stderr", err)
    bar = progress_bar(4, desc="loudly", unit="run")
    bar.update(4)
    bar.close()
    assert "loudly" in err.getvalue() and "/4" in err.getvalue()  # drawn (then cleared)
    quiet = Terminal()
    monkeypatch.setattr(sys, "stderr", quiet)
    progress_bar(4, desc="asked to be quiet", quiet=True).close()
    assert quiet.getvalue() == ""
