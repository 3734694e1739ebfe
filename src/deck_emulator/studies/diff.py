"""The emulator and the core on one deck, side by side, and how their difference shrinks with h.

Both are read through the registry (:data:`COMPARED`, the terminal P, Q, R, and the largest
distance between the mass-centre trajectories at the emulator's steps). The convergence table
runs the emulator with every "one step" literal divided by 2**k against the core's ``legacy``
preset matched to that step (:func:`legacy_options`), so that the difference measures the 1967
scheme's discretisation error; its rows apply the erratum ``ed-direction`` unless told not to
(``ed_direction_rows``): as printed, SUBROUTINE ED walks away from its root on every deck once
the step is halved.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from deck_emulator.engine import CoreEngine, EmulatorEngine, quantities
from deck_emulator.engine import errata as errata_policy
from deck_emulator.engine.sources import parse_deck
from deck_emulator.studies.distributed import run_longest_first
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.scene import LEGACY, StartupKick


class DiffStopped(RuntimeError):
    """One of the runs the diff needs did not end (the message says which, and why)."""

H0 = defaults.LISTING_STEP_S
POINTS = ("P", "Q", "R")


#: The quantities diff sets side by side (the registry's names and definitions).
COMPARED = ("hit_time_s", "first_spring_lost_s", "vehicle_contact_lost_s",
              "delta_v_contact_mph", "max_decel_every_step_g")


def outcome_summary(out) -> dict:
    """The diff's quantities of one engine's outcome: the hit, the registry's
    :data:`COMPARED`, the terminal P, Q, R (XL, YL, ZL, ft)."""
    return {
        "hit": out.hit.short() if out.hit else None,
        **quantities.values(out, COMPARED),
        "terminal_xl_yl_zl_ft": {p: tuple(out.terminal[p]) for p in POINTS},
    }


def legacy_options(h: float):
    """The core's legacy preset matched to the emulator at step h = H0/2**k: the start-up kick
    lasts one step h and tilts the post by 0.000022*h/H0 (both one-step literals of the
    emulator), and the FCONST cap is armed where the emulator arms it at every k: its label 358
    tests LL-20*2**k, so the first capped force is that of step 20*2**k + 1, at 20*H0 + h."""
    kick = LEGACY.startup_kick or StartupKick()
    kick = replace(kick, step_s=h, tilt_at_step_rad=kick.tilt_at_step_rad * h / H0)
    return replace(LEGACY, startup_kick=kick, force_cap_from_s=defaults.LISTING_CAP_STEPS * H0 + h)


def max_trajectory_distance(emulator, core) -> float:
    """Largest distance (ft) between the mass centres of an emulator outcome at its accepted
    steps that lie in the core outcome's run, and the core's there (NaN: no step there)."""
    t, xyz = emulator.accepted_steps()
    t_start, t_end = core.span
    keep = (t >= t_start) & (t <= t_end)
    if not keep.any():
        return math.nan
    return float(np.max(np.linalg.norm(xyz[:, keep] - core.position("CM", t[keep]), axis=0)))


def _terminal_distance(a: dict, b: dict) -> float:
    return max(math.dist(a["terminal_xl_yl_zl_ft"][p], b["terminal_xl_yl_zl_ft"][p])
               for p in POINTS)


def ed_tolerance(k: int) -> str:
    """ED's tolerance shrunk with the step: 1e-6 rad * 4**-k (the listing: .0001 at every k)."""
    return f"{1e-6 / 4**k:.3e}"


def row_errata(errata=(), ed_direction_rows=True) -> tuple[str, ...]:
    """The errata of the convergence rows: those asked for, and ``ed-direction`` unless
    ``ed_direction_rows`` is False."""
    chosen = errata_policy.resolve(errata)
    return errata_policy.resolve((*chosen, errata_policy.ED_DIRECTION)) if ed_direction_rows \
        else chosen


