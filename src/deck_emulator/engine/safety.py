"""Occupant-risk numbers a modern reviewer asks for, from the car's velocity history.

Everything works on plain arrays, so either engine or a hand-made pulse is judged the same
way: ``t`` (s, strictly increasing) and ``vv`` (ft/s, the deck's sign: VVB < 0 moves the car
towards -XV), taken as piecewise linear between samples (the emulator's explicit step is
exactly that) and constant after the last one (nothing slows the car once the contact is
over). The definitions (10 ms average, flail-space OIV and ORA) and the limits'
(:data:`CRITERIA`) sources: docs/safety.md. The post's margin to the car body is
:func:`body_clearance`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from deck_emulator.vocabulary.scene import VehicleBody, car_boxes
from deck_emulator.vocabulary.units import G_FT_S2, M_PER_FT

from .trajectory import SAMPLED_POINTS


FT_PER_M = 1.0 / M_PER_FT
#: The flail-space model's longitudinal travel, m (NCHRP 350 / MASH: 0.6 m, "2.0 ft").
FLAIL_DISTANCE_M = 0.6
#: The averaging window of the 10 ms average deceleration and of the ridedown acceleration, s.
WINDOW_S = 0.010


# ----------------------------------------------------------------------------------- criteria

@dataclass(frozen=True)
class Standard:
    """A document limits come from: ``name`` as a table cell shows it, ``title`` in full."""

    name: str
    title: str


#: The documents the limits come from, in the order the answers print them.
STANDARDS: Mapping[str, Standard] = {
    "nchrp350": Standard("NCHRP 350", "NCHRP Report 350 (1993)"),
    "mash": Standard("MASH 2016", "AASHTO Manual for Assessing Safety Hardware (MASH), "
                     "2nd edition (2016)"),
}


@dataclass(frozen=True)
class Criterion:
    """A limit of ``standard`` (a key of :data:`STANDARDS`) on ``quantity`` (the registry's
    name, or ``occupant_compartment``): ``preferred`` and ``maximum`` in ``unit``; ``rule``:
    the limit in words where it is not a number to read against a value (the occupant
    compartment); ``source`` says where it is from."""

    name: str
    quantity: str
    unit: str
    preferred: float | None
    maximum: float | None
    source: str
    standard: str = "nchrp350"
    rule: str = ""

    def label(self) -> str:
        if self.rule:
            return self.rule
        pref = f"{self.preferred:g} {self.unit} preferred, " if self.preferred is not None else ""
        return f"{pref}{self.maximum:g} {self.unit} at most"


#: The limits the answers are judged by (breakaway supports), each with the document it is
#: taken from, as the source found states it. Only limits that can be cited are here; the ones
#: remembered but not confirmed are listed in docs/safety.md and never printed.
CRITERIA: Mapping[str, Criterion] = {
    "nchrp350_compartment": Criterion(
        "occupant compartment", "occupant_compartment", "ft", None, None,
        "NCHRP Report 350 (1993), its criteria for breakaway supports as the Highway "
        "Engineering Handbook, 'Sign and luminaire supports and similar features', states "
        "them: 'no significant deformation or intrusion of the passenger compartment'",
        rule="no intrusion into the passenger compartment"),
    "mash_compartment": Criterion(
        "occupant compartment", "occupant_compartment", "ft", None, None,
        "AASHTO MASH (2016) as TRB's NCHRP Project 22-59 statement describes it: MASH does "
        "'not allow for any part of the device ... to enter the vehicle compartment. If "
        "there is any penetration, the device fails that test. Some deformation of the "
        "vehicle occupant compartment is allowed, but varies by area of the vehicle'",
        standard="mash", rule="no part of the device enters the compartment; some "
                              "deformation allowed, by area of the vehicle"),
    "nchrp350_oiv": Criterion(
        "OIV", "oiv_m_s", "m/s", 3.0, 5.0,
        "NCHRP Report 350 (1993), Table 5.1, criterion H (support structures)"),
    "mash_oiv": Criterion(
        "OIV", "oiv_m_s", "m/s", None, 4.9,
        "AASHTO MASH (2016) as TRB's research-in-progress record 'Updating Full-Scale "
        "Testing Evaluation Requirements for Sign Supports, Poles, and Work-Zone Devices "
        "relative to MASH and EN12767' states it: 'The limit from MASH for Occupant Impact "
        "Velocity (OIV) is 4.9 m/s for all types of supports'", standard="mash"),
    "nchrp350_ora": Criterion(
        "ORA", "ora_g", "g", None, 20.0,
        "NCHRP Report 350 (1993), Table 5.1, criterion I"),
}

#: MASH's limits on the occupant compartment's deformation, as they were cited to this program
#: (MASH 2016, Section 5.2.2 and Appendix E): searched for and not found in a source here, so
#: printed only with the words :data:`NOT_RECHECKED` and never read against a number (a rigid
#: car computes no deformation: :func:`~deck_emulator.engine.ratings.compartment`).
COMPARTMENT_LIMITS: Mapping[str, Criterion] = {
    "mash_roof_deformation": Criterion(
        "roof deformation", "compartment_deformation_in", "in", None, 4.0,
        "AASHTO MASH (2016), Section 5.2.2 and Appendix E, as cited to this program: not "
        "re-checked in MASH (docs/safety.md)", standard="mash",
        rule="roof deformation at most 4 in"),
    "mash_windshield_deformation": Criterion(
        "windshield deformation", "compartment_deformation_in", "in", None, 3.0,
        "AASHTO MASH (2016), Section 5.2.2 and Appendix E, as cited to this program: not "
        "re-checked in MASH (docs/safety.md)", standard="mash",
        rule="windshield deformation at most 3 in, and no tear or hole in the windshield"),
}
#: How a limit of :data:`COMPARTMENT_LIMITS` is qualified wherever it is printed.
NOT_RECHECKED = "as cited to this program, not re-checked in MASH"

#: Every verdict word an answer prints, and what it says (one table: the ratings, the
#: tables and docs/safety.md take their words from here). A rigid car computes no
#: deformation, so no answer fails the occupant compartment: a strike on it is not judged.
VERDICTS: Mapping[str, str] = {
    "preferred": "within the preferred limit",
    "acceptable": "over the preferred limit (where there is one), within the maximum",
    "exceeds": "over the maximum",
    "passes": "the whole post (its points, the shaft Q-P, the arms) was tested against the "
              "car and no part of it met the car before the run ended: the occupant "
              "compartment (roof, windshield, side glass) was never reached",
    "not judged": "the model that ran cannot support a verdict on the occupant compartment "
                  "(the reason says why: a strike on it, whose deformation a rigid car does "
                  "not compute; a strike beside it, on the hood or the trunk, after which the "
                  "post is not followed; a model that tests only the points P, R and C)",
}


def rate(value: float | None, criterion: Criterion) -> str:
    """'preferred', 'acceptable' or 'exceeds' (or '' when there is no value)."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if criterion.preferred is not None and value <= criterion.preferred:
        return "preferred"
    return "acceptable" if value <= criterion.maximum else "exceeds"


