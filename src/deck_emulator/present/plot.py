"""Pictures of the crash: ``deck-emulator plot``.

* Trajectory pictures in the style of the report's Figures 18-29: the post drawn as a line
  through its named points (base Q, top P, luminaire end R; C where it differs from Q) at
  regular instants, in the report's XL, YL, ZL axes (origin on the ground under the base of
  the support): side view XL-ZL, plan view XL-YL, a 3-d view, or all three with a summary.
  The ground, the car's outline at the moment of the hit (bumper, hood, windshield, top and
  trunk from the deck's HLEN, TLEN, TRLEN, HHV, HTV, HTRV, YLFEN, YRFEN) and the hit point
  are drawn; the legend names the deck, speed, approach angle, outcome and engine.
* ``--animate FILE.gif``: the fall, frame by frame (matplotlib's animation with Pillow).
* ``--pulse``: the car's deceleration (g) and speed (mph) over the contact phase, both
  engines on one pair of axes.

Only matplotlib's object API with the Agg canvas is used (no pyplot, no display, no global
backend switch). Image sizes are fixed by ``FIGSIZE`` and ``DPI`` (no tight bounding box).
"""

from __future__ import annotations

import functools
import math
import textwrap
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from deck_emulator.engine import ENGINES, Outcome, engine_for, quantities, safety
from deck_emulator.engine.ratings import ratings
from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.files import OutputSet, check_output_file
from deck_emulator.vocabulary.choices import VIEWS
from deck_emulator.vocabulary.events import EventKind
from deck_emulator.vocabulary.scene import Scene
from deck_emulator.vocabulary.units import force_in_g, ft_s_to_mph

from .answers import compartment_words

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = [
    "VIEWS",
    "FIGSIZE",
    "DPI",
    "figure_trajectory",
    "figure_pulse",
    "save_trajectory",
    "save_animation",
    "instants",
]

#: Figure size (inches) per view; at DPI the PNG is exactly FIGSIZE * DPI pixels.
FIGSIZE = {
    "side": (13.0, 6.5),
    "plan": (13.0, 6.5),
    "3d": (10.0, 8.0),
    "all": (16.0, 11.0),
    "pulse": (11.0, 6.0),
    "animate": (9.0, 4.5),
}
DPI = 100
ENGINE_COLOUR = {"emulator": "tab:blue", "core": "tab:orange"}
CMAP = "viridis"
HIT_COLOUR = "crimson"
CAR_COLOUR = "0.35"


class _Classes:
    """matplotlib's classes the pictures use, by name."""

    def __init__(self, *classes):
        self.__dict__.update((c.__name__, c) for c in classes)


@functools.cache
def mpl():
    """matplotlib, imported on first use (so that registering the command costs nothing)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch, Polygon

    return _Classes(FigureCanvasAgg, Normalize, Figure, Line2D, Patch, Polygon)


# ====================================================================== geometry helpers


#: Most instants a picture draws the post at (``--every`` finer than the run allows is refused).
MAX_INSTANTS = 2000
#: Finest ``--every`` (ms) taken before the run: the listing prints every 1.6 ms.
MIN_EVERY_MS = 0.1


def check_every(every_ms: float | None) -> None:
    """``--every`` before any work: ``None`` (the default), or a finite number of ms at least
    :data:`MIN_EVERY_MS`; ``UsageError`` (one line) otherwise."""
    if every_ms is None:
        return
    if not (math.isfinite(every_ms) and every_ms > 0):
        raise UsageError(f"--every {every_ms:g}: must be a positive, finite number of ms")
    if every_ms < MIN_EVERY_MS:
        raise UsageError(f"--every {every_ms:g}: at least {MIN_EVERY_MS:g} ms (the listing "
                         "prints every 1.6 ms)")


def instants(res: Outcome, every: float | None = None) -> list[int]:
    """Sample indices at regular instants from t = 0 to the end (the end included); at most
    :data:`MAX_INSTANTS` of them (``ValueError`` beyond)."""
    end = res.end_time_s
    if every is None:
        every = next((s for s in (0.01, 0.02, 0.025, 0.05, 0.1, 0.2) if end / s <= 20), 0.5)
    if end / every > MAX_INSTANTS:
        raise ValueError(f"--every {1000 * every:g} ms draws the post {end / every:.0f} times "
                         f"over the run's {1000 * end:g} ms; at most {MAX_INSTANTS}: a larger "
                         "--every")
    ts = np.arange(0.0, end + 1e-9, every)
    return sorted({res.at(t) for t in ts} | {len(res.t) - 1})


def _post_chain(res: Outcome) -> list[str]:
    """The post drawn as one line: (C,) Q, P, R and, for a second luminaire, back to P and
    out to U."""
    chain = ["Q", "P", "R"] + (["P", "U"] if "U" in res.points else [])
    c, q = res.points.get("C"), res.points.get("Q")
    if c is not None and not np.allclose(c[0], q[0], equal_nan=True):
        chain = ["C"] + chain
    return [k for k in chain if k in res.points]


def post_l(res: Outcome, i: int) -> np.ndarray:
    """(k, 3) XL, YL, ZL of the post's chain at sample i (NaN rows dropped)."""
    pts = np.array([res.points[k][i] for k in _post_chain(res)])
    pts = pts[~np.isnan(pts).any(axis=1)]
    return res.to_l(pts)


