"""The modern core against references nobody here wrote.

Tolerances are stated in the quantity's own unit (ft, rad, rad/s, s), skyfield-style,
through :func:`compare`.  References: closed forms of rigid-body mechanics (steady
precession; Landau-Lifshitz section 37 via ``scipy.special.ellipj``), the parabola, the
listing's own force and torque formulas, and MuJoCo.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipj

from deck_emulator.vocabulary.events import EventKind
from deck_emulator.core import (ContactMode, angular_momentum_world, assemble,
                                attitude_angle_between, free_flight, kinetic_energy, simulate)
from deck_emulator.vocabulary.scene import LEGACY, PHYSICAL
from deck_emulator.core import laws
from deck_emulator.core import model as core_model
from deck_emulator.core.model import Kinematics
from deck_emulator.core.rigid import quat_about_axis, quat_multiply, rotation_matrix
from deck_emulator.vocabulary.scene import (
    CrushSpring,
    Environment,
    Post,
    PostInitialState,
    PostPoint,
    Scene,
    Vehicle,
    VehicleBody,
)

from test_scene import STEEL40, contact_delta_v_mph, steel40

FT = 1.0
SECOND = 1.0
RAD = 1.0
NS = 1e-9 * SECOND


def compare(value, expected, epsilon, unit=""):
    """Assert ``|value - expected| <= epsilon`` element-wise, reporting in ``unit``."""
    value, expected = np.asarray(value, dtype=float), np.asarray(expected, dtype=float)
    err = np.max(np.abs(value - expected)) if value.size else 0.0
    assert err <= epsilon, f"off by {err:.3e} {unit} (allowed {epsilon:.1e} {unit})"


@pytest.fixture(scope="module")
def runs():
    s = steel40()
    return {"legacy": simulate(s, LEGACY), "physical": simulate(s, PHYSICAL)}


def post_only(
    inertia=(3351.41, 3282.6, 69.68),
    tilt=0.0,
    initial=None,
    depth=1.0e9,
    gravity=32.174,
    points=None,
) -> Scene:
    """A post and nothing else (no car, no base): it starts in free flight."""
    points = points or {}
    initial = initial or PostInitialState()
    post = Post(
        15.1,
        *inertia,
        top=points.get("P", PostPoint(0.0, 0.0, 16.938)),
        base=points.get("Q", PostPoint(0.0, 0.0, -19.77)),
        principal_tilt_rad=tilt,
        luminaire_end=points.get("R"),
    )
    return Scene(post=post, environment=Environment(depth, gravity), initial=initial)


# --------------------------------------------------------------------------------------
# the steel40 runs


def test_steel40_runs_end_with_a_listing_message(runs):
    for name, r in runs.items():
        assert r.hit is not None, name
        assert r.hit.message.startswith("THE POST HAS HIT THE ")
        names = [e.name for e in r.events]
        assert (
            names.index(EventKind.LOST_FIRST_SPRING)
            < names.index(EventKind.LOST_VEHICLE)
            < names.index(EventKind.HIT)
        )
        assert r.first_spring_lost_s <= r.vehicle_contact_lost_s < r.hit.time_s
        assert 0.0 < contact_delta_v_mph(r) < 58.66 * 3600 / 5280
        assert r.trajectory.peak_force(after_startup=True) > 0.0
        assert set(r.terminal_points_ft) == {"P", "Q", "R"}
        # the hit point is on its surface: ZL = 0 (physical) or 0.1 ft (listing's band)
        zl = r.terminal_points_ft[r.hit.point][2]
        compare(zl, 0.1 if name == "legacy" else 0.0, 1e-9, "ft")


def test_legacy_first_step_is_the_listings(runs):
    """At t = H = 0.0004 s the listing has W2A=0.0545, THA=0.000022, V1A=H*F1B/W,
    VVA=VVB+(H/WV)*FSB, XCMA=(H/2)*V1A."""
    r = runs["legacy"]
    h = 0.0004
    y = r.trajectory.state(h)
    q_tilt = quat_about_axis((1.0, 0.0, 0.0), 0.1463)
    compare(attitude_angle_between(q_tilt, y[6:10]), 0.000022, 1e-15, "rad")
    compare(y[10:13], (0.0, 0.0545, 0.0), 1e-15, "rad/s")
    compare(y[3], h * -10000.0 / 15.1, 1e-10, "ft/s")
    compare(y[14], -58.66 + h / 100.0 * 10000.0, 1e-12, "ft/s")
    compare(y[0], h / 2 * (h * -10000.0 / 15.1), 1e-12, "ft")
    # the listing's V3A stays 0 at its first step; the core's omega x V term moves it by
    # about W2*V1*H/2 ~ 3e-6 ft/s
    compare(y[5], 0.0, 1e-5, "ft/s")


def test_contact_events_located_to_a_nanosecond(runs):
    """Each contact event's function is zero at the located time: |g| / |g'| < 1 ns."""
    for name, r in runs.items():
        model = assemble(r.scene, r.options)
        contact = model.components["vehicle contact"]
        for e in r.events:
            if e.name == EventKind.HIT:
                continue
            t = e.time_s

            def g(t, e=e, r=r, model=model, contact=contact):
                kin = Kinematics(model, r.trajectory.state(t))
                if e.name in (EventKind.LOST_FIRST_SPRING,):
                    return contact.separation(kin, "S")
                if e.name == EventKind.LOST_VEHICLE:
                    return contact.separation(kin, "T")
                if e.name == "spring force moves to T":
                    return contact.diff(kin, "S") - r.options.spring_switch_ft
                if e.name == "normal force released":
                    return model.base_travel(kin.y) + r.scene.base.normal_release_ft
                if e.name.startswith("base friction"):
                    return model.base_travel(kin.y) + model.components["base friction"].window_ft
                if e.name.startswith("force cap"):
                    return contact.diff_rate(kin)
                raise AssertionError(e.name)

            dt = 1e-6
            t_lo, t_hi = max(t - dt, 0.0), min(t + dt, r.trajectory.t_end)
            slope = (g(t_hi) - g(t_lo)) / (t_hi - t_lo)
            assert abs(g(t) / slope) < 1 * NS, (name, e.name, g(t), slope)


def test_physical_run_starts_exactly_at_theta_zero(runs):
    """The physical preset has no start-up kick: the post starts upright, theta = 0, where
    the listing's ``PHIDA=(-1.0/SIN(THA))*PFORK`` divides by zero -- the core runs."""
    r = runs["physical"]
    q0 = r.trajectory.state(0.0)[6:10]
    compare(attitude_angle_between(q0, quat_about_axis((1, 0, 0), 0.1463)), 0.0, 0.0, "rad")
    assert np.all(np.isfinite(r.trajectory.state(np.linspace(0, r.hit.time_s, 200))))


