"""Each step once (issue 47): a command reads its deck file once, builds the scene it solves
once and makes its JSON document once.

Counted here, in this process, by wrapping the one builder of each (``os.open`` of the deck
file, :meth:`Scene.from_deck`, :meth:`Answer.document`); the commands are called as Python
calls them (:func:`deck_emulator.app.call`)."""

from __future__ import annotations

import builtins
import io
import os
import shutil
from collections import Counter

import pytest

from deck_emulator import app, decks
from deck_emulator.vocabulary.scene import Scene


@pytest.fixture
def counted(monkeypatch, tmp_path):
    """A copy of steel40.dat in ``tmp_path`` and a Counter of what touched it: ``opened``
    (every open of that file, through ``os.open``, ``open`` or ``io.open``), ``scene``
    (Scene.from_deck) and ``document`` (Answer.document)."""
    deck = tmp_path / "steel40.dat"
    shutil.copyfile(decks.path("steel40"), deck)
    counts: Counter = Counter()

    def counting(fn, key, *, of_deck=False):
        def wrapper(*args, **kwargs):
            if not of_deck or (isinstance(args[0], (str, os.PathLike))
                               and os.fspath(args[0]) in (str(deck), deck.name)):
                counts[key] += 1
            return fn(*args, **kwargs)
        return wrapper

    monkeypatch.setattr(os, "open", counting(os.open, "opened", of_deck=True))
    monkeypatch.setattr(builtins, "open", counting(builtins.open, "opened", of_deck=True))
    monkeypatch.setattr(io, "open", counting(io.open, "opened", of_deck=True))
    from_deck = Scene.from_deck.__func__
    monkeypatch.setattr(Scene, "from_deck", classmethod(
        lambda cls, *a, **k: counting(from_deck, "scene")(cls, *a, **k)))
    monkeypatch.setattr(app.Answer, "document", counting(app.Answer.document, "document"))
    return deck, counts


def test_core_json_reads_its_deck_builds_its_scene_and_its_document_once(counted):
    deck, counts = counted
    answer = app.call("core", source=str(deck), json=True, quiet=True)
    printed = answer.printed()
    assert answer.status == "ok" and '"command": "core"' in printed
    assert counts == Counter(opened=1, scene=1, document=1)


def test_core_text_makes_its_document_once_for_the_text(counted):
    deck, counts = counted
    answer = app.call("core", source=str(deck), quiet=True)
    assert answer.printed() == answer.text  # the text was made from the one document
    assert counts == Counter(opened=1, scene=1, document=1)


@pytest.mark.parametrize("command, options, documents", [
    ("parse", {}, 1), ("parse", {"json": True}, 1), ("run", {}, 0), ("punch", {}, 0),
    ("summary", {"json": True}, 1), ("scene", {}, 0),
])
def test_a_command_reads_its_deck_once(counted, command, options, documents):
    """``documents``: the JSON document is made once where the answer is made from it (the
    text of parse, summary and core; any --json), and not at all where it is not."""
    deck, counts = counted
    answer = app.call(command, source=str(deck), **options)
    answer.printed()
    assert counts["opened"] == 1, (command, counts)
    assert counts["document"] == documents, (command, counts)


def test_a_studys_text_deck_is_read_once_and_handed_on(counted):
    """The studies' and the sweep's deck: read once, and the Deck read is what they use."""
    from deck_emulator.app.common import deck_file

    deck, counts = counted
    text = deck_file(str(deck), "study error")
    assert counts["opened"] == 1
    assert text.path == str(deck) and text.values["VVB"] == pytest.approx(-58.66)


def test_plot_on_the_core_builds_its_scene_once(counted, tmp_path):
    """The scene the command checks is the scene the core runs (it was built twice)."""
    deck, counts = counted
    answer = app.call("plot", source=str(deck), engine="core", out=str(tmp_path / "side.png"),
                      quiet=True)
    assert answer.status == "ok" and (tmp_path / "side.png").stat().st_size > 0
    assert counts["opened"] == 1 and counts["scene"] == 1, counts


