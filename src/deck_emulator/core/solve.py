"""Integration of a model: phases chained by located events.

Contact with the car and free flight are integrated with ``scipy.integrate.solve_ivp``
(``method="auto"``: DOP853, and Radau for the contact of a stiff scene, :func:`stiffness`).
Every switch -- a spring losing contact, the force moving from S to T, the base's normal
force and friction ending, the ``FCONST`` cap, the sliding modes (:mod:`.sliding`), the
ground under ``ModelOptions.solid_ground`` -- is an event located on the step's dense
output; the integration restarts there in the new contact mode.  A segment on which an
explicit method meets a numerical warning is solved again with Radau and the notes say so.
``t_max_s``, ``max_evaluations`` and ``max_wall_s`` bound every run, and every outcome
passes :func:`~.checks.check_outcome`.

scipy fires an event that is zero at a segment's start, so after an event the next segment
drops that function or watches it the other way; it misses two crossings in one step, so
the step is bounded by ``max_step_s``; segments are kept apart (no duplicate times).
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np

from deck_emulator.vocabulary.events import (
    LOST_MESSAGES,
    POINT_NAMES,
    EventKind,
    hit_message,
)
from deck_emulator.vocabulary.scene import ModelOptions, Scene

from . import laws, sliding
from .checks import check_outcome, ground_tolerance_ft
from .kinematics import N_STATE, ContactMode
from .laws import working_clock
from .model import Model, assemble
from .result import CoreEvent, CoreResult, Hit, Segment, Trajectory, _subdivided

__all__ = [
    "CoreError",
    "simulate",
    "free_flight",
    "stiffness",
    "check_inertia",
]

from deck_emulator.vocabulary.defaults import (
    CORE_ATOL,
    CORE_METHOD,
    CORE_RTOL,
    MAX_EVALUATIONS,
    MAX_STEP_S,
    MAX_WALL_S,
    T_MAX_S,
)

from .kinematics import Kinematics

# this many events in a row at the same instant is chattering (Zeno), not physics
_MAX_REPEATS = 50


class CoreError(RuntimeError):
    """The integration failed or an event chattered."""


class _Budget(Exception):
    """The work bound was reached inside a right-hand side (turned into CoreError)."""


IMPLICIT_METHODS = ("Radau", "BDF", "LSODA")


def stiffness(model: Model) -> tuple[float, float, float]:
    """(ratio, fastest, slowest): an estimate of the contact phase's stiffness.

    ``fastest`` (rad/s): the crush spring's mode with the post's mass reduced by its
    rotation about the impact point and the car's mass in series,
    ``sqrt(K f (1/m + r^2/I_min + 1/WV))``; ``slowest``: the spring on the two masses
    together, ``sqrt(K f / (m + WV))``.  Their ratio is the scene's stiffness: a fast mode
    the answer does not need to resolve (a car of almost no mass on a stiff spring)."""
    contact = model.components.get("vehicle contact")
    if contact is None:
        return 1.0, 0.0, 0.0
    k = max(contact.stiffness.values()) * abs(contact.factor)
    if not k > 0.0:
        return 1.0, 0.0, 0.0
    m, wv = model.mass, model.vehicle_mass
    i_min = min(model.inertia[0], model.inertia[1])
    r2 = max(sum(c * c for c in model.body_points[p]) for p in contact.stiffness)
    fast = math.sqrt(k * (1.0 / m + r2 / i_min + 1.0 / wv))
    slow = math.sqrt(k / (m + wv))
    return fast / slow, fast, slow


#: above this stiffness ratio the contact phase is integrated with an implicit method
STIFF_RATIO = 100.0
#: the implicit method chosen for a stiff contact phase
STIFF_METHOD = "Radau"


class _Run:
    def __init__(
        self, model: Model, method, rtol, atol, max_step_s, t_max_s,
        max_evaluations=None, max_wall_s=None,
    ):
        self.model = model
        self.method = method
        self.contact_method = method
        self.free_method = method
        self.rtol = rtol
        self.atol = atol
        self.max_step = max_step_s
        self.t_max = t_max_s
        self.max_evaluations = max_evaluations
        self.max_wall_s = max_wall_s
        self.started = working_clock()  # compiling the core's code is not the run's time
        self.segments: list[Segment] = []
        self.events: list[CoreEvent] = []
        self.notes: list[str] = []
        self.nfev = 0
        self._evals = 0
        self.hit: Hit | None = None
        self.hit_in_contact = False
        self.first_lost: float | None = None
        self.vehicle_lost: float | None = None
        self.contact_end: float | None = None
        self.open_modes: dict[str, float] = {}
        self.ground_passage: dict | None = None
        if method == "auto":
            ratio, fast, slow = stiffness(model)
            self.free_method = "DOP853"
            if ratio > STIFF_RATIO:
                self.contact_method = STIFF_METHOD
                self.notes.append(
                    f"contact integrated with {STIFF_METHOD} (implicit): stiffness ratio "
                    f"{ratio:.3g} > {STIFF_RATIO:g} (fastest spring mode {fast:.3g} rad/s, "
                    f"slowest {slow:.3g} rad/s); free flight with DOP853"
                )
            else:
                self.contact_method = "DOP853"
            self.method = self.contact_method

    def integrator(self) -> str:
        """Who integrated the run (``CoreResult.integrator``)."""
        return "scipy"

    def _guarded(self, fun):
        def wrapped(t, y):
            self._evals += 1
            if self.max_evaluations is not None and self._evals > self.max_evaluations:
                raise _Budget(
                    f"the run needed more than max_evaluations = {self.max_evaluations} "
                    f"right-hand-side evaluations (at t = {t:.6g} s)"
                )
            if (
                self.max_wall_s is not None
                and working_clock() - self.started > self.max_wall_s
            ):
                raise _Budget(
                    f"the run took more than max_wall_s = {self.max_wall_s:g} s of wall time "
                    f"(at t = {t:.6g} s)"
                )
            return fun(t, y)

        return wrapped

    def _solve_once(self, fun, t0, y0, t1, events, method):
        from scipy.integrate import solve_ivp  # here: the compiled batch needs no scipy

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            sol = solve_ivp(
                self._guarded(fun),
                (t0, t1),
                y0,
                method=method,
                rtol=self.rtol,
                atol=self.atol,
                max_step=self.max_step,
                dense_output=True,
                events=events or None,
            )
        return sol, list(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught))

    def _solve(self, fun, t0, y0, t1, events, method=None):
        method = method or self.method
        try:
            sol, seen = self._solve_once(fun, t0, y0, t1, events, method)
            if seen and method not in IMPLICIT_METHODS:
                # an explicit method met a non-finite error estimate (a step far too long
                # for a stiff spring): solve the segment again with an implicit method
                sol2, seen2 = self._solve_once(fun, t0, y0, t1, events, STIFF_METHOD)
                self.notes.append(
                    f"{method} met a numerical warning ({'; '.join(seen)}) between "
                    f"t = {t0:.6g} s and {t1:.6g} s: that segment was solved again with "
                    f"{STIFF_METHOD}" + (f", which warned too ({'; '.join(seen2)})" if seen2 else "")
                )
                sol, seen = sol2, seen2
            elif seen:
                self.notes.append(
                    f"{method} met a numerical warning ({'; '.join(seen)}) between "
                    f"t = {t0:.6g} s and {t1:.6g} s and recovered (rejected the step)"
                )
        except _Budget as exc:
            raise CoreError(f"run stopped: {exc}") from None
        self.nfev += sol.nfev
        if sol.status == -1:
            raise CoreError(f"integration failed at t = {sol.t[-1]!r} s: {sol.message}")
        if not np.all(np.isfinite(sol.y[:, -1])):
            raise CoreError(f"integration failed at t = {sol.t[-1]!r} s: the state is not finite")
        return sol

    @staticmethod
    def _normalised(y):
        y = np.array(y, dtype=float)
        y[6:10] /= np.linalg.norm(y[6:10])
        return y

    # -- contact phase

    def _track_modes(self, old, new, t):
        was, now = sliding.mode_labels(old), sliding.mode_labels(new)
        for label in now - was:
            self.open_modes[label] = t
        for label in was - now:
            self._close_mode(label, t)

    def _close_mode(self, label, t):
        t0 = self.open_modes.pop(label)
        if t > t0:
            self.notes.append(f"{label}, {t0:.6g}\u2013{t:.6g} s")

    def contact(self):
        m = self.model
        t, y = 0.0, self._normalised(m.y0)
        mode = sliding.initial_mode(m)
        self._track_modes(ContactMode(), mode, 0.0)
        schedule = m.schedule()
        repeats = 0
        while True:
            t_stop = min([s for s in schedule if s > t] + [self.t_max])
            specs = sliding.contact_events(m, mode)
            sol = self._solve(
                m.contact_rhs(mode), t, y, t_stop, specs, self.contact_method
            )
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
                # a ground contact ends everything: take it first
                fired.sort(key=lambda s: not s.name.startswith("ground reached by "))
                for spec in fired:
                    old = mode
                    mode, ended, ground_point = sliding.after_event(m, mode, spec.name, t, y)
                    self._track_modes(old, mode, t)
                    if ground_point:
                        self._end_modes(t)
                        self.contact_end = t
                        self.hit_in_contact = True
                        self._set_hit(t, ground_point, "GROUND")
                        self.notes.append(
                            f"point {ground_point} reached the ground at {t:.6g} s while the car "
                            "still pushed the post: a ground hit (the ground is solid in every "
                            "phase); delta-V and the largest deceleration are up to the hit"
                        )
                        return None, y
                    self._log(spec.name, t)
                    if spec.name == EventKind.LOST_FIRST_SPRING:
                        self.first_lost = t
                    if ended:
                        if spec.name != EventKind.LOST_VEHICLE:
                            self._log(EventKind.LOST_VEHICLE, t)
                        self.vehicle_lost = t
                        self.contact_end = t
                        self._end_modes(t)
                        return t, y
            elif t >= self.t_max:
                self._end_modes(t)
                self.contact_end = t
                return None, y
            else:
                old = mode
                mode = sliding.mode_at_time(m, mode, t, y)
                self._track_modes(old, mode, t)

    def _end_modes(self, t):
        for label in list(self.open_modes):
            self._close_mode(label, t)

    def _log(self, name, t):
        if name == "base stops sliding" or " sliding ends " in name or name.startswith(
                "cap sliding"):
            return
        self.events.append(CoreEvent(name, t, LOST_MESSAGES.get(name, "")))

    def report_ground_passage(self):
        """The listing's behaviour went through the ground: its run (kept whole in the
        trajectory) carries on underground to its own hit, which is no answer; the
        outcome is the ground reached at the passage, and the listing's hit is named."""
        gp = self.ground_passage
        m = self.model
        depth = m.scene.environment.ground_depth_ft
        listing = self.hit
        gp["listing_hit"] = listing.message if listing else None
        gp["listing_hit_s"] = listing.time_s if listing else None
        if listing is not None:
            traj = Trajectory(self.segments, m)
            t = min(listing.time_s, traj.t_end)
            low = min((float(traj.point(p, t)[2]) + depth, p) for p in traj.point_names)
            gp["depth_at_listing_hit_ft"] = -low[0]
            gp["deepest_at_listing_hit"] = low[1]
            self.events = [
                CoreEvent("listing's hit, post underground", e.time_s, e.message)
                if e.name == EventKind.HIT else e
                for e in self.events
            ]
        self.hit = None
        self._set_hit(gp["time_s"], gp["point"], "GROUND")
        self.events[-1] = CoreEvent(
            EventKind.HIT, gp["time_s"], self.hit.message + " (legacy: passing through)"
        )

    def ground_passage_check(self):
        """The listing's behaviour: find the first post point through the ground during
        the contact and the deepest point (recorded in ``ground_passage``)."""
        m = self.model
        depth = m.scene.environment.ground_depth_ft
        tol = ground_tolerance_ft(m.options)
        names = list(m.body_points)
        times, states = [], []
        for seg in self.segments:
            if seg.phase != "contact" or seg.t1 <= seg.t0:
                continue
            fine = _subdivided(seg.solution.ts, 5)
            times.append(fine)
            states.append(seg.solution(fine))
        if not times:
            return None
        fine = np.concatenate(times)
        ys = np.concatenate(states, axis=1)
        first = None
        deepest = (0.0, None, None)
        q = ys[6:10] / np.linalg.norm(ys[6:10], axis=0)
        for name in names:
            h = _heights(m, ys, q, name) + depth
            k = int(np.argmin(h))
            if -h[k] > deepest[0]:
                deepest = (-float(h[k]), name, float(fine[k]))
            tol_p = tol.get(name, 0.0) if isinstance(tol, dict) else tol
            below = np.nonzero(h < -tol_p)[0]
            if len(below) and (first is None or fine[below[0]] < first[1]):
                j = int(below[0])
                above = np.nonzero(h[:j] >= 0.0)[0]
                first = (name, float(fine[j]), float(fine[above[-1]]) if len(above) else None)
        if first is None:
            return None
        name, tj, ta = first
        if ta is not None:
            traj = Trajectory(self.segments, m)

            def f(s):
                return float(traj.point(name, s)[2]) + depth

            if f(ta) * f(tj) < 0.0:
                from scipy.optimize import brentq

                tj = brentq(f, ta, tj, xtol=1e-13)
        return {
            "point": name,
            "time_s": tj,
            "deepest_point": deepest[1],
            "depth_ft": deepest[0],
            "depth_time_s": deepest[2],
        }

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
        segs = m.segment_checks
        n_points = len(specs)
        if segs is not None:
            for pair in segs.inside(y0):
                self.notes.append(
                    f"the {POINT_NAMES[pair.segment]} starts free flight ({t0:.6g} s) inside "
                    "the car's "
                    f"{pair.box.part} box (the crush the car took): checked against it only "
                    "once it has left it"
                )
            specs = specs + segs.events()
        sol = self._solve(m.free_rhs(), t0, y0, self.t_max, specs, self.free_method)
        candidates = []
        for i, (te, ye) in enumerate(zip(sol.t_events, sol.y_events)):
            for tk, yk in zip(te, ye):
                if i >= n_points:  # a segment of the post against a box of the car
                    surface, s, others = segs.surface(i - n_points, yk)
                    pair = segs.pairs[i - n_points]
                    rank = len(checks.regions) + i - n_points  # a point's hit first
                    candidates.append((float(tk), rank, pair.segment, surface, (s, others)))
                    continue
                for region, surface in checks.entered(i, yk):
                    candidates.append((float(tk), checks.priority(region), region.point,
                                       surface, None))
        t_end = float(sol.t[-1])
        if candidates:
            t_first = min(c[0] for c in candidates)
            tied = [c for c in candidates if c[0] <= t_first + 1e-12]
            tk, _, point, surface, seg = min(tied, key=lambda c: c[1])
            self._set_hit(tk, point, surface)
            if seg is not None:
                s, others = seg
                self.hit = dataclasses.replace(self.hit, fraction=s, edge=others)
                where = (f", {s:.3f} of the way from {point[0]} to {point[-1]}"
                         if "-" in point else "")
                if others:
                    where += (" (at its edge with the " + " and the ".join(
                        o.lower() for o in others) + ": named by the face it was crossing "
                        "fastest)")
                self.notes.append(
                    f"the {POINT_NAMES[point]} hit the car's {surface.lower()} at "
                    f"{tk:.6g} s{where} (shaft_contact: the post's segments checked against "
                    "the car)"
                )
            t_end = tk
        self.segments.append(Segment(t0, t_end, "free flight", sol.sol))

    def _set_hit(self, t, point, surface):
        msg = hit_message(surface, point)
        self.hit = Hit(msg, t, point, surface)
        self.events.append(CoreEvent(EventKind.HIT, t, msg))