def diff_tasks(deck, *, precision="double", errata=(), ks=range(5), rtol=defaults.CORE_RTOL,
               atol=defaults.CORE_ATOL,
               tighten_ed=True, ed_direction_rows=True) -> list[dict]:
    """The diff's runs as tasks of the scene runner: one per k (the emulator and the core at
    the step H0/2**k, side by side in one task, since the trajectory difference needs both
    runs in one process). The deck travels as its card images. ``errata``: the side by side's
    (the listing's run); the rows take :func:`row_errata`."""
    chosen = list(errata_policy.resolve(errata))
    rows = list(row_errata(errata, ed_direction_rows))
    return [{"kind": "diff", "deck": str(deck.path or ""), "cards": "\n".join(deck.cards) + "\n",
             "k": int(k), "precision": precision if k == 0 else "double", "errata": chosen,
             "row_errata": rows,
             "rtol": float(rtol), "atol": float(atol), "tighten_ed": bool(tighten_ed),
             "cost": 2.0**k} for k in ks]


def diff_step(task: dict) -> dict:
    """Worker: one k of the diff -> plain values: ``stopped`` (why a run did not end, or
    None), the two engines' :func:`outcome_summary`, the convergence row, the core's method,
    and at k = 0 with a tightened ED also ``printed``: the emulator's run as printed (ED's
    tolerance .0001) and its trajectory difference."""

    deck = parse_deck(task["cards"], path=task["deck"] or None)
    k, given = task["k"], tuple(task["errata"])
    errata = tuple(task.get("row_errata", given))
    h = H0 / 2**k
    tol = ed_tolerance(k) if task["tighten_ed"] else defaults.LISTING_ED_TOLERANCE

    def emulate(tolerance, errata=errata):
        return EmulatorEngine(precision=task["precision"], errata=errata, step_scale_k=k,
                              ed_tolerance=tolerance, trace=True).run(deck)

    def stopped(out, who):
        hint = f" -- {out.hint}" if out.hint else ""
        return {"k": k, "stopped": f"the {who} stopped at k = {k}: {out.error}{hint}"}

    em = emulate(tol)
    if em.error:
        return stopped(em, "emulator")
    co = CoreEngine(options=legacy_options(h), rtol=task["rtol"], atol=task["atol"],
                    trace=False).run(CoreEngine().scene(deck), name=deck.path or "")
    if co.error is not None:  # CoreError and the like: one line, not a traceback
        return {"k": k, "stopped": f"the core stopped at k = {k}: {co.error}"}
    emu, core_row = outcome_summary(em), outcome_summary(co)
    out = {"k": k, "stopped": None, "method": co.method, "emulator": emu, "core": core_row,
           "row": {
               "k": k,
               "h_s": h,
               "hit_time_diff_s": abs(emu["hit_time_s"] - core_row["hit_time_s"]),
               "terminal_points_diff_ft": _terminal_distance(emu, core_row),
               "max_trajectory_diff_ft": max_trajectory_distance(em, co),
               "same_hit": emu["hit"] == core_row["hit"],
               "errata": list(errata),
               "ed_tolerance_rad": float(tol),
           }}
    if k == 0 and (task["tighten_ed"] or errata != given):
        # the side by side is the listing's run: ED at .0001, the errata asked for
        em0 = emulate(defaults.LISTING_ED_TOLERANCE, given)
        if em0.error:
            return stopped(em0, "emulator")
        out["printed"] = {"emulator": outcome_summary(em0),
                          "max_trajectory_diff_ft": max_trajectory_distance(em0, co)}
    return out


def diff_deck(deck, *, precision="double", errata=(), ks=range(5), rtol=defaults.CORE_RTOL,
              atol=defaults.CORE_ATOL,
              tighten_ed=True, ed_direction_rows=True, jobs=None, scheduler=None, store_dir=None, resume=False,
              quiet=False, desc="diff", files=None) -> dict:
    """Run both engines; return {emulator, core, max_trajectory_diff_ft, convergence, ...}.

    The side-by-side values are the listing's run as printed (k = 0, ED tolerance .0001). The
    convergence rows from k = 1 on shrink ED's tolerance with the step (``tighten_ed``): with
    the printed .0001 rad the scheme does not converge (see ``as_printed_ed`` in the CLI); the
    rows apply ``ed-direction`` as well unless ``ed_direction_rows`` is False.

    The ks run on the one scene runner (:func:`deck_emulator.studies.common.run_longest_first`:
    ``jobs`` workers or the cluster at ``scheduler``), stored in ``store_dir`` (a temporary
    folder if None; ``resume`` runs only the ks not stored; ``files``: the SHA-256 of the deck's
    file as the caller read it, else it is read again). A run that did not end raises
    :class:`DiffStopped` naming the smallest k at which one stopped."""
    options = dict(precision=precision, errata=errata, ks=ks, rtol=rtol, atol=atol,
                   tighten_ed=tighten_ed, ed_direction_rows=ed_direction_rows)
    return diff_decks([(deck, options)], jobs=jobs, scheduler=scheduler, store_dir=store_dir,
                      resume=resume, quiet=quiet, desc=desc, files=files)[0]


