"""The report's Chapter VI parameter study, regenerated: ``deck-emulator sweep``.

Every (speed, angle) of a grid is one scene: the base deck with VVB and ALPHA changed. Each
scene is run by one engine, in parallel over worker processes, and written as

* ``sweep.csv`` -- one row per scene: every output (events, hit, the report's quantities, the
  occupant-risk numbers of :mod:`deck_emulator.studies.safety`, the post's margin above the car) and,
  where the report has the case, the report's value and our difference;
* ``sweep.md`` -- laid out like Tables 11 and 12 of the report: one table per speed, a column
  per approach angle, each cell ``ours (report, diff)``.

This module also holds the small engine layer the pictures use (:func:`run_engine`): either
engine's run as an :class:`EngineResult` -- times, the post's named points, the car's position
and velocity, the contact pulse, the events and the hit -- so :mod:`deck_emulator.present.plot` and the
sweep treat the 1967 program and the modern core alike.

Rules (stated once, here)
-------------------------
* Speed (mph) -> ``VVB = -(mph * 88/60)`` ft/s cut to two decimals (towards zero), as the
  report's deck punched 40 mph (``-58.66`` for 58.667) and as ``decks/steel20.dat`` has 20 mph
  (``-29.33``): so 20 and 40 mph give exactly the decks in ``decks/``. ``--vvb-decimals``
  changes the number of decimals (up to 5, what F10.5 shows).
* Angle (deg) -> ``ALPHA`` in radians rounded to five decimals (F10.5): 15 deg -> 0.26180.
* Emulator: arithmetic ``double``. Where ALPHA != 0 the ``ed-direction`` erratum is applied
  (as printed, ED's root search walks away from its root and the guard stops the run); where
  ALPHA = 0 the listing runs as printed, and if ED's guard still stops it the scene is run
  again with the erratum. The ``errata`` and ``errata_note`` columns say which and why.
* Core: :func:`deck_emulator.core.simulate` with the ``legacy`` preset (the listing's quirks,
  the one comparable with the report) unless ``--preset physical``.
* The report's ΔV is the speed lost by the end of the crush pulse (``extract``'s
  ``crush_pulse_end``: where the spring force is first cut to FCONST); for the core the same
  instant is its "force cap engaged" event. The report's maximum deceleration is the largest
  *printed* FSA / (WV*G) (``extract``); the core's is its continuous maximum. The safety
  columns use the whole contact pulse of either engine.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import os
import sys
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from decimal import ROUND_DOWN, ROUND_HALF_EVEN, Decimal
from pathlib import Path

import numpy as np

from deck_emulator.studies import safety
from deck_emulator import decks
from deck_emulator.files import write_atomic
from deck_emulator.legacy.deck import Deck, read_deck

__all__ = [
    "ENGINES",
    "POSTS",
    "EngineResult",
    "run_engine",
    "run_emulator",
    "run_core",
    "emulator_result",
    "safety_summary",
    "scene_deck",
    "scene_name",
    "parse_grid",
    "result_row",
    "sweep",
    "write_csv",
    "render_markdown",
    "COLUMNS",
    "add_parser",
]

#: --post -> base deck (the report's steel post, 40 mph, 0 deg).
POSTS = {"steel": decks.path(decks.REPORT_DECK)}
ENGINES = ("emulator", "core")
ERRATUM = "ed-direction"
MPH = 88.0 / 60.0
#: Report fields: (key, row label as the report prints it, decimals).
REPORT_ROWS = (
    ("delta_v_mph", "DECREASE IN VEHICLE VELOCITY (MPH)", 2),
    ("max_decel_g", "MAXIMUM VEHICLE DECELERATION (g's)", 2),
    ("XPL", "XPL (FT)", 2),
    ("YPL", "YPL (FT)", 2),
    ("ZPL", "ZPL (FT)", 2),
    ("XRL", "XRL (FT)", 2),
    ("YRL", "YRL (FT)", 2),
    ("ZRL", "ZRL (FT)", 2),
    ("XQL", "XQL (FT)", 2),
    ("YQL", "YQL (FT)", 2),
    ("ZQL", "ZQL (FT)", 2),
    ("time_to_hit_car_ms", "TIME TO HIT CAR (MILLISEC)", 1),
    ("time_to_hit_ground_ms", "TIME TO HIT GROUND (MILLISEC)", 1),
)
CAR_SURFACES = ("HOOD", "WINDSHIELD", "TOP", "TRUNK", "FRONT", "SIDE")


# ======================================================================== the engine layer


@dataclass
class EngineResult:
    """One run of either engine, as arrays over time (road axes XX, YY, ZZ; ft, s).

    ``points``: name -> (n, 3) for the post's points ``P``, ``Q``, ``R``, ``C`` and the mass
    centre ``CM`` (NaN where an engine does not give a point). ``sv``, ``vv``: the car's
    position and velocity along XV. ``free``: the free-flight samples. ``pulse_t``,
    ``pulse_g``: the car's deceleration (g) over the contact phase (the emulator's: per
    accepted step, the value over the interval ending at that time). ``events``: (message,
    time s) in time order. ``terminal``: P, Q, R, C at the end in XL, YL, ZL (ft).
    """

    engine: str
    name: str
    values: dict
    errata: tuple[str, ...] = ()
    note: str = ""
    t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    points: dict = field(default_factory=dict)
    sv: np.ndarray = field(default_factory=lambda: np.zeros(0))
    vv: np.ndarray = field(default_factory=lambda: np.zeros(0))
    free: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    pulse_t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    pulse_g: np.ndarray = field(default_factory=lambda: np.zeros(0))
    events: list = field(default_factory=list)
    hit: str | None = None
    hit_time_s: float | None = None
    hit_point: str | None = None
    hit_surface: str | None = None
    first_spring_lost_s: float | None = None
    vehicle_contact_lost_s: float | None = None
    delta_v_mph: float | None = None
    delta_v_definition: str = ""
    max_decel_g: float | None = None
    terminal: dict = field(default_factory=dict)
    error: str | None = None
    run_s: float = 0.0

    # -- derived ------------------------------------------------------------------------

    @property
    def speed_mph(self) -> float:
        return abs(self.values["VVB"]) / MPH

    @property
    def angle_deg(self) -> float:
        return math.degrees(self.values["ALPHA"])

    @property
    def end_time_s(self) -> float:
        return float(self.t[-1]) if self.t.size else 0.0

    def at(self, t: float) -> int:
        """Index of the sample nearest to ``t``."""
        return int(np.argmin(np.abs(self.t - t)))

    def to_l(self, p):
        """XX, YY, ZZ -> the report's XL, YL, ZL (origin on the ground under the base)."""
        d = self.values
        p = np.asarray(p, dtype=float)
        return p - np.array([d["XQO"], d["YYQO"], -d["HEIGHT"]])

    def contact_history(self):
        """(t, vv) up to the end of the contact with the car (the whole run if it never ends)."""
        if self.vehicle_contact_lost_s is None or not self.t.size:
            return self.t, self.vv
        k = int(np.searchsorted(self.t, self.vehicle_contact_lost_s + 1e-9, side="right"))
        k = max(k, 2)
        return self.t[:k], self.vv[:k]

    def safety(self) -> safety.PulseMetrics | None:
        t, vv = self.contact_history()
        if t.size < 2:
            return None
        return safety.assess(t, vv, g=self.values.get("G") or safety.G_FT_S2)

    def clearance(self) -> safety.Clearance | None:
        if not self.t.size or not self.free.any():
            return None
        pts = {k: v for k, v in self.points.items() if k in ("P", "Q", "R", "C")}
        if "C" in pts and np.isnan(pts["C"][self.free]).any():
            pts.pop("C")
        return safety.body_clearance(self.t, pts, self.sv, self.values, free=self.free)

    def outcome(self) -> str:
        if self.hit:
            return _comment(self.hit)
        return f"NO HIT ({self.error})" if self.error else "NO HIT"


