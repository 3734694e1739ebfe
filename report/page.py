"""The page of the whole report: docs/report_full.md (all 18 columns of Tables 11 and 12,
Tables 9 and 10) and its figure docs/crash_test_fig18.png (``python
scripts/make_report_full.py`` writes them; :func:`write_page`).

Every number is measured here from the shipped descriptions
(``src/deck_emulator/assemblies/*.toml``), the shipped decks and the report's numbers in
``deck_emulator.studies.report_tables``, every run through the engine layer. What of the
inputs was read off the report's own tables is the page's provenance table
(:data:`~report.full.PROVENANCE`); every cause the page names is
backed by a computation on the page, and a miss nothing explains is called unexplained.
"""

from __future__ import annotations

import dataclasses
import math
import time
from pathlib import Path

import numpy as np

from deck_emulator.core.assembly import (
    Arm, Assembly, Shaft, inferred_geometry, load_assembly, mass_properties,
    STEEL_DECK_TARGET,
)
from deck_emulator.files import OutputSet
from deck_emulator.studies import crash_test as ct
from report import shaft_contact
from report.page_text import INCONSISTENCIES, UNFINISHED, say
from report.statements import STATEMENTS
from report.full import (
    DECEL_CANDIDATES, DELTA_V_CANDIDATES, DOUBTFUL, PROVENANCE, PROVENANCE_CRASH,
    as_rigid_body_requires, cell_kind, column_task, column_tasks, rigid_distances,
)
from deck_emulator.engine.quantities import QUANTITIES
from deck_emulator.studies.report_tables import (
    CASES_ALL, REPORT_ALL, SOURCE, TABLE8, TABLE9, TABLE10, report_time_ms_all,
)

__all__ = ["write_page"]

#: The page's figure, beside it (the page links it by this name).
FIG_NAME = "crash_test_fig18.png"

#: Short names of the ΔV readings (registry names in :data:`DELTA_V_CANDIDATES`).
DV_SHORT = {"delta_v_crush_mph": "crush pulse", "delta_v_first_spring_mph": "first spring",
            "delta_v_contact_mph": "whole contact"}
DECEL_SHORT = {"max_decel_g": "printed, after start-up", "max_decel_every_step_g": "every step",
               "max_decel_10ms_g": "10 ms average"}

#: A reading "fits" a column when it is within this of the report's value (mph, g): ten
#: units of the report's last digit.
FIT_DV_MPH = 0.05
FIT_DECEL_G = 0.05

#: The mark of a column whose post was fitted to the report's tables, and the words beside
#: each such column's table (the provenance table says it in full).
FITTED_MARK = "†"
FITTED_WORDS = ("fitted inputs: |PQ| and the arm's rise were read off Tables 11 and 12, the "
                "base weight and arm shape carried over; every number of ours below rests on "
                "them")

#: The point tests (the listing's and the legacy preset's) are named the cause of a miss of a
#: 20 mph 'hits car' column only where the same column run with the shaft test takes away at
#: least this share of the core's miss ('in part' where it takes away less).
SHAFT_SHARE = 0.5

ROWS = [("delta_v_crush_mph", "ΔV (crush pulse), mph", 2),
        ("delta_v_first_spring_mph", "ΔV (first spring), mph", 2),
        ("delta_v_contact_mph", "ΔV (whole contact), mph", 2),
        ("max_decel_g", "max decel., g", 2),
        ("XPL", "XPL", 2), ("YPL", "YPL", 2), ("ZPL", "ZPL", 2),
        ("XRL", "XRL", 2), ("YRL", "YRL", 2), ("ZRL", "ZRL", 2),
        ("XQL", "XQL", 2), ("YQL", "YQL", 2), ("ZQL", "ZQL", 2),
        ("XUL", "XUL", 2), ("YUL", "YUL", 2), ("ZUL", "ZUL", 2),
        ("time_ms", "time of the end, ms", 1)]

def f(x, nd=2, signed=False):
    if x is None:
        return "—"
    if round(x, nd) == 0:
        x = 0.0
    return f"{x:+.{nd}f}" if signed else f"{x:.{nd}f}"


def hit_word(msg):
    if msg is None:
        return "none"
    return msg.replace("THE POST HAS HIT THE ", "").replace("OF THE VEHICLE", "").strip().lower()


def report_value(col, key):
    """The report's value of ``key`` in ``col``: its one ΔV for every ΔV reading, its one
    deceleration for every deceleration reading."""
    rep = REPORT_ALL[col]
    if key in DELTA_V_CANDIDATES:
        return rep["delta_v_crush_mph"]
    if key in DECEL_CANDIDATES:
        return rep["max_decel_g"]
    if key == "time_ms":
        return report_time_ms_all(col)
    return rep.get(key)


def _miss(a, b):
    return None if a is None or b is None else a - b


def hits_car_at_20(col) -> bool:
    return CASES_ALL[col][1] == 20 and "CAR" in REPORT_ALL[col]["comment"]


def at_report_time_miss(run) -> float | None:
    """The largest |Δ| (ft) of the core's P, R, Q (U) at the report's time of the end."""
    col = run["column"]
    rep = REPORT_ALL[col]
    pts = run["core_points_l"]["report_time"]
    ds = [abs(a - b) for k, xl in pts.items() for a, b in
          zip(xl, (rep.get(f"{ax}{k}L") for ax in "XYZ")) if b is not None]
    return max(ds) if ds else None


def geometry_spread(geo: dict, post: str, mph: int, key: str):
    """(least, largest) of ``key`` over the base-weight variants of ``post`` (core, ``mph``,
    α = 0: :func:`geometry_run`); None without them."""
    vals = [geo[(post, label, mph)][key] for label in BASE_VARIANTS
            if (post, label, mph) in geo and geo[(post, label, mph)].get(key) is not None]
    return (min(vals), max(vals)) if vals else None


def geometry_width(geo: dict, col: str, key: str):
    """How far the base weight (0-120 lb) moves ``key`` in the post's α = 0 column of
    ``col``'s speed (core): (width, unit); a terminal coordinate is judged by the widest of
    XQL and ZQL; None without the runs."""
    post, mph, _, _ = CASES_ALL[col]
    if key == "time_ms":
        sp = geometry_spread(geo, post, mph, "hit_time_s")
        return None if sp is None else (1000 * (sp[1] - sp[0]), "ms")
    if key in DELTA_V_CANDIDATES or key in DECEL_CANDIDATES:
        sp = geometry_spread(geo, post, mph, key)
        return None if sp is None else (sp[1] - sp[0], "mph" if key.endswith("mph") else "g")
    sps = [geometry_spread(geo, post, mph, k) for k in ("XQL", "ZQL")]
    if None in sps:
        return None
    return max(b - a for a, b in sps), "ft"


def base_weights_reaching(geo: dict, post: str, mph: int, key: str, target: float) -> list:
    """The base weights (lb, linear between the base-weight variants of ``post`` at ``mph``,
    α = 0) at which the core's ``key`` equals ``target``; empty where none in 0-120 lb does."""
    ws = list(BASE_VARIANTS.values())
    ys = [geo.get((post, label, mph), {}).get(key) for label in BASE_VARIANTS]
    if key == "time_ms":
        ys = [geo.get((post, label, mph), {}).get("hit_time_s") for label in BASE_VARIANTS]
        ys = [None if y is None else 1000 * y for y in ys]
    if None in ys:
        return []
    out = []
    for (w0, y0), (w1, y1) in zip(zip(ws, ys), zip(ws[1:], ys[1:])):
        if (y0 - target) * (y1 - target) <= 0 and y0 != y1:
            w = w0 + (target - y0) * (w1 - w0) / (y1 - y0)
            if not any(abs(w - x) < 1e-6 for x in out):  # a variant's own weight, once
                out.append(w)
    return out


def _variant_value(geo, post, mph, label, key):
    r = geo[(post, label, mph)]
    if key == "time_ms":
        return None if r["hit_time_s"] is None else 1000 * r["hit_time_s"]
    return r.get(key)


def _at_base(geo, post, mph, key, w):
    ws = list(BASE_VARIANTS.values())
    ys = [_variant_value(geo, post, mph, label, key) for label in BASE_VARIANTS]
    return None if None in ys else float(np.interp(w, ws, ys))


