"""Delta debugging (Zeller and Hildebrandt's ddmin) of a disagreement to a minimal program.

The pieces are the program's statements (a statement with its continuation cards is one
piece; comment cards go first, all at once) and then its data cards.  A candidate -- the
program without some pieces -- is kept only if it is still *well defined and still the same
failure*: gfortran's checked build accepts it and runs it to its end (a deletion that leaves a
REAL unset, a DO with no trips, a label missing is rejected there), the oracle build ends
normally, and the front end's verdict has the same outcome and class (classes.py) as the
original's.  The result is 1-minimal: taking out any one more statement loses the failure or
its definedness.  Each candidate costs two gfortran builds and a front-end run, so a shrink is
bounded by ``max_tests``.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from .classes import classify
from .generate import job_deck
from .judge import judge


def _pieces(source: list[str]) -> list[list[str]]:
    """The source's statements, each with its continuation cards (comments dropped)."""
    from deck_emulator.legacy.jobdeck import is_comment, is_continuation

    pieces: list[list[str]] = []
    for line in source:
        if is_comment(line):
            continue
        if is_continuation(line) and pieces:
            pieces[-1].append(line)
        else:
            pieces.append([line])
    return pieces


def _units(pieces: list[list[str]]) -> list[list[list[str]]]:
    """The pieces by program unit (a unit ends with its END statement)."""
    units: list = [[]]
    for p in pieces:
        units[-1].append(p)
        if "".join(x[6:72] for x in p).replace(" ", "") == "END":
            units.append([])
    return [u for u in units if u]


def ddmin(items: list, interesting, max_tests: int = 400) -> list:
    """The 1-minimal sublist of ``items`` for which ``interesting`` holds (it holds for
    ``items``); at most ``max_tests`` calls."""
    tests = 0
    n = 2
    while len(items) >= 2:
        chunk = -(-len(items) // n)
        reduced = False
        for start in range(0, len(items), chunk):
            candidate = items[:start] + items[start + chunk:]
            if not candidate:
                continue
            tests += 1
            if tests > max_tests:
                return items
            if interesting(candidate):
                items = candidate
                n = max(n - 1, 2)
                reduced = True
                break
        if not reduced:
            if n >= len(items):
                break
            n = min(len(items), n * 2)
    return items


def shrink(source: list[str], data: list[str], outcome: str, klass: str, *,
           env_path: str | None = None, road: str = "job", max_tests: int = 400):
    """(minimal source, minimal data, its verdict) of a failing program (see the module
    docstring)."""
    seen: dict = {}  # (source, data) -> (still the failure, its verdict)

    def test(src: list[str], dat: list[str]) -> bool:
        key = ("\n".join(src), "\n".join(dat))
        if key not in seen:
            with tempfile.TemporaryDirectory(prefix="shrink-") as tmp:
                v = judge(Path(tmp), src, dat, job_deck([("MAIN", src)], dat), ibm7094=False,
                          env_path=env_path, road=road, fail_first=outcome)
            seen[key] = (v is not None and v.outcome == outcome
                         and classify(src, v) == klass, v)
        return seen[key][0]

    pieces = _pieces(source)
    flat = [line for p in pieces for line in p]
    if not test(flat, data):  # (without its comment cards, or in one $IBFTC: not the same)
        pieces = [[line] for line in source]
        flat = list(source)
        if not test(flat, data):
            return source, data, None
    units = _units(pieces)  # whole subprograms first, then statements
    if len(units) > 1:
        units = [units[0]] + ddmin(units[1:], lambda us: test(
            [x for u in [units[0], *us] for p in u for x in p], data), max_tests // 8)
        pieces = [p for u in units for p in u]
    pieces = ddmin(pieces, lambda ps: test([x for p in ps for x in p], data), max_tests)
    src = [x for p in pieces for x in p]
    data = ddmin(data, lambda ds: test(src, ds), max_tests // 4) if len(data) > 1 else data
    if len(data) == 1 and test(src, []):
        data = []
    test(src, data)
    return src, data, seen[("\n".join(src), "\n".join(data))][1]


def shrink_program(program, verdict, *, env_path: str | None = None, road: str = "job"):
    """(the minimal job deck's cards, its verdict's one line) for a generated program."""
    klass = classify(program.source, verdict)
    src, data, v = shrink(program.source, program.data, verdict.outcome, klass,
                          env_path=env_path, road=road)
    if v is None:
        return None, "not shrunk: the program in one $IBFTC section is not the same failure"
    return job_deck([("MAIN", src)], data), v.why


def main(argv=None) -> int:
    import argparse

    from .front import split_job
    from .judge import ROADS

    ap = argparse.ArgumentParser(prog="python -m oracle.fuzz.shrink", description=(
        "Shrink a job deck on which the front end and gfortran disagree to a minimal one "
        "(printed on stdout)."))
    ap.add_argument("job", type=Path)
    ap.add_argument("--road", choices=ROADS, default="job")
    ap.add_argument("--env-src", metavar="DIR")
    ap.add_argument("--max-tests", type=int, default=400)
    a = ap.parse_args(argv)
    source, data = split_job(a.job.read_text().splitlines())
    with tempfile.TemporaryDirectory(prefix="shrink-") as tmp:
        v = judge(Path(tmp), source, data, a.job.read_text().splitlines(), ibm7094=False,
                  env_path=a.env_src, road=a.road)
    if v.outcome in ("agree", "oracle-rejected"):
        print(f"{a.job}: nothing to shrink: {v.outcome} {v.why}".rstrip())
        return 2
    klass = classify(source, v)
    src, dat, w = shrink(source, data, v.outcome, klass, env_path=a.env_src, road=a.road,
                         max_tests=a.max_tests)
    print("\n".join(job_deck([("MAIN", src)], dat)))
    print(f"{v.outcome}: {klass}: {w.why if w else v.why}", file=__import__("sys").stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
