"""Work-precision study: error against run time and against work, for the 1967 scheme and the
modern core.

Every run is measured against the core's reference (``legacy`` preset, DOP853 at the defaults'
``REFERENCE_RTOL``, itself checked by a second method at a tenth of it); an emulator run at
``H0/2**k`` against a reference with the matching start-up kick (:func:`~.diff.legacy_options`)
and against the k = 0 one. What the columns, the orders and the timings mean is said on the page
the study writes (``templates/error_study.md``).
"""

from __future__ import annotations

import contextlib
import functools
import math
import time
from pathlib import Path

import numpy as np

from deck_emulator.vocabulary import defaults
from deck_emulator.engine import Limits
from deck_emulator.studies.diff import ed_tolerance as tight_ed_tolerance
from deck_emulator.studies.diff import max_trajectory_distance
from deck_emulator.studies.orders import QUANTISED, order_fit
from deck_emulator.vocabulary.scene import LEGACY, Scene

from deck_emulator.files import OutputSet, check_output_dir
from deck_emulator.studies.store import output_store
from deck_emulator.studies.sweep import read_base
from .pages import page, snippet
from .common import (
    H0,
    agg_backend,
    cpu_count,
    emulator_hit,
    fmt,
    machine,
    machine_line,
    legacy_options,
    md_table,
    run_emulator,
    run_longest_first,
    csv_text,
    stopped_at_wall,
)

REF_RTOL = defaults.REFERENCE_RTOL
CHECK_RTOL = defaults.REFERENCE_CHECK_RTOL
GRID_POINTS = defaults.ERROR_GRID_POINTS
BLAS_THREADS = defaults.STUDY_BLAS_THREADS
CORE_METHODS = ("DOP853", "RK45", "Radau")

SERIES_LISTING = "legacy, ED as printed (double)"
SERIES_TIGHT = "legacy, ED tightened (double)"
SERIES_IBM = "legacy, ED as printed (IBM 7094)"
#: the prefix of a series run without the largest-step bound
UNBOUNDED = "no step bound: "
COMPILED = "compiled DOP853"

COLUMNS = [
    "series", "engine", "method", "precision", "k", "h_s", "rtol", "atol", "max_step_s",
    "ed_tolerance", "status", "guard", "error", "hit", "hit_time_s", "reference",
    "err_traj_ft", "err_hit_time_s", "err_R_ft", "err_traj_ref0_ft", "err_hit_time_ref0_s",
    "err_R_ref0_ft", "wall_s", "wall_min_s", "wall_max_s", "wall_reps_s", "reps", "steps", "nfev",
    "statements", "dt_first_spring_lost_s", "dt_release_s", "err_release_ft",
    "err_release_vel_ft_s", "err_flight_propagated_ft", "err_flight_own_ft",
]


def plan(quick: bool) -> dict:
    if quick:
        return {"ks": range(3), "rtols": (1e-4, 1e-7, 1e-10), "reps": 1, "ibm": False,
                "checks": ("LSODA",)}
    return {"ks": range(7), "rtols": tuple(10.0 ** -e for e in range(3, 12)),
            "reps": defaults.ERROR_TIMED_REPS, "ibm": True, "checks": ("Radau", "LSODA")}


def core_series(method: str, bounded: bool, compiled: bool) -> str:
    name = COMPILED if compiled else f"core {method}"
    return name if bounded else UNBOUNDED + name


def emulator_limits(k: int) -> Limits:
    """The emulator's bounds for a run at H0/2**k: the defaults' (the front end scales the
    whole-run statement budget with the run's step itself: ``Limits.budget``)."""
    return Limits()


@contextlib.contextmanager
def blas_threads(n: int = BLAS_THREADS):
    """Every BLAS the process has loaded (numpy's and scipy's OpenBLAS) limited to ``n``
    threads for the block (threadpoolctl; scipy.linalg imported first so that its own is)."""
    import scipy.linalg  # noqa: F401 - scipy's BLAS loaded before the limit is set
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=n, user_api="blas"):
        yield


def _timed(fn, reps: int) -> tuple[object, list[float]]:
    """``fn()`` once (its value), then ``reps`` times timed (the page says how)."""
    value = fn()
    walls = []
    for _ in range(reps):
        started = time.perf_counter()
        fn()
        walls.append(time.perf_counter() - started)
    return value, walls


def _times(walls: list[float]) -> dict:
    if not walls:
        return {"wall_s": math.nan, "wall_min_s": math.nan, "wall_max_s": math.nan,
                "wall_reps_s": "", "reps": 0}
    return {"wall_s": float(np.median(walls)), "wall_min_s": min(walls),
            "wall_max_s": max(walls), "wall_reps_s": " ".join(f"{w:.4f}" for w in walls),
            "reps": len(walls)}


# --------------------------------------------------------------------------- references

_REFS: dict = {}


def _scene(deck_path):
    """The deck named ``deck_path`` and its scene, as :func:`_task` keeps them."""
    return _REFS[("scene", str(deck_path))]


