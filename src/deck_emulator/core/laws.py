"""The model's force laws and equations of motion, written once, compiled.

Both roads call these functions: the scipy path (:mod:`.model`, :mod:`.sliding`) and the
compiled batch (:mod:`.batch`, from compiled code).  They are numba ``@njit`` functions over
plain floats and float arrays: numba compiles plain Python arithmetic with IEEE semantics
(no fast-math: the operations in the order written) and its functions can be called from
Python and from compiled code alike.  ``cache=True`` keeps the machine code where numba's
configuration says (:func:`~deck_emulator.core.configure_numba_cache`).

A scene's numbers are packed once into a parameter vector ``P`` (layout ``P_*``, filled by
:meth:`~.model.Model.law_parameters`), the contact mode into a mode vector ``M`` (``M_*``,
:meth:`~.model.Model.mode_vector`).  The state ``y`` has the layout of
:class:`~.result.Trajectory` (15 numbers).
"""

from __future__ import annotations

import functools
import math
import os
import sys
import time

import numpy as np

from . import compiled_cache_folder

__all__ = [
    "working_clock",
    "LETTERS",
    "N_M",
    "N_P",
    "compression",
    "contact_derivative",
    "contact_loads",
    "diff_rate",
    "free_derivative",
    "listing_diff",
    "point_position",
    "point_velocity",
    "post_derivative",
    "rotation_matrix",
    "spring_force",
]


def recompiling(fn):
    """``fn`` (an entry of the core), run again once when numba failed while it held its
    compiler lock: a cache file truncated or garbled, which numba unpickles without checking.
    The core's own cache folder is removed first, so numba compiles anew instead of failing
    at every start; an error that comes back is raised.  Only where numba keeps the core's
    code in that folder (the command line's processes): a host application's cache and its
    errors are its own.  An error of the run itself is never retried."""

    @functools.wraps(fn)
    def entry(*args, **kwargs):
        if _COMPILING is not None:
            _COMPILING.failed = None
        try:
            return fn(*args, **kwargs)
        except Exception as exc:  # MemoryError too: a garbled pickle can ask for any size
            folder = compiled_cache_folder()
            if (_COMPILING is None or not _raised_by(exc, _COMPILING.failed)
                    or os.environ.get("NUMBA_CACHE_DIR") != folder):
                raise
            import shutil  # (here: a run that starts well never needs it)

            shutil.rmtree(folder, ignore_errors=True)
            return fn(*args, **kwargs)

    return entry


def _raised_by(exc: BaseException, cause: BaseException | None) -> bool:
    """``exc`` is ``cause`` or was raised while handling it (its chain of causes)."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if exc is cause:
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


class _CompilerTime:
    """The seconds numba has held (or waited for) its compiler lock in this process, and the
    exception that last ended a hold; a listener of numba's documented event
    ``numba:compiler_lock`` (:func:`compile_functions`).  Nested holds count once."""

    def __init__(self) -> None:
        self.total_s = 0.0
        self.depth = 0
        self.since = 0.0
        self.failed: BaseException | None = None  # the last exception a hold ended by

    def on_start(self, event) -> None:
        if self.depth == 0:
            self.since = time.perf_counter()
        self.depth += 1

    def on_end(self, event) -> None:
        if self.depth == 1 and sys.exc_info()[1] is not None:  # released as it unwinds
            self.failed = sys.exc_info()[1]
        self.depth = max(self.depth - 1, 0)
        if self.depth == 0:
            self.total_s += time.perf_counter() - self.since


#: numba's compiler-lock time in this process, once the core's functions are compiled
#: (:func:`compile_functions`); None while they run as plain Python
_COMPILING: _CompilerTime | None = None


def working_clock() -> float:
    """A clock for the core's wall bounds (``max_wall_s``), s: ``time.perf_counter()`` less the
    time numba has spent compiling or loading the core in this process, so that a cold cache
    never counts against a run's bound.  Only differences of its readings mean anything."""
    now = time.perf_counter()
    if _COMPILING is None:
        return now
    busy = _COMPILING.total_s + (now - _COMPILING.since if _COMPILING.depth else 0.0)
    return now - busy


#: the core's functions numba compiles (every ``@_jit`` one, of this module, :mod:`.dop853`
#: and :mod:`.batch`), with their module, as written: plain Python until
#: :func:`compile_functions`
_FUNCTIONS: list = []


