"""The report's Chapter VI parameter study, regenerated: ``deck-emulator sweep``.

Every (speed, angle) of a grid is one scene: the base deck with VVB and ALPHA changed. Each
scene is run by one engine, in parallel over worker processes, and written as

* ``sweep.csv`` -- one row per scene: every output (events, hit, the report's quantities, the
  occupant-risk numbers of :mod:`deck_emulator.engine.safety`, the post's margin above the car) and,
  where the report has the case, the report's value and our difference;
* ``sweep.md`` -- laid out like Tables 11 and 12 of the report: one table per speed, a column
  per approach angle, each cell ``ours (report, diff)``.

Each scene runs through the engine layer (:mod:`deck_emulator.engine`), so the 1967 program and
the modern core are treated alike.

Rules (stated once, here)
-------------------------
* Speed (mph) -> ``VVB = -(mph * 88/60)`` ft/s cut to two decimals (towards zero), as the
  report's deck punched 40 mph (``-58.66`` for 58.667) and as ``decks/steel20.dat`` has 20 mph
  (``-29.33``): so 20 and 40 mph give exactly the decks in ``decks/``. ``--vvb-decimals``
  changes the number of decimals (up to 5, what F10.5 shows).
* Angle (deg) -> ``ALPHA`` in radians rounded to five decimals (F10.5): 15 deg -> 0.26180.
* Emulator: arithmetic ``double``, errata as the user names them (``--erratum``; the one
  policy of :mod:`deck_emulator.engine.errata`): as printed, ED's root search walks away from
  its root on the angled decks and those scenes stop; ``--erratum ed-direction`` lets them run.
  The ``errata`` column says what was applied, ``error`` why a scene stopped.
* Core: :func:`deck_emulator.core.simulate` with the ``legacy`` preset (the listing's quirks,
  the one comparable with the report) unless ``--preset physical``.
* The ΔV compared with the report's is the speed lost by the end of the crush pulse
  (``extract``'s ``crush_pulse_end``: where the spring force is first cut to FCONST; for the
  core its "force cap engaged" event): the reading that fits the report's steel columns
  (docs/report_full.md shows which reading fits which post). The report's maximum deceleration is the largest
  *printed* FSA / (WV*G) (``extract``); the core's is its continuous maximum. The safety
  columns use the whole contact pulse of either engine.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import json
import math
from collections.abc import Sequence
from decimal import ROUND_DOWN, ROUND_HALF_EVEN, Decimal

from deck_emulator import decks
from deck_emulator.engine import Outcome, engine_for, quantities, safety
from deck_emulator.engine.ratings import RATED, ratings
from deck_emulator.engine.sources import Deck, parse_deck, read_bytes, read_deck
from deck_emulator.studies.common import run_outcomes
from deck_emulator.studies.csvfile import csv_text
from deck_emulator.studies.pages import snippet
from deck_emulator.studies.distributed import run_scenes, temporary_store
from deck_emulator.studies.store import SceneStore, Stopped, StudyChanged, scene_id
from deck_emulator.studies.report_tables import REPORT, report_comment
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.events import Surface
from deck_emulator.vocabulary.scene import Scene
from deck_emulator.vocabulary.units import FT_PER_MILE, S_PER_HOUR


#: --post -> base deck (the report's steel post, 40 mph, 0 deg).
POSTS = {"steel": decks.path(decks.REPORT_DECK)}
#: Report fields: (key, row label as the report prints it, decimals).
REPORT_ROWS = (
    ("delta_v_crush_mph", "DECREASE IN VEHICLE VELOCITY (MPH)", 2),
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


# ============================================================================ the scenes


def scene_name(speed_mph: float, angle_deg: float, post: str = "steel") -> str:
    """``steel40``, ``steel40_a15`` -- the names of decks/ and of report_tables for the report's
    cases; another base deck's scenes are named after it: ``car820_v40``, ``car820_v40_a15``."""
    s = f"{post}{speed_mph:g}" if post in POSTS else f"{post}_v{speed_mph:g}"
    return s if angle_deg == 0 else f"{s}_a{angle_deg:g}"


def _report_key(job: dict) -> tuple:
    """What decides a job's scene deck and name."""
    return job["base"], job["post"], job["speed"], job["angle"], job["vvb_decimals"]