class RunError(Exception):
    """A core run of the study ended with an error (its outcome's ``error``)."""


def _engine(options, method, rtol, *, bounded=True, compiled=False):
    from deck_emulator.engine import CoreEngine

    return CoreEngine(options=options, method=method, rtol=rtol, atol=rtol, trace=False,
                      max_step_s=defaults.MAX_STEP_S if bounded else math.inf,
                      batched=compiled)


def _simulate(scene, options, method, rtol, *, bounded=True, compiled=False):
    """One core run through the engine layer: its outcome (a run that ended with an error
    raises :class:`RunError`; one stopped by the wall bound, ``Stopped``).  ``compiled``: the
    compiled DOP853, a batch of one scene; else solve_ivp."""
    engine = _engine(options, method, rtol, bounded=bounded, compiled=compiled)
    out = engine.run_batch([scene])[0] if compiled else engine.run(scene)
    stopped_at_wall(out, engine.wall_bound_s)
    if out.error is not None:
        raise RunError(out.error)
    return out


def reference(deck_path, k: int):
    """The core at REF_RTOL with the start-up kick of step H0/2**k (cached per process)."""
    key = ("ref", str(deck_path), k)
    if key not in _REFS:
        _, scene = _scene(deck_path)
        res = _simulate(scene, legacy_options(H0 / 2**k), "DOP853", REF_RTOL)
        if res.hit_time_s is None:
            raise RuntimeError(f"the reference (k = {k}) did not end with a hit")
        _REFS[key] = res
    return _REFS[key]


def _core_errors(res, ref) -> dict:
    t_end = min(res.span[1], ref.span[1])
    grid = np.linspace(0.0, t_end, GRID_POINTS)
    d = np.linalg.norm(res.position("CM", grid) - ref.position("CM", grid), axis=0)
    out = {"err_traj_ft": float(d.max()), "err_hit_time_s": math.nan, "err_R_ft": math.nan}
    if res.hit_time_s is not None and ref.hit_time_s is not None:
        out["err_hit_time_s"] = abs(res.hit_time_s - ref.hit_time_s)
        out["err_R_ft"] = float(np.linalg.norm(
            res.position("R", res.hit_time_s) - ref.position("R", ref.hit_time_s)))
    return out


def _release_errors(res, ref, scene) -> dict:
    """Where a core run's error at the hit comes from: the instants of the first spring's loss
    and of the car's release against the reference's (``dt_*``), the mass centre's and the body
    velocity's errors at the release (``err_release_*``), and the error at the hit split in two
    (``err_flight_*``): the run's own release state carried through the free flight at the
    reference's tolerance (what the contact phase left, propagated) against the reference, and
    the run's own free flight against that (what the free flight added)."""
    from deck_emulator.vocabulary.scene import PostInitialState

    out = {}
    if res.first_spring_lost_s is not None and ref.first_spring_lost_s is not None:
        out["dt_first_spring_lost_s"] = res.first_spring_lost_s - ref.first_spring_lost_s
    tc, tc_ref = res.contact_end_s, ref.contact_end_s
    if tc is None or tc_ref is None or res.hit_time_s is None or ref.hit_time_s is None:
        return out
    out["dt_release_s"] = tc - tc_ref
    mine, theirs = res.motion(tc), ref.motion(tc)
    out["err_release_ft"] = float(np.linalg.norm(mine["mass_centre_ft"]
                                                 - theirs["mass_centre_ft"]))
    out["err_release_vel_ft_s"] = float(np.linalg.norm(
        np.asarray(mine["velocity_body_ft_s"]) - theirs["velocity_body_ft_s"]))
    post = PostInitialState(
        mass_centre_ft=tuple(map(float, mine["mass_centre_ft"])),
        velocity_body_ft_s=tuple(map(float, mine["velocity_body_ft_s"])),
        angular_velocity_body_rad_s=tuple(map(float, mine["angular_velocity_body_rad_s"])),
        attitude_wxyz=tuple(map(float, mine["attitude_wxyz"])))
    carried = _engine(LEGACY, "DOP853", REF_RTOL).run_free_flight(
        scene, post, tc, car_position_ft=float(mine["car_position_ft"]),
        car_velocity_ft_s=float(mine["car_velocity_ft_s"]))
    if carried.error is not None or carried.hit_time_s is None:
        return out
    t = min(res.hit_time_s, ref.hit_time_s, carried.hit_time_s)
    out["err_flight_propagated_ft"] = float(np.linalg.norm(
        carried.position("CM", t) - ref.position("CM", t)))
    out["err_flight_own_ft"] = float(np.linalg.norm(
        res.position("CM", t) - carried.position("CM", t)))
    return out


