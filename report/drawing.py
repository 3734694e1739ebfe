"""The report's Figures 22-29 drawn again (Chapter VI): each post's terminal positions and
trajectories at 20 and 40 mph, both engines beside the report's printed points (the pictures
of :mod:`report.figures`' cases; ``python scripts/make_report_figures.py``)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from deck_emulator.engine import Outcome, quantities
from deck_emulator.files import OutputSet
from deck_emulator.present.plot import (
    CAR_COLOUR,
    DPI,
    ENGINE_COLOUR,
    car_plan,
    car_side,
    hit_index,
    instants,
    mpl,
    post_l,
    savefig,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure


#: Figure size (inches) of one row (an angle: plan and side view) of the report's figures.
REPORT_ROW_SIZE = (17.0, 6.0)
REPORT_COLOUR = "black"
START_COLOUR = "0.55"
#: Each engine's post at the hit: the emulator wide beneath, the core narrow on top, so that
#: both show where they coincide.
ENGINE_WIDTH = {"emulator": 4.0, "core": 1.8}
#: The points' paths in the trajectory pictures, one line style per engine.
ENGINE_STYLE = {"emulator": "--", "core": "-"}
#: Every trajectory picture draws the post every this many seconds.
TRAJECTORY_EVERY_S = 0.1
POINT_MARKERS = {"P": "^", "R": "o", "U": "s", "Q": "v"}


def _chain_of(points: dict) -> np.ndarray:
    """(k, 3) the post as one line through the named points of ``points`` (name -> XL, YL, ZL):
    Q, P, R and, for a second luminaire, back to P and out to U."""
    chain = ["Q", "P", "R"] + (["P", "U"] if "U" in points else [])
    return np.array([points[k] for k in chain if k in points], dtype=float).reshape(-1, 3)


def terminal_points_l(res: Outcome) -> dict:
    """name -> (XL, YL, ZL) of the post at the end of the run, from the registry
    (``terminal_p_xl_ft`` ...): what the report's figures and tables show."""
    out = {}
    for k in ("P", "Q", "R", "U"):
        xyz = [quantities.value(f"terminal_{k.lower()}_{ax}_ft", res) for ax in ("xl", "yl", "zl")]
        if all(v is not None for v in xyz):
            out[k] = tuple(xyz)
    return out


def _start_points_l(res: Outcome) -> dict:
    out = {}
    for k in ("P", "Q", "R", "U"):
        if k in res.points and not np.isnan(res.points[k][0]).any():
            out[k] = tuple(res.to_l(res.points[k][0]))
    return out


def _engine_words(res: Outcome) -> str:
    if res.engine == "emulator":
        return "emulator (1967 listing, " + ("+".join(res.errata) or "as printed") + ")"
    return "core (legacy preset)"


def _end_words(res: Outcome) -> str:
    if res.hit is None:
        return f"no hit by {1000 * res.end_time_s:.0f} ms" + (" (run stopped)" if res.error else "")
    return f"{res.hit.short()} at {1000 * res.hit_time_s:.1f} ms"


def _label_points(ax, points: dict, axes: tuple[int, int], colour="k", dx=6, dy=6):
    done = []
    for k in ("Q", "P", "R", "U"):
        if k not in points:
            continue
        xy = np.array([points[k][axes[0]], points[k][axes[1]]])
        if any(np.hypot(*(xy - o)) < 0.8 for o in done):
            continue
        done.append(xy)
        ax.annotate(k, tuple(xy), xytext=(dx, dy), textcoords="offset points", fontsize=10,
                    fontweight="bold", color=colour, zorder=8)


def _at_report_time(res: Outcome, t_s: float | None) -> dict:
    """The core's post at the report's time of the end (name -> XL, YL, ZL), where the report
    ended earlier than the run did (more than 1 ms): empty otherwise."""
    if t_s is None or res.engine != "core" or res.hit_time_s is None \
            or t_s >= res.hit_time_s - 1e-3:
        return {}
    got = {k: res.point_l(k, t_s) for k in ("P", "Q", "R", "U")}
    return {k: p for k, p in got.items() if p is not None}