def safety_summary(res: EngineResult) -> dict:
    """The occupant-risk numbers, the limits they are judged by, and the post's margin above
    the car, as plain JSON-able values (for ``deck-emulator summary``)."""
    m = res.safety()
    c = res.clearance()
    return {
        "basis": "vehicle velocity over the contact phase; flail-space model (0.6 m); "
        "see docs/safety.md",
        "pulse": None if m is None else m.as_dict(),
        "limits": {
            k: {"preferred": v.preferred, "maximum": v.maximum, "unit": v.unit, "source": v.source}
            for k, v in safety.CRITERIA.items()
        },
        "clearance_ft": None if c is None else c.as_dict(),
    }


def _comment(message: str) -> str:
    """'THE POST HAS HIT THE GROUND WITH POINT R' -> 'POST HITS GROUND WITH POINT R'."""
    text = message.replace("THE POST HAS HIT THE ", "POST HITS ")
    return text.replace(" OF THE VEHICLE", " OF CAR")


def _surface(message: str | None) -> str | None:
    if not message:
        return None
    for s in ("GROUND",) + CAR_SURFACES:
        if s in message:
            return s
    return None


def _initial_points(d) -> dict:
    return {
        "P": (d["XPO"], d["YYPO"], d["ZZPO"]),
        "Q": (d["XQO"], d["YYQO"], d["ZZQO"]),
        "R": (d["XRO"], d["YYRO"], d["ZZRO"]),
        "C": (d["XCO"], d["YYCO"], d["ZZCO"]),
        "CM": (0.0, 0.0, 0.0),
    }


def errata_for(values, requested: Sequence[str] | None = None) -> tuple[tuple[str, ...], str]:
    """The errata the emulator runs a deck with, and why (see the module docstring)."""
    if requested is not None and len(requested):
        return tuple(requested), "errata as requested"
    if values["ALPHA"] != 0.0:
        return (ERRATUM,), (
            f"{ERRATUM} applied: ALPHA != 0 (as printed, ED's root search "
            "walks away from its root and never ends)"
        )
    return (), "as printed"


