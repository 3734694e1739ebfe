#!/usr/bin/env python3
"""Line coverage of legacy/luminaire.f (MAIN and SUBROUTINE ED) by the differential corpus.

    python benchmarks/oracle_coverage.py [--decks 500] [--seed 1] [--extra tests/decks] [--timeout 0.5]

Compiles the listing as scripts/make_goldens.py does (REAL*8; its functions, with ``--coverage``
added to the flags), as printed and with the ``ed-direction`` erratum, runs every deck of the
corpus (the checkout's oracle/; the erratum where ALPHA != 0) and the decks in ``--extra``,
and reads the counts with ``gcov``. The erratum changes two statements and no line numbers, so
the two builds' executed lines are merged by line number.

A run that is cut off by the clock or traps does not write its counts (the counts are written
when the program ends normally): such runs add nothing here. Prints the executable lines of
MAIN and ED, how many ran, and those that did not.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "src"), str(ROOT)]  # the package and oracle/ beside it



def gcov_lines(build: Path, exe: Path, src: Path) -> dict[int, tuple[bool, str]]:
    """line number -> (executed?, text) for every executable line gcov reports (the notes
    and counts of a program linked in one step are named after it: <exe>-<source>.gcno)."""
    subprocess.run(["gcov", "-o", str(build), f"{exe.name}-{src.stem}.gcda"], cwd=build,
                   check=True, capture_output=True)
    out = {}
    for line in (build / (src.name + ".gcov")).read_text().splitlines():
        m = re.match(r"\s*([^:]+):\s*(\d+):(.*)", line)
        if not m or int(m.group(2)) == 0:
            continue
        count, n, text = m.group(1).strip(), int(m.group(2)), m.group(3)
        if count == "-":
            continue
        out[n] = (count not in ("#####", "====="), text)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--decks", type=int, default=500)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--extra", type=Path, action="append", default=[],
                    help="a directory of hand-made decks (*.dat) to run as well")
    ap.add_argument("--timeout", type=float, default=0.5)
    args = ap.parse_args(argv)
    if shutil.which("gfortran") is None or shutil.which("gcov") is None:
        print("gfortran and gcov are needed", file=sys.stderr)
        return 2
    from deck_emulator.legacy.deck import read_deck

    import oracle as mg

    mg.COMMON_FLAGS = [*mg.COMMON_FLAGS, "--coverage"]
    mg.TIMEOUT_S = args.timeout
    decks = mg.corpus(args.decks, args.seed)
    for d in args.extra:
        decks += [read_deck(p) for p in sorted(d.glob("*.dat"))]
    merged: dict[int, tuple[bool, str]] = {}
    endings: dict[str, int] = {}
    with tempfile.TemporaryDirectory(prefix="coverage-") as tmp:
        tmp = Path(tmp)
        for erratum in (None, "ed-direction"):
            build = tmp / (erratum or "printed")
            build.mkdir()
            exe = mg.compile_program(build, "r8", erratum)
            src = build / f"src-{erratum or 'printed'}" / "legacy" / mg.SOURCE
            deck_file = build / "deck.dat"
            for deck in decks:
                if (deck["ALPHA"] != 0) != (erratum is not None):
                    continue
                deck_file.write_text(deck.to_text())
                _out, _err, ending = mg.run_program(exe, deck_file)
                endings[ending] = endings.get(ending, 0) + 1
            for n, (ran, text) in gcov_lines(build, exe, src).items():
                merged[n] = (merged.get(n, (False, text))[0] or ran, text)
    source = (ROOT / "legacy" / mg.SOURCE).read_text().splitlines()
    ed_start = next(i for i, t in enumerate(source, start=1) if re.match(r"\s+SUBROUTINE ED", t))
    print(f"{len(decks)} decks (corpus seed {args.seed}: {args.decks}; hand-made: "
          f"{len(decks) - args.decks}); endings {endings}")
    for unit, lines in (("MAIN", [n for n in merged if n < ed_start]),
                        ("ED", [n for n in merged if n >= ed_start])):
        ran = [n for n in lines if merged[n][0]]
        print(f"{unit}: {len(ran)} of {len(lines)} executable lines ran "
              f"({100.0 * len(ran) / max(1, len(lines)):.1f} %)")
        for n in sorted(set(lines) - set(ran)):
            print(f"  not run: line {n}: {merged[n][1].strip()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
