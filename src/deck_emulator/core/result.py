"""What a core run returns: events, the hit, the report's summary numbers, the trajectory."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from deck_emulator.vocabulary.scene import ModelOptions, Scene

from . import laws

__all__ = ["CoreEvent", "Hit", "Segment", "Trajectory", "CoreResult"]


@dataclass(frozen=True)
class CoreEvent:
    """A located event: ``name`` (the core's), ``time_s``, and the listing's ``message``
    where the listing prints one (else "")."""

    name: str
    time_s: float
    message: str = ""


@dataclass(frozen=True)
class Hit:
    """The run's end: ``surface`` GROUND, HOOD, WINDSHIELD, TOP, TRUNK (or the core's
    FRONT, SIDE), the post ``point`` that touched it, and the listing's ``message``.  A
    segment's hit (``ModelOptions.shaft_contact``: ``point`` Q-P, P-R, P-U) says where along
    it (``fraction``, 0 at its first letter) and the other faces through the contact
    (``edge``: the hit is on that edge of ``surface``)."""

    message: str
    time_s: float
    point: str
    surface: str
    fraction: float | None = None
    edge: tuple[str, ...] = ()


@dataclass(frozen=True)
class Segment:
    """A stretch of trajectory between two events: ``solution(t)`` -> states (15, n)."""

    t0: float
    t1: float
    phase: str  # "contact" or "free flight"
    solution: object = field(repr=False)
    mode: object = None


class Trajectory:
    """Dense trajectory of a run, in the road axes XX, YY, ZZ (ft) -- vectorised over ``t``.

    State columns: 0-2 mass centre, 3-5 body velocity, 6-9 attitude quaternion (w, x, y,
    z; body -> road), 10-12 body angular velocity, 13 car position SV, 14 car velocity VV.
    """

    def __init__(self, segments: list[Segment], model):
        self.segments = [s for s in segments if s.t1 > s.t0]
        self._model = model
        self.t_start = segments[0].t0 if segments else 0.0
        self.t_end = segments[-1].t1 if segments else 0.0
        self.point_names = tuple(model.body_points)
        self._peaks: dict[int, float] = {}  # segment -> its largest force (:meth:`peak_force`)

    def state(self, t) -> np.ndarray:
        """State(s) at ``t`` (scalar -> (15,), array -> (15, n)); quaternion normalised."""
        ts = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.empty((15, ts.size))
        if ts.size:
            first, last = (ts[0], ts[0]) if ts.size == 1 else (ts.min(), ts.max())
            if first < self.t_start - 1e-12 or last > self.t_end + 1e-12:
                raise ValueError(f"t outside the run [{self.t_start}, {self.t_end}] s")
        # each segment takes the instants up to its end not taken before it
        if ts.size == 1:  # one instant (the checks, a hit's points): its segment, no search
            seg = next((s for s in self.segments if ts[0] <= s.t1 + 1e-15), None)
            if seg is not None:
                out[:, :1] = seg.solution(np.clip(ts, seg.t0, seg.t1))
        elif ts.size:  # in time order (a grid already is), a segment's instants are a slice
            order = None if np.all(ts[1:] >= ts[:-1]) else np.argsort(ts, kind="stable")
            ordered = ts if order is None else ts[order]
            lo = 0
            for seg, hi in zip(self.segments, np.searchsorted(
                    ordered, [seg.t1 + 1e-15 for seg in self.segments], side="right")):
                if hi > lo:
                    at = slice(lo, hi) if order is None else order[lo:hi]
                    out[:, at] = seg.solution(np.clip(ordered[lo:hi], seg.t0, seg.t1))
                    lo = hi
        q = out[6:10]
        out[6:10] = q / np.linalg.norm(q, axis=0)
        return out[:, 0] if np.ndim(t) == 0 else out

    def mass_centre(self, t) -> np.ndarray:
        """Mass-centre position (XX, YY, ZZ), ft: shape (3,) or (3, n)."""
        return self.state(t)[0:3]

    def rotation(self, t) -> np.ndarray:
        """Body -> road rotation matrices, (3, 3) or (n, 3, 3)."""
        return _rotation_matrices(self.state(t)[6:10])

    def point(self, name: str, t) -> np.ndarray:
        """Position of post point ``name`` (P, Q, S, T, R, C) in XX, YY, ZZ, ft."""
        return self.points(t, (name,))[name]

    def points(self, t, names=None) -> dict[str, np.ndarray]:
        """The post's points ``names`` (default: all) at ``t``, by name: the state and its
        rotation evaluated once for all of them."""
        return self.points_of(self.state(t), names)

    def points_of(self, state: np.ndarray, names=None) -> dict[str, np.ndarray]:
        """The post's points ``names`` (default: all) in the state(s) ``state`` (a
        :meth:`state` answer), by name."""
        R = _rotation_matrices(state[6:10])
        out = {}
        for k in self.point_names if names is None else names:
            body = np.asarray(self._model.body_points[k])
            out[k] = state[0:3] + (R @ body if R.ndim == 2 else (R @ body).T)
        return out

    def contact_force(self, step_s: float) -> tuple[np.ndarray, np.ndarray]:
        """The force on the car along ``+XV`` (lb) over the contact segments, sampled at
        least every ``step_s`` and at each segment's ends: (times, forces); empty arrays
        without a contact."""
        ts, fs = [], []
        for seg in self.segments:
            if seg.phase != "contact" or seg.t1 <= seg.t0:
                continue
            n = max(math.ceil((seg.t1 - seg.t0) / step_s), 2)
            tt = np.linspace(seg.t0, seg.t1, n + 1)
            ys = np.ascontiguousarray(seg.solution(tt), dtype=float)
            fs.append(self._model.vehicle_forces(tt, ys, seg.mode))
            ts.append(tt)
        if not ts:
            return np.zeros(0), np.zeros(0)
        return np.concatenate(ts), np.asarray(np.concatenate(fs), dtype=float)

    def peak_force(self, after_startup: bool = False) -> float | None:
        """The largest force on the car (lb) over the contact segments -- with
        ``after_startup``, those after the start-up kick's window (the listing's 10,000 lb
        over its first steps is a device of its scheme, not an impact force) -- located on
        the dense solution with the model's force law
        (:func:`segment_peak_force`); None without a contact."""
        best = -math.inf
        for i, seg in enumerate(self.segments):
            if seg.phase != "contact" or (after_startup and seg.mode.window is not None):
                continue
            if i not in self._peaks:
                self._peaks[i] = segment_peak_force(self._model, seg)
            best = max(best, self._peaks[i])
        return float(best) if math.isfinite(best) else None

    def vehicle(self, t) -> np.ndarray:
        """Car position SV (ft) and velocity VV (ft/s) along XV: shape (2,) or (2, n)."""
        return self.state(t)[13:15]


def segment_peak_force(model, seg: Segment) -> float:
    """The largest force on the car (lb) over one contact segment of ``model``'s run: on a
    grid of 9 points a step, then refined by a bounded Brent search around the grid's best
    (a compiled segment's own search where it has one, :mod:`.batch`)."""
    P, M = model.law_parameters, model.mode_vector(seg.mode)
    own = getattr(seg.solution, "peak_force", None)
    if own is not None:
        return own(P, M)
    fine = _subdivided(seg.solution.ts, 9)
    ys = seg.solution(fine)
    f = np.array([laws.sliding_vehicle_force(tk, np.ascontiguousarray(ys[:, k]), P, M)
                  for k, tk in enumerate(fine)])
    k = int(np.argmax(f))
    fk = f[k]
    lo, hi = fine[max(k - 1, 0)], fine[min(k + 1, len(fine) - 1)]
    if hi > lo:
        from scipy.optimize import minimize_scalar

        r = minimize_scalar(
            lambda s: -laws.sliding_vehicle_force(s, np.ascontiguousarray(seg.solution(s)), P, M),
            bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
        fk = max(fk, -r.fun)
    return fk


def _subdivided(ts, n: int) -> np.ndarray:
    """The ``n`` points of ``np.linspace(a, b, n)`` on every step ``[a, b]`` of ``ts``, sorted,
    each once: linspace's own arithmetic (its exact values), for all the steps at once."""
    ts = np.asarray(ts, dtype=float)
    a, b = ts[:-1], ts[1:]
    delta = b - a
    step = delta / (n - 1)
    i = np.arange(n, dtype=float)[:, None]
    y = i * step + a
    zero = step == 0
    if zero.any():  # linspace's own way with a step that underflows to zero
        y[:, zero] = i / (n - 1) * delta[zero] + a[zero]
    y[-1] = b
    return distinct(y)


def distinct(values) -> np.ndarray:
    """The distinct values of a float array without NaN, sorted: ``np.unique``'s answer
    without its import of numpy's masked arrays (a single run's start pays for every
    module it loads)."""
    v = np.sort(np.asarray(values, dtype=float).ravel())
    return v[np.concatenate(([True], v[1:] != v[:-1]))]


def _rotation_matrices(q: np.ndarray) -> np.ndarray:
    """Body -> road rotation matrices of unit quaternions ``q`` (w, x, y, z): (4,) -> (3, 3),
    (4, n) -> (n, 3, 3)."""
    w, x, y, z = q
    R = np.array(
        [
            [w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z],
        ]
    )
    return np.moveaxis(R, -1, 0) if R.ndim == 3 else R


@dataclass(frozen=True)
class CoreResult:
    """One core run.

    * ``events`` -- located events in time order (:class:`CoreEvent`).
    * ``hit`` -- :class:`Hit` or ``None`` (nothing hit before ``t_max_s``).
    * ``first_spring_lost_s``, ``vehicle_contact_lost_s`` -- the listing's two messages.
    * ``contact_end_s`` -- when the contact with the car ends (the car let go, or the post hit
      the car while in contact): the instant the registry reads the speed lost at
      (``deck_emulator.engine.quantities``).
    * ``terminal_points_ft`` -- P, Q, R (and U, where the scene has a second luminaire) at
      the hit in the report's axes: ``XL = XX - XXQ0, YL = YY - YYQ0, ZL = ZZ + HEIGHT``
      (``None`` for a point the scene lacks).
    * ``trajectory`` -- :class:`Trajectory`.
    * ``notes`` -- what a reader should know of the run: the sliding modes and their
      intervals, the method chosen for the contact and why, a warning recovered from.
    * ``no_hit_reason`` -- why there is no hit (``None`` when there is one).
    * ``ground_passage`` -- under the listing's behaviour (no ground during the contact):
      the first post point that went through the ground, when, and how deep the post got
      (``{"point", "time_s", "deepest_point", "depth_ft", "depth_time_s"}``), else ``None``.
    """

    scene: Scene
    options: ModelOptions
    method: str
    events: tuple[CoreEvent, ...]
    hit: Hit | None
    first_spring_lost_s: float | None
    vehicle_contact_lost_s: float | None
    terminal_points_ft: dict[str, tuple[float, float, float] | None]
    end_time_s: float
    nfev: int
    trajectory: Trajectory = field(repr=False)
    notes: tuple[str, ...] = ()
    no_hit_reason: str | None = None
    ground_passage: dict | None = None
    contact_end_s: float | None = None
    #: who integrated the run: "scipy" (``solve_ivp``), "compiled" (:mod:`.dop853`, the
    #: batch), or "compiled+scipy" (a batch run some of whose segments ``solve_ivp`` solved)
    integrator: str = "scipy"

    @property
    def hit_message(self) -> str | None:
        return self.hit.message if self.hit else None

    @property
    def hit_time_s(self) -> float | None:
        return self.hit.time_s if self.hit else None
