#!/usr/bin/env python3
"""The compiled listing as a standing oracle: seeded plausible decks (and some physically odd
ones), run through the compiled legacy/luminaire.f (REAL*8, built as scripts/make_goldens.py
builds it) and through the emulator in binary64, printouts compared byte for byte
(:mod:`the checkout's oracle/`).

    python benchmarks/differential.py [--decks 500] [--seed 1] [--keep DIR]

A deck with ALPHA != 0 runs with the ``ed-direction`` erratum on both sides (as printed, ED
walks away from its root there: see legacy/CORRECTIONS.md). How a run ends is compared too:

* the compiled program ends normally  <-> the emulator ends normally: identical bytes;
* it traps (SIGFPE)                   <-> the emulator stops on an arithmetic error: the
  records printed up to the stop identical;
* it does not end within the goldens' time limit <-> one of the emulator's guards fires (ED
  without a root, endless halving, a post that never lands): the shorter record list is a
  prefix of the longer (the compiled program is cut off by the clock, the emulator by its
  guard, so either may have printed more).

tests/legacy/test_differential.py runs 20 decks in the default test run and this script's corpus
under the ``slow_corpus`` marker.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # oracle/, beside the package
from oracle import Oracle, corpus  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--decks", type=int, default=500)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", type=Path, help="write every deck that disagrees here")
    ap.add_argument("--timeout", type=float, default=2.0,
                    help="seconds after which the compiled program counts as not ending (default 2)")
    args = ap.parse_args(argv)
    oracle = Oracle(args.timeout)
    t0 = time.perf_counter()
    tally: dict[tuple[str, str], int] = {}
    bad = 0
    try:
        for i, deck in enumerate(corpus(args.decks, args.seed)):
            o = oracle.compare(deck)
            tally[(o.ending_compiled, o.ending_emulator)] = tally.get((o.ending_compiled, o.ending_emulator), 0) + 1
            if not o.agree:
                bad += 1
                print(f"deck {i}: {o.why}", file=sys.stderr)
                if args.keep:
                    args.keep.mkdir(parents=True, exist_ok=True)
                    (args.keep / f"deck{i:04d}.dat").write_text(deck.to_text())
    finally:
        oracle.close()
    print(f"{args.decks} decks (seed {args.seed}), {bad} disagree, {time.perf_counter() - t0:.1f} s")
    for (c, e), n in sorted(tally.items()):
        print(f"  compiled {c:6s} / emulator {e:13s}: {n}")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
