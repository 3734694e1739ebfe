"""The core ends cleanly, with a physical answer, where the physics is well posed (#16).

Sliding modes (the capped spring holding DIFF stationary; the base sticking), the solid
ground during the contact, friction as a reaction, stiff scenes, the work bound and the
outcome checks.  Expected values are closed forms or stated properties of the physics.
"""

from __future__ import annotations

import dataclasses
import math
import re
import warnings

import numpy as np
import pytest

from deck_emulator.vocabulary.events import EventKind
from deck_emulator.core import CoreError, simulate
from deck_emulator.vocabulary.scene import LEGACY, PHYSICAL
from deck_emulator.core import sliding
from deck_emulator.core.checks import check_outcome, check_summary
from deck_emulator.core.kinematics import IDX_VV, Kinematics
from deck_emulator.vocabulary.scene import (
    BaseFriction,
    BreakawayBase,
    CrushSpring,
    Environment,
    Post,
    PostInitialState,
    PostPoint,
    Scene,
    Vehicle,
)
from deck_emulator.core.solve import _checked

from test_scene import STEEL40, contact_delta_v_mph

FT_S_PER_MPH = 5280.0 / 3600.0


def deck(**changes) -> Scene:
    return Scene.from_deck({**STEEL40, **changes}, name="steel40*")


def heavy_post() -> Scene:
    return deck(**{n: round(STEEL40[n] * 10.0, 5) for n in ("W", "A", "B", "C", "FNA")})


def speed(mph: float) -> Scene:
    return deck(VVB=round(-mph * FT_S_PER_MPH, 4))


def _intervals(notes, label):
    out = []
    for n in notes:
        m = re.fullmatch(rf"{label}, ([0-9.e+-]+)\u2013([0-9.e+-]+) s", n)
        if m:
            out.append((float(m.group(1)), float(m.group(2))))
    return out


# --------------------------------------------------------------------------------------
# the sliding mode of the capped spring: a block, a car, a closed form


def _block_scene(m, M, k, v0, vb0, R, Fc, W):
    """A 'block': the post with every force through its mass centre's line along XX (the
    spring at S = (1, 0, 0), the friction at Q = (-0.5, 0, 0); no gravity, no normal
    force), so it translates along XX only: one degree of freedom, and the car another."""
    post = Post(
        m,
        3351.41,
        3282.6,
        69.68,
        top=PostPoint(0.0, 0.0, 1.0),
        base=PostPoint(-0.5, 0.0, 0.0),
        first_impact=PostPoint(1.0, 0.0, 0.0),
    )
    vehicle = Vehicle(
        mass_slug=M, initial_velocity_ft_s=v0, first_spring=CrushSpring(k), force_cap_lb=Fc
    )
    return Scene(
        post=post,
        environment=Environment(1.0e6, 0.0),
        initial=PostInitialState(velocity_body_ft_s=(vb0, 0.0, 0.0)),
        vehicle=vehicle,
        base=BreakawayBase(0.0, 0.4166, BaseFriction(R, W)),
    )


