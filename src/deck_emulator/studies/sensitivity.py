"""Which uncertain input decides the outcome: Sobol indices, ``deck-emulator sensitivity``.

The inputs the report takes as estimates (base friction and its travel, the crush springs
``CK`` and ``CT``, the cap ``FCONST``, the car's mass ``WV``: :data:`DEFAULT_INPUTS`, ranges
ours) or any deck input named with ``--input NAME=LO:HI`` are sampled uniformly (SALib:
Saltelli's scheme on a Sobol' sequence, ``N (D + 2)`` scenes for ``D`` inputs) and every
sample run on either engine; the answer is each outcome's (:data:`OUTCOMES`) first-order and
total indices with 95 % bootstrap intervals. What the inputs, the outcomes and the rules of
a withheld index mean: docs/sensitivity.md.
"""

from __future__ import annotations

import csv
import dataclasses
import functools
import io
import math
import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from deck_emulator import decks
from deck_emulator.engine import CoreEngine, EmulatorEngine, core_keywords, quantities
from deck_emulator.engine.sources import read_deck
from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.files import OutputError, OutputSet, check_output_dir
from deck_emulator.studies.common import agg_backend, fmt, run_outcomes
from deck_emulator.studies.pages import page
from deck_emulator.studies.distributed import run_scenes
from deck_emulator.studies.store import SceneStore, scene_id
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.deck_fields import DECK_UNITS, NAMES, deck_label
from deck_emulator.vocabulary.defaults import SCENE_STORE
from deck_emulator.vocabulary.scene import (
    LISTING_BASE_FRICTION,
    LISTING_FRICTION_WINDOW_FT,
    BaseFriction,
)


# =================================================================================== inputs


@dataclass(frozen=True)
class InputRange:
    """One uncertain input: ``name`` (a READ-list name or one of :data:`SCENE_INPUTS`), the
    interval it is sampled from (uniform), the nominal value and what it is."""

    name: str
    low: float
    high: float
    nominal: float | None = None
    what: str = ""


#: The core scene's inputs that are not deck fields: base friction (lb) and its travel (ft).
SCENE_INPUTS = {
    "friction_lb": "base friction force at Q (lb); the listing's 3.1*300 = 930",
    "friction_travel_ft": "travel of the base over which friction acts (ft); the listing's "
    "0.083333 - 0.004 = 0.079333",
}

LISTING_FRICTION_LB = LISTING_BASE_FRICTION.force_lb
LISTING_FRICTION_TRAVEL_FT = LISTING_FRICTION_WINDOW_FT

#: The inputs the report calls estimates, with our ranges (docs/sensitivity.md).
DEFAULT_INPUTS: tuple[InputRange, ...] = (
    InputRange("friction_lb", 465.0, 1395.0, LISTING_FRICTION_LB, SCENE_INPUTS["friction_lb"]),
    InputRange(
        "friction_travel_ft", 0.04, 0.12, LISTING_FRICTION_TRAVEL_FT,
        SCENE_INPUTS["friction_travel_ft"],
    ),
    InputRange("CK", 23100.0, 42900.0, 33000.0, "first crush spring (lb/ft)"),
    InputRange("CT", 14000.0, 26000.0, 20000.0, "second crush spring (lb/ft)"),
    InputRange("FCONST", 840.0, 1560.0, 1200.0, "cap on the spring force (lb)"),
    InputRange("WV", 80.0, 120.0, 100.0, "car's mass (slug)"),
)

#: Outcome key -> (label, unit).
OUTCOMES: dict[str, tuple[str, str]] = {
    "hits_car": ("P(first hit on the car)", "-"),
    "hits_roof": ("P(first hit on roof: top or windshield)", "-"),
    "hit_time_ms": ("time of the first hit", "ms"),
    "delta_v_crush_mph": ("delta-V, end of crush pulse", "mph"),
    "delta_v_contact_mph": ("delta-V, end of contact", "mph"),
    "max_decel_g": ("maximum deceleration", "g"),
    "oiv_m_s": ("occupant impact velocity", "m/s"),
    "roof_clearance_ft": ("least clearance above the roof", "ft"),
}
ROOF_SURFACES = ("WINDSHIELD", "TOP")

#: The outcomes that depend on what the model tests against the car (the first hit, its time,
#: the margin over the roof up to it): a model that tests only the points P, R and C does not
#: see the shaft or the arms strike the car, so it is blind to them (:func:`blind_outcomes`).
CAR_TEST_OUTCOMES = ("hits_car", "hits_roof", "hit_time_ms", "roof_clearance_ft")


def tests_whole_post(engine: str, keywords: dict) -> bool:
    """The model a study runs tests the shaft and the arms against the car, not only the
    points P, R and C: the core with shaft contact (given, or its preset's: physical)."""
    if engine != "core":
        return False
    given = keywords.get("shaft_contact")
    return bool(given) if given is not None else keywords.get("preset") == "physical"