def geometry_cause(geo, col, key, miss) -> str:
    """Whether the base weight (0-120 lb, the one input of the inferred geometry the variants
    move; core, the post's α = 0 column of the same speed) explains a miss of ``key``: it
    does only where some base weight moves the α = 0 value by the miss (the value the column
    needs: the shipped one less the miss) and, for every cell but the deceleration itself (a
    ΔV reading, the end, the coordinates), the car's largest deceleration there still fits
    the report's; else the miss is unexplained, with what was tried."""
    post, mph, _, _ = CASES_ALL[col]
    if (post, GEOMETRY_VARIANTS[0], mph) not in (geo or {}):
        return say("cause.no_variants")
    if key not in ("time_ms", "XQL", "ZQL", "max_decel_g") + DELTA_V_CANDIDATES:
        return say("cause.not_among", width=geometry_width(geo, col, key)[0], mph=mph)
    unit, nd = {"time_ms": ("ms", 1)}.get(key, ("g" if key in DECEL_CANDIDATES else
                                                  "mph" if key.endswith("mph") else "ft", 2))
    shipped = _variant_value(geo, post, mph, GEOMETRY_VARIANTS[0], key)
    needed = shipped - miss
    ws = base_weights_reaching(geo, post, mph, key, needed)
    if not ws:
        vals = {w: _variant_value(geo, post, mph, label, key)
                for label, w in BASE_VARIANTS.items()}
        w_near = min(vals, key=lambda w: abs(vals[w] - needed))
        return say("cause.none_reaches", weights=ws, needed=f"{needed:.{nd}f}", unit=unit,
                   mph=mph, nearest=f"{vals[w_near]:.{nd}f}", w_near=w_near)
    if key == "max_decel_g":
        return say("cause.base_fits_reading", weights=", ".join(f"{w:.0f}" for w in ws),
                   mph=mph)
    rep_decel = REPORT_ALL[f"{post}{mph}"]["max_decel_g"]
    fits = [(w, _at_base(geo, post, mph, "max_decel_g", w)) for w in ws]
    good = [(w, d) for w, d in fits if d is not None and abs(d - rep_decel) <= FIT_DECEL_G]
    if good:
        return say("cause.base_fits", w=good[0][0], mph=mph, decel=good[0][1],
                   rep_decel=rep_decel, fit=FIT_DECEL_G)
    w_dec = base_weight_fitting(geo, post, mph, "max_decel_g")
    at_dec = "" if w_dec is None else say(
        "cause.base_misfits.at_dec", w=w_dec, unit=unit,
        miss=f"{_at_base(geo, post, mph, key, w_dec) - report_value(f'{post}{mph}', key):+.{nd}f}")
    return say("cause.base_misfits", rep_decel=rep_decel, at_dec=at_dec, tried=", ".join(
        f"{w:.0f} lb, where the max decel. is {d:.2f} g" for w, d in fits))


def shaft_cell_cause(col, key, rep, core, shaft, other) -> str:
    """A 20 mph 'hits car' column's cell: whether the point tests are its miss's cause, by
    the same column run with the shaft test (``shaft``: its row, whose ``cells`` are the
    column's values keyed like the tables'): named only where that run takes away at least
    :data:`SHAFT_SHARE` of the core's miss (``core``: the core's value without the test), in
    part where less, not at all where none; ``other``: the cause of what it leaves."""
    with_ = None if shaft is None else (shaft.get("cells") or {}).get(key)
    if with_ is None or core is None:
        return say("cause.no_shaft_run", other=other,
                   why=f" ({shaft['error']})" if shaft and shaft.get("error") else "")
    nd = 1 if key == "time_ms" else 2
    # each miss as the page shows it: a difference below the last digit shown (the same
    # pulse solved twice) is no change
    m_with, m_without = round(with_ - rep, nd), round(core - rep, nd)
    figures = dict(m_with=m_with, m_without=m_without, share=SHAFT_SHARE, other=other,
                   with_=f(m_with, nd, True), without=f(m_without, nd, True))
    if abs(m_with) <= SHAFT_SHARE * abs(m_without):
        return say("cause.points_only", **figures)
    if abs(m_with) < abs(m_without):
        return say("cause.points_only_part", **figures)
    return say("cause.not_points", **figures)


def cause(col, key, rep, ours, geo=None, shaft=None, core=None):
    """The named cause of a miss beyond the report's last digit: every one is a computation
    on this page (the sensitivity to the inferred geometry, the same column with the shaft
    test, the core's post at the report's time, the readings table); 'unexplained' where
    none explains it. ``shaft``: the column's row with the shaft test, ``core``: the core's
    value of the cell (the 20 mph 'hits car' columns)."""
    post, mph, alpha, _ = CASES_ALL[col]
    kind = cell_kind(col, key)
    if kind is not None:
        return say(f"not_a_test.{kind}")
    nd = 1 if key == "time_ms" else 2
    half = 0.2 if key == "time_ms" else 0.5 * 10 ** -nd
    if rep is None or ours is None or abs(ours - rep) <= half + 1e-12:
        return ""
    if key in DELTA_V_CANDIDATES:
        causes = [say("cause.reading")]
        if post != "steel":
            causes.append(geometry_cause(geo, col, key, ours - rep))
    elif hits_car_at_20(col):
        other = (say("cause.steel") if post == "steel"
                 else geometry_cause(geo, col, key, ours - rep))
        core_miss = None if core is None else core - rep
        if core_miss is not None and abs(core_miss) <= half + 1e-12:
            causes = [other]  # the core has no miss here: the shaft test has none to take away
        else:
            causes = [shaft_cell_cause(col, key, rep, core, shaft, other)]
    elif post == "steel":
        causes = [say("cause.steel")]
    else:
        causes = [geometry_cause(geo, col, key, ours - rep)]
    return "; ".join(causes)


def cell_cause(col, key, r, geo) -> str:
    """The cause column of one cell (``r``: the column's runs): the core's miss first, the
    emulator's where the core has none."""
    rv = report_value(col, key)
    em, co = r["emulator"], r["core"]
    ev = None if em is None else em.get(key)
    cv = co.get(key)
    sh = r.get("shaft")
    return (cause(col, key, rv, cv, geo, sh, cv)
            or cause(col, key, rv, ev, geo, sh, cv))


def fitted_cause_counts(runs, geo) -> dict:
    """Over the aluminium and twin columns' cells that test the model and miss the report's
    last digit (core, else the emulator: :func:`cell_cause`): how many name the base weight as
    their cause, and how many none at all ('variants.moves')."""
    n = base = none = 0
    for col in CASES_ALL:
        if CASES_ALL[col][0] == "steel":
            continue
        for key, _, _ in ROWS:
            if (key[1] == "U" and CASES_ALL[col][0] != "twin") or cell_kind(col, key):
                continue
            why = cell_cause(col, key, runs[col], geo)
            if not why:
                continue
            n += 1
            if "the base weight (fitted inputs)" in why:
                base += 1
            elif "unexplained" in why and not any(
                    w in why for w in ("points only", "arithmetic", "the listing's step")):
                none += 1
    return {"n_miss": n, "n_base": base, "n_unexplained": none}


def columns_section(lines, runs, geo):
    lines.append("## Tables 11 and 12, all 18 columns\n")
    lines.append(say("columns.intro", share=f"{SHAFT_SHARE:.0%}"))
    for col in CASES_ALL:
        post, mph, alpha, table = CASES_ALL[col]
        r = runs[col]
        rep = REPORT_ALL[col]
        em, co = r["emulator"], r["core"]
        lines.append(f"### `{col}` — {post}, {mph} mph, α = {alpha}° (Table {table})"
                     + (f"; {FITTED_WORDS}" if post != "steel" else "") + "\n")
        if r["listing_refusal"]:
            lines.append(f"Emulator: refused — {r['listing_refusal']}.\n")
        elif em and em.get("error"):
            lines.append(f"Emulator stopped: {em['error']}\n")
        lines.append("| quantity | report | emulator | Δ emulator | core | Δ core | cause of the miss |")
        lines.append("|---|---|---|---|---|---|---|")
        for key, label, nd in ROWS:
            if key[1] == "U" and post != "twin":
                continue
            rv = report_value(col, key)
            ev = None if em is None else em.get(key)
            cv = co.get(key)
            de, dc = _miss(ev, rv), _miss(cv, rv)
            why = cell_cause(col, key, r, geo)
            misses = dict(em_miss=None if de is None else abs(de),
                          core_miss=None if dc is None else abs(dc),
                          half=0.2 if key == "time_ms" else 0.005)
            if None not in misses.values():
                if cell_kind(col, key) is None and misses["em_miss"] <= misses["half"] \
                        < misses["core_miss"]:
                    why = say("cause.arithmetic", **misses)
                elif key in DECEL_CANDIDATES and misses["core_miss"] <= misses["half"] \
                        < misses["em_miss"]:
                    why = say("cause.step", **misses)
            lines.append(f"| {label} | {f(rv, nd)} | {f(ev, nd)} | {f(de, nd, True)} | "
                         f"{f(cv, nd)} | {f(dc, nd, True)} | {why} |")
        lines.append(f"| end | {rep['comment'].lower()} | "
                     f"{hit_word(em['hit']) if em else '—'} | | {hit_word(co['hit'])} | | |")
        rep_time = report_time_ms_all(col)
        if hits_car_at_20(col) and rep_time is not None:
            pts = r["core_points_l"]["report_time"]
            if pts:
                cells = []
                for k, xl in pts.items():
                    rr = tuple(rep.get(f"{a}{k}L") for a in "XYZ")
                    d = max(abs(a - b) for a, b in zip(xl, rr)) if None not in rr else None
                    cells.append(f"{k} ({f(xl[0])}, {f(xl[1])}, {f(xl[2])}), max |Δ| {f(d)} ft")
                lines.append(say("columns.at_report_time", ms=rep_time,
                                 cells="; ".join(cells)))
        lines.append("")


def largest_coordinate_miss(col, e):
    """The largest |ours − report| over the terminal coordinates that test the model (not an
    input, a symmetry or the end condition: :func:`cell_kind`)."""
    rep = REPORT_ALL[col]
    ds = [abs(e[k] - rep[k]) for k in rep if k[-1] == "L" and len(k) == 3
          and rep[k] is not None and e.get(k) is not None and cell_kind(col, k) is None]
    return max(ds) if ds else None