def test_capped_spring_holds_diff_stationary_closed_form():
    # block m moving at vb0, car M at v0 (both towards -XX), spring k, cap Fc, a constant
    # friction R on the block (the listing's kind) over its first W ft of travel
    m, M, k, v0, vb0, R, Fc, W = 15.1, 100.0, 33000.0, -58.66, -29.33, 2000.0, 1200.0, 3.0
    scene = _block_scene(m, M, k, v0, vb0, R, Fc, W)
    options = PHYSICAL.replace(force_cap_from_s=0.001, friction_reaction=False)
    r = simulate(scene, options, t_max_s=0.2)

    # closed form.  Compression c = car travel - block travel:
    # c'' = -w^2 c + R/m, c(0) = 0, c'(0) = vb0 - v0; the cap engages when c' = 0 (DIFF
    # stops decreasing), at the largest compression, where k c >> Fc
    w = math.sqrt(k * (1.0 / m + 1.0 / M))
    c0 = R / (m * w * w)
    a_, b_ = -c0, (vb0 - v0) / w
    t1 = (math.pi - math.atan(b_ / c0)) / w
    c_max = c0 + a_ * math.cos(w * t1) + b_ * math.sin(w * t1)
    x1 = vb0 * t1 + R * t1**2 / (2 * m) - (k / m) * (
        c0 * t1**2 / 2 + a_ * (1 - math.cos(w * t1)) / w**2 + b_ * (t1 / w - math.sin(w * t1) / w**2)
    )
    v1 = vb0 + R * t1 / m - (k / m) * (
        c0 * t1 + a_ * math.sin(w * t1) / w + b_ * (1 - math.cos(w * t1)) / w
    )
    # on the surface block and car keep one speed: F (1/m + 1/M) = R/m -- a force between
    # the cap and the spring's, so the cap holds (a sliding mode) -- and both decelerate
    # at R / (m + M) until the block leaves the friction's travel W
    f_eq = R * M / (m + M)
    assert Fc < f_eq < k * c_max
    acc = R / (m + M)
    tau = (-v1 - math.sqrt(v1 * v1 - 2 * acc * (x1 + W))) / acc
    t2 = t1 + tau

    (held,) = _intervals(r.notes, "cap holding")
    assert held[0] == pytest.approx(t1, abs=1e-6)
    assert held[1] == pytest.approx(t2, abs=1e-6)
    ev = {e.name: e.time_s for e in r.events}
    assert ev[EventKind.FORCE_CAP] == pytest.approx(t1, abs=1e-9)
    assert ev["base friction ends"] == pytest.approx(t2, abs=1e-9)

    model = r.trajectory._model
    seen = 0
    for seg in r.trajectory.segments:
        if seg.phase != "contact":
            continue
        for t in np.linspace(seg.t0, seg.t1, 7)[1:-1]:
            y = seg.solution(t)
            f = sliding.vehicle_force(model, t, y, seg.mode)
            if seg.mode.cap_sliding:
                seen += 1
                assert f == pytest.approx(f_eq, rel=1e-9)  # the force that holds DIFF
                v_block = Kinematics(model, y).point_velocity("S")[0]
                assert v_block == pytest.approx(y[IDX_VV], abs=1e-8)
            elif t2 < t < t2 + 0.01:
                assert seg.mode.cap_engaged  # left at the lower bound: the cap itself
                assert f == pytest.approx(Fc, rel=1e-12)
    assert seen > 0


def _sigma_dot(model, mode, t, y):
    """d/dt of the cap's switching function (``dDIFF/dt`` of S) under the plain (non-sliding)
    force law of ``mode``: a central difference along the model's own derivative, so the
    Filippov construction under test is not used to check itself."""
    contact = model.components["vehicle contact"]
    d = np.asarray(model.contact_rhs(mode)(t, np.asarray(y)))
    h = 1e-7
    rate = [contact.diff_rate(Kinematics(model, list(np.asarray(y) + k * h * d))) for k in (1, -1)]
    return (rate[0] - rate[1]) / (2 * h)