def run_emulator(
    deck: Deck, *, errata: Sequence[str] | None = None, name: str = ""
) -> EngineResult:
    """The 1967 program in binary64 with a trace; errata as :func:`errata_for` decides."""
    from deck_emulator.legacy.emulator import EmulatorError, run_deck

    d = dict(deck.values)
    chosen, note = errata_for(d, errata)
    started = time.perf_counter()
    error = None
    try:
        run = run_deck(deck, "double", errata=chosen, trace=True)
    except EmulatorError as exc:
        if exc.guard == "ed_iterations" and ERRATUM not in chosen and errata is None:
            chosen = chosen + (ERRATUM,)
            note = (
                f"{ERRATUM} applied: as printed, ED's root search did not end "
                f"(t = {exc.time if exc.time is not None else float('nan'):.4f} s)"
            )
            try:
                run = run_deck(deck, "double", errata=chosen, trace=True)
            except EmulatorError as exc2:
                run, error = exc2.run, str(exc2)
        else:
            run, error = exc.run, str(exc)
    res = emulator_result(run, deck, errata=chosen, note=note, error=error, name=name)
    res.run_s = time.perf_counter() - started
    return res


def emulator_result(
    run, deck: Deck, *, errata=(), note: str = "", error: str | None = None, name: str = ""
) -> EngineResult:
    """An emulator :class:`~deck_emulator.legacy.emulator.Run` (made with ``trace=True``) of ``deck``
    as an :class:`EngineResult` (what ``summary`` needs for :func:`safety_summary`)."""
    from deck_emulator.legacy.extract import ExtractError, extract

    d = dict(deck.values)
    errata = tuple(errata or getattr(run, "errata", ()) or ())
    note = note or (f"errata: {'+'.join(errata)}" if errata else "as printed")
    res = EngineResult("emulator", name or _deck_name(deck), d, errata, note, error=error)
    rows = run.trace
    init = _initial_points(d)
    n = len(rows) + 1
    t = np.empty(n)
    t[0] = 0.0
    pts = {k: np.full((n, 3), np.nan) for k in init}
    for k, p in init.items():
        pts[k][0] = p
    sv, vv = np.empty(n), np.empty(n)
    sv[0], vv[0] = d["SVB"], d["VVB"]
    free = np.zeros(n, dtype=bool)
    c_is_q = init["C"] == init["Q"]
    for i, r in enumerate(rows, start=1):
        t[i] = r["t"]
        sv[i], vv[i] = r["SV"], r["VV"]
        free[i] = r["phase"] == "free"
        pts["CM"][i] = (r["XCM"], r["YYCM"], r["ZZCM"])
        for k in ("P", "Q", "R"):
            pts[k][i] = (r[f"X{k}"], r[f"YY{k}"], r[f"ZZ{k}"])
        if "XC" in r:
            pts["C"][i] = (r["XC"], r["YYC"], r["ZZC"])
        elif c_is_q:
            pts["C"][i] = pts["Q"][i]
    # the contact-to-free handover is recorded twice (label 42 and the first free step):
    # keep times strictly increasing
    keep = np.concatenate([[True], np.diff(t) > 0])
    res.t, res.sv, res.vv, res.free = t[keep], sv[keep], vv[keep], free[keep]
    res.points = {k: v[keep] for k, v in pts.items()}
    res.events = list(run.events)
    for msg, te in res.events:
        if "FIRST SPRING" in msg:
            res.first_spring_lost_s = te
        elif "THE VEHICLE" in msg and "LOST" in msg:
            res.vehicle_contact_lost_s = te
        elif "HAS HIT" in msg:
            res.hit, res.hit_time_s = msg, te
    res.hit_surface = _surface(res.hit)
    if res.hit:
        res.hit_point = (
            res.hit.rsplit("POINT ", 1)[1].strip()
            if "POINT" in res.hit
            else _vehicle_hit_point(res)
        )
    # the pulse: the deceleration over each accepted contact step
    contact = ~res.free
    tc, vc = res.t[contact], res.vv[contact]
    if tc.size >= 2:  # speed |VV| falling = deceleration > 0
        res.pulse_t = tc[1:]
        res.pulse_g = -np.diff(np.abs(vc)) / np.diff(tc) / d["G"]
    try:
        out = extract(run, deck)
    except ExtractError:
        out = None
    if out is not None:
        res.delta_v_mph = out.delta_v_mph
        res.delta_v_definition = "crush pulse end (printed FSA first cut to FCONST)"
        res.max_decel_g = out.max_decel_g
        res.terminal = {k: (p.XL, p.YL, p.ZL) for k, p in out.terminal.items()}
    return res


def _vehicle_hit_point(res: EngineResult) -> str | None:
    """Which of P, R, C met the car (the listing's message does not say): the one nearest
    the surface inside the outline at the hit."""
    if res.hit_time_s is None:
        return None
    i = res.at(res.hit_time_s)
    d = res.values
    out = safety.body_outline_xv(res.sv[i], d)
    ca, sa = math.cos(d["ALPHA"]), math.sin(d["ALPHA"])
    best = None
    for k in ("P", "R", "C"):
        x, y, z = res.points[k][i]
        if np.isnan(x):
            continue
        xv, yv = x * ca - y * sa, x * sa + y * ca
        if not (d["YLFEN"] <= yv <= d["YRFEN"] and out["XBUMP"] <= xv <= out["XTAIL"]):
            continue
        h = d["HHV"] if xv < out["SV"] else d["HTV"] if xv <= out["XENTOP"] else d["HTRV"]
        gap = abs(z - h)
        if best is None or gap < best[0]:
            best = (gap, k)
    return best[1] if best else None