# --------------------------------------------------------------------------------------
# free-flight invariants, for every propagator


@pytest.mark.parametrize(
    "method, rtol, bound",
    [("DOP853", None, 1e-9), ("Radau", 1e-10, 1e-8), ("LSODA", 1e-10, 1e-8), ("RK45", 1e-10, 1e-8)],
)
def test_free_flight_conserves_energy_and_angular_momentum(runs, method, rtol, bound):
    """From the physical run's state at loss of contact: energy and angular momentum about
    the mass centre, relative change < ``bound`` (DOP853 at the default tolerances)."""
    r0 = runs["physical"]
    s = r0.scene
    y0 = r0.trajectory.state(r0.vehicle_contact_lost_s)
    kw = {} if rtol is None else {"rtol": rtol, "atol": rtol}
    r = free_flight(s, y0, r0.vehicle_contact_lost_s, PHYSICAL, method=method, **kw)
    assert r.hit is not None
    ts = np.linspace(r0.vehicle_contact_lost_s, r.hit.time_s, 400)
    Y = r.trajectory.state(ts)
    m, inertia, g = s.post.mass_slug, s.post.principal_inertia_slug_ft2, s.environment.gravity_ft_s2
    E = kinetic_energy(Y, m, inertia) + m * g * Y[2]
    L = angular_momentum_world(Y, inertia)
    assert np.max(np.abs(E - E[0])) / abs(E[0]) < bound
    assert np.max(np.linalg.norm(L - L[:, [0]], axis=0)) / np.linalg.norm(L[:, 0]) < bound


# --------------------------------------------------------------------------------------
# torque-free rotation against closed forms


