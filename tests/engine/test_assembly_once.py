"""Each step once (issue 47): ``assembly NAME WHAT`` builds the scene of its post once, and
the emulator's outcome carries that scene rather than a second one built from the deck.

Counted by wrapping the one builder (:meth:`Scene.from_deck`), the command called as Python
calls it (:func:`deck_emulator.app.call`)."""

from __future__ import annotations

from collections import Counter

import pytest

from deck_emulator import app
from deck_emulator.engine import EmulatorEngine
from deck_emulator.legacy.deck import parse_deck
from deck_emulator.vocabulary.scene import Scene


@pytest.fixture
def built(monkeypatch) -> Counter:
    counts: Counter = Counter()
    from_deck = Scene.from_deck.__func__

    def counting(cls, *args, **kwargs):
        counts["scene"] += 1
        return from_deck(cls, *args, **kwargs)

    monkeypatch.setattr(Scene, "from_deck", classmethod(counting))
    return counts


@pytest.mark.parametrize("what", ["emulator", "deck", "scene", "core"])
def test_assembly_builds_its_scene_once(built, what):
    answer = app.call("assembly", description="steel", what=what, json=True)
    answer.printed()
    assert answer.status == "ok"
    assert built["scene"] == 1, built


def test_the_emulators_outcome_carries_the_scene_it_is_given(built):
    """The scene handed in is the one the outcome keeps, and it is the deck's scene: built
    from the deck it equals the one the engine would build itself."""
    from deck_emulator import decks

    with open(decks.path("steel40"), encoding="ascii") as fh:
        deck = parse_deck(fh.read())
    scene = Scene.from_deck(deck, name="steel40", checked=False)
    given = EmulatorEngine(trace=False).run(deck, name="steel40", scene=scene)
    own = EmulatorEngine(trace=False).run(deck, name="steel40")
    assert given.scene is scene
    assert own.scene == scene
    assert built["scene"] == 2  # the test's own scene, and the engine's for `own` alone
