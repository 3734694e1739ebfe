"""Studies (issue 6): error against run time, and numerical stability on stiff and extreme scenes.

* :func:`error_study` -- ``deck-emulator study error DECK --out DIR [--quick] [--jobs N]``:
  the work-precision study (``error_study.csv``, ``work_precision.png``, ``README.md``);
* :func:`stability_study` -- ``deck-emulator study stability --out DIR [--quick] [--jobs N]``:
  the stability grid (``stability_study.csv``, ``stability_map.png``, ``extreme_scenes.png``,
  ``README.md``).

Both run their runs on the one scene runner (an embedded Dask cluster of ``--jobs`` workers,
default ``os.cpu_count()``, or an existing one with ``--scheduler``), store them in
``DIR/.scenes`` as they finish (``--resume`` runs only the missing ones) and are deterministic
apart from the timings.  :func:`add_parser` registers the ``study`` command with the CLI.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys

from .distributed import scheduler_of
from .error import error_study
from .stability import stability_study

__all__ = ["error_study", "stability_study"]


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
        s = error_study(args.deck, args.out, quick=args.quick, jobs=args.jobs, command=cmd,
                        quiet=args.quiet, scheduler=scheduler_of(args), resume=args.resume)
        o = s["orders"]
        lines = [f"observed order (listing as printed): {o['legacy, ED as printed (double)']['vs_h']:.2f}",
                 f"observed order (ED tightened): {o['legacy, ED tightened (double)']['vs_h']:.2f}"]
    else:
        deck = getattr(args, "deck", None)
        if deck:
            read_deck(deck)
        s = stability_study(args.out, quick=args.quick, jobs=args.jobs, deck_path=deck,
                            command=cmd, quiet=args.quiet, scheduler=scheduler_of(args),
                            resume=args.resume)
        lines = [f"emulator classes: {s['classes']}"]
    for line in lines + [f"wrote {args.out} in {s['wall_s']:.0f} s"]:
        print(f"deck-emulator: study {args.study}: {line}", file=sys.stderr)
    return 0