def _jit(fn=None, *, plain=None):
    """One of the core's compiled functions: plain Python as written (a single scene runs it
    so, importing no numba) until :func:`compile_functions` puts numba's dispatcher in its
    place.  ``plain``: what runs instead while uncompiled, the same operations in the same
    order over whole rows, where the loops written for numba are slow in Python
    (tests/core/test_interpreted.py holds the two to the same numbers)."""
    if fn is None:
        return functools.partial(_jit, plain=plain)
    if _COMPILING is not None:  # a module imported after compile_functions
        return _njit(fn)
    _FUNCTIONS.append((sys.modules[fn.__module__], fn))
    return fn if plain is None else plain


def _njit(fn):
    """``njit(cache=True)`` of ``fn``, or plain ``njit`` where numba finds no place to cache."""
    from numba import njit

    try:
        return njit(cache=True)(fn)
    except RuntimeError:  # "cannot cache function ...: no locator available"
        return njit(fn)


def compiled() -> bool:
    """The core's functions are numba's compiled ones in this process."""
    return _COMPILING is not None


def compile_functions() -> None:
    """Each of the core's functions (``@_jit``) replaced in its module by :func:`_njit` of it
    (those of a module imported later, as they are defined); once a process.  numba compiles
    each at its first call, or loads it from its cache; the numbers are the plain Python's."""
    global _COMPILING
    if _COMPILING is not None:
        return
    from numba.core import event as numba_event

    class Listener(_CompilerTime, numba_event.Listener):
        pass

    listener = Listener()
    numba_event.register("numba:compiler_lock", listener)
    for module, fn in _FUNCTIONS:
        setattr(module, fn.__name__, _njit(fn))
    _COMPILING = listener  # from here on, a function defined is compiled at once (_jit)


#: the post's points in the parameter vector, in this order
LETTERS = "PQRCSTU"

# -- parameter vector P
P_MASS, P_I1, P_I2, P_I3, P_WV, P_WEIGHT, P_COS, P_SIN = range(8)
P_POINTS = 8  # 3 numbers per letter of LETTERS (principal axes, ft)
(P_FN, P_FN_RELEASE, P_FR, P_FR_WINDOW, P_FR_REACTION, P_K_S, P_K_T, P_SV_CONTACT, P_XV0_S,
 P_XV0_T, P_FACTOR, P_ABSOLUTE, P_CAP, P_KICK_F1, P_KICK_FV, P_KICK_FS, P_Q0X, P_DEPTH,
 P_HAS_NORMAL, P_HAS_FRICTION, P_HAS_CONTACT, P_HAS_T, P_LISTING_DIFF, P_SWITCH,
 P_HAS_KICK, P_HAS_LEAF, P_LEAF_K1, P_LEAF_K2, P_LEAF_KNEE, P_LEAF_STOP, P_LEAF_U1, P_LEAF_U2,
 P_LEAF_UKNEE) = range(P_POINTS + 3 * len(LETTERS), P_POINTS + 3 * len(LETTERS) + 33)
N_P = P_LEAF_UKNEE + 1

# -- mode vector M (booleans as 0.0 / 1.0; NaN: "not set")
(M_POINT, M_NORMAL_ON, M_FRICTION_ON, M_CAP_ENGAGED, M_WINDOW, M_FRICTION_STICK,
 M_FRICTION_SIGN, M_SPRING_OVERRIDE, M_FRICTION_OVERRIDE, M_CAP_SLIDING,
 M_LEAF_PEAK) = range(11)
N_M = 11
#: M_WINDOW values
WINDOW_NONE, WINDOW_KICK, WINDOW_FIRST_STEP = 0.0, 1.0, 2.0
#: M_POINT values (the spring acts at S or at T)
AT_S, AT_T = 0.0, 1.0


@_jit
def rotation_matrix(w, x, y, z):
    """Row-major 3x3 (a flat 9-tuple) of the normalised quaternion: body -> road.

    It is eq. 3.21 with ``(w, x, y, z) = (chi, xi, eta, zeta)``."""
    n = 1.0 / math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w * n, x * n, y * n, z * n
    return (
        w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z,
    )  # fmt: skip


@_jit
def point_position(y0, y1, y2, R, bx, by, bz):
    """Road-axes position of the body point ``(bx, by, bz)`` (principal axes, ft)."""
    return (
        y0 + R[0] * bx + R[1] * by + R[2] * bz,
        y1 + R[3] * bx + R[4] * by + R[5] * bz,
        y2 + R[6] * bx + R[7] * by + R[8] * bz,
    )


@_jit
def point_velocity(R, v1, v2, v3, w1, w2, w3, bx, by, bz):
    """Road-axes velocity of a body point: ``R (V + omega x r_body)``."""
    u1 = v1 + w2 * bz - w3 * by
    u2 = v2 + w3 * bx - w1 * bz
    u3 = v3 + w1 * by - w2 * bx
    return (
        R[0] * u1 + R[1] * u2 + R[2] * u3,
        R[3] * u1 + R[4] * u2 + R[5] * u3,
        R[6] * u1 + R[7] * u2 + R[8] * u3,
    )


