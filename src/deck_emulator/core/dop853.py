"""DOP853, compiled: the scipy path's explicit method, callable from compiled code.

``solve_ivp`` cannot be called from compiled code and numba has no ODE solver, so this
module transcribes the method scipy uses, the Runge-Kutta pair 8(5,3) of Dormand and Prince
(E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary Differential Equations I", 2nd ed.,
Springer 1993, II.10) in the form of ``scipy.integrate.DOP853`` -- its tableau
(:mod:`.dop853_tableau`), error norm, step-size control, first step and dense output -- and
``solve_ivp``'s event handling: an event is active where its function changes sign in the
direction asked over a step, its root found on the dense output by Brent's method (scipy's
``brentq``, ``xtol = rtol = 4 eps``); the integration stops at the first terminal root.

The right-hand side and the events are the model's compiled laws (:mod:`.laws`), chosen
by ``phase`` (contact or free flight) with the scene's parameter vector ``P`` and the
contact mode's vector ``M``; the events are rows ``(code, arg, direction, terminal)``.
"""

from __future__ import annotations

import math

import numpy as np
from . import dop853_tableau as _tableau
from . import laws
from .laws import _jit

__all__ = [
    "PHASE_CONTACT",
    "PHASE_FREE",
    "STATUS_BUDGET",
    "STATUS_EVENT",
    "STATUS_FAILED",
    "STATUS_FINISHED",
    "STATUS_NOT_FINITE",
    "brentq",
    "dense_eval",
    "solve",
]

PHASE_CONTACT = 0
PHASE_FREE = 1

STATUS_FINISHED = 0  # reached t_bound
STATUS_EVENT = 1  # a terminal event
STATUS_FAILED = -1  # step size too small
STATUS_BUDGET = -2  # more right-hand-side evaluations than allowed
STATUS_NOT_FINITE = -3  # the state or the error estimate is not finite

N_STAGES = _tableau.N_STAGES
N_EXT = N_STAGES + 1 + len(_tableau.C_EXTRA)  # the stages, the solution's, the dense output's
N_F = _tableau.ORDER - 1  # the dense output's degree
# one (16, 16) matrix of every stage: the step's 12, the solution's (row 12: B, its time 1),
# the dense output's 3 (rows 13-15)
_A = np.zeros((N_EXT, N_EXT))
_A[:N_STAGES, :N_STAGES] = _tableau.A
_A[N_STAGES, :N_STAGES] = _tableau.B
_A[N_STAGES + 1:] = _tableau.A_EXTRA
_C = np.concatenate([_tableau.C, [1.0], _tableau.C_EXTRA])
_B = np.ascontiguousarray(_tableau.B)
_E3 = np.ascontiguousarray(_tableau.E3)
_E5 = np.ascontiguousarray(_tableau.E5)
_D = np.ascontiguousarray(_tableau.D)
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
ERROR_EXPONENT = -1.0 / 8.0  # -1 / (error estimator order 7 + 1)
EPS = np.finfo(float).eps
N = 15  # the core's state


def _derivative_floats(phase, t, y, P, M):
    """The state derivative (a list) of the state ``y``, the parameters ``P`` and the mode
    ``M`` given as lists of Python floats: the compiled laws' same operations in the same
    order, as a double's (a numpy scalar's arithmetic is the same IEEE arithmetic, at
    several times the cost)."""
    out = [0.0] * len(y)
    if phase == PHASE_CONTACT:
        laws.contact_derivative_with(t, y, P, M, [0.0] * 7, out)
    else:
        laws.free_derivative_into(y, P, out)
    return out


def _rhs_floats(phase, t, y, P, M, acc, out):
    """:func:`_rhs` (its plain-Python form) over Python floats (:func:`_derivative_floats`)."""
    out[:] = _derivative_floats(phase, t, y.tolist(), P.tolist(), M.tolist())