def _car_xy_l(res: Outcome, xv: np.ndarray, yv: np.ndarray):
    """XV, YV of the car -> XL, YL."""
    a = safety.approach_angle_rad(res.scene)
    ca, sa = math.cos(a), math.sin(a)
    xx = xv * ca + yv * sa
    yy = -xv * sa + yv * ca
    base = res.scene.post.base
    return xx - base.xx_ft, yy - base.yy_ft


def _profile(res: Outcome, sv: float, yv: float):
    """The car's side profile at YV = yv: XL and ZL arrays (bumper at the ground round to tail)."""
    body = safety.car_body(res.scene)
    o = body.outline_xv(sv)
    h = res.scene.environment.ground_depth_ft
    xv = np.array(
        [o["XBUMP"], o["XBUMP"], o["SV"], o["SV"], o["XENTOP"], o["XENTOP"], o["XTAIL"], o["XTAIL"]]
    )
    zz = np.array([-h, body.hood_height_ft, body.hood_height_ft, body.top_height_ft,
                   body.top_height_ft, body.trunk_height_ft, body.trunk_height_ft, -h])
    xl, _ = _car_xy_l(res, xv, np.full_like(xv, yv))
    return xl, zz + h


def hit_index(res: Outcome) -> int:
    return res.at(res.hit_time_s) if res.hit_time_s is not None else len(res.t) - 1


def _hit_point_l(res: Outcome):
    point = res.hit.point if res.hit else None
    point = "R" if point == "R&U" else point  # the twin's joint hit: marked at R
    if point is None or point not in res.points:
        return None
    p = res.points[point][hit_index(res)]
    return None if np.isnan(p).any() else res.to_l(p)


def _legend_title(res: Outcome) -> str:
    if res.hit:
        t = res.hit.sentence()
        t = t[:1].upper() + t[1:]
    else:
        t = f"no hit by {1000 * res.end_time_s:.0f} ms" + (" (run stopped)" if res.error else "")
    if res.engine == "core":
        eng = f"core, {res.settings}"
    else:
        eng = "emulator, " + (f"{'+'.join(res.errata)} erratum" if res.errata
                              else "listing as printed")
    return (f"{res.name}: {res.speed_mph:.3g} mph, α = {res.angle_deg:.3g}°\n{t}\n"
            + "".join(f"{line}\n" for line in _compartment_lines(res)) + f"engine: {eng}")


def _compartment_lines(res: Outcome, width: int = 60) -> list[str]:
    """What the run's ratings say of the occupant compartment, for a caption: the post that
    goes through the car is said, whatever point the listing's hit names."""
    comp = (ratings(res) or {}).get("occupant_compartment")
    if comp is None:
        return []
    words = f"Occupant compartment {compartment_words(comp)}"
    if comp["verdict"] == "not judged" and comp["contact_test"] != "segments":
        words += " (this model tests only P, R and C against the car)"
    return textwrap.wrap(words, width, subsequent_indent="  ")


def _every_label(res: Outcome, idx: list[int]) -> str:
    if len(idx) > 2:
        step = 1000 * (res.t[idx[1]] - res.t[idx[0]])
        return f"post every {step:.0f} ms (colour: time)"
    return "post (colour: time)"


# ============================================================================= views


def _norm(res):
    return mpl().Normalize(0.0, max(res.end_time_s, 1e-6))


def _draw_post(ax, res: Outcome, idx: list[int], axes: tuple[int, int]):
    """The post through its named points at the instants ``idx`` (coloured by time) and at the
    hit (red), projected on the coordinate pair ``axes`` of XL, YL, ZL."""
    import matplotlib

    cmap = matplotlib.colormaps[CMAP]
    norm = _norm(res)
    a, b = axes
    for i in idx:
        p = post_l(res, i)
        ax.plot(
            p[:, a], p[:, b], "-", color=cmap(norm(res.t[i])), lw=1.6, marker="o", ms=2.5, zorder=3
        )
    hi = hit_index(res)
    p = post_l(res, hi)
    ax.plot(p[:, a], p[:, b], "-", color=HIT_COLOUR, lw=2.6, marker="o", ms=4, zorder=5)
    hp = _hit_point_l(res)
    if hp is not None:
        ax.plot(hp[a], hp[b], marker="*", ms=18, color="gold", mec="k", zorder=6)
    _name_points(ax, res, 0, axes)
    if hi != 0:  # a run that ended at its first sample: its points are named once
        _name_points(ax, res, hi, axes)