@_jit
def _arm(R, bx, by, bz):
    return (
        R[0] * bx + R[1] * by + R[2] * bz,
        R[3] * bx + R[4] * by + R[5] * bz,
        R[6] * bx + R[7] * by + R[8] * bz,
    )


@_jit
def post_derivative(y, R, f0, f1, f2, t0, t1, t2, mass, a, b, c, out):
    """Time derivative of the 13 post states into ``out[:13]`` (eq. 3.16, 3.17 and the
    kinematics): force ``f`` and torque ``t`` about the mass centre in road components."""
    v1, v2, v3 = y[3], y[4], y[5]
    qw, qx, qy, qz = y[6], y[7], y[8], y[9]
    w1, w2, w3 = y[10], y[11], y[12]
    # road -> body: R.T @ f
    g1 = R[0] * f0 + R[3] * f1 + R[6] * f2
    g2 = R[1] * f0 + R[4] * f1 + R[7] * f2
    g3 = R[2] * f0 + R[5] * f1 + R[8] * f2
    h1 = R[0] * t0 + R[3] * t1 + R[6] * t2
    h2 = R[1] * t0 + R[4] * t1 + R[7] * t2
    h3 = R[2] * t0 + R[5] * t1 + R[8] * t2
    out[0] = R[0] * v1 + R[1] * v2 + R[2] * v3
    out[1] = R[3] * v1 + R[4] * v2 + R[5] * v3
    out[2] = R[6] * v1 + R[7] * v2 + R[8] * v3
    # eq. 3.16: M (V' + omega x V) = F
    out[3] = g1 / mass - (w2 * v3 - w3 * v2)
    out[4] = g2 / mass - (w3 * v1 - w1 * v3)
    out[5] = g3 / mass - (w1 * v2 - w2 * v1)
    # q' = q (x) (0, omega) / 2
    out[6] = 0.5 * (-qx * w1 - qy * w2 - qz * w3)
    out[7] = 0.5 * (qw * w1 + qy * w3 - qz * w2)
    out[8] = 0.5 * (qw * w2 - qx * w3 + qz * w1)
    out[9] = 0.5 * (qw * w3 + qx * w2 - qy * w1)
    # eq. 3.17: A w1' - (B - C) w2 w3 = T1 ...
    out[10] = ((b - c) * w2 * w3 + h1) / a
    out[11] = ((c - a) * w3 * w1 + h2) / b
    out[12] = ((a - b) * w1 * w2 + h3) / c


@_jit
def _add_force(acc, fx, fy, fz, ax, ay, az):
    acc[0] += fx
    acc[1] += fy
    acc[2] += fz
    acc[3] += ay * fz - az * fy
    acc[4] += az * fx - ax * fz
    acc[5] += ax * fy - ay * fx


@_jit
def _rot(y):
    return rotation_matrix(y[6], y[7], y[8], y[9])


@_jit
def point_xv(y, R, P, k):
    """``XV`` of point number ``k`` of :data:`LETTERS` (the car's axis, ft)."""
    j = P_POINTS + 3 * k
    x, yy, _ = point_position(y[0], y[1], y[2], R, P[j], P[j + 1], P[j + 2])
    return x * P[P_COS] - yy * P[P_SIN]


@_jit
def compression(sv_contact, sv, xv0, xv):
    """``(SVO - SV) - (XVO - XV)`` of a point (ft); positive: crushed (eq. 3.13-3.15)."""
    return (sv_contact - sv) - (xv0 - xv)


@_jit
def compression_rate(vv, vxv):
    """The rate of :func:`compression` (ft/s) given the car's and the point's velocity
    along ``XV``."""
    return -vv + vxv


@_jit
def listing_diff(sv_contact, sv, xv0, xv):
    """The listing's ``DIFF`` (S) or ``DIFFT`` (T): ``|XV - XVO| - |SV - SVO|``."""
    return abs(xv - xv0) - abs(sv - sv_contact)


@_jit
def diff_rate(dxv, dsv, vxv, vv):
    """``d DIFF/dt`` given ``XV - XVO``, ``SV - SVO`` and their rates (ft/s)."""
    return math.copysign(1.0, dxv) * vxv - math.copysign(1.0, dsv) * vv