def blind_outcomes(engine: str, keywords: dict) -> dict[str, str]:
    """Outcome -> why the model is blind to it (empty for a model that tests the whole
    post): the outcomes of :data:`CAR_TEST_OUTCOMES`, which no index is given for."""
    if tests_whole_post(engine, keywords):
        return {}
    why = ("blind: this model tests only the points P, R and C against the car, not the "
           "shaft and the arms (the core with --shaft-contact does)")
    return {k: why for k in CAR_TEST_OUTCOMES}


def unresolved(index: float | None, half_width: float | None) -> bool:
    """The index's 95 % interval, clipped to [0, 1], spans more than
    ``defaults.SENSITIVITY_UNRESOLVED_SPAN`` of it (or is not a number): not resolved at this N."""
    if index is None or half_width is None or not (math.isfinite(index)
                                                   and math.isfinite(half_width)):
        return True
    lo, hi = max(index - abs(half_width), 0.0), min(index + abs(half_width), 1.0)
    return max(hi - lo, 0.0) > defaults.SENSITIVITY_UNRESOLVED_SPAN


def _round6(x: float) -> float:
    """Six significant digits: a sampled value punched in an ``F10.5`` field reads back exactly."""
    return float(f"{float(x):.6g}")


def problem_for(inputs) -> dict:
    """SALib's problem dict for a sequence of :class:`InputRange`."""
    return {
        "num_vars": len(inputs),
        "names": [i.name for i in inputs],
        "bounds": [[i.low, i.high] for i in inputs],
    }


def sample(problem: dict, n: int, *, seed: int = 0) -> np.ndarray:
    """Saltelli's scheme on a scrambled Sobol' sequence, no second-order terms:
    ``n * (D + 2)`` rows. The first ``m * (D + 2)`` rows are the sample of size ``m`` for any
    power of two ``m <= n`` (same seed): convergence is read off one run."""
    from deck_emulator import signals

    if n < 2 or n & (n - 1):
        raise ValueError(f"N must be a power of two >= 2, got {n}")
    with signals.held():  # (a Ctrl-C inside scipy's compiled code: its traceback, not ours)
        from SALib.sample import sobol as sobol_sample

        return sobol_sample.sample(problem, n, calc_second_order=False, seed=seed)


def tasks_for(problem: dict, X: np.ndarray, base_task: dict, *, digits: bool = True) -> list[dict]:
    """One task per sample row: ``base_task`` plus ``inputs`` = {name: value} (values rounded
    to six significant digits when ``digits``)."""
    names = problem["names"]
    out = []
    for row in X:
        vals = {n: (_round6(v) if digits else float(v)) for n, v in zip(names, row)}
        out.append({**base_task, "inputs": vals})
    return out


# ==================================================================== the engine adapter

_DECKS: dict[str, object] = {}


def _base_deck(deck: str):
    if deck not in _DECKS:
        try:
            path = decks.path(deck)
        except KeyError:
            path = Path(deck)
        _DECKS[deck] = read_deck(path)
    return _DECKS[deck]


#: The registry's quantities the study reports (:data:`OUTCOMES` are read from them and the
#: hit): its engines compute these and what they need, and nothing else.
REPORTED = ("hit_time_s", "delta_v_crush_mph", "delta_v_contact_mph", "max_decel_g",
            "oiv_m_s", "roof_clearance_ft")


@functools.lru_cache(maxsize=None)
def _core_engine(preset: str, shaft_contact: bool | None, scene_friction: bool) -> CoreEngine:
    """The core engine of a study's scenes: the preset's, making only the arrays
    :data:`REPORTED` reads; with ``scene_friction`` the listing's friction switched off (the
    scene's used).  One object per setting, so that a batch's scenes run together."""
    core = CoreEngine(**core_keywords(preset, shaft_contact),
                      arrays=quantities.arrays_for(REPORTED))
    if not scene_friction:
        return core
    return dataclasses.replace(
        core, options=core.model_options().replace(listing_friction=False))


@functools.lru_cache(maxsize=64)
def _deck_with(deck: str, values: tuple):
    """The deck ``deck`` with ``values`` ((name, value) pairs), punched; kept for the next
    scenes of a batch (Saltelli's scheme repeats a row's deck values in the rows that change
    only a scene input)."""
    base = _base_deck(deck)
    return base.with_values(**dict(values)) if values else base


@functools.lru_cache(maxsize=64)
def _deck_scene(deck: str, values: tuple):
    """:func:`_deck_with`'s deck as the core's scene."""
    return CoreEngine().scene(_deck_with(deck, values))


