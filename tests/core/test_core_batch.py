"""The compiled core (core/laws.py, core/dop853.py, core/batch.py) against the scipy path.

The scipy path (``simulate``: ``solve_ivp``) is the reference: the batch must find the same
events (name, in the same order), the same hit (point, surface) and the same times and
positions within stated tolerances, at the default settings (rtol = atol = 1e-12).  The
compiled DOP853's order is checked on a problem with a closed-form solution.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from test_scene import STEEL40, contact_delta_v_mph, steel40

from deck_emulator.engine import quantities
from deck_emulator.vocabulary.events import EventKind
from deck_emulator.core import CoreError, dop853, laws, simulate, simulate_batch
from deck_emulator.vocabulary.scene import LEGACY, PHYSICAL
from deck_emulator.core import model as core_model
from deck_emulator.vocabulary.scene import Scene
from deck_emulator.decks import path as deck_path
from deck_emulator.legacy.deck import read_deck
from deck_emulator.vocabulary import defaults

#: the tolerances the batch holds against the scipy path at the default settings (the
#: defaults' rows: what the core states)
TIME_TOL_S = defaults.BATCH_AGREE_TIME_S
POSITION_TOL_FT = defaults.BATCH_AGREE_POSITION_FT
DELTA_V_TOL_MPH = defaults.BATCH_AGREE_DELTA_V_MPH
DECEL_TOL_G = defaults.BATCH_AGREE_DECEL_G


def assert_same(ref, got, label=""):
    """``got`` (the batch) answers as ``ref`` (the scipy path) does."""
    assert not isinstance(got, Exception), f"{label}: {got}"
    assert [e.name for e in got.events] == [e.name for e in ref.events], label
    for a, b in zip(ref.events, got.events):
        assert abs(a.time_s - b.time_s) <= TIME_TOL_S, (label, a, b)
        assert a.message == b.message, label
    assert (ref.hit is None) == (got.hit is None), label
    if ref.hit is not None:
        assert (got.hit.point, got.hit.surface, got.hit.message) == (
            ref.hit.point, ref.hit.surface, ref.hit.message), label
        assert abs(got.hit.time_s - ref.hit.time_s) <= TIME_TOL_S, label
    for k, p in ref.terminal_points_ft.items():
        q = got.terminal_points_ft[k]
        assert (p is None) == (q is None), (label, k)
        if p is not None:
            assert max(abs(x - y) for x, y in zip(p, q)) <= POSITION_TOL_FT, (label, k, p, q)
    for name, tol in (("contact_end_s", TIME_TOL_S),
                      ("vehicle_contact_lost_s", TIME_TOL_S), ("first_spring_lost_s", TIME_TOL_S)):
        a, b = getattr(ref, name), getattr(got, name)
        assert (a is None) == (b is None), (label, name)
        if a is not None:
            assert abs(a - b) <= tol, (label, name, a, b)
    car = ref.scene.vehicle
    for after_startup in (False, True):  # the largest force on the car, as a deceleration
        a, b = (r.trajectory.peak_force(after_startup) for r in (ref, got))
        assert (a is None) == (b is None), (label, after_startup)
        if a is not None:
            weight = car.mass_slug * ref.scene.environment.gravity_ft_s2
            assert abs(a - b) / weight <= DECEL_TOL_G, (label, after_startup, a, b)
    a, b = contact_delta_v_mph(ref), contact_delta_v_mph(got)
    assert (a is None) == (b is None) and (a is None or abs(a - b) <= DELTA_V_TOL_MPH), label
    # the crush ΔV (engine/core_engine.py): the car's velocity at the force cap, from the trajectory
    cap = next((e.time_s for e in ref.events if e.name == EventKind.FORCE_CAP), None)
    if cap is not None:
        va = ref.trajectory.vehicle(cap)[1]
        vb = got.trajectory.vehicle(cap)[1]
        assert abs(va - vb) <= 1e-6, label


def both(scenes, options):
    refs = [simulate(s, options) for s in scenes]
    return refs, simulate_batch(scenes, options)


# --------------------------------------------------------------------------------------
# the shipped decks and assemblies

DECKS = ("steel20", "steel20_a15", "steel20_a30", "steel40", "steel40_a15", "steel40_a30")


@pytest.mark.parametrize("options", [LEGACY, PHYSICAL], ids=["legacy", "physical"])
def test_shipped_decks_same_as_scipy(options):
    scenes = [Scene.from_deck(read_deck(str(deck_path(d))), name=d) for d in DECKS]
    refs, got = both(scenes, options)
    for d, a, b in zip(DECKS, refs, got):
        assert_same(a, b, d)
        assert b.integrator == "compiled" and a.integrator == "scipy"


def test_shipped_assemblies_and_crash_test_same_as_scipy():
    from deck_emulator.core.assembly import load_assembly
    from deck_emulator.engine.assemblies import to_scene
    from deck_emulator.studies.crash_test import crash_scene

    scenes = [to_scene(load_assembly(a)[0]) for a in ("steel", "twin", "aluminium")]
    for options in (LEGACY, PHYSICAL):
        refs, got = both(scenes, options)
        for a, b in zip(refs, got):
            assert_same(a, b, f"{a.scene.name} {options.name}")
    crash = crash_scene()
    for options in (LEGACY, PHYSICAL):  # the leaf spring, its hysteresis as located events
        refs, got = both([crash], options)
        assert_same(refs[0], got[0], f"crash test {options.name}")
        assert got[0].integrator == "compiled"
        assert EventKind.LEAF_UNLOADS in [e.name for e in got[0].events]


# --------------------------------------------------------------------------------------
# the stability study's extreme grid


def _grid_scene(spec):
    """The core's scene and options of one of the stability study's scenes (the study's own
    ``core_case``)."""
    from deck_emulator.studies.stability import core_case

    deck = read_deck(str(deck_path("steel40"))).with_values(**spec["deck"])
    return (spec["scene"], *core_case(spec, deck))


def _grid(quick):
    from deck_emulator.studies.stability import scenes

    base = read_deck(str(deck_path("steel40"))).values
    return [_grid_scene(s) for s in scenes(base, quick)]


def _check_grid(grid):
    for name, scene, options in grid:
        try:
            ref = simulate(scene, options)
        except (CoreError, ValueError, ArithmeticError) as exc:  # refused: so must the batch
            got = simulate_batch([scene], options)[0]
            assert isinstance(got, Exception), (name, exc)
            continue
        got = simulate_batch([scene], options)[0]
        assert_same(ref, got, name)
        for preset in (PHYSICAL,):
            try:
                ref = simulate(scene, preset)
            except (CoreError, ValueError, ArithmeticError):
                assert isinstance(simulate_batch([scene], preset)[0], Exception), name
                continue
            assert_same(ref, simulate_batch([scene], preset)[0], f"{name} physical")


@pytest.mark.parametrize("quick", [
    True, pytest.param(False, marks=pytest.mark.slow_corpus)], ids=["quick grid", "whole grid"])
def test_extreme_grid_same_as_scipy(quick):
    """Every scene of the stability study's extreme grid: its quick grid (each axis's ends) in
    the default suite, the whole grid (the quick one is a part of it) with -m slow_corpus."""
    _check_grid(_grid(quick=quick))


# --------------------------------------------------------------------------------------
# a random sample of perturbed scenes (fixed seed)


def perturbed_scenes(n=30, seed=25):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        v = dict(STEEL40)
        for key in ("W", "WV", "CK", "CT", "FNA"):
            v[key] = STEEL40[key] * float(rng.uniform(0.7, 1.3))
        # the moments together, C no smaller relatively: they stay a rigid body's
        f = float(rng.uniform(0.8, 1.2))
        v["A"], v["B"] = STEEL40["A"] * f, STEEL40["B"] * f
        v["C"] = STEEL40["C"] * f * float(rng.uniform(1.0, 1.3))
        v["VVB"] = -float(rng.uniform(20.0, 90.0))
        v["ALPHA"] = float(rng.uniform(0.0, 0.6))
        v["DELTA"] = STEEL40["DELTA"] * float(rng.uniform(0.0, 1.5))
        out.append(Scene.from_deck(v))
    return out


def test_perturbed_sample_same_as_scipy():
    scenes = perturbed_scenes()
    refs, got = both(scenes, LEGACY)
    for i, (a, b) in enumerate(zip(refs, got)):
        assert_same(a, b, f"perturbed {i}")
        assert b.integrator == "compiled"
    refs, got = both(scenes[:8], PHYSICAL)
    for i, (a, b) in enumerate(zip(refs, got)):
        assert_same(a, b, f"perturbed {i} physical")
        assert b.integrator == "compiled"


def test_batch_answers_in_order_with_errors_in_place():
    bad = Scene.from_deck(dict(STEEL40, A=1e12))  # no rigid body: CoreError
    good = steel40()
    out = simulate_batch([good, bad, good], LEGACY)
    assert isinstance(out[1], Exception) and "triangle inequality" in str(out[1])
    assert out[0].hit_message == out[2].hit_message == simulate(good, LEGACY).hit_message


# --------------------------------------------------------------------------------------
# the batch's wall bound (a starved or suspended machine)


def test_a_batch_past_its_wall_bound_stops_every_scene_it_has_not_finished():
    good = steel40()
    out = simulate_batch([good, good], LEGACY, max_wall_s=0.0)
    for got in out:  # the bound passed before either started
        assert isinstance(got, CoreError)
        assert str(got) == ("run stopped: the batch took more than max_wall_s = 0 s of wall "
                            "time (before this scene started)")
    (ran,) = simulate_batch([good], LEGACY, max_wall_s=math.inf)
    assert ran.hit_message == simulate(good, LEGACY).hit_message


def test_a_scene_in_progress_stops_at_its_next_segment_once_the_batch_is_past_its_bound(
        monkeypatch):
    """The clock is the test's: it passes the bound after the scene's first segment."""
    import deck_emulator.core.batch as batch

    solved, now = [], [0.0]
    real = batch._CompiledRun._solve

    def solve(self, *args, **kwargs):
        got = real(self, *args, **kwargs)
        solved.append(got.t[-1])
        now[0] = 100.0  # the machine was suspended during the first segment
        return got

    monkeypatch.setattr(batch._CompiledRun, "_solve", solve)
    monkeypatch.setattr(batch.laws, "working_clock", lambda: now[0])  # the bound's clock
    good = steel40()
    first, second = simulate_batch([good, good], LEGACY, max_wall_s=50.0)
    assert len(solved) == 1  # the first segment ran; the second did not start
    assert str(first) == ("run stopped: the batch took more than max_wall_s = 50 s of wall "
                          f"time (at t = {solved[0]:.6g} s)")
    assert "before this scene started" in str(second)


# --------------------------------------------------------------------------------------
# what a scene lacks is never evaluated, in the batch too


def test_absent_base_friction_is_never_evaluated_in_the_batch(monkeypatch):
    def boom(*args, **kwargs):
        raise AssertionError("base friction evaluated although the scene has none")

    monkeypatch.setattr(core_model.BaseFriction, "pack", boom)
    monkeypatch.setattr(core_model.BaseFriction, "events", boom)
    monkeypatch.setattr(core_model.BaseFriction, "active_at", boom)
    s = steel40()
    no_friction = dataclasses.replace(s, base=dataclasses.replace(s.base, friction=None))
    for options in (LEGACY, PHYSICAL):
        options = dataclasses.replace(options, listing_friction=False)
        (r,) = simulate_batch([no_friction], options)
        assert r.hit is not None
        assert not any(e.name.startswith("base friction") for e in r.events)
    with pytest.raises(AssertionError, match="base friction evaluated"):
        simulate_batch([s], PHYSICAL)


def test_absent_laws_are_never_evaluated_by_compiled_code(monkeypatch):
    """The compiled laws cannot be monkeypatched: instead every parameter of what the
    scene lacks (the friction, the second spring, the point R) is NaN.  A law that read
    one would spread the NaN into the state; the run is the same as without the poison."""
    real = core_model.Model._pack
    values = dict(STEEL40, XRO=0.0, YYRO=0.0, ZZRO=0.0, CT=0.0)
    s = Scene.from_deck(values)
    s = dataclasses.replace(s, base=dataclasses.replace(s.base, friction=None))
    options = dataclasses.replace(LEGACY, listing_friction=False)
    clean = simulate_batch([s], options)[0]

    def poisoned(self):
        P = real(self)
        assert "base friction" not in self.components and "R" not in self.body_points
        P[[laws.P_FR, laws.P_FR_WINDOW, laws.P_FR_REACTION, laws.P_K_T, laws.P_XV0_T]] = np.nan
        j = laws.P_POINTS + 3 * laws.LETTERS.index("R")
        P[j:j + 3] = np.nan
        return P

    monkeypatch.setattr(core_model.Model, "_pack", poisoned)
    got = simulate_batch([s], options)[0]
    assert got.integrator == "compiled"
    assert got.events == clean.events
    assert got.terminal_points_ft == clean.terminal_points_ft
    assert got.terminal_points_ft["R"] is None


# --------------------------------------------------------------------------------------
# the compiled DOP853


def _top(omega3=20.0):
    """An axisymmetric post (A = B) spinning about its axis, with a transverse angular
    velocity: torque-free, so ``w1 + i w2`` turns at ``lambda = (C - A) w3 / A`` (Euler's
    equations in closed form)."""
    P = np.zeros(laws.N_P)
    P[laws.P_MASS], P[laws.P_WV], P[laws.P_WEIGHT] = 1.0, 1.0, 32.174
    P[laws.P_I1], P[laws.P_I2], P[laws.P_I3] = 2.0, 2.0, 1.0
    y0 = np.zeros(15)
    y0[6] = 1.0
    y0[10], y0[11], y0[12] = 1.5, -0.5, omega3
    lam = (P[laws.P_I3] - P[laws.P_I1]) * omega3 / P[laws.P_I1]
    return P, y0, lam



@pytest.mark.parametrize("name", ["A", "B", "C", "E3", "E5", "D", "A_EXTRA", "C_EXTRA"])
def test_the_dop853_tableau_is_scipys(name):
    """The project's own copy of the Dormand-Prince 8(5,3) tableau, number for number the one
    scipy's public ``scipy.integrate.DOP853`` integrates with (exact: the same binary64s)."""
    from scipy.integrate import DOP853

    from deck_emulator.core import dop853_tableau

    ours, scipys = getattr(dop853_tableau, name), getattr(DOP853, name)
    assert ours.shape == scipys.shape and np.array_equal(ours, scipys)
    assert dop853_tableau.N_STAGES == DOP853.n_stages and dop853_tableau.ORDER == DOP853.order
    assert dop853_tableau.ERROR_ESTIMATOR_ORDER == DOP853.error_estimator_order