def run_core(
    deck: Deck,
    *,
    preset: str = "legacy",
    name: str = "",
    contact_step_s: float = 0.0002,
    free_step_s: float = 0.001,
) -> EngineResult:
    """The modern core (:func:`deck_emulator.core.simulate`) sampled on a regular grid."""
    from deck_emulator.core import CoreError, simulate
    from deck_emulator.core.scene import PRESETS, Scene

    d = dict(deck.values)
    options = PRESETS[preset]
    res = EngineResult("core", name or _deck_name(deck), d, (), f"preset {preset}")
    started = time.perf_counter()
    try:
        r = simulate(Scene.from_deck(deck, name=res.name), options)
    except (CoreError, ValueError, ArithmeticError) as exc:
        res.error = f"{type(exc).__name__}: {exc}"
        res.run_s = time.perf_counter() - started
        return res
    res.run_s = time.perf_counter() - started
    traj = r.trajectory
    t_end = float(traj.t_end)
    t_c = r.vehicle_contact_lost_s if r.vehicle_contact_lost_s is not None else t_end
    edges = [s.t0 for s in traj.segments] + [s.t1 for s in traj.segments]
    grid = np.concatenate(
        [
            np.arange(0.0, t_c, contact_step_s),
            np.arange(t_c, t_end, free_step_s),
            edges,
            [t_c, t_end],
        ]
    )
    t = np.unique(np.clip(grid, 0.0, t_end))
    res.t = t
    allp = traj.points(t)
    res.points = {k: np.asarray(allp[k]).T for k in ("P", "Q", "R", "C") if k in allp}
    res.points["CM"] = np.asarray(traj.mass_centre(t)).T
    veh = traj.vehicle(t)
    res.sv, res.vv = np.asarray(veh[0]), np.asarray(veh[1])
    res.free = t > t_c + 1e-12
    res.events = [(e.message or e.name, e.time_s) for e in r.events]
    res.first_spring_lost_s = r.first_spring_lost_s
    res.vehicle_contact_lost_s = r.vehicle_contact_lost_s
    if r.hit:
        res.hit, res.hit_time_s = r.hit.message, r.hit.time_s
        res.hit_point, res.hit_surface = r.hit.point, r.hit.surface
    # report's delta-V: at the force cap (the instant extract's crush_pulse_end marks)
    cap = next((e.time_s for e in r.events if e.name == "force cap engaged"), None)
    if cap is not None:
        vv_cap = float(traj.vehicle(cap)[1])
        res.delta_v_mph = (abs(d["VVB"]) - abs(vv_cap)) / MPH
        res.delta_v_definition = "crush pulse end (force cap engaged)"
    else:
        res.delta_v_mph = r.delta_v_mph
        res.delta_v_definition = "end of contact with the car"
    res.max_decel_g = r.max_decel_g
    res.terminal = {k: v for k, v in r.terminal_points_ft.items() if v is not None}
    if "C" in res.points and res.hit_time_s is not None:
        c = res.to_l(traj.point("C", min(res.hit_time_s, t_end)))
        res.terminal["C"] = tuple(float(x) for x in c)
    res.pulse_t, res.pulse_g = _core_pulse(traj, d, t_c, contact_step_s)
    return res


def _core_pulse(traj, d, t_c, step):
    """The car's deceleration (g) over the contact, from the model's force where it can be
    had, else from the velocity's slope."""
    model = getattr(traj, "_model", None)
    ts, gs = [], []
    try:
        for seg in traj.segments:
            if seg.phase != "contact" or seg.t1 <= seg.t0:
                continue
            n = max(math.ceil((seg.t1 - seg.t0) / (step / 2)), 2)
            tt = np.linspace(seg.t0, seg.t1, n + 1)
            ys = seg.solution(tt)
            f = [model.vehicle_force(tk, ys[:, k], seg.mode) for k, tk in enumerate(tt)]
            ts.append(tt)
            # force on the car along +XV; the car moves towards -XV when VVB < 0
            gs.append(np.asarray(f) / (d["WV"] * d["G"]) * (1.0 if d["VVB"] < 0 else -1.0))
        return np.concatenate(ts), np.concatenate(gs)
    except Exception:  # noqa: BLE001 - any change in the core's internals: use the slope
        t = np.arange(0.0, t_c, step / 2)
        if t.size < 3:
            return np.zeros(0), np.zeros(0)
        u = np.abs(traj.vehicle(t)[1])
        return t, -np.gradient(u, t) / d["G"]


def _deck_name(deck) -> str:
    path = getattr(deck, "path", None)
    return Path(path).stem if path else "deck"