def criteria_of(quantity: str) -> dict[str, Criterion]:
    """The cited limits on ``quantity``, in :data:`STANDARDS`' order."""
    rows = {k: c for k, c in CRITERIA.items() if c.quantity == quantity}
    return dict(sorted(rows.items(), key=lambda kc: list(STANDARDS).index(kc[1].standard)))


# ------------------------------------------------------------------------------- the history


def _history(t, vv):
    t = np.asarray(t, dtype=float)
    vv = np.asarray(vv, dtype=float)
    if t.ndim != 1 or t.shape != vv.shape:
        raise ValueError("t and vv must be 1-d arrays of the same length")
    if t.size < 2:
        raise ValueError("a velocity history needs at least two samples")
    if not np.all(np.isfinite(t)) or not np.all(np.isfinite(vv)):
        raise ValueError("t and vv must be finite")
    if np.any(np.diff(t) <= 0):
        raise ValueError("t must be strictly increasing")
    sign = -1.0 if vv[0] < 0 else 1.0
    return t, sign * vv  # forward speed u


def _speed_at(t, u, x):
    """u at times x: linear between samples, constant outside."""
    return np.interp(x, t, u)


def max_deceleration(t, vv) -> tuple[float, float]:
    """Largest deceleration between two samples: (ft/s^2, time at the middle of the interval)."""
    t, u = _history(t, vv)
    a = -np.diff(u) / np.diff(t)
    k = int(np.argmax(a))
    return float(a[k]), float(0.5 * (t[k] + t[k + 1]))