def test_the_cap_holds_diff_where_plain_switching_would_chatter():
    """The 100 mph car with the cap armed at the stability study's 21st step: wherever the
    core holds the cap's surface (a sliding mode), the physics says why and how.

    * entered where plain switching would chatter: on the surface ``dDIFF/dt = 0`` the capped
      spring drives ``dDIFF/dt`` below zero (which releases the cap) and the uncapped spring
      drives it above zero (which engages it again): each side points back to the surface;
    * while held, ``DIFF`` stays put and the spring force lies between the cap (``FCONST``)
      and the uncapped spring force ``CK * compression``;
    * it is left where that force reaches one of its bounds.

    The exit time against a closed form is the block's test above."""
    options = LEGACY.replace(force_cap_from_s=0.0084)
    r = simulate(speed(100), options, t_max_s=3.0, rtol=1e-9, atol=1e-9)
    model = r.trajectory._model
    contact = model.components["vehicle contact"]
    fconst = STEEL40["FCONST"]
    held = [seg for seg in r.trajectory.segments
            if seg.phase == "contact" and seg.mode.cap_sliding]
    assert held and _intervals(r.notes, "cap holding")
    for seg in held:
        capped = dataclasses.replace(seg.mode, cap_sliding=False, cap_engaged=True)
        uncapped = dataclasses.replace(seg.mode, cap_sliding=False, cap_engaged=False)
        start = seg.solution(seg.t0)
        kin = Kinematics(model, list(start))
        assert abs(contact.diff_rate(kin)) < 1e-6 * abs(start[IDX_VV])  # on the surface
        assert _sigma_dot(model, capped, seg.t0, start) < 0.0 < _sigma_dot(
            model, uncapped, seg.t0, start)
        diff0 = contact.diff(kin, "S")
        for t in np.linspace(seg.t0, seg.t1, 9):
            y = seg.solution(t)
            kin = Kinematics(model, list(y))
            assert contact.diff(kin, "S") == pytest.approx(diff0, abs=1e-6)  # ft: held
            f = sliding.vehicle_force(model, t, y, seg.mode)
            spring = contact.stiffness["S"] * contact.compression(kin, "S")
            assert fconst * (1 - 1e-9) <= f <= spring * (1 + 1e-9)
        end = seg.solution(seg.t1)
        kin = Kinematics(model, list(end))
        f = sliding.vehicle_force(model, seg.t1, end, seg.mode)
        spring = contact.stiffness["S"] * contact.compression(kin, "S")
        assert min(abs(f - fconst), abs(f - spring)) < 1e-6 * fconst  # left at a bound


# --------------------------------------------------------------------------------------
# the scenes that failed: 100 mph and the heavy post end with a hit under both presets


@pytest.mark.parametrize("make", [lambda: speed(100), heavy_post], ids=["speed-100", "heavy-post"])
@pytest.mark.parametrize("options", [LEGACY, PHYSICAL], ids=["legacy", "physical"])
def test_failed_scenes_end_with_a_checked_hit(make, options):
    r = simulate(make(), options, t_max_s=3.0)
    assert r.hit is not None
    assert check_outcome(r) == []
    lo, hi = 0.0, abs(r.scene.vehicle.initial_velocity_ft_s) / FT_S_PER_MPH
    assert lo <= contact_delta_v_mph(r) <= hi
    if options is LEGACY:
        # the cap held DIFF stationary: the sliding mode is named with its interval
        held = _intervals(r.notes, "cap holding")
        assert held and all(b > a for a, b in held)


@pytest.mark.parametrize("mph", [80, 120])
def test_fast_cars_physical_never_pass_through_the_ground(mph):
    r = simulate(speed(mph), PHYSICAL, t_max_s=3.0)
    assert r.hit is not None and r.ground_passage is None
    depth = r.scene.environment.ground_depth_ft
    traj = r.trajectory
    ts = np.linspace(traj.t_start, r.hit.time_s, 400)
    for p in traj.point_names:
        assert np.min(traj.point(p, ts)[2] + depth) >= -1e-6


# --------------------------------------------------------------------------------------
# the ground during the contact


def _dropped_post(preset):
    # no normal force, thrown down along its axis at 20 ft/s: the post falls onto the
    # ground while a slow car (10 ft/s) still pushes its base
    return simulate(deck(FNA=0.0, VVB=-10.0, V3B=-20.0), preset, t_max_s=3.0)


def _fall_time():
    # Q starts ZZQO + HEIGHT = 0.5 ft above the ground and moves down at 20 cos(DELTA);
    # the car's push and the friction are horizontal: h = 0.5 - vz t - g t^2 / 2
    h = STEEL40["HEIGHT"] + STEEL40["ZZQO"]
    vz, g = 20.0 * math.cos(STEEL40["DELTA"]), STEEL40["G"]
    return (-vz + math.sqrt(vz * vz + 2 * g * h)) / g