def run_engine(
    deck: Deck,
    engine: str = "emulator",
    *,
    errata: Sequence[str] | None = None,
    preset: str = "legacy",
    name: str = "",
) -> EngineResult:
    if engine == "emulator":
        return run_emulator(deck, errata=errata, name=name)
    if engine == "core":
        return run_core(deck, preset=preset, name=name)
    raise ValueError(f"unknown engine {engine!r}: {ENGINES}")


# ============================================================================ the scenes


def _fmt_num(x: float) -> str:
    return f"{x:g}"


def scene_name(speed_mph: float, angle_deg: float, post: str = "steel") -> str:
    """``steel40``, ``steel40_a15`` -- the names of decks/ and of report_tables for the report's
    cases."""
    s = f"{post}{_fmt_num(speed_mph)}"
    return s if angle_deg == 0 else f"{s}_a{_fmt_num(angle_deg)}"


def vvb_for(speed_mph: float, decimals: int = 2) -> float:
    """-(mph * 88/60) ft/s cut (towards zero) to ``decimals`` decimals (module docstring)."""
    exact = Decimal(repr(float(speed_mph))) * 88 / 60
    q = exact.quantize(Decimal(1).scaleb(-decimals), rounding=ROUND_DOWN)
    return -float(q)


def alpha_for(angle_deg: float) -> float:
    """Degrees -> radians rounded to five decimals (F10.5)."""
    r = Decimal(repr(math.radians(angle_deg))).quantize(
        Decimal("0.00001"), rounding=ROUND_HALF_EVEN
    )
    return float(r)


def scene_deck(base: Deck, speed_mph: float, angle_deg: float, vvb_decimals: int = 2) -> Deck:
    return base.with_values(VVB=vvb_for(speed_mph, vvb_decimals), ALPHA=alpha_for(angle_deg))


def parse_grid(text: str) -> list[float]:
    """'20,40' or '0:45:5' (start:stop:step, stop included) or a mix: '10,20:60:10'."""
    out: list[float] = []
    for part in text.split(","):
        part = part.strip()
        if not part:
            continue
        if ":" in part:
            bits = part.split(":")
            if len(bits) != 3:
                raise ValueError(f"range {part!r}: use start:stop:step")
            a, b, s = (float(x) for x in bits)
            if s <= 0:
                raise ValueError(f"range {part!r}: step must be positive")
            k = 0
            while a + k * s <= b + 1e-9 * max(1.0, abs(b)):
                out.append(round(a + k * s, 10))
                k += 1
        else:
            out.append(float(part))
    if not out:
        raise ValueError("empty list")
    return sorted(set(out))


# ========================================================================= one scene's row


def _report_for(name: str, deck: Deck):
    """The report's values for this scene, if it is one of the report's cases (same deck)."""
    from deck_emulator.studies.report_tables import REPORT

    if name not in REPORT:
        return None
    if name in decks.names():
        ref = read_deck(decks.path(name))
        if any(ref.values[k] != deck.values[k] for k in ref.values):
            return None
    return REPORT[name]


def result_row(res: EngineResult, speed_mph: float, angle_deg: float, report=None) -> dict:
    """Everything one scene gives, as a flat dict of plain values (a CSV row)."""
    d = res.values
    row: dict = {
        "scene": res.name,
        "speed_mph": speed_mph,
        "angle_deg": angle_deg,
        "VVB_ft_s": d["VVB"],
        "ALPHA_rad": d["ALPHA"],
        "engine": res.engine,
        "errata": "+".join(res.errata) or "none",
        "errata_note": res.note,
        "error": res.error or "",
        "hit": res.hit or "",
        "hit_point": res.hit_point or "",
        "hit_surface": res.hit_surface or "",
        "hit_time_ms": None if res.hit_time_s is None else 1000 * res.hit_time_s,
        "first_spring_lost_ms": None
        if res.first_spring_lost_s is None
        else 1000 * res.first_spring_lost_s,
        "vehicle_contact_lost_ms": (
            None if res.vehicle_contact_lost_s is None else 1000 * res.vehicle_contact_lost_s
        ),
        "delta_v_mph": res.delta_v_mph,
        "delta_v_definition": res.delta_v_definition,
        "max_decel_g": res.max_decel_g,
    }
    for p in ("P", "R", "Q", "C"):
        xyz = res.terminal.get(p)
        for i, ax in enumerate("XYZ"):
            row[f"{ax}{p}L"] = None if xyz is None or xyz[i] is None else float(xyz[i])
    surf = res.hit_surface
    ms = row["hit_time_ms"]
    row["time_to_hit_car_ms"] = ms if surf in CAR_SURFACES else None
    row["time_to_hit_ground_ms"] = ms if surf == "GROUND" else None
    row["comment"] = res.outcome()
    m = res.safety() if res.t.size else None
    keys = (
        "delta_v_ft_s",
        "delta_v_m_s",
        "delta_v_mph",
        "max_decel_g",
        "max_decel_10ms_g",
        "oiv_ft_s",
        "oiv_m_s",
        "occupant_strike_time_s",
        "strike_after_contact",
        "ora_g",
        "oiv_rating",
        "ora_rating",
    )
    for k in keys:
        v = getattr(m, k) if m is not None else None
        if k == "occupant_strike_time_s":
            row["occupant_strike_ms"] = None if v is None else 1000 * v
        elif k in ("delta_v_ft_s", "delta_v_m_s", "delta_v_mph", "max_decel_g"):
            row[f"contact_{k}"] = v
        else:
            row[k] = v
    row["oiv_limit_m_s"] = safety.CRITERIA["oiv"].label()
    row["ora_limit_g"] = safety.CRITERIA["ora"].label()
    c = res.clearance()
    row["margin_body_ft"] = c.body_ft if c else None
    row["margin_body_surface"] = (c.body_surface or "") if c else ""
    row["margin_body_ms"] = None if c is None or c.body_time_s is None else 1000 * c.body_time_s
    row["margin_body_where"] = (c.body_where or "") if c else ""
    row["margin_roof_ft"] = c.roof_ft if c else None
    row["margin_roof_ms"] = None if c is None or c.roof_time_s is None else 1000 * c.roof_time_s
    row["margin_roof_where"] = (c.roof_where or "") if c else ""
    row["line_meets_car_ms"] = (
        None if c is None or c.touch_time_s is None else 1000 * c.touch_time_s
    )
    row["line_meets_car_surface"] = (c.touch_surface or "") if c else ""
    row["run_s"] = res.run_s
    for key, _, _ in REPORT_ROWS:
        rep = None if report is None else report.get(key)
        ours = row.get(key)
        row[f"report_{key}"] = rep
        row[f"diff_{key}"] = (ours - rep) if (ours is not None and rep is not None) else None
    row["report_comment"] = "" if report is None else (report.get("comment") or "")
    return row


