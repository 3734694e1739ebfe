#!/usr/bin/env python3
"""Write docs/report_full.md (all 18 columns of Tables 11 and 12, Tables 9 and 10) and
docs/crash_test_fig18.png: :func:`report.page.write_page`.

    python scripts/make_report_full.py
"""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the report's code: report/, beside the package

from report.page import write_page


if __name__ == "__main__":
    page = ROOT / "docs" / "report_full.md"
    fig = write_page(page)
    print(f"wrote {page.relative_to(ROOT)} and {fig.relative_to(ROOT)}")