def best_reading(col, e, names):
    """(name, miss) of the reading in ``names`` nearest the report in ``e`` (a row)."""
    got = [(n, _miss(e.get(n), report_value(col, n))) for n in names]
    got = [(n, d) for n, d in got if d is not None]
    return min(got, key=lambda x: abs(x[1])) if got else (None, None)


def shaft_cause(col, run) -> tuple[str, bool]:
    """The 20 mph columns: the listing (and the core's legacy preset) test only points
    against the car; the same column with the shaft test, its end's time and the distance of
    its end coordinates from the report's, each against the run without it, and the post at
    the report's time. Where the report ends on the car, the point tests are named the
    column's cause only where the shaft test takes away at least :data:`SHAFT_SHARE` of both
    the end's time miss and its largest coordinate miss ('in part' where it lessens both
    less; 'not the point tests' where it lessens either not at all); where the report ends
    on the ground the shaft test is one more thing tried. Returns (the words, whether the
    shaft test accounts for the end in full)."""
    rt = report_time_ms_all(col)
    sh, off = run.get("shaft"), run.get("shaft_off")
    d = at_report_time_miss(run) if hits_car_at_20(col) else None
    at_time = say("shaft.at_time", d=f(d)) if d is not None else ""
    if sh is None or sh["time_ms"] is None or sh["surface"] is None:
        return say("shaft.none", at_time=at_time,
                   why=f" ({sh['error']})" if sh and sh.get("error") else ""), False
    ends = say("shaft.ends", surface=sh["surface"], point=sh["point"],
               dt=f(sh["time_ms"] - rt, 1, True))
    dist = ""
    a = b = None
    if off is not None and sh["max_coordinate_diff_ft"] is not None \
            and off["max_coordinate_diff_ft"] is not None:
        a, b = sh["max_coordinate_diff_ft"], off["max_coordinate_diff_ft"]
        dist = say("shaft.dist", a=a, b=b,
                   farther=" (farther)" if round(a, 2) > round(b, 2) else "")
    if not hits_car_at_20(col):
        return say("shaft.tried", ends=ends, dist=dist), False
    if a is None or off["time_ms"] is None:
        return say("shaft.none", at_time=at_time,
                   why=f" (without it: {off['error']})" if off.get("error") else ""), False
    figures = dict(ends=ends, dist=dist, at_time=at_time, a=a, b=b, share=SHAFT_SHARE,
                   t_with=sh["time_ms"] - rt, t_without=off["time_ms"] - rt)
    if a <= SHAFT_SHARE * b and abs(figures["t_with"]) <= SHAFT_SHARE * abs(
            figures["t_without"]):
        return say("shaft.cause", **figures), True
    if a < b and abs(figures["t_with"]) < abs(figures["t_without"]):
        return say("shaft.cause_part", **figures), False
    return say("shaft.not_cause", **figures), False


def main_cause(col, runs, geo) -> str:
    """The summary's cause of a column's misses: each part names the computation on the page
    that backs it, or says 'unexplained' with what was tried."""
    post, mph, alpha, _ = CASES_ALL[col]
    co = runs[col]["core"]
    parts = []
    explained = False
    if mph == 20:
        words, explained = shaft_cause(col, runs[col])
        parts.append(words)
    rt = report_time_ms_all(col)
    miss = None if co["time_ms"] is None or rt is None else co["time_ms"] - rt
    if post == "steel" and not explained:
        parts.append(say("main.end_steel"))
    elif post != "steel" and miss is not None and not explained:
        parts.append("end: " + geometry_cause(geo, col, "time_ms", miss))
    name, d = best_reading(col, co, DELTA_V_CANDIDATES)
    if d is not None and abs(d) <= FIT_DV_MPH:
        parts.append(say("main.dv_fits", reading=DV_SHORT[name],
                         miss=0.0 if round(d, 2) == 0 else d, fit=FIT_DV_MPH,
                         carried=say("main.dv_carried") if post != "steel" else ""))
    else:
        parts.append(say("main.dv_none", fit=FIT_DV_MPH, reading=DV_SHORT.get(name, "-"),
                         miss=f(d, 2, True), steel=": unexplained" if post == "steel" else ""))
    dd = _miss(co.get("max_decel_g"), report_value(col, "max_decel_g"))
    if dd is not None and abs(dd) > FIT_DECEL_G:
        parts.append(say("main.decel", miss=dd, fit=FIT_DECEL_G, why=(
            geometry_cause(geo, col, "max_decel_g", dd) if post != "steel" else "unexplained")))
    return "; ".join(parts)


def _short_end(words: str) -> str:
    """'post hits ground with point r' -> 'r': an end as the summary's cell gives it."""
    for cut in ("post hits ", "ground with ", "points ", "point "):
        words = words.replace(cut, "")
    return words


def predictions() -> int:
    """How many of the 18 columns are genuine predictions (the provenance table's)."""
    return sum(PROVENANCE[CASES_ALL[c][0]]["prediction"] for c in CASES_ALL)


def summary_section(lines, runs, geo):
    lines.append("## Summary of the misses (core; emulator in brackets where the listing runs)\n")
    lines.append(say("summary.intro"))
    lines.append("| column | end: report / ours | time Δ, ms | largest coordinate Δ, ft | ΔV Δ, mph: crush / first spring / contact | max decel. Δ, g | main cause |")
    lines.append("|---|---|---|---|---|---|---|")
    for col in CASES_ALL:
        rep, co, em = REPORT_ALL[col], runs[col]["core"], runs[col]["emulator"]
        rt = report_time_ms_all(col)

        def cellpair(fn, nd):
            a = fn(co)
            b = fn(em) if em else None
            return f(a, nd, True) + (f" ({f(b, nd, True)})" if em else "")

        def dvs(e):
            return " / ".join(f(_miss(e.get(n), rep["delta_v_crush_mph"]), 2, True)
                              for n in DELTA_V_CANDIDATES)

        mark = "" if CASES_ALL[col][0] == "steel" else f" {FITTED_MARK}"
        lines.append(
            f"| {col}{mark} | {_short_end(rep['comment'].lower())} / "
            f"{_short_end(hit_word(co['hit']))} | "
            + cellpair(lambda e: _miss(e["time_ms"], rt), 1)
            + f" | {f(largest_coordinate_miss(col, co))}"
            + (f" ({f(largest_coordinate_miss(col, em))})" if em else "") + " | "
            + dvs(co) + (f" ({dvs(em)})" if em else "")
            + " | " + cellpair(lambda e: _miss(e["max_decel_g"], rep["max_decel_g"]), 2)
            + f" | {main_cause(col, runs, geo)} |")
    lines.append("")
    lines.append(say("summary.predictions", n_pred=predictions(),
                     crash="one" if PROVENANCE_CRASH["prediction"] else "not one"))


#: The inferred geometry's variants the page runs (label of each, per post).
GEOMETRY_VARIANTS = ("as shipped (base 61 lb, up-swept arm)", "no base mass", "base 30 lb",
                     "base 90 lb", "base 120 lb", "straight arm")

#: The variants that change only the base's weight (label -> lb), in increasing weight.
BASE_VARIANTS = {"no base mass": 0.0, "base 30 lb": 30.0,
                 "as shipped (base 61 lb, up-swept arm)": 61.0, "base 90 lb": 90.0,
                 "base 120 lb": 120.0}


def _geometry_variant(post: str, label: str):
    from deck_emulator.core.assembly import BaseMass

    a, _, _ = load_assembly(post)
    if label == GEOMETRY_VARIANTS[0]:
        return a
    if label == "straight arm":
        return dataclasses.replace(
            a, arms=tuple(dataclasses.replace(x, shape="straight") for x in a.arms))
    return dataclasses.replace(a, base=BaseMass(BASE_VARIANTS[label]))


#: The speeds the geometry variants run at (α = 0; the steel deck of that speed's car).
GEOMETRY_SPEEDS = (40, 20)


def geometry_tasks() -> list[dict]:
    return [{"kind": "geometry", "post": post, "variant": label, "mph": mph, "cost": 1.0}
            for mph in GEOMETRY_SPEEDS for post in ("aluminium", "twin")
            for label in GEOMETRY_VARIANTS]


def geometry_run(task: dict) -> dict:
    """Worker of the scene runner: one variant of an inferred geometry on the core (legacy
    preset, the car of the steel deck of ``task["mph"]``, α = 0): its inertias, tilt, end and
    base point Q, and the registry's ΔV and deceleration readings."""
    from deck_emulator.engine import CoreEngine
    from deck_emulator.engine.assemblies import to_scene
    from deck_emulator.engine.quantities import values

    v = _geometry_variant(task["post"], task["variant"])
    mp = mass_properties(v)
    res = CoreEngine(preset="legacy").run(to_scene(v, mp, template=f"steel{task['mph']}"))
    q = res.terminal.get("Q")
    return {"A": mp.A, "B": mp.B, "C": mp.C, "delta_deg": mp.delta_deg, "hit": res.hit_message,
            "hit_time_s": res.hit_time_s, "XQL": None if q is None else q[0],
            "ZQL": None if q is None else q[2],
            **values(res, DELTA_V_CANDIDATES + ("max_decel_g",))}