@pytest.fixture
def in_process(monkeypatch):
    """The scene runner's workers as a thread of this process, so that what a worker reads
    is counted too (the local pool's processes would read unseen)."""
    import concurrent.futures as cf
    import contextlib

    from deck_emulator.studies import distributed

    @contextlib.contextmanager
    def pool(jobs, core):
        with cf.ThreadPoolExecutor(1) as executor:
            yield executor, 1, lambda: True

    monkeypatch.setattr(distributed, "_local_pool", pool)


def test_study_error_reads_its_deck_once_workers_included(counted, in_process, monkeypatch,
                                                          tmp_path):
    """The command hashes the bytes it read for the store's resume check and hands the
    parsed deck to the workers (it read the file three times, and each worker once more)."""
    from deck_emulator.studies import error

    pytest.importorskip("scipy")
    monkeypatch.setattr(error, "plan", lambda quick: {  # a small plan: the count, not the study
        "ks": range(2), "rtols": (1e-4, 1e-7), "reps": 1, "ibm": False, "checks": ("LSODA",)})
    deck, counts = counted
    answer = app.call("study error", deck=str(deck), quick=True, jobs=1,
                      out=str(tmp_path / "er"), quiet=True)
    assert answer.status == "ok" and (tmp_path / "er" / "README.md").is_file()
    assert counts["opened"] == 1, counts


def test_diff_reads_its_deck_once(counted, in_process):
    """The store's resume check takes the SHA-256 of the bytes read (it read the file again)."""
    deck, counts = counted
    answer = app.call("diff", source=str(deck), max_k=0, jobs=1, quiet=True)
    assert answer.status == "ok"
    assert counts["opened"] == 1, counts


def test_study_stability_reads_its_deck_once_workers_included(counted, in_process, tmp_path):
    """Its base deck read once by the command, hashed from those bytes for the store and
    handed to every task (each task read the file again, and the page's section once more)."""
    pytest.importorskip("scipy")
    deck, counts = counted
    answer = app.call("study stability", deck=str(deck), quick=True, jobs=1,
                      out=str(tmp_path / "st"), quiet=True)
    assert answer.status == "ok" and (tmp_path / "st" / "README.md").is_file()
    assert counts["opened"] == 1, counts


@pytest.mark.parametrize("what", ["emulator", "deck", "core"])
def test_assembly_reads_its_template_deck_once(monkeypatch, what):
    """The scene and the deck's values are made from one read of the template deck (the
    scene and the deck each read it)."""
    from deck_emulator.studies.sweep import car_at

    template = os.path.realpath(decks.path(car_at(40.0, 0.0)[0]))
    opened: Counter = Counter()
    real_open = os.open

    def counting(path, *args, **kwargs):
        if isinstance(path, (str, os.PathLike)) and os.path.realpath(path) == template:
            opened["template"] += 1
        return real_open(path, *args, **kwargs)

    monkeypatch.setattr(os, "open", counting)
    answer = app.call("assembly", description="steel", what=what, json=True)
    assert answer.status == "ok" and '"command": "assembly"' in answer.printed()
    assert opened["template"] == 1, opened


def test_sensitivity_reads_its_deck_once_workers_included(counted, in_process, tmp_path):
    """The command's read of --deck is the study's deck, its store's hash and the workers'
    deck (the study read it again, the store hashed it again, each worker once more)."""
    pytest.importorskip("SALib")
    deck, counts = counted
    answer = app.call("sensitivity", deck=(str(deck),), quick=True, jobs=1,
                      out=str(tmp_path / "sens"), quiet=True)
    assert answer.status == "ok" and (tmp_path / "sens" / "sensitivity.csv").is_file()
    assert counts["opened"] == 1, counts
