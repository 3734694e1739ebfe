"""The pictures: valid PNGs (and a GIF) of the expected pixel size that show the run's data
(the post's computed points where the picture puts them, in the colour of their instant; the
pulse through the computed decelerations); the command's options and messages."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest
from PIL import Image

from deck_emulator.present import plot
from deck_emulator.vocabulary.events import EventKind
from deck_emulator.legacy.deck import read_deck
from deck_emulator.engine import engine_for
from deck_emulator.vocabulary.units import ft_s_to_mph
from pictures import (
    Mapper,
    axes_box,
    colour_near,
    in_boxes,
    in_polygons,
    ink_near,
    inside_box,
    near_points,
    near_segments,
    read_png,
    segments_of,
    spots_along,
)

ROOT = Path(__file__).resolve().parents[2]
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def check_png(path: Path, view: str):
    assert path.read_bytes()[:8] == PNG_SIGNATURE
    w, h = plot.FIGSIZE[view]
    with Image.open(path) as im:
        assert im.format == "PNG"
        assert im.size == (round(w * plot.DPI), round(h * plot.DPI))
        px = np.asarray(im.convert("RGB"), dtype=np.int64)
    # not blank: many colours, real contrast, and much of the picture not background white
    assert px.std() > 20
    packed = (px[..., 0] << 16) | (px[..., 1] << 8) | px[..., 2]
    assert np.unique(packed).size > 50
    assert (px.sum(axis=2) < 700).mean() > 0.03


# ------------------------------------------------------------- what the pictures show

#: The post as the pictures draw it: base Q, top P, luminaire end R (and C where it is not Q,
#: which on steel40 it is: see test_post_points_in_the_report_axes).
CHAIN = ("Q", "P", "R")
VIEW_AXES = {"side": (0, 2), "plan": (0, 1)}  # XL-ZL, XL-YL
LINE_GAP_PX = 5.0  # a spot this close to another line may be covered by it
STAR_PX = 16.0  # the hit point's star is 18 pt (25 px) across


def point_l(res, name: str, i: int) -> np.ndarray:
    """Point ``name`` at sample i in the report's XL, YL, ZL (origin on the ground under the
    base of the support): the Outcome's road axes XX, YY, ZZ less the base Q's XQO, YYQO and
    -HEIGHT (the scene's ground depth)."""
    q, depth = res.scene.post.base, res.scene.environment.ground_depth_ft
    return np.asarray(res.points[name][i], dtype=float) - np.array([q.xx_ft, q.yy_ft, -depth])


def post_l(res, i: int) -> np.ndarray:
    return np.array([point_l(res, k, i) for k in CHAIN])


def hit_index(res) -> int:
    """The sample nearest the hit; the last one for a run that stopped without a hit (the
    pictures then draw the post at the end in HIT_COLOUR)."""
    if res.hit is None:
        return len(res.t) - 1
    return int(np.argmin(np.abs(res.t - res.hit_time_s)))


def instant_colour(res, i: int):
    """The colour map's colour for sample i's time (the colour bar runs from 0 to the end)."""
    return matplotlib.colormaps[plot.CMAP](res.t[i] / res.end_time_s)


def _spots_on(line: np.ndarray) -> np.ndarray:
    return np.vstack([spots_along(p0, p1) for p0, p1 in segments_of(line)] + [np.zeros((0, 2))])


PANELS = {"Side view": "side", "Plan view": "plan", "3-d view": "3d"}  # by the axes' title


def check_trajectory_content(path: Path, res, view: str, instants: float = 0.5) -> dict:
    """The picture at ``path`` (written by save_trajectory) shows ``res`` in every panel:
    pixels along the segments between the post's points at the hit have HIT_COLOUR, pixels
    along the post at the drawn instants the colour map's colour for their time.  The points
    come from the Outcome's arrays; the same figure drawn again by figure_trajectory gives
    only the mapping from data to pixels (its axes' transData, and the 3-d projection) and
    the boxes of its labels.  At least the fraction ``instants`` of the drawn instants must
    be seen.  Returns the counts of spots checked, per panel."""
    img = read_png(path)
    fig = plot.figure_trajectory(res, view)
    fig.canvas.draw()
    mapper = Mapper(fig, img.shape)
    assert mapper.scale == 1.0  # the PNG is written at the figure's DPI
    panels = {
        PANELS[t]: ax
        for ax in fig.axes
        for t in PANELS
        if ax.get_title().startswith(t)
    }
    assert set(panels) == ({"side", "plan", "3d"} if view == "all" else {view})
    return {kind: _check_panel(img, mapper, ax, kind, res, instants)
            for kind, ax in panels.items()}


def _check_panel(img, mapper: Mapper, ax, kind: str, res, instants: float) -> dict:
    """Spots near a label, the hit's star, the axes' edge, a line drawn over the one checked
    or (3-d) the translucent car and ground are left out; some 50 spots along the post at
    the hit and the fraction ``instants`` of the instants must remain."""
    renderer = mapper.fig.canvas.get_renderer()
    if kind == "3d":
        def project(p):
            return mapper.data3d(ax, p)
    else:
        a, b = VIEW_AXES[kind]

        def project(p):
            return mapper.data(ax, np.asarray(p)[:, [a, b]])

    hi = hit_index(res)
    idx = [i for i in plot.instants(res) if i != hi]  # the post at the hit is drawn over its own
    order = idx + [hi]  # drawing order (the hit's line has the highest zorder of the lines)
    lines = {i: project(post_l(res, i)) for i in order}
    labels = mapper.boxes(ax.texts, renderer)
    star = project(point_l(res, res.hit.point, hi)[None]) if res.hit else np.zeros((0, 2))
    frame = axes_box(mapper, ax)
    veils = []  # the 3-d view's translucent car and ground, which tint what is behind them
    if kind == "3d":
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        veils = [
            mapper.data(ax, p.vertices)
            for c in ax.collections
            if isinstance(c, Poly3DCollection)
            for p in c.get_paths()
        ]

    def hidden(spots, own):
        out = in_boxes(spots, labels) | near_points(spots, star, STAR_PX)
        out |= ~inside_box(spots, frame) | in_polygons(spots, veils)
        # lines drawn later lie over this one (mplot3d sorts only collections and patches by
        # depth, and draws them over the lines: the veils)
        for j in order[order.index(own) + 1:]:
            out |= near_segments(spots, segments_of(lines[j]), LINE_GAP_PX)
        return out

    spots = _spots_on(lines[hi])
    spots = spots[~hidden(spots, hi)]
    assert len(spots) >= 50, f"{kind}: only {len(spots)} spots along the post at the hit"
    ok = colour_near(img, spots, plot.HIT_COLOUR)
    assert ok.all(), (
        f"{kind}: {(~ok).sum()} of {len(ok)} spots along the post at the hit are not "
        f"{plot.HIT_COLOUR}, e.g. (column, row) {spots[~ok][:3].round().tolist()}"
    )
    counts = {"hit": len(spots), "instants": 0, "instant_spots": 0}
    wrong = []
    for i in idx:
        spots = _spots_on(lines[i])
        spots = spots[~hidden(spots, i)]
        if len(spots) < 3:
            continue
        ok = colour_near(img, spots, instant_colour(res, i))
        counts["instants"] += 1
        counts["instant_spots"] += len(spots)
        if not ok.all():
            wrong.append(f"t = {res.t[i]:.3f} s: {(~ok).sum()} of {len(ok)}")
    assert not wrong, f"{kind}: the post is not in its instant's colour at " + "; ".join(wrong)
    assert counts["instants"] >= instants * len(idx), (kind, counts, len(idx))
    return counts


def pulse_line(res) -> np.ndarray:
    """(time in ms, deceleration in g) along the drawn curve: the core's samples joined; the
    emulator's as steps, each value held over the step that ends at its time."""
    t, g = 1000 * res.pulse_t, res.pulse_g
    if res.engine != "emulator":
        return np.c_[t, g]
    return np.c_[np.repeat(t, 2)[:-1], np.repeat(g, 2)[1:]]


def check_pulse_content(path: Path, fig, results, least: int = 30) -> dict:
    """The pulse picture at ``path`` (written from ``fig``) draws each engine's deceleration
    through the Outcome's (pulse_t, pulse_g) points in the engine's colour.  Points near the
    axes' edge, a text, the legend, a speed curve (the same colour, dashed), a lost-contact
    line (the same colour, dotted) or a deceleration curve drawn later are left out; at least
    ``least`` points per engine must remain.  Returns the number checked per engine."""
    img = read_png(path)
    mapper = Mapper(fig, img.shape)
    ax, ax2 = fig.axes[:2]
    renderer = fig.canvas.get_renderer()
    boxes = mapper.boxes([*ax.texts, ax.get_legend()], renderer)
    frame = axes_box(mapper, ax)
    top, bottom = frame[1] - 10, frame[3] + 10
    speeds, contact_lines = [], []
    for res in results:
        t, vv = res.contact_history()
        speeds.append(mapper.data(ax2, np.c_[1000 * t, ft_s_to_mph(np.abs(vv))]))
        for e in res.events:
            if e.kind in (EventKind.LOST_FIRST_SPRING, EventKind.LOST_VEHICLE):
                c = mapper.data(ax, [[1000 * e.time_s, 0.0]])[0, 0]
                contact_lines.append([[c, top], [c, bottom]])
    curves = [mapper.data(ax, pulse_line(res)) for res in results]
    counts = {}
    for n, res in enumerate(results):
        spots = mapper.data(ax, np.c_[1000 * res.pulse_t, res.pulse_g])
        hide = ~inside_box(spots, frame) | in_boxes(spots, boxes)
        hide |= near_segments(spots, np.array(contact_lines).reshape(-1, 2, 2), 4.0)
        for line in speeds + curves[n + 1:]:
            hide |= near_segments(spots, segments_of(line), LINE_GAP_PX)
        spots = spots[~hide]
        colour = plot.ENGINE_COLOUR[res.engine]
        ok = ink_near(img, spots, colour)
        assert ok.all(), (
            f"{res.engine}: {(~ok).sum()} of {len(ok)} computed points of the pulse are not on "
            f"a {colour} line, e.g. (column, row) {spots[~ok][:3].round().tolist()}"
        )
        assert len(spots) >= least, (res.engine, len(spots))
        counts[res.engine] = len(spots)
    return counts


@pytest.fixture(scope="module")
def steel40_emulator():
    return engine_for("emulator").run(read_deck(ROOT / "decks" / "steel40.dat"))


@pytest.fixture(scope="module")
def steel40_core():
    return engine_for("core").run(read_deck(ROOT / "decks" / "steel40.dat"))


@pytest.mark.parametrize("view", plot.VIEWS)
def test_trajectory_views_show_the_post(tmp_path, steel40_emulator, view):
    out = tmp_path / f"steel40_{view}.png"
    plot.save_trajectory(steel40_emulator, out, view)
    check_png(out, view)
    check_trajectory_content(out, steel40_emulator, view)


@pytest.mark.parametrize("view", ["side", "plan"])
def test_core_trajectory_picture(tmp_path, steel40_core, view):
    out = tmp_path / f"core_{view}.png"
    plot.save_trajectory(steel40_core, out, view)
    check_png(out, view)
    check_trajectory_content(out, steel40_core, view)


def test_post_points_in_the_report_axes(steel40_emulator, steel40_core):
    """What the picture checks expect: the post's points at the hit in XL, YL, ZL are the
    engines' own terminal positions; C is Q at the start, so the post is drawn Q-P-R."""
    for res in (steel40_emulator, steel40_core):
        hi = hit_index(res)
        assert hi == len(res.t) - 1  # the run ends at the hit
        for k, p in zip(CHAIN, post_l(res, hi)):
            assert np.allclose(p, res.terminal[k], atol=1e-3), (res.engine, k, p)
        assert np.allclose(res.points["C"][0], res.points["Q"][0])
        assert not np.isnan(np.array([res.points[k] for k in CHAIN])).any()


def test_pulse_picture_with_both_engines(tmp_path, steel40_emulator, steel40_core):
    out = tmp_path / "pulse.png"
    fig = plot.figure_pulse([steel40_emulator, steel40_core])
    ax = fig.axes[0]
    assert ax.get_xlabel() == "time after impact (ms)"
    assert ax.get_ylabel() == "vehicle deceleration (g)"
    assert fig.axes[1].get_ylabel() == "vehicle speed (mph)"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(s.startswith("emulator") for s in labels) and any(
        s.startswith("core") for s in labels
    )
    fig.savefig(out, dpi=plot.DPI)
    check_png(out, "pulse")
    # the two curves coincide over most of the pulse: the core's, drawn last, hides the rest
    check_pulse_content(out, fig, [steel40_emulator, steel40_core], least=10)


@pytest.mark.parametrize("engine", ["emulator", "core"])
def test_pulse_passes_through_the_computed_decelerations(
    tmp_path, steel40_emulator, steel40_core, engine
):
    res = {"emulator": steel40_emulator, "core": steel40_core}[engine]
    out = tmp_path / f"pulse_{engine}.png"
    fig = plot.figure_pulse([res])
    fig.savefig(out, dpi=plot.DPI)
    check_png(out, "pulse")
    assert check_pulse_content(out, fig, [res])[engine] >= len(res.pulse_t) / 2


def test_side_view_axes_and_legend(steel40_emulator):
    fig = plot.figure_trajectory(steel40_emulator, "side")
    ax = fig.axes[0]
    assert ax.get_xlabel().startswith("XL (ft)") and ax.get_ylabel().startswith("ZL (ft)")
    title = fig.legends[0].get_title().get_text()
    assert "steel40" in title and "40 mph" in title and "α = 0°" in title
    assert "Post hit the ground with the luminaire end R" in title


def test_instants_are_regular_and_end_at_the_hit(steel40_emulator):
    idx = plot.instants(steel40_emulator)
    t = steel40_emulator.t[idx]
    assert t[0] == 0.0 and idx[-1] == len(steel40_emulator.t) - 1
    steps = np.diff(t[:-1])
    assert np.allclose(steps, steps[0], atol=1e-3)


def test_animation_is_a_gif_with_frames(tmp_path, steel40_emulator):
    out = tmp_path / "fall.gif"
    n = plot.save_animation(steel40_emulator, out, frame_s=0.1, dpi=40)
    with Image.open(out) as im:
        assert im.format == "GIF"
        assert im.n_frames == n > 5
        assert im.size[0] == round(plot.FIGSIZE["animate"][0] * 40)
        im.seek(n - 1)
        assert im.info["duration"] >= 1000  # the end is held (a second), not a flash


def test_the_animation_says_the_post_goes_through_the_car(tmp_path, monkeypatch):
    """steel20 as printed: the listing's run ends with C on the ground, but the shaft Q-P
    has been inside the car's outline since 778 ms, its strike on the hood (docs/safety.md's
    table, from the clearance over the computed path): the caption says so beside the
    listing's hit, and
    the frame is the shape of the scene (the view's feet the same both ways, the axes
    filling it), not a wide strip two thirds blank."""
    res = engine_for("emulator").run(read_deck(ROOT / "decks" / "steel20.dat"))
    figures = []
    made = plot.mpl().Figure
    monkeypatch.setattr(plot.mpl(), "Figure",
                        lambda *a, **k: figures.append(made(*a, **k)) or figures[-1])
    plot.save_animation(res, tmp_path / "fall.gif", frame_s=0.1, dpi=40)
    (fig,) = figures
    caption = " ".join(t.get_text() for t in fig.texts)
    assert "Post hit the ground with the point C" in caption
    assert "the shaft Q-P strikes the hood at 778.0 ms" in " ".join(caption.split())
    ax = fig.axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    box = ax.get_position()
    w, h = fig.get_size_inches()
    feet_per_inch = ((x1 - x0) / (box.width * w), (y1 - y0) / (box.height * h))
    assert feet_per_inch[0] == pytest.approx(feet_per_inch[1], rel=1e-6)
    assert box.width * box.height > 0.7  # the axes take most of the frame


def _parser():
    from deck_emulator.cli import build_parser

    parser = build_parser()
    return parser


def test_command_runs_an_angle_deck_with_the_erratum_requested(tmp_path, capsys):
    out = tmp_path / "a15_plan.png"
    args = _parser().parse_args(
        ["plot", str(ROOT / "decks" / "steel40_a15.dat"), "--out", str(out), "--view", "plan",
         "--erratum", "ed-direction"]
    )
    assert args.func(args) == 0
    check_png(out, "plan")
    res = engine_for("emulator", errata=("ed-direction",)).run(
        read_deck(ROOT / "decks" / "steel40_a15.dat"))
    assert res.hit and np.allclose(res.points["C"][0], res.points["Q"][0])
    check_trajectory_content(out, res, "plan")


def test_command_as_printed_on_an_angle_deck_names_the_erratum(tmp_path, capsys):
    out = tmp_path / "a15_side.png"
    args = _parser().parse_args(
        ["plot", str(ROOT / "decks" / "steel40_a15.dat"), "--out", str(out)]
    )
    assert args.func(args) == 3  # ED stops it as printed; the picture shows what it computed
    err = capsys.readouterr().err
    assert "stopped early" in err and "--erratum ed-direction" in err
    res = engine_for("emulator").run(read_deck(ROOT / "decks" / "steel40_a15.dat"))
    assert res.error and res.hit is None and np.allclose(res.points["C"][0], res.points["Q"][0])
    # the post at the end (6 ms) in HIT_COLOUR, over the post at t = 0, the one instant
    check_trajectory_content(out, res, "side", instants=0)


def test_command_refuses_a_non_picture_output(tmp_path):
    from deck_emulator.errors import UsageError as CLIError

    from deck_emulator.app import call

    with pytest.raises(CLIError):  # the command's function refuses it, before any run
        call("plot", source=str(ROOT / "decks" / "steel40.dat"), out=str(tmp_path / "x.txt"))
    assert not (tmp_path / "x.txt").exists()


def test_plot_writes_svg_and_pdf(tmp_path, capsys):
    from deck_emulator.cli import main

    deck = str(ROOT / "decks" / "steel40.dat")
    assert main(["plot", deck, "--out", str(tmp_path / "x.svg")]) == 0
    assert main(["plot", deck, "--out", str(tmp_path / "x.pdf"), "--view", "plan"]) == 0
    assert (tmp_path / "x.svg").read_text().lstrip().startswith(("<?xml", "<svg"))
    assert (tmp_path / "x.pdf").read_bytes().startswith(b"%PDF")


def test_twin_plan_view_draws_the_second_arm(tmp_path):
    """The twin post's plan view at the hit: the arm P-U is drawn in the hit's colour, as
    P-R is (U from the Outcome's own arrays)."""
    from deck_emulator.core.assembly import load_assembly, mass_properties
    from deck_emulator.engine import CoreEngine
    from deck_emulator.engine.assemblies import to_scene

    a, _, _ = load_assembly("twin")
    res = CoreEngine().run(to_scene(a, mass_properties(a), template="steel40"), name="twin")
    assert res.hit is not None and res.hit.point == "R&U"
    out = tmp_path / "twin_plan.png"
    plot.save_trajectory(res, out, "plan")
    img = read_png(out)
    fig = plot.figure_trajectory(res, "plan")
    fig.canvas.draw()
    mapper = Mapper(fig, img.shape)
    ax = fig.axes[0]
    hi = hit_index(res)
    labels = mapper.boxes(ax.texts, fig.canvas.get_renderer())
    for arm in ("R", "U"):
        ends = mapper.data(ax, np.array([point_l(res, "P", hi), point_l(res, arm, hi)])[:, :2])
        spots = spots_along(ends[0], ends[1])
        spots = spots[~in_boxes(spots, labels) & ~near_points(spots, ends[1:], STAR_PX)]
        assert len(spots) > 10, arm
        assert colour_near(img, spots, plot.HIT_COLOUR).all(), arm


# ---- exit statuses and bounds ----------------------------------------------


def _zero_mass_deck(tmp_path):
    # card 2, columns 21-30: W (the post's mass, slug) = 0 -- a deck the core refuses and
    # on which the listing divides by zero at its first step (`run` exits 3 on it)
    lines = (Path(__file__).resolve().parents[2] / "decks" / "steel40.dat").read_text().split("\n")
    assert lines[2][20:30] == "15.1      "
    lines[2] = lines[2][:20] + "0.0       " + lines[2][30:]
    deck = tmp_path / "w0.dat"
    deck.write_text("\n".join(lines))
    return deck


def test_a_run_that_stops_before_its_first_step_exits_3_as_run_does(tmp_path, capsys):
    from deck_emulator.cli import main

    deck = _zero_mass_deck(tmp_path)
    out = tmp_path / "p.png"
    assert main(["run", str(deck), "--out", str(tmp_path / "r.txt")]) == 3
    assert main(["plot", str(deck), "--out", str(out)]) == 3
    assert not out.exists()
    # the core refuses the scene before any run, as `core` does: bad input
    assert main(["core", str(deck)]) == 2
    assert main(["plot", str(deck), "--engine", "core", "--out", str(out)]) == 2
    assert not out.exists()
    err = capsys.readouterr().err
    assert "Traceback" not in err


@pytest.mark.parametrize("every", [1e-300, 0.05, float("inf"), float("nan")])
def test_every_is_bounded_before_the_run(every):
    from deck_emulator.errors import UsageError
    from deck_emulator.present.plot import check_every

    with pytest.raises(UsageError) as info:
        check_every(every)
    assert "\n" not in str(info.value)


def test_every_in_range_passes():
    from deck_emulator.present.plot import MIN_EVERY_MS, check_every

    for every in (None, MIN_EVERY_MS, 1.6, 20.0):
        check_every(every)
