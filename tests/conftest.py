"""Fixtures shared by the test modules."""

from __future__ import annotations

import os

import pytest

from stubs import SRC, STUB

from deck_emulator.core import configure_numba_cache

configure_numba_cache()  # the test session's numba keeps the core's code where a command's does


@pytest.fixture(autouse=True, scope="session")
def _user_cache_in_a_temporary_folder(tmp_path_factory):
    """What the package keeps in the user's cache folder (a job deck's made code) goes to a
    folder of the test session's, for every test and the commands they start, not to the
    user's own (numba's machine code stays where a command keeps it, set above)."""
    before = os.environ.get("XDG_CACHE_HOME")
    os.environ["XDG_CACHE_HOME"] = str(tmp_path_factory.mktemp("user-cache"))
    yield
    if before is None:
        os.environ.pop("XDG_CACHE_HOME", None)
    else:
        os.environ["XDG_CACHE_HOME"] = before


@pytest.fixture
def stub(tmp_path, monkeypatch):
    """The stub engine of :mod:`stubs`, importable here and in Dask's worker processes."""
    (tmp_path / "stub_engine.py").write_text(STUB)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(tmp_path), str(SRC)]))
    import importlib

    import stub_engine

    importlib.reload(stub_engine)
    return stub_engine
