"""The emulator and the core on one deck, side by side, and how their difference shrinks with h.

Both give the same quantities under the same definitions:

* loss of contact with the first spring and with the vehicle (s);
* the hit message and time;
* ``delta_v_contact_mph``: the speed the car lost up to loss of contact with the vehicle
  (the report's tables give ``delta_v_crush_mph``, by the end of the crush pulse: see
  ``deck-emulator summary``);
* ``max_decel_every_step_g``: the largest spring force over the car's weight, over every
  step of the contact phase (the emulator's every accepted step, not only the printed ones;
  the core's continuous maximum);
* terminal P, Q, R in the report's XL, YL, ZL axes (origin at the base of the support; the
  emulator's as its printout gives them);
(the quantities are the registry's, :mod:`deck_emulator.engine.quantities`)
* the largest distance between the two mass-centre trajectories, at the emulator's steps.

The convergence table runs the emulator with every "one step" literal divided by 2**k and the
core's ``legacy`` preset with the matching start-up step (``StartupKick(step_s=h)``) and force
cap time (20 steps), so that the difference measures the 1967 scheme's discretisation error.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from deck_emulator.core.scene import LEGACY, StartupKick
from deck_emulator.engine import CoreEngine, EmulatorEngine, errata as errata_policy, quantities


class DiffStopped(RuntimeError):
    """One of the runs the diff needs did not end (the message says which, and why)."""

H0 = 0.0004  # the listing's step, s
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
        "terminal_points_xl_yl_zl_ft": {p: tuple(out.terminal[p]) for p in POINTS},
    }


def legacy_options(h: float):
    """The core's legacy preset matched to the emulator at step h = H0/2**k: the start-up kick
    lasts one step h and tilts the post by 0.000022*h/H0 (both one-step literals of the
    emulator), and the FCONST cap is armed where the emulator arms it at every k: its label 358
    tests LL-20*2**k, so the first capped force is that of step 20*2**k + 1, at 20*H0 + h."""
    kick = LEGACY.startup_kick or StartupKick()
    kick = replace(kick, step_s=h, tilt_at_step_rad=kick.tilt_at_step_rad * h / H0)
    return replace(LEGACY, startup_kick=kick, force_cap_from_s=20 * H0 + h)


def max_trajectory_distance(run, result) -> float:
    """Largest distance (ft) between the mass centres at the emulator's accepted steps that lie
    in the core's run."""
    t = np.array([r["t"] for r in run.trace])
    xyz = np.array([[r["XCM"], r["YYCM"], r["ZZCM"]] for r in run.trace]).T
    traj = result.trajectory
    keep = (t >= traj.t_start) & (t <= traj.t_end)
    core = traj.mass_centre(t[keep])
    return float(np.max(np.linalg.norm(xyz[:, keep] - core, axis=0)))


def _terminal_distance(a: dict, b: dict) -> float:
    return max(math.dist(a["terminal_points_xl_yl_zl_ft"][p], b["terminal_points_xl_yl_zl_ft"][p])
               for p in POINTS)


def ed_tolerance(k: int) -> str:
    """ED's tolerance shrunk with the step: 1e-6 rad * 4**-k (the listing: .0001 at every k)."""
    return f"{1e-6 / 4**k:.3e}"


