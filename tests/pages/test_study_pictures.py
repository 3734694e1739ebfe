"""The studies' pictures say what their numbers say: the work-precision diagram's tolerance
labels can each be read (they were written at one offset and read as '1e43'), and the
sensitivity bars show every error bar whole and no panel without indices."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

pytest.importorskip("matplotlib")


def test_tolerance_labels_never_cover_one_another():
    from deck_emulator.studies.common import agg_backend
    from deck_emulator.studies.error import _labels_apart

    plt = agg_backend()
    fig, ax = plt.subplots(figsize=(6, 4))
    # nine tolerances of one method in nearly the same time, close in error: the case of
    # the core's DOP853 points, where every label at one offset fell on its neighbour's
    wall = 0.033 + 0.001 * np.arange(9)
    err = 10.0 ** -np.linspace(2, 4, 9)
    ax.loglog(wall, err, "^-")
    labelled = [(w, e, f"1e-{k + 3}", "C0") for k, (w, e) in enumerate(zip(wall, err))]
    fig.tight_layout()  # as the study's picture is laid out before its labels are placed
    _labels_apart(ax, labelled)
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in ax.texts]
    assert sorted(t.get_text() for t in ax.texts) == sorted(text for *_, text, _ in labelled)
    assert not [(a, b) for a, b in itertools.combinations(boxes, 2) if a.overlaps(b)]
    plt.close(fig)


def test_sensitivity_bars_whole_and_no_empty_panel(tmp_path, monkeypatch):
    from deck_emulator.studies.common import agg_backend
    from deck_emulator.studies.sensitivity import plot_indices

    plt = agg_backend()
    kept = []
    monkeypatch.setattr(plt, "close", kept.append)
    row = dict(N=16, note="")
    rows = [dict(row, output="hits_car", input=i, S1=None, S1_conf=None, ST=None, ST_conf=None,
                 note="constant (0) over the sample: no indices") for i in ("CK", "WV")]
    rows += [dict(row, output="hit_time_ms", input="CK", S1=0.64, S1_conf=0.5, ST=0.5,
                  ST_conf=0.3),
             dict(row, output="hit_time_ms", input="WV", S1=0.23, S1_conf=0.42, ST=0.26,
                  ST_conf=0.19)]
    plot_indices(rows, tmp_path / "s.png", n=16, title="t")
    (fig,) = kept
    shown = [ax for ax in fig.axes if ax.axison]
    assert [ax.get_title() for ax in shown] == ["time of the first hit"]  # no empty panel
    lo, hi = shown[0].get_ylim()
    assert hi > 0.64 + 0.5 and lo < 0.23 - 0.42  # both ends of every bar inside the axes
    assert "P(first hit on the car): constant (0) over the sample" in fig.get_suptitle()