def _prepare(values: dict, engine: str, preset: str, deck: str, errata=(),
             shaft_contact: bool | None = None):
    """What one scene runs: ``(engine, deck, name, scene)`` -- the engine object, the deck
    ``deck`` (a shipped deck's name or a path) with ``values`` (READ-list names -> values; on
    the core also :data:`SCENE_INPUTS`), its name, and the core's scene where the deck cannot
    hold the values (the base's friction), else None.  ``preset`` and ``shaft_contact`` (None:
    the preset's) are the core's."""

    deck_values = {k: v for k, v in values.items() if k in NAMES}
    scene_values = {k: v for k, v in values.items() if k in SCENE_INPUTS}
    unknown = set(values) - set(deck_values) - set(scene_values)
    if unknown:
        raise ValueError(f"unknown input(s) {sorted(unknown)}")
    if scene_values and engine != "core":
        raise ValueError(f"{sorted(scene_values)}: only the core has base friction inputs")
    d = _deck_with(deck, tuple(deck_values.items()))
    name = Path(deck).stem
    if engine == "emulator":
        return EmulatorEngine(errata=tuple(errata)), d, name, None
    core = _core_engine(preset, shaft_contact, bool(scene_values))
    scene = None
    if scene_values:  # the deck has no friction field: the base's friction on the scene
        scene = _deck_scene(deck, tuple(deck_values.items()))
        friction = BaseFriction(
            force_lb=scene_values.get("friction_lb", LISTING_FRICTION_LB),
            slip_window_ft=scene_values.get("friction_travel_ft", LISTING_FRICTION_TRAVEL_FT))
        scene = dataclasses.replace(
            scene, base=dataclasses.replace(scene.base, friction=friction))
    return core, d, name, scene


def study_row(outcome) -> dict:
    """An outcome -> the study's outcomes (:data:`OUTCOMES`, from the registry's values of
    :data:`REPORTED`) plus the hit surface, the engine's error text and its run time."""
    got = quantities.values(outcome, REPORTED)
    hit = outcome.hit
    where = hit.surface if hit is not None else None  # a Surface, or None
    surf = where.value.upper() if where is not None else ""
    t = got["hit_time_s"]
    return {
        "hit_surface": surf or "NONE",
        "hits_car": float(where.on_car) if surf else None,
        "hits_roof": float(surf in ROOF_SURFACES) if surf else None,
        "hit_time_ms": None if t is None else 1000 * t,
        **{k: got[k] for k in REPORTED[1:]},
        "engine_error": outcome.error or "",
        "engine_run_s": outcome.run_s,
    }


def _use_bases(bases: dict) -> None:
    """The decks ``bases`` (a task's ``deck`` -> the deck the command read) kept as this
    process's decks of those names, in place of any other kept before."""
    for name, deck in bases.items():
        known = _DECKS.get(name)
        if known is None or known.values != deck.values:
            _DECKS[name] = deck
            _deck_with.cache_clear()
            _deck_scene.cache_clear()


def scene_tasks(tasks: list[dict], bases: dict | None = None) -> list:
    """A worker's batch function (``run_scenes(many=True)``): each task's :func:`study_row`,
    the core's scenes run together; a task that cannot be prepared (an unknown input), or
    whose scene stopped at the wall bound, is its exception, in its place.  ``bases``: the
    decks the tasks name as the command read them (else each is read here, once a process)."""
    _use_bases(bases or {})
    prepared: list = []
    for task in tasks:
        try:
            prepared.append(_prepare(task["inputs"], task["engine"], task["preset"],
                                     task["deck"], task.get("errata", ()),
                                     task.get("shaft_contact")))
        except Exception as exc:  # noqa: BLE001 - that task's failure, stored as its row
            prepared.append(exc)
    done = iter(run_outcomes([(e, d if scene is None else scene, name) for e, d, name, scene
                              in (p for p in prepared if not isinstance(p, Exception))]))
    rows = [p if isinstance(p, Exception) else next(done) for p in prepared]
    return [r if isinstance(r, Exception) else study_row(r) for r in rows]


# ============================================================== a function with known indices


def ishigami_task(task: dict) -> dict:
    """The Ishigami function ``sin x1 + a sin^2 x2 + b x3^4 sin x1`` of ``task["inputs"]``
    (``x1, x2, x3`` in [-pi, pi]); ``a``, ``b`` from the task (default 7, 0.1). A stand-in for an
    engine with indices known in closed form (:func:`ishigami_indices`)."""
    x = task["inputs"]
    a, b = task.get("a", 7.0), task.get("b", 0.1)
    x1, x2, x3 = x["x1"], x["x2"], x["x3"]
    return {"y": math.sin(x1) + a * math.sin(x2) ** 2 + b * x3**4 * math.sin(x1)}


