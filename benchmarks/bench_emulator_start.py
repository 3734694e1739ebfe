#!/usr/bin/env python3
"""The emulator's start (issue 25, item 6): whole-process times against a plain transcription.

    python benchmarks/bench_emulator_start.py [--repeat 7] [--ibm7094-repeat 7]

Prints, measured in this one run, the median wall time of the whole process (interpreter
start, imports, the run, the printout written to /dev/null) of

* ``python -c pass`` (the floor);
* ``python benchmarks/plain_listing.py decks/steel40.dat``: the listing transcribed into plain
  Python floats, its output formatted by ``%`` (the reference; tests/legacy/test_plain_listing.py
  checks that it prints the r8 golden and the emulator's printout byte for byte);
* ``deck-emulator run decks/steel40.dat`` and the same with ``--precision ibm7094``: the
  listing through the FORTRAN front end, its made code kept in the user's cache folder (made
  by a first run outside the timing: no parse at the start);
* ``deck-emulator run`` on a job deck of steel40 (``punch --job``) whose FORTRAN is the listing
  with one constant respelled (``HI=0.00040``): the deck's own program, read from its cards,
  parsed, made Python and run by the FORTRAN front end (legacy/fortran), in binary64 and in the
  7094's arithmetic: the listing through the front end;

then the ratio of ``run`` (the listing, and a job deck's own program) to the transcription and whether each
target is met: within 2x the transcription, ``--precision ibm7094`` at most 1.5 s; the targets are judged on the
median wall time, and again on the median CPU time (user + system, from ``os.wait4``), which
other people's work on a shared machine inflates less.

The processes run with their bytecode cached, as an installed package's is (the environment's
PYTHONDONTWRITEBYTECODE is dropped and PYTHONPYCACHEPREFIX points into a temporary folder, so
the checkout is left untouched), and a job deck's own program made once (the front end keeps
its made code by the cards' SHA-256 in the user's cache folder: XDG_CACHE_HOME points into the
same temporary folder); one unmeasured run of each fills the caches.  The commands
alternate within each repetition, so that a change in the machine's load falls on all of
them alike.  Times are wall-clock: say how loaded the machine was when quoting them.

``--baseline REF`` adds ``run steel40`` of the package as it stood at the git commit REF (its
``src/`` exported to a temporary folder, with a cache folder of its own), measured in the same
alternation, and prints the ratio of this checkout's run to it: "no slower than REF" is judged
on that ratio, not on figures of two different runs.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from whole_process import environment, machine_line, measure

ROOT = Path(__file__).resolve().parent.parent
DECK = str(ROOT / "decks" / "steel40.dat")
RUN_TARGET_RATIO = 2.0  # run / transcription, at most
IBM7094_TARGET_S = 1.5  # run --precision ibm7094, at most


def commands(job: str) -> dict[str, list[str]]:
    py = sys.executable
    return {
        "python -c pass (floor)": [py, "-c", "pass"],
        "plain transcription": [py, str(ROOT / "benchmarks" / "plain_listing.py"), DECK],
        "deck-emulator run steel40": [py, "-m", "deck_emulator", "run", DECK],
        "run steel40 --precision ibm7094": [py, "-m", "deck_emulator", "run", DECK,
                                            "--precision", "ibm7094"],
        "front end: run the job deck": [py, "-m", "deck_emulator", "run", job],
        "front end: ... --precision ibm7094": [py, "-m", "deck_emulator", "run", job,
                                               "--precision", "ibm7094"],
    }


def job_deck(folder: str, env: dict[str, str]) -> str:
    """steel40 as a job deck whose FORTRAN is the listing's with HI=0.0004 spelled 0.00040."""
    path = Path(folder) / "steel40_respelled.job"
    subprocess.run([sys.executable, "-m", "deck_emulator", "punch", DECK, "--to", "text",
                    "--job", "--out", str(path)], check=True, env=env)
    text = path.read_text()
    assert "      HI=0.0004\n" in text
    path.write_text(text.replace("      HI=0.0004\n", "      HI=0.00040\n", 1))
    return str(path)




def baseline(ref: str, folder: str) -> tuple[list[str], dict[str, str]]:
    """``run steel40`` of the package at the commit ``ref`` (its src/ and legacy/ exported into
    ``folder``), and the environment it runs in: bytecode and user cache in ``folder`` too."""
    tree = Path(folder) / "baseline"
    tree.mkdir()
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", ref, "src", "legacy"],
                             check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(tree)], input=archive, check=True)
    return [sys.executable, "-m", "deck_emulator", "run", DECK], environment(
        str(tree / "cache"), tree / "src")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="runs of each command (default 7)")
    ap.add_argument("--ibm7094-repeat", type=int, default=7,
                    help="runs of the ibm7094 command (default 7, ~1.5 s each)")
    ap.add_argument("--baseline", metavar="REF",
                    help="also run steel40 with the package at git commit REF, alternating")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as cache:
        env = environment(cache)
        cmds = commands(job_deck(cache, env))
        envs = dict.fromkeys(cmds, env)
        if args.baseline:
            at_ref = f"run steel40 at {args.baseline}"
            cmds[at_ref], envs[at_ref] = baseline(args.baseline, cache)
        walls: dict[str, list[float]] = {name: [] for name in cmds}
        cpus: dict[str, list[float]] = {name: [] for name in cmds}
        for name, argv_ in cmds.items():  # fill the bytecode cache, unmeasured
            measure(argv_, envs[name])
        for i in range(max(args.repeat, args.ibm7094_repeat)):
            for name, argv_ in cmds.items():
                wanted = args.ibm7094_repeat if "ibm7094" in name else args.repeat
                if i < wanted:
                    wall_s, cpu_s = measure(argv_, envs[name])
                    walls[name].append(wall_s)
                    cpus[name].append(cpu_s)
    med = {name: statistics.median(t) for name, t in walls.items()}
    cpu = {name: statistics.median(t) for name, t in cpus.items()}
    print(f"{'command (whole process)':<34}{'median s':>10}{'min s':>8}{'CPU s':>8}{'runs':>6}")
    for name, t in walls.items():
        print(f"{name:<34}{med[name]:>10.3f}{min(t):>8.3f}{cpu[name]:>8.3f}{len(t):>6}")
    print("(median and min: wall time; CPU s: the median of user + system time, which a busy "
          "machine inflates less)")
    print()
    for what, m in (("wall", med), ("CPU", cpu)):
        for who, run, ibm7094 in (
                ("listing", "deck-emulator run steel40", "run steel40 --precision ibm7094"),
                ("job deck", "front end: run the job deck",
                 "front end: ... --precision ibm7094")):
            ratio = m[run] / m["plain transcription"]
            ibm = m[ibm7094]
            print(f"{what:>4}, {who}: run / transcription {ratio:.2f} (target at most "
                  f"{RUN_TARGET_RATIO:g}): {'met' if ratio <= RUN_TARGET_RATIO else 'NOT met'}; "
                  f"run --precision ibm7094 {ibm:.3f} s (target at most {IBM7094_TARGET_S:g} "
                  f"s): {'met' if ibm <= IBM7094_TARGET_S else 'NOT met'}")
    if args.baseline:
        for what, m in (("wall", med), ("CPU", cpu)):
            ratio = m["deck-emulator run steel40"] / m[at_ref]
            print(f"{what:>4}: run steel40 / the same at {args.baseline} {ratio:.3f} "
                  f"({'no slower' if ratio <= 1 else 'slower'})")
    print(machine_line())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
