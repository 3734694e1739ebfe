"""The package's one process-pool map: :func:`parallel_map`.

* Results in input order; ``jobs <= 1`` (or one item) runs in this process.
* Progress (tqdm) on stderr only when stderr is a terminal and not ``quiet``.
* An exception in a worker, KeyboardInterrupt (SIGINT) or :class:`deck_emulator.signals.Terminated`
  (SIGTERM) in the parent: the queued items are cancelled and the workers are killed and
  reaped before the exception goes on, so no worker outlives the map.
* Workers ignore SIGINT (a Ctrl-C reaches the whole process group; the parent decides) and die
  with their parent: on Linux by ``prctl(PR_SET_PDEATHSIG, SIGKILL)``; everywhere by a thread
  that polls ``os.getppid()`` twice a second and ends the worker when its parent has gone (a
  SIGKILL of the main process leaves no orphan computing for minutes).
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import ctypes
import ctypes.util
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable

__all__ = ["parallel_map", "progress_bar", "busy", "POLL_S"]

POLL_S = 0.5  # how often a worker looks for its parent
_PR_SET_PDEATHSIG = 1
_USE_PDEATHSIG = True  # False: only the polling thread (the tests check each way alone)


def _die_with_parent(parent: int) -> None:
    """Worker initializer: ignore SIGINT, default SIGTERM, and end when ``parent`` ends."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if hasattr(signal, "SIGHUP"):
        signal.signal(signal.SIGHUP, signal.SIG_DFL)
    if _USE_PDEATHSIG and sys.platform.startswith("linux"):
        with contextlib.suppress(Exception):
            libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    if os.getppid() != parent:  # the parent died before prctl: nothing to work for
        os._exit(1)

    def watch():
        while True:
            time.sleep(POLL_S)
            if os.getppid() != parent:
                os._exit(1)

    threading.Thread(target=watch, name="parent-watch", daemon=True).start()


def _stop(pool: concurrent.futures.ProcessPoolExecutor) -> None:
    """Cancel what is queued, kill the workers and reap them."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:
        with contextlib.suppress(Exception):
            p.kill()
    with contextlib.suppress(Exception):
        pool.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        with contextlib.suppress(Exception):
            p.join(timeout=5)


def _on_terminal() -> bool:
    """Whether stderr is a terminal (False for a closed or replaced stderr)."""
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def parallel_map(fn: Callable, items: Iterable, *, jobs: int | None, desc: str,
                 unit: str = "scene", quiet: bool = False) -> list:
    """``[fn(x) for x in items]`` over ``jobs`` worker processes (default ``os.cpu_count()``),
    in input order.  ``fn`` and the items must be picklable.  See the module's notes for
    progress, interruption and orphans."""
    items = list(items)
    jobs = max(1, int(jobs or os.cpu_count() or 1))
    bar = progress_bar(len(items), desc=desc, unit=unit, quiet=quiet or not items,
                       dynamic_ncols=True)
    try:
        if jobs == 1 or len(items) <= 1:
            out = []
            for x in items:
                out.append(fn(x))
                bar.update(1)
            return out
        results: list = [None] * len(items)
        pool = concurrent.futures.ProcessPoolExecutor(
            max_workers=min(jobs, len(items)), initializer=_die_with_parent,
            initargs=(os.getpid(),))
        try:
            futures = {pool.submit(fn, x): i for i, x in enumerate(items)}
            for fut in concurrent.futures.as_completed(futures):
                results[futures[fut]] = fut.result()
                bar.update(1)
        except BaseException:
            _stop(pool)
            raise
        pool.shutdown(wait=True)
        return results
    finally:
        bar.close()


def progress_bar(total: int | None = None, *, desc: str = "", unit: str = "it",
                 quiet: bool = False, **options):
    """The package's one progress display: a tqdm bar on stderr, shown only when stderr is a
    terminal and not ``quiet`` (``total=None``: a counter)."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, leave=False,
                disable=quiet or not _on_terminal(), **options)


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
        if self.quiet or not _on_terminal():
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
