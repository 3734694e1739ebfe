"""``python -m report``: every page of the report's regeneration, in turn (each one's own
script in ``scripts/`` with its options builds one): docs/comparison.md, docs/report_full.md,
docs/report/ (figures and verdicts), docs/shaft_contact.md."""

from __future__ import annotations

import runpy
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: the pages' scripts, in the order they are built
SCRIPTS = ("compare_report.py", "make_report_full.py", "make_report_figures.py",
           "make_shaft_contact.py")

if __name__ == "__main__":
    for script in SCRIPTS:
        started = time.perf_counter()
        print(f"== python scripts/{script}", flush=True)
        sys.argv = [script]
        try:  # a script ends with sys.exit: the next page is still built, a failure stops
            runpy.run_path(str(ROOT / "scripts" / script), run_name="__main__")
        except SystemExit as done:
            if done.code not in (None, 0):
                raise
        print(f"   {time.perf_counter() - started:.0f} s", flush=True)