def car_side(ax, res: Outcome, i: int) -> list[float]:
    """The car's side profile at sample i (near and far fender for an angled approach) and its
    windshield; returns the YV of the profiles drawn."""
    sv = res.sv[i]
    body = safety.car_body(res.scene)
    fenders = [body.left_fender_ft, body.right_fender_ft]
    sides = fenders if safety.approach_angle_rad(res.scene) != 0 else [0.5 * sum(fenders)]
    for k, yv in enumerate(sides):
        xl, zl = _profile(res, sv, yv)
        ax.add_patch(
            mpl().Polygon(
                np.c_[xl, zl],
                closed=True,
                fc="0.85" if k == 0 else "none",
                ec=CAR_COLOUR,
                lw=1.4,
                ls="-" if k == 0 else "--",
                zorder=2,
            )
        )
    o = body.outline_xv(sv)
    wx, _ = _car_xy_l(res, np.array([o["SV"]]), np.array([sides[0]]))
    h = res.scene.environment.ground_depth_ft
    ax.plot(
        [wx[0], wx[0]],
        [body.hood_height_ft + h, body.top_height_ft + h],
        color="tab:cyan",
        lw=3,
        zorder=2.5,
    )
    return sides


def _draw_side(ax, res: Outcome, idx: list[int]):
    hi = hit_index(res)
    _draw_post(ax, res, idx, (0, 2))
    # car at the hit (near and far fender for an angled approach)
    sides = car_side(ax, res, hi)
    sv = res.sv[hi]
    body = safety.car_body(res.scene)
    o = body.outline_xv(sv)
    # ground
    ax.axhline(0.0, color="saddlebrown", lw=1.5, zorder=1)
    # direction of travel
    xb, _ = _car_xy_l(res, np.array([o["XBUMP"]]), np.array([sides[0]]))
    ax.annotate(
        "",
        xy=(xb[0] - 4, 1.0),
        xytext=(xb[0] - 0.3, 1.0),
        arrowprops=dict(arrowstyle="->", color=CAR_COLOUR, lw=1.5),
    )
    ax.update_datalim([(xb[0] - 5, 1.0)])  # keep the arrow in view
    ax.set_xlabel("XL (ft): along the highway from the base of the support; car travels to −XL")
    ax.set_ylabel("ZL (ft): height above the ground")
    ax.set_aspect("equal", adjustable="datalim")
    ylo = min(-1.0, float(np.nanmin([post_l(res, i)[:, 2].min() for i in idx])) - 1)
    ax.update_datalim([(0.0, ylo)])  # a strip of ground below the lowest point
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_title("Side view (XL–ZL)")


def car_plan(ax, res: Outcome, i: int) -> None:
    """The car's outline in plan at sample i: hood, roof (darker), trunk and windshield."""
    body = safety.car_body(res.scene)
    sv = res.sv[i]
    o = body.outline_xv(sv)
    yl, yr = body.left_fender_ft, body.right_fender_ft

    def rect(x0, x1, **kw):
        xv = np.array([x0, x1, x1, x0])
        yv = np.array([yl, yl, yr, yr])
        x, y = _car_xy_l(res, xv, yv)
        ax.add_patch(mpl().Polygon(np.c_[x, y], closed=True, **kw))

    rect(o["XBUMP"], o["SV"], fc="0.88", ec=CAR_COLOUR, lw=1.2, zorder=1)
    rect(o["SV"], o["XENTOP"], fc="0.72", ec=CAR_COLOUR, lw=1.2, zorder=1)
    rect(o["XENTOP"], o["XTAIL"], fc="0.88", ec=CAR_COLOUR, lw=1.2, zorder=1)
    wx, wy = _car_xy_l(res, np.array([o["SV"], o["SV"]]), np.array([yl, yr]))
    ax.plot(wx, wy, color="tab:cyan", lw=3, zorder=1.5)


def _draw_plan(ax, res: Outcome, idx: list[int]):
    hi = hit_index(res)
    body = safety.car_body(res.scene)
    sv = res.sv[hi]
    o = body.outline_xv(sv)
    yl, yr = body.left_fender_ft, body.right_fender_ft
    car_plan(ax, res, hi)
    _draw_post(ax, res, idx, (0, 1))
    # direction of travel along -XV
    a = safety.approach_angle_rad(res.scene)
    bx, by = _car_xy_l(res, np.array([o["XBUMP"]]), np.array([0.5 * (yl + yr)]))
    tip = (bx[0] - 4 * math.cos(a), by[0] + 4 * math.sin(a))
    ax.annotate(
        "",
        xy=tip,
        xytext=(bx[0], by[0]),
        arrowprops=dict(arrowstyle="->", color=CAR_COLOUR, lw=1.5),
    )
    ax.update_datalim([(tip[0] - math.cos(a), tip[1] + math.sin(a))])  # keep the arrow in view
    ax.set_xlabel("XL (ft): along the highway from the base of the support")
    ax.set_ylabel("YL (ft): across the highway")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_title("Plan view (XL–YL)")


