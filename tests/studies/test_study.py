"""The error and stability studies, run with --quick through their command-line parser."""

from __future__ import annotations

import csv
import itertools
import math
from pathlib import Path

import numpy as np
import pytest
from matplotlib.colors import to_rgba

from deck_emulator.studies.error import COLUMNS as ERROR_COLUMNS
from deck_emulator.studies.stability import COLUMNS as STABILITY_COLUMNS, STIFF_SPRING
from pictures import (
    Mapper,
    axes_box,
    colour_near,
    in_boxes,
    ink_near,
    inside_box,
    near_points,
    near_segments,
    read_png,
    rgb255,
    saved_figures,
    segments_of,
)

DECK = Path(__file__).resolve().parents[2] / "decks" / "steel40.dat"


def _run(argv: list[str]) -> int:
    from deck_emulator.cli import build_parser

    parser = build_parser()
    args = parser.parse_args(argv)
    return args.func(args)


def _rows(path: Path) -> tuple[list[str], list[dict]]:
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        return list(reader.fieldnames or []), list(reader)


def _num(text: str) -> float:
    return float(text) if text not in ("", None) else float("nan")


def _check_png(path: Path) -> None:
    import matplotlib.image as mpimg

    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    img = mpimg.imread(path)
    assert img.ndim == 3 and img.shape[0] > 300 and img.shape[1] > 600
    rgb = img[..., :3]
    assert float(rgb.std()) > 0.05  # not blank
    assert float((rgb.mean(axis=2) < 0.5).mean()) > 0.005  # some dark ink: text, lines


# The studies draw and write their pictures in one go; the fixtures keep the figures that
# wrote them (pictures.saved_figures), whose axes map the CSV's data into the written PNGs.


@pytest.fixture(scope="module")
def error_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("error")
    with saved_figures() as figures:
        assert _run(["study", "error", str(DECK), "--out", str(out), "--quick", "--jobs", "2"]) == 0
    return out, figures


@pytest.fixture(scope="module")
def error_dir(error_run):
    return error_run[0]


@pytest.fixture(scope="module")
def stability_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("stability")
    with saved_figures() as figures:
        assert _run(["study", "stability", "--out", str(out), "--quick", "--jobs", "2"]) == 0
    return out, figures


@pytest.fixture(scope="module")
def stability_dir(stability_run):
    return stability_run[0]


MARKER_PX = 12.0  # a marker of another line this close may cover the one checked
LINE_PX = 4.0  # so may another line
FILLED = 16  # of the 25 pixels around a filled marker's centre in its colour (a line: <= 10)


def _picture(run, name):
    """(figure, picture, mapper, renderer) of the study picture ``name``."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    out, figures = run
    fig = figures[name]
    img = read_png(out / name)
    if not isinstance(fig.canvas, FigureCanvasAgg):  # pyplot's close may leave a bare canvas
        FigureCanvasAgg(fig)  # (only text extents need it: the picture is the file)
    return fig, img, Mapper(fig, img.shape), fig.canvas.get_renderer()


def _covers(mapper, ax, renderer):
    """Boxes of what lies over an axes' lines and markers: its texts and its legend."""
    legend = [ax.get_legend()] if ax.get_legend() is not None else []
    return mapper.boxes([*ax.texts, *legend], renderer)


def _check_markers(img, mapper, ax, line, xy, renderer, hollow=False) -> int:
    """The markers of ``line`` (an axes' Line2D) are at the data points ``xy`` of the
    picture, in the line's colour: filled markers fill the 5 x 5 pixels around their centre
    with it, hollow ones leave ink of it within 6 pixels (also given by a filled marker of
    the same series under them).  Points under a text, the legend, or a line or marker of
    another colour drawn later are left out.  Returns the number of points checked."""
    spots = mapper.data(ax, xy)
    hide = ~inside_box(spots, axes_box(mapper, ax, 2.0)) | in_boxes(
        spots, _covers(mapper, ax, renderer))
    for other in ax.lines[ax.lines.index(line) + 1:]:
        if to_rgba(other.get_color()) == to_rgba(line.get_color()):
            continue  # the same series (against another reference): the same colour
        pts = mapper.display(other.get_transform().transform(other.get_xydata()))
        hide |= near_segments(spots, segments_of(pts), LINE_PX)
        if other.get_marker() not in (None, "None", "none", "", " "):
            hide |= near_points(spots, pts, MARKER_PX)
    spots = spots[~hide]
    colour = line.get_color()
    ok = (ink_near(img, spots, colour, radius=6) if hollow
          else colour_near(img, spots, colour, radius=2, least=FILLED))
    assert ok.all(), (
        f"{line.get_label()!r}: {(~ok).sum()} of {len(ok)} data points have no {colour} "
        f"marker, e.g. (column, row) {spots[~ok][:3].round().tolist()}")
    return len(spots)


