"""Command-line pieces for card files, job decks, the punch and the printed pages.

Kept apart from ``deck_emulator.cli`` so that the command line only calls these:
:func:`add_card_options` and :func:`load_job` (every command that reads a deck),
:func:`add_pages_options` and :func:`write_pages` (``run``), and :func:`add_punch_parser`
(the ``punch`` subcommand).
"""

from __future__ import annotations

import argparse
import sys

from deck_emulator.legacy.cardimage import FORMATS, write_images
from deck_emulator.legacy.deck import DeckError
from deck_emulator.legacy.jobdeck import Job, data_deck_texts, job_deck_texts, read_job
from deck_emulator.legacy.keypunch import CODES

PROG = "deck-emulator"


def add_card_options(p: argparse.ArgumentParser) -> None:
    """--card-format and --keypunch, for a command that reads a deck."""
    p.add_argument("--card-format", choices=("auto", *FORMATS), default="auto",
                   help="the deck file's card image format (default: detected when the file "
                   "is unambiguous)")
    p.add_argument("--keypunch", choices=sorted(CODES), default=None,
                   help="the code holes are read in: 026 (the 7090/7094 FORTRAN code, the "
                   "default for binary images) or 029; text cards are taken as they stand")


def load_job(args: argparse.Namespace) -> Job:
    """Read ``args.deck`` as a plain or job deck; say on stderr what the source is and
    what the deck reader warns of."""
    job = read_job(args.deck, getattr(args, "card_format", "auto"),
                   getattr(args, "keypunch", None))
    if job.source_verdict:
        print(f"{PROG}: {job.path}: {job.source_verdict}", file=sys.stderr)
    for deck in job.decks:
        for warning in deck.warnings:
            print(f"{PROG}: {deck.path}: warning: {warning}", file=sys.stderr)
    return job


def load_one_deck(args: argparse.Namespace):
    """The one data deck of ``args.deck``; DeckError if it holds several $DATA sections."""
    job = load_job(args)
    if len(job.decks) != 1:
        raise DeckError(f"this command takes one $DATA section and the deck holds "
                        f"{len(job.decks)}; `run` runs each in turn", path=job.path)
    return job.decks[0]


def add_pages_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--pages", metavar="FILE.pdf",
                   help="also lay the printout out as the line printer's pages, as PDF")
    p.add_argument("--paper", choices=("plain", "striped"), default="plain",
                   help="the fan-fold paper of --pages (default plain)")


def write_pages(args: argparse.Namespace, records: list[str]) -> None:
    if getattr(args, "pages", None):
        from deck_emulator.legacy.pages import write_pdf

        write_pdf(records, args.pages, paper=args.paper)


# --------------------------------------------------------------------------- punch


def _cmd_punch(args: argparse.Namespace) -> int:
    job = load_job(args)
    texts = (job_deck_texts(list(job.decks)) if args.job else data_deck_texts(list(job.decks)))
    try:
        data = write_images(texts, args.to, args.code)
    except DeckError as err:
        raise DeckError(f"cannot punch in the {args.code} code: {err}") from None
    if args.out:
        _write_bytes_atomic(args.out, data)
    else:
        sys.stdout.buffer.write(data)
        sys.stdout.flush()
    return 0


def _write_bytes_atomic(path: str, data: bytes) -> None:
    """Write whole or not at all: a temporary file beside ``path``, then a rename."""
    import contextlib
    import os
    import tempfile
    from pathlib import Path

    target = Path(path)
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def add_punch_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "punch",
        help="punch a deck's data cards (or a whole job deck) in a card image format",
        description="Read a deck (any card format) and punch its data cards, in the report's "
        "layout (8F10.5, a $DATA card first), as text, binary, column binary (cbn) or BCD "
        "card images, in the 026 or 029 keypunch code.  --job punches a whole IBSYS job "
        "deck: control cards, the listing's FORTRAN source and the data.",
    )
    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    add_card_options(p)
    p.add_argument("--to", choices=FORMATS, default="text", help="card format to punch")
    p.add_argument("--code", choices=sorted(CODES), default="026",
                   help="keypunch code of the punched holes (default 026)")
    p.add_argument("--job", action="store_true", help="punch a whole job deck")
    p.add_argument("--out", metavar="FILE", help="write to FILE (default: stdout)")
    p.set_defaults(func=_cmd_punch)