def max_window_average(
    t, vv, window: float = WINDOW_S, start: float | None = None
) -> tuple[float, float | None]:
    """Largest average deceleration over ``window`` seconds, for windows starting at or after
    ``start`` (default: the first sample): (ft/s^2, window start). The history is constant
    after its end, so late windows count the quiet tail. Returns (0.0, None) when no window
    decelerates."""
    t, u = _history(t, vv)
    lo = t[0] if start is None else max(float(start), t[0])
    if lo >= t[-1]:
        return 0.0, None
    cand = np.concatenate([t, t - window, [lo]])
    cand = np.unique(cand[(cand >= lo) & (cand <= t[-1])])
    avg = (_speed_at(t, u, cand) - _speed_at(t, u, cand + window)) / window
    k = int(np.argmax(avg))
    if avg[k] <= 0:
        return 0.0, None
    return float(avg[k]), float(cand[k])


@dataclass(frozen=True)
class FlailSpace:
    oiv_ft_s: float
    strike_time_s: float | None  # None: the occupant never strikes (no speed change)
    strike_after_contact: bool  # the history ended before the occupant had moved D
    ora_ft_s2: float
    ora_window_start_s: float | None
    distance_ft: float


def flail_space(
    t, vv, *, flail_distance_ft: float = FLAIL_DISTANCE_M * FT_PER_M, window: float = WINDOW_S
) -> FlailSpace:
    """The flail-space model on a piecewise-linear history (see the module docstring)."""
    t, u = _history(t, vv)
    D = float(flail_distance_ft)
    if D <= 0:
        raise ValueError("flail distance must be positive")
    u0 = u[0]
    rel = u0 - u  # relative speed of the occupant, at the samples
    dt = np.diff(t)
    x = np.concatenate([[0.0], np.cumsum(0.5 * (rel[:-1] + rel[1:]) * dt)])
    hit = np.nonzero(x >= D)[0]
    if hit.size:
        k = int(hit[0]) - 1  # strike inside [t_k, t_k+1]
        # x(s) = x_k + r_k s + (r_k1 - r_k) s^2 / (2 h) = D on 0 < s <= h
        h, rk, rk1 = dt[k], rel[k], rel[k + 1]
        a, b, c = (rk1 - rk) / (2 * h), rk, x[k] - D
        if abs(a) < 1e-15 * max(abs(b), 1.0):
            s = -c / b
        else:
            disc = max(b * b - 4 * a * c, 0.0)
            roots = [(-b + sq) / (2 * a) for sq in (math.sqrt(disc), -math.sqrt(disc))]
            inside = [r for r in roots if -1e-12 <= r <= h * (1 + 1e-12)]
            s = min(inside) if inside else h
        ts = float(t[k] + s)
        oiv = float(rk + (rk1 - rk) * s / h)
        after = False
    else:
        dv = float(rel[-1])
        if dv <= 0:
            return FlailSpace(0.0, None, True, 0.0, None, D)
        ts = float(t[-1] + (D - x[-1]) / dv)
        oiv = dv
        after = True
    ora, start = max_window_average(t, u, window, start=ts)
    return FlailSpace(oiv, ts, after, ora, start, D)


# ------------------------------------------------------------------------------------ assess


