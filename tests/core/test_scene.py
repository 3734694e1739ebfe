"""Scene description: building from a deck, TOML round trip, absent components, options."""

from __future__ import annotations

import dataclasses
import math
import re
import tomllib
from pathlib import Path

import pytest

from deck_emulator.vocabulary.units import speed_lost_mph
from deck_emulator.vocabulary.scene import (
    LEGACY,
    LISTING_BASE_FRICTION,
    PHYSICAL,
    PRESETS,
    BaseFriction,
    BreakawayBase,
    CrushSpring,
    Environment,
    ModelOptions,
    Post,
    PostInitialState,
    PostPoint,
    Scene,
    SceneError,
    StartupKick,
    Vehicle,
)

DECKS = Path(__file__).resolve().parents[2] / "decks"

#: the steel40 deck's values (the report's appendix $DATA cards)
STEEL40 = {
    "VVB": -58.66, "W": 15.1, "WV": 100.0, "A": 3351.41, "B": 3282.6, "C": 69.68,
    "G": 32.174, "CK": 33000.0, "HEIGHT": 20.27, "SVB": 5.0, "XSO": 0.0, "YYSO": 1.53,
    "ZZSO": -18.77, "FNA": 485.07, "XPO": 0.0, "YYPO": 1.53, "ZZPO": 16.938, "XQO": 0.0,
    "YYQO": 1.53, "ZZQO": -19.77, "SVO": 5.0, "ALPHA": 0.0, "HLEN": 5.0, "TLEN": 7.0,
    "DELTA": 0.1463, "YLFEN": -1.47, "YRFEN": 4.53, "TRLEN": 6.0, "HTRV": -16.77,
    "HTV": -15.27, "HHV": -16.27, "XRO": 0.0, "YYRO": -8.47, "ZZRO": 21.938, "XCO": 0.0,
    "YYCO": 1.53, "ZZCO": -19.77, "XTO": 0.0, "YYTO": 1.53, "ZZTO": -17.5, "CT": 20000.0,
    "FCONST": 1200.0,
}  # fmt: skip


def contact_delta_v_mph(r) -> float | None:
    """The speed a core run's car lost by the end of its contact: the registry's reading
    (``vocabulary.units.speed_lost_mph`` of the car's velocity at ``contact_end_s``)."""
    if r.contact_end_s is None:
        return None
    v = float(r.trajectory.vehicle(r.contact_end_s)[1])
    return speed_lost_mph(r.scene.vehicle.initial_velocity_ft_s, v)


def steel40() -> Scene:
    return Scene.from_deck(STEEL40, name="steel40")


def test_from_mapping_names_and_units():
    s = steel40()
    assert s.post.mass_slug == 15.1
    assert s.post.principal_inertia_slug_ft2 == (3351.41, 3282.6, 69.68)
    assert s.post.principal_tilt_rad == 0.1463
    assert s.post.top == PostPoint(0.0, 1.53, 16.938)
    assert s.post.base == PostPoint(0.0, 1.53, -19.77)
    assert s.post.first_impact == PostPoint(0.0, 1.53, -18.77)
    assert s.post.second_impact == PostPoint(0.0, 1.53, -17.5)
    assert s.post.luminaire_end == PostPoint(0.0, -8.47, 21.938)
    assert s.post.point_c == PostPoint(0.0, 1.53, -19.77)
    v = s.vehicle
    assert (v.mass_slug, v.initial_velocity_ft_s, v.approach_angle_rad) == (100.0, -58.66, 0.0)
    assert (v.initial_position_ft, v.contact_position_ft) == (5.0, 5.0)
    assert v.first_spring == CrushSpring(33000.0) and v.second_spring == CrushSpring(20000.0)
    assert v.force_cap_lb == 1200.0
    assert v.body.hood_height_ft == -16.27 and v.body.right_fender_ft == 4.53
    assert s.environment == Environment(ground_depth_ft=20.27, gravity_ft_s2=32.174)
    assert s.base == BreakawayBase(485.07, 0.4166, LISTING_BASE_FRICTION)
    assert s.base.friction.force_lb == pytest.approx(930.0, abs=1e-12)
    assert s.initial == PostInitialState()


def test_principal_coordinates_are_the_listings():
    # YPO=YYPO*COS(DELTA)+ZZPO*SIN(DELTA), ZPO=-YYPO*SIN(DELTA)+ZZPO*COS(DELTA)
    p = PostPoint(0.25, 1.53, 16.938)
    d = 0.1463
    x, y, z = p.principal_coordinates(d)
    assert x == 0.25
    assert y == pytest.approx(1.53 * math.cos(d) + 16.938 * math.sin(d), abs=1e-15)
    assert z == pytest.approx(-1.53 * math.sin(d) + 16.938 * math.cos(d), abs=1e-15)