def test_symmetric_post_steady_precession():
    """A = B: omega_3 constant, (omega_1, omega_2) turning at (C-A) omega_3 / A in the body;
    in space the axis 3 precesses about the fixed L at |L|/A."""
    A, C = 3300.0, 69.68
    w0 = (0.4, -0.1, 3.0)
    s = post_only(inertia=(A, A, C), initial=PostInitialState(angular_velocity_body_rad_s=w0))
    r = free_flight(s, assemble(s, PHYSICAL).y0, 0.0, PHYSICAL, t_max_s=10.0, max_step_s=0.05)
    assert r.hit is None
    t = np.linspace(0.0, 10.0, 201)
    Y = r.trajectory.state(t)
    Om = (C - A) * w0[2] / A
    w1 = w0[0] * np.cos(Om * t) - w0[1] * np.sin(Om * t)
    w2 = w0[0] * np.sin(Om * t) + w0[1] * np.cos(Om * t)
    compare(Y[10], w1, 1e-10, "rad/s")
    compare(Y[11], w2, 1e-10, "rad/s")
    compare(Y[12], w0[2], 1e-12, "rad/s")
    # in space: e3(t) = e3(0) turned about L by |L| t / A (Rodrigues)
    L = np.array(rotation_matrix(Y[6:10, 0])).reshape(3, 3) @ (np.array([A, A, C]) * np.array(w0))
    n = L / np.linalg.norm(L)
    e30 = r.trajectory.rotation(0.0)[:, 2]
    for k in range(0, t.size, 20):
        a = np.linalg.norm(L) / A * t[k]
        expect = (
            e30 * math.cos(a) + np.cross(n, e30) * math.sin(a) + n * (n @ e30) * (1 - math.cos(a))
        )
        compare(r.trajectory.rotation(t[k])[:, 2], expect, 1e-9, "(unit vector)")


@pytest.mark.parametrize(
    "inertia, w0",
    [((100.0, 200.0, 300.0), (1.0, 0.0, 0.8)), ((69.68, 3282.6, 3351.41), (0.5, 0.0, 3.0))],
)
def test_asymmetric_post_landau_lifshitz(inertia, w0):
    """I1 < I2 < I3, M^2 > 2 E I2, omega_2(0) = 0: omega = (A1 cn, A2 sn, A3 dn)(tau)."""
    I1, I2, I3 = inertia
    s = post_only(inertia=inertia, initial=PostInitialState(angular_velocity_body_rad_s=w0))
    r = free_flight(s, assemble(s, PHYSICAL).y0, 0.0, PHYSICAL, t_max_s=10.0, max_step_s=0.05)
    E = 0.5 * (I1 * w0[0] ** 2 + I2 * w0[1] ** 2 + I3 * w0[2] ** 2)
    M2 = (I1 * w0[0]) ** 2 + (I2 * w0[1]) ** 2 + (I3 * w0[2]) ** 2
    assert M2 > 2 * E * I2
    k = math.sqrt((I3 - I2) * (M2 - 2 * E * I1) / (I1 * I2 * I3))
    m = (I2 - I1) * (2 * E * I3 - M2) / ((I3 - I2) * (M2 - 2 * E * I1))
    A1 = math.sqrt((2 * E * I3 - M2) / (I1 * (I3 - I1)))
    A2 = math.sqrt((2 * E * I3 - M2) / (I2 * (I3 - I2)))
    A3 = math.sqrt((M2 - 2 * E * I1) / (I3 * (I3 - I1)))
    t = np.linspace(0.0, 10.0, 301)
    sn, cn, dn, _ = ellipj(k * t, m)
    Y = r.trajectory.state(t)
    scale = max(abs(x) for x in w0)
    compare(Y[10], A1 * cn, 1e-10 * scale, "rad/s")
    compare(Y[11], A2 * sn, 1e-10 * scale, "rad/s")
    compare(Y[12], A3 * dn, 1e-10 * scale, "rad/s")


# --------------------------------------------------------------------------------------
# free fall, events


