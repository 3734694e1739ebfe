"""The embedded runner: :class:`LocalPool`, a ``ProcessPoolExecutor`` whose workers are forked
from one server (multiprocessing's *forkserver*) that imported :data:`PRELOAD` (for core scenes
:data:`CORE_PRELOAD`: the compiled core) once, so that they share those pages (docs/scale.md),
plus what the standard library lacks:

* a worker that dies breaks the executor (``BrokenProcessPool`` for every batch it holds): the
  batches go to a new one.  Workers take batches in the order given, so the ``jobs`` oldest
  unfinished ones were those running: each runs again *alone*, and a batch whose worker dies
  alone more than ``WORKER_DEATHS_PER_BATCH`` times is answered :class:`WorkerDied`;
* a worker ends as soon as its command is gone (``kill -9``), and :meth:`LocalPool.shutdown`
  ends busy workers (SIGTERM, then SIGKILL) instead of waiting for their batches.

Workers ignore SIGINT (the command handles a terminal's Ctrl-C) and take the command's
environment, import path and folder as they are when the pool starts.
"""

from __future__ import annotations

import collections
import concurrent.futures as cf
import contextlib
import functools
import multiprocessing
import os
import signal
import sys
import threading
from concurrent.futures.process import BrokenProcessPool

from deck_emulator import SPAWNED_WORKER_ENV
from deck_emulator.errors import RunFailed
from deck_emulator.vocabulary import defaults

__all__ = ["CORE_PRELOAD", "PRELOAD", "LocalPool", "WorkerDied"]

#: what the server imports for every pool: SIGINT ignored, the runner's own module
PRELOAD = ("deck_emulator.studies.worker_preload",)
#: and for a pool of core scenes: the compiled core loaded (after the above)
CORE_PRELOAD = (*PRELOAD, "deck_emulator.studies.core_preload")


class WorkerDied(Exception):
    """A batch whose worker died every time it ran it alone."""


def _worker_start(env: dict, path: list, cwd: str) -> None:
    """A worker's initializer: the command's context, SIGINT ignored, an end with its
    command."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    os.environ.clear()
    os.environ.update(env)
    os.environ[SPAWNED_WORKER_ENV] = "1"
    sys.path[:] = path
    with contextlib.suppress(OSError):
        os.chdir(cwd)
    parent = multiprocessing.parent_process()
    if parent is not None:
        threading.Thread(target=_end_with, args=(parent,), daemon=True).start()


def _end_with(parent) -> None:
    parent.join()
    os._exit(1)


def _start_server() -> None:
    """Start the forkserver (once a process), its ``pymp-*`` folder in the command's own
    (``files.own_temp_folder``), SIGINT ignored and blocked meanwhile (an ignored signal stays
    ignored across exec): a Ctrl-C while its interpreter starts waits for the command's
    handler instead of printing the server's traceback."""
    import tempfile
    from multiprocessing import forkserver

    from deck_emulator.files import own_temp_folder

    default, tempfile.tempdir = tempfile.tempdir, own_temp_folder()
    try:
        if threading.current_thread() is not threading.main_thread():
            forkserver.ensure_running()
            return
        blocked = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            handler = signal.signal(signal.SIGINT, signal.SIG_IGN)
            try:
                forkserver.ensure_running()
            finally:
                signal.signal(signal.SIGINT, handler)
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, blocked)
    finally:
        tempfile.tempdir = default