def test_from_deck_file_matches_mapping():
    deck_mod = pytest.importorskip("deck_emulator.legacy.deck")
    deck = deck_mod.read_deck(DECKS / "steel40.dat")
    s = Scene.from_deck(deck)
    assert s.name == "steel40.dat"
    assert dataclasses.replace(s, name="steel40") == steel40()


def test_absent_components_are_none():
    values = dict(STEEL40)
    for k in ("XRO", "YYRO", "ZZRO", "XCO", "YYCO", "ZZCO", "CT", "FCONST"):
        values[k] = 0.0
    for k in ("HLEN", "TLEN", "TRLEN", "HHV", "HTV", "HTRV"):
        values[k] = 0.0
    s = Scene.from_deck(values)
    assert s.post.luminaire_end is None
    assert s.post.point_c is None
    assert s.post.second_impact is None
    assert s.vehicle.second_spring is None
    assert s.vehicle.force_cap_lb is None
    assert s.vehicle.body is None
    assert set(s.post.points()) == {"P", "Q", "S"}


def test_initial_state_from_deck_euler_angles():
    values = dict(STEEL40, PSIB=0.3, THB=0.2, PHIB=-0.1, XCMB=0.0, YCMB=1.0, ZCMB=0.0)
    s = Scene.from_deck(values)
    w, x, y, z = s.initial.attitude_wxyz
    assert w * w + x * x + y * y + z * z == pytest.approx(1.0, abs=1e-15)
    # eq. 2.51: chi = cos(th/2) cos((psi+phi)/2)
    assert w == pytest.approx(math.cos(0.1) * math.cos(0.1), abs=1e-15)
    d = 0.1463
    assert s.initial.mass_centre_ft == pytest.approx((0.0, math.cos(d), math.sin(d)), abs=1e-15)


def test_toml_round_trip():
    tilted = Scene.from_deck(dict(STEEL40, PSIB=0.3, THB=0.2, PHIB=-0.1, W2B=0.5, XCMB=1e-7))
    for s in (
        steel40(),
        tilted,
        Scene.from_deck(dict(STEEL40, CT=0.0, XRO=0.0, YYRO=0.0, ZZRO=0.0, HLEN=0.0)),
    ):
        text = s.to_toml()
        tomllib.loads(text)  # plain TOML
        assert Scene.from_toml(text) == s
    assert (
        "luminaire_end" not in Scene.from_deck(dict(STEEL40, XRO=0.0, YYRO=0.0, ZZRO=0.0)).to_toml()
    )


def test_toml_written_by_hand():
    text = """
name = "dropped post"
[post]
mass_slug = 15          # integers are fine
inertia_1_slug_ft2 = 3351.41
inertia_2_slug_ft2 = 3282.6
inertia_3_slug_ft2 = 69.68
[post.top]
xx_ft = 0
yy_ft = 0
zz_ft = 16.938
[post.base]
xx_ft = 0
yy_ft = 0
zz_ft = -19.77
[environment]
ground_depth_ft = 20.27
[initial]
velocity_body_ft_s = [1.0, 0.0, 2.0]
"""
    s = Scene.from_toml(text)
    assert s.post.mass_slug == 15.0 and s.vehicle is None and s.base is None
    assert s.environment.gravity_ft_s2 == 32.174
    assert s.initial.velocity_body_ft_s == (1.0, 0.0, 2.0)


@pytest.mark.parametrize(
    "text, message",
    [
        ("[post]\nmass_slug = 1\nfoo = 2\n", "unknown key"),
        ("[environment]\nground_depth_ft = 'deep'\n", "must be a number"),
        ("[environment]\nground_depth_ft = 1.0\n", "post"),
        ("x = [", "not valid TOML"),
    ],
)
def test_toml_errors(text, message):
    with pytest.raises(SceneError, match=message):
        Scene.from_toml(text)


def test_vehicle_needs_impact_point():
    post = Post(1.0, 1.0, 1.0, 1.0, top=PostPoint(0, 0, 1), base=PostPoint(0, 0, -1))
    with pytest.raises(SceneError, match="first impact"):
        Scene(
            post=post, environment=Environment(10.0), vehicle=Vehicle(1.0, -1.0, CrushSpring(1.0))
        )