def diff_deck(deck, *, precision="double", errata=(), ks=range(5), rtol=1e-10, atol=1e-10,
              tighten_ed=True, progress=None) -> dict:
    """Run both engines; return {emulator, core, max_trajectory_diff_ft, convergence, ...}.

    The side-by-side values are the listing's run as printed (k = 0, ED tolerance .0001). The
    convergence rows from k = 1 on shrink ED's tolerance with the step (``tighten_ed``): with
    the printed .0001 rad the scheme does not converge (see ``as_printed_ed`` in the CLI)."""
    chosen = errata_policy.resolve(errata)
    core = CoreEngine(rtol=rtol, atol=atol)
    scene = core.scene(deck)
    convergence = []
    methods: set[str] = set()
    first = None

    def emulate(k, precision, tol):
        out = EmulatorEngine(precision=precision, errata=chosen, step_scale_k=k,
                             ed_tolerance=tol, trace=True).run(deck)
        if out.error:
            hint = f" -- {out.hint}" if out.hint else ""
            raise DiffStopped(f"the emulator stopped at k = {k}: {out.error}{hint}")
        return out

    for k in ks:
        h = H0 / 2**k
        if progress:
            progress(f"k = {k}: emulator with H = {h:g} s, core legacy preset with a {h:g} s start-up")
        tol = ed_tolerance(k) if tighten_ed else ".0001"
        em = emulate(k, precision if k == 0 else "double", tol)
        co = CoreEngine(options=legacy_options(h), rtol=rtol, atol=atol, trace=False).run(scene)
        if co.error is not None:  # CoreError and the like: one line, not a traceback
            raise DiffStopped(f"the core stopped at k = {k}: {co.error}")
        run, result = em.raw, co.raw
        emu, core_row = outcome_summary(em), outcome_summary(co)
        row = {
            "k": k,
            "h_s": h,
            "hit_time_diff_s": abs(emu["hit_time_s"] - core_row["hit_time_s"]),
            "terminal_points_diff_ft": _terminal_distance(emu, core_row),
            "max_trajectory_diff_ft": max_trajectory_distance(run, result),
            "same_hit": emu["hit"] == core_row["hit"],
            "errata": list(chosen),
            "ed_tolerance_rad": float(tol),
        }
        convergence.append(row)
        methods.add(result.method)
        if first is None:
            first = (emu, core_row, row)
            if tighten_ed:  # the side by side is the printed run: redo k = 0 with .0001
                em0 = emulate(0, precision, ".0001")
                first = (outcome_summary(em0), core_row, dict(
                    row, max_trajectory_diff_ft=max_trajectory_distance(em0.raw, result)))
    if first is None:
        raise DiffStopped("no step size to compare: give --max-k 0 or more")
    emu, core_row, row0 = first
    orders = {}
    for key in ("hit_time_diff_s", "terminal_points_diff_ft", "max_trajectory_diff_ft"):
        pairs = [(a[key], b[key]) for a, b in zip(convergence, convergence[1:]) if a[key] > 0 and b[key] > 0]
        orders[key] = [math.log2(a / b) for a, b in pairs]
    return {
        "deck": str(deck.path),
        "precision": precision,
        "errata": list(chosen),
        "core_method": "/".join(sorted(methods)),
        "core_rtol": rtol,
        "emulator": emu,
        "core": core_row,
        "max_trajectory_diff_ft": row0["max_trajectory_diff_ft"],
        "convergence": convergence,
        "observed_order": orders,
        "ed_tolerance_scaled": tighten_ed,
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
        for axis, a, b in zip(("XL", "YL", "ZL"), e["terminal_points_xl_yl_zl_ft"][p],
                              c["terminal_points_xl_yl_zl_ft"][p]):
            row(f"terminal {axis} of {p} (ft)", a, b, "{:.4f}")
    lines.append(f"hit: emulator {e['hit']}")
    lines.append(f"     core     {c['hit']}")
    lines.append(f"largest distance between the mass-centre trajectories: {d['max_trajectory_diff_ft']:.4f} ft")
    lines += ["", "as H is halved (emulator step literals / 2**k; core start-up over the same step; "
              + ("ED tolerance 1e-6 rad / 4**k" if d["ed_tolerance_scaled"] else "ED tolerance .0001 as printed")
              + "):",
              f"{'k':>2}{'H (s)':>12}{'hit time diff (s)':>20}{'terminal diff (ft)':>20}{'trajectory diff (ft)':>22}"]
    for r in d["convergence"]:
        lines.append(f"{r['k']:>2}{r['h_s']:>12.3e}{r['hit_time_diff_s']:>20.3e}"
                     f"{r['terminal_points_diff_ft']:>20.3e}{r['max_trajectory_diff_ft']:>22.3e}"
                     + ("" if r["same_hit"] else "   (different hit)"))
    for key, label in (("hit_time_diff_s", "hit time"), ("terminal_points_diff_ft", "terminal points"),
                       ("max_trajectory_diff_ft", "trajectory")):
        ords = d["observed_order"][key]
        lines.append(f"observed order ({label}): " + (", ".join(f"{o:.2f}" for o in ords) or "n/a"))
    return "\n".join(lines) + "\n"