def _name_points(ax, res, i, axes):
    """Name the post's points at sample i (a point on top of one already named is skipped)."""
    done = []
    left = i != 0  # the end state is named on the left, t = 0 on the right
    chain = _post_chain(res)
    c_on_q = "C" not in chain and "C" in res.points and not np.isnan(res.points["C"][0]).any()
    for k in chain:
        p = res.points[k][i]
        if np.isnan(p).any():
            continue
        name = "Q=C" if k == "Q" and c_on_q else k
        q = res.to_l(p)
        xy = np.array([q[axes[0]], q[axes[1]]])
        if any(np.hypot(*(xy - o)) < 0.8 for o in done):
            continue
        done.append(xy)
        ax.annotate(
            name,
            tuple(xy),
            xytext=(-10 if left else 5, 5),
            textcoords="offset points",
            fontsize=9,
            fontweight="bold",
            zorder=7,
        )


def _box_faces(x0, x1, y0, y1, z0, z1):
    c = np.array(
        [
            [x0, y0, z0],
            [x1, y0, z0],
            [x1, y1, z0],
            [x0, y1, z0],
            [x0, y0, z1],
            [x1, y0, z1],
            [x1, y1, z1],
            [x0, y1, z1],
        ]
    )
    f = [[0, 1, 2, 3], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 3, 7, 4]]
    return c, f


def _draw_3d(ax, res: Outcome, idx: list[int]):
    import matplotlib
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    cmap = matplotlib.colormaps[CMAP]
    norm = _norm(res)
    hi = hit_index(res)
    body = safety.car_body(res.scene)
    h = res.scene.environment.ground_depth_ft
    sv = res.sv[hi]
    o = body.outline_xv(sv)
    faces = []
    for x0, x1, ztop in (
        (o["XBUMP"], o["SV"], body.hood_height_ft),
        (o["SV"], o["XENTOP"], body.top_height_ft),
        (o["XENTOP"], o["XTAIL"], body.trunk_height_ft),
    ):
        corners, fidx = _box_faces(x0, x1, body.left_fender_ft, body.right_fender_ft, -h, ztop)
        xl, yl = _car_xy_l(res, corners[:, 0], corners[:, 1])
        cl = np.c_[xl, yl, corners[:, 2] + h]
        faces += [cl[f] for f in fidx]
    ax.add_collection3d(
        Poly3DCollection(faces, facecolor="0.8", edgecolor=CAR_COLOUR, lw=0.6, alpha=0.35)
    )
    allp = np.vstack([post_l(res, i) for i in idx] + [np.vstack(faces)])
    lo, hi_ = allp.min(axis=0), allp.max(axis=0)
    pad = 2.0
    gx = [lo[0] - pad, hi_[0] + pad]
    gy = [lo[1] - pad, hi_[1] + pad]
    ax.add_collection3d(
        Poly3DCollection(
            [[(gx[0], gy[0], 0), (gx[1], gy[0], 0), (gx[1], gy[1], 0), (gx[0], gy[1], 0)]],
            facecolor="tan",
            alpha=0.25,
            edgecolor="saddlebrown",
        )
    )
    for i in idx:
        p = post_l(res, i)
        ax.plot(p[:, 0], p[:, 1], p[:, 2], "-", color=cmap(norm(res.t[i])), lw=1.5)
    p = post_l(res, hi)
    ax.plot(p[:, 0], p[:, 1], p[:, 2], "-", color=HIT_COLOUR, lw=2.6)
    hp = _hit_point_l(res)
    if hp is not None:
        ax.scatter(
            [hp[0]],
            [hp[1]],
            [hp[2]],
            marker="*",
            s=250,
            color="gold",
            edgecolor="k",
            depthshade=False,
        )
    for k in dict.fromkeys(_post_chain(res)):
        q = res.to_l(res.points[k][hi])
        if not np.isnan(q).any():
            ax.text(q[0], q[1], q[2], f" {k}", fontsize=9, fontweight="bold")
    ax.set_xlim(gx)
    ax.set_ylim(gy)
    ax.set_zlim(0, max(hi_[2], 1.0) + 1)
    dx, dy, dz = gx[1] - gx[0], gy[1] - gy[0], max(hi_[2], 1.0) + 1
    ax.set_box_aspect((dx, max(dy, 0.45 * dx), max(dz, 0.3 * dx)))  # not to scale across
    from matplotlib.ticker import MaxNLocator

    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(5))
    ax.set_xlabel("XL (ft)")
    ax.set_ylabel("YL (ft)")
    ax.set_zlabel("ZL (ft)")
    ax.view_init(elev=22, azim=-60)
    ax.set_title("3-d view")


def _legend_handles(res: Outcome, idx):
    import matplotlib

    cmap = matplotlib.colormaps[CMAP]
    h = [
        mpl().Line2D(
            [], [], color=cmap(0.5), lw=1.6, marker="o", ms=2.5, label=_every_label(res, idx)
        ),
        mpl().Line2D(
            [],
            [],
            color=HIT_COLOUR,
            lw=2.6,
            marker="o",
            ms=4,
            label=f"post at the {'hit' if res.hit else 'end'}"
            f" (t = {1000 * float(res.t[hit_index(res)]):.1f} ms)",
        ),
    ]
    if _hit_point_l(res) is not None:
        h.append(
            mpl().Line2D(
                [],
                [],
                color="gold",
                marker="*",
                ms=14,
                mec="k",
                ls="none",
                label=f"hit point ({res.hit.point} on the {res.hit.surface.value})",
            )
        )
    h += [
        mpl().Patch(fc="0.85", ec=CAR_COLOUR, label=f"car at the {'hit' if res.hit else 'end'} "
                     "(listing's outline)"),
        mpl().Line2D([], [], color="tab:cyan", lw=3, label="windshield (at SV)"),
        mpl().Line2D([], [], color="saddlebrown", lw=1.5, label="ground"),
    ]
    return h


