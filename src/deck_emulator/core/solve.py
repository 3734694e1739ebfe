"""Integration of a model: phases chained by located events.

Contact with the car (spring at S, then at T) and free flight are integrated with
``scipy.integrate.solve_ivp`` (DOP853 by default; Radau, LSODA ... selectable).  Every
switch -- a spring losing contact, the force moving from S to T, the base friction and
normal force ending, the ``FCONST`` cap engaging -- is an event function located by
scipy's root finder on the step's dense output (to a few units in the last place of t);
the integration restarts from the event with the new contact mode.  No step halving.

scipy pitfalls handled here (see the project notes): an event that is zero at the start
of a segment and moving in its direction fires at once -- so after an event the next
segment either drops that function (a latch) or watches it in the opposite direction;
two crossings inside one step are missed -- so the step is bounded by ``max_step_s``;
segments are kept apart (no concatenated dense output with duplicate times).
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from .scene import PHYSICAL, ModelOptions, Scene
from .kinematics import IDX_VV, N_STATE
from .model import Model, assemble
from .regions import hit_message
from .result import MPH_PER_FT_S, CoreEvent, CoreResult, Hit, Segment, Trajectory

__all__ = ["CoreError", "simulate", "free_flight", "DEFAULT_RTOL", "DEFAULT_ATOL"]

DEFAULT_METHOD = "DOP853"
DEFAULT_RTOL = 1e-12
DEFAULT_ATOL = 1e-12
DEFAULT_MAX_STEP_S = 0.005
DEFAULT_T_MAX_S = 10.0

LISTING_MESSAGES = {
    "first spring lost": "THE POST HAS LOST CONTACT WITH FIRST SPRING",
    "vehicle contact lost": "THE POST HAS LOST CONTACT WITH THE VEHICLE",
}

# this many events in a row at the same instant is chattering (Zeno), not physics
_MAX_REPEATS = 50


class CoreError(RuntimeError):
    """The integration failed or an event chattered."""


class _Run:
    def __init__(self, model: Model, method, rtol, atol, max_step_s, t_max_s):
        self.model = model
        self.method = method
        self.rtol = rtol
        self.atol = atol
        self.max_step = max_step_s
        self.t_max = t_max_s
        self.segments: list[Segment] = []
        self.events: list[CoreEvent] = []
        self.nfev = 0
        self.hit: Hit | None = None
        self.first_lost: float | None = None
        self.vehicle_lost: float | None = None

    def _solve(self, fun, t0, y0, t1, events):
        sol = solve_ivp(
            fun,
            (t0, t1),
            y0,
            method=self.method,
            rtol=self.rtol,
            atol=self.atol,
            max_step=self.max_step,
            dense_output=True,
            events=events or None,
        )
        self.nfev += sol.nfev
        if sol.status == -1:
            raise CoreError(f"integration failed at t = {sol.t[-1]!r} s: {sol.message}")
        return sol

    @staticmethod
    def _normalised(y):
        y = np.array(y, dtype=float)
        y[6:10] /= np.linalg.norm(y[6:10])
        return y

    # -- contact phase

    def contact(self):
        m = self.model
        t, y = 0.0, self._normalised(m.y0)
        mode = m.initial_mode()
        schedule = m.schedule()
        repeats = 0
        while True:
            t_stop = min([s for s in schedule if s > t] + [self.t_max])
            specs = m.contact_events(mode)
            sol = self._solve(m.contact_rhs(mode), t, y, t_stop, specs)
            t_new, y_new = float(sol.t[-1]), sol.y[:, -1]
            self.segments.append(Segment(t, t_new, "contact", sol.sol, mode))
            repeats = repeats + 1 if t_new - t <= 1e-14 else 0
            if repeats > _MAX_REPEATS:
                raise CoreError(f"contact events chatter at t = {t_new!r} s (mode {mode})")
            t, y = t_new, self._normalised(y_new)
            if sol.status == 1:
                fired = [s for s, te in zip(specs, sol.t_events) if len(te) and te[-1] == t_new]
                if not fired:  # pragma: no cover - scipy always reports the terminal root
                    raise CoreError(f"integration stopped at t = {t_new!r} s without an event")
                for spec in fired:
                    mode, ended = m.transition(mode, spec.name, y)
                    self._log(spec.name, t)
                    if spec.name == "first spring lost":
                        self.first_lost = t
                    if ended:
                        if spec.name != "vehicle contact lost":
                            self._log("vehicle contact lost", t)
                        self.vehicle_lost = t
                        return t, y
            elif t >= self.t_max:
                return None, y
            else:
                mode = m.mode_at_time(mode, t, y)

    def _log(self, name, t):
        self.events.append(CoreEvent(name, t, LISTING_MESSAGES.get(name, "")))

    # -- free flight

    def free_flight(self, t0, y0):
        m = self.model
        checks = m.checks
        y0 = self._normalised(y0)
        inside = checks.inside(y0)
        if inside:
            region, surface = min(inside, key=lambda rs: checks.priority(rs[0]))
            self._set_hit(t0, region.point, surface)
            self.segments.append(Segment(t0, t0, "free flight", None))
            return
        specs = checks.events()
        sol = self._solve(m.free_rhs(), t0, y0, self.t_max, specs)
        candidates = []
        for i, (te, ye) in enumerate(zip(sol.t_events, sol.y_events)):
            for tk, yk in zip(te, ye):
                for region, surface in checks.entered(i, yk):
                    candidates.append((float(tk), checks.priority(region), region.point, surface))
        t_end = float(sol.t[-1])
        if candidates:
            t_first = min(c[0] for c in candidates)
            tied = [c for c in candidates if c[0] <= t_first + 1e-12]
            tk, _, point, surface = min(tied, key=lambda c: c[1])
            self._set_hit(tk, point, surface)
            t_end = tk
        self.segments.append(Segment(t0, t_end, "free flight", sol.sol))

    def _set_hit(self, t, point, surface):
        msg = hit_message(surface, point)
        self.hit = Hit(msg, t, point, surface)
        self.events.append(CoreEvent("hit", t, msg))

    # -- summary

    def max_vehicle_force(self):
        """Largest force on the car over the contact segments: (lb, time s)."""
        m = self.model
        best = (-math.inf, None)
        for seg in self.segments:
            if seg.phase != "contact" or seg.t1 <= seg.t0:
                continue
            mode = seg.mode
            ts = np.asarray(seg.solution.ts)
            fine = np.unique(
                np.concatenate([np.linspace(a, b, 9) for a, b in zip(ts[:-1], ts[1:])])
            )
            ys = seg.solution(fine)
            f = np.array([m.vehicle_force(tk, ys[:, k], mode) for k, tk in enumerate(fine)])
            k = int(np.argmax(f))
            fk, tk = f[k], fine[k]
            lo, hi = fine[max(k - 1, 0)], fine[min(k + 1, len(fine) - 1)]
            if hi > lo:
                r = minimize_scalar(
                    lambda s, sol=seg.solution, mode=mode: -m.vehicle_force(s, sol(s), mode),
                    bounds=(lo, hi),
                    method="bounded",
                    options={"xatol": 1e-12},
                )
                if -r.fun > fk:
                    fk, tk = -r.fun, float(r.x)
            if fk > best[0]:
                best = (fk, float(tk))
        return best


def _result(run: _Run, scene: Scene, options: ModelOptions, started: float) -> CoreResult:
    m = run.model
    traj = Trajectory(run.segments, m)
    end = run.hit.time_s if run.hit else traj.t_end
    delta_v = max_g = max_t = None
    if scene.vehicle is not None and run.vehicle_lost is not None:
        vv_loss = float(traj.state(run.vehicle_lost)[IDX_VV])
        delta_v = (abs(scene.vehicle.initial_velocity_ft_s) - abs(vv_loss)) * MPH_PER_FT_S
        f, max_t = run.max_vehicle_force()
        max_g = f / (m.vehicle_mass * m.gravity)
    terminal: dict[str, tuple[float, float, float] | None] = {}
    q0 = m._q0
    depth = scene.environment.ground_depth_ft
    for name in ("P", "Q", "R"):
        if name not in m.body_points or not traj.segments:
            terminal[name] = None if name not in m.body_points else _xl(m, m.y0, name, q0, depth)
            continue
        p = traj.point(name, min(end, traj.t_end))
        terminal[name] = (float(p[0] - q0[0]), float(p[1] - q0[1]), float(p[2] + depth))
    return CoreResult(
        scene=scene,
        options=options,
        method=run.method,
        rtol=run.rtol,
        atol=run.atol,
        events=tuple(sorted(run.events, key=lambda e: e.time_s)),
        hit=run.hit,
        first_spring_lost_s=run.first_lost,
        vehicle_contact_lost_s=run.vehicle_lost,
        delta_v_contact_mph=delta_v,
        max_decel_g=max_g,
        max_decel_time_s=max_t,
        terminal_points_ft=terminal,
        planar=scene.is_planar,
        end_time_s=end,
        nfev=run.nfev,
        run_time_s=time.perf_counter() - started,
        trajectory=traj,
    )


def _xl(m, y, name, q0, depth):
    from .kinematics import Kinematics

    p = m.point_position(Kinematics(m, list(y)), name)
    return (p[0] - q0[0], p[1] - q0[1], p[2] + depth)


def simulate(
    scene: Scene,
    options: ModelOptions = PHYSICAL,
    *,
    method: str = DEFAULT_METHOD,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    max_step_s: float = DEFAULT_MAX_STEP_S,
    t_max_s: float = DEFAULT_T_MAX_S,
) -> CoreResult:
    """Run ``scene`` from t = 0: contact with the car (if it has one), then free flight
    until the first hit (or ``t_max_s``)."""
    started = time.perf_counter()
    model = assemble(scene, options)
    run = _Run(model, method, rtol, atol, max_step_s, t_max_s)
    if scene.vehicle is None:
        run.free_flight(0.0, model.y0)
    else:
        t, y = run.contact()
        if t is not None:
            run.free_flight(t, y)
    return _result(run, scene, options, started)


def free_flight(
    scene: Scene,
    state,
    t0_s: float = 0.0,
    options: ModelOptions = PHYSICAL,
    *,
    method: str = DEFAULT_METHOD,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    max_step_s: float = DEFAULT_MAX_STEP_S,
    t_max_s: float | None = None,
) -> CoreResult:
    """Free flight of the post from ``state`` (15 numbers, the layout of
    :class:`~.result.Trajectory`) at ``t0_s`` until the first hit or ``t_max_s``."""
    started = time.perf_counter()
    model = assemble(scene, options)
    state = np.asarray(state, dtype=float)
    if state.shape != (N_STATE,):
        raise ValueError(f"state must have {N_STATE} numbers, got shape {state.shape}")
    t_max = t0_s + DEFAULT_T_MAX_S if t_max_s is None else t_max_s
    run = _Run(model, method, rtol, atol, max_step_s, t_max)
    run.free_flight(t0_s, state)
    return _result(run, scene, options, started)