@_jit(plain=_rhs_floats)
def _rhs(phase, t, y, P, M, acc, out):
    if phase == PHASE_CONTACT:
        laws.contact_derivative_with(t, y, P, M, acc, out)
    else:
        laws.free_derivative_into(y, P, out)


def _event_floats(k, t, y, P, M, EV, rows_a, rows_c, letters, pairs, z):
    """:func:`_event` (its plain-Python form) over the state, the parameters and the mode as
    Python floats (as :func:`_rhs_floats`), a row's sum in index order."""
    code = int(EV[k, 0])
    yl, Pl = y.tolist(), P.tolist()
    if code == laws.EV_ROW:
        laws.check_coordinates(yl, Pl, letters, z)
        s = 0.0
        for a, b in zip(rows_a[int(EV[k, 1])].tolist(), z.tolist()):
            s += a * b
        return s + float(rows_c[int(EV[k, 1])])
    if code == laws.EV_SEGMENT:
        laws.check_coordinates(yl, Pl, letters, z)
        return laws.pair_depth(z, pairs[int(EV[k, 1])])[0]
    return laws.contact_event(code, float(EV[k, 1]), t, yl, Pl, M.tolist())


@_jit(plain=_event_floats)
def _event(k, t, y, P, M, EV, rows_a, rows_c, letters, pairs, z):
    code = int(EV[k, 0])
    if code == laws.EV_ROW:
        laws.check_coordinates(y, P, letters, z)
        r = int(EV[k, 1])
        s = 0.0
        for j in range(z.size):
            s += rows_a[r, j] * z[j]
        return s + rows_c[r]
    if code == laws.EV_SEGMENT:
        laws.check_coordinates(y, P, letters, z)
        return laws.pair_depth(z, pairs[int(EV[k, 1])])[0]
    return laws.contact_event(code, EV[k, 1], t, y, P, M)


def _events_all_rows(t, y, P, M, EV, rows_a, rows_c, letters, pairs, z, g):
    """:func:`_events_all` (its plain-Python form): the checks' rows all at once, each row's
    sum in index order (:func:`_sums`), the other events over Python floats."""
    yl, Pl, Ml = y.tolist(), P.tolist(), M.tolist()
    codes = EV[:, 0]
    rows = codes == laws.EV_ROW
    if rows.any() or (codes == laws.EV_SEGMENT).any():
        laws.check_coordinates(yl, Pl, letters, z)
    if rows.any():
        r = EV[rows, 1].astype(np.int64)
        terms = np.zeros((r.size, z.size + 1))  # 0.0, then each row's terms in order
        np.multiply(rows_a[r], z, out=terms[:, 1:])
        g[rows] = np.add.accumulate(terms, axis=1)[:, -1] + rows_c[r]
    for k in np.flatnonzero(~rows).tolist():
        if codes[k] == laws.EV_SEGMENT:
            g[k] = laws.pair_depth(z, pairs[int(EV[k, 1])])[0]
        else:
            g[k] = laws.contact_event(int(codes[k]), float(EV[k, 1]), t, yl, Pl, Ml)


@_jit(plain=_events_all_rows)
def _events_all(t, y, P, M, EV, rows_a, rows_c, letters, pairs, z, g):
    """Every event's value into ``g`` (the checks' coordinates computed once)."""
    have_z = False
    for k in range(EV.shape[0]):
        code = int(EV[k, 0])
        if code == laws.EV_ROW or code == laws.EV_SEGMENT:
            if not have_z:
                laws.check_coordinates(y, P, letters, z)
                have_z = True
            r = int(EV[k, 1])
            if code == laws.EV_SEGMENT:
                g[k] = laws.pair_depth(z, pairs[r])[0]
                continue
            s = 0.0
            for j in range(z.size):
                s += rows_a[r, j] * z[j]
            g[k] = s + rows_c[r]
        else:
            g[k] = laws.contact_event(code, EV[k, 1], t, y, P, M)


@_jit
def _norm(x):
    s = 0.0  # summed in order, as numba's np.sum does (numpy's own sums pairwise)
    for i in range(x.size):
        s += x[i] * x[i]
    return math.sqrt(s) / math.sqrt(x.size)