def _emulator_errors(run, hit_time, ref) -> dict:
    out = {"err_traj_ft": max_trajectory_distance(run, ref), "err_hit_time_s": math.nan,
           "err_R_ft": math.nan}
    if hit_time is not None and ref.hit_time_s is not None:
        r_emu = np.asarray(run.points["R"][-1], dtype=float)  # R at the last accepted step
        out["err_hit_time_s"] = abs(hit_time - ref.hit_time_s)
        out["err_R_ft"] = float(np.linalg.norm(r_emu - ref.position("R", ref.hit_time_s)))
    return out


# --------------------------------------------------------------------------- tasks


def _task(spec: dict, decks: dict) -> dict:
    """A worker's run of one task; ``decks``: path -> the deck read by the command, handed
    on with the function (no worker reads the file), kept with its scene for the process's
    next tasks."""
    key, deck = ("scene", spec["deck"]), decks[spec["deck"]]
    if key not in _REFS:
        _REFS[key] = (deck, Scene.from_deck(deck))
    with blas_threads():
        kind = spec["kind"]
        if kind == "check":
            return _task_check(spec)
        if kind == "emulator":
            return _task_emulator(spec)
        return _task_core(spec)


def _core_error_row(exc) -> dict:
    return {"status": "error", "error": f"{type(exc).__name__}: {exc}"}


def _task_check(spec):
    """A reference against the same model by a second method at a tenth of the tolerance."""
    deck_path, k, method = spec["deck"], spec["k"], spec["method"]
    _, scene = _scene(deck_path)
    ref = reference(deck_path, k)
    row = {"series": "reference check", "engine": "core", "method": method, "k": k,
           "h_s": H0 / 2**k, "rtol": CHECK_RTOL, "atol": CHECK_RTOL,
           "max_step_s": defaults.MAX_STEP_S, "reference": f"DOP853 rtol {REF_RTOL:g}, k = {k}"}
    started = time.perf_counter()
    try:
        res = _simulate(scene, legacy_options(H0 / 2**k), method, CHECK_RTOL)
    except RunError as exc:
        return {**row, **_core_error_row(exc)}
    row.update(_core_errors(res, ref), status="hit" if res.hit_time_s is not None else "no hit",
               error="", hit=res.hit_message or "", hit_time_s=res.hit_time_s,
               nfev=res.evaluations, steps=res.solver_steps(), wall_s=time.perf_counter() - started,
               reps=1)
    return row


def _task_emulator(spec):
    deck_path, k, precision, tol = spec["deck"], spec["k"], spec["precision"], spec["ed_tolerance"]
    deck, _ = _scene(deck_path)
    limits = emulator_limits(k)

    def once():
        return run_emulator(deck, precision=precision, k=k, ed_tolerance=tol, limits=limits)

    first = once()
    # a run that did not end with a hit is not timed (its time is not comparable)
    _, walls = _timed(once, spec["reps"]) if first["status"] == "hit" else (None, [])
    run = first["outcome"]
    message, hit_time = emulator_hit(first)
    row = {"series": spec["series"], "engine": "emulator", "method": "listing scheme",
           "precision": precision, "k": k, "h_s": H0 / 2**k, "ed_tolerance": tol,
           "status": first["status"], "guard": first["guard"], "error": first["error"],
           "hit": message, "hit_time_s": hit_time, "reference": f"k = {k}",
           "steps": run.accepted_steps()[0].size, "statements": limits.budget(k),
           **_times(walls)}
    if first["status"] == "hit":
        row.update(_emulator_errors(run, hit_time, reference(deck_path, k)))
        ref0 = _emulator_errors(run, hit_time, reference(deck_path, 0))
        row.update(err_traj_ref0_ft=ref0["err_traj_ft"], err_hit_time_ref0_s=ref0["err_hit_time_s"],
                   err_R_ref0_ft=ref0["err_R_ft"])
    return row


def _task_core(spec):
    deck_path, method, rtol = spec["deck"], spec["method"], spec["rtol"]
    bounded, compiled = spec["bounded"], spec["compiled"]
    _, scene = _scene(deck_path)
    ref = reference(deck_path, 0)
    row = {"series": core_series(method, bounded, compiled), "engine": "core",
           "method": method, "rtol": rtol, "atol": rtol,
           "max_step_s": defaults.MAX_STEP_S if bounded else math.inf, "reference": "k = 0"}

    def once():
        return _simulate(scene, LEGACY, method, rtol, bounded=bounded, compiled=compiled)

    try:
        res, walls = _timed(once, spec["reps"])
    except RunError as exc:
        return {**row, **_core_error_row(exc)}
    errs = _core_errors(res, ref)
    row.update(errs, status="hit" if res.hit_time_s is not None else "no hit", error="",
               hit=res.hit_message or "", hit_time_s=res.hit_time_s, nfev=res.evaluations,
               steps=res.solver_steps(), **_times(walls))
    row.update(err_traj_ref0_ft=errs["err_traj_ft"], err_hit_time_ref0_s=errs["err_hit_time_s"],
               err_R_ref0_ft=errs["err_R_ft"])
    row.update(_release_errors(res, ref, scene))
    return row


