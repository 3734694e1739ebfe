"""Many scenes through the compiled core: :func:`simulate_batch`.

Each scene runs as :func:`~.solve.simulate` runs it -- the same contact modes, events,
transitions and hit rules -- but its segments are integrated by the compiled DOP853
(:mod:`.dop853`) over the compiled laws (:mod:`.laws`), and the car's largest force is found
in compiled code too; only the bookkeeping between segments is Python.  A segment the
compiled integrator cannot do (a stiff contact, which ``method="auto"`` gives to Radau, or a
non-finite explicit step) is solved by ``solve_ivp`` in the same run, and the result says so
(``CoreResult.integrator == "compiled+scipy"``).  Besides each scene's own bounds, the batch
as a whole is bounded by ``max_wall_s``: past it, the scene in progress stops at its next
segment and the others do not start, each a ``CoreError`` saying so.
"""

from __future__ import annotations

import functools
import math
from collections import namedtuple

import numpy as np

from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.defaults import (
    CORE_ATOL,
    CORE_METHOD,
    CORE_RTOL,
    MAX_EVALUATIONS,
    MAX_STEP_S,
    T_MAX_S,
)
from deck_emulator.vocabulary.scene import ModelOptions

from . import dop853, laws
from .kinematics import ContactMode
from .laws import _jit
from .result import distinct
from .solve import CoreError, _Run, _simulate_with

__all__ = ["CompiledSolution", "simulate_batch"]


#: a compiled segment's answer, read as solve_ivp's (the fields the solve reads of it)
_Solved = namedtuple("_Solved", "t y sol t_events y_events nfev status message")


class CompiledSolution:
    """The dense output of a compiled segment, as ``scipy``'s ``OdeSolution`` answers:
    ``ts`` (the steps' ends) and ``solution(t)`` -> (15,) or (15, n)."""

    __slots__ = ("F", "h", "t_old", "ts", "y_old")

    def __init__(self, ts, t_old, h, y_old, F):
        self.ts, self.t_old, self.h, self.y_old, self.F = ts, t_old, h, y_old, F

    def __call__(self, t):
        tq = np.atleast_1d(np.asarray(t, dtype=float))
        out = dop853.dense_eval(self.ts, self.t_old, self.h, self.y_old, self.F, tq)
        return out[:, 0] if np.ndim(t) == 0 else out

    def peak_force(self, P, M) -> float:
        """The largest force on the car (lb) over this contact segment under the laws'
        parameters ``P`` and mode ``M`` (:func:`segment_max_force`)."""
        return segment_max_force(self.ts, self.t_old, self.h, self.y_old, self.F, P, M)


# --------------------------------------------------------------------------------------
# the largest force on the car over a compiled segment (result.segment_peak_force)

_SQRT_EPS = math.sqrt(2.2e-16)
_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))


def _force_at_floats(s, ts, t_old, h, y_old, F, P, M, tmp):
    """:func:`_force_at` (its plain-Python form): the law over Python floats (as
    :func:`~.dop853._rhs_floats`)."""
    seg = min(max(np.searchsorted(ts, s) - 1, 0), t_old.size - 1)
    dop853._interp(t_old[seg], h[seg], y_old[seg], F[seg], s, tmp)
    return laws.sliding_vehicle_force(s, tmp.tolist(), P.tolist(), M.tolist())


@_jit(plain=_force_at_floats)
def _force_at(s, ts, t_old, h, y_old, F, P, M, tmp):
    seg = min(max(np.searchsorted(ts, s) - 1, 0), t_old.size - 1)
    dop853._interp(t_old[seg], h[seg], y_old[seg], F[seg], s, tmp)
    return laws.sliding_vehicle_force(s, tmp, P, M)


@_jit
def _fminbound_neg_force(x1, x2, xatol, maxfun, ts, t_old, h, y_old, F, P, M, tmp):
    """Brent's bounded search of ``-force`` over ``[x1, x2]``, as scipy's public
    ``scipy.optimize.minimize_scalar(method="bounded", options={"xatol": xatol,
    "maxiter": maxfun})`` (the same method as ``scipy.optimize.fminbound``) does it, step
    for step (the scipy path calls that; R. P. Brent, "Algorithms for Minimization without
    Derivatives", 1973, ch. 5), transcribed so that compiled code can call it."""
    a, b = x1, x2
    fulc = a + _GOLDEN * (b - a)
    nfc, xf = fulc, fulc
    rat = e = 0.0
    x = xf
    fx = -_force_at(x, ts, t_old, h, y_old, F, P, M, tmp)
    num = 1
    ffulc = fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = True
        if abs(e) > tol1:
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r = e
            e = rat
            if (abs(p) < abs(0.5 * q * r)) and (p > q * (a - xf)) and (p < q * (b - xf)):
                rat = (p + 0.0) / q
                x = xf + rat
                if ((x - a) < tol2) or ((b - x) < tol2):
                    si = np.sign(xm - xf) + (1.0 if (xm - xf) == 0 else 0.0)
                    rat = tol1 * si
            else:
                golden = True
        if golden:
            if xf >= xm:
                e = a - xf
            else:
                e = b - xf
            rat = _GOLDEN * e
        si = np.sign(rat) + (1.0 if rat == 0 else 0.0)
        x = xf + si * max(abs(rat), tol1)
        fu = -_force_at(x, ts, t_old, h, y_old, F, P, M, tmp)
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if (fu <= fnfc) or (nfc == xf):
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif (fu <= ffulc) or (fulc == xf) or (fulc == nfc):
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxfun:
            break
    return xf, fx