def test_post_dropped_while_the_car_pushes_lands_physical():
    r = _dropped_post(PHYSICAL)
    assert r.hit is not None and r.hit.surface == "GROUND" and r.hit.point in ("Q", "C")
    assert r.vehicle_contact_lost_s is None  # the car still pushed
    # the post turns a little under the push: Q lands within 20 microseconds of the fall
    assert r.hit.time_s == pytest.approx(_fall_time(), abs=2e-5)
    q = r.trajectory.point("Q", r.hit.time_s)
    assert q[2] + STEEL40["HEIGHT"] == pytest.approx(0.0, abs=1e-9)
    assert check_outcome(r) == []
    assert any("still pushed the post" in n for n in r.notes)


def test_post_dropped_while_the_car_pushes_passes_through_legacy():
    r = _dropped_post(LEGACY)
    gp = r.ground_passage
    assert gp is not None and gp["point"] in ("Q", "C")
    # the listing's start-up kick changes the fall a little more than the push does
    assert gp["time_s"] == pytest.approx(_fall_time(), abs=2e-3)
    assert gp["depth_ft"] > 0.1  # deeper than any of the listing's ground tolerances
    assert r.hit.point == gp["point"] and r.hit.time_s == gp["time_s"]
    assert r.vehicle_contact_lost_s > r.hit.time_s  # the car still pushed
    assert any("passing through" in e.message for e in r.events)
    assert any("went through the ground" in n and "ft below the ground" in n for n in r.notes)
    assert check_outcome(r) == []


# --------------------------------------------------------------------------------------
# friction as a reaction


@pytest.mark.parametrize("force", [930.0, 93000.0])
def test_friction_never_accelerates_the_base(force):
    s = deck()
    s = dataclasses.replace(
        s, base=dataclasses.replace(s.base, friction=BaseFriction(force, 0.083333))
    )
    r = simulate(s, PHYSICAL, t_max_s=3.0)
    model = r.trajectory._model
    tol = 1e-6 * force  # ft lb/s: a base velocity of 1e-6 ft/s while it sticks
    steps = 0
    for seg in r.trajectory.segments:
        if seg.phase != "contact":
            continue
        ts = np.asarray(seg.solution.ts)
        for a, b in zip(ts[:-1], ts[1:]):
            nodes, weights = np.polynomial.legendre.leggauss(5)
            tk = 0.5 * (b - a) * nodes + 0.5 * (a + b)
            power = []
            for t in tk:
                y = seg.solution(t)
                f = sliding.friction_force(model, t, y, seg.mode)
                v = Kinematics(model, y).point_velocity("Q")[0]
                power.append(f * v)
                assert f * v <= tol
            work = 0.5 * (b - a) * float(np.dot(weights, power))
            assert -work >= -tol * (b - a)  # energy dissipated over the step >= 0
            steps += 1
    assert steps > 10
    # the base never travels towards the car (+XX) under its own friction
    traj = r.trajectory
    t_end = r.vehicle_contact_lost_s
    ts = np.linspace(0.0, t_end, 200)
    travel = traj.point("Q", ts)[0] - traj.point("Q", 0.0)[0]
    assert travel.max() <= 1e-9


# --------------------------------------------------------------------------------------
# stiff scenes, the work bound


def test_stiff_scene_gets_an_implicit_method_and_says_so():
    r = simulate(deck(WV=1e-6), PHYSICAL, max_wall_s=30.0)
    assert r.method == "Radau"
    assert any("Radau" in n and "stiffness ratio" in n for n in r.notes)


def test_no_numpy_warning_reaches_the_user():
    from deck_emulator.vocabulary.scene import StartupKick

    options = LEGACY.replace(startup_kick=StartupKick(step_s=0.0004 / 16))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = simulate(
            deck(CK=3.3e9, CT=3.3e9), options, method="DOP853", rtol=1e-9, atol=1e-9,
            t_max_s=3.0,
        )
    assert r.hit is not None
    assert any("numerical warning" in n for n in r.notes)


class _TickingClock:
    """A wall clock that moves on 10 ms at every reading: the core reads it once per
    right-hand-side evaluation, so the wall bound is reached after a known amount of work,
    whatever the machine's speed."""

    tick_s = 0.01

    def __init__(self):
        self.now = 0.0

    def perf_counter(self) -> float:
        self.now += self.tick_s
        return self.now


