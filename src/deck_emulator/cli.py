"""Command line: ``deck-emulator COMMAND ...``.

Each subcommand is a function ``_cmd_<name>(args) -> int`` plus a small function that
adds its subparser, registered with ``@_subcommand``.  A command reports bad input by
raising :class:`~deck_emulator.deck.DeckError` (or another ``CLIError``); ``main`` turns
that into ``deck-emulator: error: <message>`` on stderr and exit status 2.  A command
builds its whole output before writing it, so an error leaves stdout empty.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Sequence

from deck_emulator.deck import READ_LIST, DeckError, field_columns, read_deck

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
    except (DeckError, CLIError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT


if __name__ == "__main__":
    raise SystemExit(main())
