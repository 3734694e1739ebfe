"""Where the post ends and how it has turned, read off an :class:`Outcome`: the definitions
behind the registry's terminal coordinates and arm spin
(:mod:`deck_emulator.engine.quantities`), and the comparison of two runs' paths (Chapter V's
"variations of up to 15 degrees in the angle Alpha do not significantly affect the
trajectory").

Axes: the report's XL, YL, ZL (Chapter VI, seed line 1724: origin on the ground under the base
of the support, the road axes XX, YY, ZZ translated): :meth:`Outcome.to_l`.  The car drives
towards -XL; the arm reaches out over the highway along -YL (the report's deck: R at YYRO =
-8.47 ft, the shaft at YYPO = 1.53 ft), so +YL is away from the highway.
"""

from __future__ import annotations

import math

import numpy as np


def _rot_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation taking unit vector ``a`` to unit vector ``b`` (Rodrigues'
    formula); the identity where they are parallel."""
    v = np.cross(a, b)
    c = float(a @ b)
    s = float(np.linalg.norm(v))
    if s < 1e-12:
        return np.eye(3)
    k = v / s
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    ang = math.atan2(s, c)
    return np.eye(3) + math.sin(ang) * K + (1.0 - math.cos(ang)) * K @ K


def spin_deg(P, Q, R, P0, Q0, R0) -> float:
    """The rotation (deg, in (-180, 180], right hand about the post's axis Q->P at the start)
    that takes the post from (P0, Q0, R0) to (P, Q, R), once the fall of its axis is taken
    out; read from one attitude alone, it cannot tell a turn of +160 deg from one of -200
    deg (a run's turn is tracked by :func:`spin_track_deg`): the final
    attitude is written as a spin about the initial axis followed by the smallest rotation
    (the swing) taking the initial axis Q0->P0 to the final axis Q->P; the spin is read from
    the arm P->R.  For a post standing upright at the start the axis is +ZL: a negative spin
    is clockwise seen from above (the report's "negative rotation ... about the ZL axis")."""
    P, Q, R, P0, Q0, R0 = (np.asarray(x, dtype=float) for x in (P, Q, R, P0, Q0, R0))
    a0 = (P0 - Q0) / np.linalg.norm(P0 - Q0)
    a1 = (P - Q) / np.linalg.norm(P - Q)
    swing = _rot_between(a0, a1)
    v0 = R0 - P0
    v0 = v0 - (v0 @ a0) * a0
    w = swing.T @ (R - P)
    w = w - (w @ a0) * a0
    return math.degrees(math.atan2(float(np.cross(v0, w) @ a0), float(v0 @ w)))


def end_index(o) -> int:
    """The sample at the hit (nearest it); the last sample of a run without one."""
    return o.at(o.hit_time_s) if o.hit_time_s is not None else len(o.t) - 1


def start_l(o, name: str):
    """Point ``name`` at t = 0 in XL, YL, ZL (None where the outcome has no such point)."""
    if not o.t.size or name not in o.points:
        return None
    p = np.asarray(o.points[name][0], dtype=float)
    return None if np.isnan(p).any() else tuple(float(x) for x in o.to_l(p))


def point_at_end_l(o, name: str):
    """Point ``name`` at the end of the run in XL, YL, ZL: the engine's own terminal point
    (``Outcome.terminal``: P, Q, R, U, C as the engine reports them at the hit), else (the
    mass centre ``CM``) the sample at the hit; None where there is none."""
    if o.hit is not None and name in o.terminal and o.terminal[name] is not None:
        xyz = o.terminal[name]
        if all(x is not None for x in xyz):
            return tuple(float(x) for x in xyz)
    if not o.t.size or name not in o.points:
        return None
    p = np.asarray(o.points[name][end_index(o)], dtype=float)
    return None if np.isnan(p).any() else tuple(float(x) for x in o.to_l(p))


def spin_track_deg(P, Q, R) -> np.ndarray:
    """The spin of :func:`spin_deg` at every sample of a path (``P``, ``Q``, ``R``: arrays of
    shape (n, 3), the first row the start), tracked continuously: each sample's spin is the
    one of the values :func:`spin_deg` gives modulo 360 deg nearest the previous sample's, so
    a post that turns on past a half turn reads -200 deg, not +160 deg.  The path must be
    sampled finely enough that the spin moves less than half a turn from one sample to the
    next (:func:`arm_spin_track` reports the largest step)."""
    P, Q, R = (np.asarray(x, dtype=float) for x in (P, Q, R))
    a0 = (P[0] - Q[0]) / np.linalg.norm(P[0] - Q[0])
    a1 = (P - Q) / np.linalg.norm(P - Q, axis=1)[:, None]
    v0 = R[0] - P[0]
    v0 = v0 - (v0 @ a0) * a0
    w = R - P
    # the swing's inverse (Rodrigues, by -angle about a0 x a1) applied to each arm P->R
    k = np.cross(a0, a1)
    s = np.linalg.norm(k, axis=1)
    c = a1 @ a0
    turned = s >= 1e-12
    k[turned] /= s[turned, None]
    k[~turned] = 0.0
    ang = np.arctan2(s, c)
    kw = np.einsum("ij,ij->i", k, w)
    w = (w * np.cos(ang)[:, None] - np.cross(k, w) * np.sin(ang)[:, None]
         + k * (kw * (1.0 - np.cos(ang)))[:, None])
    w = w - np.outer(w @ a0, a0)
    wrapped = np.degrees(np.arctan2(np.cross(v0, w) @ a0, w @ v0))
    return np.unwrap(wrapped, period=360.0)


def _index(o, at: str) -> int | None:
    if at == "end":
        return end_index(o)
    if at == "release":
        return None if o.vehicle_contact_lost_s is None else o.at(o.vehicle_contact_lost_s)
    raise ValueError(f"at: 'end' or 'release', not {at!r}")


def arm_spin_track(o, at: str = "end") -> dict | None:
    """The arm's spin about the post's axis tracked over the run's samples from t = 0 to
    ``at`` (``"end"``: the sample at the hit, or the last; ``"release"``: the sample at the
    loss of contact with the car): ``t`` (s) and ``spin_deg`` (:func:`spin_track_deg`), with
    what the tracking rests on: ``largest_step_deg`` (the largest change between two
    samples: the tracking holds while it is well under 180 deg) and ``largest_swing_deg``
    (the largest angle the post's axis has turned from its start: the decomposition is
    singular at 180 deg).  None without the points or the instant."""
    if not o.t.size or any(k not in o.points for k in "PQR"):
        return None
    i = _index(o, at)
    if i is None:
        return None
    P, Q, R = (np.asarray(o.points[k][: i + 1], dtype=float) for k in ("P", "Q", "R"))
    if np.isnan(P).any() or np.isnan(Q).any() or np.isnan(R).any():
        return None
    spin = spin_track_deg(P, Q, R)
    a = (P - Q) / np.linalg.norm(P - Q, axis=1)[:, None]
    swing = np.degrees(np.arccos(np.clip(a @ a[0], -1.0, 1.0)))
    return {"t": np.asarray(o.t[: i + 1], dtype=float), "spin_deg": spin,
            "largest_step_deg": float(np.abs(np.diff(spin)).max()) if spin.size > 1 else 0.0,
            "largest_swing_deg": float(swing.max())}


def arm_spin_deg(o, at: str = "end") -> float | None:
    """The arm's spin about the post's axis from t = 0 to ``at`` (``"end"`` or
    ``"release"``), tracked continuously over the run's samples (:func:`arm_spin_track`):
    the turn the arm made, not only its attitude at ``at`` (which :func:`spin_deg` reads,
    within a half turn either way).  None without the points or the instant."""
    track = arm_spin_track(o, at)
    return None if track is None else float(track["spin_deg"][-1])


def largest_distance_ft(a, b, name: str) -> float | None:
    """The largest distance (ft) between point ``name`` of two runs at the same instants,
    over the time both ran (``a``'s samples, ``b`` linearly interpolated between its own);
    in XL, YL, ZL, each run about its own base.  None where either lacks the point."""
    if not a.t.size or not b.t.size or name not in a.points or name not in b.points:
        return None
    end = min(a.end_time_s, b.end_time_s)
    keep = a.t <= end + 1e-12
    t = a.t[keep]
    pa = a.to_l(np.asarray(a.points[name], dtype=float)[keep])
    pb_all = b.to_l(np.asarray(b.points[name], dtype=float))
    pb = np.column_stack([np.interp(t, b.t, pb_all[:, k]) for k in range(3)])
    d = np.linalg.norm(pa - pb, axis=1)
    d = d[~np.isnan(d)]
    return float(d.max()) if d.size else None
