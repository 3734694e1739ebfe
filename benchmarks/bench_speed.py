#!/usr/bin/env python3
"""Speed of the emulator beside the compiled listing, measured in one run.

    python benchmarks/bench_speed.py [--repeat 5] [--ibm7094-repeat 1] [--sweep]

Prints, per deck of decks/:

* the emulator's run time in process (``EmulatorEngine(...).run``, no trace: its ``run_s``,
  the program's loop alone) in double, single and ibm7094 (median of the repetitions; single
  stops at the trap of step 2, as the compiled REAL build);
* the compiled listing's time (REAL*8 and REAL builds, compiled into a temporary directory with
  the flags of scripts/make_goldens.py; the time of the whole process, start-up included) and
  the ratio of the emulator's double to the compiled REAL*8;
* the whole ``deck-emulator run DECK`` process in double (interpreter start-up and imports
  included) and its ratio to the compiled REAL*8.

Decks whose goldens need the ``ed-direction`` erratum run with it on both sides. With
``--sweep`` it also times the 1,000-scene sweep (10 speeds x 100 angles) on both engines, as
``deck-emulator sweep ... --jobs 2 --out TMPDIR`` subprocesses (minutes).

Times are wall-clock and depend on the machine's load: say how loaded it was when quoting them.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
import timeit
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SWEEP_GRID = ["--speeds", "10:55:5", "--angles", "0:49.5:0.5"]  # 10 x 100 = 1,000 scenes


def median_time(fn, repeat: int) -> float:
    return statistics.median(timeit.repeat(fn, number=1, repeat=repeat))


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), env.get("PYTHONPATH")]))
    return env


def _cli(*args) -> list[str]:
    return [sys.executable, "-m", "deck_emulator", *args]


def errata_for(deck_name: str) -> tuple[str, ...]:
    """The errata its r8 golden was made with (from the golden's name)."""
    for golden in (ROOT / "golden").glob(f"{deck_name}.*r8.txt"):
        return tuple(golden.name.split(".")[1:-2])
    return ()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--ibm7094-repeat", type=int, default=1)
    ap.add_argument("--sweep", action="store_true", help="also time the 1,000-scene sweep on both engines")
    args = ap.parse_args(argv)
    sys.path[:0] = [str(ROOT / "src"), str(ROOT)]  # the package and oracle/ beside it
    from deck_emulator.engine import EmulatorEngine
    from deck_emulator.legacy.deck import read_deck

    import oracle as mg
    rows = []
    env = _env()
    with tempfile.TemporaryDirectory() as tmp:
        build = Path(tmp)
        for deck_path in sorted((ROOT / "decks").glob("*.dat")):
            name = deck_path.stem
            errata = errata_for(name)
            deck = read_deck(deck_path)
            row = {"deck": name + (f" ({', '.join(errata)})" if errata else "")}

            def emulate(precision, repeat):
                # the program's own time; single precision traps at step 2, as the compiled
                # program does (the outcome says so, nothing is raised)
                engine = EmulatorEngine(precision=precision, errata=errata, trace=False)
                return statistics.median(engine.run(deck).run_s for _ in range(repeat))

            row["double"] = emulate("double", args.repeat)
            row["single"] = emulate("single", args.repeat)
            row["ibm7094"] = emulate("ibm7094", args.ibm7094_repeat)
            for precision in ("r8", "r4"):
                exe = mg.compile_program(build, precision, errata[0] if errata else None)
                row[f"compiled {precision}"] = median_time(lambda: mg.run_program(exe, deck_path), args.repeat)
            row["double / r8"] = row["double"] / row["compiled r8"]
            cmd = _cli("run", str(deck_path), *(a for e in errata for a in ("--erratum", e)))
            row["process double"] = median_time(
                lambda: subprocess.run(cmd, env=env, capture_output=True), args.repeat)
            row["process / r8"] = row["process double"] / row["compiled r8"]
            rows.append(row)
    cols = list(rows[0])
    print(f"Median wall time in seconds (ratios are emulator / compiled REAL*8); "
          f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the end; "
          f"Python {sys.version.split()[0]}; repeat {args.repeat} (ibm7094: {args.ibm7094_repeat})\n")
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for r in rows:
        cells = [f"{r[c]:.1f}x" if "/" in c else f"{r[c]:.4f}" for c in cols[1:]]
        print("| " + " | ".join([r["deck"]] + cells) + " |")
    if args.sweep:
        print("\n1,000-scene sweep (" + " ".join(SWEEP_GRID) + ", --jobs 2):\n")
        for engine in ("emulator", "core"):
            with tempfile.TemporaryDirectory() as out:
                cmd = _cli("sweep", *SWEEP_GRID, "--jobs", "2", "--engine", engine, "--out", out)
                t0 = time.perf_counter()
                proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
                dt = time.perf_counter() - t0
                rows_written = max(0, len((Path(out) / "sweep.csv").read_text().splitlines()) - 1) \
                    if (Path(out) / "sweep.csv").exists() else 0
            status = "" if proc.returncode == 0 else f" (exit status {proc.returncode}: {proc.stderr.strip()[-200:]})"
            print(f"* {engine}: {dt:.1f} s, {rows_written} scenes{status}")
    print(f"\nload average at the end: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
