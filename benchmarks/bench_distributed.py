#!/usr/bin/env python3
"""Scenes per second on the embedded runner, with 1 and 2 workers, for both engines.

    python benchmarks/bench_distributed.py [--scenes 10000] [--emulator-scenes N] [--workers 1,2]

Every scene is the steel post at 40 mph (``steel40``) with its crush spring CK changed (so no two
scenes are the same), run through the sensitivity study's batch function (a worker's task is a
batch of scenes, the core's through ``CoreEngine.run_batch``) -- the same path as
``deck-emulator sensitivity`` -- into a fresh store. The time is the whole of
``run_scenes``: the workers' start, the batches, the scenes, the writing of the store.

Parallel efficiency = rate with k workers / (k * rate with 1 worker).

When fewer scenes are run than 10^4 (``--scenes``), the time for 10^4 is also printed,
extrapolated from the measured rate and labelled so.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

from deck_emulator.studies.distributed import run_scenes
from deck_emulator.studies.sensitivity import scene_tasks
from deck_emulator.vocabulary.units import S_PER_HOUR

TARGET = 10_000


def tasks(engine: str, n: int) -> list[dict]:
    # CK from 23100 to 42900 lb/ft in n distinct steps (six significant digits)
    return [
        {"deck": "steel40", "engine": engine, "preset": "legacy",
         "inputs": {"CK": float(f"{23100 + 19800 * k / max(n - 1, 1):.6g}")}}
        for k in range(n)
    ]


def measure(engine: str, n: int, workers: int) -> tuple[float, int]:
    with tempfile.TemporaryDirectory() as d:
        started = time.perf_counter()
        store = run_scenes(tasks(engine, n), scene_tasks, store_dir=d, jobs=workers,
                           progress=False, desc=engine, many=True)
        wall = time.perf_counter() - started
        rows = store.rows()
        failed = sum(r["status"] != "ok" for r in rows)
        assert len(rows) == n, (len(rows), n)
    return wall, failed


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", type=int, default=TARGET, help="core scenes (default 10^4)")
    ap.add_argument("--emulator-scenes", type=int, default=None,
                    help="emulator scenes (default: as --scenes)")
    ap.add_argument("--workers", default="1,2", help="worker counts, e.g. 1,2")
    args = ap.parse_args()
    counts = [int(x) for x in args.workers.split(",")]
    plan = [("core", args.scenes), ("emulator", args.emulator_scenes or args.scenes)]
    print(f"host: {os.cpu_count()} cores; load average at start "
          f"{os.getloadavg()[0]:.2f} (a shared machine: timings are measured under load)")
    print()
    print("| engine | workers | scenes | wall s | scenes/s | efficiency | failed | "
          "10^4 scenes (h) |")
    print("|---|---|---|---|---|---|---|---|")
    for engine, n in plan:
        base = None
        for w in counts:
            wall, failed = measure(engine, n, w)
            rate = n / wall
            if base is None:
                base = rate / w
            eff = rate / (w * base)
            ext = TARGET / rate / S_PER_HOUR
            label = f"{ext:.2f}" if n >= TARGET else f"{ext:.2f} (extrapolated from {n})"
            print(f"| {engine} | {w} | {n} | {wall:.1f} | {rate:.2f} | {eff:.2f} | {failed} | "
                  f"{label} |", flush=True)
    print()
    print(f"load average at end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
