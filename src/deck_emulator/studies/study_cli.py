"""Studies (issue 6): error against run time, and numerical stability on stiff and extreme scenes.

* :func:`error_study` -- ``deck-emulator study error DECK --out DIR [--quick] [--jobs N]``:
  the work-precision study (``error_study.csv``, ``work_precision.png``, ``README.md``);
* :func:`stability_study` -- ``deck-emulator study stability --out DIR [--quick] [--jobs N]``:
  the stability grid (``stability_study.csv``, ``stability_map.png``, ``extreme_scenes.png``,
  ``README.md``).

Both run their runs over ``--jobs`` processes (default ``os.cpu_count()``) and are deterministic
apart from the timings.  :func:`add_parser` registers the ``study`` command with the CLI.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys

from .error import error_study
from .stability import stability_study

__all__ = ["error_study", "stability_study", "add_parser"]


def _jobs(text: str) -> int:
    n = int(text)
    if n < 1:
        raise argparse.ArgumentTypeError("--jobs must be at least 1")
    return n


def _command(args) -> str:
    argv = ["deck-emulator", "study", args.study]
    if args.study == "error":
        argv.append(args.deck)
    argv += ["--out", args.out] + (["--quick"] if args.quick else []) + ["--jobs", str(args.jobs)]
    return shlex.join(argv)


def _cmd_study(args: argparse.Namespace) -> int:
    from deck_emulator.legacy.deck import read_deck

    args.jobs = args.jobs or os.cpu_count() or 1
    cmd = _command(args)
    if args.study == "error":
        read_deck(args.deck)  # DeckError -> exit status 2 before any work
        s = error_study(args.deck, args.out, quick=args.quick, jobs=args.jobs, command=cmd)
        o = s["orders"]
        lines = [f"observed order (listing as printed): {o['legacy, ED as printed (double)']['vs_h']:.2f}",
                 f"observed order (ED tightened): {o['legacy, ED tightened (double)']['vs_h']:.2f}"]
    else:
        deck = getattr(args, "deck", None)
        if deck:
            read_deck(deck)
        s = stability_study(args.out, quick=args.quick, jobs=args.jobs, deck_path=deck, command=cmd)
        lines = [f"emulator classes: {s['classes']}"]
    for line in lines + [f"wrote {args.out} in {s['wall_s']:.0f} s"]:
        print(f"deck-emulator: study {args.study}: {line}", file=sys.stderr)
    return 0


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``deck-emulator study error|stability`` on the CLI's subparsers."""
    p = sub.add_parser(
        "study",
        help="work-precision and stability studies (CSV, PNG and Markdown into --out)",
        description="Numerical studies of the 1967 scheme (the emulator) and the modern core. "
        "Each writes a CSV of every run, PNG figures and a README.md report into --out.",
    )
    studies = p.add_subparsers(dest="study", metavar="STUDY", required=True)

    def common(q):
        q.add_argument("--out", required=True, metavar="DIR", help="directory for the outputs")
        q.add_argument("--quick", action="store_true",
                       help="a small grid (seconds, for tests) instead of the full study")
        q.add_argument("--jobs", type=_jobs, default=None, metavar="N",
                       help="worker processes (default: os.cpu_count())")
        q.set_defaults(func=_cmd_study)

    e = studies.add_parser(
        "error", help="error against run time: the emulator at H = 0.0004/2**k, the core at "
        "rtol 1e-3 ... 1e-11, against a 1e-12 reference",
        description="Work-precision study on DECK: the emulator in double precision at H = "
        "0.0004/2**k (k = 0..6; the listing's ED tolerance and a tightened one), in the IBM 7094 "
        "arithmetic at k = 0, and the core with DOP853, RK45 and Radau at rtol 1e-3 ... 1e-11, "
        "all against the core at rtol 1e-12 (itself checked with Radau and LSODA at 1e-13).")
    e.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    common(e)
    s = studies.add_parser(
        "stability", help="stiff springs against H, and extreme scenes, for the emulator and "
        "the core",
        description="Stability study: a grid of scenes derived from steel40 (CK = CT from "
        "3.3e4 to 1e10 lb/ft against H; speeds 5-120 mph; approach angles to 90 deg; delta = 0; "
        "the start-up THA; A = B = C; light and heavy posts; base friction; THB near 90 deg), "
        "each run by the emulator and the core, with how it ended.")
    s.add_argument("--deck", metavar="DECK", default=None,
                   help="base deck (default: the repository's decks/steel40.dat)")
    common(s)
