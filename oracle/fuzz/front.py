"""The front end through its Python API, past the job deck's reading: ``python -m
oracle.fuzz.front JOB PRECISION OUT`` runs the job deck's FORTRAN cards (between the first
``$IBFTC`` and ``$ENTRY``) on its ``$DATA`` cards as they are, with
``Program(cards).runner(cards, precision).run()``, and writes the records to OUT.

The campaign's ``--road program``: what the front end itself does with a program, whatever
the job deck's reading of its ``$DATA`` section (``--road job``, the default, is the user's
command).  Exit status as the command's: 0 normal, 3 stopped, 2 refused (one line on
stderr); a traceback is a defect."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path


@dataclass
class Cards:
    """Data cards as the runner reads a deck's."""
    cards: list
    path: str = "data"


def split_job(lines: list[str]) -> tuple[list[str], list[str]]:
    """(FORTRAN cards, data cards) of a job deck laid out as generate.job_deck lays it."""
    source, data, where = [], [], None
    for line in lines:
        if line.startswith("$"):
            word = line.split()[0]
            where = {"$IBFTC": "source", "$DATA": "data"}.get(word, None if word in (
                "$ENTRY", "$IBSYS") else where)
            continue
        if where == "source":
            source.append(line)
        elif where == "data":
            data.append(line)
    return source, data


def main(argv: list[str]) -> int:
    from deck_emulator.legacy.deck import DeckError
    from deck_emulator.legacy.fortran import DialectError, Program
    from deck_emulator.legacy.stops import EmulatorError

    job, precision, out = argv
    source, data = split_job(Path(job).read_text().splitlines())
    try:
        program = Program(source, list(range(1, len(source) + 1)), name="the fuzzed program")
    except DialectError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    try:
        run, status = program.runner(Cards(data), precision).run(), 0
    except EmulatorError as exc:
        run, status = exc.run, 3
        print(f"stopped: {exc}", file=sys.stderr)
    except DeckError as exc:  # (a data card its READ cannot take: refused, as the command does)
        print(f"error: {exc}", file=sys.stderr)
        return 2
    Path(out).write_text("".join(r + "\n" for r in run.records))
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
