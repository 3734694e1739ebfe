"""A command says an extra is missing only where its module is not installed."""

from __future__ import annotations

import importlib.util

from deck_emulator.extras import missing_extra


def test_an_installed_module_that_fails_to_import_is_not_called_missing(monkeypatch):
    import deck_emulator.extras as extras

    assert importlib.util.find_spec("numpy") is not None  # (the suite's own install)
    monkeypatch.setitem(extras.EXTRA_OF_MODULE, "numpy", "core")  # as if an extra's module
    exc = ImportError("cannot import name 'nothing' from 'numpy.linalg'", name="numpy.linalg")
    assert missing_extra(exc) is None


def test_a_module_of_an_extra_that_is_not_installed_names_the_extra(monkeypatch):
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None)
    message = missing_extra(ModuleNotFoundError("No module named 'dask'", name="dask"))
    assert message is not None and "deck_emulator[studies]" in message


def test_a_module_of_no_extra_is_not_called_missing():
    assert missing_extra(ModuleNotFoundError("No module named 'nowhere'", name="nowhere")) is None