def _colorbar(fig, ax, res):
    import matplotlib
    from matplotlib.cm import ScalarMappable

    sm = ScalarMappable(norm=_norm(res), cmap=matplotlib.colormaps[CMAP])
    cb = fig.colorbar(sm, ax=ax, shrink=0.8, pad=0.01)
    cb.set_label("time (s)")


def _summary_text(res: Outcome) -> str:
    lines = _legend_title(res).split("\n") + [""]
    for e in res.events:
        lines.append(f"{1000 * e.time_s:7.1f} ms  {e.sentence()}")
    m = quantities.pulse(res)
    if m is not None:
        dv = quantities.QUANTITIES["delta_v_contact_mph"]
        lines += ["", "Occupant risk (flail-space model):",
                  f"  ΔV {dv.show(dv.of(res))} {dv.unit}"] + ["  " + s for s in m.lines()]
    c = quantities.clearance(res)
    if c is not None:
        lines.append("")
        if c.body_ft is None:
            lines.append("The post never passes over the car in free flight.")
        else:
            lines.append(
                f"Least clearance over the car: {c.body_ft:.2f} ft over the "
                f"{c.body_surface} at {1000 * c.body_time_s:.0f} ms ({c.body_where})"
            )
            lines.append(
                "Least clearance over roof/windshield: "
                + (
                    "never over it"
                    if c.roof_ft is None
                    else f"{c.roof_ft:.2f} ft at {1000 * c.roof_time_s:.0f} ms ({c.roof_where})"
                )
            )
            if c.touch_time_s is not None:
                lines.append(
                    f"The post's line Q-P-R is first inside the car's outline at "
                    f"{1000 * c.touch_time_s:.1f} ms ({c.touch_surface}); the listing "
                    "checks only P, R and C."
                )
    if res.error:
        lines += ["", f"Run stopped: {res.error}"]
    return "\n".join(_wrap(s, 92) for s in lines)


def _wrap(s: str, width: int) -> str:
    return "\n".join(textwrap.wrap(s, width, subsequent_indent="    ")) if len(s) > width else s


#: the trajectory pictures' legend beside or under the views
_LEGEND = dict(fontsize=9, title_fontsize=9, alignment="left")


def figure_trajectory(res: Outcome, view: str = "side", every: float | None = None) -> Figure:
    """The trajectory picture of one run."""
    if view not in VIEWS:
        raise ValueError(f"view must be one of {VIEWS}")
    if not res.t.size:
        raise ValueError(f"{res.name}: the {res.engine} gave no trajectory ({res.error})")
    idx = instants(res, every)
    fig = mpl().Figure(figsize=FIGSIZE[view], dpi=DPI, layout="constrained")
    mpl().FigureCanvasAgg(fig)
    handles = _legend_handles(res, idx)
    title = _legend_title(res)
    if view in ("side", "plan"):
        ax = fig.add_subplot()
        (_draw_side if view == "side" else _draw_plan)(ax, res, idx)
        _colorbar(fig, ax, res)
        if view == "plan":
            handles = [h for h in handles if h.get_label() != "ground"]
            handles.insert(
                4, mpl().Patch(fc="0.72", ec=CAR_COLOUR, label="roof (passenger compartment)")
            )
        fig.legend(handles=handles, title=title, loc="outside right upper", **_LEGEND)
    elif view == "3d":
        ax = fig.add_subplot(projection="3d")
        _draw_3d(ax, res, idx)
        handles = [h for h in handles if not h.get_label().startswith("windshield")]
        fig.legend(handles=handles, title=title, loc="outside lower center", ncols=3, **_LEGEND)
    else:
        gs = fig.add_gridspec(2, 2)
        ax1 = fig.add_subplot(gs[0, 0])
        _draw_side(ax1, res, idx)
        ax2 = fig.add_subplot(gs[0, 1])
        _draw_plan(ax2, res, idx)
        _colorbar(fig, ax2, res)
        ax3 = fig.add_subplot(gs[1, 0], projection="3d")
        _draw_3d(ax3, res, idx)
        ax4 = fig.add_subplot(gs[1, 1])
        ax4.axis("off")
        ax4.legend(handles=handles, loc="upper left", fontsize=9, framealpha=0.9)
        ax4.text(
            0.0,
            0.55,
            _summary_text(res),
            transform=ax4.transAxes,
            va="top",
            ha="left",
            fontsize=9,
            family="monospace",
        )
    return fig


def save_trajectory(res: Outcome, out, view: str = "side", every: float | None = None) -> None:
    """Write the trajectory picture to ``out`` (whole or not at all)."""
    with OutputSet() as files:
        savefig(figure_trajectory(res, view, every), files.path(out))


