"""docs/tutorial.md runs: its Python blocks, in order, in one namespace."""

from __future__ import annotations

import re
from pathlib import Path

TUTORIAL = Path(__file__).resolve().parents[2] / "docs" / "tutorial.md"


def test_the_tutorial_runs(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"```python\n(.*?)```", TUTORIAL.read_text(), re.S)
    assert len(blocks) >= 4
    monkeypatch.chdir(tmp_path)  # the shipped decks are found by name, from any folder
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, str(TUTORIAL), "exec"), namespace)
    assert "THE POST HAS HIT THE GROUND WITH POINT R" in capsys.readouterr().out


def test_the_trajectory_option_writes_what_pandas_reads(tmp_path):
    import pandas as pd

    from deck_emulator.cli import main

    csv, parquet = tmp_path / "t.csv", tmp_path / "t.parquet"
    assert main(["run", "steel40", "--trajectory", str(csv), "--out", str(tmp_path / "p")]) == 0
    assert main(["core", "steel40", "--trajectory", str(parquet), "--quiet",
                 "--out", str(tmp_path / "a")]) == 0
    emulator, core = pd.read_csv(csv), pd.read_parquet(parquet)
    for frame in (emulator, core):
        assert {"t_s", "phase", "P_xl_ft", "Q_zl_ft", "R_yl_ft", "car_velocity_ft_s"} <= set(frame)
    # the emulator's rows are its accepted steps of 0.0004 s (the printout's last TIME is the hit)
    steps = emulator["t_s"].diff().dropna()
    assert steps.min() > 0 and abs(steps.median() - 0.0004) < 1e-12
    # both start with R where the deck puts it: XRO, YYRO, ZZRO less the base Q, above ground
    from deck_emulator.decks import path
    from deck_emulator.legacy.deck import read_deck

    d = read_deck(path("steel40")).values
    want = (d["XRO"] - d["XQO"], d["YYRO"] - d["YYQO"], d["ZZRO"] + d["HEIGHT"])
    for frame in (emulator, core):
        got = tuple(frame[f"R_{a}l_ft"].iloc[0] for a in "xyz")
        assert max(abs(g - w) for g, w in zip(got, want)) < 1e-4
    assert main(["core", "steel40", "--trajectory", str(tmp_path / "t.txt")]) == 2