def _finite(text: str) -> bool:
    return math.isfinite(_num(text))


def test_error_study_files(error_dir):
    for name in ("error_study.csv", "work_precision.png", "README.md"):
        assert (error_dir / name).is_file(), name
    header, rows = _rows(error_dir / "error_study.csv")
    assert header == ERROR_COLUMNS
    assert "np." not in (error_dir / "error_study.csv").read_text()
    series = {r["series"] for r in rows}
    assert {"legacy, ED as printed (double)", "legacy, ED tightened (double)", "core DOP853",
            "core RK45", "core Radau", "reference check"} <= series


def test_error_decreases_with_h_for_the_legacy_scheme(error_dir):
    _, rows = _rows(error_dir / "error_study.csv")
    tight = sorted((r for r in rows if r["series"] == "legacy, ED tightened (double)"),
                   key=lambda r: int(r["k"]))
    assert len(tight) >= 3 and all(r["status"] == "hit" for r in tight)
    errors = [_num(r["err_traj_ft"]) for r in tight]
    assert all(b < a for a, b in itertools.pairwise(errors)), errors
    # first order: halving H about halves the error
    assert all(0.35 < b / a < 0.65 for a, b in itertools.pairwise(errors)), errors
    hit = [_num(r["err_R_ft"]) for r in tight]
    assert hit[-1] < hit[0]


def test_core_error_at_rtol_1e10_below_a_micro_foot(error_dir):
    _, rows = _rows(error_dir / "error_study.csv")
    core = [r for r in rows if r["engine"] == "core" and r["series"] != "reference check"
            and _num(r["rtol"]) == 1e-10]
    assert {r["method"] for r in core} == {"DOP853", "RK45", "Radau"}
    for r in core:
        assert r["status"] == "hit"
        assert _num(r["err_traj_ft"]) < 1e-6, r
        assert _num(r["err_hit_time_s"]) < 1e-6, r


def test_reference_error_is_known_and_small(error_dir):
    _, rows = _rows(error_dir / "error_study.csv")
    checks = [r for r in rows if r["series"] == "reference check"]
    assert checks and all(_num(r["err_traj_ft"]) < 1e-8 for r in checks)
    text = (error_dir / "README.md").read_text()
    assert "Its own error" in text


def test_error_report(error_dir):
    text = (error_dir / "README.md").read_text()
    assert "deck-emulator study error" in text and "--quick" in text
    assert "observed order" in text.lower()
    assert "cores" in text and "os.cpu_count()" in text
    assert "times faster" in text
    assert "![work-precision diagram](work_precision.png)" in text
    _check_png(error_dir / "work_precision.png")