@_jit
def spring_force(k, x, factor, absolute, cap_engaged, cap):
    """``FS`` (lb) of a crush spring of stiffness ``k`` at compression ``x`` (eq. 3.15):
    ``|k x|`` (the listing) or ``max(0, k x)``, times ``factor``, capped at ``cap``
    (NaN: no cap) while the cap is engaged."""
    kx = k * x
    fs = abs(kx) if absolute else max(0.0, kx)
    fs *= factor
    if cap_engaged and not math.isnan(cap) and fs > cap:
        fs = cap
    return fs


@_jit
def leaf_loading_force(x, k1, k2, knee, stop):
    """The leaf spring's loading curve ``F_L(x)`` (lb; :mod:`.leaf_spring`)."""
    if x <= 0.0:
        return 0.0
    if x <= knee:
        return k1 * x
    xe = min(x, stop)
    return k1 * knee + k2 * (xe - knee)


@_jit
def leaf_knee_force(x_m, k1, k2, knee, stop, u1, uknee):
    """(knee compression, force there) on the unloading line from ``x_m``."""
    xk = min(x_m, uknee)
    return xk, leaf_loading_force(x_m, k1, k2, knee, stop) - u1 * (x_m - xk)


@_jit
def leaf_unloading_force(x, x_m, k1, k2, knee, stop, u1, u2, uknee):
    """The unloading line from the largest compression ``x_m``, never below zero."""
    xk, fk = leaf_knee_force(x_m, k1, k2, knee, stop, u1, uknee)
    if x >= xk:
        f = leaf_loading_force(x_m, k1, k2, knee, stop) - u1 * (x_m - x)
    else:
        f = fk - u2 * (xk - x)
    return max(f, 0.0)


@_jit
def leaf_force(x, x_peak, k1, k2, knee, stop, u1, u2, uknee):
    """Leaf spring force at compression ``x`` given the peak so far (NaN: loading)."""
    if math.isnan(x_peak) or x >= x_peak:
        return leaf_loading_force(x, k1, k2, knee, stop)
    return leaf_unloading_force(x, x_peak, k1, k2, knee, stop, u1, u2, uknee)


@_jit
def _leaf_at(x, x_peak, P):
    return leaf_force(x, x_peak, P[P_LEAF_K1], P[P_LEAF_K2], P[P_LEAF_KNEE], P[P_LEAF_STOP],
                      P[P_LEAF_U1], P[P_LEAF_U2], P[P_LEAF_UKNEE])


@_jit
def _letter_index(point):
    return 4 if point == AT_S else 5  # S or T in LETTERS


@_jit
def contact_spring_force(y, R, P, M):
    """The crush spring's force (lb) in mode ``M`` (window, override, point, cap)."""
    if P[P_HAS_LEAF] != 0.0:  # the leaf spring at S (no window, override or cap of its own)
        x = compression(P[P_SV_CONTACT], y[13], P[P_XV0_S], point_xv(y, R, P, 4))
        return P[P_FACTOR] * _leaf_at(x, M[M_LEAF_PEAK], P)
    if M[M_WINDOW] == WINDOW_FIRST_STEP:
        return P[P_KICK_FS]
    if not math.isnan(M[M_SPRING_OVERRIDE]):
        return M[M_SPRING_OVERRIDE]
    at_s = M[M_POINT] == AT_S
    k = P[P_K_S] if at_s else P[P_K_T]
    xv0 = P[P_XV0_S] if at_s else P[P_XV0_T]
    x = compression(P[P_SV_CONTACT], y[13], xv0, point_xv(y, R, P, _letter_index(M[M_POINT])))
    return spring_force(k, x, P[P_FACTOR], P[P_ABSOLUTE] != 0.0, M[M_CAP_ENGAGED] != 0.0,
                        P[P_CAP])


@_jit
def friction_force(P, M):
    """The base friction along ``+XX`` (lb) in mode ``M`` (section 3.3): the listing's
    constant force, or Coulomb friction slipping against ``M_FRICTION_SIGN``, or the
    reaction that holds a sticking base (``M_FRICTION_OVERRIDE``)."""
    if M[M_FRICTION_ON] == 0.0:
        return 0.0
    if not math.isnan(M[M_FRICTION_OVERRIDE]):
        return M[M_FRICTION_OVERRIDE]
    if P[P_FR_REACTION] == 0.0:
        return P[P_FR]
    if M[M_FRICTION_STICK] != 0.0:
        return 0.0
    return -P[P_FR] * M[M_FRICTION_SIGN]


@_jit
def contact_loads(t, y, P, M, acc):
    """(Fx, Fy, Fz, Tx, Ty, Tz, F_vehicle) of the contact phase into ``acc`` (road axes,
    torques about the mass centre, ``torque = r x F``; eq. 3.28-3.31): gravity, the base's
    normal force and friction at Q, the crush spring at S or T -- each only if the scene
    has it (``P_HAS_*``) -- or, in the start-up kick's window, the kick alone."""
    _contact_loads_turned(t, y, _rot(y), P, M, acc)