#: The CSV's columns, in order (the keys of :func:`result_row`).
COLUMNS: tuple[str, ...] = tuple(
    result_row(EngineResult("emulator", "", {"VVB": 0.0, "ALPHA": 0.0}), 0.0, 0.0)
)


def _scene_job(job: dict) -> dict:
    """Worker: one scene -> its row (plain data, picklable)."""
    base = read_deck(job["base"])
    deck = scene_deck(base, job["speed"], job["angle"], job["vvb_decimals"])
    name = scene_name(job["speed"], job["angle"], job["post"])
    try:
        res = run_engine(deck, job["engine"], preset=job["preset"], name=name)
    except Exception as exc:  # noqa: BLE001 - a scene that cannot run is a row, not a crash
        res = EngineResult(
            job["engine"], name, dict(deck.values), error=f"{type(exc).__name__}: {exc}"
        )
    report = _report_for(name, deck) if job["post"] == "steel" else None
    return result_row(res, job["speed"], job["angle"], report)


class _Progress:
    """A text progress bar on stderr, only when stderr is a terminal."""

    def __init__(self, total: int, stream=None, enabled: bool | None = None):
        self.total, self.done = total, 0
        self.stream = stream or sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.started = time.perf_counter()

    def step(self):
        self.done += 1
        if not self.enabled:
            return
        width = 30
        fill = int(width * self.done / self.total) if self.total else width
        el = time.perf_counter() - self.started
        eta = el / self.done * (self.total - self.done) if self.done else 0.0
        self.stream.write(
            f"\r[{'#' * fill}{'.' * (width - fill)}] {self.done}/{self.total} "
            f"scenes, {el:.0f} s, ~{eta:.0f} s left "
        )
        self.stream.flush()

    def close(self):
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()


def sweep(
    speeds: Sequence[float],
    angles: Sequence[float],
    *,
    engine: str = "emulator",
    post: str = "steel",
    base: str | os.PathLike | None = None,
    jobs: int | None = None,
    preset: str = "legacy",
    vvb_decimals: int = 2,
    progress: bool | None = None,
) -> list[dict]:
    """Run every (speed, angle); rows sorted by speed, then angle."""
    base = Path(base) if base is not None else POSTS[post]
    todo = [
        dict(
            base=str(base),
            speed=float(s),
            angle=float(a),
            engine=engine,
            preset=preset,
            post=post,
            vvb_decimals=vvb_decimals,
        )
        for s in speeds
        for a in angles
    ]
    jobs = max(1, int(jobs or os.cpu_count() or 1))
    bar = _Progress(len(todo), enabled=progress)
    rows = []
    try:
        if jobs == 1 or len(todo) == 1:
            for job in todo:
                rows.append(_scene_job(job))
                bar.step()
        else:
            with ProcessPoolExecutor(max_workers=min(jobs, len(todo))) as pool:
                futures = [pool.submit(_scene_job, job) for job in todo]
                for fut in as_completed(futures):
                    rows.append(fut.result())
                    bar.step()
    finally:
        bar.close()
    rows.sort(key=lambda r: (r["speed_mph"], r["angle_deg"]))
    return rows


# ============================================================================== writing


def _csv_value(v):
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "" if math.isnan(v) else repr(v)
    return v


def write_csv(rows: list[dict]) -> str:
    cols = list(rows[0].keys()) if rows else list(COLUMNS)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    for r in rows:
        w.writerow([_csv_value(r.get(c)) for c in cols])
    return buf.getvalue()


def _num(x, nd=2, signed=False):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    return f"{x:+.{nd}f}" if signed else f"{x:.{nd}f}"


