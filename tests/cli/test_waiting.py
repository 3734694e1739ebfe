"""Waiting, explained: the core's first compilation is said as what it is, done once, and a
bar shows no time left before the time left means something."""

from __future__ import annotations

import io
import sys

import pytest

from deck_emulator.parallel import SETTLED, progress_bar


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_no_time_left_until_a_share_of_the_work_is_done(monkeypatch):
    monkeypatch.setattr(sys, "stderr", Terminal())
    bar = progress_bar(100, desc="scenes", unit="scene")
    bar.update(1)  # the first scene carries the workers' start: its rate says nothing
    assert "<" not in str(bar) and "1/100" in str(bar)
    bar.update(int(SETTLED * 100))
    assert "<" in str(bar)  # elapsed<remaining, tqdm's own form
    bar.close()
    resumed = progress_bar(100, initial=90, desc="resumed")  # 10 to run: settled after 2
    resumed.update(1)
    assert "<" not in str(resumed)
    resumed.update(1)
    assert "<" in str(resumed)
    resumed.close()


def test_the_core_is_compiled_once_and_says_so(monkeypatch, tmp_path):
    pytest.importorskip("numba")
    import deck_emulator.core

    from deck_emulator.app import common
    from deck_emulator.engine import CoreEngine

    runs = []
    monkeypatch.setattr(CoreEngine, "run_batch", lambda self, decks: runs.append(self.batched))
    monkeypatch.setattr(deck_emulator.core, "compiled_cache_folder", lambda: str(tmp_path))
    err = Terminal()
    monkeypatch.setattr(sys, "stderr", err)
    common.compile_core(quiet=False)
    assert runs == [True]  # the compiled batch: what a study's workers then load
    assert "compiling the core once" in err.getvalue()
    assert [p.name.startswith("compiled-") for p in tmp_path.iterdir()] == [True]
    common.compile_core(quiet=False)
    assert runs == [True]  # not again


def test_the_pages_are_counted_as_they_are_drawn(monkeypatch, tmp_path):
    pytest.importorskip("matplotlib")
    from deck_emulator.legacy.pages import write_pdf

    err = Terminal()
    monkeypatch.setattr(sys, "stderr", err)
    records = ["1FIRST FORM", "1SECOND FORM"]
    assert write_pdf(records, tmp_path / "a.pdf", progress="writing the pages") == 2
    assert "writing the pages" in err.getvalue() and "/2 " in err.getvalue()  # of 2 forms
    quiet = Terminal()
    monkeypatch.setattr(sys, "stderr", quiet)
    write_pdf(records, tmp_path / "b.pdf")  # no words: no display
    assert quiet.getvalue() == ""