@dataclass(frozen=True)
class PulseMetrics:
    """The occupant-risk numbers of one velocity history (see the module docstring)."""

    max_decel_sampled_g: float
    max_decel_sampled_time_s: float
    max_decel_10ms_g: float
    max_decel_10ms_start_s: float | None
    oiv_ft_s: float
    oiv_m_s: float
    occupant_strike_time_s: float | None
    strike_after_contact: bool
    ora_g: float
    ora_window_start_s: float | None
    flail_distance_ft: float

    def lines(self) -> list[str]:
        """Human-readable lines, with the cited limits (no verdict: a pulse alone cannot say
        whether the post entered the car; :func:`ratings` rates a run)."""
        ms = lambda s: "never" if s is None else f"{1000 * s:.1f} ms"
        limits = lambda q: "; ".join(f"{STANDARDS[c.standard].name}: {c.label()}"  # noqa: E731
                                     for c in criteria_of(q).values())
        when = " (after contact ended: relative speed = ΔV)" if self.strike_after_contact else ""
        return [
            f"max deceleration between samples {self.max_decel_sampled_g:.2f} g at "
            f"{ms(self.max_decel_sampled_time_s)}; "
            f"max 10 ms average {self.max_decel_10ms_g:.2f} g",
            f"OIV {self.oiv_m_s:.2f} m/s ({self.oiv_ft_s:.2f} ft/s), occupant strikes at "
            f"{ms(self.occupant_strike_time_s)}{when} ({limits('oiv_m_s')})",
            f"ORA {self.ora_g:.2f} g ({limits('ora_g')})",
        ]


def assess(
    t,
    vv,
    *,
    g: float = G_FT_S2,
    flail_distance_ft: float = FLAIL_DISTANCE_M * FT_PER_M,
    window: float = WINDOW_S,
) -> PulseMetrics:
    """All the pulse numbers of a velocity history ``(t s, vv ft/s)``."""
    t, u = _history(t, vv)
    amax, tmax = max_deceleration(t, u)
    a10, t10 = max_window_average(t, u, window)
    fs = flail_space(t, u, flail_distance_ft=flail_distance_ft, window=window)
    oiv_m_s = fs.oiv_ft_s / FT_PER_M
    ora_g = fs.ora_ft_s2 / g
    return PulseMetrics(
        max_decel_sampled_g=amax / g,
        max_decel_sampled_time_s=tmax,
        max_decel_10ms_g=a10 / g,
        max_decel_10ms_start_s=t10,
        oiv_ft_s=fs.oiv_ft_s,
        oiv_m_s=oiv_m_s,
        occupant_strike_time_s=fs.strike_time_s,
        strike_after_contact=fs.strike_after_contact,
        ora_g=ora_g,
        ora_window_start_s=fs.ora_window_start_s,
        flail_distance_ft=fs.distance_ft,
    )


# ---------------------------------------------------------------------- the post over the car

#: A car without an outline, drawn and checked as one of zero size.
NO_BODY = VehicleBody(0, 0, 0, 0, 0, 0, 0, 0)


def car_body(scene) -> VehicleBody:
    """The car's outline of a scene (:data:`NO_BODY` without a car or an outline)."""
    car = scene.vehicle
    return car.body if car is not None and car.body is not None else NO_BODY


def approach_angle_rad(scene) -> float:
    """The car's approach angle alpha of a scene (0 without a car)."""
    return scene.vehicle.approach_angle_rad if scene.vehicle is not None else 0.0


@dataclass(frozen=True)
class Clearance:
    """Least vertical clearance of the post above the car body while over it (ft).

    ``body_ft``: over the whole outline (hood, roof, trunk); ``roof_ft``: over the passenger
    compartment only (windshield base SV to the end of the top XENTOP: the roof line HTV,
    below which the listing calls it the windshield). ``None``: the post was never over
    that part of the car. Negative: the post's line is inside the outline (a hit, or a
    pass through the body the listing does not see because it tests only P, R and C).
    ``*_time_s`` when, ``*_surface`` over what (hood, roof, trunk), ``*_where`` the place
    on the post (``Q-P 0.73``: 73 % of the way from Q to P). ``touch_time_s``: the first
    instant any place on the post's line is inside the outline (None: never) -- when the post
    would meet the car if the whole line were checked, not just P, R and C as the listing does;
    ``touch_surface`` what it meets first, ``touch_where`` the place on the post (as
    ``*_where``).
    """

    body_ft: float | None
    body_time_s: float | None
    body_surface: str | None
    body_where: str | None
    roof_ft: float | None
    roof_time_s: float | None
    roof_where: str | None
    instants: int
    touch_time_s: float | None = None
    touch_surface: str | None = None
    touch_where: str | None = None