def savefig(fig, path) -> None:
    fig.savefig(path, dpi=DPI)  # the format from the name (a staged name keeps the suffix)


# ============================================================================= pulse


def figure_pulse(results: list[Outcome]) -> Figure:
    """Deceleration (g, left) and speed (mph, right) over the contact, every engine given."""
    fig = mpl().Figure(figsize=FIGSIZE["pulse"], dpi=DPI, layout="constrained")
    mpl().FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax2 = ax.twinx()
    handles = []
    t_max = 0.0
    first = results[0]
    notes = []
    for res in results:
        col = ENGINE_COLOUR.get(res.engine, "k")
        label = res.engine + (f" ({'+'.join(res.errata)})" if res.errata else "")
        if res.engine == "core":
            label = f"core ({res.settings})"
        if res.pulse_t.size:
            tms = 1000 * res.pulse_t
            if res.engine == "emulator":  # per step: the value over the step ending at t
                ax.step(tms, res.pulse_g, where="pre", color=col, lw=1.0)
            else:
                ax.plot(tms, res.pulse_g, color=col, lw=1.3)
            handles.append(
                mpl().Line2D([], [], color=col, lw=1.3, label=f"{label}: deceleration (g)")
            )
        t, vv = res.contact_history()
        if t.size:
            ax2.plot(1000 * t, ft_s_to_mph(np.abs(vv)), color=col, lw=1.6, ls="--")
            handles.append(
                mpl().Line2D([], [], color=col, lw=1.6, ls="--", label=f"{label}: speed (mph)")
            )
            t_max = max(t_max, float(t[-1]))
        for e in res.events:
            if e.kind in (EventKind.LOST_FIRST_SPRING, EventKind.LOST_VEHICLE):
                ax.axvline(1000 * e.time_s, color=col, lw=0.8, ls=":")
        m = quantities.pulse(res)
        if m is not None:
            q = quantities.values(res, ("delta_v_contact_mph", "delta_v_crush_mph",
                                        "max_decel_every_step_g", "max_decel_10ms_g", "oiv_m_s",
                                        "ora_g"))
            show = {k: quantities.QUANTITIES[k].show(v) for k, v in q.items()}
            crush = ("" if q["delta_v_crush_mph"] is None else
                     f" (to the end of the crush pulse, the reading that fits the report's steel "
                     f"columns: "
                     f"{show['delta_v_crush_mph']} mph)")
            rated = (ratings(res) or {}).get("oiv_m_s", {}).get("verdicts", {})
            rating = (f" ({rated['nchrp350_oiv']}, NCHRP 350)" if rated.get("nchrp350_oiv")
                      else "")
            notes.append(
                f"{res.engine}: ΔV to the end of contact {show['delta_v_contact_mph']} mph{crush},"
                f"\n    max, every step {show['max_decel_every_step_g']} g, 10 ms avg "
                f"{show['max_decel_10ms_g']} g, OIV {show['oiv_m_s']} m/s{rating}, "
                f"ORA {show['ora_g']} g"
            )
        if res.error:
            notes.append(f"{res.engine}: run stopped: {res.error}")
    handles.append(
        mpl().Line2D(
            [], [], color="0.3", lw=0.8, ls=":", label="lost contact: first spring, then the car"
        )
    )
    car = first.scene.vehicle
    fc = (car.force_cap_lb or 0.0) if car is not None else 0.0
    if fc > 0 and t_max > 0:
        g_cap = force_in_g(fc, car.mass_slug, first.gravity_ft_s2)
        ax.annotate(
            f"force capped at FCONST = {fc:g} lb ({g_cap:.2f} g)",
            xy=(1000 * t_max * 0.45, g_cap),
            xytext=(1000 * t_max * 0.45, g_cap + 0.6),
            ha="center",
            fontsize=8,
            arrowprops=dict(arrowstyle="->", color="0.3"),
        )
    ax.set_xlim(0, 1000 * t_max * 1.03 if t_max else None)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("time after impact (ms)")
    ax.set_ylabel("vehicle deceleration (g)")
    ax2.set_ylabel("vehicle speed (mph)")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_title(
        f"{first.name}: vehicle pulse over the contact with the post — "
        f"{first.speed_mph:.3g} mph, α = {first.angle_deg:.3g}°"
    )
    ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    if notes:
        oiv, ora = safety.CRITERIA["nchrp350_oiv"], safety.CRITERIA["nchrp350_ora"]
        notes.append(f"NCHRP 350 limits (breakaway supports): OIV {oiv.label()}; "
                     f"ORA {ora.label()}")
        ax.text(
            0.22,
            0.62,
            "\n".join(notes),
            transform=ax.transAxes,
            fontsize=8,
            va="center",
            ha="left",
            bbox=dict(fc="white", ec="0.7", alpha=0.9),
        )
    return fig


# ============================================================================= animation


def save_animation(
    res: Outcome, out, view: str = "side", frame_s: float = 0.01, fps: int = 20, dpi: int = 80
) -> int:
    """Write the fall as an animated GIF to ``out`` (whole or not at all); returns the number
    of frames."""
    with OutputSet() as files:
        return _save_animation(res, files.path(out), view, frame_s, fps, dpi)