def test_presets_name_every_quirk():
    assert PRESETS == {"legacy": LEGACY, "physical": PHYSICAL}
    assert LEGACY.startup_kick == StartupKick(0.0545, 0.000022, 0.0004, -10000.0, 10000.0, 1320.0)
    assert LEGACY.spring_factor == 0.8 and LEGACY.spring_absolute
    assert LEGACY.spring_switch_ft == 0.01
    assert LEGACY.force_cap_from_s == pytest.approx(0.008, abs=1e-15)
    assert LEGACY.listing_friction and LEGACY.listing_hit_tolerances and LEGACY.listing_diff
    # physical: none of them
    assert PHYSICAL.startup_kick is None and PHYSICAL.spring_factor == 1.0
    assert not (PHYSICAL.spring_absolute or PHYSICAL.listing_friction or PHYSICAL.listing_diff)
    assert PHYSICAL.force_cap_from_s is None and PHYSICAL.spring_switch_ft == 0.0
    assert not PHYSICAL.listing_hit_tolerances
    one = LEGACY.replace(spring_factor=1.0)
    assert one.name == "custom" and one.startup_kick == LEGACY.startup_kick
    with pytest.raises(dataclasses.FrozenInstanceError):
        LEGACY.spring_factor = 1.0  # type: ignore[misc]


def test_scene_is_frozen_and_hashable():
    s = steel40()
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.name = "x"  # type: ignore[misc]
    assert hash(s) == hash(steel40())
    assert isinstance(s.base.friction, BaseFriction)
    assert ModelOptions() == PHYSICAL.replace(name="custom")


def test_the_deck_scene_mapping_goes_both_ways():
    """Every shipped deck, read into a scene and written back through the one mapping
    (SCENE_PATHS), gives the deck's own values for every name the mapping has."""
    from deck_emulator import decks
    from deck_emulator.vocabulary.deck_fields import SCENE_PATHS as DECK_FIELDS
    from deck_emulator.legacy.deck import read_deck

    for name in decks.names():
        deck = read_deck(decks.path(name))
        back = Scene.from_deck(deck).deck_values()
        assert set(back) == set(DECK_FIELDS)
        assert {k: deck[k] for k in DECK_FIELDS} == back, name


# ---- scene files answered key by key ---------------------------------------

def _deck_scene_text() -> str:
    from deck_emulator.legacy.deck import read_deck

    return Scene.from_deck(read_deck(STEEL40_DECK), name="steel40").to_toml()


STEEL40_DECK = Path(__file__).resolve().parents[2] / "decks" / "steel40.dat"


@pytest.mark.parametrize("old,new,key", [
    ("mass_slug = 15.1", "mass_slug = " + "9" * 400, "post.mass_slug"),
    ("mass_slug = 15.1", "mass_slug = inf", "post.mass_slug"),
    ("mass_slug = 15.1", "mass_slug = nan", "post.mass_slug"),
])
def test_numbers_beyond_a_double_or_not_finite_name_the_key(old, new, key):
    text = _deck_scene_text()
    assert old in text
    with pytest.raises(SceneError, match=re.escape(key)) as info:
        Scene.from_toml(text.replace(old, new, 1))
    assert "\n" not in str(info.value)


def test_a_zero_attitude_quaternion_names_the_key():
    data = tomllib.loads(_deck_scene_text())
    for q in ([0.0, 0.0, 0.0, 0.0], [1e-300, 0.0, 0.0, 0.0]):
        data["initial"]["attitude_wxyz"] = q
        import tomli_w

        with pytest.raises(SceneError, match=re.escape("initial.attitude_wxyz")):
            Scene.from_toml(tomli_w.dumps(data))


def test_a_missing_table_is_named():
    with pytest.raises(SceneError, match=r"lacks post, environment"):
        Scene.from_toml('name = "x"\n')


def test_scene_files_are_size_capped_and_utf8(tmp_path):
    from deck_emulator.vocabulary.scene import MAX_SCENE_BYTES, read_scene

    good = tmp_path / "s.toml"
    good.write_text(_deck_scene_text())
    assert read_scene(good).post.mass_slug == 15.1  # the deck's W (card 1)
    big = tmp_path / "big.toml"
    big.write_bytes(good.read_bytes() + b"#" * MAX_SCENE_BYTES)
    with pytest.raises(SceneError, match="larger than"):
        read_scene(big)
    bom = tmp_path / "bom.toml"
    bom.write_bytes(b"\xef\xbb\xbf" + good.read_bytes())
    with pytest.raises(SceneError, match="byte-order mark"):
        read_scene(bom)
    latin = tmp_path / "latin.toml"
    latin.write_bytes(good.read_bytes() + b"# \xe9\n")
    with pytest.raises(SceneError, match="not UTF-8"):
        read_scene(latin)