def _segments(points: Mapping[str, np.ndarray]):
    """The post as segments (label, A (n,3), B (n,3)): Q-P, P-R, the second arm P-U where the
    post has one, and C as a point if it is not on them."""
    out = []
    chain = [k for k in ("Q", "P", "R") if k in points]
    pairs = list(zip(chain, chain[1:]))
    if "U" in points and "P" in points:
        pairs.append(("P", "U"))
    for a, b in pairs:
        out.append((f"{a}-{b}", np.asarray(points[a], float), np.asarray(points[b], float)))
    if "C" in points:
        c = np.asarray(points["C"], float)
        if not any(np.allclose(c, np.asarray(points[k], float)) for k in chain):
            out.append(("C", c, c))
    return out


def _clip(ax, ay, dx, dy, x0, x1, y0, y1):
    """Liang-Barsky: the parameter interval [lo, hi] of A + s*(B - A), s in [0, 1], inside the
    rectangle x0 <= x <= x1, y0 <= y <= y1 (vectorised, the arguments broadcast together);
    ok where it is not empty."""
    shape = np.broadcast_shapes(*(np.shape(v) for v in (ax, ay, dx, dy, x0, x1, y0, y1)))
    lo = np.zeros(shape)
    hi = np.ones(shape)
    ok = np.ones(shape, dtype=bool)
    for p, q in ((-dx, ax - x0), (dx, x1 - ax), (-dy, ay - y0), (dy, y1 - ay)):
        ok &= ~((p == 0) & (q < 0))
        with np.errstate(divide="ignore", invalid="ignore"):
            r = q / p  # read only where p is not 0
        lo = np.where(p < 0, np.maximum(lo, r), lo)
        hi = np.where(p > 0, np.minimum(hi, r), hi)
    return lo, hi, ok & (lo <= hi)