def test_work_precision_picture_shows_the_csv(error_run):
    """Every series of error_study.csv (its runs that ended with a hit) is a line through its
    (wall time, error) points on the left, and the emulator's double-precision series are
    lines through (H, error) and (H, error against the k = 0 reference) on the right: the
    figure's lines hold the CSV's numbers, and the written picture has a marker of the
    line's colour at each of them."""
    fig, img, mapper, renderer = _picture(error_run, "work_precision.png")
    ax, bx = fig.axes[:2]
    assert ax.get_title().startswith("Work-precision") and bx.get_title().startswith("The 1967")
    _, rows = _rows(error_run[0] / "error_study.csv")
    every = [s for s in dict.fromkeys(r["series"] for r in rows) if s != "reference check"]

    def hits(series):
        return [r for r in rows if r["series"] == series and r["status"] == "hit"
                and _finite(r["err_traj_ft"])]

    # left: where the markers land depends on the run times, so which of them other series
    # cover does too; the last series drawn is covered by none of theirs
    checked = 0
    for series in every:
        (line,) = [ln for ln in ax.lines if ln.get_label().startswith(series)]
        xy = np.array([[_num(r["wall_s"]), _num(r["err_traj_ft"])] for r in hits(series)])
        np.testing.assert_allclose(line.get_xydata(), xy, rtol=1e-11)  # the CSV: 12 digits
        hollow = line.get_markerfacecolor() == "none"  # a series without the step bound
        checked += _check_markers(img, mapper, ax, line, xy, renderer, hollow=hollow)
    assert checked > 0
    emulator = [s for s in every
                if any(r["engine"] == "emulator" and r["precision"] == "double"
                       for r in rows if r["series"] == s)]
    assert len(emulator) == 2
    for series in emulator:
        ok = hits(series)
        (line,) = [ln for ln in bx.lines if ln.get_label().startswith(series)]
        h = [_num(r["h_s"]) for r in ok]
        xy = np.c_[h, [_num(r["err_traj_ft"]) for r in ok]]
        np.testing.assert_allclose(line.get_xydata(), xy, rtol=1e-11)  # the CSV: 12 digits
        ref0 = bx.lines[bx.lines.index(line) + 1]  # the same, against the k = 0 reference
        assert ref0.get_color() == line.get_color() and ref0.get_linestyle() == "--"
        xy0 = np.c_[h, [_num(r["err_traj_ref0_ft"]) for r in ok]]
        np.testing.assert_allclose(ref0.get_xydata(), xy0, rtol=1e-11)  # the CSV: 12 digits
        # right: H and the errors do not depend on the machine
        assert _check_markers(img, mapper, bx, line, xy, renderer) > 0, series
        assert _check_markers(img, mapper, bx, ref0, xy0, renderer, hollow=True) > 0, series


def test_stability_study_files(stability_dir):
    for name in ("stability_study.csv", "stability_map.png", "extreme_scenes.png", "README.md"):
        assert (stability_dir / name).is_file(), name
    header, rows = _rows(stability_dir / "stability_study.csv")
    assert header == STABILITY_COLUMNS
    assert "np." not in (stability_dir / "stability_study.csv").read_text()
    scenes = {r["scene"] for r in rows}
    assert {"base", "speed-5", "speed-120", "angle-90", "tha-0.0", "abc-equal",
            "friction-large", "thb-1.5"} <= scenes
    assert any(s.startswith("spring-") for s in scenes)
    known = {"agrees", "same hit, off", "other hit", "no hit", "crash", "n/a", "hit (core failed)"}
    for r in rows:
        assert r["emulator_class"] in known or r["emulator_class"].startswith("guard: "), r
        assert r["core_status"] in ("hit", "no hit", "error"), r
    base = next(r for r in rows if r["scene"] == "base")
    assert base["emulator_class"] == "agrees"
    # a stiff spring at a large step: the emulator's launch energy is far off
    stiff = [r for r in rows if r["group"] == STIFF_SPRING]
    worst = max(stiff, key=lambda r: _num(r["h_omega"]))
    assert _num(worst["launch_ke_rel_diff"]) > 0.1
    # friction is not a deck input: core only
    fric = next(r for r in rows if r["scene"] == "friction-large")
    assert fric["emulator_class"] == "n/a" and fric["core_status"] in ("hit", "no hit", "error")


def test_stability_report(stability_dir):
    text = (stability_dir / "README.md").read_text()
    assert "deck-emulator study stability" in text and "--quick" in text
    assert "cores" in text and "os.cpu_count()" in text
    section = text.split("## Failure modes found", 1)[1].split("##", 1)[0]
    bullets = [line for line in section.splitlines() if line.startswith("* ")]
    assert bullets and all("`" in b for b in bullets)  # each names a scene
    for png in ("stability_map.png", "extreme_scenes.png"):
        assert f"]({png})" in text
        _check_png(stability_dir / png)