def _fixed_steps(phase, t0, y0, h, n_steps, P, M):
    """``n_steps`` steps of the compiled core's 8th-order formula (``dop853._rk_step``) with
    the fixed step ``h``, no error control."""
    n = y0.size
    acc, K = np.empty(7), np.empty((dop853.N_EXT, n))
    ytmp, y_new, f = np.empty(n), np.empty(n), np.empty(n)
    y, t = y0.copy(), t0
    for _ in range(n_steps):
        dop853._rhs(phase, t, y, P, M, acc, f)
        dop853._rk_step(phase, t, y, f, h, P, M, K, acc, ytmp, y_new)
        y[:] = y_new
        t += h
    return y


def test_dop853_order_is_eight():
    """Hairer's DOP853 (scipy's tableau) is of order 8: as the fixed step halves, the error
    at t = 1 falls by 2^8 = 256 (here: the transverse angular velocity against its closed
    form, and the whole state against a 16 times finer run)."""
    P, y0, lam = _top()
    M = np.full(laws.N_M, math.nan)
    T = 1.0
    exact = np.array([y0[10] * math.cos(lam * T) - y0[11] * math.sin(lam * T),
                      y0[10] * math.sin(lam * T) + y0[11] * math.cos(lam * T)])
    errs, states = [], {}
    for n in (16, 32, 64, 1024):
        y = _fixed_steps(dop853.PHASE_FREE, 0.0, y0, T / n, n, P, M)
        states[n] = y
        errs.append(float(np.max(np.abs(y[10:12] - exact))))
    ratios = [errs[i] / errs[i + 1] for i in range(2)]
    assert all(200.0 < r < 330.0 for r in ratios), (errs, ratios)
    whole = [float(np.max(np.abs(states[n] - states[1024]))) for n in (16, 32, 64)]
    ratios = [whole[i] / whole[i + 1] for i in range(2)]
    assert all(200.0 < r < 330.0 for r in ratios), (whole, ratios)