def body_clearance(
    times, points: Mapping[str, np.ndarray], sv, body: VehicleBody, alpha_rad: float = 0.0, *,
    free=None
) -> Clearance:
    """The post's least clearance above the car body (see :class:`Clearance`).

    ``times`` (n,) s; ``points`` name -> (n, 3) positions in XX, YY, ZZ (ft) of Q, P, R
    (and C); ``sv`` (n,) the car's position; ``body`` the car's outline, ``alpha_rad`` its
    approach angle; ``free`` (n,) bool, the free-flight instants (default: all).

    Exact for straight segments: each segment Q-P, P-R is clipped to the footprint of the
    hood, the top and the trunk (in XV, YV), and its height above that part's surface is
    least at an end of the clipped piece. A (segment, part) pair counts only from the first
    free-flight instant at which the segment is not inside that part: right after separation
    the foot of the post can still be inside the *undeformed* outline (the crush the car
    took), which is not a post falling on the car.
    """
    times = np.asarray(times, dtype=float)
    sv = np.asarray(sv, dtype=float)
    n = times.size
    free = np.ones(n, dtype=bool) if free is None else np.asarray(free, dtype=bool)
    idx = np.nonzero(free)[0]
    ca, sa = math.cos(alpha_rad), math.sin(alpha_rad)
    segments = _segments(points) if idx.size else []
    least = roof = touch = None  # (clearance, time, surface, where) / (time, surface, where)
    if segments:  # every (segment, part) pair at once, axes (segment, part, instant): each
        # number is the one a pair alone would give (the same operations, element by element)
        boxes = car_boxes(body)  # the car's three boxes (the core's one definition), at SV
        A = np.stack([a[idx] for _, a, _ in segments])[:, None]
        B = np.stack([b[idx] for _, _, b in segments])[:, None]
        axv, ayv = A[..., 0] * ca - A[..., 1] * sa, A[..., 0] * sa + A[..., 1] * ca
        bxv, byv = B[..., 0] * ca - B[..., 1] * sa, B[..., 0] * sa + B[..., 1] * ca
        dx, dy, dz = bxv - axv, byv - ayv, B[..., 2] - A[..., 2]
        x0 = np.stack([sv[idx] + b.x0_ft for b in boxes])[None]
        x1 = np.stack([sv[idx] + b.x1_ft for b in boxes])[None]
        top = np.array([b.top_ft for b in boxes])[None, :, None]
        lo, hi, ok = _clip(axv, ayv, dx, dy, x0, x1, body.left_fender_ft,
                           body.right_fender_ft)
        z_lo, z_hi = A[..., 2] + lo * dz, A[..., 2] + hi * dz
        clear = np.minimum(z_lo, z_hi) - top
        at = np.where(z_lo <= z_hi, lo, hi)
        outside = ~ok | (clear >= 0)
        # a pair counts from its first instant outside the part (the docstring)
        count = ok & (np.arange(idx.size) >= np.argmax(outside, axis=-1)[..., None])
        counted = outside.any(axis=-1) & count.any(axis=-1)
        ks = np.argmin(np.where(count, clear, np.inf), axis=-1)
        inside = count & (clear < 0)
        touched, js = inside.any(axis=-1), np.argmax(inside, axis=-1)
        t = times[idx]
    for i, (label, _, _) in enumerate(segments):
        for j, part in enumerate(boxes):
            if not counted[i, j]:
                continue
            surface, k = part.part, ks[i, j]
            c = float(clear[i, j, k])
            where = label if label == "C" else f"{label} {at[i, j, k]:.2f}"
            if least is None or c < least[0]:
                least = (c, float(t[k]), surface, where)
            if surface == "roof" and (roof is None or c < roof[0]):
                roof = (c, float(t[k]), where)
            if touched[i, j]:
                k = js[i, j]
                if touch is None or t[k] < touch[0]:
                    touch = (float(t[k]), surface,
                             label if label == "C" else f"{label} {at[i, j, k]:.2f}")
    b = least or (None,) * 4
    r = roof or (None,) * 3
    tt = touch or (None, None, None)
    return Clearance(
        body_ft=b[0],
        body_time_s=b[1],
        body_surface=b[2],
        body_where=b[3],
        roof_ft=r[0],
        roof_time_s=r[1],
        roof_where=r[2],
        instants=int(idx.size),
        touch_time_s=tt[0],
        touch_surface=tt[1],
        touch_where=tt[2],
    )


# ------------------------------------------------------------------------- of an engine's run


def assess_outcome(out) -> PulseMetrics | None:
    """The pulse numbers of an :class:`~deck_emulator.engine.Outcome` over its contact."""
    t, vv = out.contact_history()
    if t.size < 2:
        return None
    return assess(t, vv, g=out.gravity_ft_s2 or G_FT_S2)


def clearance_of(out, until_s: float = math.inf) -> Clearance | None:
    """The post's least clearance above the car in an outcome's free flight, up to ``until_s``
    (inclusive): the margin it kept before a strike the model cannot follow past."""
    if not out.t.size or not out.free.any():
        return None
    free = out.free & (out.t <= until_s)
    if not free.any():
        return None
    pts = {k: v for k, v in out.points.items() if k in SAMPLED_POINTS}
    if "C" in pts and np.isnan(pts["C"][free]).any():
        pts.pop("C")
    return body_clearance(out.t, pts, out.sv, car_body(out.scene),
                          approach_angle_rad(out.scene), free=free)


# ------------------------------------------------------------------ where the post meets the car


@dataclass(frozen=True)
class Strike:
    """Where a place on the post meets the car: ``car_part`` the box of the car's outline
    (hood, roof, trunk: :func:`~deck_emulator.vocabulary.scene.car_boxes`), ``face`` what it
    meets in the verdicts' words (for the occupant compartment its windshield, roof or side
    glass: :data:`~deck_emulator.vocabulary.scene.COMPARTMENT_FACES`; else the part's name),
    ``occupant_compartment`` whether that box is the occupant compartment (None: where on the
    car is not known, the engine gave neither the place nor a surface that says)."""

    car_part: str
    face: str
    occupant_compartment: bool | None


