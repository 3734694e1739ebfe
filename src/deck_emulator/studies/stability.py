"""Stability study: the emulator and the core on stiff springs and extreme scenes derived from
steel40, and the stability of both stated from the scheme and the model (:func:`scheme_growth`:
the 1967 scheme's one-step matrix on a spring; :func:`contact_spectrum`: the eigenvalues of the
core's contact Jacobian).

Every scene runs on both engines; the emulator's end is classed against the core's
(:func:`classify`). How each runs and what the classes mean is said on the page the study
writes (``templates/stability_study.md``).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
import time
from pathlib import Path

import numpy as np

from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.scene import (
    LISTING_BASE_FRICTION,
    PHYSICAL,
    BaseFriction,
    Scene,
)
from deck_emulator.engine import Limits
from deck_emulator.vocabulary.events import EventKind
from deck_emulator.files import OutputSet, check_output_dir
from deck_emulator.studies.diff import ed_tolerance as tight_ed_tolerance
from deck_emulator.studies.store import output_store
from deck_emulator.studies.sweep import read_base, vvb_for

from .pages import page, snippet
from .common import (
    ERRATA,
    H0,
    agg_backend,
    cpu_count,
    csv_text,
    default_deck,
    emulator_hit,
    energies,
    fmt,
    machine,
    machine_line,
    legacy_options,
    md_table,
    run_core,
    run_emulator,
    run_longest_first,
)

LIMITS = Limits(ed_iterations=defaults.STABILITY_ED_ITERATIONS,
                halvings=defaults.STABILITY_HALVINGS, time_s=defaults.STUDY_T_MAX_S)
CORE_RTOL = defaults.STUDY_RTOL
CORE_T_MAX_S = defaults.STUDY_T_MAX_S
AGREE_HIT_S = defaults.STABILITY_AGREE_HIT_S
AGREE_KE = defaults.STABILITY_AGREE_KE
#: the group of the scenes whose crush springs are made stiffer: "stiff spring", not "stiff" --
#: their contact's fast mode is the answer itself, resolved by any method that gets it right
#: (the page's "Stability from the scheme and the model")
STIFF_SPRING = "stiff spring"

COLUMNS = [
    "scene", "group", "description", "CK_lb_ft", "k", "H_s", "h_omega", "speed_mph", "alpha_deg",
    "emulator_class", "emulator_status", "emulator_guard", "emulator_error", "emulator_hit",
    "emulator_hit_time_s", "emulator_vehicle_contact_lost_s", "emulator_launch_ke_ftlb", "emulator_free_flight_energy_drift",
    "emulator_wall_s", "emulator_steps",
    "core_status", "core_error", "core_hit", "core_hit_time_s", "core_vehicle_contact_lost_s", "core_launch_ke_ftlb",
    "core_free_flight_energy_drift", "core_wall_s", "core_nfev",
    "core_warnings", "core_lowest_at_release_ft", "core_base_travel_ft", "hit_time_diff_s", "launch_ke_rel_diff", "traj_diff_ft",
    "ed_tolerance", "core_notes",
    "physical_status", "physical_error", "physical_hit", "physical_hit_time_s", "physical_notes",
]


# --------------------------------------------------------------------------- the scenes


def _scene(sid, group, description, deck=None, *, k=0, tha=None, friction="listing",
           emulator=True, ed=defaults.LISTING_ED_TOLERANCE, **params):
    return {"scene": sid, "group": group, "description": description, "deck": deck or {},
            "k": k, "tha": tha, "friction": friction, "emulator": emulator, "ed_tolerance": ed,
            **params}


def scenes(base: dict, quick: bool) -> list[dict]:
    """The grid.  ``base``: the steel40 deck's values (for the scaled fields)."""
    out = []
    cks = (3.3e4, 1e7, 1e9) if quick else (3.3e4, 1e5, 3.3e5, 1e6, 3.3e6, 1e7, 3.3e7, 1e8,
                                            3.3e8, 1e9, 3.3e9, 1e10)
    ks = (0, 1) if quick else (0, 1, 2, 3, 4)
    for ck in cks:
        for k in ks:
            h = H0 / 2**k
            out.append(_scene(
                f"spring-{ck:.2g}-k{k}", STIFF_SPRING, f"CK = CT = {ck:.3g} lb/ft, H = {h:.3g} s",
                {"CK": ck, "CT": ck}, k=k, ed=tight_ed_tolerance(k), CK_lb_ft=ck, H_s=h,
                h_omega=h * math.sqrt(ck / base["W"])))
    out.append(_scene("base", "extreme", "steel40 as it is (40 mph, alpha 0, delta 0.1463)"))
    speeds = (5, 120) if quick else (5, 10, 20, 30, 60, 80, 100, 120)
    for mph in speeds:
        out.append(_scene(f"speed-{mph}", "speed", f"{mph} mph",
                          {"VVB": vvb_for(mph)}, speed_mph=mph))
    top = int(defaults.MAX_APPROACH_ANGLE_DEG)  # the largest angle a scene may have
    angles = (top,) if quick else tuple(range(15, top + 1, 15))
    for deg in angles:
        out.append(_scene(f"angle-{deg}", "approach angle", f"alpha = {deg} deg",
                          {"ALPHA": round(math.radians(deg), 5)}, alpha_deg=deg))
    if not quick:
        out.append(_scene("delta-0", "extreme", "untilted post: DELTA = 0", {"DELTA": 0.0}))
    thas = ("0.0", "1.5") if quick else ("0.0", "0.000001", "0.001", "0.01", "0.1", "0.5", "1.0",
                                         "1.5")
    for tha in thas:
        out.append(_scene(f"tha-{tha}", "start-up THA",
                          f"start-up THA = {tha} rad (printed {defaults.LISTING_THA_START})",
                          tha=tha))
    a = base["A"]
    out.append(_scene("abc-equal", "extreme", f"A = B = C = {a:g} slug ft^2",
                      {"A": a, "B": a, "C": a}))
    for f, name in ((10.0, "heavy"), (0.1, "light")):
        if quick and f == 10.0:
            continue
        changes = {n: round(base[n] * f, 5) for n in ("W", "A", "B", "C", "FNA")}
        out.append(_scene(f"{name}-post", "extreme",
                          f"{name} post: W, A, B, C and FNA (its weight) x {f:g}", changes))
    frictions = ((93000.0, "large"),) if quick else ((0.0, "zero"), (93000.0, "large"))
    for force, name in frictions:
        out.append(_scene(f"friction-{name}", "base friction",
                          f"base friction {force:g} lb (listing: 930 lb)",
                          friction=force, emulator=False))
    thbs = (1.5,) if quick else (1.0, 1.5, 1.5707)
    for thb in thbs:
        out.append(_scene(f"thb-{thb}", "theta near 90 deg",
                          f"deck THB = {thb} rad ({math.degrees(thb):.1f} deg)", {"THB": thb}))
    return out


