#!/usr/bin/env python3
"""Write docs/shaft_contact.md: Table 11's nine 20 mph columns on the core's legacy preset
without and with the shaft test (:func:`report.shaft_contact.write_page`).

    python scripts/make_shaft_contact.py
"""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the report's code: report/, beside the package

from report.shaft_contact import write_page


if __name__ == "__main__":
    page = write_page(ROOT / "docs" / "shaft_contact.md")
    print(f"wrote {page.relative_to(ROOT)}")