def _tasks(deck_path: str, p: dict) -> list[dict]:
    tasks = []
    reps = p["reps"]
    for k in p["ks"]:
        for series, tol in ((SERIES_LISTING, defaults.LISTING_ED_TOLERANCE),
                            (SERIES_TIGHT, tight_ed_tolerance(k))):
            tasks.append({"kind": "emulator", "deck": deck_path, "series": series, "k": k,
                          "precision": "double", "ed_tolerance": tol, "reps": reps,
                          "cost": 0.06 * 2**k * (reps + 1)})
    if p["ibm"]:
        tasks.append({"kind": "emulator", "deck": deck_path, "series": SERIES_IBM, "k": 0,
                      "precision": "ibm7094", "ed_tolerance": defaults.LISTING_ED_TOLERANCE,
                      "reps": reps,
                      "cost": 0.6 * (reps + 1)})
    for bounded in (True, False):
        for method in CORE_METHODS:
            for rtol in p["rtols"]:
                cost = (0.3 if method == "Radau" else 0.08) * (1 - math.log10(rtol) / 6)
                tasks.append({"kind": "core", "deck": deck_path, "method": method, "rtol": rtol,
                              "bounded": bounded, "compiled": False, "reps": reps,
                              "cost": cost * (reps + 1)})
        for rtol in p["rtols"]:
            tasks.append({"kind": "core", "deck": deck_path, "method": "DOP853", "rtol": rtol,
                          "bounded": bounded, "compiled": True, "reps": reps,
                          "cost": 0.01 * (reps + 1)})
    for method in p["checks"]:
        tasks.append({"kind": "check", "deck": deck_path, "k": 0, "method": method,
                      "cost": 4.0 if method == "Radau" else 0.5})
    for k in p["ks"]:
        if k:
            tasks.append({"kind": "check", "deck": deck_path, "k": k, "method": "LSODA",
                          "cost": 0.5})
    return tasks


# --------------------------------------------------------------------------- the study


def error_study(deck_path, out_dir, quick: bool = False, jobs: int | None = None,
                command: str | None = None, quiet: bool = False, scheduler: str | None = None,
                resume: bool = False, deck=None, deck_sha256: str | None = None) -> dict:
    """Run the work-precision study on ``deck_path``; write ``error_study.csv``,
    ``work_precision.png`` and ``README.md`` into ``out_dir`` (the runs are stored in its
    ``.scenes`` as they finish: ``resume`` runs only the missing ones).  ``deck``,
    ``deck_sha256``: that file as the caller read it (else it is read here, once).  Returns
    the summary."""
    started = time.perf_counter()
    out = Path(out_dir)
    check_output_dir(out)  # a missing or read-only folder fails before any run
    deck_path = str(deck_path)
    if deck is None:  # a bad deck fails here, before any process starts
        deck, deck_sha256 = read_base(deck_path)
    p = plan(quick)
    jobs = jobs or cpu_count()
    # the deck handed to the workers with the function; the tasks name its file (their ids)
    rows = run_longest_first(functools.partial(_task, decks={deck_path: deck}),
                             _tasks(deck_path, p), jobs=jobs, desc="study error",
                             quiet=quiet, store_dir=output_store(out, resume),
                             scheduler=scheduler, resume=resume, core=True,
                             files=None if deck_sha256 is None else {deck_path: deck_sha256})
    summary = _summarise(rows, p)
    with OutputSet(directory=out) as files:  # the three files appear together or not at all
        files.write("error_study.csv", csv_text(rows, COLUMNS))
        _plot(rows, summary, files.path("work_precision.png"), Path(deck_path).stem)
        wall = time.perf_counter() - started
        cmd = command or (f"deck-emulator study error {deck_path} --out {out_dir}"
                          + (" --quick" if quick else "") + f" --jobs {jobs}")
        files.write("README.md", _report(rows, summary, p, deck_path, cmd, jobs, wall))
    summary["wall_s"] = wall
    return summary


def _ok(rows, series):
    return [r for r in rows if r["series"] == series and r["status"] == "hit"
            and np.isfinite(r.get("err_traj_ft", math.nan))]


def _all_core_series() -> list[str]:
    return [core_series(m, b, c) for b in (True, False)
            for m, c in [(m, False) for m in CORE_METHODS] + [("DOP853", True)]]