def test_dop853_adaptive_meets_its_tolerance_and_scipys_steps():
    """Adaptive: at rtol = atol = 1e-10 the top's angular velocity is right to ~1e-9 and the
    step count is scipy's DOP853's on the same problem (the same controller)."""
    from scipy.integrate import solve_ivp

    P, y0, lam = _top()
    M = np.full(laws.N_M, math.nan)
    no_ev = np.zeros((0, 4))
    r = dop853.solve(dop853.PHASE_FREE, 0.0, y0, 1.0, P, M, no_ev, np.zeros((0, 1)),
                     np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros((0, 7)), 1e-10, 1e-10,
                     np.inf, -1)
    assert r[0] == dop853.STATUS_FINISHED
    ts = r[2]
    y_end = dop853.dense_eval(ts, r[3], r[4], r[5], r[6], np.array([1.0]))[:, 0]
    exact = y0[10] * math.cos(lam) - y0[11] * math.sin(lam)
    assert abs(y_end[10] - exact) < 1e-8
    ref = solve_ivp(lambda t, y: laws.free_derivative(t, y, P), (0.0, 1.0), y0,
                    method="DOP853", rtol=1e-10, atol=1e-10, dense_output=True)
    assert abs(len(ts) - len(ref.t)) <= 1
    assert abs(r[1] - ref.nfev) <= 16  # one step's stages, at most