def _heights(m, ys, q, name):
    """ZZ of point ``name`` for states ``ys`` (15, n) with their attitudes ``q`` normalised."""
    bx, by, bz = m.body_points[name]
    w, x, y, z = q
    return ys[2] + 2 * (x * z - w * y) * bx + 2 * (y * z + w * x) * by + (
        w * w - x * x - y * y + z * z
    ) * bz


def _result(run: _Run, scene: Scene, options: ModelOptions) -> CoreResult:
    m = run.model
    traj = Trajectory(run.segments, m)
    end = run.hit.time_s if run.hit else traj.t_end
    notes = list(run.notes)
    t_release = run.vehicle_lost
    if t_release is None and run.hit_in_contact:
        t_release = run.contact_end
    terminal: dict[str, tuple[float, float, float] | None] = {}
    q0 = m._q0
    depth = scene.environment.ground_depth_ft
    # P, Q, R always (None where the scene lacks one), and a second luminaire U where it has one
    names = ("P", "Q", "R") + (("U",) if "U" in m.body_points else ())
    at_end = (traj.points(min(end, traj.t_end), [n for n in names if n in m.body_points])
              if traj.segments else {})
    for name in names:
        if name not in m.body_points or not traj.segments:
            terminal[name] = None if name not in m.body_points else _xl(m, m.y0, name, q0, depth)
            continue
        p = at_end[name]
        terminal[name] = (float(p[0] - q0[0]), float(p[1] - q0[1]), float(p[2] + depth))
    passage = run.ground_passage
    reason = None
    if passage is not None:
        after = (
            f"; the listing's run carries on underground to {passage['listing_hit']!r} at "
            f"{passage['listing_hit_s']:.6g} s with point {passage['deepest_at_listing_hit']} "
            f"{passage['depth_at_listing_hit_ft']:.3g} ft below the ground: not an answer"
            if passage.get("listing_hit")
            else "; the listing's run never hits anything after that"
        )
        notes.append(
            f"legacy: the post went through the ground during the contact (the listing checks "
            f"the ground only in free flight): point {passage['point']} at "
            f"{passage['time_s']:.6g} s is reported as the hit (passing through); deepest "
            f"in the contact: point {passage['deepest_point']} {passage['depth_ft']:.3g} ft "
            f"below the ground at {passage['depth_time_s']:.6g} s" + after
        )
    if run.hit is None:
        if run.vehicle_lost is None and scene.vehicle is not None:
            reason = (
                f"the car still pushed the post at the simulated-time bound "
                f"t_max_s = {run.t_max:g} s"
            )
        else:
            reason = f"nothing was hit before the simulated-time bound t_max_s = {run.t_max:g} s"
    return CoreResult(
        scene=scene,
        options=options,
        method=run.method,
        events=tuple(sorted(run.events, key=lambda e: e.time_s)),
        hit=run.hit,
        first_spring_lost_s=run.first_lost,
        vehicle_contact_lost_s=run.vehicle_lost,
        terminal_points_ft=terminal,
        end_time_s=end,
        nfev=run.nfev,
        trajectory=traj,
        notes=tuple(notes),
        no_hit_reason=reason,
        ground_passage=passage,
        contact_end_s=t_release,
        integrator=run.integrator(),
    )