def _reports(jobs: list[dict], bases: dict) -> dict[tuple, str]:
    """The report's cases among the jobs' scenes (their names in REPORT), by :func:`_report_key`:
    the report's post by its scene's name; another base deck only where its scene is, value
    for value, one of the shipped report decks.  ``bases``: the decks read so far, by path
    (each shipped deck is read at most once, and added)."""
    out = {}
    for job in jobs:
        mine = job["post"] in POSTS
        name = scene_name(job["speed"], job["angle"], job["post"] if mine else "steel")
        if name not in REPORT or not (mine or name in decks.names()):
            continue
        if name in decks.names():
            deck, ref = _scene_of(job, bases)[0], str(decks.path(name))
            if ref not in bases:
                bases[ref] = read_deck(ref)
            if any(bases[ref].values[k] != deck.values[k] for k in bases[ref].values):
                continue
        out[_report_key(job)] = name
    return out


def vvb_for(speed_mph: float, decimals: int = defaults.VVB_DECIMALS) -> float:
    """-(mph * 88/60) ft/s cut (towards zero) to ``decimals`` decimals (module docstring)."""
    exact = Decimal(repr(float(speed_mph))) * FT_PER_MILE / S_PER_HOUR
    q = exact.quantize(Decimal(1).scaleb(-decimals), rounding=ROUND_DOWN)
    return -float(q)


def alpha_for(angle_deg: float) -> float:
    """Degrees -> radians rounded to five decimals (F10.5)."""
    r = Decimal(repr(math.radians(angle_deg))).quantize(
        Decimal("0.00001"), rounding=ROUND_HALF_EVEN
    )
    return float(r)


def car_at(speed_mph: float, alpha_deg: float) -> tuple[str, dict]:
    """The car a described post meets at any speed and angle, as ``(template, car)``: the
    report's deck of that speed and angle where one is shipped (``steel20``,
    ``steel40_a15`` ...; ``car`` empty), else steel40's car with VVB and ALPHA set by the
    sweep's rules (``car``: the keywords ``speed_ft_s`` and ``alpha_rad`` of
    :func:`deck_emulator.engine.assemblies.to_scene` and ``to_deck_values``)."""

    template = scene_name(speed_mph, alpha_deg)
    if template in decks.names():
        return template, {}
    return "steel40", dict(speed_ft_s=abs(vvb_for(speed_mph)), alpha_rad=alpha_for(alpha_deg))


def read_base(path) -> tuple[Deck, str]:
    """A base deck read once: the deck and the SHA-256 of its file's bytes (what a resume of
    its store checks)."""
    shown, data = read_bytes(path)
    return parse_deck(data, path=shown), hashlib.sha256(data).hexdigest()


def scene_deck(base: Deck, speed_mph: float, angle_deg: float,
               vvb_decimals: int = defaults.VVB_DECIMALS) -> Deck:
    return base.with_values(VVB=vvb_for(speed_mph, vvb_decimals), ALPHA=alpha_for(angle_deg))


def parse_grid(text: str) -> list[float]:
    """'20,40' or '0:45:5' (start:stop:step, stop included) or a mix: '10,20:60:10'; every
    value finite, at most ``defaults.MAX_SWEEP_GRID`` of them (a range counted before it is
    expanded, so that a tiny step is refused instead of filling the memory)."""
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
            if not all(map(math.isfinite, (a, b, s))):
                raise ValueError(f"range {part!r}: not finite")
            if s <= 0:
                raise ValueError(f"range {part!r}: step must be positive")
            if (b - a) / s + 1 > defaults.MAX_SWEEP_GRID:
                raise ValueError(f"range {part!r}: {math.floor((b - a) / s) + 1:.3g} values, "
                                 f"more than {defaults.MAX_SWEEP_GRID}")
            k = 0
            while a + k * s <= b + 1e-9 * max(1.0, abs(b)):
                out.append(round(a + k * s, 10))
                k += 1
        else:
            x = float(part)
            if not math.isfinite(x):
                raise ValueError(f"{part!r}: not finite")
            out.append(x)
        if len(out) > defaults.MAX_SWEEP_GRID:
            raise ValueError(f"more than {defaults.MAX_SWEEP_GRID} values")
    if not out:
        raise ValueError("empty list")
    return sorted(set(out))


# ========================================================================= one scene's row