def test_brentq_transcription_finds_scipys_roots():
    """An event located on the dense output: the car's crush point's ground crossing of
    a free flight, by the compiled Brent and by scipy's brentq on the same interpolant."""
    from scipy.optimize import brentq

    P, y0, _ = _top(omega3=0.0)
    y0[2] = 1.0  # the mass centre 1 ft up, falling freely: z = 1 - g t^2 / 2
    M = np.full(laws.N_M, math.nan)
    EV = np.array([[laws.EV_GROUND, float(laws.LETTERS.index("P")), 1.0, 1.0]])
    r = dop853.solve(dop853.PHASE_FREE, 0.0, y0, 2.0, P, M, EV, np.zeros((0, 1)), np.zeros(0),
                     np.zeros(0, dtype=np.int64), np.zeros((0, 7)), 1e-12, 1e-12, np.inf, -1)
    assert r[0] == dop853.STATUS_EVENT
    t_hit = float(r[8][0])
    assert abs(t_hit - math.sqrt(2.0 / 32.174)) < 1e-12
    f = lambda t: 1.0 - 0.5 * 32.174 * t * t
    assert abs(t_hit - brentq(f, 0.0, 2.0, xtol=1e-15)) < 1e-12


# --------------------------------------------------------------------------------------
# through the engine: CoreEngine.run_batch hands its scenes to simulate_batch