def _summarise(rows, p) -> dict:
    checks = [r for r in rows if r["series"] == "reference check"]
    ref_err = max((r.get("err_traj_ft", math.nan) for r in checks if r["k"] == 0),
                  default=math.nan)
    ref_err_all = max((r.get("err_traj_ft", math.nan) for r in checks), default=math.nan)
    floor = max(ref_err_all, 1e-15) * 10
    orders = {}
    for series in (SERIES_LISTING, SERIES_TIGHT):
        ok = _ok(rows, series)
        h = [r["h_s"] for r in ok]
        orders[series] = {
            "vs_h": order_fit(h, [r["err_traj_ft"] for r in ok]),
            "vs_h_ref0": order_fit(h, [r.get("err_traj_ref0_ft", math.nan) for r in ok]),
            "vs_h_R": order_fit(h, [r.get("err_R_ft", math.nan) for r in ok]),
            "hit_in_steps": [r.get("err_hit_time_s", math.nan) / r["h_s"] for r in ok],
        }
    for series in _all_core_series():
        ok = [r for r in _ok(rows, series) if r["err_traj_ft"] > floor]
        orders[series] = {
            "vs_rtol": order_fit([r["rtol"] for r in ok], [r["err_traj_ft"] for r in ok]),
            "vs_nfev": order_fit([r["nfev"] for r in ok], [r["err_traj_ft"] for r in ok]),
            "points": len(ok),
            "n_min": min((r["nfev"] for r in ok), default=0),
            "n_max": max((r["nfev"] for r in ok), default=0),
        }
    core_ok = [r for s in _all_core_series() for r in _ok(rows, s)]
    ratios = []
    for series in (SERIES_LISTING, SERIES_TIGHT, SERIES_IBM):
        for r in _ok(rows, series):
            better = [c for c in core_ok if c["err_traj_ft"] <= r["err_traj_ft"]]
            if not better or not np.isfinite(r["wall_s"]):
                continue
            best = min(better, key=lambda c: c["wall_s"])
            ratios.append({"series": series, "k": r["k"], "err_ft": r["err_traj_ft"],
                           "wall_s": r["wall_s"],
                           "core": f"{best['series']} rtol {best['rtol']:g}",
                           "core_err_ft": best["err_traj_ft"], "core_wall_s": best["wall_s"],
                           "ratio": r["wall_s"] / best["wall_s"]})
    return {"reference_error_ft": ref_err, "reference_error_all_ft": ref_err_all,
            "orders": orders, "speed": ratios, "floor_ft": floor}


# --------------------------------------------------------------------------- outputs

_STYLE = {
    SERIES_LISTING: dict(color="#c0392b", marker="o"),
    SERIES_TIGHT: dict(color="#e67e22", marker="s"),
    SERIES_IBM: dict(color="#7f3c8d", marker="D", markersize=9),
    "core DOP853": dict(color="#1f77b4", marker="^"),
    "core RK45": dict(color="#2ca02c", marker="v"),
    "core Radau": dict(color="#17becf", marker="P"),
    COMPILED: dict(color="#000000", marker="X", markersize=8),
}


def _style(series: str) -> tuple[dict, str]:
    """A series' colour and marker, and its line style: dashed without the step bound."""
    if series.startswith(UNBOUNDED):
        st = dict(_STYLE[series[len(UNBOUNDED):]])
        st["mfc"] = "none"
        return st, "--"
    return _STYLE[series], "-"


#: where a label may go, in points from its point: the nearest first, then further out
_PLACES = [(dx * r, dy * r) for r in (1, 2, 3.2) for dx, dy in
           ((5, 3), (5, -9), (-5, 3), (-5, -9), (0, 7), (0, -13), (8, -3), (-8, -3))]


def _labels_apart(ax, labelled) -> None:
    """Write each ``(x, y, text, colour)`` beside its point where it covers no label already
    written and no point: the first free place of :data:`_PLACES` (beyond the nearest ring
    with a leader line), on white where a line passes under it.  The core's points lie close together (a method's tolerances take
    about the same time), and labels written at one fixed offset read as one ('1e43')."""
    renderer = ax.figure.canvas.get_renderer()
    dots = ax.transData.transform([(x, y) for x, y, *_ in labelled])
    taken = []
    for (x, y, text, colour), dot in zip(labelled, dots):
        for k, (dx, dy) in enumerate(_PLACES):
            note = ax.annotate(text, (x, y), textcoords="offset points", xytext=(dx, dy),
                               ha="left" if dx >= 0 else "right", fontsize=7, color=colour,
                               bbox=dict(fc="white", ec="none", alpha=0.75, pad=0.3),
                               arrowprops=dict(arrowstyle="-", color=colour, lw=0.5)
                               if k >= 8 else None)
            box = note.get_window_extent(renderer).expanded(1.1, 1.2)
            if not any(box.overlaps(t) for t in taken) and not any(
                    box.contains(*d) for d in dots):
                break
            if k < len(_PLACES) - 1:
                note.remove()
        taken.append(box)