#: The registry's quantities a sweep row carries, under their registry names and units.
ROW_QUANTITIES = (
    "hit_time_s", "first_spring_lost_s", "vehicle_contact_lost_s", "delta_v_crush_mph",
    "delta_v_contact_mph", "max_decel_g", "max_decel_every_step_g", "max_decel_10ms_g",
    "oiv_m_s", "occupant_strike_time_s", "ora_g", "body_clearance_ft", "roof_clearance_ft",
)


#: The sampled arrays a row reads: its quantities' (the clearances' points also give the
#: ratings their compartment and the terminal C); not the contact force, a picture's.
ROW_ARRAYS = quantities.arrays_for(ROW_QUANTITIES)


def result_row(res: Outcome, speed_mph: float, angle_deg: float, report=None) -> dict:
    """Everything one scene gives, as a flat dict of plain values (a CSV row): the scene, the
    run, the registry's quantities (:data:`ROW_QUANTITIES`, names and units of
    :mod:`deck_emulator.engine.quantities`), where and when the clearances were least, the
    ratings (none for a run that stopped: its numbers are of a run cut short), and the
    report's values beside ours."""
    car = res.scene.vehicle if res.scene is not None else None
    hit = res.hit
    row: dict = {
        "scene": res.name,
        "speed_mph": speed_mph,
        "angle_deg": angle_deg,
        "VVB_ft_s": car.initial_velocity_ft_s if car is not None else None,
        "ALPHA_rad": car.approach_angle_rad if car is not None else None,
        "engine": res.engine,
        "errata": "+".join(res.errata) or "none",
        "settings": res.settings,
        "error": res.error or "",
        "hit": hit.short() if hit else "",
        "hit_point": (hit.point or "") if hit else "",
        "hit_surface": hit.surface.value if hit and hit.surface else "",
    }
    row.update(quantities.values(res, ROW_QUANTITIES))
    for p in ("P", "R", "Q", "C"):
        xyz = res.terminal.get(p)
        for i, ax in enumerate("XYZ"):
            row[f"{ax}{p}L"] = None if xyz is None or xyz[i] is None else float(xyz[i])
    ms = lambda s: None if s is None else 1000 * s  # noqa: E731 - the report's rows are in ms
    on_car = hit is not None and hit.surface is not None and hit.surface.on_car
    row["time_to_hit_car_ms"] = ms(row["hit_time_s"]) if on_car else None
    row["time_to_hit_ground_ms"] = (ms(row["hit_time_s"]) if hit and hit.surface is Surface.GROUND
                                    else None)
    row["comment"] = report_comment(hit) if hit else ("NO HIT" + (f" ({res.error})" if res.error else ""))
    m = quantities.pulse(res)  # the readings the registry's values came from
    row["occupant_strike_after_contact"] = m.strike_after_contact if m is not None else None
    # the verdicts (none for a run that stopped): the engine layer's one rating of a run
    rated = ratings(res) or {}
    comp = rated.get("occupant_compartment") or {}
    row["compartment_verdict"] = comp.get("verdict") or ""
    row["compartment_part"] = comp.get("part") or ""
    row["compartment_surface"] = comp.get("surface") or ""
    row["compartment_in_compartment"] = {True: "yes", False: "no"}.get(
        comp.get("in_compartment"), "")
    row["compartment_depth_ft"] = comp.get("depth_ft")
    row["compartment_deepest_surface"] = comp.get("deepest_surface") or ""
    row["compartment_time_s"] = comp.get("time_s")
    for key, c in safety.CRITERIA.items():  # nchrp350_oiv_rating, mash_oiv_rating ...
        if c.quantity in RATED:
            row[f"{key}_rating"] = rated.get(c.quantity, {}).get("verdicts", {}).get(key, "")
    c = quantities.clearance(res)
    row["body_clearance_surface"] = (c.body_surface or "") if c else ""
    row["body_clearance_time_s"] = c.body_time_s if c else None
    row["body_clearance_where"] = (c.body_where or "") if c else ""
    row["roof_clearance_time_s"] = c.roof_time_s if c else None
    row["roof_clearance_where"] = (c.roof_where or "") if c else ""
    row["line_meets_car_time_s"] = c.touch_time_s if c else None
    row["line_meets_car_surface"] = (c.touch_surface or "") if c else ""
    row["stopped_hint"] = (res.hint or "") if res.error else ""  # what would let it run
    row["run_s"] = res.run_s
    for key, _, _ in REPORT_ROWS:
        rep = None if report is None else report.get(key)
        ours = row.get(key)
        row[f"report_{key}"] = rep
        row[f"diff_{key}"] = (ours - rep) if (ours is not None and rep is not None) else None
    row["report_comment"] = "" if report is None else (report.get("comment") or "")
    return row