def _save_animation(res: Outcome, out, view: str, frame_s: float, fps: int, dpi: int) -> int:
    """The frames: the post every ``frame_s`` (a trail every fifth), the car, the instant the
    post first enters the car (where the ratings say it does: the car's outline turns red
    and the post there stays drawn), and the run's end held for a second, its hit point
    starred; the caption is the still picture's (:func:`_legend_title`).  The figure takes
    the shape of what it shows, so the axes fill the frame."""
    import matplotlib
    from matplotlib.animation import FuncAnimation

    cmap, norm = matplotlib.colormaps[CMAP], _norm(res)
    comp = (0, 2) if view == "side" else (0, 1)
    body = safety.car_body(res.scene)
    yl, yr = body.left_fender_ft, body.right_fender_ft
    base_yy = res.scene.post.base.yy_ft
    last = len(res.t) - 1
    # fixed limits from the whole run and the car's path
    allp = np.vstack([post_l(res, i) for i in range(0, len(res.t), 5)] + [post_l(res, last)])
    car_x = []
    for i in (0, last):
        o = body.outline_xv(res.sv[i])
        xs, _ = _car_xy_l(res, np.array([o["XBUMP"], o["XTAIL"]]), np.array([yl, yr]))
        car_x += list(xs)
    x0, x1 = min(allp[:, 0].min(), min(car_x)) - 2, max(allp[:, 0].max(), 12.0) + 2
    if view == "side":
        y0, y1 = min(-1.0, allp[:, 2].min() - 1), max(allp[:, 2].max(), 6) + 1
    else:
        y0 = min(allp[:, 1].min(), yl - base_yy - 2) - 1
        y1 = max(allp[:, 1].max(), yr - base_yy + 2) + 1
    title = _legend_title(res)
    top_in = 0.2 + 0.16 * title.count("\n")  # the caption's lines above the axes
    width = FIGSIZE["animate"][0]
    box_h = min(max((width - 0.9) * (y1 - y0) / (x1 - x0), 2.0), 1.5 * width)
    height = box_h + top_in + 0.6
    # one foot the same length both ways: where the box was bounded, the view widens to fill it
    grow = max(box_h / (width - 0.9) * (x1 - x0) - (y1 - y0), 0.0)
    y0, y1 = y0 - grow / 2, y1 + grow / 2
    grow = max((width - 0.9) / box_h * (y1 - y0) - (x1 - x0), 0.0)
    x0, x1 = x0 - grow / 2, x1 + grow / 2
    fig = mpl().Figure(figsize=(width, height), dpi=dpi)  # fixed layout: fast frames
    mpl().FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    fig.subplots_adjust(left=0.7 / width, right=1 - 0.2 / width, bottom=0.6 / height,
                        top=1 - top_in / height)
    ax.set(xlim=(x0, x1), ylim=(y0, y1))
    ax.set_xlabel("XL (ft)")
    ax.set_ylabel("ZL (ft)" if view == "side" else "YL (ft)")
    ax.grid(True, lw=0.4, alpha=0.5)
    if view == "side":
        ax.axhline(0.0, color="saddlebrown", lw=1.5)
    fig.text(0.1 / width, 1 - 0.1 / height, title, ha="left", va="top", fontsize=8)
    clock = fig.text(1 - 0.2 / width, 1 - 0.1 / height, "", ha="right", va="top", fontsize=9)
    compartment = (ratings(res) or {}).get("occupant_compartment") or {}
    enters = compartment.get("time_s")  # the post's first strike on the car, if any
    entry = None if enters is None else res.at(enters)
    frames = sorted({res.at(t) for t in np.arange(0, res.end_time_s + 1e-9, frame_s)}
                    | {last} | ({entry} if entry is not None else set()))
    (post,) = ax.plot([], [], "-o", color=HIT_COLOUR, lw=2.5, ms=3, zorder=5)
    car = mpl().Polygon(np.zeros((4, 2)), closed=True, fc="0.85", ec=CAR_COLOUR, zorder=2)
    ax.add_patch(car)
    hp = _hit_point_l(res)

    def car_shape(i):
        sv = res.sv[i]
        if view == "side":
            xl, zl = _profile(res, sv, 0.5 * (yl + yr))
            return np.c_[xl, zl]
        o = body.outline_xv(sv)
        x, y = _car_xy_l(res, np.array([o["XBUMP"], o["XTAIL"], o["XTAIL"], o["XBUMP"]]),
                         np.array([yl, yl, yr, yr]))
        return np.c_[x, y]

    def update(k):
        if k >= len(frames):  # the end, held
            return []
        i = frames[k]
        p = post_l(res, i)
        post.set_data(p[:, comp[0]], p[:, comp[1]])
        if k and k % 5 == 0:
            q = post_l(res, frames[k - 5])
            ax.plot(q[:, comp[0]], q[:, comp[1]], "-", color=cmap(norm(res.t[frames[k - 5]])),
                    lw=1, alpha=0.6, zorder=3)
        car.set_xy(car_shape(i))
        words = f"t = {1000 * res.t[i]:.0f} ms"
        if i == entry:
            ax.plot(p[:, comp[0]], p[:, comp[1]], "--", color=HIT_COLOUR, lw=1.5, zorder=4)
            car.set(ec=HIT_COLOUR, lw=2.5)
        if entry is not None and i >= entry:
            words += (f"\n{compartment['part']} struck the {compartment['surface']} at "
                      f"{1000 * enters:.0f} ms")
        if i == last:
            words += "\n" + (res.hit.sentence() if res.hit else _legend_title(res).split("\n")[1])
            if hp is not None:
                ax.plot(hp[comp[0]], hp[comp[1]], marker="*", ms=14, color="gold", mec="k",
                        zorder=6)
        clock.set_text(words)
        return []

    anim = FuncAnimation(fig, update, frames=len(frames) + fps, blit=False)
    anim.save(str(out), writer=animation_writer(out)(fps=fps), dpi=dpi)
    return len(frames)


