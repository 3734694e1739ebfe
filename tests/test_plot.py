"""The pictures: valid PNGs (and a GIF) of the expected pixel size, not blank; the command's
options and messages."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from deck_emulator.present import plot
from deck_emulator.legacy.deck import read_deck
from deck_emulator.engine import run_engine

ROOT = Path(__file__).resolve().parent.parent
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


@pytest.fixture(scope="module")
def steel40_emulator():
    return run_engine(read_deck(ROOT / "decks" / "steel40.dat"), "emulator")


@pytest.fixture(scope="module")
def steel40_core():
    return run_engine(read_deck(ROOT / "decks" / "steel40.dat"), "core")


@pytest.mark.parametrize("view", plot.VIEWS)
def test_trajectory_views_are_valid_pictures(tmp_path, steel40_emulator, view):
    out = tmp_path / f"steel40_{view}.png"
    plot.save_trajectory(steel40_emulator, out, view)
    check_png(out, view)


def test_core_trajectory_picture(tmp_path, steel40_core):
    out = tmp_path / "core.png"
    plot.save_trajectory(steel40_core, out, "side")
    check_png(out, "side")


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
        w, h = plot.FIGSIZE["animate"]
        assert im.size == (round(w * 40), round(h * 40))


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


def test_command_as_printed_on_an_angle_deck_names_the_erratum(tmp_path, capsys):
    out = tmp_path / "a15_side.png"
    args = _parser().parse_args(
        ["plot", str(ROOT / "decks" / "steel40_a15.dat"), "--out", str(out)]
    )
    assert args.func(args) == 3  # ED stops it as printed; the picture shows what it computed
    err = capsys.readouterr().err
    assert "stopped early" in err and "--erratum ed-direction" in err


def test_command_refuses_a_non_picture_output(tmp_path):
    from deck_emulator.errors import UsageError as CLIError

    args = _parser().parse_args(
        ["plot", str(ROOT / "decks" / "steel40.dat"), "--out", str(tmp_path / "x.txt")]
    )
    with pytest.raises(CLIError):
        args.func(args)
    assert not (tmp_path / "x.txt").exists()


def test_plot_writes_svg_and_pdf(tmp_path, capsys):
    from deck_emulator.cli import main

    deck = str(ROOT / "decks" / "steel40.dat")
    assert main(["plot", deck, "--out", str(tmp_path / "x.svg")]) == 0
    assert main(["plot", deck, "--out", str(tmp_path / "x.pdf"), "--view", "plan"]) == 0
    assert (tmp_path / "x.svg").read_text().lstrip().startswith(("<?xml", "<svg"))
    assert (tmp_path / "x.pdf").read_bytes().startswith(b"%PDF")
