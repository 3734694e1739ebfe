"""What the emulator (legacy/emulator.py) reads from its own text, and the file that keeps it.

The label machine checks each block's assigned variables when the block ends, converts the
program's literals once per run, and starts each program unit with every variable it names at
zero: the names and literals come from the program text by patterns (:func:`tables`).  So that
a run need not read the text at every start, ``emulator_tables.py`` keeps them, with the
checksum of the text they were made from; :func:`read_tables` uses them only while the text
is unchanged.  ``python scripts/make_emulator_tables.py`` writes the file (:func:`module_text`).

This module does not import the emulator: it reads its file.
"""

from __future__ import annotations

import re
import zlib
from pathlib import Path

#: The emulator's file, beside this one.
EMULATOR = Path(__file__).with_name("emulator.py")
#: The file that keeps the tables.
TABLES_FILE = Path(__file__).with_name("emulator_tables.py")


def _assigned_names(source: str) -> dict[str, list[str]]:
    """Block method name -> the names it assigns (``v.NAME = ...``, ``self.v.NAME = ...``,
    ``v.A, v.B, v.C = ...``), read from the program text by a pattern
    (tests/legacy/test_emulator.py checks that an AST walk finds the same)."""
    block = re.compile(r"^    def (L\w+)\(self\):.*?(?=^    def |^\S)", re.M | re.S)
    target = re.compile(r"^\s+((?:self\.)?v\.\w+(?:\s*,\s*v\.\w+)*)\s*=(?!=)", re.M)
    out = {}
    for m in block.finditer(source):
        names = []
        for t in target.finditer(m.group(0)):
            for part in t.group(1).split(","):
                name = part.strip().rsplit(".", 1)[1]
                if name not in names:
                    names.append(name)
        if names:
            out[m.group(1)] = names
    return out


def tables(source: str) -> dict:
    """``ASSIGNED``: each block's assigned names; ``LITERALS``: every literal the program
    writes as K("...") or KSTEP("..."), with the ones ED binds; ``STEP_LITERALS``: those
    written as KSTEP("..."); ``VARIABLES``: every variable it names as v.NAME."""
    number = r'"([-+.\dE]*\d[-+.\dE]*)"'
    literals = tuple(sorted(set(re.findall(r"\bK(?:STEP)?\(" + number + r"\)", source))
                            | {"2.", "0.0"}))
    steps = tuple(sorted(set(re.findall(r"\bKSTEP\(" + number + r"\)", source))))
    variables = tuple(sorted(set(re.findall(r"\bv\.([A-Z][A-Z0-9]*)\b", source))))
    return {"ASSIGNED": _assigned_names(source), "LITERALS": literals, "STEP_LITERALS": steps,
            "VARIABLES": variables}


def read_tables(path, made) -> dict:
    """The tables of the program text at ``path``: ``made.TABLES`` (the module
    emulator_tables) when its checksum is that text's, else read from the text now."""

    try:
        with open(path, "rb") as f:
            text = f.read()
    except OSError:  # no source beside the bytecode: the tables made from it are all there is
        return made.TABLES
    if zlib.crc32(text) == made.SOURCE_CRC32 and len(text) == made.SOURCE_BYTES:
        return made.TABLES
    return tables(text.decode("utf-8"))


def module_text(path=EMULATOR) -> str:
    """The text of emulator_tables.py for the emulator's text as it is now."""
    import pprint

    text = Path(path).read_bytes()
    return ('"""What legacy/emulator.py reads from its own text (legacy/emulator_text.py), made from\n'
            'it by ``python scripts/make_emulator_tables.py``: do not edit.  The emulator uses it\n'
            'only while the checksum below is its text\'s, and reads its text again otherwise."""\n\n'
            f"SOURCE_BYTES = {len(text)}\n"
            f"SOURCE_CRC32 = {zlib.crc32(text)}\n"
            f"TABLES = {pprint.pformat(tables(text.decode('utf-8')), width=99, compact=True)}\n")
