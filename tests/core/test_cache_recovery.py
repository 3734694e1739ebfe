"""An unreadable numba cache of the core (a file cut short or garbled) is compiled anew, once,
instead of ending every run in numba's unpickling error; any other error is left alone."""

from __future__ import annotations

import pickle

import pytest

pytest.importorskip("numba")

import numba  # noqa: E402

from deck_emulator.core import laws  # noqa: E402


def _raising_inside_numbas_cache(exc: BaseException):
    """A function raising ``exc`` from a frame of numba's cache loader (what a garbled .nbi
    or .nbc file gives: numba unpickles it in numba/core/caching.py)."""
    code = compile("raise exc", "/site-packages/numba/core/caching.py", "exec")

    def load():
        exec(code, {"exc": exc})

    return load


def test_an_unreadable_cache_is_removed_and_the_entry_runs_again(tmp_path, monkeypatch):
    cache = tmp_path / "deck_emulator-cache"
    (cache / "core").mkdir(parents=True)
    (cache / "core" / "laws.x.nbi").write_bytes(b"\x80\x04cut")
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(cache))
    calls = []

    def entry(x):
        calls.append(x)
        if len(calls) == 1:
            _raising_inside_numbas_cache(pickle.UnpicklingError("pickle data was truncated"))()
        return 2 * x

    assert laws.recompiling(entry)(21) == 42
    assert calls == [21, 21] and not cache.exists()


@pytest.mark.parametrize("exc", [MemoryError(), EOFError("Ran out of input")])
def test_what_a_garbled_pickle_raises_is_recovered_too(tmp_path, monkeypatch, exc):
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path / "c"))
    calls = []

    def entry():
        calls.append(1)
        if len(calls) == 1:
            _raising_inside_numbas_cache(exc)()
        return "ran"

    assert laws.recompiling(entry)() == "ran" and len(calls) == 2


def test_an_error_of_the_run_itself_is_not_taken_for_the_cache(tmp_path, monkeypatch):
    cache = tmp_path / "c"
    cache.mkdir()
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(cache))
    calls = []

    def entry():
        calls.append(1)
        raise pickle.UnpicklingError("raised by the run, not by numba's cache")

    with pytest.raises(pickle.UnpicklingError):
        laws.recompiling(entry)()
    assert calls == [1] and cache.exists()


def test_the_core_entries_are_the_recompiling_ones():
    import deck_emulator.core as core

    for name in ("simulate", "free_flight", "simulate_batch"):
        assert getattr(core, name).__wrapped__.__name__ == name