@pytest.mark.parametrize("trace", [False, True])
def test_engine_batch_outcomes_match_the_reference_path(trace):
    from deck_emulator.engine import CoreEngine

    decks = [read_deck(str(deck_path(d))) for d in ("steel40", "steel20_a15", "steel40_a30")]
    decks.append(decks[0].with_values(W=0.0))  # refused: an outcome with its error
    batched = CoreEngine(trace=trace, batched=True).run_batch(decks)
    reference = CoreEngine(trace=trace, batched=False)
    for d, got in zip(decks, batched):
        ref = reference.run(d)
        assert got.error == ref.error
        if ref.error is not None:
            continue
        assert got.trajectory.integrator == "compiled" and ref.trajectory.integrator == "scipy"
        assert got.hit_message == ref.hit_message
        assert [(e.kind, e.point, e.surface) for e in got.events] == [
            (e.kind, e.point, e.surface) for e in ref.events]
        assert all(abs(a.time_s - b.time_s) <= TIME_TOL_S for a, b in zip(got.events, ref.events))
        for name in ("delta_v_contact_mph", "delta_v_crush_mph", "max_decel_g"):
            a, b = quantities.value(name, got), quantities.value(name, ref)
            assert (a is None) == (b is None) and (a is None or abs(a - b) <= 1e-6), name
        for k, p in ref.terminal.items():
            assert max(abs(x - y) for x, y in zip(p, got.terminal[k])) <= POSITION_TOL_FT, k
        if trace:  # the sampled arrays come from the compiled dense output
            assert got.t.shape == ref.t.shape or abs(got.t[-1] - ref.t[-1]) <= TIME_TOL_S
            n = min(len(got.t), len(ref.t)) - 2
            assert np.max(np.abs(got.points["P"][:n] - ref.points["P"][:n])) <= POSITION_TOL_FT


def test_the_steps_subdivided_at_once_are_linspaces_points_bit_for_bit():
    """The ground-passage check and the scipy path's force grid subdivide every step at once
    (result._subdivided): numpy's linspace, step by step, is the reference -- steps of every
    scale, a step of no length, and steps so short that linspace's step underflows to zero."""
    from deck_emulator.core.result import _subdivided

    rng = np.random.default_rng(7)
    cases = [np.cumsum(rng.random(30) * 10.0 ** rng.integers(-9, 1, 30)) for _ in range(50)]
    cases += [np.array([0.0, 0.1, 0.1, 0.2]), np.cumsum(np.full(6, 5e-324)),
              1e-300 + np.cumsum(np.full(6, 5e-324))]
    for ts in cases:
        for n in (5, 9):
            ref = np.unique(np.concatenate([np.linspace(a, b, n)
                                            for a, b in zip(ts[:-1], ts[1:])]))
            assert _subdivided(ts, n).tobytes() == ref.tobytes()