def _sums(coefficients, rows, work):
    """``0.0 + c[0] r[0] + c[1] r[1] + ...`` (``coefficients`` a column (k, 1), or a stack
    of them (m, k, 1), against the rows ``rows`` (k, n)): each element's sum in that order,
    as the compiled loops do it (``np.add.accumulate`` is sequential by definition; a
    reduction may sum pairwise).  ``work``: (k + 1, n), or (m, k + 1, n), row 0 zero."""
    k = rows.shape[0]
    terms = work[..., : k + 1, :]
    np.multiply(rows, coefficients, out=terms[..., 1:, :])
    return np.add.accumulate(terms, axis=-2)[..., k, :]


def _work(n, m=None):
    """A :func:`_sums` work buffer for up to :data:`N_EXT` terms of ``n`` elements."""
    return np.zeros((N_EXT + 1, n) if m is None else (m, N_EXT + 1, n))


#: the stages' coefficients as columns: ``_A_COLUMNS[s]`` is ``_A[s, :s]`` shaped (s, 1)
_A_COLUMNS = [np.ascontiguousarray(_A[s, :s, None]) for s in range(N_EXT)]
_B_COLUMN = np.ascontiguousarray(_B[:, None])
_D_COLUMNS = np.ascontiguousarray(_D[:, :, None])
_E_COLUMNS = np.ascontiguousarray(np.stack((_E5, _E3))[:, :, None])


def _rk_step_rows(phase, t, y, f, h, P, M, K, acc, ytmp, y_new):
    """:func:`_rk_step` over whole rows (its plain-Python form): each element's sum in the
    same order, ``0.0 + K[0] a_0 + K[1] a_1 + ...``."""
    Pl, Ml = P.tolist(), M.tolist()
    K[0, :] = f
    work = _work(y.size)
    for s in range(1, N_STAGES):
        ytmp[:] = y + _sums(_A_COLUMNS[s], K[:s], work) * h
        K[s] = _derivative_floats(phase, t + _C[s] * h, ytmp.tolist(), Pl, Ml)
    y_new[:] = y + h * _sums(_B_COLUMN, K[:N_STAGES], work)
    K[N_STAGES] = _derivative_floats(phase, t + h, y_new.tolist(), Pl, Ml)


@_jit(plain=_rk_step_rows)
def _rk_step(phase, t, y, f, h, P, M, K, acc, ytmp, y_new):
    """One step of the 8th-order formula (scipy's ``rk_step``): stages into ``K``."""
    n = y.size
    K[0, :] = f
    for s in range(1, N_STAGES):
        for i in range(n):
            dy = 0.0
            for j in range(s):
                dy += K[j, i] * _A[s, j]
            ytmp[i] = y[i] + dy * h
        _rhs(phase, t + _C[s] * h, ytmp, P, M, acc, K[s])
    for i in range(n):
        d = 0.0
        for j in range(N_STAGES):
            d += K[j, i] * _B[j]
        y_new[i] = y[i] + h * d
    _rhs(phase, t + h, y_new, P, M, acc, K[N_STAGES])


def _error_norm_rows(K, h, scale):
    """:func:`_error_norm` over whole rows (its plain-Python form): the estimates' sums
    element by element in the same order, their squares summed in index order."""
    a5, a3 = _sums(_E_COLUMNS, K[:N_STAGES + 1], _work(scale.size, 2)) / scale
    e5 = e3 = 0.0
    for v5, v3 in zip((a5 * a5).tolist(), (a3 * a3).tolist()):
        e5 += v5
        e3 += v3
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * scale.size)


@_jit(plain=_error_norm_rows)
def _error_norm(K, h, scale):
    n = scale.size
    e5 = 0.0
    e3 = 0.0
    for i in range(n):
        a5 = 0.0
        a3 = 0.0
        for j in range(N_STAGES + 1):
            a5 += K[j, i] * _E5[j]
            a3 += K[j, i] * _E3[j]
        a5 /= scale[i]
        a3 /= scale[i]
        e5 += a5 * a5
        e3 += a3 * a3
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)