#: The row's own hit times in the report's ms, for the Markdown tables only: the CSV has the
#: hit once, as ``hit_time_s`` and ``hit_surface`` (the report's values and our difference
#: keep the report's ms, named so: ``report_time_to_hit_ground_ms`` ...).
_MD_ONLY = ("time_to_hit_car_ms", "time_to_hit_ground_ms")

#: The keys of :func:`result_row`, in order.
ROW_KEYS: tuple[str, ...] = tuple(result_row(Outcome("emulator", ""), 0.0, 0.0))
#: The CSV's columns, in order.
COLUMNS: tuple[str, ...] = tuple(k for k in ROW_KEYS if k not in _MD_ONLY)
#: A row's keys are the scene store's columns under this prefix: the store's own columns
#: (its ``error`` and ``run_s``) never mix with the row's.
ROW_PREFIX = "row."


def _scene_of(job: dict, bases: dict) -> tuple[Deck, str]:
    """A job's deck and name (``bases``: the base decks read so far, by path: a batch reads
    its base deck once)."""
    if job["base"] not in bases:
        bases[job["base"]] = read_deck(job["base"])
    deck = scene_deck(bases[job["base"]], job["speed"], job["angle"], job["vvb_decimals"])
    return deck, scene_name(job["speed"], job["angle"], job["post"])


def _scene_rows(jobs: list[dict], bases: dict | None = None,
                reports: dict | None = None) -> list[dict]:
    """Worker: a batch of scenes -> their rows (plain data, picklable), in order, run by
    :func:`~.common.run_outcomes` (a core run past its wall bound: :class:`Stopped` in its
    row's place, run again on resume).  A scene the engine cannot run is a row saying why
    (the outcome's error); anything else raised here is a defect: it ends the batch, and the
    runner runs each of its scenes again alone and stores the one that fails as failed.
    ``bases``: the base decks the command has read, by path (a deck not in it is read here)."""
    bases = dict(bases or {})
    reports = _reports(jobs, bases) if reports is None else reports
    engines: dict[str, object] = {}  # one engine object per setting: its scenes run together
    items = []
    for job in jobs:
        key = json.dumps([job["engine"], job["options"]], sort_keys=True)
        if key not in engines:
            engine = engine_for(job["engine"], **job["options"])
            engines[key] = (dataclasses.replace(engine, arrays=ROW_ARRAYS)  # what a row reads
                            if job["engine"] == "core" else engine)
        items.append((engines[key], *_scene_of(job, bases)))
    return [res if isinstance(res, Stopped) else  # the store's status for it, not a row
            result_row(res, job["speed"], job["angle"],
                       REPORT.get(reports.get(_report_key(job))))
            for job, res in zip(jobs, run_outcomes(items))]


def _stored_scene_jobs(jobs: list[dict], bases: dict | None = None,
                       reports: dict | None = None) -> list[dict]:
    """Worker: a batch of scenes -> one row each, its keys as the store's columns
    (:data:`ROW_PREFIX`)."""
    return [row if isinstance(row, Exception) else {ROW_PREFIX + k: v for k, v in row.items()}
            for row in _scene_rows(jobs, bases, reports)]