def base_weight_fitting(runs: dict, post: str, mph: int, key: str) -> float | None:
    """The base weight (lb) at which the core's ``key`` (``mph``, α = 0) equals the report's,
    by linear interpolation between the base-weight variants; None if the report's value is
    outside their range (``key`` must grow with the base's weight over the variants)."""
    ws = list(BASE_VARIANTS.values())
    ys = [runs[(post, label, mph)][key] for label in BASE_VARIANTS]
    target = report_value(f"{post}{mph}", key)
    if None in ys or any(b <= a for a, b in zip(ys, ys[1:])) or not ys[0] <= target <= ys[-1]:
        return None
    return float(np.interp(target, ys, ws))


def variants_move(runs: dict, cols_runs: dict) -> dict:
    """How far the base weight (0-120 lb) moves the α = 0 columns of aluminium and twin (the
    least and largest over posts and speeds: the end in ms, the base point XQL, ZQL in ft, ΔV
    and the deceleration) and the largest of their columns' misses (core; ΔV by the nearest
    reading): what 'variants.moves' claims."""
    def widths(keys, scale=1.0):
        w = [scale * (b - a) for k in keys for a, b in (geometry_spread(runs, p, m, k)
             for m in GEOMETRY_SPEEDS for p in ("aluminium", "twin"))]
        return min(w), max(w)

    cols = [c for c in CASES_ALL if CASES_ALL[c][0] != "steel"]
    dv_miss = max(abs(best_reading(c, cols_runs[c]["core"], DELTA_V_CANDIDATES)[1])
                  for c in cols)
    decel_miss = max(abs(_miss(cols_runs[c]["core"].get("max_decel_g"),
                               report_value(c, "max_decel_g"))) for c in cols)
    out = dict(dv_miss=dv_miss, decel_miss=decel_miss)
    for name, keys, scale in (("end", ("hit_time_s",), 1000.0), ("base", ("XQL", "ZQL"), 1.0),
                              ("dv", DELTA_V_CANDIDATES, 1.0), ("decel", ("max_decel_g",), 1.0)):
        out[f"{name}_lo"], out[f"{name}_hi"] = widths(keys, scale)
    return out


def geometry_sensitivity_section(lines, runs: dict, cols_runs: dict):
    """How much the two calibrated unknowns move the aluminium and twin 0° columns
    (``runs``: (post, variant, mph) -> :func:`geometry_run`; ``cols_runs``: the columns')."""
    lines.append("### How much the inferred geometry moves the answer (core, α = 0°)\n")
    lines.append("| post | mph | variant | A, B, C (slug ft²) | δ, deg | end | time, ms (report) | XQL, ZQL (report) | ΔV crush / first spring / contact, mph (report) | max decel., g (report) |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|")
    for mph in GEOMETRY_SPEEDS:
        for post in ("aluminium", "twin"):
            col = f"{post}{mph}"
            rep = REPORT_ALL[col]
            for label in GEOMETRY_VARIANTS:
                r = runs[(post, label, mph)]
                t = None if r["hit_time_s"] is None else 1000 * r["hit_time_s"]
                dvs = " / ".join(f(r[n]) for n in DELTA_V_CANDIDATES)
                lines.append(
                    f"| {post} | {mph} | {label} | {r['A']:.0f}, {r['B']:.0f}, {r['C']:.1f} | "
                    f"{r['delta_deg']:.2f} | {hit_word(r['hit'])} | {f(t, 1)} "
                    f"({f(report_time_ms_all(col), 1)}, {rep['comment'].lower()}) | "
                    f"{f(r['XQL'])}, {f(r['ZQL'])} ({rep['XQL']}, {rep['ZQL']}) | "
                    f"{dvs} ({rep['delta_v_crush_mph']:.2f}) | "
                    f"{f(r['max_decel_g'])} ({rep['max_decel_g']:.2f}) |")
    lines.append(say("variants.moves", **variants_move(runs, cols_runs),
                     **fitted_cause_counts(cols_runs, runs)))
    lines.append(say("variants.fit_intro"))
    lines.append("| post | mph | reading | base that fits the report's value, lb | max decel. at that base, g (report) |")
    lines.append("|---|---|---|---|---|")
    ws = list(BASE_VARIANTS.values())
    joint = {}
    for mph in GEOMETRY_SPEEDS:
        for post in ("aluminium", "twin"):
            decel = [runs[(post, label, mph)]["max_decel_g"] for label in BASE_VARIANTS]
            rep = REPORT_ALL[f"{post}{mph}"]["max_decel_g"]
            for k in DELTA_V_CANDIDATES:
                w = base_weight_fitting(runs, post, mph, k)
                at = None if w is None or None in decel else float(np.interp(w, ws, decel))
                if at is not None:
                    joint.setdefault((post, mph), []).append((abs(at - rep), at - rep, k, w))
                lines.append(f"| {post} | {mph} | ΔV {DV_SHORT[k]} | {f(w, 0)} | "
                             f"{f(at)} ({rep:.2f}) |")
            w = base_weight_fitting(runs, post, mph, "max_decel_g")
            lines.append(f"| {post} | {mph} | max decel. | {f(w, 0)} | {rep:.2f} ({rep:.2f}) |")
    lines.append("")
    for (post, mph), rows in joint.items():
        _, d, k, w = min(rows)
        lines.append(say("variants.joint", post=post, mph=mph, reading=DV_SHORT[k], w=w,
                         miss=0.0 if round(d, 2) == 0 else d,
                         others="; the others " + ", ".join(
                             f"{DV_SHORT[k2]} {d2:+.2f} g" for _, d2, k2, _ in rows if k2 != k)
                         if len(rows) > 1 else ""))
    lines.append(say("variants.closing"))


def _fit_stats(runs, cols, engine, key):
    ds = [_miss(runs[c][engine].get(key) if runs[c][engine] else None, report_value(c, key))
          for c in cols]
    ds = [d for d in ds if d is not None]
    if not ds:
        return None
    return sum(abs(d) for d in ds) / len(ds), min(ds), max(ds), len(ds)


def readings_section(lines, runs):
    """Issue 24, item 4: every reading of ΔV and of the maximum deceleration, all 18
    columns, both engines where both run; which fits which posts, by how much."""
    lines.append("## ΔV and the maximum deceleration: every reading, all 18 columns\n")
    lines.append(say("readings.intro"))
    for n in DELTA_V_CANDIDATES + DECEL_CANDIDATES:
        lines.append(f"* `{n}`: {QUANTITIES[n].what}.")
    lines.append("")
    def cell(e, key, col):
        if e is None or e.get(key) is None:
            return "—"
        return f"{f(e[key])} ({f(_miss(e[key], report_value(col, key)), 2, True)})"

    for title, names, short in (("ΔV, mph", DELTA_V_CANDIDATES, DV_SHORT),
                                ("Maximum deceleration, g", DECEL_CANDIDATES, DECEL_SHORT)):
        lines.append(f"### {title}: ours (ours − report)\n")
        head = " | ".join(f"{short[n]}, emulator | {short[n]}, core" for n in names)
        lines.append(f"| column | report | {head} |")
        lines.append("|---|---|" + "---|" * (2 * len(names)))
        for col in CASES_ALL:
            em, co = runs[col]["emulator"], runs[col]["core"]
            lines.append(f"| {col} | {f(report_value(col, names[0]))} | " + " | ".join(
                f"{cell(em, n, col)} | {cell(co, n, col)}" for n in names) + " |")
        lines.append("")
    lines.append("### Which reading fits which posts\n")
    lines.append(say("readings.mean"))
    lines.append("| post | engine | " + " | ".join(f"ΔV {DV_SHORT[n]}" for n in DELTA_V_CANDIDATES)
                 + " | " + " | ".join(f"decel. {DECEL_SHORT[n]}" for n in DECEL_CANDIDATES) + " |")
    lines.append("|---|---|" + "---|" * (len(DELTA_V_CANDIDATES) + len(DECEL_CANDIDATES)))
    best = {}
    for post in ("aluminium", "steel", "twin"):
        cols = [c for c in CASES_ALL if CASES_ALL[c][0] == post]
        for engine in ("emulator", "core"):
            stats = {n: _fit_stats(runs, cols, engine, n)
                     for n in DELTA_V_CANDIDATES + DECEL_CANDIDATES}
            if all(v is None for v in stats.values()):
                continue
            best[(post, engine)] = stats
            lines.append(f"| {post} | {engine} | " + " | ".join(
                "—" if stats[n] is None else
                f"{stats[n][0]:.3f} ({stats[n][1]:+.2f} to {stats[n][2]:+.2f})"
                for n in DELTA_V_CANDIDATES + DECEL_CANDIDATES) + " |")
    lines.append("")
    for post in ("aluminium", "steel", "twin"):
        st = best[(post, "core")]
        dv = min(DELTA_V_CANDIDATES, key=lambda n: st[n][0])
        dc = min(DECEL_CANDIDATES, key=lambda n: st[n][0])
        lines.append(say("readings.best", post=post, dv=DV_SHORT[dv], dv_mean=st[dv][0],
                         dc=DECEL_SHORT[dc], dc_mean=st[dc][0], others=", ".join(
                             f"{DV_SHORT[n]} {st[n][0]:.3f}" for n in DELTA_V_CANDIDATES
                             if n != dv)))
    em_core = [runs[c]["emulator"]["max_decel_g"] - runs[c]["core"]["max_decel_g"]
               for c in CASES_ALL if runs[c]["emulator"]
               and runs[c]["emulator"].get("max_decel_g") is not None]
    steel = [c for c in CASES_ALL if CASES_ALL[c][0] == "steel"]
    em_steel = [_miss(runs[c]["emulator"]["max_decel_g"], report_value(c, "max_decel_g"))
                for c in steel]
    co_steel = [_miss(runs[c]["core"]["max_decel_g"], report_value(c, "max_decel_g"))
                for c in steel]
    twin40 = [c for c in CASES_ALL if CASES_ALL[c][:2] == ("twin", 40)]
    lines.append(say(
        "readings.steel_decel", em_lo=min(em_steel), em_hi=max(em_steel), co_lo=min(co_steel),
        co_hi=max(co_steel), d_lo=min(em_core), d_hi=max(em_core), fit=FIT_DECEL_G,
        twin40_best=min(abs(_miss(runs[c]["core"].get(n), report_value(c, n)))
                        for c in twin40 for n in DECEL_CANDIDATES)))

    def rng(post, n, engine="core", speed=None):
        cols = [c for c in CASES_ALL if CASES_ALL[c][0] == post
                and (speed is None or CASES_ALL[c][1] == speed)]
        ds = [_miss(runs[c][engine].get(n), report_value(c, n)) for c in cols]
        ds = [abs(d) for d in ds if d is not None]
        return f"{min(ds):.2f}-{max(ds):.2f}"

    short = {"delta_v_crush_mph": "crush", "delta_v_first_spring_mph": "first",
             "delta_v_contact_mph": "contact"}
    lines.append(say("readings.no_one", **{
        f"{short[n]}_{post}{speed or ''}": rng(post, n, speed=speed)
        for n in DELTA_V_CANDIDATES for post in ("aluminium", "steel", "twin")
        for speed in (None, 20, 40)}))
    lines.append("")