def test_dropped_post_falls_as_a_parabola():
    """No car: the mass centre follows x0 + v0 t - g t^2/2 while the post tumbles."""
    v0_body = (3.0, -1.0, 12.0)
    ini = PostInitialState(
        mass_centre_ft=(1.0, 2.0, 3.0),
        velocity_body_ft_s=v0_body,
        angular_velocity_body_rad_s=(0.7, -0.3, 4.0),
    )
    s = post_only(tilt=0.1463, initial=ini, depth=20.27)
    r = simulate(s, PHYSICAL)
    assert r.vehicle_contact_lost_s is None and r.contact_end_s is None
    v0 = np.array(rotation_matrix(assemble(s, PHYSICAL).y0[6:10])).reshape(3, 3) @ v0_body
    t = np.linspace(0.0, r.hit.time_s, 101)
    expect = (
        np.array(ini.mass_centre_ft)[:, None]
        + v0[:, None] * t
        - np.array([0, 0, 32.174 / 2])[:, None] * t**2
    )
    compare(r.trajectory.mass_centre(t), expect, 1e-10, "ft")


@pytest.mark.parametrize("options, tol", [(PHYSICAL, 0.0), (LEGACY, 0.01)])
def test_ground_event_time_against_the_parabola(options, tol):
    """A post thrown up without rotation: Q (the lowest point) meets ZZ = -HEIGHT (+0.01 ft,
    the listing's Q band) at the root of the parabola, located within 1 ns."""
    vz = 7.5
    s = post_only(initial=PostInitialState(velocity_body_ft_s=(2.0, 0.0, vz)), depth=20.27)
    r = simulate(s, options)
    z0, g, h = -19.77, 32.174, 20.27
    # z0 + vz t - g t^2/2 = -h + tol
    t_hit = (vz + math.sqrt(vz * vz + 2 * g * (z0 + h - tol))) / g
    assert r.hit.point == "Q" and r.hit.surface == "GROUND"
    assert r.hit.message == "THE POST HAS HIT THE GROUND WITH POINT Q"
    compare(r.hit.time_s, t_hit, 1 * NS, "s")


def test_rotating_point_ground_event_time():
    """Post turning steadily about axis 2 while falling: R meets the ground at the root of
    z_cm(t) + (R's height)(t) = -HEIGHT, found by brentq on the closed form."""
    w2, depth = 2.5, 12.0
    R0 = PostPoint(0.0, 0.0, 10.0)
    ini = PostInitialState(angular_velocity_body_rad_s=(0.0, w2, 0.0))
    s = post_only(
        initial=ini,
        depth=depth,
        points={"R": R0, "Q": PostPoint(0, 0, -1.0), "P": PostPoint(0, 0, 1.0)},
    )
    r = simulate(s, PHYSICAL)
    zr = lambda t: -32.174 * t * t / 2 + 10.0 * math.cos(w2 * t) + depth  # noqa: E731
    t_hit = brentq(zr, 0.5, 1.0, xtol=1e-15)
    assert (r.hit.point, r.hit.surface) == ("R", "GROUND")
    compare(r.hit.time_s, t_hit, 1 * NS, "s")


def _car_scene():
    post = Post(
        15.1, 3351.41, 3282.6, 69.68,
        top=PostPoint(0.0, 0.0, -2.0),  # P below the mass centre: the first to come down
        base=PostPoint(0.0, 0.0, 5.0),
        first_impact=PostPoint(0.0, 0.0, 4.0),
    )  # fmt: skip
    body = VehicleBody(5.0, 7.0, 6.0, -3.6, -3.0, -3.4, -2.0, 2.0)
    vehicle = Vehicle(100.0, -10.0, CrushSpring(1.0), body=body)
    return Scene(post=post, environment=Environment(50.0), vehicle=vehicle)


G2 = 32.174 / 2