def _legend_colours(ax) -> dict:
    """The legend's key: label -> the colour of its handle's face."""
    legend = ax.get_legend()
    out = {}
    for text, handle in zip(legend.get_texts(), legend.legend_handles):
        face = (handle.get_markerfacecolor() if hasattr(handle, "get_markerfacecolor")
                else handle.get_facecolor())
        out[text.get_text()] = to_rgba(face)
    return out


def test_stability_map_shows_the_csv(stability_run):
    """Left: a square at (CK, H) of each stiff scene of stability_study.csv, in the colour the
    legend gives its emulator class, numbered with its launch-energy difference in %.  Right:
    per step H, a line through (h omega, |launch-energy difference|).  Checked in the figure's
    artists and in the written picture."""
    fig, img, mapper, renderer = _picture(stability_run, "stability_map.png")
    ax, bx = fig.axes[:2]
    _, rows = _rows(stability_run[0] / "stability_study.csv")
    stiff = [r for r in rows if r["group"] == STIFF_SPRING]
    assert len(stiff) >= 4
    key = _legend_colours(ax)
    covers = _covers(mapper, ax, renderer)
    numbers = {tuple(np.round(t.xy, 12)): t.get_text() for t in ax.texts if hasattr(t, "xy")}
    for r in stiff:
        xy = (_num(r["CK_lb_ft"]), _num(r["H_s"]))
        colour = key[r["emulator_class"]]
        cells = [c for c in ax.collections if len(c.get_offsets()) == 1
                 and np.allclose(c.get_offsets()[0], xy, rtol=1e-11)  # the CSV's 12 digits
                 and np.allclose(c.get_facecolor()[0], colour)]
        assert len(cells) == 1, (r["scene"], r["emulator_class"])
        if _finite(r["launch_ke_rel_diff"]):
            shown = numbers[tuple(np.round(xy, 12))]
            assert abs(float(shown) - 100 * _num(r["launch_ke_rel_diff"])) <= 0.5 + 1e-9, shown
        # the picture: the square's colour around its number (and any cross at its centre)
        centre = mapper.data(ax, [xy])[0]
        probes = centre + np.array([[0.0, 11.0], [0.0, -11.0], [13.0, 0.0], [-13.0, 0.0]])
        probes = probes[~in_boxes(probes, covers)]
        assert len(probes) >= 2, r["scene"]
        assert colour_near(img, probes, colour).all(), (r["scene"], probes.round().tolist())

    ks = sorted({int(r["k"]) for r in stiff})
    lines = [ln for ln in bx.lines if ln.get_label().startswith("H = ")]
    assert len(lines) == len(ks)
    checked = 0
    for k in ks:
        sel = [r for r in stiff if int(r["k"]) == k and _finite(r["launch_ke_rel_diff"])]
        xy = np.array([[_num(r["h_omega"]), abs(_num(r["launch_ke_rel_diff"]))] for r in sel])
        (line,) = [ln for ln in lines if ln.get_xydata().shape == xy.shape
                   and np.allclose(ln.get_xydata(), xy, rtol=1e-11)]  # the CSV's 12 digits
        assert f"{_num(sel[0]['H_s']) * 1e6:.0f}" in line.get_label()
        checked += _check_markers(img, mapper, bx, line, xy, renderer)
    assert checked >= len(stiff) / 2