def _cells(*texts) -> str:
    """A markdown table row (a '|' inside a cell escaped)."""
    return "| " + " | ".join(t.replace("|", "\\|") for t in texts) + " |"


def provenance_section(lines):
    """Issue 24, item 5: where each column's inputs come from."""
    lines.append("## Provenance: what each column's inputs come from\n")
    lines.append(say("provenance.intro"))
    lines.append("| columns | deck | description | fitted to the tables | assumed | a prediction? |")
    lines.append("|---|---|---|---|---|---|")
    rows = [(", ".join(f"`{c}`" for c in CASES_ALL if CASES_ALL[c][0] == post), PROVENANCE[post])
            for post in ("steel", "aluminium", "twin")]
    for cols, p in rows + [("crash test (Tables 9, 10)", PROVENANCE_CRASH)]:
        lines.append(_cells(cols, p['deck'], p['description'], p['fitted'], p['assumed'],
                            f"{'yes' if p['prediction'] else 'no'}: {p['why']}"))
    marked = [(c, k) for c in CASES_ALL for k in REPORT_ALL[c]
              if len(k) == 3 and k[-1] == "L" and cell_kind(c, k) is not None]
    by_kind = {}
    for c, k in marked:
        by_kind.setdefault(cell_kind(c, k), []).append(f"{c} {k}")
    lines.append(say("provenance.predictions", n_pred=predictions()))
    for kind, cells in by_kind.items():
        lines.append(f"* {kind} ({len(cells)}): " + ", ".join(cells))
    lines.append("")


def doubtful_section(lines, runs):
    """Issue 24, item 7: the two doubtful cells of the source, each reading's effect."""
    lines.append("## Two doubtful cells of the source, each reading's effect\n")
    col, key = DOUBTFUL[0]
    rep = REPORT_ALL[col]
    em, co = runs[col]["emulator"], runs[col]["core"]
    fit = as_rigid_body_requires(col, key)
    means = fit["means"]
    lines.append(say("doubtful.sign", col=col, key=key, pq=means["PQ"], qr=means["QR"],
                     value=fit["value"], misfit=fit["misfit_ft"]))
    lines.append(f"| reading of {key} | \\|PQ\\|, ft | \\|QR\\|, ft | Δ emulator | Δ core |")
    lines.append("|---|---|---|---|---|")
    for v in (rep[key], -rep[key], fit["value"]):
        d = rigid_distances(col, {key: v})
        lines.append(f"| {v:+.2f} | {d['PQ']:.2f} | {d['QR']:.2f} | "
                     f"{f(_miss(em.get(key) if em else None, v), 2, True)} | "
                     f"{f(_miss(co.get(key), v), 2, True)} |")
    shifts = [abs(2 * rep[key])]  # the miss moves by the readings' difference, each engine
    other = largest_coordinate_miss(col, co)
    lines.append(say(
        "doubtful.sign_effect", key=key, shift=shifts[0], other=f(other), other_ft=other,
        plus=rigid_distances(col)["PQ"] - means["PQ"],
        minus=rigid_distances(col, {key: -rep[key]})["PQ"] - means["PQ"]))
    col, _ = DOUBTFUL[1]
    rep = REPORT_ALL[col]
    em, co = runs[col]["emulator"], runs[col]["core"]
    d0 = rigid_distances(col)
    fits = {k: as_rigid_body_requires(col, k) for k in ("XRL", "YRL", "ZRL")}
    means = fits["XRL"]["means"]
    lines.append(say("doubtful.r", col=col, pr=d0["PR"], qr=d0["QR"], pr_mean=means["PR"],
                     qr_mean=means["QR"]))
    lines.append("| cell changed | printed | as the rigid body requires | misfit left, ft | Δ emulator: printed → rigid | Δ core: printed → rigid |")
    lines.append("|---|---|---|---|---|---|")
    for k, fk in fits.items():
        ev, cv = (em.get(k) if em else None), co.get(k)
        lines.append(f"| {k} | {rep[k]:+.2f} | {fk['value']:+.2f} | {fk['misfit_ft']:.2f} | "
                     f"{f(_miss(ev, rep[k]), 2, True)} → {f(_miss(ev, fk['value']), 2, True)} | "
                     f"{f(_miss(cv, rep[k]), 2, True)} → {f(_miss(cv, fk['value']), 2, True)} |")
    best = min(fits, key=lambda k: fits[k]["misfit_ft"])
    lines.append(say("doubtful.r_best", best=best, value=fits[best]["value"],
                     printed=rep[best], misfit=fits[best]["misfit_ft"], others=" and ".join(
                         f"{fits[k]['misfit_ft']:.2f}" for k in fits if k != best)))


def geometry_section(lines):
    lines.append("## Geometry from the tables (rigid-body invariants)\n")
    lines.append(say("geometry.intro"))
    lines.append("| post | pair | 20 mph 0° | 15° | 30° | 40 mph 0° | 15° | 30° | mean | s.d. |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|")
    out = {}
    for post in ("aluminium", "steel", "twin"):
        cols = [c for c in CASES_ALL if CASES_ALL[c][0] == post]
        pts = "PQRU" if post == "twin" else "PQR"
        cells = {p: [tuple(REPORT_ALL[c][f"{a}{p}L"] for a in "XYZ") for c in cols] for p in pts}
        g = inferred_geometry(cells)
        out[post] = g
        for pair, v in g.items():
            if not isinstance(v, dict):
                continue
            lines.append(f"| {post} | {pair} | " + " | ".join(f"{x:.2f}" for x in v["values"])
                         + f" | {v['mean']:.2f} | {v['sd']:.2f} |")
    lines.append("")
    for post, g in out.items():
        lines.append(say("geometry.post", post=post, pq=g["PQ"]["mean"], sd=g["PQ"]["sd"],
                         reach=g["reach_ft"], rise=g["rise_ft"]))
    lines.append(say("geometry.consistency", **consistency(out)))


def _span(values) -> str:
    """'36.70-36.71' (one number where they agree to the page's two decimals)."""
    lo, hi = f"{min(values):.2f}", f"{max(values):.2f}"
    return lo if lo == hi else f"{lo}-{hi}"


def consistency(g: dict) -> dict:
    """The figures of 'geometry.consistency' from the rigid-body distances of each post's six
    columns (``g``: post -> :func:`inferred_geometry`; columns in Tables 11-12's order, the
    20 mph ones first; the aluminium 20 mph 15° column second)."""
    steel, al, twin = (g[p] for p in ("steel", "aluminium", "twin"))
    pq = [round(v, 2) for v in al["PQ"]["values"]]
    mode = max(set(pq), key=pq.count)
    others = [i for i in range(6) if i != 1]

    def off(pair):
        v = al[pair]["values"]
        return abs(v[1] - sum(v[i] for i in others) / len(others))

    return dict(steel_pq=_span(steel["PQ"]["values"]), steel_pr20=_span(steel["PR"]["values"][:3]),
                steel_pr40=_span(steel["PR"]["values"][3:]), al_pq=_span(al["PQ"]["values"]),
                al_pq_mode=f"{mode:.2f}", al_pq_n=pq.count(mode), al_pr=al["PR"]["values"][1],
                al_pr_off=off("PR"), al_qr=al["QR"]["values"][1], al_qr_off=off("QR"),
                twin_pq=_span(twin["PQ"]["values"]), twin_short=27.75 - twin["PQ"]["mean"],
                twin_ru=_span(twin["RU"]["values"]), twin_pr=_span(twin["PR"]["values"]),
                twin_pu=_span(twin["PU"]["values"]),
                twin_pr_pu=max(twin["PR"]["values"] + twin["PU"]["values"])
                - min(twin["PR"]["values"] + twin["PU"]["values"]))


