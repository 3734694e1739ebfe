"""The `assembly` subcommand: build, print and refuse."""

from deck_emulator.cli import main
from deck_emulator.legacy.deck import parse_deck


def test_assembly_props_and_deck(capsys):
    assert main(["assembly", "aluminium"]) == 0
    out = capsys.readouterr().out
    assert "316.63 lb" in out and "R: (" in out
    assert main(["assembly", "aluminium", "deck", "--speed-mph", "20"]) == 0
    deck = parse_deck(capsys.readouterr().out)
    assert deck["VVB"] == -29.33 and deck["FNA"] == 316.63


def test_assembly_twin_refused_on_the_listing(capsys):
    assert main(["assembly", "twin", "deck"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "second (U)" in err


def test_assembly_twin_scene_has_u(capsys):
    assert main(["assembly", "twin", "scene"]) == 0
    assert "[post.second_luminaire_end]" in capsys.readouterr().out
