"""Fixtures shared by the test modules."""

from __future__ import annotations

import os

import pytest

from stubs import SRC, STUB


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