def _tolerance_label(rtol: float) -> str:
    """1e-07 -> '1e-7'."""
    mantissa, exponent = f"{rtol:.0e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def _plot(rows, summary, path: Path, title: str = "") -> None:
    plt = agg_backend()
    from matplotlib.ticker import NullFormatter

    fig, axes = plt.subplots(2, 2, figsize=(16, 15.5))
    (ax, bx), (wx, tx) = axes
    # fig.axes in this order: time, the 1967 scheme against H, work, tolerance
    labelled = []
    every = [SERIES_LISTING, SERIES_TIGHT, SERIES_IBM, *_all_core_series()]
    for series in every:
        ok = [r for r in _ok(rows, series) if np.isfinite(r["wall_s"])]
        if not ok:
            continue
        style, ls = _style(series)
        wall = np.array([r["wall_s"] for r in ok])
        err = [r["err_traj_ft"] for r in ok]
        spread = np.array([wall - [r["wall_min_s"] for r in ok],
                           [r["wall_max_s"] for r in ok] - wall])
        ax.errorbar(wall, err, xerr=spread, fmt="none", ecolor=style["color"], elinewidth=0.8,
                    capsize=2)
        ax.plot(wall, err, ls=ls, lw=1.4, label=series + (" (points labelled by rtol = atol)"
                                                          if series == "core DOP853" else ""),
                **style)
        work = [r["steps"] if r["engine"] == "emulator" else r["nfev"] for r in ok]
        wx.loglog(work, err, ls=ls, lw=1.4, label=series, **style)
        for r, w in zip(ok, work):
            if r["engine"] == "emulator":
                for axis, x in ((ax, r["wall_s"]), (wx, w)):
                    axis.annotate(f"k={r['k']}", (x, r["err_traj_ft"]),
                                  textcoords="offset points", xytext=(5, 4), fontsize=8,
                                  color=style["color"])
            elif series == "core DOP853":
                labelled.append((r["wall_s"], r["err_traj_ft"], _tolerance_label(r["rtol"]),
                                 style["color"]))
        if ok[0]["engine"] == "core":
            tx.loglog([r["rtol"] for r in ok], err, ls=ls, lw=1.4, label=series, **style)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ref_err = summary["reference_error_all_ft"]
    for axis in (ax, wx, tx):
        if np.isfinite(ref_err) and ref_err > 0:
            axis.axhline(ref_err, color="grey", ls=":", lw=1)
            axis.annotate("the references' own error", (1.0, ref_err),
                          xycoords=("axes fraction", "data"), textcoords="offset points",
                          xytext=(-4, 4), ha="right", fontsize=8, color="dimgrey")
        axis.set_ylabel("largest mass-centre distance to the reference, ft")
        axis.grid(True, which="major", alpha=0.4)
        axis.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("wall time per run, s: median of the repetitions, bar from least to largest")
    ax.set_title(f"Work-precision{' (' + title + ')' if title else ''}: error against run time")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.09), ncol=3,
              frameon=False)
    wx.set_xlabel("work per run: right-hand-side evaluations (core, nfev); accepted steps "
                  "(emulator: one force evaluation each)")
    wx.set_title("Error against work (dashed: no largest-step bound)")
    tx.set_xlabel("rtol = atol")
    tx.set_title("The core's error against its tolerance (dashed: no largest-step bound)")
    tx.axvline(defaults.CORE_RTOL, color="grey", lw=1)
    tx.annotate(f"the core's default rtol {defaults.CORE_RTOL:g}", (defaults.CORE_RTOL, 0.35),
                xycoords=("data", "axes fraction"), rotation=90, fontsize=8, xytext=(3, 0),
                textcoords="offset points", color="dimgrey")
    tx.invert_xaxis()
    tx.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.09), ncol=3,
              frameon=False)

    for series in (SERIES_LISTING, SERIES_TIGHT):
        ok = _ok(rows, series)
        if not ok:
            continue
        style = _STYLE[series]
        h = np.array([r["h_s"] for r in ok])
        o = summary["orders"][series]
        bx.loglog(h, [r["err_traj_ft"] for r in ok], "-", lw=1.6, color=style["color"],
                  marker=style["marker"], label=f"{series}: order {_short(o['vs_h'])}")
        bx.loglog(h, [r["err_traj_ref0_ft"] for r in ok], "--", lw=1, color=style["color"],
                  marker=style["marker"], mfc="none",
                  label=f"the same against the k = 0 reference: order {_short(o['vs_h_ref0'])}")
    for r in _ok(rows, SERIES_IBM):
        bx.loglog([r["h_s"]], [r["err_traj_ft"]], ls="", label=SERIES_IBM, **_STYLE[SERIES_IBM])
    ok = _ok(rows, SERIES_TIGHT)
    if ok:
        h = np.array([r["h_s"] for r in ok])
        bx.loglog(h, ok[0]["err_traj_ft"] * (h / h[0]), ":", color="black", lw=1, label="slope 1")
    for r in [r for r in rows if r["engine"] == "emulator" and r["status"] != "hit"]:
        bx.axvline(r["h_s"], color="black", lw=0.8, ls="-.")
        bx.annotate(f"k={r['k']}: {r['status']}", (r["h_s"], 0.5),
                    xycoords=("data", "axes fraction"), rotation=90, fontsize=8.5,
                    xytext=(3, 0), textcoords="offset points")
    hs = sorted({r["h_s"] for r in rows if r["engine"] == "emulator"})
    bx.set_xticks(hs)
    bx.set_xticklabels([f"{h * 1e6:.3g}" for h in hs])
    bx.xaxis.set_minor_formatter(NullFormatter())
    bx.set_xlabel("emulator step H, \u00b5s")
    bx.set_ylabel("largest mass-centre distance to the reference, ft")
    bx.set_title("The 1967 scheme as H = 0.0004/2**k shrinks")
    bx.grid(True, which="major", alpha=0.4)
    bx.legend(fontsize=8.5, loc="lower right", ncol=1)
    fig.tight_layout()
    _labels_apart(ax, labelled)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _short(fit) -> str:
    return "n/a" if not np.isfinite(fit.p) else f"{fit.p:.2f} ± {fit.half:.2f}"


