"""The emulator and the core on one deck, side by side, and how their difference shrinks with h.

Both give the same quantities under the same definitions:

* loss of contact with the first spring and with the vehicle (s);
* the hit message and time;
* ``delta_v_mph``: the speed the car lost up to loss of contact with the vehicle;
* ``max_decel_g``: the largest spring force over the car's weight, over the contact phase;
* terminal P, Q, R in the report's XL, YL, ZL axes (origin at the base of the support);
* the largest distance between the two mass-centre trajectories, at the emulator's steps.

The convergence table runs the emulator with every "one step" literal divided by 2**k and the
core's ``legacy`` preset with the matching start-up step (``StartupKick(step_s=h)``) and force
cap time (20 steps), so that the difference measures the 1967 scheme's discretisation error.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from deck_emulator.core import LEGACY, StartupKick, simulate
from deck_emulator.core.result import MPH_PER_FT_S
from deck_emulator.legacy.emulator import EmulatorError, Run, run_deck
from deck_emulator.core.scene import Scene

H0 = 0.0004  # the listing's step, s
POINTS = ("P", "Q", "R")


def emulator_summary(run: Run, deck) -> dict:
    """The diff's quantities from one emulator run (its trace and events)."""
    d = deck.values
    contact = [r for r in run.trace if r["phase"] == "contact"]
    events = dict((m, t) for m, t in run.events)
    last = run.trace[-1]
    hit = run.events[-1][0] if run.events and "HIT" in run.events[-1][0] else None
    terminal = {
        p: (last[f"X{p}"] - d["XQO"], last[f"YY{p}"] - d["YYQO"], last[f"ZZ{p}"] + d["HEIGHT"])
        for p in POINTS
    }
    return {
        "hit": hit,
        "hit_time_s": run.events[-1][1] if hit else None,
        "first_spring_lost_s": events.get("THE POST HAS LOST CONTACT WITH FIRST SPRING"),
        "vehicle_contact_lost_s": events.get("THE POST HAS LOST CONTACT WITH THE VEHICLE"),
        "delta_v_mph": (abs(d["VVB"]) - abs(contact[-1]["VV"])) * MPH_PER_FT_S,
        "max_decel_g": max(r["FS"] for r in contact) / (d["WV"] * d["G"]),
        "terminal_points_xl_yl_zl_ft": terminal,
    }


def core_summary(result) -> dict:
    s = result.summary()
    keep = ("hit", "hit_time_s", "first_spring_lost_s", "vehicle_contact_lost_s", "delta_v_mph",
            "max_decel_g", "terminal_points_xl_yl_zl_ft")
    out = {k: s[k] for k in keep}
    out["terminal_points_xl_yl_zl_ft"] = {p: tuple(out["terminal_points_xl_yl_zl_ft"][p]) for p in POINTS}
    return out


def legacy_options(h: float):
    """The core's legacy preset matched to the emulator at step h = H0/2**k: the start-up kick
    lasts one step h and tilts the post by 0.000022*h/H0 (both one-step literals of the
    emulator), and the FCONST cap is armed where the emulator arms it at every k: its label 358
    tests LL-20*2**k, so the first capped force is that of step 20*2**k + 1, at 20*H0 + h."""
    kick = LEGACY.startup_kick or StartupKick()
    kick = replace(kick, step_s=h, tilt_at_step_rad=kick.tilt_at_step_rad * h / H0)
    return replace(LEGACY, startup_kick=kick, force_cap_from_s=20 * H0 + h)


def max_trajectory_distance(run: Run, result) -> float:
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
    scene = Scene.from_deck(deck)
    convergence = []
    first = None
    for k in ks:
        h = H0 / 2**k
        if progress:
            progress(f"k = {k}: emulator with H = {h:g} s, core legacy preset with a {h:g} s start-up")
        row_errata = tuple(errata)
        tol = ed_tolerance(k) if tighten_ed else ".0001"
        kw = dict(step_scale_k=k, ed_tolerance=tol)
        try:
            run = run_deck(deck, precision if k == 0 else "double", errata=row_errata, **kw)
        except EmulatorError as exc:
            if exc.guard != "ed_iterations" or "ed-direction" in row_errata:
                raise
            # as printed, ED walks away from its root at this step size: say so, apply the erratum
            row_errata += ("ed-direction",)
            run = run_deck(deck, precision if k == 0 else "double", errata=row_errata, **kw)
        result = simulate(scene, legacy_options(h), rtol=rtol, atol=atol)
        emu, core = emulator_summary(run, deck), core_summary(result)
        row = {
            "k": k,
            "h_s": h,
            "hit_time_diff_s": abs(emu["hit_time_s"] - core["hit_time_s"]),
            "terminal_points_diff_ft": _terminal_distance(emu, core),
            "max_trajectory_diff_ft": max_trajectory_distance(run, result),
            "same_hit": emu["hit"] == core["hit"],
            "errata": list(row_errata),
            "ed_tolerance_rad": float(tol),
        }
        convergence.append(row)
        if first is None:
            first = (emu, core, row)
            if tighten_ed:  # the side by side is the printed run: redo k = 0 with .0001
                run0 = run_deck(deck, precision, errata=row_errata, step_scale_k=0)
                first = (emulator_summary(run0, deck), core, dict(
                    row, max_trajectory_diff_ft=max_trajectory_distance(run0, result)))
    emu, core, row0 = first
    orders = {}
    for key in ("hit_time_diff_s", "terminal_points_diff_ft", "max_trajectory_diff_ft"):
        pairs = [(a[key], b[key]) for a, b in zip(convergence, convergence[1:]) if a[key] > 0 and b[key] > 0]
        orders[key] = [math.log2(a / b) for a, b in pairs]
    return {
        "deck": str(deck.path),
        "precision": precision,
        "errata": list(errata),
        "core_method": "DOP853",
        "core_rtol": rtol,
        "emulator": emu,
        "core": core,
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
    row("hit time (s)", e["hit_time_s"], c["hit_time_s"])
    row("delta-V (mph)", e["delta_v_mph"], c["delta_v_mph"], "{:.4f}")
    row("max deceleration (g)", e["max_decel_g"], c["max_decel_g"], "{:.4f}")
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
                     + ("" if r["same_hit"] else "   (different hit)")
                     + (f"   (erratum {', '.join(r['errata'])})" if r["errata"] != d["errata"] else ""))
    for key, label in (("hit_time_diff_s", "hit time"), ("terminal_points_diff_ft", "terminal points"),
                       ("max_trajectory_diff_ft", "trajectory")):
        ords = d["observed_order"][key]
        lines.append(f"observed order ({label}): " + (", ".join(f"{o:.2f}" for o in ords) or "n/a"))
    return "\n".join(lines) + "\n"
