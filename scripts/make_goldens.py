#!/usr/bin/env python3
"""Compile legacy/ with gfortran and run it on every deck: the only way golden/ is made.

    python scripts/make_goldens.py            # rewrite golden/
    python scripts/make_goldens.py --out DIR  # write elsewhere (the reproducibility test does)

What is written, and how: the checkout's ``oracle/``.
"""

import argparse
import shutil
import sys
from pathlib import Path

from deck_emulator.files import OutputError, check_output_dir
from deck_emulator.signals import run as run_guarded

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the oracle: oracle/, beside the package
from oracle import make_goldens  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "golden", help="where to write (default golden/)")
    args = ap.parse_args(argv)
    if shutil.which("gfortran") is None:
        print("make_goldens: gfortran is not installed (apt-get install -y gfortran)", file=sys.stderr)
        return 2
    check_output_dir(args.out)  # a missing or read-only folder fails before any compilation
    print("\n".join(make_goldens(args.out)))
    return 0


if __name__ == "__main__":
    try:
        code = run_guarded(main)
    except OutputError as exc:  # one line, no traceback: the path and why
        print(f"make_goldens: error: {exc}", file=sys.stderr)
        code = 2
    sys.exit(code)
