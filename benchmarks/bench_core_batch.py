#!/usr/bin/env python3
"""Core scenes per second, both paths, in one run: the scipy loop and the batched core.

    python benchmarks/bench_core_batch.py [--repeat 5] [--full | --commands]

Prints, for 1 and 100 scenes (and 10,000 with ``--full``):

* scenes per second of ``CoreEngine(batched=False).run_batch`` (the scipy path, one
  ``simulate`` after another) and of ``CoreEngine(batched=True).run_batch`` (the compiled
  batched core, ``deck_emulator.core.simulate_batch``; "not available" when the core has none),
  in process, after one warm-up scene, in the scene runner's batches of at most 64 scenes;
  the legacy preset with the outcome's arrays (what a sweep runs).  1 scene: the median of ``--repeat`` runs; more: one run.  Wall and CPU time;
* the peak memory of the process that measured it (each measurement runs in its own process:
  ``resource.getrusage(RUSAGE_SELF).ru_maxrss``);
* the ratio of the time per scene to the compiled listing's (gfortran, REAL*8, the flags of
  scripts/make_goldens.py, steel40: the median of ``--repeat`` whole-process runs, start-up
  included; the one scene is steel40 too, the batches are the sweep's scenes);
* with ``--full`` (or ``--commands``, which leaves out the 10,000 scenes in process: the scipy
  path's take about 16 minutes), the whole commands: ``deck-emulator sweep`` of 10,000 core
  scenes (:data:`SWEEP_GRID`) and ``deck-emulator sensitivity --deck steel40 -N 1024`` (8,192
  core scenes), both ``--jobs 2``, timed as subprocesses; for the sensitivity, which input
  decides the ΔV to the end of contact (the largest total index ST, from its
  ``sensitivity.csv``), to hold beside docs/sensitivity.md's N = 256 answer (the car's mass
  WV).

The scenes are the sweep's (``deck_emulator.studies.sweep.scene_deck``: steel40 with VVB and
ALPHA changed), spread evenly over :data:`SWEEP_GRID`.  Times are wall-clock and depend on the
machine's load: say how loaded it was when quoting them.  Nothing here passes or fails.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: 100 speeds x 100 angles = 10,000 core scenes
SWEEP_GRID = ["--speeds", "10:59.5:0.5", "--angles", "0:49.5:0.5"]
PATHS = ("scipy", "batched")


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), env.get("PYTHONPATH")]))
    return env


def scenes(n: int) -> list:
    """``n`` of the sweep's decks, spread evenly over :data:`SWEEP_GRID`; one scene is steel40
    itself (the deck the compiled listing is timed on)."""
    from deck_emulator import decks
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.studies.sweep import parse_grid, scene_deck

    base = read_deck(decks.path("steel40"))
    if n == 1:
        return [base]
    speeds, angles = parse_grid(SWEEP_GRID[1]), parse_grid(SWEEP_GRID[3])
    grid = [(s, a) for s in speeds for a in angles]
    return [scene_deck(base, *grid[i * len(grid) // n]) for i in range(n)]


def measure(path: str, n: int, repeat: int) -> dict:
    """In this process: ``n`` scenes on ``path``; seconds (wall, CPU) per run of the batch."""
    import resource

    import deck_emulator.core as core
    from deck_emulator.engine import CoreEngine
    from deck_emulator.studies.distributed import BATCH_TASK_MAX

    if path == "batched" and getattr(core, "simulate_batch", None) is None:
        return {"available": False}
    engine = CoreEngine(preset="legacy", batched=(path == "batched"))
    batch = scenes(n)
    engine.run_batch(batch[:1])  # warm-up: imports, compilation
    walls, cpus, failed = [], [], 0
    for _ in range(repeat if n == 1 else 1):
        w0, c0 = time.perf_counter(), time.process_time()
        failed = 0
        # in the scene runner's batches (BATCH_TASK_MAX scenes), each dropped once counted, as
        # a worker does: 10,000 outcomes with their arrays kept would take about 10 GB
        for k in range(0, n, BATCH_TASK_MAX):
            failed += sum(o.error is not None for o in engine.run_batch(batch[k:k + BATCH_TASK_MAX]))
        walls.append(time.perf_counter() - w0)
        cpus.append(time.process_time() - c0)
    return {"available": True, "wall_s": statistics.median(walls),
            "cpu_s": statistics.median(cpus), "failed": failed,
            "maxrss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def compiled_seconds(repeat: int) -> float | None:
    """The compiled listing (REAL*8, as printed) on steel40: median whole-process seconds."""
    import shutil

    sys.path[:0] = [str(ROOT / "src"), str(ROOT)]
    from deck_emulator import decks
    import oracle

    if shutil.which("gfortran") is None:
        return None
    with tempfile.TemporaryDirectory() as tmp:
        exe = oracle.compile_program(Path(tmp), "r8", None)
        deck = Path(decks.path("steel40"))
        times = []
        for _ in range(max(3, repeat)):
            t0 = time.perf_counter()
            oracle.run_program(exe, deck)
            times.append(time.perf_counter() - t0)
    return statistics.median(times)


def _timed(cmd: list[str]) -> tuple[float, int, str]:
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=_env(), capture_output=True, text=True)
    return time.perf_counter() - t0, proc.returncode, proc.stderr.strip()[-300:]


def _deciding_input(table: Path, output: str) -> str | None:
    """For each deck of a sensitivity.csv, the input with the largest total index ST of
    ``output`` at the largest N, with its ST and interval; None when there is no table."""
    import csv

    if not table.is_file():
        return None
    rows = [r for r in csv.DictReader(table.open()) if r["output"] == output and r["ST"]]
    said = []
    for deck in dict.fromkeys(r["deck"] for r in rows):
        mine = [r for r in rows if r["deck"] == deck]
        n = max(int(r["N"]) for r in mine)
        mine = sorted((r for r in mine if int(r["N"]) == n), key=lambda r: -float(r["ST"]))
        top = mine[0]
        rest = ", ".join(f"{r['input']} {float(r['ST']):.2f}" for r in mine[1:])
        said.append(f"{deck}, {output}, N = {n}: {top['input']} decides it (ST "
                    f"{float(top['ST']):.2f} ± {float(top['ST_conf']):.2f}); then {rest}")
    return "; ".join(said) or None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--full", action="store_true",
                    help="also 10,000 scenes in process and the two whole commands (long)")
    ap.add_argument("--commands", action="store_true",
                    help="also the two whole commands (not the 10,000 scenes in process)")
    ap.add_argument("--measure", nargs=2, metavar=("PATH", "N"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.measure:  # a child: one measurement, as JSON
        print(json.dumps(measure(args.measure[0], int(args.measure[1]), args.repeat)))
        return 0
    compiled = compiled_seconds(args.repeat)
    sizes = (1, 100, 10_000) if args.full else (1, 100)
    print(f"Core scenes per second (legacy preset, arrays sampled, after one warm-up scene; "
          f"1 scene: median of {args.repeat}); {os.cpu_count()} cores; Python "
          f"{sys.version.split()[0]}; compiled listing (gfortran REAL*8, steel40, whole "
          "process): " + ("not available" if compiled is None else f"{compiled * 1e3:.1f} ms")
          + "\n")
    print("| path | scenes | wall s | CPU s | scenes/s | ms/scene | x compiled | failed | "
          "peak MB |")
    print("|---|---|---|---|---|---|---|---|---|")
    for path in PATHS:
        for n in sizes:
            proc = subprocess.run([sys.executable, __file__, "--measure", path, str(n),
                                   "--repeat", str(args.repeat)], env=_env(),
                                  capture_output=True, text=True)
            if proc.returncode != 0:
                print(f"| {path} | {n} | failed: {proc.stderr.strip()[-200:]} |")
                continue
            m = json.loads(proc.stdout.strip().splitlines()[-1])
            if not m["available"]:
                print(f"| {path} | {n} | not available (deck_emulator.core has no "
                      "simulate_batch) |||||||")
                break
            per = m["wall_s"] / n
            ratio = "—" if compiled is None else f"{per / compiled:.1f}"
            print(f"| {path} | {n} | {m['wall_s']:.3f} | {m['cpu_s']:.3f} | {n / m['wall_s']:.1f}"
                  f" | {per * 1e3:.1f} | {ratio} | {m['failed']} | {m['maxrss_mb']:.0f} |")
    if args.full or args.commands:
        cli = [sys.executable, "-m", "deck_emulator"]
        print("\nWhole commands (subprocesses, --jobs 2):\n")
        with tempfile.TemporaryDirectory() as tmp:
            for label, cmd, count in (
                ("sweep, 10,000 core scenes",
                 [*cli, "sweep", *SWEEP_GRID, "--engine", "core", "--jobs", "2", "--quiet",
                  "--out", f"{tmp}/sweep"], 10_000),
                ("sensitivity --deck steel40 -N 1024 (8,192 scenes)",
                 [*cli, "sensitivity", "--deck", "steel40", "-N", "1024", "--engine", "core",
                  "--jobs", "2", "--quiet", "--out", f"{tmp}/sensitivity"], 8_192),
            ):
                dt, status, err = _timed(cmd)
                said = "" if status == 0 else f" (exit status {status}: {err})"
                print(f"* {label}: {dt:.1f} s, {count / dt:.1f} scenes/s{said}")
            decides = _deciding_input(Path(tmp) / "sensitivity" / "sensitivity.csv",
                                      "delta_v_contact_mph")
            if decides:
                print(f"* sensitivity's answer: {decides}")
    print(f"\nload average at the end: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
