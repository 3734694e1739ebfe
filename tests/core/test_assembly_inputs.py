"""Description files answered key by key: every bad value is one line naming its key
(:class:`AssemblyError`), never a traceback, never the shipped crash test run instead."""

import importlib.resources
import re

import pytest

from deck_emulator.core.assembly import (
    MAX_DESCRIPTION_BYTES,
    AssemblyError,
    assembly_from_toml,
    load_assembly,
)
from deck_emulator.studies.crash_test import crash_description, crash_scene


def _shipped(name: str) -> str:
    return (importlib.resources.files("deck_emulator.assemblies") / f"{name}.toml").read_text()


STEEL = _shipped("steel")
CRASH = _shipped("crash_test")


def _refused(text: str, key: str) -> str:
    with pytest.raises(AssemblyError) as info:
        assembly_from_toml(text)
    msg = str(info.value)
    assert "\n" not in msg
    assert key in msg, msg
    return msg


def _with(text: str, old: str, new: str) -> str:
    assert old in text
    return text.replace(old, new, 1)


def test_an_empty_or_foreign_toml_is_refused_not_run_as_the_crash_test():
    for text in ("", "name = 'x'\n", "[run]\nspeed = 1\n"):
        _refused(text, "neither a [shaft] nor a [crash_test]")


@pytest.mark.parametrize("old,new,key", [
    ("density_lb_ft3 = 490.0", 'density_lb_ft3 = "490"', "density_lb_ft3"),
    ("density_lb_ft3 = 490.0", "density_lb_ft3 = -490.0", "density_lb_ft3"),
    ("density_lb_ft3 = 490.0", "density_lb_ft3 = true", "density_lb_ft3"),
    ("density_lb_ft3 = 490.0", "density_lb_ft3 = " + "9" * 400, "density_lb_ft3"),
    ("length_ft = 36.708", "length_ft = 0.0", "length_ft"),
    ("length_ft = 36.708", "length_ft = nan", "length_ft"),
    ("length_ft = 36.708", "length_ft = inf", "length_ft"),
    ("control = [0.775, 1.0]", "control = []", "control"),
    ("control = [0.775, 1.0]", 'control = ["a", 1.0]', "control[0]"),
    ('shape = "bezier"', 'shape = "zigzag"', "shape"),
    ("side = -1.0", "side = 0.5", "side"),
    ("weight_lb = 83.5", "weight_lb = -83.5", "weight_lb"),
    ("total_weight_lb = 485.07", "total_weight_lb = -1", "total_weight_lb"),
    ("s_height_ft = 1.0 ", "s_height_ft = 100.0 ", "s_height_ft"),
    ("[base]", "[base]\ncolour = 1", "colour"),
    ('name = "steel"', "name = 5", "name"),
])
def test_every_key_of_a_support_is_checked(old, new, key):
    _refused(_with(STEEL, old, new), key)


def test_non_utf8_and_oversized_files_are_named(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_bytes(STEEL.encode() + b"\n# \xff\xfe\n")
    with pytest.raises(AssemblyError, match="not UTF-8"):
        load_assembly(str(bad))
    big = tmp_path / "big.toml"
    big.write_bytes(b"#" * (MAX_DESCRIPTION_BYTES + 1))
    with pytest.raises(AssemblyError, match="larger than"):
        load_assembly(str(big))


def test_a_users_crash_test_is_the_one_used(tmp_path):
    # The shipped description's car runs at 40 ft/s; a copy at 400 ft/s must give a car
    # at 400 ft/s towards -XX (the scene's sign convention, crash_scene's docstring).
    copy = tmp_path / "fast.toml"
    copy.write_text(_with(CRASH, "vehicle_speed_ft_s = 40.0", "vehicle_speed_ft_s = 400"))
    _, extra, _ = load_assembly(str(copy))
    assert crash_scene(extra["crash_test"]).vehicle.initial_velocity_ft_s == -400.0
    assert crash_scene(crash_description(str(copy))).vehicle.initial_velocity_ft_s == -400.0
    assert crash_scene().vehicle.initial_velocity_ft_s == -40.0


@pytest.mark.parametrize("old,new,key", [
    ("post_weight_lb = 215.0", "post_weight_lb = -5", "post_weight_lb"),
    ("vehicle_speed_ft_s = 40.0", 'vehicle_speed_ft_s = "fast"', "vehicle_speed_ft_s"),
    ("base_on_ground = true", "base_on_ground = 1", "base_on_ground"),
    ("knee_ft = 0.25 ", "knee_ft = 0.0 ", "knee_ft"),
    ("loading_stiffness_lb_per_ft = [12000.0, 26400.0]", "loading_stiffness_lb_per_ft = [1.0]",
     "loading_stiffness_lb_per_ft"),
    ("gravity_ft_s2 = 32.174", "", "gravity_ft_s2"),
    ("cm_from_base_ft = 4.63", "cm_from_base_ft = 9.5", "cm_from_base_ft"),
    ("[crash_test]", "[crash_test]\nwheels = 4", "wheels"),
])
def test_every_key_of_a_crash_test_is_checked(old, new, key):
    _refused(_with(CRASH, old, new), key)


def test_the_messages_are_one_line_naming_the_key():
    msg = _refused(_with(STEEL, "length_ft = 36.708", "length_ft = -3"), "shaft.length_ft")
    assert re.fullmatch(r"shaft\.length_ft = -3 must be > 0", msg)


STEEL_WALL_IN = 0.25


def test_a_wall_beside_a_total_weight_is_refused_with_the_weight_it_gives():
    """total_weight_lb = 290 with [shaft] wall_in = 0.25: each decides the shaft's wall, and
    the wall wins in silence no more. The weight the wall gives, by the thin-wall formula (a
    tapered tube weighs rho * pi * t * L * (mean OD - t)) plus the base, arm and luminaire
    of the shipped steel post."""
    import math
    import tomllib

    text = _with(STEEL, "total_weight_lb = 485.07", "total_weight_lb = 290")
    text = _with(text, "length_ft = 36.708", f"length_ft = 36.708\nwall_in = {STEEL_WALL_IN}")
    msg = _refused(text, "total_weight_lb = 290 and shaft.wall_in = 0.25")
    data = tomllib.loads(STEEL)
    sh = data["shaft"]
    t = STEEL_WALL_IN / 12
    mean_od = (sh["base_od_in"] + sh["top_od_in"]) / 2 / 12
    tube = sh["density_lb_ft3"] * math.pi * t * sh["length_ft"] * (mean_od - t)
    parts = data.get("base", {}).get("weight_lb", 0.0) + sum(
        a["weight_lb"] + a["luminaire_weight_lb"] for a in data.get("arm", []))
    assert f"makes the post {tube + parts:.2f} lb" in msg
    assert msg.endswith("give one of them")


def test_a_control_point_a_straight_arm_does_not_read_is_refused():
    text = _with(STEEL, 'shape = "bezier"', 'shape = "straight"')
    _refused(text, 'control is not read by shape = "straight"')
    # without shape (straight, the default) too
    _refused(_with(STEEL, 'shape = "bezier"\n', ""), "control is not read")


def test_a_run_table_nothing_reads_is_refused():
    _refused(STEEL + "\n[run]\nspeed_mph = 20\n", "[run] is not read")