# --------------------------------------------------------------------------- the runs


def _task(spec: dict, bases: dict) -> dict:
    """A worker's run of one scene; ``bases``: path -> the base deck read by the command,
    handed on with the function, so that no worker reads the file."""
    deck = bases[spec["deck_path"]].with_values(**spec["deck"])
    if spec["engine"] == "emulator":
        return _task_emulator(spec, deck)
    return _task_core(spec, deck)


def _task_emulator(spec, deck) -> dict:
    out = run_emulator(deck, k=spec["k"], tha_start=spec["tha"], limits=LIMITS, errata=ERRATA,
                       ed_tolerance=spec["ed_tolerance"])
    run = out["outcome"]
    t, xyz = run.accepted_steps()
    message, hit_time = emulator_hit(out)
    release = next((e.time_s for e in run.events if e.kind is EventKind.LOST_VEHICLE), None)
    row = {"emulator_status": out["status"], "emulator_guard": out["guard"],
           "emulator_error": out["error"], "emulator_hit": message, "emulator_hit_time_s": hit_time,
           "emulator_vehicle_contact_lost_s": release, "emulator_wall_s": out["wall_s"],
           "emulator_steps": t.size, "_t": t, "_xyz": xyz}
    e = energies(out)
    row["emulator_launch_ke_ftlb"], row["emulator_free_flight_energy_drift"] = e["launch_ke_ftlb"], e["free_drift"]
    return row


def core_case(spec, deck):
    """The core's scene and model options for one scene of the grid (``spec`` from
    :func:`scenes`, ``deck`` its deck): the listing's step matched, the start-up tilt and the
    base's friction as the spec says."""
    scene = Scene.from_deck(deck)
    options = legacy_options(H0 / 2 ** spec["k"])
    if spec["tha"] is not None:
        options = dataclasses.replace(options, startup_kick=dataclasses.replace(
            options.startup_kick, tilt_at_step_rad=float(spec["tha"])))
    if spec["friction"] != "listing":
        friction = (None if spec["friction"] == 0.0 else
                    BaseFriction(spec["friction"], LISTING_BASE_FRICTION.slip_window_ft))
        scene = dataclasses.replace(scene, base=dataclasses.replace(scene.base, friction=friction))
        options = dataclasses.replace(options, listing_friction=False)
    return scene, options


def _task_core(spec, deck) -> dict:
    scene, options = core_case(spec, deck)
    out = run_core(scene, options, rtol=CORE_RTOL, t_max_s=CORE_T_MAX_S)
    res = out["result"]
    row = {"core_status": out["status"], "core_error": out["error"], "core_wall_s": out["wall_s"],
           "core_warnings": out["warnings"],
           "core_notes": "; ".join(res.notes) if res is not None else ""}
    # the same scene under the physical preset, beside the legacy one
    phys = run_core(scene, PHYSICAL, rtol=CORE_RTOL, t_max_s=CORE_T_MAX_S)
    pres = phys["result"]
    row.update(physical_status=phys["status"], physical_error=phys["error"],
               physical_hit=pres.hit_message or "" if pres is not None else "",
               physical_hit_time_s=pres.hit_time_s if pres is not None else None,
               physical_notes="; ".join(pres.notes) if pres is not None else "")
    if res is not None:
        e = energies(out)
        row.update(core_hit=res.hit_message or "", core_hit_time_s=res.hit_time_s,
                   core_vehicle_contact_lost_s=res.vehicle_contact_lost_s,
                   core_nfev=res.evaluations,
                   core_launch_ke_ftlb=e["launch_ke_ftlb"], core_free_flight_energy_drift=e["free_drift"])
        t_start, t_stop = res.span
        if res.vehicle_contact_lost_s is not None:
            depth = res.scene.environment.ground_depth_ft
            row["core_lowest_at_release_ft"] = min(
                float(res.position(p, res.vehicle_contact_lost_s)[2]) + depth
                for p in res.point_names)
        t_end = min(res.end_s, t_stop)
        row["core_base_travel_ft"] = float(res.position("Q", t_end)[0]
                                           - res.position("Q", t_start)[0])
        # the core's mass centre on a fine grid, for the distance to the emulator's steps
        grid = np.linspace(t_start, t_stop, 4001)
        row["_grid"], row["_cm"] = grid, res.position("CM", grid)
    return row


