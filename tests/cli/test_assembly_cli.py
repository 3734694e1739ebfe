"""The `assembly` subcommand: build, print and refuse."""

import json

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


def test_assembly_twin_core_json_carries_u(capsys):
    """The twin post's second luminaire U goes all the way to the answer: its point at the
    hit, the joint "R&U" ground hit, and a clearance over the car measured with both arms.
    At 0 deg the twin is symmetric about the shaft's plane, so U lands as R's mirror image
    (Table 12's "POST HITS GROUND WITH POINTS R&U")."""
    import json

    import pytest

    assert main(["assembly", "twin", "core", "--json"]) == 0
    answer = json.loads(capsys.readouterr().out)
    pts = answer["terminal_xl_yl_zl_ft"]
    assert {"P", "Q", "R", "U"} <= set(pts)
    (xr, yr, zr), (xu, yu, zu), yp = pts["R"], pts["U"], pts["P"][1]
    assert (xu, yu - yp, zu) == pytest.approx((xr, yp - yr, zr), abs=1e-4)
    hit = answer["events"][-1]
    assert (hit["kind"], hit["surface"], hit["point"]) == ("hit", "ground", "R&U")
    assert answer["occupant_risk"]["body_clearance_ft"] is not None


def test_assembly_props_json_is_the_table_as_numbers(capsys):
    """props --json carries the numbers the props table prints (to its digits)."""
    assert main(["assembly", "twin", "props"]) == 0
    table = capsys.readouterr().out
    assert main(["assembly", "twin", "props", "--json"]) == 0
    answer = json.loads(capsys.readouterr().out)
    assert answer["command"] == "assembly" and answer["settings"]["what"] == "props"
    assert f"weight {answer['weight_lb']:.2f} lb" in table
    a, b, c = answer["inertia_slug_ft2"]
    assert f"A {a:.2f}, B {b:.2f}, C {c:.3f} slug ft^2" in table
    assert set(answer["points_ft"]) >= {"P", "Q", "R", "U"}


def test_assembly_emulator_and_core_run_the_same_deck(capsys):
    """`assembly NAME emulator --json` and `assembly NAME core --json` report the deck values
    they ran: the same, field for field, for each shipped assembly the listing can run (the
    core's are the fields its scene carries; the others are the listing's start values)."""
    from deck_emulator.vocabulary.deck_fields import SCENE_PATHS

    for name in ("steel", "aluminium"):
        assert main(["assembly", name, "emulator", "--json"]) == 0
        emulator = json.loads(capsys.readouterr().out)["deck"]
        assert main(["assembly", name, "core", "--json"]) == 0
        core = json.loads(capsys.readouterr().out)["deck"]
        assert len(emulator) == 64 and set(core) == set(SCENE_PATHS)
        assert core == {k: emulator[k] for k in core}, name
