#!/usr/bin/env python3
"""Rewrite the vocabulary table of docs/json.md from the registry of quantities
(:func:`deck_emulator.engine.quantities.markdown_table`; a test keeps the two equal).

    python scripts/make_json_doc.py
"""

import re
from pathlib import Path

from deck_emulator.engine.quantities import markdown_table
from deck_emulator.files import write_file

page = Path(__file__).resolve().parent.parent / "docs" / "json.md"
table = re.compile(r"^\| name \| label in the tables \|.*?(?=\n\n)", re.S | re.M)
write_file(page, table.sub(lambda _: markdown_table(), page.read_text(), count=1))