@pytest.mark.parametrize("changes", [{"WV": 1e-6}, {"B": 1e12}], ids=["WV=1e-6", "B=1e12"])
@pytest.mark.parametrize("options", [LEGACY, PHYSICAL], ids=["legacy", "physical"])
def test_every_run_ends_within_the_bound(changes, options, monkeypatch):
    from deck_emulator.core import solve

    clock = _TickingClock()
    monkeypatch.setattr(solve, "working_clock", clock.perf_counter)  # the bound's clock
    bound = 3.0
    try:
        r = simulate(deck(**changes), options, max_wall_s=bound)
    except CoreError as exc:
        assert "\n" not in str(exc)
        assert re.search(r"max_wall_s|triangle inequality", str(exc))
    else:
        assert r.hit is not None or r.no_hit_reason
    # the clock was read no more than the bound allows (and one reading past it, which ends
    # the run), plus the reading as the run starts
    assert clock.now <= bound + 4 * clock.tick_s


def test_the_wall_bound_is_what_ends_an_endless_run(monkeypatch):
    """On a clock that races, an ordinary scene is ended by the bound, in one line."""
    from deck_emulator.core import solve

    clock = _TickingClock()
    clock.tick_s = 1.0
    monkeypatch.setattr(solve, "working_clock", clock.perf_counter)  # the bound's clock
    with pytest.raises(CoreError, match=r"max_wall_s = 3 s") as info:
        simulate(deck(), LEGACY, max_wall_s=3.0)
    assert "\n" not in str(info.value)


# --------------------------------------------------------------------------------------
# the outcome checks


def test_check_summary_flags_absurd_numbers():
    flags = check_summary(
        hit="ground hit",
        hit_time_s=0.82,
        heights_at_hit_ft={"P": 3.0, "Q": -11.4, "R": 0.0},
        delta_v_contact_mph=-1.0,
        car_speed_mph=40.0,
        max_decel_g=math.inf,
        ground_tolerance_ft={"P": 0.1, "Q": 0.01, "R": 0.1},
        who="the listing",
    )
    assert "the listing reports a ground hit at 0.82 s with Q 11.4 ft below the ground" in flags[1]
    assert any("non-finite largest deceleration" in f for f in flags)
    assert any("negative delta-V" in f for f in flags)
    assert len(flags) == 3
    assert any(
        "more than the car's speed" in f
        for f in check_summary(hit="top hit", hit_time_s=1.0, delta_v_contact_mph=45.0, car_speed_mph=40.0)
    )
    assert check_summary(hit=None, hit_time_s=None) == ["the run reports no hit and names no reason"]
    assert check_summary(hit=None, hit_time_s=None, no_hit_reason="t_max reached") == []


def test_check_outcome_and_simulate_check():
    r = simulate(deck(), PHYSICAL)
    assert check_outcome(r) == []
    bad = dataclasses.replace(r, end_time_s=math.inf)
    assert any("non-finite end time" in f for f in check_outcome(bad))
    with pytest.raises(CoreError, match="outcome check failed: .*non-finite end time"):
        _checked(bad, True)
    # G = 0: the run has its largest force on the car, the registry no deceleration in g
    # (not an infinity)
    from deck_emulator.engine import CoreEngine, quantities

    o = CoreEngine(preset="physical", trace=False).run(deck(G=0.0))
    assert o.error is None and o.trajectory.peak_car_force(True) > 0.0
    assert quantities.value("max_decel_g", o) is None


def test_huge_gravity_is_no_windshield_hit_underground():
    # the listing's behaviour: with G = 1e6 the post sinks 7,700 ft during the contact and
    # "hits the windshield"; the core reports the ground reached, and names the rest
    r = simulate(deck(G=1.0e6), LEGACY)
    assert r.hit.surface == "GROUND"
    assert check_outcome(r) == []
    assert r.ground_passage["listing_hit"] == "THE POST HAS HIT THE WINDSHIELD OF THE VEHICLE"
    assert r.ground_passage["depth_at_listing_hit_ft"] > 1000.0
    rp = simulate(deck(G=1.0e6), PHYSICAL)
    assert rp.hit.surface == "GROUND" and check_outcome(rp) == []
