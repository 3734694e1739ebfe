#!/usr/bin/env python3
"""A single core run where a person waits (issue 48): `core steel40` against `run steel40`.

    python benchmarks/bench_core_start.py [--repeat 7] [--first-use-repeat 1] [--src DIR]

Prints, measured in this one run, the median wall time and the median CPU time (user +
system, from ``os.wait4``) of the whole process (interpreter start, imports, the run, the
answer written to /dev/null) of

* ``deck-emulator run steel40``: the emulator, the reference;
* ``deck-emulator core steel40``, warm: numba's machine code of the core already in its
  cache (one unmeasured run fills it where it was empty);
* ``deck-emulator core steel40``, first use: numba's cache pointed (NUMBA_CACHE_DIR, numba's
  documented setting) at a new empty folder for each run, as after a fresh install;

then the ratio of the warm core to ``run`` and whether the targets are met: warm ``core`` at
most 3x ``run``, judged on the median wall time and again on the median CPU time, which other
people's work on a shared machine inflates less; the first use at most 15 s of CPU.

The processes run with their bytecode cached, as an installed package's is
(:func:`whole_process.environment`); the warm commands alternate within each repetition, so
that a change in the machine's load falls on both alike.  ``--src DIR``: measure another
checkout's ``src`` (its own numba cache: run once first, or the unmeasured run compiles).
Say how loaded the machine was when quoting the times.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

from whole_process import environment, machine_line, measure

ROOT = Path(__file__).resolve().parent.parent
DECK = str(ROOT / "decks" / "steel40.dat")
TARGET_RATIO = 3.0  # warm core / run, at most
FIRST_USE_TARGET_CPU_S = 15.0  # first core run after an install, CPU s at most
REFERENCE = "run steel40"
WARM = "core steel40 (warm)"
FIRST = "core steel40 (first use)"


def commands() -> dict[str, list[str]]:
    py = sys.executable
    return {
        REFERENCE: [py, "-m", "deck_emulator", "run", DECK, "--quiet"],
        WARM: [py, "-m", "deck_emulator", "core", DECK, "--quiet"],
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="runs of each warm command "
                    "(default 7)")
    ap.add_argument("--first-use-repeat", type=int, default=1,
                    help="first-use runs, each with an empty numba cache (default 1; about a "
                    "minute each before issue 48); 0: none")
    ap.add_argument("--src", help="the src folder to measure (default: this checkout's)")
    args = ap.parse_args(argv)
    walls: dict[str, list[float]] = {REFERENCE: [], WARM: [], FIRST: []}
    cpus: dict[str, list[float]] = {REFERENCE: [], WARM: [], FIRST: []}
    with tempfile.TemporaryDirectory() as cache:
        env = environment(cache, *([Path(args.src).resolve()] if args.src else []))
        cmds = commands()
        for argv_ in cmds.values():  # fills the bytecode (and numba's) caches, unmeasured
            measure(argv_, env)
        for _ in range(args.repeat):
            for name, argv_ in cmds.items():
                wall_s, cpu_s = measure(argv_, env)
                walls[name].append(wall_s)
                cpus[name].append(cpu_s)
        for k in range(args.first_use_repeat):
            empty = Path(cache) / f"numba-empty-{k}"
            empty.mkdir()
            wall_s, cpu_s = measure(cmds[WARM], {**env, "NUMBA_CACHE_DIR": str(empty)})
            walls[FIRST].append(wall_s)
            cpus[FIRST].append(cpu_s)
    print(f"{'command (whole process)':<28}{'median s':>10}{'min s':>8}{'CPU s':>8}{'runs':>6}")
    for name, t in walls.items():
        if t:
            print(f"{name:<28}{statistics.median(t):>10.3f}{min(t):>8.3f}"
                  f"{statistics.median(cpus[name]):>8.3f}{len(t):>6}")
    print("(median and min: wall time; CPU s: the median of user + system time, which a busy "
          "machine inflates less)")
    print()
    for what, m in (("wall", walls), ("CPU", cpus)):
        ratio = statistics.median(m[WARM]) / statistics.median(m[REFERENCE])
        print(f"{what:>4}: warm core / run {ratio:.2f} (target at most {TARGET_RATIO:g}): "
              f"{'met' if ratio <= TARGET_RATIO else 'NOT met'}")
    if cpus[FIRST]:
        first = statistics.median(cpus[FIRST])
        print(f"first use: {first:.1f} s CPU, {statistics.median(walls[FIRST]):.1f} s wall "
              f"(target at most {FIRST_USE_TARGET_CPU_S:g} s CPU): "
              f"{'met' if first <= FIRST_USE_TARGET_CPU_S else 'NOT met'}")
    print(machine_line())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