def _cell(row, key, nd):
    ours = row.get(key)
    rep = row.get(f"report_{key}")
    if rep is None:
        return _num(ours, nd)
    if ours is None:
        return f"— ({_num(rep, nd)})"
    return f"{_num(ours, nd)} ({_num(rep, nd)}, {_num(ours - rep, nd, True)})"


def _deg(a):
    return f"{a:g}"


def render_markdown(rows: list[dict], *, command: str = "", engine: str = "emulator") -> str:
    """Tables laid out like the report's Tables 11 and 12: one table per speed."""
    oiv, ora = safety.CRITERIA["oiv"], safety.CRITERIA["ora"]
    lines = ["# Parameter study (the report's Chapter VI), regenerated", ""]
    if command:
        lines += [f"Command: `{command}`", ""]
    eng = rows[0]["errata_note"] if rows and engine == "core" else ""
    lines += [
        f"Engine: **{engine}**{' (' + eng + ')' if eng else ''}. Base deck: the report's steel post "
        "(`decks/steel40.dat`), VVB and ALPHA changed (rules in `deck_emulator.studies.sweep`).",
        "",
        "Each cell: **ours (report, ours − report)** where the report's Tables 11 (20 mph) and "
        "12 (40 mph), steel-post columns, have the case; otherwise ours alone. The report's "
        "numbers come from `deck_emulator.studies.report_tables`.",
        "",
        f"- ΔV (the report's row): {rows[0]['delta_v_definition'] if rows else ''}; the "
        "maximum deceleration is "
        + (
            "the largest *printed* FSA/(WV·G), as the report read it."
            if engine == "emulator"
            else "the core's continuous maximum."
        ),
        "- Terminal coordinates in the report's XL, YL, ZL axes (origin on the ground under the "
        "base of the support), at the hit.",
        f"- Occupant risk (flail-space model, `deck_emulator.studies.safety`, docs/safety.md): OIV "
        f"limit {oiv.label()}; ORA limit {ora.label()} (breakaway supports, NCHRP Report 350 "
        "/ MASH).",
        "- Margin: the least vertical clearance (ft) between the post (the line Q–P–R) and the "
        "car's outline while the post is over the car in free flight; over the roof = over the "
        "passenger compartment (windshield base to the end of the top). — : never over it.",
        "",
    ]
    speeds = sorted({r["speed_mph"] for r in rows})
    for s in speeds:
        rs = [r for r in rows if r["speed_mph"] == s]
        rs.sort(key=lambda r: r["angle_deg"])
        lines.append(f"## {_deg(s)} mph (VVB = {rs[0]['VVB_ft_s']:g} ft/s)")
        lines.append("")
        head = ["APPROACH ANGLE α (DEG)"] + [_deg(r["angle_deg"]) for r in rs]
        lines.append("| " + " | ".join(head) + " |")
        lines.append("|" + "---|" * len(head))

        def add(label, cells):
            lines.append("| " + " | ".join([label] + cells) + " |")

        for key, label, nd in REPORT_ROWS:
            add(label, [_cell(r, key, nd) for r in rs])
        add(
            "COMMENTS",
            [
                r["comment"] + (f" (report: {r['report_comment']})" if r["report_comment"] else "")
                for r in rs
            ],
        )
        add("lost contact with the car (ms)", [_num(r["vehicle_contact_lost_ms"], 1) for r in rs])
        add(
            "ΔV over the contact, ft/s (m/s)",
            [f"{_num(r['contact_delta_v_ft_s'])} ({_num(r['contact_delta_v_m_s'])})" for r in rs],
        )
        add(
            "max deceleration, any step (g); max 10 ms average (g)",
            [f"{_num(r['contact_max_decel_g'])}; {_num(r['max_decel_10ms_g'])}" for r in rs],
        )
        add(
            f"OIV m/s ({oiv.label()})",
            [f"{_num(r['oiv_m_s'])} {r['oiv_rating'] or ''}".strip() for r in rs],
        )
        add(
            "occupant strikes the interior (ms)",
            [
                _num(r["occupant_strike_ms"], 0)
                + (" (after contact)" if r["strike_after_contact"] else "")
                for r in rs
            ],
        )
        add(
            f"ORA g ({ora.label()})",
            [f"{_num(r['ora_g'])} {r['ora_rating'] or ''}".strip() for r in rs],
        )
        add(
            "least clearance over the car (ft)",
            [
                (
                    f"{_num(r['margin_body_ft'])} {r['margin_body_surface']} at "
                    f"{_num(r['margin_body_ms'], 0)} ms"
                )
                if r["margin_body_ft"] is not None
                else "—"
                for r in rs
            ],
        )
        add(
            "least clearance over roof/windshield (ft)",
            [
                (f"{_num(r['margin_roof_ft'])} at {_num(r['margin_roof_ms'], 0)} ms")
                if r["margin_roof_ft"] is not None
                else "—"
                for r in rs
            ],
        )
        add(
            "post's line first inside the car outline (ms)²",
            [
                (
                    f"{_num(r['line_meets_car_ms'], 1)} {r['line_meets_car_surface']}"
                    if r["line_meets_car_ms"] is not None
                    else "never"
                )
                for r in rs
            ],
        )
        if engine == "emulator":
            add("errata", [r["errata"] + ("" if r["errata"] == "none" else "¹") for r in rs])
        else:
            add("engine settings", [r["errata_note"] for r in rs])
        if any(r["error"] for r in rs):
            add("run stopped", [r["error"] or "" for r in rs])
        lines.append("")
    if engine == "emulator" and any(r["errata"] != "none" for r in rows):
        notes = sorted({r["errata_note"] for r in rows if r["errata"] != "none"})
        lines += ["¹ " + "; ".join(notes) + ".", ""]
    lines += [
        "² The listing tests only the points P, R and C against the car (labels 500-462); "
        "this is the first instant at which any place on the line Q–P–R is inside the "
        "car's outline (hood, roof, trunk), i.e. when the post would meet the car if the "
        "whole post were checked.",
        "",
    ]
    return "\n".join(lines).rstrip("\n") + "\n"


