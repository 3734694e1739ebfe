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


def progress_bar(total: int | None = None, *, desc: str = "", unit: str = "it",
                 quiet: bool = False, **options):
    """The package's one progress display: a tqdm bar on stderr, shown only when stderr is a
    terminal and not ``quiet`` (``total=None``: a counter)."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, leave=False,
                disable=quiet or not sys.stderr.isatty(), **options)


class busy:
    """``with busy("emulator"): work()`` -- for one long call that reports nothing itself:
    the same bar, counting seconds of wall time from a background thread (nothing is added
    to the work's own loop)."""

    def __init__(self, desc: str, *, quiet: bool = False, every_s: float = 0.5, status=None):
        """``status``: a callable giving a short text to show (e.g. the emulator's step)."""
        self.desc, self.quiet, self.every_s, self.status = desc, quiet, every_s, status

    def __enter__(self):
        import threading
        import time

        self._bar = None
        self._stop = threading.Event()
        if self.quiet or not sys.stderr.isatty():
            return self
        self._bar = progress_bar(desc=self.desc, unit="s", quiet=self.quiet,
                                 bar_format="{desc}: {elapsed}{postfix}")
        started = time.monotonic()

        def tick():
            while not self._stop.wait(self.every_s):
                self._bar.n = int(time.monotonic() - started)
                if self.status is not None:
                    try:
                        self._bar.set_postfix_str(self.status(), refresh=False)
                    except Exception:  # a status is a courtesy: never stop the work for it
                        pass
                self._bar.refresh()

        self._thread = threading.Thread(target=tick, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        if self._bar is not None:
            self._thread.join()
            self._bar.close()
        return False