def builder_section(lines):
    lines.append("## The post-assembly builder against the report's steel deck\n")
    lines.append(say("builder.intro"))
    plain = Assembly("steel", Shaft(490.0, 9.5, 4.0, 36.708), arms=(Arm(10.0, 5.0, 83.5, 35.0),),
                     total_weight_lb=485.07)
    cal, _, _ = load_assembly("steel")
    T = STEEL_DECK_TARGET
    lines.append("| quantity | steel deck | uniform wall, straight arm, no base | Δ | calibrated (steel.toml) | Δ |")
    lines.append("|---|---|---|---|---|---|")
    mps = [mass_properties(plain), mass_properties(cal)]
    rows = [("mass centre above Q, ft", T["cm_height_ft"], lambda m: m.cm_height_ft, "{:.3f}"),
            ("mass centre YY from the axis, ft", T["cm_offset_ft"], lambda m: m.cm_offset_ft, "{:.3f}"),
            ("A, slug ft²", T["A"], lambda m: m.A, "{:.1f}"),
            ("B, slug ft²", T["B"], lambda m: m.B, "{:.1f}"),
            ("C, slug ft²", T["C"], lambda m: m.C, "{:.2f}"),
            ("δ, deg", round(math.degrees(T["DELTA"]), 3), lambda m: m.delta_deg, "{:.3f}"),
            ("W, slug", T["W"], lambda m: m.mass_slug, "{:.3f}")]
    for label, tv, fn, fmt in rows:
        cells = []
        for m in mps:
            v = fn(m)
            rel = f" ({100 * (v / tv - 1):+.1f} %)" if label[0] in "ABC" else ""
            cells += [fmt.format(v), f"{v - tv:+.3f}{rel}"]
        lines.append(f"| {label} | {tv} | " + " | ".join(cells) + " |")
    b = cal.base
    arm = cal.arms[0]
    lines.append(say("builder.calibrated", base_lb=b.weight_lb, reach=arm.control[0],
                     rise=arm.control[1], wall_in=mps[1].wall_in,
                     **{f"{k.lower()}_pct": 100 * (getattr(mps[1], k) / T[k] - 1) for k in "ABC"}))
    lines.append("| post | weight, lb | W, slug | wall, in | A | B | C | δ, deg | mass centre above Q, ft | YY from axis, ft |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|")
    for name in ("steel", "aluminium", "twin"):
        a, _, _ = load_assembly(name)
        m = mass_properties(a)
        lines.append(f"| {name} | {m.weight_lb:.2f} | {m.mass_slug:.4f} | {m.wall_in:.4f} | "
                     f"{m.A:.1f} | {m.B:.1f} | {m.C:.2f} | {m.delta_deg:.3f} | "
                     f"{m.cm_height_ft:.3f} | {m.cm_offset_ft:.3f} |")
    lines.append("")


# ------------------------------------------------------------------------------ the crash test

T10_KEYS = [("time_ms", "TIME, ms", 1), ("theta_deg", "θ, deg", 1),
            ("thetadot_rad_s", "θ̇, rad/s", 2), ("XCM_ft", "XCM, ft", 2), ("ZCM_ft", "ZCM, ft", 2),
            ("V1_ft_s", "V1, ft/s", 2), ("V3_ft_s", "V3, ft/s", 2), ("SV_ft", "SV, ft", 2)]


#: The crash test's variants: label -> the keywords of crash_scene (the first: as assumed).
CRASH_VARIANTS = {
    "as assumed (S 1.5 ft, knee 3.0 in, normal force)": {},
    "S 1.0 ft above the base": {"impact_height_ft": 1.0},
    "S 2.0 ft above the base": {"impact_height_ft": 2.0},
    "S 2.5 ft above the base": {"impact_height_ft": 2.5},
    "unloading knee at 0 (38,400 lb/ft all the way)": {"unloading_knee_ft": 0.0},
    "unloading at 12,000 lb/ft only (no stiff branch)":
        {"unloading_stiffness_lb_per_ft": [12000.0, 12000.0]},
    "no U-bolt stop (26,400 lb/ft beyond 4.5 in)": {"stop_ft": 100.0},
    "base 0.5 ft above the ground": {"base_on_ground": False},
}


def crash_tasks() -> list[dict]:
    """The scene runner's tasks of the crash test: each variant; the first (as assumed) also
    runs Table 9's free flights."""
    return [{"kind": "crash", "label": label, "changes": changes, "free_flight": not changes,
             "cost": 2.0} for label, changes in CRASH_VARIANTS.items()]


def report_task(task: dict) -> dict:
    """Worker of the scene runner: a column of Tables 11-12, a crash-test variant or a
    variant of an inferred geometry."""
    if task["kind"] == "crash":
        return ct.crash_run(task)
    if task["kind"] == "geometry":
        return geometry_run(task)
    if task["kind"] == "table10":
        return table10_search(task)
    if task["kind"] == "shaft":
        return shaft_contact.run_task(task)
    return column_task(task)


# ----------------------------------------------------- Table 10's model column: which variant


#: The report's model column of Table 10 (at the loss of contact): what the search aims at,
#: with the scale each miss is weighed by in the whole-column fit (about the printed digits
#: and the reading error of a number like it).
T10_TARGET_SCALES = {"time_ms": 1.0, "theta_deg": 1.0, "thetadot_rad_s": 0.1, "XCM_ft": 0.1,
                     "ZCM_ft": 0.05, "V1_ft_s": 1.0, "V3_ft_s": 1.0, "SV_ft": 0.1}

#: Section 5.2's spring (Figure 17's stiffnesses) over these impact heights (ft above the base).
T10_GRID_HEIGHTS = (1.0, 1.5, 2.0, 2.5, 3.0, 3.5)
T10_GRID_UNLOADING = {"38,400 then 12,000 below 3.0 in (as read)": {},
                      "12,000 only": {"unloading_stiffness_lb_per_ft": [12000.0, 12000.0]}}


def _plateau_lb(stop_ft: float) -> float:
    """The leaf spring's constant force beyond its stop (the loading line's value there)."""
    d = ct.crash_description()["leaf_spring"]
    k1, k2 = d["loading_stiffness_lb_per_ft"]
    return k1 * d["knee_ft"] + k2 * (stop_ft - d["knee_ft"])


def _loss_row(changes: dict) -> dict | None:
    _, loss, _ = ct.table10(ct.crash_scene(**changes))
    return loss


def _params(names, x) -> dict:
    out = {}
    for n, v in zip(names, x):
        if n == "unloading_lb_per_ft":
            out["unloading_stiffness_lb_per_ft"] = [float(v), float(v)]
        else:
            out[n] = float(v)
    return out


def table10_search(task: dict) -> dict:
    """Worker of the scene runner, one of three searches for the report's Table 10 model
    column (``task["search"]``):

    * ``grid``: section 5.2's spring (Figure 17's stiffnesses, its unloading as read or at
      12,000 lb/ft only) over the impact heights :data:`T10_GRID_HEIGHTS`;
    * ``two``: one unloading stiffness and the impact height solved (scipy least squares)
      for the contact lost at 71.8 ms and θ̇ 12.50 rad/s;
    * ``column``: one unloading stiffness, the impact height and the spring's constant force
      (its stop) fitted to the whole column (8 numbers, weighed by :data:`T10_TARGET_SCALES`)
      from several starts.
    """
    from scipy.optimize import least_squares

    if task["search"] == "grid":
        rows = []
        for label, changes in T10_GRID_UNLOADING.items():
            for s in T10_GRID_HEIGHTS:
                lo = _loss_row({**changes, "impact_height_ft": s})
                rows.append({"unloading": label, "impact_height_ft": s, "loss": lo})
        return {"rows": rows}
    target = {k: TABLE10[k][0] for k in T10_TARGET_SCALES}
    if task["search"] == "two":
        names, keys = ("unloading_lb_per_ft", "impact_height_ft"), ("time_ms", "thetadot_rad_s")
        lo_b, hi_b, starts = [1500.0, 0.5], [38400.0, 4.0], [[6000.0, 2.2]]
        x_scale = [1000.0, 0.1]
    else:
        names = ("unloading_lb_per_ft", "impact_height_ft", "stop_ft")
        keys = tuple(T10_TARGET_SCALES)
        lo_b, hi_b = [1500.0, 0.5, 0.25], [38400.0, 3.0, 0.6]
        starts = [[6000.0, 1.0, 0.3], [6000.0, 2.0, 0.375], [3000.0, 1.0, 0.26],
                  [12000.0, 1.0, 0.45]]
        x_scale = [1000.0, 0.1, 0.01]

    def resid(x):
        lo = _loss_row(_params(names, x))
        if lo is None:
            return [100.0] * len(keys)
        return [(lo[k] - target[k]) / T10_TARGET_SCALES[k] for k in keys]

    fits = [least_squares(resid, x0, bounds=(lo_b, hi_b), x_scale=x_scale, diff_step=1e-3)
            for x0 in starts]
    best = min(fits, key=lambda r: r.cost)
    params = _params(names, best.x)
    return {"names": list(names), "x": [float(v) for v in best.x],
            "starts_agree": max(abs(r.x[1] - best.x[1]) for r in fits) < 0.01,
            "starts": len(starts),
            "loss": _loss_row(params), "at_70": ct.table10(ct.crash_scene(**params))[2],
            "plateau_lb": _plateau_lb(params.get("stop_ft",
                                                 ct.crash_description()["leaf_spring"]["stop_ft"]))}


