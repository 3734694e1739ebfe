"""Work-precision study: error against run time for the 1967 scheme and the modern core.

The reference is the core (``legacy`` preset, DOP853) at the defaults' ``REFERENCE_RTOL``, checked against a
second method at a tenth of that tolerance (Radau and LSODA; LSODA only with ``quick``).
Errors of a run against a reference:

* ``err_traj_ft``: the largest distance between the post's mass-centre trajectories -- at the
  emulator's accepted steps (the reference's dense output interpolated there), or on a fixed
  grid of 2001 times for a core run -- over the time both runs cover;
* ``err_hit_time_s``: the difference of the hit times;
* ``err_R_ft``: the distance between the luminaire point R of the two runs at their hits.

The emulator and the core's legacy preset are not the same discretisation of the start-up kick
once the step is scaled: the emulator's run at step ``H0/2**k`` is therefore measured against
a reference with ``StartupKick(step_s=h)`` (and the ``FCONST`` cap armed at 8 ms, as the
emulator arms it at every k; :func:`~.common.matched_options`) (``err_*``), and also against the
single k = 0 reference (``err_*_ref0``).  Core runs use the k = 0 model, so both coincide.
"""

from __future__ import annotations

import itertools
import math
import time
import timeit
from pathlib import Path

import numpy as np

from deck_emulator.vocabulary import defaults
from deck_emulator.engine.sources import read_deck
from deck_emulator.studies.diff import ed_tolerance as tight_ed_tolerance
from deck_emulator.vocabulary.scene import LEGACY, Scene

from deck_emulator.files import OutputSet, check_output_dir
from deck_emulator.studies.distributed import output_store
from .common import (
    H0,
    agg_backend,
    cpu_count,
    emulator_hit,
    emulator_trajectory,
    fit_slope,
    fmt,
    machine,
    machine_line,
    matched_options,
    md_table,
    run_core,
    run_emulator,
    run_longest_first,
    csv_text,
)

REF_RTOL = defaults.REFERENCE_RTOL
CHECK_RTOL = defaults.REFERENCE_CHECK_RTOL
GRID_POINTS = defaults.ERROR_GRID_POINTS
CORE_METHODS = ("DOP853", "RK45", "Radau")

SERIES_LISTING = "legacy, ED as printed (double)"
SERIES_TIGHT = "legacy, ED tightened (double)"
SERIES_IBM = "legacy, ED as printed (IBM 7094)"

COLUMNS = [
    "series", "engine", "method", "precision", "k", "h_s", "rtol", "atol", "ed_tolerance",
    "status", "guard", "error", "hit", "hit_time_s", "reference",
    "err_traj_ft", "err_hit_time_s", "err_R_ft", "err_traj_ref0_ft", "err_hit_time_ref0_s", "err_R_ref0_ft",
    "wall_s", "wall_reps_s", "reps", "steps", "nfev",
]


def plan(quick: bool) -> dict:
    if quick:
        return {"ks": range(3), "rtols": (1e-4, 1e-7, 1e-10), "emu_reps": 1, "core_reps": 3,
                "ibm": False, "checks": ("LSODA",)}
    return {"ks": range(7), "rtols": tuple(10.0 ** -e for e in range(3, 12)), "emu_reps": 3,
            "core_reps": 5, "ibm": True, "checks": ("Radau", "LSODA")}


# --------------------------------------------------------------------------- references

_REFS: dict = {}


def _scene(deck_path):
    key = ("scene", str(deck_path))
    if key not in _REFS:
        deck = read_deck(deck_path)
        _REFS[key] = (deck, Scene.from_deck(deck))
    return _REFS[key]


def reference(deck_path, k: int):
    """The core at rtol 1e-12 with the start-up kick of step H0/2**k (cached per process)."""
    key = ("ref", str(deck_path), k)
    if key not in _REFS:
        _, scene = _scene(deck_path)
        out = run_core(scene, matched_options(H0 / 2**k), rtol=REF_RTOL)
        if out["status"] != "hit":
            raise RuntimeError(f"the reference (k = {k}) did not end with a hit: {out['error']}")
        _REFS[key] = out["result"]
    return _REFS[key]


def _core_errors(res, ref) -> dict:
    t_end = min(res.span[1], ref.span[1])
    grid = np.linspace(0.0, t_end, GRID_POINTS)
    d = np.linalg.norm(res.position("CM", grid) - ref.position("CM", grid), axis=0)
    out = {"err_traj_ft": float(d.max()), "err_hit_time_s": math.nan, "err_R_ft": math.nan}
    if res.hit and ref.hit:
        out["err_hit_time_s"] = abs(res.hit_time_s - ref.hit_time_s)
        out["err_R_ft"] = float(np.linalg.norm(
            res.position("R", res.hit_time_s) - ref.position("R", ref.hit_time_s)))
    return out