def _time_cell(r) -> str:
    if not np.isfinite(r.get("wall_s", math.nan)):
        return "–"
    return f"{r['wall_s']:.3g} [{r['wall_min_s']:.3g}–{r['wall_max_s']:.3g}]"


def _unbounded_note(rows) -> str:
    """What the DOP853 runs without the step bound show, from their rows."""
    ok = sorted(_ok(rows, UNBOUNDED + "core DOP853"), key=lambda r: -r["rtol"])
    flat = [r for r in ok if r["err_traj_ft"] > 0.01]
    if not flat:
        return "each method's error follows its tolerance."
    dts = [abs(r.get("dt_first_spring_lost_s", math.nan)) for r in flat]
    tols = {r["rtol"] for r in flat}
    bounded = [abs(r.get("dt_first_spring_lost_s", math.nan)) for r in _ok(rows, "core DOP853")
               if r["rtol"] in tols]
    against = (f", against {min(bounded):.2g} to {max(bounded):.2g} s with the bound at the "
               "same tolerances." if bounded else ".")
    errs = [r["err_traj_ft"] for r in flat]
    return snippet("error_tolerance.md", "unbounded", lo=f"{min(errs):.2g}",
                   hi=f"{max(errs):.2g}", tolerances=_tolerances(flat),
                   dt_lo=f"{min(dts):.2g}", dt_hi=f"{max(dts):.2g}", against=against)


def _tolerances(rows) -> str:
    return ", ".join(format(r["rtol"], "g") for r in rows)


def _tolerance_rows(rows) -> list[dict]:
    return sorted(_ok(rows, "core DOP853"), key=lambda r: -r["rtol"])


def _report(rows, summary, p, deck_path, cmd, jobs, wall) -> str:
    """The page (``templates/error_study.md``) of the study's rows and summary."""
    o = summary["orders"]
    lst, tight = o[SERIES_LISTING], o[SERIES_TIGHT]
    checks = [r for r in rows if r["series"] == "reference check"]
    core_orders = "".join(
        f"\n* **{series}**: slope of error against rtol {_short(c['vs_rtol'])} "
        f"(tolerance proportionality, {c['points']} runs above ten times the references' "
        f"error); work {c['n_min']} ... {c['n_max']} evaluations, slope of error against "
        f"work {_short(c['vs_nfev'])}." for series in _all_core_series()
        if (c := o[series])["points"])
    sp = summary["speed"]
    head = next((s for s in sp if s["series"] == SERIES_LISTING and s["k"] == 0), None)
    speed_head = "" if head is None else snippet(
        "error_tolerance.md", "speed_head", err=f"{head['err_ft']:.3g}",
        wall=f"{head['wall_s']:.3g}", core=head["core"], core_err=f"{head['core_err_ft']:.2g}",
        core_wall=f"{head['core_wall_s']:.3g}", ratio=f"{head['ratio']:.1f}") + "\n"
    failed = [r for r in rows if r["engine"] == "emulator" and r["status"] != "hit"]
    failed_section = "".join(line + "\n" for line in [
        "## Runs that failed", "",
        *(f"* {r['series']}, k = {r['k']} (H = {r['h_s']:.3g} s): {r['status']}"
          + (f" ({r['guard']})" if r["guard"] != r["status"] else "") + f": {r['error']}"
          for r in failed), ""]) if failed else ""
    return page(
        "error_study.md", command=cmd, machine_line=machine_line(machine(), jobs, wall),
        blas_threads=BLAS_THREADS, listing_order=lst["vs_h"].text(),
        listing_diverges="" if lst["vs_h"].p > 0.5 else (
            " It does not converge: ED's error in psi per step does not shrink with H, so "
            "halving the step adds error."),
        tight_order=tight["vs_h"].text(), tight_order_R=tight["vs_h_R"].text(),
        quantised=QUANTISED, hit_in_steps=", ".join(f"{x:.2f}" for x in tight["hit_in_steps"]),
        core_orders=core_orders, max_step=defaults.MAX_STEP_S,
        max_step_g=f"{defaults.MAX_STEP_S:g}", unbounded_note=_unbounded_note(rows),
        tolerance="".join(line + "\n" for line in _tolerance_section(rows)),
        speed_head=speed_head, speed_table=_speed_table(sp), ref_rtol=f"{REF_RTOL:g}",
        checks=" and ".join(p["checks"]), check_rtol=f"{CHECK_RTOL:g}",
        reference_error=f"{summary['reference_error_ft']:.2g}",
        reference_error_all=f"{summary['reference_error_all_ft']:.2g}",
        checks_table=md_table(
            ["reference", "checked with", "trajectory (ft)", "hit time (s)", "R at the hit (ft)",
             "check's time (s)"],
            [[r["reference"], f"{r['method']} rtol {r['rtol']:g}", fmt(r.get("err_traj_ft")),
              fmt(r.get("err_hit_time_s")), fmt(r.get("err_R_ft")), fmt(r.get("wall_s"))]
             for r in checks]),
        grid_points=GRID_POINTS, reps=p["reps"], jobs=jobs, runs_table=_runs_table(rows),
        failed=failed_section, deck_path=deck_path)