def sweep(
    speeds: Sequence[float],
    angles: Sequence[float],
    *,
    engine: str = "emulator",
    options: dict | None = None,
    post: str = "steel",
    base=None,
    base_deck: Deck | None = None,
    base_sha256: str | None = None,
    jobs: int | None = None,
    vvb_decimals: int = defaults.VVB_DECIMALS,
    quiet: bool = False,
    store_dir=None,
    scheduler: str | None = None,
    resume: bool = False,
) -> list[dict]:
    """Run every (speed, angle) on ``engine`` (``engine_for(engine, **options)``); rows
    sorted by speed, then angle. ``base``: another base deck than ``post``'s; ``post`` then
    names its scenes (the deck's name: ``car820`` gives ``car820_v40_a15``); ``base_deck``,
    ``base_sha256``: that file as the caller read it (:func:`read_base`; else it is read here).

    The scenes run on worker processes (:func:`deck_emulator.studies.distributed.run_scenes`:
    the embedded runner's ``jobs`` workers, or the Dask cluster at ``scheduler``), a batch of
    scenes a task (the core's through ``CoreEngine.run_batch``), and are stored as they
    finish in ``store_dir`` (a temporary folder if none); ``resume`` runs only the scenes not stored."""

    base = str(base if base is not None else POSTS[post])
    if base_deck is None:
        base_deck, base_sha256 = read_base(base)
    # the base deck read once, handed to the workers with each batch with the report's values
    bases = {base: base_deck}
    todo = [dict(base=base, speed=float(s), angle=float(a), engine=engine,
                 options=dict(options or {}), post=post, vvb_decimals=vvb_decimals)
            for s in speeds for a in angles]
    reports = _reports(todo, bases)
    if resume and store_dir is not None:  # an ended scene must have its row's columns
        kept = SceneStore(store_dir).columns(("status", ROW_PREFIX + "scene"))
        if any(s == "ok" and name is None for s, name in zip(*kept.values())):
            raise StudyChanged(f"--resume: {store_dir} holds rows stored by an earlier sweep "
                               "(one JSON text a row): run without --resume to start again, "
                               "or use a new folder")
    # the caller's store (the command's --out) where it gives one; a temporary one only if not
    with (contextlib.nullcontext(store_dir) if store_dir is not None
          else temporary_store("sweep-")) as where:
        store = run_scenes(todo, functools.partial(_stored_scene_jobs, bases={base: base_deck},
                                                   reports=reports),
                           store_dir=where, jobs=jobs,
                           files=None if base_sha256 is None else {base: base_sha256},
                           scheduler=scheduler, resume=resume, desc=f"sweep ({engine})",
                           progress=False if quiet else None, many=True,
                           core=engine == "core")
        got = store.columns(("scene_id", "status", "error", *(ROW_PREFIX + k for k in ROW_KEYS)))
    last = {sid: i for i, sid in enumerate(got.pop("scene_id"))}  # a scene's last row
    status, error = got.pop("status"), got.pop("error")
    values = list(got.values())
    rows = []
    for job in todo:
        i = last.get(scene_id(job))
        if i is not None and status[i] == "ok":
            rows.append(dict(zip(ROW_KEYS, [column[i] for column in values])))
        else:  # the worker died with it (WorkerDied, or Dask's KilledWorker): a row saying so
            deck, name = _scene_of(job, bases)
            out = Outcome(engine, name, Scene.from_deck(deck, name=name, checked=False),
                          error=(error[i] if i is not None else None) or "not run")
            rows.append(result_row(out, job["speed"], job["angle"]))
    rows.sort(key=lambda r: (r["speed_mph"], r["angle_deg"]))
    return rows


# ============================================================================== writing


def write_csv(rows: list[dict]) -> str:
    """The sweep's CSV: one row per scene, the columns of :data:`COLUMNS`."""
    return csv_text(rows, list(COLUMNS))


def _num(x, nd=2, signed=False):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    return f"{x:+.{nd}f}" if signed else f"{x:.{nd}f}"


def _ms(seconds, nd=1):
    """Seconds shown in ms (the tables' unit for times)."""
    return _num(None if seconds is None else 1000 * seconds, nd)


def _cell(row, key, nd):
    ours = row.get(key)
    rep = row.get(f"report_{key}")
    if rep is None:
        return _num(ours, nd)
    if ours is None:
        return f"— ({_num(rep, nd)})"
    return f"{_num(ours, nd)} ({_num(rep, nd)}, {_num(ours - rep, nd, True)})"


