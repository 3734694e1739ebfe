"""Command line: ``deck-emulator COMMAND ...``.

Each subcommand is a function ``_cmd_<name>(args) -> int`` plus a small function that
adds its subparser, registered with ``@_subcommand``.  A command reports bad input by
raising :class:`~deck_emulator.deck.DeckError` (or another ``CLIError``); ``main`` turns
that into ``deck-emulator: error: <message>`` on stderr and exit status 2.  A command
builds its whole output before writing it, so an error leaves stdout empty.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import sys
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path

from deck_emulator.arithmetic import ARITHMETICS, get_arithmetic
from deck_emulator.deck import READ_LIST, DeckError, field_columns, read_deck
from deck_emulator.emulator import ERRATA, EmulatorError, Limits, Program
from deck_emulator.printer import render_asa

PROG = "deck-emulator"
EXIT_BAD_INPUT = 2


class CLIError(Exception):
    """A user-facing error that is not about a deck's contents."""


# Functions that add one subcommand's parser; main() calls each of them in order.
_SUBCOMMANDS: list[Callable[[argparse._SubParsersAction], None]] = []


def _subcommand(add: Callable[[argparse._SubParsersAction], None]):
    _SUBCOMMANDS.append(add)
    return add


# --------------------------------------------------------------------------- parse


def _cmd_parse(args: argparse.Namespace) -> int:
    deck = read_deck(args.deck)
    if args.json:
        text = json.dumps(deck.values) + "\n"
    else:
        text = _deck_table(deck)
    sys.stdout.write(text)
    return 0


def _deck_table(deck) -> str:
    lines = [f"{deck.path}: 8 cards, FORMAT(8F10.5)"]
    for card_no, names in enumerate(READ_LIST, start=1):
        lines.append("")
        lines.append(f"card {card_no}   columns  name       value")
        for field_no, name in enumerate(names, start=1):
            first, last = field_columns(field_no)
            lines.append(f"         {first:2d}-{last:<2d}    {name:<8s} {deck[name]!r:>12s}")
    return "\n".join(lines) + "\n"


@_subcommand
def _add_parse(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "parse",
        help="read a card deck and print its 64 values",
        description="Read a $DATA card deck (8 cards, FORMAT(8F10.5)) with the 1967 input "
        "rules and print the values under their READ-list names.",
    )
    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    p.add_argument(
        "--json", action="store_true", help="print one JSON object, name -> value, in READ order"
    )
    p.set_defaults(func=_cmd_parse)


# --------------------------------------------------------------------------- run


EXIT_RUN_FAILED = 3


def write_atomic(path: str, text: str) -> None:
    """Write a file whole or not at all: a temporary file beside it, then a rename."""
    target = Path(path)
    fd, tmp = tempfile.mkstemp(dir=target.parent or ".", prefix=f".{target.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def _emit(args, text: str) -> None:
    if getattr(args, "out", None):
        write_atomic(args.out, text)
    else:
        sys.stdout.write(text)


def _arithmetic(args):
    options = {}
    if args.precision == "ibm7094":
        options = dict(sincos=args.sincos, decimal=args.decimal, output=args.output_rounding)
    elif any(x is not None for x in (args.sincos, args.decimal, args.output_rounding)):
        raise CLIError("--sincos, --decimal and --output-rounding are assumptions of --precision ibm7094")
    return get_arithmetic(args.precision, **{k: v for k, v in options.items() if v is not None})


def _run_emulator(args, deck):
    limits = Limits(ed_iterations=args.max_ed_iterations, halvings=args.max_halvings,
                    time_s=args.max_time)
    return Program(deck, _arithmetic(args), errata=tuple(args.erratum), step_scale_k=args.step_scale,
                   tha_start=args.tha_start, limits=limits).run()


def _describe(run) -> str:
    errata = ", ".join(run.errata) or "none (the listing as printed)"
    scale = f"; step literals / 2**{run.step_scale_k}" if run.step_scale_k else ""
    return f"arithmetic {run.arithmetic}; errata: {errata}{scale}"


def _cmd_run(args: argparse.Namespace) -> int:
    deck = read_deck(args.deck)
    try:
        run = _run_emulator(args, deck)
        error = None
    except EmulatorError as exc:
        run, error = exc.run, exc
    text = render_asa(run.records) if args.render else run.text()
    _emit(args, text)
    print(f"{PROG}: {deck.path}: {_describe(run)}", file=sys.stderr)
    if error is not None:
        print(f"{PROG}: error: {error}", file=sys.stderr)
        return EXIT_RUN_FAILED
    return 0


def _add_emulator_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    p.add_argument("--precision", choices=ARITHMETICS, default="double",
                   help="arithmetic: double (IEEE binary64, as the r8 goldens), single (IEEE "
                   "binary32, as the r4 goldens, trapping), ibm7094 (the 1967 machine's 36-bit words)")
    p.add_argument("--erratum", action="append", default=[], choices=sorted(ERRATA),
                   help="apply a named erratum to the listing (default: none, as printed)")
    p.add_argument("--step-scale", type=int, default=0, metavar="K",
                   help="divide every literal that means one step (0.0004 s) by 2**K")
    p.add_argument("--tha-start", metavar="VALUE",
                   help="start-up THA at label 123 instead of the printed 0.000022")
    p.add_argument("--max-time", type=float, default=Limits.time_s, metavar="S",
                   help="stop when simulated time passes S seconds (default %(default)s)")
    p.add_argument("--max-ed-iterations", type=int, default=Limits.ed_iterations, metavar="N",
                   help="stop when one call of ED iterates N times (default %(default)s)")
    p.add_argument("--max-halvings", type=int, default=Limits.halvings, metavar="N",
                   help="stop after N consecutive step halvings at label 108 (default %(default)s)")
    p.add_argument("--sincos", choices=("chop", "round"), help="ibm7094: how SIN/COS were rounded")
    p.add_argument("--decimal", choices=("chop", "round"),
                   help="ibm7094: how decimal constants and deck fields were converted")
    p.add_argument("--output-rounding", choices=("nearest", "truncate"),
                   help="ibm7094: how F-format output rounded")


@_subcommand
def _add_run(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "run",
        help="run the 1967 program on a deck and write its line-printer output",
        description="Run the emulated 1967 program on a deck. The printout goes to stdout (or "
        "--out FILE, written whole or not at all); what was run (arithmetic, its assumptions, "
        "errata) is said on stderr. If the run stops early (a trap or a guard), the records "
        "printed until then are written and the exit status is 3.",
    )
    _add_emulator_options(p)
    p.add_argument("--out", metavar="FILE", help="write the printout to FILE")
    p.add_argument("--render", action="store_true",
                   help="render ASA carriage control (1 = form feed, 0 = blank line, + = "
                   "overprint) as the POSIX asa utility does, instead of the raw records")
    p.set_defaults(func=_cmd_run)


# --------------------------------------------------------------------------- main


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Emulator of the 1967 TTI luminaire-support impact program (Report 75-9).",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for add in _SUBCOMMANDS:
        add(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (2) and --help (0)
        return exc.code if isinstance(exc.code, int) else 2
    try:
        return args.func(args)
    except (DeckError, CLIError, OSError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT


if __name__ == "__main__":
    raise SystemExit(main())