def _dense_rows(phase, t_old, h, y_old, y, f, P, M, K, acc, ytmp, F):
    """:func:`_dense` over whole rows (its plain-Python form), each element as it does."""
    Pl, Ml = P.tolist(), M.tolist()
    work = _work(y.size)
    for s in range(N_STAGES + 1, N_EXT):
        ytmp[:] = y_old + _sums(_A_COLUMNS[s], K[:s], work) * h
        K[s] = _derivative_floats(phase, t_old + _C[s] * h, ytmp.tolist(), Pl, Ml)
    dlt = y - y_old
    F[0] = dlt
    F[1] = h * K[0] - dlt
    F[2] = 2 * dlt - h * (f + K[0])
    F[3:] = h * _sums(_D_COLUMNS, K, _work(y.size, len(_D_COLUMNS)))


@_jit(plain=_dense_rows)
def _dense(phase, t_old, h, y_old, y, f, P, M, K, acc, ytmp, F):
    """The step's interpolant (scipy's ``DOP853._dense_output_impl``) into ``F`` (7, n)."""
    n = y.size
    for s in range(N_STAGES + 1, N_EXT):
        for i in range(n):
            dy = 0.0
            for j in range(s):
                dy += K[j, i] * _A[s, j]
            ytmp[i] = y_old[i] + dy * h
        _rhs(phase, t_old + _C[s] * h, ytmp, P, M, acc, K[s])
    for i in range(n):
        dlt = y[i] - y_old[i]
        F[0, i] = dlt
        F[1, i] = h * K[0, i] - dlt
        F[2, i] = 2 * dlt - h * (f[i] + K[0, i])
        for r in range(N_F - 3):
            d = 0.0
            for j in range(N_EXT):
                d += _D[r, j] * K[j, i]
            F[3 + r, i] = h * d


def _interp_rows(t_old, h, y_old, F, t, out):
    """:func:`_interp` over the whole row (its plain-Python form), each element as it does."""
    x = (t - t_old) / h
    v = np.zeros(y_old.size)
    for r in range(N_F - 1, -1, -1):
        v += F[r]
        if (N_F - 1 - r) % 2 == 0:
            v *= x
        else:
            v *= 1 - x
    out[:] = v + y_old


@_jit(plain=_interp_rows)
def _interp(t_old, h, y_old, F, t, out):
    x = (t - t_old) / h
    n = y_old.size
    for i in range(n):
        v = 0.0
        for r in range(N_F - 1, -1, -1):
            v += F[r, i]
            if (N_F - 1 - r) % 2 == 0:
                v *= x
            else:
                v *= 1 - x
        out[i] = v + y_old[i]


def _dense_eval_rows(ts, t_old, h, y_old, F, tq):
    """:func:`dense_eval` (its plain-Python form) for all the times at once, each element as
    :func:`_interp` does it."""
    seg = np.minimum(np.maximum(np.searchsorted(ts, tq) - 1, 0), t_old.size - 1)
    x = ((tq - t_old[seg]) / h[seg])[:, None]
    Fq = F[seg]
    v = np.zeros((tq.size, y_old.shape[1]))
    for r in range(N_F - 1, -1, -1):
        v += Fq[:, r]
        if (N_F - 1 - r) % 2 == 0:
            v *= x
        else:
            v *= 1 - x
    return (v + y_old[seg]).T.copy()


@_jit(plain=_dense_eval_rows)
def dense_eval(ts, t_old, h, y_old, F, tq):
    """States (n, m) at times ``tq`` from stored steps (scipy's ``OdeSolution``: the
    step is found by ``searchsorted(ts, t, 'left') - 1``, clipped)."""
    m = tq.size
    n = y_old.shape[1]
    out = np.empty((n, m))
    tmp = np.empty(n)
    nseg = t_old.size
    for k in range(m):
        ind = np.searchsorted(ts, tq[k]) - 1
        seg = min(max(ind, 0), nseg - 1)
        _interp(t_old[seg], h[seg], y_old[seg], F[seg], tq[k], tmp)
        out[:, k] = tmp
    return out