@_jit
def _contact_loads_turned(t, y, R, P, M, acc):
    """:func:`contact_loads` with the attitude's rotation ``R`` of ``y`` given."""
    for i in range(7):
        acc[i] = 0.0
    if M[M_WINDOW] == WINDOW_KICK:
        f1 = P[P_KICK_F1]
        fx, fy, fz = _arm(R, f1, 0.0, 0.0)
        acc[0] += fx
        acc[1] += fy
        acc[2] += fz
        acc[6] += P[P_KICK_FV]
        return
    acc[2] -= P[P_WEIGHT]
    jq = P_POINTS + 3 * 1
    if P[P_HAS_NORMAL] != 0.0 and M[M_NORMAL_ON] != 0.0:
        ax, ay, az = _arm(R, P[jq], P[jq + 1], P[jq + 2])
        _add_force(acc, 0.0, 0.0, P[P_FN], ax, ay, az)
    if P[P_HAS_FRICTION] != 0.0 and M[M_FRICTION_ON] != 0.0:
        f = friction_force(P, M)
        if f != 0.0:
            ax, ay, az = _arm(R, P[jq], P[jq + 1], P[jq + 2])
            _add_force(acc, f, 0.0, 0.0, ax, ay, az)
    if P[P_HAS_CONTACT] != 0.0:
        fs = contact_spring_force(y, R, P, M)
        if fs != 0.0:
            j = P_POINTS + 3 * _letter_index(M[M_POINT])
            ax, ay, az = _arm(R, P[j], P[j + 1], P[j + 2])
            _add_force(acc, fs * -P[P_COS], fs * P[P_SIN], 0.0, ax, ay, az)
        acc[6] += fs


@_jit
def plain_derivative(t, y, P, M, acc, out):
    """The contact phase's state derivative into ``out`` with the forces of ``M`` as they
    are (no sliding mode solved for; the loads left in ``acc``)."""
    R = _rot(y)
    _contact_loads_turned(t, y, R, P, M, acc)
    post_derivative(y, R, acc[0], acc[1], acc[2], acc[3], acc[4], acc[5],
                    P[P_MASS], P[P_I1], P[P_I2], P[P_I3], out)
    out[13] = y[14]
    out[14] = acc[6] / P[P_WV]


@_jit
def sliders(M):
    """(cap slides, base sticks): the Filippov sliding modes of ``M`` (:mod:`.sliding`)."""
    cap = M[M_CAP_SLIDING] == 1.0
    stick = M[M_FRICTION_ON] != 0.0 and M[M_FRICTION_STICK] != 0.0
    return cap, stick


@_jit
def point_acceleration(y, R, d, bx, by, bz):
    """Road-axes acceleration (ft/s^2) of the body point ``(bx, by, bz)`` given the state
    derivative ``d``: ``R (omega x (V + omega x r) + V' + omega' x r)``."""
    v1, v2, v3 = y[3], y[4], y[5]
    w1, w2, w3 = y[10], y[11], y[12]
    u1 = v1 + w2 * bz - w3 * by
    u2 = v2 + w3 * bx - w1 * bz
    u3 = v3 + w1 * by - w2 * bx
    dw1, dw2, dw3 = d[10], d[11], d[12]
    a1 = w2 * u3 - w3 * u2 + d[3] + dw2 * bz - dw3 * by
    a2 = w3 * u1 - w1 * u3 + d[4] + dw3 * bx - dw1 * bz
    a3 = w1 * u2 - w2 * u1 + d[5] + dw1 * by - dw2 * bx
    return _arm(R, a1, a2, a3)


@_jit
def _sigma_dot(cap, y, R, P, d):
    """The rate of a sliding surface's function: ``d(dDIFF/dt)/dt`` of S (the cap) or the
    base's acceleration along XX (sticking)."""
    if cap:
        j = P_POINTS + 3 * 4
        ax, ay, _ = point_acceleration(y, R, d, P[j], P[j + 1], P[j + 2])
        dxv = point_xv(y, R, P, 4) - P[P_XV0_S]
        dsv = y[13] - P[P_SV_CONTACT]
        return diff_rate(dxv, dsv, ax * P[P_COS] - ay * P[P_SIN], d[14])
    j = P_POINTS + 3
    return point_acceleration(y, R, d, P[j], P[j + 1], P[j + 2])[0]