def test_extreme_scenes_picture_shows_the_csv(stability_run):
    """A row per scene of stability_study.csv outside the stiff grid, named by its scene: the
    emulator's cell in the colour the legend gives its class, the core's in the legend's
    "core failed" colour when the core did not end with a hit (else one light green), the
    hit times and the emulator's free-flight drift in its texts.  Checked in the figure's
    artists and in the written picture."""
    fig, img, mapper, renderer = _picture(stability_run, "extreme_scenes.png")
    ax = fig.axes[0]
    _, rows = _rows(stability_run[0] / "stability_study.csv")
    ext = [r for r in rows if r["group"] != STIFF_SPRING]
    assert len(ext) >= 5
    key = _legend_colours(ax)
    covers = _covers(mapper, ax, renderer)
    heads = [next(t for t in ax.texts if t.get_text().startswith(name))
             for name in ("emulator (", "core (")]
    columns = [h.get_position()[0] for h in heads]  # the columns' centres
    green = []
    for r in ext:
        (label,) = [t for t in ax.texts if t.get_text().endswith(f"[{r['scene']}]")]
        y = label.get_position()[1]
        core_hit = r["core_status"] == "hit"
        for engine, x in zip(("emulator", "core"), columns):
            probes_data = np.array([[x, y + 0.3], [x, y - 0.3]])
            display = ax.transData.transform(probes_data)
            cells = [p for p in ax.patches if p.contains_point(display[0])]
            assert len(cells) == 1, (r["scene"], engine, "cells", len(cells))
            face = to_rgba(cells[0].get_facecolor())
            if engine == "emulator":
                assert np.allclose(face, key[r["emulator_class"]]), r["scene"]
            elif not core_hit:
                assert np.allclose(face, key["core failed"]), r["scene"]
            else:
                assert not np.allclose(face, key["core failed"]), r["scene"]
            probes = mapper.display(display)
            probes = probes[~in_boxes(probes, covers)]
            assert len(probes) >= 1, (r["scene"], engine, "probes")
            assert colour_near(img, probes, face).all(), (
                r["scene"], engine, "not in the picture", probes.round().tolist())
            if engine == "core" and core_hit:
                green.append(face)
            # the cell's text: the hit time
            if r[f"{engine}_status"] == "hit":
                (text,) = [t for t in ax.texts if np.allclose(t.get_position(), (x, y))]
                assert f"{_num(r[f'{engine}_hit_time_s']):.3f} s" in text.get_text(), text.get_text()
        drift = [t for t in ax.texts
                 if math.isclose(t.get_position()[1], y) and t.get_position()[0] > 1]
        if _finite(r["emulator_free_flight_energy_drift"]):
            (text,) = drift
            shown = float(text.get_text().rstrip(" %"))
            assert math.isclose(shown, 100 * _num(r["emulator_free_flight_energy_drift"]), rel_tol=0.05)
        else:
            assert not drift, r["scene"]
    # a core that ended with a hit: one light green
    assert green and all(np.allclose(g, green[0]) for g in green)
    rgb = rgb255(green[0])
    assert rgb[1] > rgb[0] + 20 and rgb[1] > rgb[2] + 20


def test_jobs_must_be_positive():
    with pytest.raises(SystemExit):
        _run(["study", "stability", "--out", "x", "--jobs", "0"])


def test_energy_helpers_on_a_plain_run():
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.studies.common import energies, run_emulator

    deck = read_deck(DECK)
    out = run_emulator(deck)
    assert out["status"] == "hit"
    e = energies(out)
    assert np.isfinite(e["launch_ke_ftlb"]) and e["launch_ke_ftlb"] > 0
    assert 0 < e["free_drift"] < 0.05  # the explicit scheme gains a little energy in free flight


def test_a_resumed_study_runs_nothing_it_has_stored(stability_dir):
    """The study's runs are in its scene store (the one runner's, as the sweep's): --resume
    adds no batch to it and writes the same table (but for the measured times)."""
    store = stability_dir / ".scenes" / "results"
    before = sorted(p.name for p in store.glob("*.parquet"))
    assert before
    rows_before = _rows(stability_dir / "stability_study.csv")[1]
    assert _run(["study", "stability", "--out", str(stability_dir), "--quick", "--jobs", "2",
                 "--resume"]) == 0
    assert sorted(p.name for p in store.glob("*.parquet")) == before
    rows_after = _rows(stability_dir / "stability_study.csv")[1]
    timing = {k for k in rows_before[0] if k.endswith("wall_s")}
    strip = lambda rows: [{k: v for k, v in r.items() if k not in timing} for r in rows]  # noqa: E731
    assert strip(rows_after) == strip(rows_before)