def table10_tasks() -> list[dict]:
    return [{"kind": "table10", "search": s, "cost": c}
            for s, c in (("grid", 1.0), ("two", 1.0), ("column", 4.0))]


def table10_section(lines, found: dict, ours: dict):
    """Issue 24, item 6: which variant of the crash test's model reproduces Table 10's model
    column (``found``: search -> :func:`table10_search`; ``ours``: our run's Table 10 row at
    the loss of contact)."""
    lines.append("### Table 10's model column: which variant reproduces it\n")
    lines.append(say("t10.intro", ours_ms=ours["time_ms"], ours_spin=ours["thetadot_rad_s"]))
    lines.append("| unloading | " + " | ".join(f"S {s:.1f} ft" for s in T10_GRID_HEIGHTS) + " |")
    lines.append("|---|" + "---|" * len(T10_GRID_HEIGHTS))
    rows = found["grid"]["rows"]
    for label in T10_GRID_UNLOADING:
        cells = []
        for r in rows:
            if r["unloading"] == label:
                lo = r["loss"]
                cells.append("—" if lo is None else
                             f"{lo['time_ms']:.1f} ms, {lo['thetadot_rad_s']:.2f} rad/s")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    ok = [r for r in rows if r["loss"] is not None]
    near = [r for r in ok if abs(r["loss"]["time_ms"] - 71.8) <= 5.0]
    top = max(ok, key=lambda r: r["loss"]["thetadot_rad_s"])["loss"]
    lines.append(say("t10.grid", top=top["thetadot_rad_s"], top_ms=top["time_ms"], near=say(
        "t10.grid_near", cases=", ".join(f"S {r['impact_height_ft']:.1f} ft, {r['unloading']}"
                                          for r in near),
        spins=", ".join(f"{r['loss']['thetadot_rad_s']:.2f}" for r in near))
        if near else say("t10.grid_none")))
    two, col = found["two"], found["column"]
    lines.append(say("t10.fits", two_k=two["x"][0], two_s=two["x"][1], starts=col["starts"],
                     agree="yes" if col["starts_agree"] else "no", col_k=col["x"][0],
                     col_s=col["x"][1], plateau=col["plateau_lb"]))
    lines.append("| quantity | report's model | two unknowns (fitted) | Δ | whole column (fitted) | Δ |")
    lines.append("|---|---|---|---|---|---|")
    for key, label, nd in T10_KEYS:
        m = TABLE10[key][0]
        a, b = two["loss"][key], col["loss"][key]
        lines.append(f"| {label} | {f(m, nd)} | {f(a, nd)} | {f(a - m, nd, True)} | "
                     f"{f(b, nd)} | {f(b - m, nd, True)} |")
    label = {k: lab.split(",")[0] for k, lab, _ in T10_KEYS}
    worst = max(T10_TARGET_SCALES, key=lambda k: abs(two["loss"][k] - TABLE10[k][0])
                / T10_TARGET_SCALES[k])
    lines.append(say(
        "t10.closing", worst=f"{label[worst]} {two['loss'][worst] - TABLE10[worst][0]:+.2f}",
        misses=", ".join(f"{label[k]} {col['loss'][k] - TABLE10[k][0]:+.2f}"
                         for k in T10_TARGET_SCALES),
        col_k=col["x"][0], col_s=col["x"][1], plateau=col["plateau_lb"]))


def hit_ft(xcm_ft: float, theta_deg: float, sv_ft: float) -> float:
    """Table 9's HIT as section 5.3 defines it, 'the distance from the front end of the
    vehicle to the point on the vehicle where the post strikes': read here as the distance
    along the car's path from the car's front (which met the post's axis at the impact, and
    has travelled SV towards -XX since) back to the post's top P (ft). Planar: P is
    ``post_length - cm_from_base`` along the post's axis from the mass centre, the axis at
    θ from the vertical, its top towards +XX."""
    d = ct.crash_description()
    return xcm_ft + (d["post_length_ft"] - d["cm_from_base_ft"]) * math.sin(
        math.radians(theta_deg)) + sv_ft


def crash_section(lines, fig_path, crash: dict, found: dict):
    """Chapter V's tables from the crash-test rows (label -> :func:`crash_test.crash_run`)
    and the searches for Table 10's model column (:func:`table10_search`)."""
    lines.append("## Chapter V: the crash test (Tables 9 and 10, Figure 18)\n")
    lines.append(say("crash.scene"))
    base = crash[next(iter(CRASH_VARIANTS))]
    loss, r70 = base["loss"], base["at_70"]
    lines.append("### Table 10: model against crash test at ~70 ms\n")
    lines.append("| quantity | report's model | crash test | ours at loss of contact | ours at 70 ms | ours − test (70 ms) |")
    lines.append("|---|---|---|---|---|---|")
    for key, label, nd in T10_KEYS:
        m, t = TABLE10[key]
        a, b = loss[key], r70[key]
        lines.append(f"| {label} | {f(m, nd)} | {f(t, nd)} | {f(a, nd)} | {f(b, nd)} | {f(b - t, nd, True)} |")
    ev = ", ".join(f"{name} {1000 * t:.1f} ms" for name, t in base["events"])
    x_m, x_set = base["leaf_spring_peak_compression_ft"], base["leaf_spring_set_ft"]
    lines.append(say("crash.events", events=ev, vv=abs(loss["VV_ft_s"]), peak_in=12 * x_m,
                     set_in=12 * x_set))
    ours_ms = 1000 * base["vehicle_contact_lost_s"]
    soft_ms = crash["unloading at 12,000 lb/ft only (no stiff branch)"]["loss"]["time_ms"]
    # every run of the section: the assumptions' variants and the grid of impact heights
    every = [(k, crash[k]["loss"]) for k in CRASH_VARIANTS] + [
        (f"S {r['impact_height_ft']:.1f} ft, unloading {r['unloading']}", r["loss"])
        for r in found["grid"]["rows"] if r["loss"] is not None]
    longest, lo_long = max(every, key=lambda kv: kv[1]["time_ms"])
    long_enough = [(k, lo) for k, lo in every if lo["time_ms"] >= 71.8]
    reach = (say("crash.reach_long", cases="; ".join(k for k, _ in long_enough),
                 spins=", ".join(f"{lo['thetadot_rad_s']:.2f}" for _, lo in long_enough))
             if long_enough else say("crash.reach_short"))
    lines.append(say("crash.early", ours_ms=ours_ms, early=71.8 - ours_ms, soft_ms=soft_ms,
                     gained=soft_ms - ours_ms, longest_ms=lo_long["time_ms"],
                     longest=longest, longest_spin=lo_long["thetadot_rad_s"],
                     n_runs=len(every), reach=reach, thetadot=loss["thetadot_rad_s"],
                     both=sum(lo["thetadot_rad_s"] >= 12.50 for _, lo in long_enough)))

    # sensitivity
    lines.append("### How much each assumption moves Table 10\n")
    lines.append("| variant | contact lost, ms | θ̇ at loss, rad/s | θ at 70 ms, deg | XCM 70 ms | ZCM 70 ms | V1 at loss | V3 at loss | SV at loss, ft | post hits ground, ms |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|")
    got = {}
    for label in CRASH_VARIANTS:
        r = crash[label]
        lo, s70 = r["loss"], r["at_70"]
        got[label] = lo
        hit = f(1000 * r["hit_time_s"], 1) if r["hit_time_s"] is not None else "—"
        lines.append(f"| {label} | {f(lo['time_ms'], 1)} | {f(lo['thetadot_rad_s'])} | "
                     f"{f(s70['theta_deg'], 1)} | {f(s70['XCM_ft'])} | {f(s70['ZCM_ft'])} | "
                     f"{f(lo['V1_ft_s'])} | {f(lo['V3_ft_s'])} | {f(lo['SV_ft'])} | {hit} |")
    hs = [got[k]["thetadot_rad_s"] for k in got if k.startswith(("S ", "as assumed"))]
    soft = got["unloading at 12,000 lb/ft only (no stiff branch)"]
    lines.append(say("crash.variants", lo=min(hs), hi=max(hs), soft_ms=soft["time_ms"],
                     soft_spin=soft["thetadot_rad_s"]))
    table10_section(lines, found, loss)

    lines.append("### Table 9: free flight from the crash test's state at 70 ms\n")
    lines.append(say("t9.intro", vv=abs(r70["VV_ft_s"])))
    lines.append("| quantity | report's model | crash test (Table 9) | crash test (Table 8) | ours at 270 ms | ours at 273 ms | ours − test (270 ms; XCM, ZCM signed as Table 8, SV as Table 9) | ours, car at 40 ft/s, 270 ms |")
    lines.append("|---|---|---|---|---|---|---|---|")
    a, b = base["table9"]["at_270"], base["table9"]["at_273"]
    c = base["table9_40"]["at_270"]
    for key, label, nd in [("theta_deg", "θ, deg", 1), ("XCM_ft", "XCM, ft", 2),
                           ("ZCM_ft", "ZCM, ft", 2), ("SV_ft", "SV, ft", 2), ("time_ms", "TIME, ms", 1)]:
        m, t = TABLE9[key]
        t8 = TABLE8[key][1] if key in TABLE8 else None
        taken = t8 if key in ("XCM_ft", "ZCM_ft", "theta_deg") else t  # see Inconsistencies
        lines.append(f"| {label} | {f(m, nd)} | {f(t, nd)} | {f(t8, nd)} | {f(a[key], nd)} | "
                     f"{f(b[key], nd)} | {f(a[key] - taken, nd, True)} | {f(c[key], nd)} |")
    hits = {"ours 270": hit_ft(a["XCM_ft"], a["theta_deg"], a["SV_ft"]),
            "ours 273": hit_ft(b["XCM_ft"], b["theta_deg"], b["SV_ft"]),
            "ours 40": hit_ft(c["XCM_ft"], c["theta_deg"], c["SV_ft"]),
            "model": hit_ft(-TABLE9["XCM_ft"][0], TABLE9["theta_deg"][0], TABLE9["SV_ft"][0]),
            "test9": hit_ft(-TABLE9["XCM_ft"][1], TABLE9["theta_deg"][1], TABLE9["SV_ft"][1]),
            "test8": hit_ft(TABLE8["XCM_ft"][1], TABLE8["theta_deg"][1], TABLE8["SV_ft"][1])}
    lines.append(f"| HIT, ft | {TABLE9['HIT_ft'][0]} | {TABLE9['HIT_ft'][1]} | — | "
                 f"{hits['ours 270']:.2f} | {hits['ours 273']:.2f} | "
                 f"{hits['ours 270'] - TABLE9['HIT_ft'][1]:+.2f} | {hits['ours 40']:.2f} |")
    lines.append(say("t9.closed_form", x=abs(a["XCM_ft"]), z=abs(a["ZCM_ft"]),
                     dx=abs(a["XCM_ft"]) - 7.61, dz=abs(a["ZCM_ft"]) - 0.27))
    lines.append(say("t9.hit", model=hits["model"], test9=hits["test9"], test8=hits["test8"],
                     model_miss=abs(hits["model"] - 7.55), miss9=hits["test9"] - 7.83,
                     miss8=hits["test8"] - 7.83))
    figure18(base, fig_path, a)
    lines.append(f"![Figure 18 regenerated]({FIG_NAME})\n")
    lines.append(say("fig18.caption"))
    return base, loss, r70, a