@_jit
def filippov(t, y, P, M, d, lam, force, lo, hi, diag):
    """The sliding forces of mode ``M`` at ``(t, y)`` (Filippov's convex combination,
    :class:`~.sliding.Filippov`): the state derivative into ``d``; per slider (the cap
    first, then the base) ``lam`` (unclamped place of its force between its bounds), its
    ``force``, bounds ``lo``, ``hi`` and ``diag`` (d sigma_dot / d lam: > 0 where it
    attracts).  Returns the number of sliders (0, 1 or 2)."""
    cap, stick = sliders(M)
    R = _rot(y)
    n = 0
    kind = np.empty(2, dtype=np.bool_)  # True: the cap
    if cap:
        Mhi = M.copy()
        Mhi[M_CAP_ENGAGED] = 0.0
        Mhi[M_CAP_SLIDING] = 0.0
        lo[n] = P[P_CAP]
        hi[n] = contact_spring_force(y, R, P, Mhi)
        kind[n] = True
        n += 1
    if stick:
        lo[n] = -P[P_FR]
        hi[n] = P[P_FR]
        kind[n] = False
        n += 1
    acc = np.empty(7)
    d0 = np.empty(15)
    Mw = M.copy()
    for i in range(n):
        Mw[M_SPRING_OVERRIDE if kind[i] else M_FRICTION_OVERRIDE] = lo[i]
    plain_derivative(t, y, P, Mw, acc, d0)
    sig0 = np.empty(2)
    for j in range(n):
        sig0[j] = _sigma_dot(kind[j], y, R, P, d0)
    cols = np.empty((2, 15))
    A = np.zeros((2, 2))
    for i in range(n):
        for k in range(n):
            Mw[M_SPRING_OVERRIDE if kind[k] else M_FRICTION_OVERRIDE] = hi[k] if k == i else lo[k]
        plain_derivative(t, y, P, Mw, acc, cols[i])
        for j in range(n):
            A[j, i] = _sigma_dot(kind[j], y, R, P, cols[i]) - sig0[j]
    if n == 1:
        lam[0] = -sig0[0] / A[0, 0] if A[0, 0] != 0.0 else 1.0
    elif n == 2:
        det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
        if det == 0.0:
            lam[0], lam[1] = 1.0, 0.5
        else:
            lam[0] = (-sig0[0] * A[1, 1] + sig0[1] * A[0, 1]) / det
            lam[1] = (-sig0[1] * A[0, 0] + sig0[0] * A[1, 0]) / det
    d[:] = d0
    for i in range(n):
        li = min(max(lam[i], 0.0), 1.0)
        if li != 0.0:
            for k in range(15):
                d[k] = d[k] + li * (cols[i, k] - d0[k])
        force[i] = lo[i] + li * (hi[i] - lo[i])
        diag[i] = A[i, i]
    return n


@_jit
def contact_derivative_with(t, y, P, M, acc, out):
    """The contact phase's state derivative into ``out``: :func:`plain_derivative`, or in
    a sliding mode the Filippov derivative (:func:`filippov`)."""
    cap, stick = sliders(M)
    if cap or stick:
        s = np.empty(2)
        filippov(t, y, P, M, out, s, np.empty(2), np.empty(2), np.empty(2), np.empty(2))
        return
    plain_derivative(t, y, P, M, acc, out)


def _vehicle_forces_floats(ts, ys, P, M):
    """:func:`vehicle_forces` (its plain-Python form) over Python floats: the same
    arithmetic as numpy's scalars, at a fraction of the cost."""
    Pl, Ml = P.tolist(), M.tolist()
    return np.array([vehicle_force(t, y, Pl, Ml) for t, y in zip(ts.tolist(), ys.T.tolist())],
                    dtype=float)


@_jit(plain=_vehicle_forces_floats)
def vehicle_forces(ts, ys, P, M):
    """:func:`vehicle_force` at each time ``ts[k]`` and state ``ys[:, k]``."""
    out = np.empty(ts.size)
    y = np.empty(ys.shape[0])
    for k in range(ts.size):
        y[:] = ys[:, k]
        out[k] = vehicle_force(ts[k], y, P, M)
    return out


@_jit
def sliding_vehicle_force(t, y, P, M):
    """Force on the car along ``+XV`` (lb) in mode ``M``, the cap's sliding force while it
    holds (:func:`filippov`)."""
    if M[M_CAP_SLIDING] == 1.0 and M[M_WINDOW] != WINDOW_KICK:
        f = np.empty(2)
        filippov(t, y, P, M, np.empty(15), np.empty(2), f, np.empty(2), np.empty(2),
                 np.empty(2))
        return f[0]
    return vehicle_force(t, y, P, M)