def _xl(m, y, name, q0, depth):
    p = m.point_position(Kinematics(m, list(y)), name)
    return (p[0] - q0[0], p[1] - q0[1], p[2] + depth)


#: relative slack on the inertia triangle inequality (decks print 5 or 6 digits)
INERTIA_SLACK = 1e-6


def check_inertia(scene: Scene) -> None:
    """A rigid body's principal moments satisfy the triangle inequality (each at most the
    sum of the other two); moments that do not are no body at all, and their Euler
    equations are gyroscopically stiff beyond any bound (B = 1e12 with A, C of a post)."""
    a = scene.post.principal_inertia_slug_ft2
    names = ("A", "B", "C")
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        if a[i] > (a[j] + a[k]) * (1.0 + INERTIA_SLACK):
            raise CoreError(
                f"the post's moments of inertia are no rigid body's: {names[i]} = {a[i]:g} "
                f"slug ft^2 exceeds {names[j]} + {names[k]} = {a[j] + a[k]:g} slug ft^2 "
                "(the triangle inequality)"
            )


def _checked(result: CoreResult, check: bool) -> CoreResult:
    if check:
        failed = check_outcome(result)
        if failed:
            raise CoreError(
                "outcome check failed: " + "; ".join(failed)
                + (f" [{result.options.name} preset]" if result.options.name else "")
            )
    return result