def diff_decks(cases, *, jobs=None, scheduler=None, store_dir=None, resume=False,
               quiet=False, desc="diff", files=None) -> list[dict]:
    """:func:`diff_deck` of each ``(deck, options)`` in ``cases`` (options: the keywords of
    :func:`diff_tasks`), all their runs in one call of the scene runner (``desc``: its
    progress bar's label; ``files``: as :func:`run_scenes`)."""

    plans = []
    for deck, options in cases:
        tasks = diff_tasks(deck, **options)
        if not tasks:
            raise DiffStopped("no step size to compare: give --max-k 0 or more")
        plans.append((deck, options, tasks))
    steps = run_longest_first(diff_step, [t for _, _, tasks in plans for t in tasks], jobs=jobs,
                              desc=desc, store_dir=store_dir, quiet=quiet,
                              scheduler=scheduler, resume=resume, core=True, files=files)
    out, at = [], 0
    for deck, options, tasks in plans:
        out.append(_diff_result(deck, options, steps[at:at + len(tasks)]))
        at += len(tasks)
    return out


def _diff_result(deck, options: dict, steps: list[dict]) -> dict:
    """The diff of one deck from its ks' steps. A run that stops at k = 0 leaves nothing to
    compare (:class:`DiffStopped`); one that stops at a smaller step is a row that says so
    (``stopped``), and the observed orders use the consecutive rows that ran."""
    if steps[0]["stopped"]:
        raise DiffStopped(steps[0]["stopped"])
    convergence = [step["row"] if not step["stopped"] else
                   {"k": step["k"], "h_s": H0 / 2**step["k"], "stopped": step["stopped"]}
                   for step in steps]
    stopped = [r for r in convergence if r.get("stopped")]
    first = steps[0]
    emu, core_row, row0 = first["emulator"], first["core"], first["row"]
    if "printed" in first:
        emu = first["printed"]["emulator"]
        row0 = dict(row0, max_trajectory_diff_ft=first["printed"]["max_trajectory_diff_ft"])
    orders = {}
    ran = [(a, b) for a, b in zip(convergence, convergence[1:])
           if not a.get("stopped") and not b.get("stopped")]
    for key in ("hit_time_diff_s", "terminal_points_diff_ft", "max_trajectory_diff_ft"):
        pairs = [(a[key], b[key]) for a, b in ran if a[key] > 0 and b[key] > 0]
        orders[key] = [math.log2(a / b) for a, b in pairs]
    return {
        "deck": str(deck.path),
        "precision": options.get("precision", "double"),
        "errata": list(errata_policy.resolve(options.get("errata", ()))),
        "row_errata": list(row_errata(options.get("errata", ()),
                                      options.get("ed_direction_rows", True))),
        "core_method": "/".join(sorted({step["method"] for step in steps if not step["stopped"]})),
        "core_rtol": options.get("rtol", defaults.CORE_RTOL),
        "emulator": emu,
        "core": core_row,
        "max_trajectory_diff_as_printed_ft": row0["max_trajectory_diff_ft"],
        "convergence": convergence,
        "stopped_from_k": stopped[0]["k"] if stopped else None,
        "observed_order": orders,
        "ed_tolerance_scaled": options.get("tighten_ed", True),
    }