def classify(row: dict) -> str:
    """The emulator's end against the core's: ``agrees`` (same hit, hit times within
    :data:`AGREE_HIT_S`, launch energies within :data:`AGREE_KE`), ``same hit, off``, ``other
    hit``, ``no hit``, ``guard: NAME``, ``crash``, ``n/a`` (the scene's change is no deck input)
    or ``hit (core failed)``."""
    if not row["emulator"]:
        return "n/a"
    status = row.get("emulator_status")
    if status == "guard":
        return f"guard: {row['emulator_guard']}"
    if status == "crash":
        return "crash"
    if status != "hit":
        return "no hit"
    if row.get("core_status") != "hit":
        return "hit (core failed)"
    dt = abs(row["emulator_hit_time_s"] - row["core_hit_time_s"])
    dke = row.get("launch_ke_rel_diff", math.nan)
    if row["emulator_hit"].strip() != row["core_hit"].strip():
        return "other hit"
    if dt <= AGREE_HIT_S and (not np.isfinite(dke) or abs(dke) <= AGREE_KE):
        return "agrees"
    return "same hit, off"


def _merge(spec, emu, core) -> dict:
    row = {k: v for k, v in spec.items() if k not in ("deck", "deck_path", "engine")}
    row["H_s"] = spec.get("H_s", H0 / 2 ** spec["k"])
    row.update(emu or {})
    row.update(core or {})
    if emu and core and "_grid" in core and len(emu["_t"]):
        # the arrays travelled from the workers as lists (studies.common.run_longest_first)
        t, xyz, grid = np.asarray(emu["_t"]), np.asarray(emu["_xyz"]), np.asarray(core["_grid"])
        keep = t <= grid[-1]
        if keep.any():
            cm = np.array([np.interp(t[keep], grid, np.asarray(core["_cm"][i]))
                           for i in range(3)])
            row["traj_diff_ft"] = float(np.max(np.linalg.norm(xyz[:, keep] - cm, axis=0)))
    for key in ("_t", "_xyz", "_grid", "_cm"):
        row.pop(key, None)
    if emu and core and emu.get("emulator_hit_time_s") is not None and core.get("core_hit_time_s") is not None:
        row["hit_time_diff_s"] = emu["emulator_hit_time_s"] - core["core_hit_time_s"]
    ke_e, ke_c = row.get("emulator_launch_ke_ftlb"), row.get("core_launch_ke_ftlb")
    if ke_e is not None and ke_c and np.isfinite(ke_e) and np.isfinite(ke_c):
        row["launch_ke_rel_diff"] = ke_e / ke_c - 1.0
    row["emulator_class"] = classify(row)
    return row


def stability_study(out_dir, quick: bool = False, jobs: int | None = None, deck_path=None,
                    command: str | None = None, quiet: bool = False,
                    scheduler: str | None = None, resume: bool = False, deck=None,
                    deck_sha256: str | None = None) -> dict:
    """Run the stability grid; write ``stability_study.csv``, ``stability_map.png``,
    ``extreme_scenes.png`` and ``README.md`` into ``out_dir``.  ``deck``, ``deck_sha256``:
    the file ``deck_path`` as the caller read it (else it is read here, once).  Returns the
    summary."""
    started = time.perf_counter()
    out = Path(out_dir)
    check_output_dir(out)  # a missing or read-only folder fails before any run
    deck_path = str(deck_path or default_deck())
    shown = os.path.relpath(deck_path) if not os.path.relpath(deck_path).startswith("..") else deck_path
    if deck is None:
        deck, deck_sha256 = read_base(deck_path)
    base = deck.values
    jobs = jobs or cpu_count()
    grid = scenes(base, quick)
    tasks = []
    for i, s in enumerate(grid):
        for engine in ("emulator", "core") if s["emulator"] else ("core",):
            cost = (0.4 * 2 ** s["k"]) if engine == "emulator" else 0.3
            tasks.append(dict(s, engine=engine, deck_path=deck_path, index=i, cost=cost))
    # the base deck handed to the workers with the function; the tasks name its file
    done = run_longest_first(functools.partial(_task, bases={deck_path: deck}), tasks,
                             jobs=jobs, desc="study stability", quiet=quiet,
                             store_dir=output_store(out, resume), scheduler=scheduler,
                             resume=resume, core=True, files={deck_path: deck_sha256})
    results = {(t["index"], t["engine"]): r for t, r in zip(tasks, done)}
    rows = [_merge(s, results.get((i, "emulator")), results.get((i, "core")))
            for i, s in enumerate(grid)]
    summary = _summarise(rows)
    with OutputSet(directory=out) as files:  # the four files appear together or not at all
        files.write("stability_study.csv", csv_text(rows, COLUMNS))
        _plot_map(rows, summary, files.path("stability_map.png"))
        _plot_extremes(rows, files.path("extreme_scenes.png"))
        wall = time.perf_counter() - started
        cmd = command or (f"deck-emulator study stability --out {out_dir}"
                          + (" --quick" if quick else "") + f" --jobs {jobs}")
        files.write("README.md", _report(rows, summary, shown, cmd, jobs, wall, quick, deck))
    summary["wall_s"] = wall
    return summary


# --------------------------------------------------------------------------- analysis


CLEAN = ("agrees", "same hit, off", "other hit")


def _stiff(rows):
    return [r for r in rows if r["group"] == STIFF_SPRING]


def _finite(x) -> bool:
    return x is not None and isinstance(x, float) and math.isfinite(x)