def simulate(
    scene: Scene,
    options: ModelOptions,
    *,
    method: str = CORE_METHOD,
    rtol: float = CORE_RTOL,
    atol: float = CORE_ATOL,
    max_step_s: float = MAX_STEP_S,
    t_max_s: float = T_MAX_S,
    max_evaluations: int | None = MAX_EVALUATIONS,
    max_wall_s: float | None = MAX_WALL_S,
    check: bool = True,
) -> CoreResult:
    """Run ``scene`` under ``options`` (a preset: ``vocabulary.scene.PRESETS``) from t = 0:
    contact with the car (if it has one), then free flight until the first hit (or
    ``t_max_s``).

    ``method``: a ``solve_ivp`` method, or ``"auto"`` (DOP853; Radau for the contact phase
    of a stiff scene, see :func:`stiffness`).  The core's work is bounded by ``t_max_s``
    (simulated time), ``max_evaluations`` (right-hand-side evaluations) and ``max_wall_s``
    (wall time): a run that reaches the last two ends in one ``CoreError`` line.
    ``check``: every outcome goes through :func:`~.checks.check_outcome` first; a failed
    check raises ``CoreError`` naming it."""
    laws.compile_functions()  # the laws scipy calls: numba's compiled ones
    return _simulate_with(_Run, scene, options, method, rtol, atol, max_step_s, t_max_s,
                          max_evaluations, max_wall_s, check)