def format_diff(d: dict) -> str:
    """The diff as a readable table."""
    e, c = d["emulator"], d["core"]
    lines = [
        f"deck {d['deck']}: emulator ({d['precision']}, errata: {', '.join(d['errata']) or 'none'}) "
        f"against the core (legacy preset, {d['core_method']}, rtol {d['core_rtol']:g})",
        "",
        f"{'quantity':<34}{'emulator':>16}{'core':>16}{'difference':>14}",
    ]

    def row(name, a, b, fmt="{:.6f}"):
        if isinstance(a, str) or isinstance(b, str) or a is None or b is None:
            lines.append(f"{name:<34}{str(a):>16}{str(b):>16}")
        else:
            lines.append(f"{name:<34}{fmt.format(a):>16}{fmt.format(b):>16}{fmt.format(a - b):>14}")

    row("lost first spring (s)", e["first_spring_lost_s"], c["first_spring_lost_s"])
    row("lost the vehicle (s)", e["vehicle_contact_lost_s"], c["vehicle_contact_lost_s"])
    row("post hits, hit_time_s (s)", e["hit_time_s"], c["hit_time_s"])
    row("delta_v_contact_mph (mph)", e["delta_v_contact_mph"], c["delta_v_contact_mph"],
        "{:.4f}")
    row("max_decel_every_step_g (g)", e["max_decel_every_step_g"],
        c["max_decel_every_step_g"], "{:.4f}")
    for p in POINTS:
        for axis, a, b in zip(("XL", "YL", "ZL"), e["terminal_xl_yl_zl_ft"][p],
                              c["terminal_xl_yl_zl_ft"][p]):
            row(f"terminal {axis} of {p} (ft)", a, b, "{:.4f}")
    lines.append(f"hit: emulator {e['hit']}")
    lines.append(f"     core     {c['hit']}")
    lines.append("largest distance between the mass-centre trajectories (the listing as "
                 f"printed, ED's tolerance .0001 rad): {d['max_trajectory_diff_as_printed_ft']:.4f} ft")
    lines += ["", "as H is halved (emulator step literals / 2**k; core start-up over the same step; "
              + ("ED tolerance 1e-6 rad / 4**k" if d["ed_tolerance_scaled"] else "ED tolerance .0001 as printed")
              + ("" if d["row_errata"] == d["errata"] else
                 f"; errata: {', '.join(d['row_errata']) or 'none'}, since as printed ED walks "
                 "away from its root once the step is halved")
              + "):",
              f"{'k':>2}{'H (s)':>12}{'hit time diff (s)':>20}{'terminal diff (ft)':>20}{'trajectory diff (ft)':>22}"]
    for r in d["convergence"]:
        if r.get("stopped"):
            lines.append(f"{r['k']:>2}{r['h_s']:>12.3e}   stopped: {r['stopped']}")
            continue
        lines.append(f"{r['k']:>2}{r['h_s']:>12.3e}{r['hit_time_diff_s']:>20.3e}"
                     f"{r['terminal_points_diff_ft']:>20.3e}{r['max_trajectory_diff_ft']:>22.3e}"
                     + ("" if r["same_hit"] else "   (different hit)"))
    scaled, more = d["ed_tolerance_scaled"], d["row_errata"] != d["errata"]
    if scaled or more:
        row = " with ".join((["ED at 1e-6 rad"] if scaled else [])
                           + ([f"errata {', '.join(d['row_errata'])}"] if more else []))
        side = ", ".join((["ED at .0001 rad"] if scaled else [])
                         + ([f"errata: {', '.join(d['errata']) or 'none'}"] if more else []))
        lines.append(f"(the k = 0 row runs {row}, like the rows below it; the side by side "
                     f"above is the listing as printed, {side}: hence two k = 0 trajectory "
                     "differences)")
    if d.get("stopped_from_k") is not None:
        lines.append(f"note: the emulator ({', '.join(d['row_errata']) or 'no errata'}) cannot run "
                     f"this deck from k = {d['stopped_from_k']} on (the rows say why); the orders "
                     "below use the rows that ran")
    from deck_emulator.studies.orders import QUANTISED, order_fit

    ran = [r for r in d["convergence"] if not r.get("stopped")]
    lines.append(f"order (hit time): none: {QUANTISED}")
    for key, label in (("terminal_points_diff_ft", "terminal points"),
                       ("max_trajectory_diff_ft", "trajectory")):
        fit = order_fit([r["h_s"] for r in ran], [r[key] for r in ran])
        lines.append(f"observed order ({label}): {fit.text()}")
    return "\n".join(lines) + "\n"
