"""An unreadable numba cache of the core (a file cut short or garbled) is compiled anew, once,
instead of ending every run in numba's unpickling error; any other error is left alone, and
so is a host application's own numba cache."""

from __future__ import annotations

import pickle

import pytest

pytest.importorskip("numba")

from numba.core import event as numba_event  # noqa: E402

from deck_emulator.core import laws  # noqa: E402


def _raising_inside_numbas_compiler_lock(exc: BaseException):
    """A function raising ``exc`` while numba's compiler lock is held (what a garbled .nbi or
    .nbc file gives: numba unpickles it while it holds the lock), told by numba's documented
    events ``numba:compiler_lock`` as numba's lock tells them."""

    def load():
        numba_event.start_event("numba:compiler_lock")
        try:
            raise exc
        except BaseException:
            numba_event.end_event("numba:compiler_lock")
            raise

    return load


@pytest.fixture
def own_cache(tmp_path, monkeypatch):
    """The core's cache folder, numba pointed at it (as the command line does), and the core's
    functions handed to numba (its compiler-lock listener registered), whatever ran before."""
    laws.compile_functions()
    cache = tmp_path / "deck_emulator-cache"
    monkeypatch.setattr(laws, "compiled_cache_folder", lambda: str(cache))
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(cache))
    return cache


def test_an_unreadable_cache_is_removed_and_the_entry_runs_again(own_cache):
    (own_cache / "core").mkdir(parents=True)
    (own_cache / "core" / "laws.x.nbi").write_bytes(b"\x80\x04cut")
    calls = []

    def entry(x):
        calls.append(x)
        if len(calls) == 1:
            _raising_inside_numbas_compiler_lock(
                pickle.UnpicklingError("pickle data was truncated"))()
        return 2 * x

    assert laws.recompiling(entry)(21) == 42
    assert calls == [21, 21] and not own_cache.exists()


@pytest.mark.parametrize("exc", [MemoryError(), EOFError("Ran out of input")])
def test_what_a_garbled_pickle_raises_is_recovered_too(own_cache, exc):
    calls = []

    def entry():
        calls.append(1)
        if len(calls) == 1:
            _raising_inside_numbas_compiler_lock(exc)()
        return "ran"

    assert laws.recompiling(entry)() == "ran" and len(calls) == 2


def test_an_error_that_comes_back_is_raised(own_cache):
    calls = []

    def entry():
        calls.append(1)
        _raising_inside_numbas_compiler_lock(EOFError("Ran out of input"))()

    with pytest.raises(EOFError):
        laws.recompiling(entry)()
    assert len(calls) == 2


def test_an_error_of_the_run_itself_is_not_taken_for_the_cache(own_cache):
    own_cache.mkdir()
    calls = []

    def entry():
        calls.append(1)
        raise pickle.UnpicklingError("raised by the run, not by numba's cache")

    with pytest.raises(pickle.UnpicklingError):
        laws.recompiling(entry)()
    assert calls == [1] and own_cache.exists()


def test_an_error_after_a_clean_compile_is_the_runs(own_cache):
    """numba held its lock and let it go cleanly, then the run failed: not the cache's."""
    own_cache.mkdir()
    calls = []

    def entry():
        calls.append(1)
        numba_event.start_event("numba:compiler_lock")
        numba_event.end_event("numba:compiler_lock")
        raise ValueError("the run's own")

    with pytest.raises(ValueError):
        laws.recompiling(entry)()
    assert calls == [1] and own_cache.exists()


def test_a_host_applications_cache_is_left_to_it(tmp_path, monkeypatch):
    """Where numba's cache is not the core's own folder (NUMBA_CACHE_DIR the host's, or
    unset), nothing is removed and the error is raised."""
    cache = tmp_path / "deck_emulator-cache"
    cache.mkdir()
    monkeypatch.setattr(laws, "compiled_cache_folder", lambda: str(cache))
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "host"))
    calls = []

    def entry():
        calls.append(1)
        _raising_inside_numbas_compiler_lock(EOFError("Ran out of input"))()

    with pytest.raises(EOFError):
        laws.recompiling(entry)()
    assert calls == [1] and cache.exists()


def test_the_core_entries_are_the_recompiling_ones():
    import deck_emulator.core as core

    for name in ("simulate", "free_flight", "simulate_batch"):
        assert getattr(core, name).__wrapped__.__name__ == name