# ================================================================================== CLI


def picture_formats() -> list[str]:
    """The file types matplotlib writes a still picture in (png, svg, pdf, ...)."""
    return sorted(set(mpl().FigureCanvasAgg(mpl().Figure()).get_supported_filetypes())
                  - {"gif", "raw", "rgba"})


def animation_writer(path):
    """The animation writer for ``path``'s suffix, or a UsageError saying why there is none."""
    from matplotlib.animation import FFMpegWriter, PillowWriter, writers

    suffix = Path(path).suffix.lower()
    if suffix == ".gif":
        return PillowWriter
    if suffix == ".mp4":
        if writers.is_available("ffmpeg"):
            return FFMpegWriter
        raise UsageError(f"--animate {path}: MP4 needs ffmpeg, which is not installed here; "
                         "name a .gif file instead")
    raise UsageError(f"--animate {path}: the animation is written as .gif (or .mp4 with ffmpeg)")


def check_plot_outputs(out, animate=None) -> None:
    """Before any work: the formats, and that every output can be written."""
    formats = picture_formats()
    if Path(out).suffix.lower().lstrip(".") not in formats:
        raise UsageError(f"--out {out}: name a picture file ending in ." + ", .".join(
            f for f in formats if f in ("png", "svg", "pdf")) + " or another matplotlib "
            "format (" + ", ".join(formats) + ")")
    check_output_file(out)
    if animate:
        animation_writer(animate)
        check_output_file(animate)
        if Path(animate).resolve() == Path(out).resolve():
            raise UsageError("--out and --animate name the same file")


def draw(source, name: str, *, engine: str, options: dict, out, view: str = "side",
         pulse: bool = False, animate=None, every_ms: float | None = None,
         scene: Scene | None = None) -> tuple[bool, list[str]]:
    """``deck-emulator plot``: run ``source`` (a deck, or a scene for the core) on ``engine``
    (both with ``pulse``; ``options``: each engine's keywords) and write the picture ``out``
    (the trajectory's ``view``, or the pulse) and ``animate`` (the fall as a GIF), both or
    neither (the command has checked them: :func:`check_plot_outputs`); ``scene``: the core's
    scene of ``source``, already built and checked by the command.  Returns whether a run it
    drew stopped early (exit status 3) and the lines it says (each run that stopped, the
    files written)."""
    check_every(every_ms)
    said: list[str] = []

    def run(which: str) -> Outcome:
        given = {"scene": scene} if which == "core" and scene is not None else {}
        res = engine_for(which, **options[which]).run(source, **given)
        if res.error:
            said.append(f"{getattr(source, 'path', None) or name}: the {which} stopped early: "
                        f"{res.error}" + (f"; {res.hint}" if res.hint else ""))
        return res

    every = None if every_ms is None else every_ms / 1000.0
    with OutputSet() as files:  # the picture and the animation: both written, or neither
        if pulse:
            results = []
            for which in ENGINES:
                try:
                    results.append(run(which))
                except ImportError as exc:  # the core not installed: the emulator alone
                    said.append(f"the {which} is not available ({exc})")
            results = [r for r in results if r.t.size]
            if not results:  # every run stopped before its first step: as `run` says, exit 3
                raise RunFailed("no engine produced a velocity history")
            savefig(figure_pulse(results), files.path(Path(out)))
            main = next((r for r in results if r.engine == engine), results[0])
            stopped = any(r.error for r in results)
        else:
            main = run(engine)
            if not main.t.size:  # the run stopped before its first step: exit 3
                raise RunFailed(f"the {engine} produced no trajectory: {main.error}")
            try:
                instants(main, every)  # too many instants for --every: said before drawing
            except ValueError as exc:
                raise UsageError(str(exc)) from None
            savefig(figure_trajectory(main, view, every), files.path(Path(out)))
            stopped = bool(main.error)
        if animate:
            _save_animation(main, files.path(Path(animate)), "plan" if view == "plan" else "side",
                            0.01, 20, 80)
    said.append(f"wrote {', '.join([str(out)] + ([str(animate)] if animate else []))}")
    return stopped, said