def _emulator_errors(run, hit_time, ref) -> dict:
    t, xyz = emulator_trajectory(run)
    t_start, t_end = ref.span
    keep = (t >= t_start) & (t <= t_end)
    out = {"err_traj_ft": math.nan, "err_hit_time_s": math.nan, "err_R_ft": math.nan}
    if keep.any():
        out["err_traj_ft"] = float(np.max(np.linalg.norm(
            xyz[:, keep] - ref.position("CM", t[keep]), axis=0)))
    if hit_time is not None and ref.hit:
        r_emu = np.asarray(run.points["R"][-1], dtype=float)  # R at the last accepted step
        out["err_hit_time_s"] = abs(hit_time - ref.hit_time_s)
        out["err_R_ft"] = float(np.linalg.norm(r_emu - ref.position("R", ref.hit_time_s)))
    return out


# --------------------------------------------------------------------------- tasks


def _task(spec: dict) -> dict:
    kind = spec["kind"]
    if kind == "check":
        return _task_check(spec)
    if kind == "emulator":
        return _task_emulator(spec)
    return _task_core(spec)


def _task_check(spec):
    """A reference against the same model by a second method at a tenth of the tolerance."""
    deck_path, k, method = spec["deck"], spec["k"], spec["method"]
    _, scene = _scene(deck_path)
    ref = reference(deck_path, k)
    out = run_core(scene, matched_options(H0 / 2**k), method=method, rtol=CHECK_RTOL)
    row = {"series": "reference check", "engine": "core", "method": method, "k": k,
           "h_s": H0 / 2**k, "rtol": CHECK_RTOL, "atol": CHECK_RTOL, "status": out["status"],
           "error": out["error"], "reference": f"DOP853 rtol {REF_RTOL:g}, k = {k}",
           "wall_s": out["wall_s"], "reps": 1}
    if out["result"] is not None:
        res = out["result"]
        row.update(_core_errors(res, ref), hit=res.hit_message or "", hit_time_s=res.hit_time_s,
                   nfev=res.evaluations)
        row["ref_wall_s"] = ref.run_s
    return row


LONG_RUN_S = defaults.ERROR_LONG_RUN_S
#: How a point is timed, in words (the README says it).  The least, not the median: on a
#: machine shared with other work a run is only ever slowed down, never sped up, so the least
#: of the repetitions is the nearest to the run's own cost (timeit's advice).
TIMING = ("the least of the repetitions' wall times in this process run (the core's by "
          "`timeit.Timer.repeat(number=1)` after one untimed run; the emulator's the program's "
          "own loop)")


def _task_emulator(spec):
    deck_path, k, precision, tol = spec["deck"], spec["k"], spec["precision"], spec["ed_tolerance"]
    deck, _ = _scene(deck_path)

    # the program's own loop time (run_emulator's wall_s), the least of the repetitions
    # (TIMING); a failed run is not repeated (its time is not comparable), nor one that takes
    # over LONG_RUN_S (its timing noise is small beside it, and the study must stay within
    # 5 minutes)
    first = run_emulator(deck, precision=precision, k=k, ed_tolerance=tol)
    walls = [first["wall_s"]]
    if first["status"] == "hit" and first["wall_s"] < LONG_RUN_S:
        walls += [run_emulator(deck, precision=precision, k=k, ed_tolerance=tol)["wall_s"]
                  for _ in range(spec["reps"] - 1)]
    wall = min(walls)
    run = first["outcome"]
    message, hit_time = emulator_hit(first)
    row = {"series": spec["series"], "engine": "emulator", "method": "listing scheme",
           "precision": precision, "k": k, "h_s": H0 / 2**k, "ed_tolerance": tol,
           "status": first["status"], "guard": first["guard"], "error": first["error"],
           "hit": message, "hit_time_s": hit_time, "reference": f"k = {k}",
           "wall_s": wall, "wall_reps_s": " ".join(f"{w:.4f}" for w in walls), "reps": len(walls),
           "steps": run.accepted_steps()[0].size}
    if first["status"] == "hit":
        row.update(_emulator_errors(run, hit_time, reference(deck_path, k)))
        ref0 = _emulator_errors(run, hit_time, reference(deck_path, 0))
        row.update(err_traj_ref0_ft=ref0["err_traj_ft"], err_hit_time_ref0_s=ref0["err_hit_time_s"],
                   err_R_ref0_ft=ref0["err_R_ft"])
    return row


