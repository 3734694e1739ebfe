"""What both studies share: one emulator run, one core run, energies, the machine, the files.

An emulator run here is :class:`~deck_emulator.legacy.emulator.Program` with its trace rows extended by
the body velocities ``V1, V2, V3`` and angular velocities ``W1, W2, W3`` of the step (the
listing's ``V1A ...`` in contact, ``V1FA ...`` in free flight), so that the kinetic energy of
every accepted step is known.  Every failure is caught and described: a guard of the emulator
(:class:`~deck_emulator.legacy.emulator.EmulatorError` with its ``guard``) or any other exception (an
emulator defect: ``guard = "crash"``).
"""

from __future__ import annotations

import datetime
import math
import os
import platform
import statistics
import time
import warnings
from pathlib import Path

import numpy as np

from deck_emulator.engine import EmulatorEngine, errata as errata_policy
from deck_emulator.studies.diff import legacy_options
from deck_emulator.core import kinetic_energy, simulate
from deck_emulator.files import write_file
from deck_emulator.studies.csvfile import csv_text, csv_value
from deck_emulator.legacy.emulator import EmulatorError, Limits
from deck_emulator.legacy.printer import event_message

H0 = 0.0004  # the listing's step, s
#: the emulator's errata in every study run, by the studies' design: ED steps towards its root
#: (no effect at alpha = 0 on steel40, needed by every angled deck); said in each README
ERRATA = (errata_policy.ED_DIRECTION,)
_BODY_RATES = ("V1", "V2", "V3", "W1", "W2", "W3")


matched_options = legacy_options  # one definition: deck_emulator.studies.diff.legacy_options


def default_deck() -> Path:
    """The report's deck, steel40 (the studies' base scene), as shipped with the package."""
    from deck_emulator import decks

    return decks.path(decks.REPORT_DECK)


# --------------------------------------------------------------------------- the emulator


_DEFAULT_LIMITS = Limits()


def run_emulator(deck, *, precision="double", k=0, tha_start=None, ed_tolerance=".0001",
                 limits=_DEFAULT_LIMITS, errata=ERRATA) -> dict:
    """One emulator run -> {status, guard, error, run, wall_s}.

    ``status``: ``"hit"`` (ended by a hit message), ``"guard"`` (a guard of the emulator fired:
    ``guard`` is its name), ``"crash"`` (any other exception: a defect), ``"stop"`` (ended
    without a hit message)."""
    prog = EmulatorEngine(precision=precision, errata=errata, step_scale_k=k, tha_start=tha_start,
                          ed_tolerance=ed_tolerance, limits=limits).program(deck)
    started = time.perf_counter()
    status, guard, error = "stop", "", ""
    try:
        run = prog.run()
    except EmulatorError as exc:
        run, status, guard = prog.run_, "guard", exc.guard or "?"
        error = str(exc)
    except Exception as exc:  # noqa: BLE001 - an emulator defect, recorded as such
        run, status, guard = prog.run_, "crash", "crash"
        error = f"{type(exc).__name__}: {exc} (label {prog.label}, step {prog.step})"
    wall = time.perf_counter() - started
    if status == "stop" and run.events and run.events[-1].is_hit:
        status = "hit"
    return {"status": status, "guard": guard, "error": error, "run": run, "wall_s": wall}


def emulator_hit(run) -> tuple[str, float | None]:
    """The hit as the line printer wrote it, and its time ('', None without a hit)."""
    if run.events and run.events[-1].is_hit:
        return event_message(run.events[-1]), run.events[-1].time_s
    return "", None


def emulator_trajectory(run) -> tuple[np.ndarray, np.ndarray]:
    """Times (n,) and mass centres (3, n) of the accepted steps."""
    t = np.array([r["t"] for r in run.trace], dtype=float)
    xyz = np.array([[r["XCM"], r["YYCM"], r["ZZCM"]] for r in run.trace], dtype=float).T
    return t, xyz.reshape(3, -1)


def emulator_energies(run, deck) -> dict:
    """Kinetic energy of the post when the car lets go, and the free-flight energy drift.

    ``launch_ke_ftlb``: kinetic energy at the last contact step.  ``free_drift``: (E_end -
    E_start) / E_start over the free-flight steps, E = kinetic + W G (ZZ + HEIGHT)."""
    d = deck.values
    mass, g, depth = d["W"], d["G"], d["HEIGHT"]
    inertia = (d["A"], d["B"], d["C"])

    def energy(row, potential=True):
        ke = 0.5 * mass * (row["V1"] ** 2 + row["V2"] ** 2 + row["V3"] ** 2) + 0.5 * (
            inertia[0] * row["W1"] ** 2 + inertia[1] * row["W2"] ** 2 + inertia[2] * row["W3"] ** 2)
        return ke + (mass * g * (row["ZZCM"] + depth) if potential else 0.0)

    contact = [r for r in run.trace if r["phase"] == "contact"]
    free = [r for r in run.trace if r["phase"] != "contact"]
    out = {"launch_ke_ftlb": math.nan, "free_drift": math.nan}
    if contact and free:
        out["launch_ke_ftlb"] = energy(contact[-1], potential=False)
    if len(free) >= 2:
        e0, e1 = energy(free[0]), energy(free[-1])
        out["free_drift"] = (e1 - e0) / e0 if e0 else math.nan
    return out


