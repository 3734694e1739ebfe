#!/usr/bin/env python3
"""Start-up time of the command line, whole process, median of N runs.

    python benchmarks/bench_startup.py [--repeat 7]

Prints, for each command, the median wall time of the whole process (interpreter start, the
imports, the work) and whether scipy or matplotlib were imported; the interpreter alone
(``python -c pass``) is the floor.  Goal: ``parse`` at most 0.35 s on a quiet 2-core machine,
with neither scipy nor matplotlib imported.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DECK = str(ROOT / "decks" / "steel40.dat")
COMMANDS = {
    "python -c pass (floor)": [sys.executable, "-c", "pass"],
    "deck-emulator --version": [sys.executable, "-m", "deck_emulator", "--version"],
    "deck-emulator parse": [sys.executable, "-m", "deck_emulator", "parse", DECK],
    "deck-emulator run": [sys.executable, "-m", "deck_emulator", "run", DECK],
}
PROBE = ("import sys, runpy; sys.argv = ['deck-emulator'] + sys.argv[1:]\n"
         "try:\n    runpy.run_module('deck_emulator', run_name='__main__')\n"
         "except SystemExit:\n    pass\n"
         "print(sorted(m for m in ('scipy', 'matplotlib') if m in sys.modules), file=sys.stderr)")


def median_wall(argv: list[str], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        times.append(time.perf_counter() - started)
    return statistics.median(times)


def heavy_imports(argv: list[str]) -> str:
    if "-m" not in argv:
        return ""
    args = argv[argv.index("deck_emulator") + 1:]
    proc = subprocess.run([sys.executable, "-c", PROBE, *args], capture_output=True, text=True)
    return proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "?"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="runs per command (default 7)")
    args = parser.parse_args()
    print(f"{'command':<28}{'median s':>10}   heavy modules imported")
    for name, argv in COMMANDS.items():
        t = median_wall(argv, args.repeat)
        print(f"{name:<28}{t:>10.3f}   {heavy_imports(argv)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