def _task_core(spec):
    deck_path, method, rtol = spec["deck"], spec["method"], spec["rtol"]
    _, scene = _scene(deck_path)
    ref = reference(deck_path, 0)

    # the first run gives the answer (and warms the process up); the point's time is the
    # least of ``reps`` more, timed by timeit (TIMING)
    first = run_core(scene, LEGACY, method=method, rtol=rtol)
    walls = ([first["wall_s"]] if first["status"] != "hit" else timeit.Timer(
        lambda: run_core(scene, LEGACY, method=method, rtol=rtol)).repeat(
            repeat=spec["reps"], number=1))
    wall = min(walls)
    row = {"series": f"core {method}", "engine": "core", "method": method, "rtol": rtol,
           "atol": rtol, "status": first["status"], "error": first["error"], "reference": "k = 0",
           "wall_s": wall, "wall_reps_s": " ".join(f"{w:.4f}" for w in walls), "reps": len(walls)}
    res = first["result"]
    if res is not None:
        errs = _core_errors(res, ref)
        row.update(errs, hit=res.hit_message or "", hit_time_s=res.hit_time_s,
                   nfev=res.evaluations)
        row.update(err_traj_ref0_ft=errs["err_traj_ft"], err_hit_time_ref0_s=errs["err_hit_time_s"],
                   err_R_ref0_ft=errs["err_R_ft"])
    return row


def _tasks(deck_path: str, p: dict) -> list[dict]:
    tasks = []
    for k in p["ks"]:
        for series, tol in ((SERIES_LISTING, ".0001"), (SERIES_TIGHT, tight_ed_tolerance(k))):
            tasks.append({"kind": "emulator", "deck": deck_path, "series": series, "k": k,
                          "precision": "double", "ed_tolerance": tol, "reps": p["emu_reps"],
                          "cost": 0.6 * 2**k * p["emu_reps"]})
    if p["ibm"]:
        tasks.append({"kind": "emulator", "deck": deck_path, "series": SERIES_IBM, "k": 0,
                      "precision": "ibm7094", "ed_tolerance": ".0001", "reps": p["emu_reps"],
                      "cost": 3.5 * p["emu_reps"]})
    for method in CORE_METHODS:
        for rtol in p["rtols"]:
            cost = (0.3 if method == "Radau" else 0.15) * (1 - math.log10(rtol) / 6) * p["core_reps"]
            tasks.append({"kind": "core", "deck": deck_path, "method": method, "rtol": rtol,
                          "reps": p["core_reps"], "cost": cost})
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
                resume: bool = False) -> dict:
    """Run the work-precision study on ``deck_path``; write ``error_study.csv``,
    ``work_precision.png`` and ``README.md`` into ``out_dir`` (the runs are stored in its
    ``.scenes`` as they finish: ``resume`` runs only the missing ones).  Returns the
    summary."""
    started = time.perf_counter()
    out = Path(out_dir)
    check_output_dir(out)  # a missing or read-only folder fails before any run
    deck_path = str(deck_path)
    read_deck(deck_path)  # a bad deck fails here, before any process starts
    p = plan(quick)
    jobs = jobs or cpu_count()
    rows = run_longest_first(_task, _tasks(deck_path, p), jobs=jobs, desc="study error",
                             quiet=quiet, store_dir=output_store(out, resume),
                             scheduler=scheduler, resume=resume, core=True)
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
            "vs_h": fit_slope(h, [r["err_traj_ft"] for r in ok]),
            "vs_h_ref0": fit_slope(h, [r.get("err_traj_ref0_ft", math.nan) for r in ok]),
            "vs_h_hit": fit_slope(h, [r.get("err_hit_time_s", math.nan) for r in ok]),
            "vs_h_R": fit_slope(h, [r.get("err_R_ft", math.nan) for r in ok]),
            "vs_time": fit_slope([r["wall_s"] for r in ok], [r["err_traj_ft"] for r in ok]),
            "pairwise": [math.log2(a["err_traj_ft"] / b["err_traj_ft"])
                         for a, b in itertools.pairwise(ok) if b["k"] == a["k"] + 1],
        }
    for method in CORE_METHODS:
        ok = [r for r in _ok(rows, f"core {method}") if r["err_traj_ft"] > floor]
        orders[f"core {method}"] = {
            "vs_rtol": fit_slope([r["rtol"] for r in ok], [r["err_traj_ft"] for r in ok]),
            "vs_time": fit_slope([r["wall_s"] for r in ok], [r["err_traj_ft"] for r in ok]),
            "vs_nfev": fit_slope([r["nfev"] for r in ok], [r["err_traj_ft"] for r in ok]),
            "points": len(ok),
            "t_min": min((r["wall_s"] for r in ok), default=math.nan),
            "t_max": max((r["wall_s"] for r in ok), default=math.nan),
            "n_min": min((r["nfev"] for r in ok), default=0),
            "n_max": max((r["nfev"] for r in ok), default=0),
        }
    core_ok = [r for m in CORE_METHODS for r in _ok(rows, f"core {m}")]
    ratios = []
    for series in (SERIES_LISTING, SERIES_TIGHT, SERIES_IBM):
        for r in _ok(rows, series):
            better = [c for c in core_ok if c["err_traj_ft"] <= r["err_traj_ft"]]
            if not better:
                continue
            best = min(better, key=lambda c: c["wall_s"])
            ratios.append({"series": series, "k": r["k"], "err_ft": r["err_traj_ft"],
                           "wall_s": r["wall_s"], "core": f"{best['method']} rtol {best['rtol']:g}",
                           "core_err_ft": best["err_traj_ft"], "core_wall_s": best["wall_s"],
                           "ratio": r["wall_s"] / best["wall_s"]})
    return {"reference_error_ft": ref_err, "reference_error_all_ft": ref_err_all,
            "orders": orders, "speed": ratios}