def post_line(xcm, zcm, theta_deg):
    th = math.radians(theta_deg)
    d = ct.crash_description()
    zc, L = d["cm_from_base_ft"], d["post_length_ft"]
    u = np.array([math.sin(th), math.cos(th)])
    c = np.array([xcm, zcm])
    return c - zc * u, c + (L - zc) * u


def figure18(run: dict, path, free: dict):
    """Figure 18 from a crash-test row (:func:`crash_test.crash_run`: its ``figure``) and our
    free flight from the test's 70 ms state at 270 ms (``free``: XCM_ft, ZCM_ft, theta_deg)."""
    from deck_emulator.studies.common import agg_backend

    agg_backend()
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4.5))
    marked = (0.07, 0.27)
    for t, qx, qz, px, pz in run["figure"]:
        if t not in marked:
            ax.plot([qx, px], [qz, pz], color="0.7", lw=1)
    for t, qx, qz, px, pz in run["figure"]:
        if t in marked:
            ax.plot([qx, px], [qz, pz], color="k", lw=2.5, label="ours" if t == marked[0] else None)
            ax.annotate(f"{1000 * t:.0f} ms", (px, pz), fontsize=8)
    for i, (xc, zc, th) in enumerate([(-1.50, 0.01, 25.0), (-7.10, -0.19, 122.0)]):
        q, p = post_line(xc, zc, th)
        ax.plot([q[0], p[0]], [q[1], p[1]], color="tab:red", lw=2,
                label="crash test (Table 8)" if i == 0 else None)
    q, p = post_line(TABLE10["XCM_ft"][0], TABLE10["ZCM_ft"][0], TABLE10["theta_deg"][0])
    ax.plot([q[0], p[0]], [q[1], p[1]], color="tab:blue", lw=1.5, ls="--",
            label="report's model, 71.8 ms (Table 10)")
    # Table 9 prints magnitudes; Table 8's signs (see the inconsistencies)
    q, p = post_line(-TABLE9["XCM_ft"][0], -TABLE9["ZCM_ft"][0], TABLE9["theta_deg"][0])
    ax.plot([q[0], p[0]], [q[1], p[1]], color="tab:blue", lw=1.5, ls=":",
            label="Table 9 'model', 273 ms: restarted from the test's 70 ms state")
    q, p = post_line(free["XCM_ft"], free["ZCM_ft"], free["theta_deg"])
    ax.plot([q[0], p[0]], [q[1], p[1]], color="tab:green", lw=1.5,
            label="ours restarted from the test's 70 ms state, 270 ms")
    ax.axhline(-run["ground_depth_ft"], color="tab:brown", lw=1)
    ax.set_aspect("equal")
    ax.set_xlabel("XX, ft (car moves towards −XX)")
    ax.set_ylabel("ZZ, ft (from the initial mass centre)")
    ax.set_title("Crash test, Figure 18 regenerated: post Q–P, ours every 20 ms")
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ------------------------------------------------------------------------ statements, sources


def statements_section(lines, runs, crash):
    base, loss, r70, f270 = crash
    lines.append("## The report's statements, checked\n")
    lines.append(say("statements.intro"))
    lead70 = "ahead of" if r70["theta_deg"] > 25.0 else "behind"
    lead270 = "ahead of" if base["at_270"]["theta_deg"] > 122.0 else "behind"
    figures = {
        "crash_lead": dict(lead70=lead70, lead270=lead270, t70=f"{r70['theta_deg']:.1f}°",
                           t270_free=f"{f270['theta_deg']:.1f}°",
                           t270=f"{base['at_270']['theta_deg']:.1f}°"),
        "crash_spin": dict(ours=f"{loss['thetadot_rad_s']:.2f}",
                           pct=f"{100 * (loss['thetadot_rad_s'] / 8.75 - 1):+.0f} %")}
    rows = [(f"{st.section}, line {st.line}: \"{st.quote}\"", st.why.format(**figures[st.rule]))
            for st in STATEMENTS if st.rule in figures]
    lines.append("\n| statement (`report/statements.py`) | what we find |")
    lines.append("|---|---|")
    for s, w in rows:
        lines.append(f"| {s} | {w} |")
    lines.append("")


def write_page(page: Path, *, jobs=None, scheduler=None, store_dir=None, resume=False,
               quiet=False) -> Path:
    """Write the page to ``page`` and its figure beside it (both, or neither); returns the
    figure's path. The 18 columns and the crash test's variants run on the one scene runner
    (:func:`deck_emulator.studies.common.run_longest_first`; ``store_dir``: where the runs are
    kept, a temporary folder if None; ``resume``: only the runs not stored)."""
    from deck_emulator.studies.distributed import run_longest_first

    page = Path(page)
    fig = page.with_name(FIG_NAME)
    t0 = time.perf_counter()
    tasks = (column_tasks(CASES_ALL) + crash_tasks() + geometry_tasks() + table10_tasks()
             + shaft_contact.tasks())
    rows = run_longest_first(report_task, tasks, jobs=jobs, desc="report_full",
                             store_dir=store_dir, quiet=quiet, scheduler=scheduler,
                             resume=resume)
    runs = {t["column"]: r for t, r in zip(tasks, rows) if t["kind"] == "column"}
    for t, r in zip(tasks, rows):  # the 20 mph columns with and without the shaft test
        if t["kind"] == "shaft":
            runs[t["column"]]["shaft" if t["shaft_contact"] else "shaft_off"] = r
    crash_rows = {t["label"]: r for t, r in zip(tasks, rows) if t["kind"] == "crash"}
    geometry_rows = {(t["post"], t["variant"], t["mph"]): r for t, r in zip(tasks, rows)
                     if t["kind"] == "geometry"}
    table10_rows = {t["search"]: r for t, r in zip(tasks, rows) if t["kind"] == "table10"}
    lines = ["# The report's Tables 9-12, all columns, against both engines\n"]
    lines.append(say("head", source=SOURCE, n_pred=predictions()))
    lines.append(say("contents"))
    with OutputSet() as files:  # the page and its figure: both, or neither
        summary_section(lines, runs, geometry_rows)
        provenance_section(lines)
        builder_section(lines)
        geometry_section(lines)
        geometry_sensitivity_section(lines, geometry_rows, runs)
        readings_section(lines, runs)
        columns_section(lines, runs, geometry_rows)
        doubtful_section(lines, runs)
        crash = crash_section(lines, files.path(fig), crash_rows, table10_rows)
        statements_section(lines, runs, crash)
        lines.append("## Inconsistencies in the source, and what we took\n")
        for i, s in enumerate(INCONSISTENCIES, 1):
            lines.append(f"{i}. {s}")
        lines.append("")
        lines.append("## Unfinished\n")
        lines.append("".join(f"* {u}\n" for u in UNFINISHED))
        lines.append(f"\n_Wall time of this script: {time.perf_counter() - t0:.0f} s._\n")
        files.write(page, "\n".join(lines))
    return fig
