#!/usr/bin/env python3
"""Run time of the emulator per deck and arithmetic, next to the compiled listing's, measured in
one run (median of several repetitions). Prints a Markdown table.

    python benchmarks/bench_emulator.py [--repeat 5] [--ibm7094-repeat 1]

The compiled program is built exactly as scripts/make_goldens.py builds it; its time includes
process start-up (a few ms). Single precision stops at the trap of step 2 in both.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.emulator import EmulatorError, run_deck

ROOT = Path(__file__).resolve().parent.parent


def _make_goldens():
    spec = importlib.util.spec_from_file_location("make_goldens", ROOT / "scripts" / "make_goldens.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def median_time(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--ibm7094-repeat", type=int, default=1)
    args = ap.parse_args(argv)
    mg = _make_goldens()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        build = Path(tmp)
        for golden in sorted((ROOT / "golden").glob("*.r8.txt")):
            name = golden.name.split(".")[0]
            errata = tuple(golden.name.split(".")[1:-2])
            deck_path = ROOT / "decks" / f"{name}.dat"
            deck = read_deck(deck_path)
            row = {"deck": name + (f" ({', '.join(errata)})" if errata else "")}
            for precision in ("r8", "r4"):
                exe = mg.compile_program(build, precision, errata[0] if errata else None)
                row[f"gfortran {precision}"] = median_time(lambda: mg.run_program(exe, deck_path), args.repeat)

            def emulate(precision):
                try:
                    run_deck(deck, precision, errata=errata, trace=False)
                except EmulatorError:
                    pass  # single precision traps at step 2, as the compiled program does

            row["emulator double"] = median_time(lambda: emulate("double"), args.repeat)
            row["emulator single"] = median_time(lambda: emulate("single"), args.repeat)
            row["emulator ibm7094"] = median_time(lambda: emulate("ibm7094"), args.ibm7094_repeat)
            rows.append(row)
    cols = list(rows[0])
    print(f"Median wall time in seconds; {os.cpu_count()} cores; Python {sys.version.split()[0]}; "
          f"repeat {args.repeat} (ibm7094: {args.ibm7094_repeat})\n")
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for r in rows:
        print("| " + " | ".join([r["deck"]] + [f"{r[c]:.4f}" for c in cols[1:]]) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
