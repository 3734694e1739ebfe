#!/usr/bin/env python3
"""Write docs/report_full.md (all 18 columns of Tables 11 and 12, Tables 9 and 10) and
docs/crash_test_fig18.png: :func:`deck_emulator.studies.report_page.write_page`.

    python scripts/make_report_full.py
"""

from pathlib import Path

from deck_emulator.studies.report_page import write_page

ROOT = Path(__file__).resolve().parent.parent

if __name__ == "__main__":
    page = ROOT / "docs" / "report_full.md"
    fig = write_page(page)
    print(f"wrote {page.relative_to(ROOT)} and {fig.relative_to(ROOT)}")