@_jit
def contact_derivative(t, y, P, M):
    """The contact phase's state derivative (15 numbers): the car feels ``+FS`` along
    ``XV`` (``VV' = FS/WV``, the listing's ``VVA=VVB+(H/WV)*FSB``)."""
    acc = np.empty(7)
    out = np.empty(15)
    contact_derivative_with(t, y, P, M, acc, out)
    return out


@_jit
def free_derivative_into(y, P, out):
    R = _rot(y)
    post_derivative(y, R, 0.0, 0.0, -P[P_WEIGHT], 0.0, 0.0, 0.0,
                    P[P_MASS], P[P_I1], P[P_I2], P[P_I3], out)
    out[13] = y[14]
    out[14] = 0.0


@_jit
def free_derivative(t, y, P):
    """Free flight: gravity alone; the car coasts."""
    out = np.empty(15)
    free_derivative_into(y, P, out)
    return out


@_jit
def vehicle_force(t, y, P, M):
    """Force on the car along ``+XV`` (lb) in mode ``M``."""
    acc = np.empty(7)
    contact_loads(t, y, P, M, acc)
    return acc[6]


# --------------------------------------------------------------------------------------
# event functions (the located events of both phases), by code

#: ``base_travel(y) + arg``: the normal force's release and the friction's window
EV_BASE_TRAVEL = 0
#: a crush-spring point leaves the car (``arg``: its index in LETTERS)
EV_SEPARATION = 1
#: ``DIFF`` of S minus ``arg``: the spring force moves to T
EV_DIFF_S = 2
#: ``dDIFF/dt`` of S: the force cap engages or releases
EV_DIFF_RATE = 3
#: ``-(ZZ + depth)`` of point ``arg``: it reaches the ground (``solid_ground``)
EV_GROUND = 4
#: ``arg * v_Q`` along XX: the base stops sliding
EV_BASE_VELOCITY = 5
#: free flight: row ``arg`` of the checks' matrix (:class:`~.regions.FreeFlightChecks`)
EV_ROW = 6
#: free flight: the depth of segment/box pair ``arg`` (:class:`~.segments.SegmentChecks`)
EV_SEGMENT = 7
#: slider ``arg``'s ``lam`` (its force at its lower bound)
EV_LAM = 8
#: slider ``arg``'s ``lam - 1`` (its force at its upper bound)
EV_LAM_UPPER = 9
#: slider ``arg``'s ``hi - lo`` (the cap no longer binds)
EV_SPAN = 10
#: the compression of S minus ``arg`` (the leaf spring reloads, or lets go)
EV_COMPRESSION = 11
#: the compression rate of S (the leaf spring starts to unload)
EV_COMPRESSION_RATE = 12


@_jit
def base_travel(y, R, P):
    """``XQ - XQ0``: the base's travel along ``XX`` (ft)."""
    j = P_POINTS + 3
    return point_position(y[0], y[1], y[2], R, P[j], P[j + 1], P[j + 2])[0] - P[P_Q0X]


@_jit
def contact_event(code, arg, t, y, P, M):
    """The value of a contact-phase event function (codes ``EV_*``) at ``(t, y)``."""
    if code == EV_LAM or code == EV_LAM_UPPER or code == EV_SPAN:
        lam = np.empty(2)
        lo = np.empty(2)
        hi = np.empty(2)
        filippov(t, y, P, M, np.empty(15), lam, np.empty(2), lo, hi, np.empty(2))
        i = int(arg)
        if code == EV_LAM:
            return lam[i]
        if code == EV_LAM_UPPER:
            return lam[i] - 1.0
        return hi[i] - lo[i]
    R = _rot(y)
    if code == EV_BASE_TRAVEL:
        return base_travel(y, R, P) + arg
    if code == EV_SEPARATION:
        k = int(arg)
        at_s = k == 4
        xv0 = P[P_XV0_S] if at_s else P[P_XV0_T]
        xv = point_xv(y, R, P, k)
        if P[P_LISTING_DIFF] != 0.0:
            return listing_diff(P[P_SV_CONTACT], y[13], xv0, xv)
        return -compression(P[P_SV_CONTACT], y[13], xv0, xv)
    if code == EV_DIFF_S:
        return listing_diff(P[P_SV_CONTACT], y[13], P[P_XV0_S], point_xv(y, R, P, 4)) - arg
    if code == EV_DIFF_RATE:
        j = P_POINTS + 3 * 4
        bx, by, bz = P[j], P[j + 1], P[j + 2]
        vx, vy, _ = point_velocity(R, y[3], y[4], y[5], y[10], y[11], y[12], bx, by, bz)
        dxv = point_xv(y, R, P, 4) - P[P_XV0_S]
        dsv = y[13] - P[P_SV_CONTACT]
        return diff_rate(dxv, dsv, vx * P[P_COS] - vy * P[P_SIN], y[14])
    if code == EV_GROUND:
        j = P_POINTS + 3 * int(arg)
        return -(point_position(y[0], y[1], y[2], R, P[j], P[j + 1], P[j + 2])[2]
                 + P[P_DEPTH])
    if code == EV_COMPRESSION:
        return compression(P[P_SV_CONTACT], y[13], P[P_XV0_S], point_xv(y, R, P, 4)) - arg
    if code == EV_COMPRESSION_RATE:
        j = P_POINTS + 3 * 4
        vx, vy, _ = point_velocity(R, y[3], y[4], y[5], y[10], y[11], y[12], P[j], P[j + 1],
                                   P[j + 2])
        return compression_rate(y[14], vx * P[P_COS] - vy * P[P_SIN])
    if code == EV_BASE_VELOCITY:
        j = P_POINTS + 3
        bx, by, bz = P[j], P[j + 1], P[j + 2]
        return arg * point_velocity(R, y[3], y[4], y[5], y[10], y[11], y[12], bx, by, bz)[0]
    return math.nan


