#!/usr/bin/env python3
"""Write docs/report/: the report's Figures 22-29 regenerated (figure_22.png ...
figure_29b.png), figures.md (each figure beside the report's words and numbers) and
verdicts.md (the statements of Sections 5.4 and 6.2-6.4, checked):
:func:`deck_emulator.present.plot.write_report_figures`.

    python scripts/make_report_figures.py [--out DIR]
"""

import argparse
import sys
import time
from pathlib import Path

from deck_emulator.errors import UsageError
from deck_emulator.files import OutputError
ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the report's code: report/, beside the package

from report.drawing import write_report_figures


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=ROOT / "docs" / "report", help="the folder")
    t0 = time.perf_counter()
    try:
        written = write_report_figures(p.parse_args().out)
    except (OutputError, UsageError) as exc:  # a folder that cannot be written: one line
        print(f"make_report_figures.py: {exc}", file=sys.stderr)
        sys.exit(2)
    for path in written:
        print(f"wrote {path}")
    print(f"took {time.perf_counter() - t0:.1f} s")