@pytest.mark.parametrize(
    "options, sv0, vv, surface, t_hit",
    [
        # the windshield plane XV = SV sweeps past P (ZZ_P < HTV) at SV = 0
        (PHYSICAL, 3.0, -10.0, "WINDSHIELD", 0.3),
        (LEGACY, 3.0, -10.0, "WINDSHIELD", 0.3),
        # P comes down on the top (SV <= 0 <= SV + 7): ZZ_P = -3 (or -2.9, the band)
        (PHYSICAL, -1.0, -5.0, "TOP", math.sqrt(1.0 / G2)),
        (LEGACY, -1.0, -5.0, "TOP", math.sqrt(0.9 / G2)),
        # the hood (SV - 5 <= 0 <= SV): ZZ_P = -3.6 (-3.5)
        (PHYSICAL, 4.9, -1.0, "HOOD", math.sqrt(1.6 / G2)),
        (LEGACY, 4.9, -1.0, "HOOD", math.sqrt(1.5 / G2)),
        # the trunk (SV + 7 <= 0 <= SV + 13): ZZ_P = -3.4 (-3.3)
        (PHYSICAL, -10.0, -1.0, "TRUNK", math.sqrt(1.4 / G2)),
        (LEGACY, -10.0, -1.0, "TRUNK", math.sqrt(1.3 / G2)),
        # the front bumper face XV = SV - 5 sweeps past P (the core's own word)
        (PHYSICAL, 9.0, -10.0, "FRONT", 0.4),
    ],
)
def test_car_surface_events(options, sv0, vv, surface, t_hit):
    s = _car_scene()
    y0 = list(assemble(s, PHYSICAL).y0)  # (no start-up kick: it would turn the post)
    y0[13], y0[14] = sv0, vv
    r = free_flight(s, y0, 0.0, options)
    assert (r.hit.surface, r.hit.point) == (surface, "P")
    compare(r.hit.time_s, t_hit, 1 * NS, "s")


# --------------------------------------------------------------------------------------
# no Euler-angle singularities


def test_passes_through_theta_zero():
    """Turning about axis 2 from theta = 0.3 back through the upright (theta = 0) and on."""
    tilt, w2 = 0.1463, -3.0
    ini = PostInitialState.from_euler(0.0, 0.3, 0.0, angular_velocity_body_rad_s=(0.0, w2, 0.0))
    s = post_only(tilt=tilt, initial=ini)
    r = free_flight(s, assemble(s, PHYSICAL).y0, 0.0, PHYSICAL, t_max_s=0.3)
    q_tilt = quat_about_axis((1.0, 0.0, 0.0), tilt)
    for t in np.linspace(0.0, 0.3, 31):
        expect = quat_multiply(q_tilt, quat_about_axis((0.0, 1.0, 0.0), 0.3 + w2 * t))
        compare(attitude_angle_between(r.trajectory.state(t)[6:10], expect), 0.0, 1e-10, "rad")


@pytest.mark.parametrize("psi0", [math.pi / 2 - 0.2, math.pi / 2])
def test_passes_through_cos_psi_zero(psi0):
    """Spinning about the post axis so that psi crosses pi/2 (cos psi = 0), or starts there."""
    w3 = 2.0
    ini = PostInitialState.from_euler(psi0, 0.4, 0.3, angular_velocity_body_rad_s=(0.0, 0.0, w3))
    s = post_only(tilt=0.1463, initial=ini)
    y0 = assemble(s, PHYSICAL).y0
    r = free_flight(s, y0, 0.0, PHYSICAL, t_max_s=0.3)
    for t in np.linspace(0.0, 0.3, 31):
        expect = quat_multiply(y0[6:10], quat_about_axis((0.0, 0.0, 1.0), w3 * t))
        compare(attitude_angle_between(r.trajectory.state(t)[6:10], expect), 0.0, 1e-10, "rad")


# --------------------------------------------------------------------------------------
# forces and torques are the listing's (eq. 3.28-3.31)