def render_markdown(rows: list[dict], *, command: str = "", engine: str = "emulator",
                    base: str | None = None) -> str:
    """Tables laid out like the report's Tables 11 and 12: one table per speed. ``base``: the
    base deck as the user named it (None: the report's steel post)."""
    limits = {q: "; ".join(f"{safety.STANDARDS[c.standard].name}: {c.label()}"
                           for c in safety.criteria_of(q).values())
              for q in ("occupant_compartment", *RATED)}

    def rated(r, quantity):  # "NCHRP 350: preferred; MASH: acceptable" from the row's columns
        return "; ".join(f"{safety.STANDARDS[safety.CRITERIA[k].standard].name}: "
                         f"{r[f'{k}_rating']}"
                         for k in safety.criteria_of(quantity) if r.get(f"{k}_rating"))

    lines = ["# Parameter study (the report's Chapter VI), regenerated", ""]
    if command:
        lines += [f"Command: `{command}`", ""]
    eng = rows[0]["settings"] if rows and engine == "core" else ""
    lines += [*snippet("sweep.md", "header", engine=engine, settings=f" ({eng})" if eng else "",
                       base=snippet("sweep.md", "steel_post") if base is None else f"`{base}`",
                       decel=snippet("sweep.md", f"decel_{engine}"), oiv=limits["oiv_m_s"],
                       ora=limits["ora_g"], compartment=limits["occupant_compartment"]
                       ).split("\n"), ""]
    speeds = sorted({r["speed_mph"] for r in rows})
    for s in speeds:
        rs = [r for r in rows if r["speed_mph"] == s]
        rs.sort(key=lambda r: r["angle_deg"])
        lines.append(f"## {s:g} mph (VVB = {rs[0]['VVB_ft_s']:g} ft/s)")
        lines.append("")
        head = ["APPROACH ANGLE α (DEG)"] + [f"{r['angle_deg']:g}" for r in rs]
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
        add("lost contact with the car (ms)", [_ms(r["vehicle_contact_lost_s"], 1) for r in rs])
        add("ΔV to the end of contact (mph)", [_num(r["delta_v_contact_mph"]) for r in rs])
        add(
            "max deceleration, every step (g); max 10 ms average (g)",
            [f"{_num(r['max_decel_every_step_g'])}; {_num(r['max_decel_10ms_g'])}" for r in rs],
        )
        add(
            "occupant compartment",
            [
                r["compartment_verdict"]
                + (
                    f": {r['compartment_part']} strikes the {r['compartment_surface']} at "
                    f"{_ms(r['compartment_time_s'], 0)} ms"
                    + ("" if r["compartment_in_compartment"] == "yes" else
                       " (outside the occupant compartment)")
                    + (f"; its path {_num(r['compartment_depth_ft'])} ft inside the car at the "
                       f"most, over the {r['compartment_deepest_surface']}"
                       if r["compartment_deepest_surface"] else "")
                    if r["compartment_part"]
                    else ""
                )
                for r in rs
            ],
        )
        add(
            "OIV m/s",
            [f"{_num(r['oiv_m_s'])} {rated(r, 'oiv_m_s')}".strip() for r in rs],
        )
        add(
            "occupant strikes the interior (ms)",
            [
                _ms(r["occupant_strike_time_s"], 0)
                + (" (after contact)" if r["occupant_strike_after_contact"] else "")
                for r in rs
            ],
        )
        add(
            "ORA g",
            [f"{_num(r['ora_g'])} {rated(r, 'ora_g')}".strip() for r in rs],
        )
        add(
            "least clearance over the car (ft)",
            [
                (
                    f"{_num(r['body_clearance_ft'])} {r['body_clearance_surface']} at "
                    f"{_ms(r['body_clearance_time_s'], 0)} ms"
                )
                if r["body_clearance_ft"] is not None
                else "—"
                for r in rs
            ],
        )
        add(
            "least clearance over roof/windshield (ft)",
            [
                (f"{_num(r['roof_clearance_ft'])} at {_ms(r['roof_clearance_time_s'], 0)} ms")
                if r["roof_clearance_ft"] is not None
                else "—"
                for r in rs
            ],
        )
        add(
            "post's line first inside the car outline (ms)²",
            [
                (
                    f"{_ms(r['line_meets_car_time_s'], 1)} {r['line_meets_car_surface']}"
                    if r["line_meets_car_time_s"] is not None
                    else "never"
                )
                for r in rs
            ],
        )
        if engine == "emulator":
            add("errata", [r["errata"] + ("" if r["errata"] == "none" else "¹") for r in rs])
        else:
            add("engine settings", [r["settings"] for r in rs])
        if any(r["error"] for r in rs):
            add("run stopped", [r["error"] or "" for r in rs])
        lines.append("")
    if engine == "emulator" and any(r["errata"] != "none" for r in rows):
        used = sorted({r["errata"] for r in rows if r["errata"] != "none"})
        lines += [snippet("sweep.md", "errata", used=", ".join(used)), ""]
    lines += [snippet("sweep.md", "line_meets_car"), ""]
    return "\n".join(lines).rstrip("\n") + "\n"
