"""Nothing ignored in silence: a scene field the chosen preset overrides is named on stderr,
with the preset that would honour it (vocabulary.scene.OVERRIDDEN)."""

from __future__ import annotations

import dataclasses

import pytest

from deck_emulator.cli import main
from deck_emulator.vocabulary.scene import OVERRIDDEN, PRESETS, BaseFriction, overridden_fields


@pytest.fixture
def scene_file(tmp_path, capsys):
    path = tmp_path / "steel40.toml"
    assert main(["scene", "steel40", "--out", str(path)]) == 0
    capsys.readouterr()
    return path


def _with_friction(path, force_lb):
    text = path.read_text()
    assert text.count("\nforce_lb = 930.0\n") == 1  # [base.friction]'s, as written
    changed = path.with_name(f"friction{force_lb:g}.toml")
    changed.write_text(text.replace("\nforce_lb = 930.0\n", f"\nforce_lb = {force_lb!r}\n"))
    return changed


def test_core_names_the_friction_the_legacy_preset_overrides(scene_file, capsys):
    code = main(["core", str(_with_friction(scene_file, 5000.0)), "--quiet"])
    err = capsys.readouterr().err
    assert code == 0
    (line,) = [l for l in err.splitlines() if "base.friction.force_lb" in l]
    assert "5000" in line and "listing_friction" in line and "--preset physical" in line


def test_a_scene_as_written_from_its_deck_is_not_warned_about(scene_file, capsys):
    assert main(["core", str(scene_file), "--quiet"]) == 0
    assert "not used" not in capsys.readouterr().err


def test_the_mapping_is_what_the_core_does():
    """Under the legacy preset the base friction's force changes nothing (the listing's own is
    used), under the physical preset it changes the run: the field the mapping names is the
    one the preset sets aside, and the preset it points to honours it."""
    from deck_emulator import decks
    from deck_emulator.engine import CoreEngine
    from deck_emulator.engine.sources import read_deck
    from deck_emulator.vocabulary.scene import Scene

    base = Scene.from_deck(read_deck(decks.path("steel40")), name="steel40")
    hits = {}
    for preset in ("legacy", "physical"):
        for force in (0.0, 5000.0):
            friction = BaseFriction(force_lb=force, slip_window_ft=base.base.friction.slip_window_ft)
            scene = dataclasses.replace(base, base=dataclasses.replace(base.base,
                                                                        friction=friction))
            said = overridden_fields(scene, PRESETS[preset])
            assert any("base.friction.force_lb" in s for s in said) == (preset == "legacy")
            hits[preset, force] = CoreEngine(preset=preset).run(scene).hit_time_s
    assert hits["legacy", 0.0] == hits["legacy", 5000.0]
    assert hits["physical", 0.0] != hits["physical", 5000.0]


def test_every_overridden_field_names_a_real_option():
    names = {f.name for f in dataclasses.fields(PRESETS["legacy"])}
    for o in OVERRIDDEN:
        assert o.flag in names
        # some preset sets it aside and some preset honours it
        assert {getattr(p, o.flag) == o.when for p in PRESETS.values()} == {True, False}