@_jit
def check_coordinates(y, P, letters, z):
    """``XV, YV, ZZ`` of each point ``letters[i]`` (indices into LETTERS) into
    ``z[3i:3i+3]``, and ``SV`` into ``z[-1]``: the free-flight checks' variables."""
    R = _rot(y)
    ca, sa = P[P_COS], P[P_SIN]
    for i in range(letters.size):
        j = P_POINTS + 3 * letters[i]
        x, yy, zz = point_position(y[0], y[1], y[2], R, P[j], P[j + 1], P[j + 2])
        z[3 * i] = x * ca - yy * sa
        z[3 * i + 1] = x * sa + yy * ca
        z[3 * i + 2] = zz
    z[z.size - 1] = y[13]


# --------------------------------------------------------------------------------------
# the shaft's segments against the car's boxes (ModelOptions.shaft_contact; :mod:`.segments`)

#: the box's faces along a segment, the order of :data:`.segments.FACE_SURFACES`
N_FACES = 5


@_jit
def segment_faces(ax, ay, az, bx, by, bz, sv, x0, x1, left, right, top):
    """``(ga, db)``: the five faces' functions at the segment's end A and their change to
    end B (``a``, ``b`` in XV, YV, ZZ; the box ``x0 <= XV - SV <= x1``, ``left <= YV <=
    right``, ``ZZ <= top``)."""
    ga = np.empty(N_FACES)
    db = np.empty(N_FACES)
    ga[0] = ax - sv - x0
    ga[1] = x1 - (ax - sv)
    ga[2] = ay - left
    ga[3] = right - ay
    ga[4] = top - az
    gb0 = bx - sv - x0
    gb1 = x1 - (bx - sv)
    gb2 = by - left
    gb3 = right - by
    gb4 = top - bz
    db[0] = gb0 - ga[0]
    db[1] = gb1 - ga[1]
    db[2] = gb2 - ga[2]
    db[3] = gb3 - ga[3]
    db[4] = gb4 - ga[4]
    return ga, db


@_jit
def segment_depth(ga, db):
    """``max over s in [0, 1] of min_k (ga[k] + db[k] s)`` and an ``s`` where it is reached
    (exact: the maximum of a concave piecewise-linear function lies at an end of [0, 1] or
    where two of its lines cross)."""
    n = ga.size
    cand = np.empty(2 + n * (n - 1) // 2)
    cand[0] = 0.0
    cand[1] = 1.0
    nc = 2
    for i in range(n):
        for j in range(i + 1, n):
            den = db[i] - db[j]
            if den != 0.0:
                s = (ga[j] - ga[i]) / den
                if 0.0 < s < 1.0:
                    cand[nc] = s
                    nc += 1
    best, where = -np.inf, 0.0
    for c in range(nc):
        s = cand[c]
        v = ga[0] + db[0] * s
        for k in range(1, n):
            w = ga[k] + db[k] * s
            if w < v:
                v = w
        if v > best:
            best, where = v, s
    return best, where


@_jit
def pair_depth(z, pair):
    """(h, s) of one segment/box pair from the checks' coordinates ``z``
    (:func:`check_coordinates`); ``pair``: the ends' positions in ``z``'s points, the box's
    x0, x1, left, right, top."""
    i, j = int(pair[0]), int(pair[1])
    ga, db = segment_faces(z[3 * i], z[3 * i + 1], z[3 * i + 2], z[3 * j], z[3 * j + 1],
                           z[3 * j + 2], z[z.size - 1], pair[2], pair[3], pair[4], pair[5],
                           pair[6])
    return segment_depth(ga, db)
