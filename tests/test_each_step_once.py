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
