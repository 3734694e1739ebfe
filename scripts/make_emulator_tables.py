#!/usr/bin/env python3
"""Write src/deck_emulator/legacy/emulator_tables.py: what the emulator reads from its own text
(each block's assigned names, its literals, its variables), so that a run need not read it at
every start.

    python scripts/make_emulator_tables.py

Run it after changing legacy/emulator.py (tests/cli/test_start.py fails until then; the emulator
reads its text itself meanwhile).  What is written: deck_emulator.legacy.emulator_text.
"""

import sys

from deck_emulator.files import OutputError, write_file
from deck_emulator.legacy.emulator_text import TABLES_FILE, module_text

if __name__ == "__main__":
    try:
        write_file(TABLES_FILE, module_text())
    except OutputError as exc:
        print(f"make_emulator_tables: error: {exc}", file=sys.stderr)
        sys.exit(2)
    print(TABLES_FILE)