@_jit
def _grid(ts):
    """9 points on every step of ``ts``, the steps' ends repeated."""
    n_steps = ts.size - 1
    grid = np.empty(8 * n_steps + 1)
    for k in range(n_steps):
        grid[8 * k: 8 * k + 9] = np.linspace(ts[k], ts[k + 1], 9)
    return grid


@_jit
def _refined(fine, best_k, best_f, ts, t_old, h, y_old, F, P, M, tmp):
    """(lb): the grid's best, refined by the bounded search between its neighbours."""
    fk = best_f
    lo, hi = fine[max(best_k - 1, 0)], fine[min(best_k + 1, fine.size - 1)]
    if hi > lo:
        fx = _fminbound_neg_force(lo, hi, 1e-12, 500, ts, t_old, h, y_old, F, P, M, tmp)[1]
        if -fx > fk:
            fk = -fx
    return fk


def _segment_max_force_rows(ts, t_old, h, y_old, F, P, M):
    """:func:`segment_max_force` (its plain-Python form): the grid's states interpolated all
    at once (:func:`~.dop853.dense_eval`), each force over Python floats."""
    fine = distinct(_grid(ts))  # np.unique's values, as compiled code finds them
    states = dop853.dense_eval(ts, t_old, h, y_old, F, fine).T.tolist()
    Pl, Ml = P.tolist(), M.tolist()
    best_k = 0
    best_f = -np.inf
    for k, (s, y) in enumerate(zip(fine.tolist(), states)):
        fk = laws.sliding_vehicle_force(s, y, Pl, Ml)
        if fk > best_f or k == 0:
            best_f = fk
            best_k = k
    return _refined(fine, best_k, best_f, ts, t_old, h, y_old, F, P, M,
                    np.empty(y_old.shape[1]))


@_jit(plain=_segment_max_force_rows)
def segment_max_force(ts, t_old, h, y_old, F, P, M):
    """(lb): the largest force on the car over a compiled segment, on a grid of 9 points
    a step refined by a bounded search (as :func:`~.result.segment_peak_force`)."""
    fine = np.unique(_grid(ts))
    tmp = np.empty(y_old.shape[1])
    best_k = 0
    best_f = -np.inf
    for k in range(fine.size):
        fk = _force_at(fine[k], ts, t_old, h, y_old, F, P, M, tmp)
        if fk > best_f or k == 0:
            best_f = fk
            best_k = k
    return _refined(fine, best_k, best_f, ts, t_old, h, y_old, F, P, M, tmp)


# --------------------------------------------------------------------------------------
# a run whose segments the compiled integrator solves


_NO_ROWS = np.zeros((0, 1))
_NO_CONST = np.zeros(0)
_NO_LETTERS = np.zeros(0, dtype=np.int64)
_NO_PAIRS = np.zeros((0, 7))