def test_forces_and_torques_match_the_listing_formulas():
    """At an arbitrary attitude, the body-axis forces and torques equal the listing's
    F1A..F3A and T1A..T3A (direction cosines, rotation parameters, moment arms in X,Y,Z)."""
    alpha, delta = 0.3, 0.1463
    s = Scene.from_deck(dict(STEEL40, ALPHA=alpha))
    model = assemble(s, LEGACY)
    psi, th, phi = 0.7, 0.25, -0.4
    q = quat_multiply(model.q_tilt, PostInitialState.quaternion_from_euler(psi, th, phi))
    y = [0.1, -0.2, 0.05, 1.0, 2.0, 3.0, *q, 0.1, 0.2, 0.3, 4.2, -50.0]
    kin = Kinematics(model, y)
    mode = ContactMode(normal_on=True, friction_on=True)
    acc = np.empty(7)  # the compiled law both roads evaluate
    laws.contact_loads(0.05, np.asarray(y, dtype=float), model.law_parameters,
                       model.mode_vector(mode), acc)
    R = np.array(kin.R).reshape(3, 3)
    F_body, T_body = R.T @ acc[0:3], R.T @ acc[3:6]

    FSA = laws.contact_spring_force(np.asarray(y, dtype=float), kin.R, model.law_parameters,
                                    model.mode_vector(mode))
    FFXA, FFYA, FNA, W, G = 930.0, 0.0, 485.07, 15.1, 32.174
    FSXA, FSYA = FSA * math.cos(alpha), FSA * math.sin(alpha)
    sd, cd = math.sin(delta), math.cos(delta)
    sf, cf, sp, cp, st, ct = (
        math.sin(phi),
        math.cos(phi),
        math.sin(psi),
        math.cos(psi),
        math.sin(th),
        math.cos(th),
    )
    D = np.array(
        [
            [-sf * sp + ct * cf * cp, cf * sp + ct * sf * cp, -st * cp],
            [-sf * cp - ct * cf * sp, cf * cp - ct * sf * sp, st * sp],
            [st * cf, st * sf, ct],
        ]
    )
    SQ = math.sin(th / 2) * math.sin((psi - phi) / 2)
    ET = math.sin(th / 2) * math.cos((psi - phi) / 2)
    ZE = math.cos(th / 2) * math.sin((psi + phi) / 2)
    CH = math.cos(th / 2) * math.cos((psi + phi) / 2)

    def arm(xo, yyo, zzo):
        yo, zo = yyo * cd + zzo * sd, -yyo * sd + zzo * cd
        return (
            xo * (SQ**2 - ET**2 - ZE**2 + CH**2)
            + 2 * yo * (SQ * ET - ZE * CH)
            + 2 * zo * (SQ * ZE + ET * CH),
            2 * xo * (SQ * ET + ZE * CH)
            + yo * (-(SQ**2) + ET**2 - ZE**2 + CH**2)
            + 2 * zo * (ET * ZE - SQ * CH),
            2 * xo * (SQ * ZE - ET * CH)
            + 2 * yo * (ET * ZE + SQ * CH)
            + zo * (-(SQ**2) - ET**2 + ZE**2 + CH**2),
        )

    XQ, YQ, ZQ = arm(0.0, 1.53, -19.77)
    XS, YS, ZS = arm(0.0, 1.53, -18.77)
    FX = FFXA - FSXA
    FY = FSYA * cd + FNA * sd - W * G * sd - FFYA * cd
    FZ = FFYA * sd + FNA * cd - W * G * cd - FSYA * sd
    F_listing = D @ np.array([FX, FY, FZ])
    TXA = (
        (FFYA * cd) * ZQ
        + (FNA * cd) * YQ
        - (FNA * sd) * ZQ
        + (FFYA * sd) * YQ
        - (FSYA * cd) * ZS
        - (FSYA * sd) * YS
    )
    TYA = FFXA * ZQ - (FNA * cd) * XQ - FSXA * ZS - (FFYA * sd) * XQ + (FSYA * sd) * XS
    TZA = -FFXA * YQ - (FFYA * cd) * XQ + FSXA * YS + (FSYA * cd) * XS + (FNA * sd) * XQ
    T_listing = D @ np.array([TXA, TYA, TZA])
    assert FSA > 1000.0  # a real spring force is being compared
    compare(F_body, F_listing, 1e-9, "lb")
    compare(T_body, T_listing, 1e-8, "lb ft")


# --------------------------------------------------------------------------------------
# assembled from the components the scene has


def test_absent_base_friction_is_never_evaluated(monkeypatch):
    def boom(*args, **kwargs):
        raise AssertionError("base friction evaluated although the scene has none")

    monkeypatch.setattr(core_model.BaseFriction, "pack", boom)
    monkeypatch.setattr(core_model.BaseFriction, "events", boom)
    monkeypatch.setattr(core_model.BaseFriction, "active_at", boom)
    s = steel40()
    no_friction = dataclasses.replace(s, base=dataclasses.replace(s.base, friction=None))
    r = simulate(no_friction, PHYSICAL)
    assert r.hit is not None
    assert not any(e.name.startswith("base friction") for e in r.events)
    # the same scene with friction does evaluate it (so the trap is live)
    with pytest.raises(AssertionError, match="base friction evaluated"):
        simulate(s, PHYSICAL)


