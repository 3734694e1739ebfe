"""What both studies share: one emulator run, one core run (each through the engine layer),
energies, the machine, the files.

An emulator run keeps the program's trace, whose rows carry the body velocities ``V1, V2, V3``
and angular velocities ``W1, W2, W3`` of every accepted step, so that the energies of
:mod:`deck_emulator.engine.energy` are known.  Every failure is caught and described: a guard
of the emulator (its name in ``guard``) or any other exception (an emulator defect:
``guard = "crash"``, :attr:`~deck_emulator.engine.EmulatorEngine.record_defects`).
"""

from __future__ import annotations

import datetime
import math
import os
import platform
import time
import warnings

import numpy as np

from deck_emulator import decks
from deck_emulator.engine import CoreEngine, EmulatorEngine, quantities
from deck_emulator.engine import errata as errata_policy
from deck_emulator.studies.csvfile import csv_text  # noqa: F401 - the studies' CSV
from deck_emulator.studies.diff import H0, legacy_options  # noqa: F401 - the studies' step and options
from deck_emulator.studies.distributed import run_longest_first  # noqa: F401 - the studies' runner
from deck_emulator.studies.store import Stopped
from deck_emulator.vocabulary import defaults

#: the emulator's errata in every study run, by the studies' design: ED steps towards its root
#: (no effect at alpha = 0 on steel40, needed by every angled deck); said in each README
ERRATA = (errata_policy.ED_DIRECTION,)


def default_deck() -> str:
    """The report's deck, steel40 (the studies' base scene), as shipped with the package."""

    return decks.path(decks.REPORT_DECK)


# --------------------------------------------------------------------------- the emulator


def run_emulator(deck, *, precision="double", k=0, tha_start=None,
                 ed_tolerance=defaults.LISTING_ED_TOLERANCE, limits=None, errata=ERRATA) -> dict:
    """One emulator run through the engine layer -> {status, guard, error, run, wall_s,
    outcome}.

    ``status``: ``"hit"`` (ended by a hit message), ``"guard"`` (a guard of the emulator fired:
    ``guard`` is its name), ``"crash"`` (any other exception: a defect), ``"stop"`` (ended
    without a hit message). ``run``: the program's own record (its trace), ``wall_s`` the
    program's run time."""
    out = EmulatorEngine(precision=precision, errata=errata, step_scale_k=k, tha_start=tha_start,
                         ed_tolerance=ed_tolerance, limits=limits,
                         record_defects=True).run(deck)
    if out.guard == "crash":
        status, guard = "crash", "crash"
    elif out.error is not None:
        status, guard = "guard", out.guard or "?"
    else:
        status, guard = ("hit" if out.hit is not None else "stop"), ""
    return {"status": status, "guard": guard, "error": out.error or "", "wall_s": out.run_s,
            "outcome": out}


def emulator_hit(run_out: dict) -> tuple[str, float | None]:
    """The hit of a :func:`run_emulator` run as the line printer wrote it, and its time ('',
    None without a hit)."""
    out = run_out["outcome"]
    return (out.hit_message or "", out.hit_time_s) if out.hit is not None else ("", None)


def energies(run_out: dict) -> dict:
    """The launch energy and the free-flight energy drift of a :func:`run_emulator` or
    :func:`run_core` run (:mod:`deck_emulator.engine.energy`, the registry's definitions)."""
    return {k: quantities.value(name, run_out["outcome"])
            for k, name in (("launch_ke_ftlb", "launch_ke_ftlb"),
                            ("free_drift", "free_flight_energy_drift"))}


# --------------------------------------------------------------------------- the core


def run_core(scene, options, *, method="DOP853", rtol=defaults.STUDY_RTOL, atol=None,
             t_max_s=defaults.T_MAX_S) -> dict:
    """One core run through the engine layer -> {status, error, result, wall_s, warnings,
    outcome}; ``status`` "hit", "no hit" (t_max reached) or "error" (CoreError or any
    exception, in ``error``); ``result``: the outcome of a run without an error, else None.
    A run past the wall bound (``defaults.MAX_WALL_S``, read as it starts) raises
    :class:`Stopped` (:func:`stopped_at_wall`): the machine's bound, not the model's, so its
    scene is run again on resume."""
    engine = CoreEngine(options=options, method=method, rtol=rtol,
                        atol=rtol if atol is None else atol, t_max_s=t_max_s, trace=False)
    started = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            out = engine.run(scene)
        except Exception as exc:  # noqa: BLE001 - a defect: recorded
            return {"status": "error", "error": f"{type(exc).__name__}: {exc}", "result": None,
                    "wall_s": time.perf_counter() - started, "warnings": _warnings(caught),
                    "outcome": None}
    stopped_at_wall(out, engine.wall_bound_s)
    if out.error is not None:
        return {"status": "error", "error": out.error, "result": None, "wall_s": out.run_s,
                "warnings": _warnings(caught), "outcome": out}
    return {"status": "hit" if out.hit is not None else "no hit", "error": "", "result": out,
            "wall_s": out.run_s, "warnings": _warnings(caught), "outcome": out}


def stopped_at_wall(out, max_wall_s: float, batch_s: float | None = None):
    """:class:`Stopped` when the core run ``out`` (an Outcome) ended with an error after its
    engine's wall bound ``max_wall_s``, by its own time or by that of the batch it ran in
    (``batch_s``: the compiled core bounds a batch as a whole) -- the bound ended it: a
    starved or suspended machine; else ``out``."""
    took = out.run_s if batch_s is None else max(out.run_s, batch_s)
    if out.error is not None and took >= max_wall_s:
        raise Stopped(f"{out.error} (a slow, starved or suspended machine)")
    return out


def run_outcomes(items: list) -> list:
    """``(engine, deck or scene, name)`` items -> their outcomes, in order.  The core's scenes
    of one engine run together (``CoreEngine.run_batch``); the emulator's one after another
    (the 1967 program runs one deck at a time).  A core scene stopped by the wall bound is
    :class:`Stopped` in its place: its scene runs again on resume."""
    outcomes: list = [None] * len(items)
    groups: list[tuple[object, list[int]]] = []  # engines are compared, not hashed
    for i, (engine, *_) in enumerate(items):
        for e, members in groups:
            if e == engine:
                members.append(i)
                break
        else:
            groups.append((engine, [i]))
    for engine, members in groups:
        if not isinstance(engine, CoreEngine):
            for i in members:
                outcomes[i] = engine.run(items[i][1], name=items[i][2])
            continue
        started = time.perf_counter()
        got = engine.run_batch([items[i][1] for i in members],
                               names=[items[i][2] for i in members])
        batch_s = time.perf_counter() - started
        for i, res in zip(members, got):
            try:
                outcomes[i] = stopped_at_wall(res, engine.wall_bound_s, batch_s)
            except Stopped as exc:
                outcomes[i] = exc
    return outcomes


def _warnings(caught) -> str:
    """The distinct warnings of a run (scipy's, e.g. a NaN in an error estimate it recovered from)."""
    seen = []
    for w in caught:
        text = f"{w.category.__name__}: {w.message}"
        if text not in seen:
            seen.append(text)
    return "; ".join(seen)


# --------------------------------------------------------------------------- files


def cpu_count() -> int:
    """Worker processes by default: every core."""
    return os.cpu_count() or 1


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


def agg_backend():
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt
