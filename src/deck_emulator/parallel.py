"""The one parallel map of the package: worker processes, a progress bar, clean stops."""

from __future__ import annotations

import os
import sys
from concurrent.futures import ProcessPoolExecutor, as_completed


def parallel_map(fn, items, *, jobs: int | None = None, desc: str = "", unit: str = "scene",
                 quiet: bool = False) -> list:
    """``[fn(x) for x in items]`` over ``jobs`` worker processes (default: all cores), results
    in input order; a tqdm bar on stderr when it is a terminal and not ``quiet``."""
    from tqdm import tqdm

    items = list(items)
    jobs = max(1, int(jobs or os.cpu_count() or 1))
    bar = tqdm(total=len(items), desc=desc, unit=unit, file=sys.stderr,
               disable=quiet or not sys.stderr.isatty())
    results: list = [None] * len(items)
    try:
        if jobs == 1 or len(items) <= 1:
            for i, x in enumerate(items):
                results[i] = fn(x)
                bar.update()
        else:
            with ProcessPoolExecutor(max_workers=min(jobs, len(items))) as pool:
                futures = {pool.submit(fn, x): i for i, x in enumerate(items)}
                try:
                    for fut in as_completed(futures):
                        results[futures[fut]] = fut.result()
                        bar.update()
                except BaseException:
                    pool.shutdown(wait=False, cancel_futures=True)
                    raise
    finally:
        bar.close()
    return results
