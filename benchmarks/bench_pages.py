#!/usr/bin/env python3
"""The printer's pages (issue 48): `run steel40 --pages` against `run steel40`, whole process.

    python benchmarks/bench_pages.py [--repeat 7]

Prints, measured in this one run, the median wall time and the median CPU time (user +
system, from ``os.wait4``) of the whole process (interpreter start, imports, the run, the
output written) of

* ``deck-emulator run steel40`` (the printout to /dev/null): the reference;
* ``deck-emulator run steel40 --pages p.pdf``: the same run and its 120 pages as PDF;
* ``deck-emulator run steel40 --pages p.pdf --paper striped --listing``: 133 pages on green-bar
  paper, the compile listing before the output;

then the ratio of each to the reference and whether the target is met: ``--pages`` at most 3x
``run``, judged on the median wall time and again on the median CPU time, which other
people's work on a shared machine inflates less.  Two PDFs of the same command must be the
same bytes: the script says whether they were.

The processes run with their bytecode cached, as an installed package's is (the environment's
PYTHONDONTWRITEBYTECODE is dropped and PYTHONPYCACHEPREFIX points into a temporary folder, so
the checkout is left untouched); one unmeasured run of each fills the caches.  The commands
alternate within each repetition, so that a change in the machine's load falls on all of
them alike.  Say how loaded the machine was when quoting the times.
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
TARGET_RATIO = 3.0  # run --pages / run, at most
REFERENCE = "run steel40"


def commands(folder: str) -> dict[str, list[str]]:
    run = [sys.executable, "-m", "deck_emulator", "run", DECK, "--quiet"]
    pdf = str(Path(folder) / "p.pdf")
    return {
        REFERENCE: run,
        "run steel40 --pages p.pdf": [*run, "--pages", pdf],
        "... --paper striped --listing": [*run, "--pages", pdf, "--paper", "striped",
                                          "--listing"],
    }




def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="runs of each command (default 7)")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as cache:
        env = environment(cache)
        cmds = commands(cache)
        pdf = Path(cache) / "p.pdf"
        measure(cmds["run steel40 --pages p.pdf"], env)  # fills the caches, unmeasured
        first = pdf.read_bytes()
        for argv_ in cmds.values():
            measure(argv_, env)
        walls: dict[str, list[float]] = {name: [] for name in cmds}
        cpus: dict[str, list[float]] = {name: [] for name in cmds}
        same = True
        for _ in range(args.repeat):
            for name, argv_ in cmds.items():
                wall_s, cpu_s = measure(argv_, env)
                walls[name].append(wall_s)
                cpus[name].append(cpu_s)
                if name == "run steel40 --pages p.pdf":
                    same = same and pdf.read_bytes() == first
    med = {name: statistics.median(t) for name, t in walls.items()}
    cpu = {name: statistics.median(t) for name, t in cpus.items()}
    print(f"{'command (whole process)':<34}{'median s':>10}{'min s':>8}{'CPU s':>8}{'runs':>6}")
    for name, t in walls.items():
        print(f"{name:<34}{med[name]:>10.3f}{min(t):>8.3f}{cpu[name]:>8.3f}{len(t):>6}")
    print("(median and min: wall time; CPU s: the median of user + system time)")
    print()
    for what, m in (("wall", med), ("CPU", cpu)):
        for name in list(cmds)[1:]:
            ratio = m[name] / m[REFERENCE]
            print(f"{what:>4}: {name} / {REFERENCE} = {ratio:.2f} (target at most "
                  f"{TARGET_RATIO:g}): {'met' if ratio <= TARGET_RATIO else 'NOT met'}")
    print(f"the same PDF bytes on every run of `run steel40 --pages`: {'yes' if same else 'NO'}"
          f" ({len(first)} bytes)")
    print(machine_line())
    return 0 if same else 1


if __name__ == "__main__":
    raise SystemExit(main())