def ishigami_indices(a: float = 7.0, b: float = 0.1) -> dict:
    """Closed-form S1 and ST of the Ishigami function (Ishigami and Homma 1990; Sobol' and
    Levitan 1999): ``V = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2``."""
    pi = math.pi
    v1 = 0.5 * (1 + b * pi**4 / 5) ** 2
    v2 = a**2 / 8
    v13 = b**2 * pi**8 * (1 / 18 - 1 / 50)
    v = v1 + v2 + v13
    return {
        "S1": {"x1": v1 / v, "x2": v2 / v, "x3": 0.0},
        "ST": {"x1": (v1 + v13) / v, "x2": v2 / v, "x3": v13 / v},
    }


# =============================================================================== the study


@dataclass
class Study:
    """One sample run and analysed: the problem, the sample, the tasks, the store, each
    task's stored row (``rows``, in the tasks' order; None: not stored) and the indices
    (:func:`analyse`'s rows)."""

    problem: dict
    n: int
    X: np.ndarray
    tasks: list
    store: SceneStore
    outputs: list
    indices: list = field(default_factory=list)
    rows: list = field(default_factory=list)
    Y: dict = field(default_factory=dict)
    wall_s: float = 0.0
    ran: int = 0


def run_study(
    problem: dict,
    n: int,
    fn,
    *,
    base_task: dict,
    outputs,
    store_dir,
    seed: int = 0,
    jobs: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    digits: bool = True,
    desc: str = "scenes",
    progress: bool | None = None,
    chunk: int | None = None,
    many: bool = False,
    blind: dict[str, str] | None = None,
    files: dict[str, str] | None = None,
) -> Study:
    """Sample, run every scene with ``fn`` through :func:`run_scenes`, analyse. Indices are given
    for ``n`` and for ``n/2`` (the first half of the same sample).
    ``chunk``, ``many``: as :func:`run_scenes` (``many``: ``fn`` takes a batch of tasks, as
    :func:`scene_tasks`); ``blind``: the outputs the model cannot see, and why
    (:func:`blind_outcomes`); ``files``: as :func:`run_scenes`."""
    X = sample(problem, n, seed=seed)
    tasks = tasks_for(problem, X, base_task, digits=digits)
    store = SceneStore(store_dir)
    before = len(store.ids()) if resume else 0
    started = time.perf_counter()
    store = run_scenes(
        tasks, fn, store_dir=store_dir, jobs=jobs, scheduler=scheduler, resume=resume,
        desc=desc, progress=progress, chunk=chunk, many=many,
        core=base_task.get("engine") == "core", files=files,
    )
    wall = time.perf_counter() - started
    by_id = store.by_id()  # read once; each task's id hashed once
    rows = [by_id.get(scene_id(t)) for t in tasks]
    Xused = np.array([[t["inputs"][k] for k in problem["names"]] for t in tasks])
    Y = {}
    for key in outputs:
        vals = []
        for r in rows:
            v = None if r is None or r.get("status") != "ok" else r.get(key)
            vals.append(np.nan if v is None else float(v))
        Y[key] = np.array(vals)
    sizes = [n // 2, n] if n >= 4 else [n]
    study = Study(problem, n, Xused, tasks, store, list(outputs), rows=rows, Y=Y, wall_s=wall)
    study.ran = len(store.ids()) - before
    study.indices = analyse(problem, Y, sizes, seed=seed, blind=blind)
    return study


def all_failed(study: Study) -> str | None:
    """The first scene's error when no scene of ``study`` ran to its end (each failed, or its
    engine stopped early: the inputs' ranges left the model's domain, e.g. ``--input
    W=-1:-0.5``), else ``None``."""
    got = study.rows

    def why(r):  # None: the scene ran to its end
        if r is None:
            return "not run"
        if r.get("status") != "ok":
            return r.get("error") or "failed"
        return r.get("engine_error") or None  # the engine stopped early

    reasons = [why(r) for r in got]
    if not reasons or any(x is None for x in reasons):
        return None
    return str(reasons[0]).splitlines()[0][:200]


def bootstrap_seed(seed: int) -> int:
    """The seed of SALib's bootstrap of the confidence intervals, drawn from ``seed``: never 0,
    which SALib takes as "no seed" (``if seed:``), so that the intervals of seed 0 -- the
    default -- were different at every run."""
    return int(np.random.SeedSequence(seed).generate_state(1)[0]) | 1


def analyse(problem: dict, Y: dict, sizes, *, seed: int = 0,
            blind: dict[str, str] | None = None) -> list:
    """Sobol S1 and ST (with 95 % bootstrap half-widths) for every output in ``Y`` and
    every base-sample size in ``sizes`` (using the first ``size * (D + 2)`` scenes). An output
    the model is blind to (``blind``: output -> why, :func:`blind_outcomes`), with a missing
    value (NaN), or constant or nearly so (its most common value in at least
    ``defaults.SENSITIVITY_CONSTANT_FRACTION`` of the scenes) gets no indices; its row says
    why. An index whose interval covers most of [0, 1] (:func:`unresolved`) is named in the
    row's ``unresolved`` ("S1", "ST", "S1 ST"), printed as not resolved at this N."""
    from SALib.analyze import sobol

    D = problem["num_vars"]
    blind = blind or {}
    out = []
    for key, y in Y.items():
        for m in sizes:
            ym = np.asarray(y[: m * (D + 2)], dtype=float)
            missing = int(np.isnan(ym).sum())
            base = {"output": key, "N": m, "scenes": len(ym), "missing": missing,
                    "mean": float(np.nanmean(ym)) if len(ym) > missing else None,
                    "sd": float(np.nanstd(ym)) if len(ym) > missing else None}
            note = ""
            if key in blind:  # no number of it either: the model cannot see it
                note = f"{blind[key]}: no indices"
                base.update(mean=None, sd=None)
            elif missing:
                note = f"{missing} of {len(ym)} scenes without a value: no indices"
            else:
                values, counts = np.unique(ym, return_counts=True)
                top = int(counts.max())
                if top == len(ym):
                    note = f"constant ({ym[0]:g}) over the sample: no indices"
                elif top >= defaults.SENSITIVITY_CONSTANT_FRACTION * len(ym):
                    note = (f"constant ({values[int(np.argmax(counts))]:g}) in {top} of "
                            f"{len(ym)} scenes: no indices")
            if note:
                for name in problem["names"]:
                    out.append({**base, "input": name, "S1": None, "S1_conf": None,
                                "ST": None, "ST_conf": None, "note": note, "unresolved": ""})
                continue
            with np.errstate(all="ignore"):
                si = sobol.analyze(problem, ym, calc_second_order=False, conf_level=0.95,
                                   num_resamples=200, seed=bootstrap_seed(seed))
            for i, name in enumerate(problem["names"]):
                row = {**base, "input": name,
                       "S1": float(si["S1"][i]), "S1_conf": float(si["S1_conf"][i]),
                       "ST": float(si["ST"][i]), "ST_conf": float(si["ST_conf"][i]),
                       "note": ""}
                row["unresolved"] = " ".join(k for k in ("S1", "ST")
                                             if unresolved(row[k], row[f"{k}_conf"]))
                out.append(row)
    return out


# ================================================================================= writing

INDEX_COLUMNS = ("deck", "engine", "output", "input", "N", "scenes", "missing", "mean", "sd",
                 "S1", "S1_conf", "ST", "ST_conf", "note", "unresolved")
#: what a cell says of an index whose interval covers most of [0, 1] (:func:`unresolved`)
NOT_RESOLVED = "not resolved at this N"


def indices_csv(rows: list) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(INDEX_COLUMNS)
    for r in rows:
        w.writerow(["" if r.get(c) is None else (repr(r[c]) if isinstance(r[c], float) else r[c])
                    for c in INDEX_COLUMNS])
    return buf.getvalue()


def indices_markdown(rows: list, *, header: str = "") -> str:
    lines = [header.rstrip(), ""] if header else []
    groups: dict = {}
    for r in rows:
        groups.setdefault((r["deck"], r["engine"], r["N"]), []).append(r)
    for (deck, engine, n), rs in groups.items():
        lines += [f"### {deck}, {engine}, N = {n} ({rs[0]['scenes']} scenes)", ""]
        names = list(dict.fromkeys(r["input"] for r in rs))
        lines.append("| outcome (mean ± sd) | " + " | ".join(names) + " |")
        lines.append("|---|" + "---|" * len(names))
        for out in dict.fromkeys(r["output"] for r in rs):
            cells = []
            orow = [r for r in rs if r["output"] == out]
            for name in names:
                r = next(x for x in orow if x["input"] == name)
                gone = set((r.get("unresolved") or "").split())
                if r["S1"] is None:
                    cells.append("—")
                elif gone == {"S1", "ST"}:
                    cells.append(NOT_RESOLVED)
                else:
                    s1 = ("S1 " + NOT_RESOLVED if "S1" in gone
                          else f"{r['S1']:.2f}±{r['S1_conf']:.2f}")
                    st = ("ST " + NOT_RESOLVED if "ST" in gone
                          else f"**{r['ST']:.2f}**±{r['ST_conf']:.2f}")
                    cells.append(f"{s1} / {st}")
            label, unit = OUTCOMES.get(out, (out, ""))
            m = orow[0]
            stat = (f" ({fmt(m['mean'], '.3f', '—')} ± {fmt(m['sd'], '.3f', '—')} {unit})"
                    if m["mean"] is not None else "")
            note = f" — {orow[0]['note']}" if orow[0]["note"] else ""
            lines.append(f"| {label}{stat}{note} | " + " | ".join(cells) + " |")
        lines.append("")
    span = defaults.SENSITIVITY_UNRESOLVED_SPAN
    lines.append("Cells: S1 ± 95 % half-width / **ST** ± 95 % half-width (SALib bootstrap, 200 "
                 "resamples). — : no indices (see the note in the outcome's cell). "
                 f"{NOT_RESOLVED[0].upper() + NOT_RESOLVED[1:]}: the index's 95 % interval, "
                 f"clipped to [0, 1], spans more than {span:g} of it.")
    return "\n".join(lines) + "\n"


def _top_inputs(rows: list, n: int) -> list[str]:
    """The two inputs with the largest total index on the class outcomes (hits_car, hits_roof);
    if the class does not change, on the roof clearance; else summed over every outcome."""
    for outs in (("hits_car", "hits_roof"), ("roof_clearance_ft",), tuple(OUTCOMES)):
        score: dict = {}
        for r in rows:
            if (r["N"] == n and r["output"] in outs and r["ST"] is not None
                    and "ST" not in (r.get("unresolved") or "")):
                score[r["input"]] = score.get(r["input"], 0.0) + max(r["ST"], 0.0)
        if score and max(score.values()) > 0:
            return sorted(score, key=score.get, reverse=True)[:2]
    return []


def plot_indices(rows: list, path, *, n: int, title: str = "") -> None:
    """One panel an outcome that has indices (S1 and ST, bars to the 95 % half-width, the
    axis wide enough for every bar: they pass 1.0 and 0 at small N); the outcomes that have
    none (constant over the sample) are named under the title, not drawn as empty panels."""
    plt = agg_backend()
    outs = [o for o in OUTCOMES if any(r["output"] == o and r["N"] == n for r in rows)]
    outs += [o for o in dict.fromkeys(r["output"] for r in rows) if o not in outs]
    of = {o: [r for r in rows if r["output"] == o and r["N"] == n] for o in outs}
    drawn = [o for o in outs if of[o] and of[o][0]["S1"] is not None]
    none = [f"{OUTCOMES.get(o, (o,))[0]}: {of[o][0]['note'] if of[o] else 'no data'}"
            for o in outs if o not in drawn]
    nrow = max(1, math.ceil(len(drawn) / 4))
    ncol = max(1, math.ceil(len(drawn) / nrow))  # rows as full as they can be
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.6 * ncol, 3.0 * nrow + 0.3 * bool(none)),
                             squeeze=False)
    for ax, out in zip(axes.flat, drawn):
        rs = of[out]
        x = np.arange(len(rs))
        ax.set_title(OUTCOMES.get(out, (out, ""))[0], fontsize=8)
        ends = []
        for shift, key in ((-0.2, "S1"), (0.2, "ST")):
            v, e = np.array([r[key] for r in rs]), np.array([r[f"{key}_conf"] for r in rs])
            bars = ax.bar(x + shift, v, 0.4, yerr=e, capsize=2, label=key)
            for bar, r in zip(bars, rs):  # not resolved at this N: hatched, pale
                if key in (r.get("unresolved") or "").split():
                    bar.set(alpha=0.3, hatch="//")
            ends += [np.nanmin(v - e), np.nanmax(v + e)]
        ax.axhline(0, color="k", lw=0.5)
        ax.set_ylim(min(-0.1, ends[0], ends[2]) - 0.05, max(1.05, ends[1], ends[3]) + 0.05)
        ax.set_xticks(x, [r["input"] for r in rs], rotation=45, ha="right", fontsize=7)
        ax.tick_params(axis="y", labelsize=7)
    for ax in list(axes.flat)[len(drawn):]:
        ax.axis("off")
    if drawn:
        axes.flat[0].legend(fontsize=7)
    fig.suptitle(title + f" (N = {n}; bars: 95 % confidence; hatched: {NOT_RESOLVED})"
                 + "".join(f"\n{w}" for w in none), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_class_map(study: Study, path, *, inputs: list[str], title: str = "") -> None:
    """What the post hits first (marker) and its least clearance above the roof (colour), per
    scene, over the two given inputs (every scene of the sample; the others vary underneath)."""
    plt = agg_backend()
    names = study.problem["names"]
    ix = [names.index(k) for k in inputs]
    surf = []
    for r in study.rows:
        surf.append("FAILED" if r is None or r.get("status") != "ok" else r.get("hit_surface"))
    clear = []
    for r in study.rows:
        v = None if r is None else r.get("roof_clearance_ft")
        clear.append(np.nan if v is None else float(v))
    clear = np.array(clear)
    fig, ax = plt.subplots(figsize=(6.5, 4.8))
    markers = {"GROUND": "o", "HOOD": "s", "WINDSHIELD": "^", "TOP": "D", "TRUNK": "v",
               "NONE": "x", "FAILED": "x"}
    sc = None
    for s in sorted(set(surf)):
        k = [i for i, v in enumerate(surf) if v == s]
        sc = ax.scatter(study.X[k, ix[0]], study.X[k, ix[1]], s=14, c=clear[k], cmap="viridis",
                        vmin=np.nanmin(clear) if np.isfinite(clear).any() else 0,
                        vmax=np.nanmax(clear) if np.isfinite(clear).any() else 1,
                        marker=markers.get(s, "P"), label=f"{s} ({len(k)})")
    if sc is not None:
        fig.colorbar(sc, ax=ax, label="least clearance above the roof (ft)")
    ax.set_xlabel(deck_label(inputs[0]))  # a READ-list name with its listing unit
    ax.set_ylabel(deck_label(inputs[1]))
    ax.legend(fontsize=7, title="post hits first", title_fontsize=7)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_outputs(studies: list, out: Path, *, header: str = "") -> list[Path]:
    """``sensitivity.csv``, ``sensitivity.md`` (every study) and, per study, the picture of the
    indices and the class map. Returns the files written."""

    rows = []
    written = []
    with OutputSet(directory=out) as files:  # the tables and pictures appear together
        for label, engine, st in studies:
            rows += [{**r, "deck": label, "engine": engine} for r in st.indices]
            pic = f"sensitivity_{label}.png"
            plot_indices(st.indices, files.path(pic), n=st.n,
                         title=f"Sobol indices, {label}, {engine}")
            written.append(out / pic)
            top = _top_inputs(st.indices, st.n)
            if len(top) == 2:
                cm = f"hit_map_{label}.png"
                plot_class_map(st, files.path(cm), inputs=top,
                               title=f"{label}, {engine}: first hit over {top[0]} and {top[1]}")
                written.append(out / cm)
        files.write("sensitivity.csv", indices_csv(rows))
        files.write("sensitivity.md", indices_markdown(rows, header=header))
    return [out / "sensitivity.csv", out / "sensitivity.md", *written]


# ===================================================================================== CLI


def parse_input(text: str) -> InputRange:
    """``NAME=LO:HI`` -> :class:`InputRange`."""
    try:
        name, rng = text.split("=", 1)
        lo, hi = (float(x) for x in rng.split(":"))
    except ValueError:
        raise ValueError(f"--input {text!r}: use NAME=LO:HI") from None
    name = name.strip()
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError(f"--input {text!r}: LO and HI must be finite numbers")
    if not lo < hi:
        raise ValueError(f"--input {text!r}: LO must be below HI")

    if name not in NAMES and name not in SCENE_INPUTS:
        raise ValueError(
            f"--input {name!r}: not a deck (READ-list) name nor one of {sorted(SCENE_INPUTS)}"
        )
    if name in NAMES and DECK_UNITS.get(name) == "rad" and max(abs(lo), abs(hi)) > 2 * math.pi:
        raise ValueError(f"--input {text!r}: {name} is in radians (the listing's unit), and "
                         f"{max(abs(lo), abs(hi)):g} rad is more than a turn; degrees? "
                         f"{math.radians(lo):.5f}:{math.radians(hi):.5f} rad is {lo:g}:{hi:g} deg")
    return InputRange(name, lo, hi, None, SCENE_INPUTS.get(name, "deck input"))


#: Largest base sample N (2**16: 524,288 scenes with the six default inputs).
MAX_N = defaults.MAX_SENSITIVITY_N


def check_options(n: int | None, seed: int) -> None:
    """The study's N and seed, before any work: ``ValueError`` (one line) unless N is a power
    of two in [2, :data:`MAX_N`] (``None``: the default) and the seed is an integer >= 0 (the
    Sobol' sequence's scrambling and the bootstrap take no negative seed)."""
    if n is not None:
        if isinstance(n, bool) or not isinstance(n, int) or n < 2 or n & (n - 1):
            raise ValueError(f"-N {n}: N must be a power of two >= 2 (2, 4, 8 ... 256)")
        if n > MAX_N:
            raise ValueError(f"-N {n}: at most {MAX_N} (N (D + 2) scenes are run)")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"--seed {seed}: the seed must be an integer >= 0")