@_jit
def brentq(k, a, b, t_old, h, y_old, F, P, M, EV, rows_a, rows_c, letters, pairs, z, ytmp,
           xtol, rtol, maxiter):
    """Root of event ``k`` on the step's dense output in [a, b]: scipy's ``brentq``
    (``scipy/optimize/Zeros/brentq.c``, itself Brent 1973), transcribed."""
    xpre, xcur = a, b
    xblk = 0.0
    fblk = 0.0
    spre = 0.0
    scur = 0.0
    _interp(t_old, h, y_old, F, xpre, ytmp)
    fpre = _event(k, xpre, ytmp, P, M, EV, rows_a, rows_c, letters, pairs, z)
    _interp(t_old, h, y_old, F, xcur, ytmp)
    fcur = _event(k, xcur, ytmp, P, M, EV, rows_a, rows_c, letters, pairs, z)
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    for _ in range(maxiter):
        if fpre != 0.0 and fcur != 0.0 and (math.copysign(1.0, fpre) != math.copysign(1.0, fcur)):
            xblk = xpre
            fblk = fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre = xcur
            xcur = xblk
            xblk = xpre
            fpre = fcur
            fcur = fblk
            fblk = fpre
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                spre = scur
                scur = stry
            else:
                spre = sbis
                scur = sbis
        else:
            spre = sbis
            scur = sbis
        xpre = xcur
        fpre = fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        _interp(t_old, h, y_old, F, xcur, ytmp)
        fcur = _event(k, xcur, ytmp, P, M, EV, rows_a, rows_c, letters, pairs, z)
    return xcur


def _step_scale_rows(y, y_new, atol, rtol, scale):
    """:func:`_step_scale` (its plain-Python form), element by element as it does (Python's
    ``max(a, b)``: ``b if b > a else a``)."""
    a, b = np.abs(y), np.abs(y_new)
    scale[:] = atol + np.where(b > a, b, a) * rtol


@_jit(plain=_step_scale_rows)
def _step_scale(y, y_new, atol, rtol, scale):
    """The error's scale of a step from ``y`` to ``y_new`` into ``scale``."""
    for i in range(y.size):
        scale[i] = atol + max(abs(y[i]), abs(y_new[i])) * rtol


def _finite_rows(y):
    """:func:`_finite` (its plain-Python form)."""
    return bool(np.isfinite(y).all())


@_jit(plain=_finite_rows)
def _finite(y):
    """Every element of ``y`` is finite."""
    for i in range(y.size):
        if not math.isfinite(y[i]):
            return False
    return True


def _crossed_rows(g, g_new, EV, active):
    """:func:`_crossed` (its plain-Python form), the same comparisons for all events at once."""
    up = (g <= 0) & (g_new >= 0)
    down = (g >= 0) & (g_new <= 0)
    d = EV[:, 2]
    found = np.flatnonzero((up & (d > 0)) | (down & (d < 0)) | ((up | down) & (d == 0)))
    active[: found.size] = found
    return found.size


@_jit(plain=_crossed_rows)
def _crossed(g, g_new, EV, active):
    """The events whose function crossed zero over the step in their direction (``g`` at
    its start, ``g_new`` at its end; solve_ivp's ``find_active_events``) into ``active``, in
    their order; returns how many."""
    n_act = 0
    for k in range(g.size):
        up = g[k] <= 0 and g_new[k] >= 0
        down = g[k] >= 0 and g_new[k] <= 0
        d = EV[k, 2]
        if (up and d > 0) or (down and d < 0) or ((up or down) and d == 0):
            active[n_act] = k
            n_act += 1
    return n_act


@_jit
def _grow(a, need):
    if need <= a.shape[0]:
        return a
    shape = (max(need, 2 * a.shape[0]),) + a.shape[1:]
    b = np.empty(shape, dtype=a.dtype)
    b[: a.shape[0]] = a
    return b


@_jit
def solve(phase, t0, y0, t_bound, P, M, EV, rows_a, rows_c, letters, pairs, rtol, atol,
          max_step, max_nfev):
    """Integrate from ``(t0, y0)`` towards ``t_bound`` (> t0) as ``solve_ivp(...,
    method="DOP853", dense_output=True, events=...)`` does.

    ``EV`` (n_events, 4): code, arg, direction, terminal (1.0/0.0) of each event; the
    free flight's checks: ``rows_a``, ``rows_c`` (their matrix and constants), ``letters``
    (their points), ``pairs`` (the shaft's segment/box pairs, :func:`~.laws.pair_depth`).
    Returns (status, nfev, ts (steps + 1), t_old, h, y_old (steps, n), F (steps, 7, n),
    event rows recorded (index, time) and their states (k, n))."""
    n = y0.size
    acc = np.empty(7)
    K = np.empty((N_EXT, n))
    ytmp = np.empty(n)
    y_new = np.empty(n)
    scale = np.empty(n)
    z = np.empty(3 * letters.size + 1)
    n_ev = EV.shape[0]
    cap = 64
    ts = np.empty(cap + 1)
    t_olds = np.empty(cap)
    hs = np.empty(cap)
    y_olds = np.empty((cap, n))
    Fs = np.empty((cap, N_F, n))
    rec_k = np.empty(8, dtype=np.int64)
    rec_t = np.empty(8)
    rec_y = np.empty((8, n))
    n_rec = 0
    nsteps = 0

    y = y0.copy()
    t = t0
    f = np.empty(n)
    _rhs(phase, t, y, P, M, acc, f)
    nfev = 1
    ts[0] = t0
    # first step (scipy's select_initial_step, error estimator order 7)
    interval = abs(t_bound - t0)
    if interval == 0.0:
        return (STATUS_FINISHED, nfev, ts[:1], t_olds[:0], hs[:0], y_olds[:0], Fs[:0],
                rec_k[:0], rec_t[:0], rec_y[:0])
    for i in range(n):
        scale[i] = atol + abs(y[i]) * rtol
    d0 = _norm(y / scale)
    d1 = _norm(f / scale)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, interval)
    for i in range(n):
        ytmp[i] = y[i] + h0 * f[i]
    f1 = np.empty(n)
    _rhs(phase, t0 + h0, ytmp, P, M, acc, f1)
    nfev += 1
    d2 = _norm((f1 - f) / scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    h_abs = min(100 * h0, h1, interval, max_step)

    g = np.empty(n_ev)
    g_new = np.empty(n_ev)
    _events_all(t, y, P, M, EV, rows_a, rows_c, letters, pairs, z, g)
    roots = np.empty(n_ev)
    active = np.empty(n_ev, dtype=np.int64)

    status = 99
    while status == 99:
        # -- one step (scipy's RungeKutta._step_impl)
        min_step = 10 * abs(np.nextafter(t, np.inf) - t)
        if h_abs > max_step:
            h_abs = max_step
        elif h_abs < min_step:
            h_abs = min_step
        rejected = False
        while True:
            if h_abs < min_step:
                return (STATUS_FAILED, nfev, ts[: nsteps + 1], t_olds[:nsteps], hs[:nsteps],
                        y_olds[:nsteps], Fs[:nsteps], rec_k[:n_rec], rec_t[:n_rec],
                        rec_y[:n_rec])
            h = h_abs
            t_new = t + h
            if t_new - t_bound > 0:
                t_new = t_bound
            h = t_new - t
            h_abs = abs(h)
            _rk_step(phase, t, y, f, h, P, M, K, acc, ytmp, y_new)
            nfev += N_STAGES
            _step_scale(y, y_new, atol, rtol, scale)
            err = _error_norm(K, h, scale)
            if not math.isfinite(err):
                return (STATUS_NOT_FINITE, nfev, ts[: nsteps + 1], t_olds[:nsteps],
                        hs[:nsteps], y_olds[:nsteps], Fs[:nsteps], rec_k[:n_rec],
                        rec_t[:n_rec], rec_y[:n_rec])
            if err < 1:
                if err == 0:
                    factor = MAX_FACTOR
                else:
                    factor = min(MAX_FACTOR, SAFETY * err ** ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            h_abs *= max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT)
            rejected = True
        t_old = t
        y_old = y.copy()
        t = t_new
        y[:] = y_new
        f[:] = K[N_STAGES]
        if t - t_bound >= 0:
            status = STATUS_FINISHED
        # -- the step's dense output
        ts = _grow(ts, nsteps + 2)
        t_olds = _grow(t_olds, nsteps + 1)
        hs = _grow(hs, nsteps + 1)
        y_olds = _grow(y_olds, nsteps + 1)
        Fs = _grow(Fs, nsteps + 1)
        _dense(phase, t_old, h, y_old, y, f, P, M, K, acc, ytmp, Fs[nsteps])
        nfev += N_EXT - N_STAGES - 1
        t_olds[nsteps] = t_old
        hs[nsteps] = h
        y_olds[nsteps] = y_old
        Fst = Fs[nsteps]
        nsteps += 1
        ts[nsteps] = t
        if not _finite(y):
            return (STATUS_NOT_FINITE, nfev, ts[: nsteps + 1], t_olds[:nsteps],
                    hs[:nsteps], y_olds[:nsteps], Fs[:nsteps], rec_k[:n_rec],
                    rec_t[:n_rec], rec_y[:n_rec])
        # -- events (solve_ivp's find_active_events and handle_events)
        _events_all(t, y, P, M, EV, rows_a, rows_c, letters, pairs, z, g_new)
        n_act = _crossed(g, g_new, EV, active)
        if n_act > 0:
            for a in range(n_act):
                roots[a] = brentq(active[a], t_old, t, t_old, h, y_old, Fst, P, M, EV, rows_a,
                                  rows_c, letters, pairs, z, ytmp, 4 * EPS, 4 * EPS, 100)
            keep = n_act
            terminal = False
            for a in range(n_act):
                if EV[active[a], 3] != 0.0:
                    terminal = True
            if terminal:
                order = np.argsort(roots[:n_act], kind="mergesort")
                act2 = active[:n_act][order].copy()
                roots2 = roots[:n_act][order].copy()
                for a in range(n_act):
                    active[a] = act2[a]
                    roots[a] = roots2[a]
                for a in range(n_act):
                    if EV[active[a], 3] != 0.0:
                        keep = a + 1
                        break
            rec_k = _grow(rec_k, n_rec + keep)
            rec_t = _grow(rec_t, n_rec + keep)
            rec_y = _grow(rec_y, n_rec + keep)
            for a in range(keep):
                rec_k[n_rec] = active[a]
                rec_t[n_rec] = roots[a]
                _interp(t_old, h, y_old, Fst, roots[a], ytmp)
                rec_y[n_rec] = ytmp
                n_rec += 1
            if terminal:
                status = STATUS_EVENT
                t = roots[keep - 1]
                _interp(t_old, h, y_old, Fst, t, y)
                ts[nsteps] = t
        g[:] = g_new
        if status == 99 and max_nfev >= 0 and nfev > max_nfev:
            return (STATUS_BUDGET, nfev, ts[: nsteps + 1], t_olds[:nsteps], hs[:nsteps],
                    y_olds[:nsteps], Fs[:nsteps], rec_k[:n_rec], rec_t[:n_rec],
                    rec_y[:n_rec])
    return (status, nfev, ts[: nsteps + 1], t_olds[:nsteps], hs[:nsteps], y_olds[:nsteps],
            Fs[:nsteps], rec_k[:n_rec], rec_t[:n_rec], rec_y[:n_rec])