def _report_view(ax, outs: list[Outcome], report: dict, axes: tuple[int, int],
                 report_time_s: float | None = None, shaft: Outcome | None = None):
    """One view of a case: the car at the core's hit, the post at t = 0, each engine's post at
    the end (gid ``terminal:ENGINE``), the report's terminal points (gid ``report``) and,
    where the report's run ended earlier, the core's post at the report's time (gid
    ``at_report_time``)."""
    main = outs[-1]
    a, b = axes
    if shaft is not None:  # the core with the shaft test, where the report ends on the car
        p = _chain_of(terminal_points_l(shaft))
        ax.plot(p[:, a], p[:, b], ls=":", color=ENGINE_COLOUR["core"], lw=2.2, marker="s",
                ms=4, zorder=4.5, gid="terminal:core-shaft")
    early = _chain_of(_at_report_time(main, report_time_s))
    if len(early):
        ax.plot(early[:, a], early[:, b], ls="-.", color=ENGINE_COLOUR["core"], lw=1.3,
                marker="d", ms=4, zorder=3.5, gid="at_report_time")
    if b == 1:
        car_plan(ax, main, hit_index(main))
    else:
        car_side(ax, main, hit_index(main))
        ax.axhline(0.0, color="saddlebrown", lw=1.5, zorder=1)
    start = _chain_of(_start_points_l(main))
    ax.plot(start[:, a], start[:, b], ls=(0, (4, 3)), color=START_COLOUR, lw=1.5, marker="o",
            ms=3, zorder=2.5, gid="start")
    for res in outs:
        p = _chain_of(terminal_points_l(res))
        ax.plot(p[:, a], p[:, b], "-", color=ENGINE_COLOUR.get(res.engine, "k"),
                lw=ENGINE_WIDTH.get(res.engine, 2.0), marker="o",
                ms=2 + ENGINE_WIDTH.get(res.engine, 2.0), zorder=4 if res.engine == "core" else 3,
                solid_capstyle="round", gid=f"terminal:{res.engine}")
    if report:
        r = _chain_of(report)
        ax.plot(r[:, a], r[:, b], ls=(0, (2, 2)), color=REPORT_COLOUR, lw=1.2, marker="x",
                ms=9, mew=2, zorder=5, gid="report")
    _label_points(ax, terminal_points_l(main), axes)
    _label_points(ax, _start_points_l(main), axes, colour=START_COLOUR, dx=-14, dy=-2)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, lw=0.4, alpha=0.5)
    if b == 1:
        ax.set_xlabel("XL (ft): along the highway; the car travels to −XL")
        ax.set_ylabel("YL (ft): +YL away from the highway")
    else:
        ax.set_xlabel("XL (ft): along the highway; the car travels to −XL")
        ax.set_ylabel("ZL (ft): height above the ground")


def _report_handles(outs: list[Outcome], report_words: str | None, trajectory=False,
                    report_time_s: float | None = None, shaft: Outcome | None = None) -> list:
    L = mpl().Line2D
    h = []
    if shaft is not None:
        h.append(L([], [], ls=":", color=ENGINE_COLOUR["core"], lw=2.2, marker="s", ms=4,
                   label=f"core with the shaft test: post at the end, {_end_words(shaft)}"))
    if _at_report_time(outs[-1], report_time_s):
        h.append(L([], [], ls="-.", color=ENGINE_COLOUR["core"], lw=1.3, marker="d", ms=4,
                   label=f"core: post at the report's time of its end "
                         f"({1000 * report_time_s:.1f} ms)"))
    for res in outs:
        c = ENGINE_COLOUR.get(res.engine, "k")
        h.append(L([], [], color=c, lw=ENGINE_WIDTH.get(res.engine, 2.0), marker="o",
                   label=f"{_engine_words(res)}: post at the end, {_end_words(res)}"))
        if trajectory:
            h.append(L([], [], color=c, lw=1.2, ls=ENGINE_STYLE[res.engine],
                       label=f"{res.engine}: paths of the points; the post every "
                             f"{1000 * TRAJECTORY_EVERY_S:.0f} ms (thin)"))
    if report_words:
        h.append(L([], [], ls=(0, (2, 2)), color=REPORT_COLOUR, lw=1.2, marker="x", ms=9,
                   mew=2, label=report_words))
    h.append(L([], [], ls=(0, (4, 3)), color=START_COLOUR, lw=1.5, marker="o", ms=3,
               label="post at t = 0 (grey letters)"))
    h.append(mpl().Patch(fc="0.85", ec=CAR_COLOUR, label="car at the core's end (listing's "
                          "outline; roof darker in plan)"))
    h.append(L([], [], color="tab:cyan", lw=3, label="windshield"))
    return h


def figure_report_terminal(rows: list[dict], title: str) -> Figure:
    """The report's terminal-position figure (Figures 22, 23, 25-28): one row per case, plan
    view XL-YL and side view XL-ZL.  Each row: ``{"label": str, "outcomes": [Outcome, ...]
    (the emulator's first), "report": {name: (XL, YL, ZL)} (may be empty), "report_words":
    str or None}``."""
    w, h = REPORT_ROW_SIZE
    fig = mpl().Figure(figsize=(w, h * len(rows) + 0.6), dpi=DPI, layout="constrained")
    mpl().FigureCanvasAgg(fig)
    fig.suptitle(title, fontsize=12, fontweight="bold")
    subs = fig.subfigures(len(rows), 1, squeeze=False)[:, 0]
    for sub, row in zip(subs, rows):
        axs = sub.subplots(1, 2, width_ratios=(1.25, 1.0))
        for ax, axes, view in zip(axs, ((0, 1), (0, 2)), ("plan view (XL–YL)",
                                                         "side view (XL–ZL)")):
            _report_view(ax, row["outcomes"], row["report"], axes, row.get("report_time_s"),
                         row.get("shaft"))
            ax.set_title(f"{row['label']}: {view}", fontsize=10)
        sub.legend(handles=_report_handles(row["outcomes"], row.get("report_words"),
                                           report_time_s=row.get("report_time_s"),
                                           shaft=row.get("shaft")),
                   loc="outside lower center", ncols=3, fontsize=8.5)
    return fig