def _speed_table(sp) -> str:
    return md_table(["series", "k", "error (ft)", "time (s)", "fastest core run at least as "
                     "accurate", "its error (ft)", "its time (s)", "speed ratio"],
                    [[s["series"], s["k"], fmt(s["err_ft"]), fmt(s["wall_s"]), s["core"],
                      fmt(s["core_err_ft"]), fmt(s["core_wall_s"]), f"{s['ratio']:.1f}"]
                     for s in sp])


def _runs_table(rows) -> str:
    table = []
    for r in rows:
        if r["series"] == "reference check":
            continue
        what = (f"k = {r['k']}, H = {r['h_s']:.3g} s" if r["engine"] == "emulator"
                else f"rtol {r['rtol']:g}")
        status = (r["hit"].replace("THE POST HAS HIT THE ", "").lower() if r["status"] == "hit"
                  else f"**{r['status']}**" + (f" ({r['guard']})" if r.get("guard", r["status"])
                                                and r.get("guard") != r["status"] else "")
                  + f": {r['error'][:100]}")
        table.append([r["series"], what, status, fmt(r.get("err_traj_ft")), fmt(r.get("err_hit_time_s")),
                      fmt(r.get("err_R_ft")), fmt(r.get("err_traj_ref0_ft")), _time_cell(r),
                      r.get("steps", ""), r.get("nfev") or ""])
    return md_table(["series", "run", "end", "traj (ft)", "hit (s)", "R (ft)",
                     "traj vs k = 0 ref (ft)", "time (s): median [least–largest]", "steps",
                     "nfev"], table)


def _tolerance_section(rows) -> list[str]:
    """The DOP853 tolerance curve and where its non-monotone points come from."""
    tol = _tolerance_rows(rows)
    if not tol:
        return []
    default = next((r for r in tol if math.isclose(r["rtol"], defaults.CORE_RTOL)), None)
    own = [r.get("err_flight_own_ft", math.nan) for r in tol]
    own_max = max((x for x in own if np.isfinite(x)), default=math.nan)
    amp = {id(r): r.get("err_flight_propagated_ft", math.nan) / r.get("err_release_ft", math.nan)
           for r in tol}
    usual = [amp[id(r)] for r in tol if amp[id(r)] >= 5]
    amp_lo, amp_hi = (min(usual), max(usual)) if usual else (math.nan, math.nan)
    table = md_table(
        ["rtol", "traj (ft)", "first spring lost, Δt (s)", "release, Δt (s)",
         "at release: position (ft)", "velocity (ft/s)", "at the hit: propagated (ft)",
         "free flight's own (ft)", "propagated / at release"],
        [[f"{r['rtol']:g}", fmt(r["err_traj_ft"]), fmt(r.get("dt_first_spring_lost_s")),
          fmt(r.get("dt_release_s")), fmt(r.get("err_release_ft")),
          fmt(r.get("err_release_vel_ft_s")), fmt(r.get("err_flight_propagated_ft")),
          fmt(r.get("err_flight_own_ft")),
          fmt(r.get("err_flight_propagated_ft", math.nan) / r.get("err_release_ft", math.nan),
              ".2g")]
         for r in tol])
    out = snippet("error_tolerance.md", "section", ref_rtol=f"{REF_RTOL:g}", table=table,
                  own=("nothing of its own (its solution does not change with rtol)"
                       if own_max == 0.0 else f"at most {own_max:.2g} ft of its own"),
                  amp_lo=f"{amp_lo:.0f}", amp_hi=f"{amp_hi:.0f}",
                  odd=_tolerances(r for r in tol if amp[id(r)] < 5)).split("\n") + [""]
    if default is not None:
        better = [r for r in tol if r["err_traj_ft"] < default["err_traj_ft"]]
        out += [snippet("error_tolerance.md", "default", core_rtol=f"{defaults.CORE_RTOL:g}",
                        traj=f"{default['err_traj_ft']:.2g}",
                        hit_time=f"{default['err_hit_time_s']:.2g}",
                        r=f"{default['err_R_ft']:.2g}", nfev=default["nfev"],
                        better=snippet("error_tolerance.md", "better",
                                       tolerances=_tolerances(better)) + " " if better else "",
                        ref_rtol=f"{REF_RTOL:g}"), ""]
    return out