class _CompiledRun(_Run):
    """:class:`~.solve._Run` with ``solve_ivp`` replaced by :func:`.dop853.solve` wherever
    the segment's law and every event have compiled forms."""

    def __init__(self, *args, wall=None, **kwargs):
        super().__init__(*args, **kwargs)
        self.wall = wall  # the batch's (deadline on laws.working_clock, max_wall_s), or None
        self.compiled_segments = 0
        self.scipy_segments: list[str] = []

    def integrator(self) -> str:
        if not self.scipy_segments:
            return "compiled"
        return "compiled+scipy" if self.compiled_segments else "scipy"

    def _solve(self, fun, t0, y0, t1, events, method=None):
        if self.wall is not None and laws.working_clock() > self.wall[0]:
            raise CoreError(_past_wall(self.wall[1], f"at t = {t0:.6g} s"))
        method = method or self.method
        if method != "DOP853":
            return self._by_scipy(f"{method} (stiff contact)", fun, t0, y0, t1, events, method)
        law = fun.law
        m = self.model
        phase = dop853.PHASE_CONTACT if law[0] == "contact" else dop853.PHASE_FREE
        M = law[1] if law[1] is not None else m.mode_vector(_DEFAULT_MODE)
        EV = np.array([[e.code[0], e.code[1], e.direction, 1.0 if e.terminal else 0.0]
                       for e in events], dtype=float).reshape(-1, 4)
        if phase == dop853.PHASE_FREE and len(events):
            rows_a, rows_c, letters = m.checks.A, m.checks.const, m.checks.letters
        else:
            rows_a, rows_c, letters = _NO_ROWS, _NO_CONST, _NO_LETTERS
        pairs = m.segment_checks.table if m.segment_checks is not None else _NO_PAIRS
        budget = -1 if self.max_evaluations is None else self.max_evaluations - self._evals
        max_step = self.max_step if self.max_step is not None else np.inf
        (status, nfev, ts, t_old, h, y_old, F, rec_k, rec_t, rec_y) = dop853.solve(
            phase, float(t0), np.asarray(y0, dtype=float), float(t1), m.law_parameters, M,
            EV, rows_a, rows_c, letters, pairs, float(self.rtol), float(self.atol),
            float(max_step),
            int(budget),
        )
        if status == dop853.STATUS_NOT_FINITE:
            # an explicit step met a non-finite number: the scipy path's own remedy
            return self._by_scipy("a non-finite explicit step", fun, t0, y0, t1, events,
                                  method)
        self._evals += nfev
        self.nfev += nfev
        if status == dop853.STATUS_BUDGET:
            raise CoreError(
                f"run stopped: the run needed more than max_evaluations = "
                f"{self.max_evaluations} right-hand-side evaluations (at t = {ts[-1]:.6g} s)"
            )
        if status == dop853.STATUS_FAILED:
            raise CoreError(
                f"integration failed at t = {float(ts[-1])!r} s: Required step size is less "
                "than spacing between numbers."
            )
        self.compiled_segments += 1
        sol = CompiledSolution(ts, t_old, h, y_old, F)
        y_end = sol(ts[-1]) if len(t_old) else np.asarray(y0, dtype=float)
        t_events, y_events = [rec_t[:0]] * len(events), [rec_y[:0]] * len(events)
        for i in set(rec_k.tolist()):  # the events that were recorded
            t_events[i], y_events[i] = rec_t[rec_k == i], rec_y[rec_k == i]
        return _Solved(
            t=ts, y=y_end[:, None], sol=sol, t_events=t_events, y_events=y_events,
            nfev=nfev, status=1 if status == dop853.STATUS_EVENT else 0, message="",
        )

    def _by_scipy(self, why, fun, t0, y0, t1, events, method):
        sol = super()._solve(fun, t0, y0, t1, events, method)
        self.scipy_segments.append(why)
        self.notes.append(f"solve_ivp, not the compiled integrator, from t = {t0:.6g} s to "
                          f"{float(sol.t[-1]):.6g} s: {why}")
        return sol


def _past_wall(max_wall_s: float, where: str) -> str:
    return (f"run stopped: the batch took more than max_wall_s = {max_wall_s:g} s of wall "
            f"time ({where})")


_DEFAULT_MODE = ContactMode()


def simulate_batch(
    scenes,
    options: ModelOptions,
    *,
    rtol: float = CORE_RTOL,
    atol: float = CORE_ATOL,
    max_step_s: float = MAX_STEP_S,
    t_max_s: float = T_MAX_S,
    max_evaluations: int | None = MAX_EVALUATIONS,
    max_wall_s: float | None = None,
    method: str = CORE_METHOD,
    check: bool = True,
    compile: bool = True,
) -> list:
    """Run every scene of ``scenes`` through the compiled core; one item per scene, in
    their order: a :class:`~.result.CoreResult` or the :class:`~.solve.CoreError` (or
    ``ValueError``, ``ArithmeticError``) the scene met -- one scene's failure does not stop
    the batch.  Scenes run in their order.

    ``options``: one preset for all, or one per scene.  The keywords are
    :func:`~.solve.simulate`'s, but ``max_wall_s`` bounds the whole batch (None: the row
    ``MAX_WALL_S`` as the batch starts; ``math.inf``: no bound).  ``compile``: have numba
    compile the core's functions (or load them) first; False: run them as this process has
    them -- plain Python where nothing compiled them, the same numbers, no numba to load
    (for a single scene)."""
    if compile:
        laws.compile_functions()
    scenes = list(scenes)
    if isinstance(options, ModelOptions):
        per_scene = [options] * len(scenes)
    else:
        per_scene = list(options)
        if len(per_scene) != len(scenes):
            raise ValueError(f"{len(per_scene)} options for {len(scenes)} scenes")
    out: list = [None] * len(scenes)
    max_wall_s = defaults.MAX_WALL_S if max_wall_s is None else max_wall_s
    # the bound's clock leaves out numba compiling or loading the core (laws.working_clock)
    wall = (laws.working_clock() + max_wall_s, max_wall_s)
    run = functools.partial(_CompiledRun, wall=wall)
    for i in range(len(scenes)):
        if laws.working_clock() > wall[0]:
            out[i] = CoreError(_past_wall(max_wall_s, "before this scene started"))
            continue
        try:
            out[i] = _simulate_with(run, scenes[i], per_scene[i], method, rtol, atol, max_step_s,
                                    t_max_s, max_evaluations, None, check)
        except (CoreError, ValueError, ArithmeticError) as exc:
            out[i] = exc
    return out
