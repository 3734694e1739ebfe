#!/usr/bin/env python3
"""How long `compare` takes on two printouts of steel40, median of N runs.

    python benchmarks/bench_compare.py [--repeat 7]

Two printouts of the golden steel40 (golden/steel40.r8.txt, 4,769 lines each): B is the
golden with its page marks dropped, one value line lost and one value changed, so the records
must be lined up again rather than read side by side.  Prints the median wall time of the
comparison in process (both read into records and lined up) and of the whole command as a
process (interpreter start, imports, reading, comparing, printing).  Goal: under a second
each, on a quiet 2-core machine.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
GOLDEN = ROOT / "golden" / "steel40.r8.txt"


def changed_copy(folder: Path) -> Path:
    lines = GOLDEN.read_text().split("\n")
    values = [i for i, line in enumerate(lines) if "THE VALUE OF" in line]
    lines[values[len(values) // 3]] = lines[values[len(values) // 3]].replace("1", "2")
    del lines[values[2 * len(values) // 3]]
    b = folder / "b.txt"
    b.write_text("\n".join(line for line in lines if line != "1"))
    return b


def median(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        fn()
        times.append(time.perf_counter() - started)
    return statistics.median(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="runs of each (default 7)")
    args = parser.parse_args()
    from deck_emulator.legacy.compare import compare

    with tempfile.TemporaryDirectory() as tmp:
        b = changed_copy(Path(tmp))
        a_text, b_text = GOLDEN.read_text(), b.read_text()
        found = compare(a_text, b_text)
        in_process = median(lambda: compare(a_text, b_text), args.repeat)
        argv = [sys.executable, "-m", "deck_emulator", "compare", str(GOLDEN), str(b)]
        whole = median(lambda: subprocess.run(argv, stdout=subprocess.DEVNULL, check=False),
                       args.repeat)
    print(f"findings: {len(found.differences)} difference(s), {len(found.damaged)} damaged, "
          f"{len(found.missing)} missing")
    print(f"{'compare, in process':<32}{in_process:>8.3f} s (median of {args.repeat})")
    print(f"{'deck-emulator compare, process':<32}{whole:>8.3f} s (median of {args.repeat})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
