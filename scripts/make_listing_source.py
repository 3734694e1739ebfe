#!/usr/bin/env python3
"""Write src/deck_emulator/legacy/fortran/listing_made.py: the listing's program (legacy/
luminaire.f) as the FORTRAN front end makes it for binary64, one FORTRAN statement a line, so
that a run of the listing needs neither parse nor compile at its start (its bytecode is cached
as a module's) and the source reads side by side with the cards.

    python scripts/make_listing_source.py

Run it after changing legacy/luminaire.f or legacy/fortran/ (parse.py, run.py): until then the
file's first line (the cards' SHA-256 and the front end's CRC-32) no longer matches, the front
end makes the source itself at each start (~30 ms), and tests/legacy/test_fortran.py fails.
"""

import sys

from deck_emulator.files import OutputError, write_file
from deck_emulator.legacy.fortran.run import MADE_LISTING, listing_program

if __name__ == "__main__":
    try:
        write_file(MADE_LISTING, listing_program().python(native=True, checking=False))
    except OutputError as exc:
        print(f"make_listing_source: error: {exc}", file=sys.stderr)
        sys.exit(2)
    print(MADE_LISTING)