def test_absent_points_are_never_computed(monkeypatch):
    calls: dict[str, int] = {}
    real = core_model.Model.point_position

    def counting(self, kin, letter):
        calls[letter] = calls.get(letter, 0) + 1
        return real(self, kin, letter)

    monkeypatch.setattr(core_model.Model, "point_position", counting)
    values = dict(STEEL40, XRO=0.0, YYRO=0.0, ZZRO=0.0, CT=0.0)
    r = simulate(Scene.from_deck(values), PHYSICAL)
    assert r.hit is not None and r.terminal_points_ft["R"] is None
    assert "R" not in calls and "T" not in calls
    assert "R" not in assemble(Scene.from_deck(values), PHYSICAL).body_points
    calls.clear()
    simulate(steel40(), PHYSICAL)
    assert calls.get("T", 0) > 0  # the second spring's point is used when it is there


def test_absent_car_body_means_no_car_checks():
    values = dict(STEEL40, HLEN=0.0, TLEN=0.0, TRLEN=0.0, HHV=0.0, HTV=0.0, HTRV=0.0)
    model = assemble(Scene.from_deck(values), LEGACY)
    assert {r.kind for r in model.checks.regions} == {"ground"}
    full = assemble(steel40(), LEGACY)
    assert {r.kind for r in full.checks.regions} == {"ground", "vehicle"}
    assert {r.point for r in full.checks.regions if r.kind == "vehicle"} == {"P", "R", "C"}


def test_planar_scene_stays_planar():
    """delta = 0, alpha = 0, every point in YY = 0: the motion stays in the plane YY = 0."""
    values = dict(STEEL40, DELTA=0.0)
    for k in ("YYSO", "YYPO", "YYQO", "YYRO", "YYCO", "YYTO"):
        values[k] = 0.0
    values["XRO"] = 8.47
    s = Scene.from_deck(values)
    r = simulate(s, LEGACY)
    assert r.hit is not None
    t = np.linspace(0.0, r.hit.time_s, 300)
    for name, pts in r.trajectory.points(t).items():
        compare(pts[1], 0.0, 1e-12, f"ft (YY of {name})")
    Y = r.trajectory.state(t)
    compare(Y[[10, 12]], 0.0, 1e-12, "rad/s")


# --------------------------------------------------------------------------------------
# an independent rigid-body engine


@pytest.mark.parametrize("preset", ["legacy", "physical"])
def test_mujoco_free_flight_lands_at_the_same_place(runs, preset):
    """MuJoCo (free body, RK4, h = 1e-4 s) from the core's state at loss of contact: at the
    last MuJoCo step before the core's hit, mass centre and P, Q, R within 1e-8 ft,
    attitude within 1e-9 rad."""
    mujoco = pytest.importorskip("mujoco")
    r = runs[preset]
    s = r.scene
    A, B, C = s.post.principal_inertia_slug_ft2
    xml = f"""<mujoco><option timestep="1e-4" integrator="RK4"
      gravity="0 0 {-s.environment.gravity_ft_s2!r}"/>
      <worldbody><body name="post"><freejoint/>
      <inertial pos="0 0 0" mass="{s.post.mass_slug!r}" diaginertia="{A!r} {B!r} {C!r}"/>
      </body></worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    t0 = r.vehicle_contact_lost_s
    y0 = r.trajectory.state(t0)
    d.qpos[0:3] = y0[0:3]
    d.qpos[3:7] = y0[6:10]  # w, x, y, z
    d.qvel[0:3] = r.trajectory.rotation(t0) @ y0[3:6]  # world-frame linear velocity
    d.qvel[3:6] = y0[10:13]  # body-frame angular velocity
    n = int((r.hit.time_s - t0) / 1e-4)
    for _ in range(n):
        mujoco.mj_step(m, d)
    t = t0 + n * 1e-4
    y = r.trajectory.state(t)
    compare(d.qpos[0:3], y[0:3], 1e-8, "ft")
    compare(attitude_angle_between(d.qpos[3:7], y[6:10]), 0.0, 1e-9, "rad")
    Rm = np.array(rotation_matrix(tuple(d.qpos[3:7]))).reshape(3, 3)
    model = assemble(s, r.options)
    for name in ("P", "Q", "R"):
        compare(
            d.qpos[0:3] + Rm @ np.array(model.body_points[name]),
            r.trajectory.point(name, t),
            1e-8,
            f"ft ({name})",
        )