#: A hit's surface -> the box it is a face of, where the surface says (the flanks, SIDE, are
#: a face of every box: the place decides). The surfaces are the engines' (vocabulary.events).
_SURFACE_PART = {"hood": "hood", "front": "hood", "windshield": "roof", "top": "roof",
                 "trunk": "trunk"}


def _place(out, time_s: float, label: str, fraction: float | None) -> np.ndarray | None:
    """A place on the post at ``time_s`` (XX, YY, ZZ): a point by its letter, a place on a
    segment ``A-B`` at ``fraction`` of the way from A (``where`` 'Q-P 0.73'); None where the
    engine did not give it."""
    ends = label.split("-")
    try:  # the engine's own names: a KeyError is a label it has no point for
        if len(ends) == 2:
            a = np.asarray(out.position(ends[0], time_s), float).reshape(3)
            b = np.asarray(out.position(ends[1], time_s), float).reshape(3)
            return a + (0.5 if fraction is None else float(fraction)) * (b - a)
        return np.asarray(out.position(label, time_s), float).reshape(3)
    except KeyError:  # a label the engine has no point for ('?', 'R&U')
        return None


def _box_faces(out, time_s: float, label: str, fraction: float | None, boxes) -> dict | None:
    """How far inside each face of each box the place is at ``time_s`` (ft, negative:
    outside that face): ``{part: {front, rear, left, right, top}}``; None without a place."""
    p = _place(out, time_s, label, fraction)
    if p is None or not np.all(np.isfinite(p)):
        return None
    alpha = approach_angle_rad(out.scene)
    ca, sa = math.cos(alpha), math.sin(alpha)
    sv = float(np.interp(time_s, out.t, out.sv)) if out.t.size else 0.0
    xv, yv, z = p[0] * ca - p[1] * sa - sv, p[0] * sa + p[1] * ca, p[2]
    return {b.part: {"front": xv - b.x0_ft, "rear": b.x1_ft - xv, "left": yv - b.left_ft,
                     "right": b.right_ft - yv, "top": b.top_ft - z} for b in boxes.values()}


def strike_on_car(out, time_s: float, label: str, *, fraction: float | None = None,
                  surface: str | None = None) -> Strike:
    """What of the car the place ``label`` (at ``fraction`` along a segment) of the post meets
    at ``time_s``: the box whose faces it is least outside of (it is on or just inside one at
    a strike), and the face it came through: of the faces it was outside of at the sample
    before, the one it crossed last (Liang-Barsky's entering face, the path taken as straight
    between the two samples); the nearest face where there is no sample before. ``surface``:
    the engine's word for the hit (vocabulary.events.Surface value) where it gave one; a
    surface that names its box (hood, windshield, top, trunk) decides the box and the face."""
    from deck_emulator.vocabulary.scene import COMPARTMENT_FACES, car_boxes

    boxes = {b.part: b for b in car_boxes(car_body(out.scene))}
    named = _SURFACE_PART.get(surface or "")
    faces = _box_faces(out, time_s, label, fraction, boxes)
    if named is None and faces is None:  # no place, no surface that says: not known
        return Strike("car", surface or "car", None)
    if named is None:
        named = min(faces, key=lambda k: max(0.0, -min(faces[k].values())))
    box = boxes[named]
    if not box.occupant_compartment:
        return Strike(named, named, False)
    if surface in ("windshield", "top"):
        return Strike(named, "windshield" if surface == "windshield" else "roof", True)
    if faces is None:
        return Strike(named, "occupant compartment", True)
    now = faces[named]
    earlier = out.t[(out.t < time_s) & out.free] if out.free.size == out.t.size else []
    before = (_box_faces(out, float(earlier[-1]), label, fraction, boxes)
              if len(earlier) else None)
    crossed = {}
    if before is not None:
        for face, d0 in before[named].items():
            d1 = now[face]
            if d0 < 0 and d1 > d0:  # outside that face before, moving in across it
                crossed[face] = d0 / (d0 - d1)  # where on the way it crossed that face
    face = max(crossed, key=crossed.get) if crossed else min(now, key=now.get)
    return Strike(named, COMPARTMENT_FACES[face], True)
