"""One road: every outcome carries its typed scene, every ΔV is one formula, the diff's and the
report's runs go through the one scene runner (and its store)."""

from __future__ import annotations

import math

import pytest

from deck_emulator.vocabulary.deck_fields import SCENE_PATHS as DECK_FIELDS
from deck_emulator.vocabulary.scene import DeckScene, Scene, SceneError
from deck_emulator.decks import path as deck_path
from deck_emulator.engine import CoreEngine, EmulatorEngine
from deck_emulator.legacy.deck import read_deck
from deck_emulator.vocabulary.units import speed_lost_mph

STEEL40 = deck_path("steel40")


def test_speed_lost_is_the_fall_of_the_speed_in_mph():
    # 88 ft/s is 60 mph by definition (5280 ft a mile, 3600 s an hour): 88 -> 44 ft/s loses 30
    assert speed_lost_mph(-88.0, -44.0) == pytest.approx(30.0, rel=1e-15)
    assert speed_lost_mph(88.0, -44.0) == pytest.approx(30.0, rel=1e-15)  # speeds, not signs
    assert speed_lost_mph(-44.0, -88.0) == pytest.approx(-30.0, rel=1e-15)  # a gain is negative


def test_the_emulators_outcome_carries_the_decks_scene():
    """The deck's values come back through the one deck <-> scene mapping, read from the
    outcome's typed scene (the deck file is the independent source)."""
    deck = read_deck(STEEL40)
    out = EmulatorEngine(trace=False).run(deck)
    assert not hasattr(out, "values")
    assert isinstance(out.scene, DeckScene) and out.scene.problems() == []
    back = out.scene.deck_values()
    for name in DECK_FIELDS:
        assert back[name] == deck.values[name], name
    assert out.arithmetic == "double"
    assert out.speed_mph == pytest.approx(abs(deck.values["VVB"]) * 3600 / 5280, rel=1e-15)
    assert out.angle_deg == 0.0


def test_a_deck_the_core_refuses_still_runs_on_the_emulator_and_says_why_on_the_core():
    deck = read_deck(STEEL40).with_values(W=0.0)
    scene = Scene.from_deck(deck, checked=False)
    assert scene.post.mass_slug == 0.0
    assert scene.problems() == ["post mass must be positive, got 0.0"]
    with pytest.raises(SceneError, match="post mass must be positive"):
        scene.checked()
    with pytest.raises(SceneError, match="post mass must be positive"):
        Scene.from_deck(deck)
    em = EmulatorEngine(trace=False).run(deck)
    assert em.scene.post.mass_slug == 0.0  # the outcome carries what ran
    co = CoreEngine(trace=False).run(deck)
    assert co.error is not None and "post mass must be positive" in co.error
    assert co.scene.post.mass_slug == 0.0


def test_the_twin_posts_outcome_carries_its_second_arm():
    from deck_emulator.core.assembly import load_assembly, mass_properties
    from deck_emulator.engine.assemblies import to_scene

    asm, _, _ = load_assembly("twin")
    scene = to_scene(asm, mass_properties(asm), template="steel40")
    out = CoreEngine(preset="physical", trace=True).run(scene)  # no start-up tilt at t = 0
    u = out.scene.post.second_luminaire_end
    assert u is not None
    assert "U" in out.points and "U" in out.terminal
    # U at t = 0 in the report's axes is the scene's point less the base's place and the ground
    base, depth = scene.post.base, scene.environment.ground_depth_ft
    got = out.point_l("U", 0.0)
    want = (u.xx_ft - base.xx_ft, u.yy_ft - base.yy_ft, u.zz_ft + depth)
    assert got == pytest.approx(want, abs=1e-9)


def test_the_diff_runs_on_the_scene_runner_and_resumes_from_its_store(tmp_path):
    from deck_emulator.studies.diff import diff_deck
    from deck_emulator.studies.store import SceneStore

    deck = read_deck(STEEL40)
    store = tmp_path / "store"
    first = diff_deck(deck, ks=range(1), jobs=1, store_dir=store, quiet=True)
    files = SceneStore(store).files()
    assert len(files) == 1 and len(SceneStore(store).rows()) == 1
    again = diff_deck(deck, ks=range(1), jobs=1, store_dir=store, resume=True, quiet=True)
    assert SceneStore(store).files() == files  # nothing ran again
    assert again == first
    assert first["emulator"]["hit"] == "hit ground (R)"
    assert math.isfinite(first["max_trajectory_diff_as_printed_ft"])
