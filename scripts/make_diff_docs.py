#!/usr/bin/env python3
"""Write docs/diff.md: `deck-emulator diff` on every deck, and the run times of both engines
(:func:`deck_emulator.studies.diff.diff_page`).

    python scripts/make_diff_docs.py
"""

import sys
from pathlib import Path

from deck_emulator.files import OutputError, check_output_file, write_file
from deck_emulator.signals import run as run_guarded
from deck_emulator.studies.diff import diff_page

PAGE = Path(__file__).resolve().parent.parent / "docs" / "diff.md"


def main() -> int:
    check_output_file(PAGE)  # before minutes of runs
    write_file(PAGE, diff_page())
    print("wrote docs/diff.md")
    return 0


if __name__ == "__main__":
    try:
        code = run_guarded(main)
    except OutputError as exc:  # one line, no traceback: the path and why
        print(f"make_diff_docs: error: {exc}", file=sys.stderr)
        code = 2
    sys.exit(code)