# --------------------------------------------------------------------------- the core


def run_core(scene, options, *, method="DOP853", rtol=1e-9, atol=None, t_max_s=10.0) -> dict:
    """One core run -> {status, error, result, wall_s}; ``status`` "hit", "no hit" (t_max
    reached) or "error" (CoreError or any exception, in ``error``)."""
    started = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result = simulate(scene, options, method=method, rtol=rtol,
                              atol=rtol if atol is None else atol, t_max_s=t_max_s)  # the core's
            # own call: the studies need its t_max_s and its warnings, not an Outcome
        except Exception as exc:  # noqa: BLE001 - CoreError or a defect: recorded
            return {"status": "error", "error": f"{type(exc).__name__}: {exc}", "result": None,
                    "wall_s": time.perf_counter() - started, "warnings": _warnings(caught)}
    wall = time.perf_counter() - started
    return {"status": "hit" if result.hit else "no hit", "error": "", "result": result,
            "wall_s": wall, "warnings": _warnings(caught)}


def _warnings(caught) -> str:
    """The distinct warnings of a run (scipy's, e.g. a NaN in an error estimate it recovered from)."""
    seen = []
    for w in caught:
        text = f"{w.category.__name__}: {w.message}"
        if text not in seen:
            seen.append(text)
    return "; ".join(seen)


def core_energies(result) -> dict:
    """As :func:`emulator_energies`, for a core run (the car lets go at
    ``vehicle_contact_lost_s``; free flight ends at the hit or at the end of the run)."""
    out = {"launch_ke_ftlb": math.nan, "free_drift": math.nan}
    t0 = result.vehicle_contact_lost_s
    if t0 is None:
        return out
    post = result.scene.post
    mass, inertia = post.mass_slug, post.principal_inertia_slug_ft2
    g, depth = result.scene.environment.gravity_ft_s2, result.scene.environment.ground_depth_ft
    traj = result.trajectory
    t1 = min(result.end_time_s, traj.t_end)

    def energy(t, potential=True):
        y = traj.state(t)
        ke = float(kinetic_energy(y[:13], mass, inertia))
        return ke + (mass * g * float(y[2] + depth) if potential else 0.0)

    out["launch_ke_ftlb"] = energy(t0, potential=False)
    if t1 > t0:
        e0 = energy(t0)
        out["free_drift"] = (energy(t1) - e0) / e0 if e0 else math.nan
    return out


# --------------------------------------------------------------------------- timing, processes


def median_wall(fn, reps: int) -> tuple[float, list[float], object]:
    """Run ``fn`` ``reps`` times: (median wall time, all times, the first run's value).
    ``fn`` returns (value, wall seconds)."""
    times, first = [], None
    for i in range(max(1, reps)):
        value, wall = fn()
        times.append(wall)
        if i == 0:
            first = value
    return statistics.median(times), times, first


# --------------------------------------------------------------------------- files


def cpu_count() -> int:
    """Worker processes by default: every core."""
    return os.cpu_count() or 1


def run_longest_first(fn, tasks: list[dict], *, jobs: int, desc: str, quiet: bool = False) -> list:
    """``[fn(t) for t in tasks]`` on the one parallel map, the costliest tasks (their
    ``cost``) started first so that no long run is left for last; results in the tasks' order."""
    from deck_emulator.parallel import parallel_map

    order = sorted(range(len(tasks)), key=lambda i: -tasks[i]["cost"])
    done = parallel_map(fn, [tasks[i] for i in order], jobs=jobs, desc=desc, unit="run",
                        quiet=quiet)
    results: list = [None] * len(tasks)
    for i, r in zip(order, done):
        results[i] = r
    return results


def machine() -> dict:
    import matplotlib
    import scipy

    return {
        "date": datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "matplotlib": matplotlib.__version__,
        "platform": platform.platform(),
        "load": " / ".join(f"{x:.2f}" for x in os.getloadavg()) if hasattr(os, "getloadavg") else "?",
    }


def machine_line(m: dict, jobs: int, wall_s: float) -> str:
    return (f"Run on {m['date']} on a machine with **{m['cores']} cores** (`os.cpu_count()`), "
            f"{jobs} worker process(es), load average {m['load']} at the start; Python "
            f"{m['python']}, NumPy {m['numpy']}, SciPy "
            f"{m['scipy']}, Matplotlib {m['matplotlib']} ({m['platform']}). The whole study took "
            f"{wall_s:.0f} s.")


def write_csv(path: Path, rows: list[dict], columns: list[str]) -> None:
    """Write :func:`csv_text` to ``path`` whole or not at all."""
    write_file(path, csv_text(rows, columns))


fmt_csv = csv_value  # the one cell format (deck_emulator.studies.csvfile)


def fmt(v, spec=".3g", none="–") -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return none
    if isinstance(v, float):
        return format(v, spec)
    return str(v)


def md_table(header: list[str], rows: list[list]) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(out)


def fit_slope(x, y) -> float:
    """Least-squares slope of log10(y) against log10(x) over the finite positive points."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    keep = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    if keep.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log10(x[keep]), np.log10(y[keep]), 1)[0])


def agg_backend():
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt
