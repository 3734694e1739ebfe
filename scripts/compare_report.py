#!/usr/bin/env python3
"""Set the report's Tables 11/12 (steel post) beside gfortran's printouts and the emulator's
runs: :func:`report.comparison.write_comparison`.

    python scripts/compare_report.py                 # writes docs/comparison.md
    python scripts/compare_report.py --out FILE      # write elsewhere
"""

import argparse
import sys
from pathlib import Path

from deck_emulator.files import OutputError
from deck_emulator.signals import run as run_guarded
ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the report's code: report/, beside the package

from report.comparison import write_comparison



def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(ROOT / "docs" / "comparison.md"))
    args = ap.parse_args(argv)
    seconds = write_comparison(args.out)
    print(f"wrote {args.out} in {seconds:.1f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    try:
        code = run_guarded(main)
    except OutputError as exc:  # one line, no traceback: the path and why
        print(f"compare_report: error: {exc}", file=sys.stderr)
        code = 2
    sys.exit(code)