def _summarise(rows) -> dict:
    s: dict = {"classes": {}}
    for r in rows:
        s["classes"][r["emulator_class"]] = s["classes"].get(r["emulator_class"], 0) + 1
    st = [r for r in _stiff(rows) if r["emulator_class"] in CLEAN]
    if st:
        bad = sorted((r for r in st if r["emulator_class"] == "other hit"), key=lambda r: r["h_omega"])
        ke = sorted((r for r in st if abs(r.get("launch_ke_rel_diff", 0.0)) > AGREE_KE),
                    key=lambda r: r["h_omega"])
        small = [r for r in st if r["h_omega"] < 0.3 and _finite(r.get("launch_ke_rel_diff"))]
        s["stiff"] = {
            "first_differs": bad[0]["scene"] if bad else "",
            "first_differs_h_omega": bad[0]["h_omega"] if bad else math.nan,
            "last_agrees_h_omega": max((r["h_omega"] for r in st if r["emulator_class"] == "agrees"),
                                       default=math.nan),
            "n_beyond": sum(1 for r in st if bad and r["h_omega"] >= bad[0]["h_omega"]),
            "n_other_beyond": len(bad),
            "first_ke10": ke[0]["scene"] if ke else "",
            "first_ke10_h_omega": ke[0]["h_omega"] if ke else math.nan,
            "slope": _ke_slope(st),
            "ke_per_h_omega": float(np.median([abs(r["launch_ke_rel_diff"]) / r["h_omega"]
                                               for r in small])) if small else math.nan,
            "failed": sorted({r["emulator_class"] for r in _stiff(rows)
                              if r["emulator_class"] not in CLEAN}),
            "max_h_omega": max(r["h_omega"] for r in _stiff(rows)),
        }
    return s


def _ke_slope(rows) -> float:
    """Least-squares slope of log |launch-energy error| against log h*omega, h*omega < 1."""
    x = np.array([r["h_omega"] for r in rows])
    y = np.array([abs(r.get("launch_ke_rel_diff", math.nan)) for r in rows])
    keep = np.isfinite(y) & (y > 1e-3) & (x < 1.0)
    if keep.sum() < 3:
        return math.nan
    return float(np.polyfit(np.log10(x[keep]), np.log10(y[keep]), 1)[0])


# --------------------------------------------------------------------------- figures

_CLASS_COLOURS = {
    "agrees": "#2ca02c",
    "same hit, off": "#ffd92f",
    "other hit": "#ff7f0e",
    "no hit": "#9467bd",
    "guard: halvings": "#d62728",
    "guard: ed_iterations": "#8c564b",
    "guard: arithmetic": "#e377c2",
    "guard: time_s": "#9467bd",
    "crash": "#555555",
    "hit (core failed)": "#bcbd22",
    "n/a": "#dddddd",
}


CORE_FAILED = "#b15928"


def _colour(cls):
    return _CLASS_COLOURS.get(cls, "#17becf")