class LocalPool(cf.Executor):
    """``jobs`` forkserver workers (``core``: sharing the compiled core), the
    ``concurrent.futures`` interface; :meth:`submit`'s futures answer a batch whose worker
    died too often with :class:`WorkerDied` (the module docstring)."""

    def __init__(self, jobs: int, *, core: bool = False):
        self.jobs = max(1, int(jobs))
        self._context = multiprocessing.get_context("forkserver")
        self._context.set_forkserver_preload(list(CORE_PRELOAD if core else PRELOAD))
        self._others = set(multiprocessing.active_children())  # not this pool's
        self._lock = threading.RLock()
        self._waiting: collections.deque = collections.deque()  # (outer, fn, args)
        self._suspects: collections.deque = collections.deque()  # to run alone
        self._live: dict = {}  # the current pool's future -> (outer, fn, args)
        self._deaths: collections.Counter = collections.Counter()
        self._alone: list | None = None  # the pool's workers while a batch runs alone
        self._closed = False
        self._broken: list = []
        self._pool = self._new_pool()
        for _ in range(self.jobs):  # the workers start now: the machine's limits show here
            self._pool.submit(int)

    def _new_pool(self) -> cf.ProcessPoolExecutor:
        _start_server()
        self._before = set(multiprocessing.active_children())  # not the new pool's
        return cf.ProcessPoolExecutor(
            self.jobs, mp_context=self._context, initializer=_worker_start,
            initargs=(dict(os.environ), list(sys.path), os.getcwd()))

    def submit(self, fn, /, *args, **kwargs):
        outer: cf.Future = cf.Future()
        with self._lock:
            self._waiting.append((outer, functools.partial(fn, **kwargs) if kwargs else fn,
                                  args))
            self._feed()
        return outer

    def _feed(self) -> None:
        """Hand batches to the pool: all that wait, or one suspect at a time, alone."""
        while not self._closed and (self._waiting or self._suspects):
            alone = bool(self._suspects)
            if alone and self._live:
                return
            queue = self._suspects if alone else self._waiting
            item = queue.popleft()
            try:
                self._pool = self._pool or self._new_pool()
                inner = self._pool.submit(item[1], *item[2])
            except BrokenProcessPool:  # broke before its batches' callbacks came
                queue.appendleft(item)
                if self._live:
                    return  # they will hand everything to a new pool
                self._pool = None
                continue
            except OSError as exc:  # no worker can start again: the machine's limits
                self._fail(RunFailed(f"no worker process could be started again ({exc}): "
                                     "the scenes completed are stored; --resume runs the "
                                     "rest"), item)
                return
            self._alone = ([p for p in multiprocessing.active_children()
                            if p not in self._before] if alone else None)
            self._live[inner] = item
            inner.add_done_callback(self._done)
            if alone:
                return

    def _done(self, inner: cf.Future) -> None:
        with self._lock:
            item = self._live.get(inner)
            if item is None or self._closed:
                return
            if not isinstance(inner.exception(), BrokenProcessPool):
                del self._live[inner]
                _copy(inner, item[0])
            else:  # the pool broke: every batch it held goes to a new one
                broken = list(self._live.values())
                self._live.clear()
                self._pool.shutdown(wait=False)  # (waited for at the end: nothing left)
                self._broken.append(self._pool)
                self._pool = None  # a new one, at the next batch
                if self._alone is not None:  # it ran alone: its own death
                    self._deaths[item[0]] += 1
                    died = self._deaths[item[0]]
                    if died > defaults.WORKER_DEATHS_PER_BATCH:
                        how = _how(next((p.exitcode for p in self._alone if p.exitcode), None))
                        item[0].set_exception(WorkerDied(
                            f"WorkerDied: the worker running it died {died} times (last "
                            f"{how}); not run again"))
                    else:
                        self._suspects.appendleft(item)
                else:
                    self._suspects.extend(broken[: self.jobs])
                    self._waiting.extendleft(reversed(broken[self.jobs:]))
            self._alone = None
            self._feed()

    def _fail(self, exc: Exception, *items) -> None:
        for item in (*items, *self._waiting, *self._suspects, *self._live.values()):
            if not item[0].done():
                item[0].set_exception(exc)
        self._waiting.clear()
        self._suspects.clear()
        self._live.clear()

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = True) -> None:
        """End the pool now: batches not started are cancelled, busy workers ended (SIGTERM,
        then SIGKILL); idle ones end at once."""
        with self._lock:
            self._closed = True
            left = [item[0] for item in (*self._waiting, *self._suspects,
                                         *self._live.values())]
            busy = bool(self._live)
            self._waiting.clear()
            self._suspects.clear()
            self._live.clear()
        for outer in left:
            outer.cancel()
        mine = [p for p in multiprocessing.active_children() if p not in self._others]
        if busy:
            for p in mine:
                p.terminate()
        for pool in [*self._broken, self._pool]:
            if pool is not None:
                pool.shutdown(wait=True, cancel_futures=True)
        for p in mine:
            p.join(timeout=2)
            if p.is_alive():
                p.kill()
                p.join()


def _copy(inner: cf.Future, outer: cf.Future) -> None:
    if not outer.cancelled():
        exc = inner.exception()
        outer.set_exception(exc) if exc is not None else outer.set_result(inner.result())


def _how(code) -> str:
    return (f"killed by {signal.Signals(-code).name}" if code and code < 0
            else f"exit status {code}")