def _simulate_with(run_class, scene, options, method, rtol, atol, max_step_s, t_max_s,
                   max_evaluations, max_wall_s, check) -> CoreResult:
    """:func:`simulate` with the run's integration by ``run_class`` (a :class:`_Run`)."""
    check_inertia(scene)
    model = assemble(scene, options)
    run = run_class(model, method, rtol, atol, max_step_s, t_max_s, max_evaluations,
                    max_wall_s)
    if scene.vehicle is None:
        run.free_flight(0.0, model.y0)
    else:
        t, y = run.contact()
        if not options.solid_ground:
            run.ground_passage = run.ground_passage_check()
        if t is not None:
            run.free_flight(t, y)
        if run.ground_passage is not None:
            run.report_ground_passage()
    return _checked(_result(run, scene, options), check)


def free_flight(
    scene: Scene,
    state,
    t0_s: float,
    options: ModelOptions,
    *,
    method: str = CORE_METHOD,
    rtol: float = CORE_RTOL,
    atol: float = CORE_ATOL,
    max_step_s: float = MAX_STEP_S,
    t_max_s: float | None = None,
    max_evaluations: int | None = MAX_EVALUATIONS,
    max_wall_s: float | None = MAX_WALL_S,
    check: bool = False,
) -> CoreResult:
    """Free flight of the post from ``state`` (15 numbers, the layout of
    :class:`~.result.Trajectory`) at ``t0_s`` until the first hit or ``t_max_s``."""
    model = assemble(scene, options)
    state = np.asarray(state, dtype=float)
    if state.shape != (N_STATE,):
        raise ValueError(f"state must have {N_STATE} numbers, got shape {state.shape}")
    t_max = t0_s + T_MAX_S if t_max_s is None else t_max_s
    laws.compile_functions()  # the laws scipy calls: numba's compiled ones
    run = _Run(model, method, rtol, atol, max_step_s, t_max, max_evaluations, max_wall_s)
    run.free_flight(t0_s, state)
    return _checked(_result(run, scene, options), check)