# --------------------------------------------------------------------------- outputs

_STYLE = {
    SERIES_LISTING: dict(color="#c0392b", marker="o"),
    SERIES_TIGHT: dict(color="#e67e22", marker="s"),
    SERIES_IBM: dict(color="#7f3c8d", marker="D", markersize=9),
    "core DOP853": dict(color="#1f77b4", marker="^"),
    "core RK45": dict(color="#2ca02c", marker="v"),
    "core Radau": dict(color="#17becf", marker="P"),
}


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

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(15, 7.4), gridspec_kw={"width_ratios": [1.35, 1]})
    labelled = []
    for series, style in _STYLE.items():
        ok = _ok(rows, series)
        if not ok:
            continue
        ax.loglog([r["wall_s"] for r in ok], [r["err_traj_ft"] for r in ok], "-", lw=1.6,
                  label=series + (" (each point labelled by its rtol = atol)"
                                  if series == "core DOP853" else ""), **style)
        for r in ok:
            if r["engine"] == "emulator":
                ax.annotate(f"k={r['k']}", (r["wall_s"], r["err_traj_ft"]), textcoords="offset points",
                            xytext=(5, 4), fontsize=8.5, color=style["color"])
            else:  # each core point by its tolerance, written once the layout is made
                labelled.append((r["wall_s"], r["err_traj_ft"], _tolerance_label(r["rtol"]),
                                 style["color"]))
    ref_err = summary["reference_error_all_ft"]
    if np.isfinite(ref_err) and ref_err > 0:
        ax.axhline(ref_err, color="grey", ls=":", lw=1)
        ax.annotate("the references' own error", (1.0, ref_err), xycoords=("axes fraction", "data"),
                    textcoords="offset points", xytext=(-4, 4), ha="right", fontsize=8.5,
                    color="dimgrey")
    ax.set_xlabel("wall time per run, s (least of the repetitions)")
    ax.set_ylabel("largest mass-centre distance to the reference, ft")
    ax.set_title(f"Work-precision{' (' + title + ')' if title else ''}: error against run time")
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.grid(True, which="major", alpha=0.4)
    ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, frameon=False)

    for series in (SERIES_LISTING, SERIES_TIGHT):
        ok = _ok(rows, series)
        if not ok:
            continue
        style = _STYLE[series]
        h = np.array([r["h_s"] for r in ok])
        o = summary["orders"][series]
        bx.loglog(h, [r["err_traj_ft"] for r in ok], "-", lw=1.6, color=style["color"],
                  marker=style["marker"], label=f"{series}: order {o['vs_h']:.2f}")
        bx.loglog(h, [r["err_traj_ref0_ft"] for r in ok], "--", lw=1, color=style["color"],
                  marker=style["marker"], mfc="none",
                  label=f"the same against the k = 0 reference: order {o['vs_h_ref0']:.2f}")
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
    bx.legend(fontsize=8.5, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=1, frameon=False)
    fig.tight_layout()
    _labels_apart(ax, labelled)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _report(rows, summary, p, deck_path, cmd, jobs, wall) -> str:
    m = machine()
    o = summary["orders"]
    lst, tight = o[SERIES_LISTING], o[SERIES_TIGHT]
    checks = [r for r in rows if r["series"] == "reference check"]
    lines = [
        "# Work-precision study: the 1967 scheme against the modern core",
        "",
        f"Command: `{cmd}`",
        "",
        machine_line(m, jobs, wall),
        "",
        "![work-precision diagram](work_precision.png)",
        "",
        "## Observed orders",
        "",
        f"* **The listing's scheme as printed** (ED's root search stops at |DF| < .0001 rad at "
        f"every step size): observed order **{lst['vs_h']:.2f}** in H (least-squares slope of "
        f"log error against log H over the runs that ended with a hit; step by step "
        f"{', '.join(f'{x:.2f}' for x in lst['pairwise'])})."
        + (" It does not converge: ED's error in psi per step does not shrink with H, so "
           "halving the step adds error." if not lst["vs_h"] > 0.5 else ""),
        f"* **The same scheme with ED's tolerance tightened with the step** (1e-6 rad / 4**k, "
        f"as `deck-emulator diff` does): observed order **{tight['vs_h']:.2f}** in H "
        f"(hit time {tight['vs_h_hit']:.2f}, terminal R {tight['vs_h_R']:.2f}; step by step "
        f"{', '.join(f'{x:.2f}' for x in tight['pairwise'])}) -- first order, as explicit "
        f"Euler velocities make it; against run time the slope is {tight['vs_time']:.2f}.",
    ]
    for method in CORE_METHODS:
        c = o[f"core {method}"]
        lines.append(
            f"* **core {method}**: error against rtol slope **{c['vs_rtol']:.2f}** (tolerance "
            f"proportionality; {c['points']} runs above ten times the reference's error); its "
            f"run time only spans {c['t_min']:.3g} ... {c['t_max']:.3g} s and its function "
            f"evaluations {c['n_min']} ... {c['n_max']} over the whole rtol range, so the fitted "
            f"slopes against time ({c['vs_time']:.1f}) and work ({c['vs_nfev']:.1f}) are not "
            "orders.")
    lines += [
        "",
        "The core's work hardly grows with accuracy here: its step is bounded by `max_step_s = "
        "0.005` s (so that no sign change of an event function falls inside one step) and every "
        "contact-mode switch restarts the integrator, so even the "
        "loosest tolerance costs about as many steps as the tight ones, and the run time is "
        "mostly the Python right-hand side and event handling. The methods' orders (8 for "
        "DOP853, 5 for RK45 and Radau) cannot show against work; the slope against rtol shows "
        "that each method's error follows its tolerance (not always monotonically: an event "
        "located a little differently moves the whole rest of the run).",
        "",
        "## Speed at equal accuracy",
        "",
    ]
    sp = [s for s in summary["speed"]]
    head = next((s for s in sp if s["series"] == SERIES_LISTING and s["k"] == 0), None)
    if head:
        lines.append(
            f"At the listing's own accuracy (k = 0, double: {head['err_ft']:.3g} ft in "
            f"{head['wall_s']:.3g} s) the fastest core run at least as accurate is "
            f"{head['core']} ({head['core_err_ft']:.2g} ft in {head['core_wall_s']:.3g} s): "
            f"**{head['ratio']:.1f} times faster**, and already "
            f"{head['err_ft'] / head['core_err_ft']:.0f} times more accurate, so the ratio at "
            "exactly equal error is larger still (the core cannot run cheaper than its step bound).")
    lines += ["", md_table(["series", "k", "error (ft)", "time (s)", "fastest core run at least as "
                            "accurate", "its error (ft)", "its time (s)", "speed ratio"],
                           [[s["series"], s["k"], fmt(s["err_ft"]), fmt(s["wall_s"]), s["core"],
                             fmt(s["core_err_ft"]), fmt(s["core_wall_s"]), f"{s['ratio']:.1f}"]
                            for s in sp])]
    lines += [
        "",
        "## The reference",
        "",
        f"The core's `legacy` preset (the listing's quirks as options), DOP853 at rtol = atol = "
        f"{REF_RTOL:g}, default `max_step_s`. Its own error, measured against "
        f"{' and '.join(p['checks'])} at rtol = atol = {CHECK_RTOL:g}: "
        f"**{summary['reference_error_ft']:.2g} ft** (k = 0; largest over all references "
        f"{summary['reference_error_all_ft']:.2g} ft).",
        "",
        md_table(["reference", "checked with", "trajectory (ft)", "hit time (s)", "R at the hit (ft)",
                  "check's time (s)"],
                 [[r["reference"], f"{r['method']} rtol {r['rtol']:g}", fmt(r.get("err_traj_ft")),
                   fmt(r.get("err_hit_time_s")), fmt(r.get("err_R_ft")), fmt(r.get("wall_s"))]
                  for r in checks]),
        "",
        "The emulator with its step literals divided by 2**k is **not** the same discretisation "
        "of the start-up as the core's k = 0 model: the listing's first step (F1B = -10000 lb, "
        "FSB = 10000 lb, THA = 0.000022) lasts one step H. Each emulator run is therefore "
        "measured against a reference with the matching `StartupKick(step_s=H)` (solid lines, "
        "`err_*` columns; the `FCONST` cap armed at 8 ms, as the emulator arms it at every k), "
        "and also against the single k = 0 reference (dashed, `err_*_ref0`): against the latter "
        "the error stops shrinking at the size of the start-up's own effect.",
        "",
        "## Errors and times",
        "",
        "Errors: `traj` the largest distance between the mass-centre trajectories over the time "
        "both runs cover (at the emulator's accepted steps; on a grid of 2001 times for the core), "
        "`hit` the hit-time difference, `R` the distance between the luminaire points R at the "
        "two hits. Times: " + TIMING + f" (emulator: {p['emu_reps']} runs, core: one run "
        f"and {p['core_reps']} timed; runs that fail, and emulator runs over "
        f"{LONG_RUN_S:g} s, are timed once); "
        f"{jobs} runs at a time, one per process. Every number is in `error_study.csv`.",
        "",
    ]
    table = []
    for r in rows:
        if r["series"] == "reference check":
            continue
        what = (f"k = {r['k']}, H = {r['h_s']:.3g} s" if r["engine"] == "emulator"
                else f"rtol {r['rtol']:g}")
        status = (r["hit"].replace("THE POST HAS HIT THE ", "").lower() if r["status"] == "hit"
                  else f"**{r['status']}**" + (f" ({r['guard']})" if r.get("guard", r["status"])
                                                != r["status"] else "") + f": {r['error'][:100]}")
        table.append([r["series"], what, status, fmt(r.get("err_traj_ft")), fmt(r.get("err_hit_time_s")),
                      fmt(r.get("err_R_ft")), fmt(r.get("err_traj_ref0_ft")), fmt(r["wall_s"]),
                      r.get("steps") or r.get("nfev") or ""])
    lines += [md_table(["series", "run", "end", "traj (ft)", "hit (s)", "R (ft)",
                        "traj vs k = 0 ref (ft)", "time (s)", "steps / nfev"], table), ""]
    failed = [r for r in rows if r["engine"] == "emulator" and r["status"] != "hit"]
    if failed:
        lines += ["## Runs that failed", ""]
        for r in failed:
            lines.append(f"* {r['series']}, k = {r['k']} (H = {r['h_s']:.3g} s): {r['status']}"
                         + (f" ({r['guard']})" if r["guard"] != r["status"] else "")
                         + f": {r['error']}")
        if any("THAD" in r["error"] for r in failed):
            lines += [
                "",
                "At this step the start-up's tilt THA = 0.000022 rad (which is 0.0545 rad/s times "
                "the printed 0.0004 s and is not a step literal, so it is not scaled) moves the "
                "impact point S further in the first step than the car moves (about 18.8 ft x "
                "0.000022 = 4.1e-4 ft against 58.66 ft/s x H), so DIFF > 0 at step 1: label 56 "
                "sends the run to the contact printout (label 88), which prints THAD, a variable "
                "only label 44 assigns -- the start-up step (label 123) never does. The 1967 "
                "program would print whatever the word held; the emulator stops with an "
                "AttributeError instead of an EmulatorError.",
            ]
        lines.append("")
    lines += [
        "## Method",
        "",
        f"Scene: `{deck_path}`. The emulator runs with the erratum `ed-direction` (ED steps "
        "towards its root; no effect on this deck as printed) and the guards' defaults. The "
        "IBM 7094 arithmetic is the emulator's model of the 1967 machine's 36-bit words, at k = 0 "
        "only. Core runs: the `legacy` preset, atol = rtol, default `max_step_s` (0.005 s).",
        "",
    ]
    return "\n".join(lines)