def choose_inputs(engine: str, extra: list, *, defaults: bool = True):
    """The inputs of a study and the notes on what was left out."""
    chosen = {i.name: i for i in (DEFAULT_INPUTS if defaults else ())}
    for e in extra:
        chosen[e.name] = e
    notes = []
    if engine != "core":
        dropped = [k for k in chosen if k in SCENE_INPUTS]
        named = [e.name for e in extra if e.name in SCENE_INPUTS]
        if named:
            raise ValueError(f"{named}: the emulator's deck has no base-friction field "
                             "(friction is a constant of the listing); use --engine core")
        for k in dropped:
            chosen.pop(k)
        if dropped:
            notes.append(f"{', '.join(dropped)} left out: the emulator's deck has no field for "
                         "them (a constant of the listing); the core has them")
    return list(chosen.values()), notes


def blind_line(blind: dict[str, str]) -> str:
    """The study's first line where its model is blind to some outcomes ('' where not)."""
    if not blind:
        return ""
    names = ", ".join(OUTCOMES[k][0] for k in blind)
    return (f"BLIND to {names}: no indices for them, since this model tests only the points "
            "P, R and C against the car, not the shaft and the arms; the core with "
            "--shaft-contact (the study's default) tests the whole post")


def run_command(*, out, decks=(), engine: str = "core", engine_keywords: dict | None = None,
                inputs_text=(), only: bool = False, n: int | None = None, quick: bool = False,
                seed: int = 0, jobs=None, scheduler=None, resume: bool = False,
                quiet: bool = False, command_line: str = "", say=print,
                read: dict | None = None) -> list:
    """``deck-emulator sensitivity``: the study of ``decks`` (default steel40) on ``engine``
    (``engine_keywords``: the core's preset and shaft contact), the files it wrote (``say``:
    the lines to report as it goes; ``command_line``: the command as typed, for the page;
    ``read``: a deck of ``decks`` -> ``(the deck, the SHA-256 of its bytes)`` as the caller
    read it, else it is read here)."""

    try:
        check_options(n, seed)
        extra = [parse_input(t) for t in inputs_text]
        inputs, notes = choose_inputs(engine, extra, defaults=not only)
        check_output_dir(out)  # before any work: a missing parent is refused, not made
    except (ValueError, OutputError) as exc:  # the CLI prints it as every command does
        raise UsageError(str(exc)) from None
    if not inputs:
        raise UsageError("no inputs: give --input, or leave out --only")
    n = n if n is not None else (16 if quick else 256)
    deck_names = list(decks) or ["steel40"]
    problem = problem_for(inputs)
    keywords = dict(engine_keywords or {})
    blind = blind_outcomes(engine, keywords)
    out = Path(out)
    studies = []
    first = blind_line(blind)
    if first:  # the study's first line: what it cannot see
        say(first)
    for note in notes:
        say(note)
    started = time.perf_counter()
    read = dict(read or {})
    for deck in deck_names:
        if deck in read:
            _use_bases({deck: read[deck][0]})
        base = _base_deck(deck)  # a bad deck fails here, before any work
        # the store's resume check: the file's SHA-256 from the caller's read (a shipped
        # deck's name names no file); without it, the store reads the file
        files = ({deck: read[deck][1]} if os.path.isfile(deck) else {}) if deck in read else None
        label = Path(deck).stem
        st = run_study(
            problem, n, functools.partial(scene_tasks, bases={deck: base}), many=True,
            files=files,
            base_task={"deck": deck, "engine": engine, **keywords},
            outputs=list(OUTCOMES), store_dir=out / SCENE_STORE / label, seed=seed,
            jobs=jobs, scheduler=scheduler, resume=resume, desc=label,
            progress=False if quiet else None, blind=blind,
        )
        studies.append((label, engine, st))
        say(f"{label}: {len(st.tasks)} scenes, {st.ran} run now, {st.wall_s:.1f} s")
        stopped = [r for r in st.rows if r is not None and r.get("status") == "stopped"]
        if stopped:  # a bound of the machine, not of the model: --resume runs them again
            raise RunFailed(f"{label}: {len(stopped)} of {len(st.tasks)} scenes stopped "
                            f"({stopped[0]['error']}); the scenes that ended are stored, "
                            "--resume runs the rest; no table written")
        failed = all_failed(st)
        if failed is not None:  # no index can come of it: a run that could not end, exit 3
            raise RunFailed(f"{label}: every scene failed ({failed}); no table written")
    wall = time.perf_counter() - started
    header = page(
        "sensitivity_header.md", blind=f" — {first}" if first else "",
        command=f"Command: `{command_line}`" if command_line else "", engine=engine,
        preset=keywords.get("preset", "legacy"),
        shaft={None: "", True: ", shaft contact on", False: ", shaft contact off"}[
            keywords.get("shaft_contact")],
        n=n, scenes=n * (len(inputs) + 2), seed=seed, wall=f"{wall:.0f}",
        inputs="; ".join(f"{i.name} {i.low:g}–{i.high:g}" for i in inputs),
        notes="".join(f"\n\nNote: {x}." for x in notes))
    files = write_outputs(studies, out, header=header)
    say("wrote " + ", ".join(str(f) for f in files))
    return files