def figure_report_trajectory(outs: list[Outcome], report: dict, report_words: str | None,
                             title: str, label: str, report_time_s: float | None = None
                             ) -> Figure:
    """The report's trajectory figure (Figures 24 and 29): plan and side view of the post
    every :data:`TRAJECTORY_EVERY_S` (thin, each engine's colour) and the paths of its points
    P, R (and U) over the whole run (gid ``path:ENGINE:POINT``), over the same views as
    :func:`figure_report_terminal`."""
    w, h = REPORT_ROW_SIZE
    fig = mpl().Figure(figsize=(w, h + 1.6), dpi=DPI, layout="constrained")
    mpl().FigureCanvasAgg(fig)
    fig.suptitle(title, fontsize=12, fontweight="bold")
    axs = fig.subplots(1, 2, width_ratios=(1.25, 1.0))
    for ax, axes, view in zip(axs, ((0, 1), (0, 2)), ("plan view (XL–YL)", "side view (XL–ZL)")):
        a, b = axes
        for res in outs:
            c = ENGINE_COLOUR.get(res.engine, "k")
            for i in instants(res, TRAJECTORY_EVERY_S):
                p = post_l(res, i)
                ax.plot(p[:, a], p[:, b], "-", color=c, lw=0.7, alpha=0.35, zorder=2.2,
                        gid=f"instant:{res.engine}")
            for k in ("P", "R", "U"):
                if k not in res.points:
                    continue
                path = res.to_l(np.asarray(res.points[k], dtype=float))
                ax.plot(path[:, a], path[:, b], ls=ENGINE_STYLE.get(res.engine, "-"), color=c,
                        lw=1.6, zorder=3.5, gid=f"path:{res.engine}:{k}")
        _report_view(ax, outs, report, axes, report_time_s)
        ax.set_title(f"{label}: {view}", fontsize=10)
    fig.legend(handles=_report_handles(outs, report_words, trajectory=True,
                                       report_time_s=report_time_s),
               loc="outside lower center", ncols=3, fontsize=8.5)
    return fig


def _report_row(case, label: str) -> dict:
    from report.figures import report_end, report_points

    comment, t_ms = report_end(case.name)
    words = None
    if comment is not None:
        from deck_emulator.studies.report_tables import CASES_ALL

        table = CASES_ALL[case.name][3]
        words = (f"report, Table {table}: {comment}"
                 + (f" at {t_ms:.1f} ms" if t_ms is not None else ""))
    return {"label": label, "outcomes": case.outcomes, "report": report_points(case.name),
            "report_words": words, "report_time_s": None if t_ms is None else t_ms / 1000.0,
            "shaft": case.core_shaft if comment is not None and "CAR" in comment else None}


def figure_report_part(part, cases: dict) -> Figure:
    """The picture of one :class:`~report.figures.FigurePart` from the
    runs ``cases`` (name -> Case)."""
    head = (f"Figure {part.figure}{part.part} (α = " + ", ".join(f"{a}°" for a in part.alphas)
            + f"): {part.caption[:1]}{part.caption[1:].lower()}")
    rows = []
    for name, alpha in zip(part.cases, part.alphas):
        case = cases[name]
        label = f"{name}: {part.mph} mph, α = {alpha}°"
        if case.emulator is None and case.refusal:
            label += " (core only: the listing has no point U)"
        rows.append(_report_row(case, label))
    if part.kind == "trajectory":
        (row,) = rows
        return figure_report_trajectory(row["outcomes"], row["report"], row["report_words"],
                                        head, row["label"], row["report_time_s"])
    return figure_report_terminal(rows, head)


#: The command that writes docs/report/ (named on the pages it writes).
REPORT_COMMAND = "python scripts/make_report_figures.py"


def write_report_figures(out_dir, *, command: str = REPORT_COMMAND, progress=None,
                         cases: dict | None = None) -> list:
    """Run every case the report's Figures 22-29 and the statements of Sections 5.4 and
    6.2-6.4 need (:func:`report.figures.run_cases`) and write into
    ``out_dir`` every picture (``figure_22.png`` ... ``figure_29b.png``), ``figures.md`` and
    ``verdicts.md``: all of them, or none.  Returns the paths written, in order."""
    from report import figures as rf
    from report import verdicts as rv

    from deck_emulator.files import check_output_dir

    out_dir = Path(out_dir)
    check_output_dir(out_dir)  # before any run: OutputError, one line
    if cases is None:
        cases = rf.run_cases(progress=progress)
    written = []
    with OutputSet(directory=out_dir) as files:
        for part in rf.FIGURES:
            if progress is not None:
                progress(part.file)
            savefig(figure_report_part(part, cases), files.path(part.file))
            written.append(out_dir / part.file)
        files.write("figures.md", rf.figures_page(cases, command))
        files.write("verdicts.md", rv.verdicts_page(rv.verdicts(cases), command))
        written += [out_dir / "figures.md", out_dir / "verdicts.md"]
    return written


