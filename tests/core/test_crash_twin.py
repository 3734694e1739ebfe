"""The hysteretic leaf spring, the crash-test scene and the twin-luminaire post."""

import dataclasses

import numpy as np
import pytest

from deck_emulator.vocabulary.events import EventKind
from deck_emulator.core import free_flight, simulate
from deck_emulator.vocabulary.scene import LEGACY, PHYSICAL

#: the physical preset without the solid ground: a post and a car alone in space
ALONE = PHYSICAL.replace(solid_ground=False)
from deck_emulator.core.assembly import load_assembly
from deck_emulator.engine.assemblies import to_scene
from deck_emulator.core.kinematics import Kinematics
from deck_emulator.core.leaf_spring import (
    leaf_force,
    loading_force,
    loop_area,
    unloading_force,
    zero_force_set,
)
from deck_emulator.core.pair_hits import joint_ground_hit
from deck_emulator.core.rigid import angular_momentum_world, kinetic_energy
from deck_emulator.vocabulary.scene import LeafSpring, Scene
from deck_emulator.studies.crash_test import crash_scene

SPRING = LeafSpring()


def test_leaf_spring_curve_points():
    assert loading_force(0.25, SPRING) == pytest.approx(3000.0)
    assert loading_force(0.375, SPRING) == pytest.approx(6300.0)
    assert loading_force(0.5, SPRING) == pytest.approx(6300.0)  # constant beyond 4.5 in
    assert unloading_force(0.25, 0.375, SPRING) == pytest.approx(1500.0)  # 6300 - 38400/8
    assert zero_force_set(0.375, SPRING) == pytest.approx(0.125)  # 0.25 - 1500/12000
    # loaded below the knee the spring is elastic (u2 = k1)
    assert leaf_force(0.1, 0.2, SPRING) == pytest.approx(loading_force(0.1, SPRING))


def test_loop_area_closed_form():
    """Load to 4.5 in, unload: loading 375 + 375 + 206.25, unloading 487.5 + 93.75 ft lb."""
    assert loop_area(0.375, SPRING) == pytest.approx(956.25 - 581.25, rel=1e-14)
    # beyond the stop: + 6300 (x_m - 0.375) on loading; unloading is one steep triangle
    xm = 0.45
    load = 956.25 + 6300 * 0.075
    assert loop_area(xm, SPRING) == pytest.approx(load - 0.5 * 6300**2 / 38400, rel=1e-14)


def _energy(scene, Y):
    m, inertia, g = scene.post.mass_slug, scene.post.principal_inertia_slug_ft2, \
        scene.environment.gravity_ft_s2
    return (kinetic_energy(Y, m, inertia) + m * g * Y[2]
            + 0.5 * scene.vehicle.mass_slug * Y[14] ** 2)


def test_leaf_spring_dissipates_the_loop_area():
    """Post and car alone (no base forces, and no ground under the base, which starts on it):
    the mechanical energy lost between contact and separation equals the closed-form loop
    area at the peak compression reached."""
    s = crash_scene()
    env = dataclasses.replace(s.environment, ground_depth_ft=s.environment.ground_depth_ft + 10)
    s = dataclasses.replace(s, base=None, environment=env)  # 10 ft above the ground: no ground
    r = simulate(s, ALONE, t_max_s=0.2, rtol=1e-12, atol=1e-12)
    names = [e.name for e in r.events]
    assert "leaf spring reloads" not in names
    t_peak = next(e.time_s for e in r.events if e.name == EventKind.LEAF_UNLOADS)
    t_lost = r.vehicle_contact_lost_s
    from deck_emulator.core.model import assemble

    m = assemble(s, ALONE)
    x_m = m.components["vehicle contact"].compression(
        Kinematics(m, list(r.trajectory.state(t_peak))), "S")
    assert x_m > s.vehicle.leaf_spring.stop_ft  # the test goes past the U-bolt stop
    E0 = _energy(s, r.trajectory.state(0.0))
    E1 = _energy(s, r.trajectory.state(t_lost))
    assert E0 - E1 == pytest.approx(loop_area(x_m, s.vehicle.leaf_spring), rel=1e-7)


def _free_flight_invariants(scene, y0, t0, t1):
    r = free_flight(scene, y0, t0, PHYSICAL, t_max_s=t1)
    ts = np.linspace(t0, r.end_time_s, 300)
    Y = r.trajectory.state(ts)
    m, inertia, g = scene.post.mass_slug, scene.post.principal_inertia_slug_ft2, \
        scene.environment.gravity_ft_s2
    E = kinetic_energy(Y, m, inertia) + m * g * Y[2]
    L = angular_momentum_world(Y, inertia)
    return np.max(np.abs(E - E[0])) / abs(E[0]), \
        np.max(np.linalg.norm(L - L[:, [0]], axis=0)) / np.linalg.norm(L[:, 0])


def test_crash_test_free_flight_invariants():
    s = crash_scene()
    r = simulate(s, PHYSICAL, t_max_s=0.5)
    t0 = r.vehicle_contact_lost_s
    dE, dL = _free_flight_invariants(s, r.trajectory.state(t0), t0, r.hit.time_s)
    assert dE < 1e-9 and dL < 1e-9


@pytest.fixture(scope="module")
def twin():
    a, _, _ = load_assembly("twin")
    return a


def test_twin_free_flight_invariants(twin):
    s = to_scene(twin, template="steel40_a15")
    r = simulate(s, PHYSICAL, t_max_s=2.0)
    t0 = r.vehicle_contact_lost_s
    dE, dL = _free_flight_invariants(s, r.trajectory.state(t0), t0, t0 + 0.5)
    assert dE < 1e-9 and dL < 1e-9


def test_twin_planar_lands_on_r_and_u_together(twin):
    s = to_scene(twin, template="steel40")
    assert s.post.principal_tilt_rad == 0.0  # symmetric: the motion stays in XX-ZZ
    r = joint_ground_hit(simulate(s, LEGACY))
    assert r.hit.message == "THE POST HAS HIT THE GROUND WITH POINTS R&U"
    pts = r.terminal_points_ft
    assert pts["R"][2] == pytest.approx(pts["U"][2], abs=1e-9)
    assert pts["R"][1] == pytest.approx(-pts["U"][1], abs=1e-9)


def test_twin_at_an_angle_lands_on_one_point(twin):
    r = joint_ground_hit(simulate(to_scene(twin, template="steel40_a30"), LEGACY))
    assert r.hit.point in ("R", "U", "P", "Q", "C")
    assert "R&U" not in r.hit.message
    other = {"R": "U", "U": "R"}.get(r.hit.point)
    if other:
        assert abs(r.terminal_points_ft[other][2]) > 0.1


def test_twin_scene_toml_round_trip(twin):
    s = to_scene(twin)
    assert Scene.from_toml(s.to_toml()) == s
    c = crash_scene()
    assert Scene.from_toml(c.to_toml()) == c