def _plot_map(rows, summary, path: Path) -> None:
    plt = agg_backend()
    st = _stiff(rows)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(15, 6.8), gridspec_kw={"width_ratios": [1.25, 1]})
    ck = np.array([r["CK_lb_ft"] for r in st])
    h = np.array([r["H_s"] for r in st])
    for r in st:
        ax.scatter(r["CK_lb_ft"], r["H_s"], s=520, marker="s", color=_colour(r["emulator_class"]),
                   edgecolor="black", linewidth=0.5, zorder=3)
        dke = r.get("launch_ke_rel_diff")
        if _finite(dke):
            ax.annotate(f"{100 * dke:+.0f}", (r["CK_lb_ft"], r["H_s"]), ha="center", va="center",
                        fontsize=7, zorder=4)
        if r.get("core_status") != "hit":
            ax.scatter(r["CK_lb_ft"], r["H_s"], s=120, marker="x", color="black", zorder=5)
    kk = np.logspace(np.log10(ck.min()) - 0.25, np.log10(ck.max()) + 0.25, 50)
    inv_sqrt_m = st[0]["h_omega"] / (st[0]["H_s"] * math.sqrt(st[0]["CK_lb_ft"]))
    top = h.max() * 1.45
    for hw, ls in ((0.1, ":"), (1.0, "--"), (2.0, "-")):
        ax.plot(kk, hw / (inv_sqrt_m * np.sqrt(kk)), ls, color="grey", lw=1.2)
        x_lab = (hw / (inv_sqrt_m * top)) ** 2
        if kk.min() < x_lab < kk.max():
            ax.annotate(f"h\u03c9 = {hw:g}", (x_lab, top), fontsize=9, color="dimgrey",
                        ha="left", va="bottom", xytext=(3, 0), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log", base=2)
    ax.set_ylim(h.min() / 1.6, h.max() * 1.9)
    ax.set_xlim(kk.min(), kk.max())
    ax.set_yticks(sorted(set(h)))
    ax.set_yticklabels([f"{v * 1e6:.0f} \u00b5s (k={round(math.log2(H0 / v))})"
                        for v in sorted(set(h))])
    ax.minorticks_off()
    ax.set_xlabel("crush springs CK = CT, lb/ft")
    ax.set_ylabel("emulator step H")
    ax.set_title("Emulator against the core on stiff springs\n(numbers: launch kinetic energy, "
                 "% above the core's)", fontsize=11)
    ax.grid(True, which="major", alpha=0.3)
    handles = [plt.Line2D([], [], marker="s", ls="", color=_colour(c), markeredgecolor="black",
                          markersize=11, label=c) for c in sorted({r["emulator_class"] for r in st})]
    if any(r.get("core_status") != "hit" for r in st):
        handles.append(plt.Line2D([], [], marker="x", ls="", color="black", label="core failed"))
    ax.legend(handles=handles, fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.11),
              ncol=len(handles), frameon=False)

    colours = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd")
    for k in sorted({r["k"] for r in st}):
        sel = [r for r in st if r["k"] == k and _finite(r.get("launch_ke_rel_diff"))]
        if sel:
            bx.loglog([r["h_omega"] for r in sel], [abs(r["launch_ke_rel_diff"]) for r in sel],
                      marker="o", ls="-", color=colours[k % 5], label=f"H = {H0 / 2**k * 1e6:.0f} \u00b5s")
    xs = np.logspace(-3, 1.2, 20)
    bx.loglog(xs, xs, color="grey", lw=1, ls="--", label="|error| = h\u03c9")
    bx.axvline(2.0, color="grey", lw=1)
    bx.annotate("h\u03c9 = 2", (2.0, 2e-3), xytext=(4, 0), textcoords="offset points", fontsize=9,
                color="dimgrey")
    bx.axhline(AGREE_KE, color="grey", lw=0.8, ls=":")
    bx.annotate(f"{100 * AGREE_KE:.0f} %", (1.2e-3, AGREE_KE), xytext=(0, 3), textcoords="offset points",
                fontsize=9, color="dimgrey")
    bx.set_xlim(1e-3, 20)
    bx.set_ylim(1e-3, 5)
    bx.set_xlabel("h\u03c9,   \u03c9 = \u221a(CK / W),  W = post mass")
    bx.set_ylabel("|launch kinetic energy, emulator / core \u2212 1|")
    bx.set_title("Energy the explicit scheme adds during the contact", fontsize=11)
    bx.grid(True, which="major", alpha=0.3)
    bx.legend(fontsize=9, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _short(msg: str) -> str:
    msg = (msg or "").replace("THE POST HAS HIT THE ", "")
    if msg.startswith("GROUND WITH POINT "):
        return "ground, point " + msg.rsplit(" ", 1)[-1]
    return msg.replace(" OF THE VEHICLE", "").lower()


def _per_cent(fraction, spec: str) -> str:
    """A relative drift as the README and the figure both give it: in per cent."""
    return fmt(None if fraction is None else 100 * fraction, spec)


def _cell_text(r, engine):
    if engine == "emulator":
        cls = r["emulator_class"]
        if cls == "n/a":
            return "not a deck input"
        if r.get("emulator_status") == "hit":
            return f"{_short(r['emulator_hit'])} at {r['emulator_hit_time_s']:.3f} s"
        when = _time_of(r.get("emulator_error", ""))
        reason = (r.get("emulator_error") or "").split(" at label", 1)[0]
        if r.get("emulator_guard") == "arithmetic":
            cls = reason.split(" (", 1)[0]
        elif r.get("emulator_guard"):
            cls = f"{r['emulator_guard']} guard"
        return cls + (f", t = {float(when):.3g} s" if when else "")
    if r.get(f"{engine}_status") == "hit":
        return f"{_short(r[f'{engine}_hit'])} at {r[f'{engine}_hit_time_s']:.3f} s"
    if r.get(f"{engine}_status") == "no hit":
        return f"no hit in {CORE_T_MAX_S:g} s"
    err = r.get(f"{engine}_error") or "?"
    return err.split(":", 1)[0] + (" (events chatter)" if "chatter" in err else "")


def _time_of(error: str) -> str:
    if error and "t = " in error:
        return error.split("t = ", 1)[1].split(" ", 1)[0].rstrip(")s")
    return ""


def _plot_extremes(rows, path: Path) -> None:
    plt = agg_backend()
    ext = [r for r in rows if r["group"] != STIFF_SPRING]
    n = len(ext)
    height = 0.36 * n + 1.9
    fig, ax = plt.subplots(figsize=(13, height))
    for i, r in enumerate(ext):
        y = n - 1 - i
        ax.text(-0.01, y, f"{r['description']}  [{r['scene']}]", ha="right", va="center", fontsize=8.5)
        core_ok = r.get("core_status") == "hit"
        colours = (_colour(r["emulator_class"]), "#a6d96a" if core_ok else CORE_FAILED)
        for j, engine in enumerate(("emulator", "core")):
            ax.add_patch(plt.Rectangle((j * 0.5, y - 0.42), 0.49, 0.84, color=colours[j], alpha=0.85))
            ax.text(j * 0.5 + 0.245, y, _cell_text(r, engine), ha="center", va="center", fontsize=8)
        drift = r.get("emulator_free_flight_energy_drift")
        if _finite(drift):
            ax.text(1.005, y, f"{_per_cent(drift, '+.2g')} %", ha="left", va="center", fontsize=8)
    ax.text(0.245, n - 0.2, "emulator (k = 0, as printed)", ha="center", fontsize=9.5, weight="bold")
    ax.text(0.745, n - 0.2, "core (legacy preset, DOP853)", ha="center", fontsize=9.5, weight="bold")
    ax.text(1.005, n - 0.2, "emulator's free-\nflight energy drift", ha="left", fontsize=8.5,
            weight="bold")
    ax.set_xlim(0, 1.12)
    ax.set_ylim(-0.6, n + 0.7)
    ax.axis("off")
    handles = [plt.Rectangle((0, 0), 1, 1, color=_colour(c), alpha=0.85, label=c)
               for c in sorted({r["emulator_class"] for r in ext})]
    handles.append(plt.Rectangle((0, 0), 1, 1, color=CORE_FAILED, alpha=0.85, label="core failed"))
    ax.legend(handles=handles, fontsize=8.5, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=4,
              title="emulator against the core (core column: light green = hit)", title_fontsize=8.5,
              frameon=False)
    fig.subplots_adjust(left=0.40, right=0.95, top=0.98, bottom=1.0 / height)
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --------------------------------------------------------------------------- the report


def _report(rows, summary, deck_path, cmd, jobs, wall, quick, deck) -> str:
    """The page (``templates/stability_study.md``) of the grid's rows and summary; ``deck``:
    the base deck read (``deck_path``: its file as the page names it)."""
    table = []
    for r in rows:
        table.append([
            f"`{r['scene']}`", r["description"],
            f"{r['h_omega']:.3g}" if _finite(r.get("h_omega")) else "",
            r["emulator_class"], _cell_text(r, "emulator"), _cell_text(r, "core"),
            _cell_text(r, "physical"),
            fmt(r.get("launch_ke_rel_diff"), "+.1%"), fmt(r.get("traj_diff_ft"), ".2g"),
            _per_cent(r.get("emulator_free_flight_energy_drift"), "+.2g"),
            _per_cent(r.get("core_free_flight_energy_drift"), "+.1e"),
        ])
    errors = []
    for r in rows:
        for key, who in (("emulator_error", "emulator"), ("core_error", "core"),
                         ("physical_error", "core (physical)")):
            if r.get(key):
                errors.append(f"* `{r['scene']}`, {who}: {r[key]}")
    return page(
        "stability_study.md", command=cmd, machine_line=machine_line(machine(), jobs, wall),
        deck_path=deck_path, ed_iterations=LIMITS.ed_iterations, halvings=LIMITS.halvings,
        time_s=f"{LIMITS.time_s:g}", core_rtol=f"{CORE_RTOL:g}",
        core_t_max=f"{CORE_T_MAX_S:g}", agree_hit=f"{AGREE_HIT_S:g}",
        agree_ke=f"{100 * AGREE_KE:.0f}",
        failure_modes="".join(f"* {s}\n" for s in failure_modes(rows, summary)),
        stability_section="".join(line + "\n"
                                  for line in stability_section(rows, deck)),
        other_findings="".join(f"* {s}\n" for s in other_findings(rows)),
        classes=", ".join(f"{k} {v}" for k, v in sorted(summary["classes"].items())),
        table=md_table(["scene", "what", "h\u03c9", "emulator", "emulator's end", "core's end",
                        "core's end, physical preset",
                        "launch energy, emulator vs core", "largest mass-centre distance (ft)",
                        "emulator free-flight drift (%)", "core free-flight drift (%)"], table),
        errors="".join(line + "\n" for line in
                       ["## Messages of the runs that failed", "", *errors, ""]) if errors else "")


MAP, EXT = "[map](stability_map.png)", "[scenes](extreme_scenes.png)"


def _finding(key: str, **fields) -> str:
    return snippet("stability_findings.md", key, **fields)


def failure_modes(rows, summary) -> list[str]:
    """One sentence per failure mode found, naming a scene that shows it."""
    out = []
    by = {r["scene"]: r for r in rows}
    s = summary.get("stiff")
    if s and s["first_ke10"]:
        r = by[s["first_ke10"]]
        out.append(_finding(
            "energy_gain", ke_per_h_omega=f"{s['ke_per_h_omega']:.2f}", slope=f"{s['slope']:.2f}",
            agree_ke=f"{100 * AGREE_KE:.0f}", h_omega=f"{s['first_ke10_h_omega']:.2g}",
            scene=r["scene"], ke_diff=f"{100 * r['launch_ke_rel_diff']:+.0f}"))
    if s and s["first_differs"]:
        r = by[s["first_differs"]]
        out.append(_finding(
            "clean_end_wrong_answer",
            guards=("never trips a guard" if not s["failed"]
                    else f"trips {', '.join(s['failed'])} only in places"),
            h_omega=f"{s['first_differs_h_omega']:.2g}", scene=r["scene"],
            emulator=_cell_text(r, "emulator"), core=_cell_text(r, "core"),
            n_beyond=s["n_beyond"], n_other_beyond=s["n_other_beyond"],
            last_agrees=f"{s['last_agrees_h_omega']:.2g}"))
    if s and not s["failed"]:
        top = max(_stiff(rows), key=lambda r: r["h_omega"])
        hi = [r["launch_ke_rel_diff"] for r in _stiff(rows)
              if r["h_omega"] > 1 and _finite(r.get("launch_ke_rel_diff"))]
        out.append(_finding(
            "no_divergence", max_h_omega=f"{s['max_h_omega']:.3g}", scene=top["scene"],
            emulator=_cell_text(top, "emulator"),
            ke_diff=f"{100 * top.get('launch_ke_rel_diff', math.nan):+.0f}",
            beyond=(f" ({100 * min(hi):+.0f} to {100 * max(hi):+.0f} % beyond h\u03c9 = 1)"
                    if hi else "")))
    for r in rows:
        if r.get("emulator_guard") == "halvings" and "DIFFT" in r.get("emulator_error", ""):
            out.append(_finding(
                "endless_halving", scene=r["scene"], description=r["description"],
                difft=r["emulator_error"].split("DIFFT = ", 1)[1].split(" ", 1)[0],
                halvings=LIMITS.halvings, time=_time_of(r["emulator_error"]),
                core=_cell_text(r, "core")))
            break
    tha_fail = [r for r in rows if r["group"] == "start-up THA"
                and r.get("emulator_guard") == "arithmetic" and "ED" in r.get("emulator_error", "")]
    if tha_fail:
        ok = [float(r["tha"]) for r in rows if r["group"] == "start-up THA"
              and r["emulator_class"] == "agrees"]
        r = min(tha_fail, key=lambda r: float(r["tha"]))
        out.append(_finding(
            "tha_division", scene=r["scene"], error=r["emulator_error"],
            passing=f"; THA = {', '.join(f'{x:g}' for x in sorted(ok))} pass" if ok else ""))
    for r in rows:
        if r.get("core_status") == "no hit":
            low = r.get("core_lowest_at_release_ft")
            below = _finite(low) and low < 0
            out.append(_finding(
                "core_no_hit", scene=r["scene"], description=r["description"],
                lost=f"{r.get('core_vehicle_contact_lost_s') or math.nan:.3g}",
                below=_finding("below_ground", depth=f"{-low:.1f}") if below else "",
                emulator=_cell_text(r, "emulator")))
    for r in rows:
        err = r.get("core_error") or ""
        if "chatter" in err:
            out.append(_finding(
                "chattering", scene=r["scene"], description=r["description"],
                error=err.split(" (mode")[0], emulator=_cell_text(r, "emulator")))
        elif r.get("core_status") == "error":
            out.append(f"**Core error** (`{r['scene']}`, {r['description']}): {err}. Figure: {EXT}.")
    warned = [r for r in rows if r.get("core_warnings")]
    if warned:
        r = warned[0]
        ended = all(x.get("core_status") == "hit" for x in warned)
        out.append(_finding(
            "scipy_warnings", n=len(warned), scene=r["scene"], description=r["description"],
            warnings=r["core_warnings"],
            ended=("DOP853 rejected the steps whose error estimate was not finite and every one "
                   "of these runs still ended with a hit." if ended else "see the CSV."),
            figure=MAP if r["group"] == STIFF_SPRING else EXT))
    fric = [r for r in rows if r["group"] == "base friction"]
    base = by.get("base")
    for r in fric:
        if base and r.get("core_hit") != base.get("core_hit"):
            out.append(_finding(
                "friction", scene=r["scene"], description=r["description"],
                travel=f"{r.get('core_base_travel_ft', math.nan):+.1f}",
                core=_cell_text(r, "core"), base=_cell_text(base, "core")))
    thb = [r for r in rows if r["group"] == "theta near 90 deg" and base
           and r.get("emulator_hit") == base.get("emulator_hit")
           and r.get("emulator_hit_time_s") == base.get("emulator_hit_time_s")]
    if thb:
        r = thb[-1]
        others = ", ".join("`" + x["scene"] + "`" for x in thb[:-1])
        out.append(_finding(
            "ignores_thb", scene=r["scene"], emulator=_cell_text(r, "emulator"),
            others=f"; so do {others}" if others else "", core=_cell_text(r, "core")))
    for r in rows:
        if r["group"] in (STIFF_SPRING, "theta near 90 deg") or r["emulator_class"] != "other hit":
            continue
        out.append(_finding(
            "different_answer", scene=r["scene"], description=r["description"],
            emulator=_cell_text(r, "emulator"), core=_cell_text(r, "core"),
            ke_diff=fmt(r.get("launch_ke_rel_diff"), "+.1%"),
            traj_diff=fmt(r.get("traj_diff_ft"), ".2g")))
    drifts = [r for r in rows if _finite(r.get("emulator_free_flight_energy_drift"))]
    if drifts:
        r = max(drifts, key=lambda r: abs(r["emulator_free_flight_energy_drift"]))
        c = [abs(x["core_free_flight_energy_drift"]) for x in rows if _finite(x.get("core_free_flight_energy_drift"))]
        b = f" (`base`: {100 * base['emulator_free_flight_energy_drift']:+.2g} %)" if base and _finite(
            base.get("emulator_free_flight_energy_drift")) else ""
        out.append(_finding(
            "energy_drift", base=b, scene=r["scene"],
            drift=f"{100 * r['emulator_free_flight_energy_drift']:+.2g}",
            core_drift=f"{100 * max(c, default=math.nan):.1e}"))
    return out


def other_findings(rows) -> list[str]:
    out = []
    groups = {}
    for r in rows:
        if r["group"] != STIFF_SPRING:
            groups.setdefault(r["group"], []).append(r)
    for group, rs in groups.items():
        ok = [r for r in rs if r["emulator_class"] == "agrees"]
        if ok:
            out.append(_finding("agrees", group=group,
                                scenes=", ".join(f"`{r['scene']}`" for r in ok),
                                agree_hit=f"{AGREE_HIT_S:g}", agree_ke=f"{100 * AGREE_KE:.0f}"))
    for r in rows:
        if r["group"] not in (STIFF_SPRING, "theta near 90 deg") and r["emulator_class"] == "same hit, off":
            out.append(_finding(
                "same_hit_off", scene=r["scene"], description=r["description"],
                diff=f"{abs(r['hit_time_diff_s']):.3f}",
                later="later" if r["hit_time_diff_s"] > 0 else "earlier",
                emulator=_cell_text(r, "emulator"), core=_cell_text(r, "core"),
                traj_diff=fmt(r.get("traj_diff_ft"), ".2g")))
    for r in rows:
        if r["emulator_class"] == "n/a":
            out.append(f"`{r['scene']}` ({r['description']}; core only): {_cell_text(r, 'core')}.")
    tha0 = next((r for r in rows if r["scene"] == "tha-0.0"), None)
    if tha0 and tha0["emulator_class"] in CLEAN:
        out.append(_finding("tha_zero", emulator=_cell_text(tha0, "emulator")))
    return out


# --------------------------------------------------------------------------- the scheme and the model


def one_step_matrix(h_omega: float, omega: float = 1.0) -> np.ndarray:
    """The 1967 scheme on an undamped spring x'' = -omega**2 x, one step h: the velocity by
    explicit Euler (v1 = v0 - h omega**2 x0), the displacement by the trapezoid of the two
    velocities (x1 = x0 + h (v0 + v1) / 2): ``(x1, v1) = M (x0, v0)``."""
    h = h_omega / omega
    return np.array([[1.0 - h_omega**2 / 2.0, h], [-h * omega**2, 1.0]])


def scheme_growth(h_omega: float) -> dict:
    """The one-step matrix's eigenvalues, their largest modulus, its determinant (the area, and
    for h omega < 4 the squared modulus of both eigenvalues: the spring's energy grows by it each
    step on average), and the growth of that energy over a half period pi/omega (the contact of
    an undamped spring from touch to release)."""
    m = one_step_matrix(h_omega)
    lam = np.linalg.eigvals(m)
    top = float(np.max(np.abs(lam)))
    steps = math.pi / h_omega
    return {"h_omega": h_omega, "eigenvalues": lam, "modulus": top, "det": float(np.linalg.det(m)),
            "energy_per_step": top**2, "energy_half_period": top ** (2 * steps)}


#: a car of almost no mass: the scene whose fast mode the core's stiffness estimate is made for
TINY_CAR_SLUG = 1e-6
#: the h omega of the scheme's table (the grid's stiff-spring scenes reach about 10)
SCHEME_H_OMEGA = (0.01, 0.1, 0.5, 1.0, 2.0, 4.0, 8.0)


def contact_spectrum(scene, options) -> dict:
    """The contact Jacobian's eigenvalues (:func:`deck_emulator.engine.spectrum.contact_spectrum`)
    summed up: ``fast`` the largest modulus, ``slow`` the largest of the others outside the fast
    pair (the motion the spring does not drive), ``contact_s`` the contact's length when under
    a millisecond."""
    from deck_emulator.engine.spectrum import contact_spectrum as spectrum

    got = spectrum(scene, options, rtol=CORE_RTOL)
    mod = got["moduli"]
    fast = float(mod[0])
    slow = float(next((x for x in mod if x < 0.5 * fast), 0.0))
    return {"fast": fast, "slow": slow, "contact_s": got["contact_s"]}


def stability_section(rows, base) -> list[str]:
    """The page's section on stability from the scheme and the model: the one-step matrix's
    eigenvalues, the contact Jacobian's for each spring of the grid, the core's own stiffness
    estimate beside them."""
    from deck_emulator.engine.spectrum import stiff_ratio, stiffness_estimate

    STIFF_RATIO = stiff_ratio()
    w = base.values["W"]
    growth = md_table(
        ["h\u03c9", "eigenvalues of M", "largest |\u03bb|", "det M", "1 + (h\u03c9)\u00b2/2",
         "energy growth per step", "over a half period \u03c0/\u03c9"],
        [[f"{g['h_omega']:g}", ", ".join(f"{z.real:.4g}{z.imag:+.4g}i" for z in g["eigenvalues"]),
          f"{g['modulus']:.6g}", f"{g['det']:.6g}", f"{1 + g['h_omega']**2 / 2:.6g}",
          f"{g['energy_per_step']:.6g}", f"{g['energy_half_period']:.4g}"]
         for g in map(scheme_growth, SCHEME_H_OMEGA)])
    table, ratios, periods_seen = [], [], []
    for ck in sorted({r["CK_lb_ft"] for r in _stiff(rows)}):
        scene = Scene.from_deck(base.with_values(CK=ck, CT=ck))
        spec = contact_spectrum(scene, legacy_options(H0))
        omega = math.sqrt(ck / w)
        estimate, est_fast, _ = stiffness_estimate(scene, legacy_options(H0))
        ratios.append((spec["fast"] / omega, estimate, est_fast / omega))
        periods = (spec["contact_s"] * spec["fast"] / (2 * math.pi)
                   if spec["contact_s"] is not None else math.nan)
        if math.isfinite(periods):
            periods_seen.append(periods)
        table.append([f"{ck:.3g}", f"{omega:.4g}", f"{spec['fast']:.4g}",
                      f"{spec['fast'] / omega:.3f}", f"{spec['slow']:.3g}",
                      f"{spec['fast'] / spec['slow']:.3g}" if spec["slow"] else "–",
                      fmt(spec["contact_s"], ".3g"), fmt(periods, ".2g"), f"{estimate:.3f}"])
    spectrum = md_table(["CK = CT (lb/ft)", "\u03c9 (rad/s)", "fast |\u03bb| (1/s)",
                         "fast / \u03c9", "slow |\u03bb| (1/s)", "spread fast / slow",
                         "contact (s, to 1 ms)", "contact in fast periods", "core's stiffness()"],
                        table)
    out = _finding("scheme", growth_table=growth, stiff_ratio=f"{STIFF_RATIO:g}",
                   spectrum_table=spectrum).split("\n") + [""]
    if ratios:
        lo, hi = min(r for r, _, _ in ratios), max(r for r, _, _ in ratios)
        tiny = Scene.from_deck(base.with_values(WV=TINY_CAR_SLUG))
        out += [_finding(
            "fast_mode", fast=f"{lo:.3f}" + (f" to {hi:.3f}" if hi - lo > 5e-4 else ""),
            reduced=", ".join(f"{f:.3f}" for f in sorted({round(f, 3) for _, _, f in ratios})),
            fast_periods=(f"{min(periods_seen):.2g} to {max(periods_seen):.2g}" if periods_seen
                          else "a few"),
            estimates=", ".join(f"{e:.3f}" for e in sorted({round(e, 3) for _, e, _ in ratios})),
            stiff_ratio=f"{STIFF_RATIO:g}", tiny_car=f"{TINY_CAR_SLUG:g}",
            tiny_stiffness=f"{stiffness_estimate(tiny, legacy_options(H0))[0]:.3g}"), ""]
        out += _explicit_against_implicit(base, max(r["CK_lb_ft"] for r in _stiff(rows)))
    return out


def _explicit_against_implicit(base, ck: float) -> list[str]:
    """DOP853 against Radau on the stiffest spring of the grid, the whole run at the study's
    tolerance: what each costs and how far apart their answers are."""
    scene = Scene.from_deck(base.with_values(CK=ck, CT=ck))
    runs = {}
    for method in ("DOP853", "Radau"):
        out = run_core(scene, legacy_options(H0), method=method, rtol=CORE_RTOL,
                       t_max_s=CORE_T_MAX_S)
        if out["result"] is None:
            return [f"On CK = CT = {ck:.3g} lb/ft, {method} at rtol {CORE_RTOL:g} failed: "
                    f"{out['error']}", ""]
        runs[method] = (out["result"], out["wall_s"])
    (d, td), (r, tr) = runs["DOP853"], runs["Radau"]
    same = d.hit_message is not None and d.hit_message == r.hit_message
    return [_finding(
        "explicit_implicit", ck=f"{ck:.3g}", rtol=f"{CORE_RTOL:g}", dop_nfev=d.evaluations,
        dop_wall=f"{td:.2g}", radau_nfev=r.evaluations, radau_wall=f"{tr:.2g}",
        ends=(f"the same hit, {abs(d.hit_time_s - r.hit_time_s):.2g} s apart." if same
              else f"different ends: DOP853 {d.hit_message}, Radau {r.hit_message}.")), ""]