# ================================================================================== CLI


def _cmd_sweep(args: argparse.Namespace) -> int:
    from deck_emulator.cli import CLIError

    try:
        speeds = parse_grid(args.speeds)
        angles = parse_grid(args.angles)
    except ValueError as exc:
        raise CLIError(f"--speeds/--angles: {exc}") from None
    if any(s <= 0 for s in speeds):
        raise CLIError("--speeds must be positive (mph)")
    if any(not (0 <= a < 90) for a in angles):
        raise CLIError("--angles must be in [0, 90) degrees")
    if not 0 <= args.vvb_decimals <= 5:
        raise CLIError("--vvb-decimals must be 0 to 5")
    if args.jobs is not None and args.jobs < 1:
        raise CLIError("--jobs must be at least 1")
    base = Path(args.base_deck) if args.base_deck else POSTS[args.post]
    base_deck = read_deck(base)  # bad deck -> DeckError, before any work
    for s in speeds:  # every VVB/ALPHA must punch: fail before running anything
        for a in angles:
            scene_deck(base_deck, s, a, args.vvb_decimals)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    rows = sweep(
        speeds,
        angles,
        engine=args.engine,
        post=args.post,
        base=base,
        jobs=args.jobs,
        preset=args.preset,
        vvb_decimals=args.vvb_decimals,
    )
    wall = time.perf_counter() - started
    command = "deck-emulator sweep " + " ".join(sys.argv[2:]) if sys.argv[1:2] == ["sweep"] else ""
    write_atomic(out / "sweep.csv", write_csv(rows))
    write_atomic(out / "sweep.md", render_markdown(rows, command=command, engine=args.engine))
    patched = sum(r["errata"] != "none" for r in rows)
    failed = sum(bool(r["error"]) for r in rows)
    print(
        f"deck-emulator: {len(rows)} scenes ({args.engine}) in {wall:.1f} s on "
        f"{args.jobs or os.cpu_count()} job(s); {patched} with the {ERRATUM} erratum; "
        f"{failed} stopped early; wrote {out / 'sweep.csv'} and {out / 'sweep.md'}",
        file=sys.stderr,
    )
    return 0


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``deck-emulator sweep``."""
    p = sub.add_parser(
        "sweep",
        help="run a grid of speeds and approach angles and tabulate it like Tables 11 and 12",
        description="Regenerate the report's parameter study: every speed x angle of the grid "
        "is the base deck with VVB and ALPHA changed, run in parallel. Writes DIR/sweep.csv (one "
        "row per scene, every output, the report's value and the difference) and DIR/sweep.md "
        "(one table per speed, laid out like Tables 11 and 12). For the emulator the "
        "ed-direction erratum is applied where ALPHA != 0 (and said so in the table).",
    )
    p.add_argument(
        "--post",
        choices=sorted(POSTS),
        default="steel",
        help="the post (base deck decks/steel40.dat)",
    )
    p.add_argument("--base-deck", metavar="DECK", help="another base deck instead of --post's")
    p.add_argument(
        "--speeds",
        required=True,
        metavar="MPH,...",
        help="vehicle speeds in mph: 20,40 or 10:60:10 (stop included)",
    )
    p.add_argument(
        "--angles",
        required=True,
        metavar="DEG,...",
        help="approach angles in degrees: 0,15,30 or 0:45:5",
    )
    p.add_argument("--engine", choices=ENGINES, default="emulator")
    p.add_argument(
        "--preset",
        choices=("legacy", "physical"),
        default="legacy",
        help="core model options (default legacy: the listing's quirks)",
    )
    p.add_argument(
        "--jobs",
        type=int,
        metavar="N",
        help="worker processes (default: all cores, %d here)" % (os.cpu_count() or 1),
    )
    p.add_argument(
        "--vvb-decimals",
        type=int,
        default=2,
        metavar="N",
        help="decimals VVB is cut to (default 2, as the report's deck: -58.66)",
    )
    p.add_argument(
        "--out", required=True, metavar="DIR", help="directory for sweep.csv and sweep.md"
    )
    p.set_defaults(func=_cmd_sweep)
