"""The embedded scene runner's worker processes: :class:`WorkerPool`.

``jobs`` worker processes, each running one batch at a time, all forked from one server
process (multiprocessing's *forkserver*) that has imported, once, what every worker needs:
with ``core=True`` the compiled core's machine code (numba's, from its cache), so that the
workers share its pages with the server instead of each loading a copy of its own (what
that saves against the embedded Dask cluster it replaced: docs/scale.md).

What a batch meets, said once here:

* a worker that dies while it runs a batch (killed, out of memory) is replaced, and the
  batch runs again on the new one, up to
  :data:`~deck_emulator.vocabulary.defaults.WORKER_DEATHS_PER_BATCH` times; then it is answered by :class:`WorkerDied` (each of its
  scenes stored failed, with why), and the other batches go on;
* a batch whose callable cannot be sent or loaded in the worker (a function the worker
  cannot import) is answered by :class:`BatchError` saying so;
* workers ignore SIGINT: a Ctrl-C at a terminal goes to the whole process group, and the
  command that owns the pool handles it (it stores what completed and closes the pool);
* a worker whose command is gone (``kill -9``) ends as soon as it sees so (a thread that
  waits on its parent), not at the end of its batch.

The forkserver is one per process, made at the first pool and kept until the process ends
(Python's own design); what it imported then (``core`` or not) holds for every later pool of
the process, which only decides how much of the workers' memory is shared.  Each worker
takes the command's environment, import path and working folder as they are when it starts.
"""

from __future__ import annotations

import collections
import contextlib
import multiprocessing
import os
import pickle
import signal
import sys
import threading
from collections.abc import Callable, Iterable, Iterator
from multiprocessing.connection import wait

from deck_emulator import SPAWNED_WORKER_ENV
from deck_emulator.errors import RunFailed
from deck_emulator.vocabulary import defaults

__all__ = ["CORE_PRELOAD", "PRELOAD", "BatchError", "WorkerDied", "WorkerPool"]

#: what the server imports for every pool: SIGINT ignored, the runner's own module
PRELOAD = ("deck_emulator.studies.worker_preload",)
#: and for a pool of core scenes: the compiled core loaded (after the above)
CORE_PRELOAD = (*PRELOAD, "deck_emulator.studies.core_preload")


class WorkerDied(Exception):
    """A batch whose worker died every time it ran it (:class:`WorkerPool`)."""


class BatchError(Exception):
    """A batch that could not be handed to a worker, or whose answer could not come back."""


def _serve(conn, context: tuple[dict, list, str]) -> None:
    """In a worker: answer batches from ``conn`` (``(callable, args)`` pickled) with
    ``("done", callable(*args))`` or ``("error", why)`` until the command closes it."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    env, path, cwd = context
    os.environ.clear()
    os.environ.update(env)
    os.environ[SPAWNED_WORKER_ENV] = "1"
    sys.path[:] = path
    with contextlib.suppress(OSError):
        os.chdir(cwd)
    parent = multiprocessing.parent_process()
    if parent is not None:  # the command gone (kill -9): this worker goes too, at once
        threading.Thread(target=_end_with, args=(parent,), daemon=True).start()
    while True:
        try:
            data = conn.recv_bytes()
        except (EOFError, OSError):
            return
        try:
            fn, args = pickle.loads(data)
        except Exception as exc:  # noqa: BLE001 - a batch the worker cannot load
            answer = ("error", f"the worker cannot load the batch: {type(exc).__name__}: "
                               f"{exc}")
        else:
            try:
                answer = ("done", fn(*args))
            except Exception as exc:  # noqa: BLE001 - said to the command, the worker stays
                answer = ("error", f"{type(exc).__name__}: {exc}")
        try:
            data = pickle.dumps(answer, protocol=pickle.HIGHEST_PROTOCOL)
        except Exception as exc:  # noqa: BLE001 - an answer that cannot travel
            data = pickle.dumps(("error", f"the batch's answer cannot be sent: "
                                          f"{type(exc).__name__}: {exc}"))
        try:
            conn.send_bytes(data)
        except OSError:
            return


def _end_with(parent) -> None:
    parent.join()
    os._exit(1)


def _start_server() -> None:
    """Start the forkserver (once a process) with SIGINT ignored from its first instruction:
    a Ctrl-C at a terminal reaches the whole process group, and one that came while the
    server's interpreter started, before its preload ignores SIGINT, printed its
    ``KeyboardInterrupt`` traceback.  An ignored signal stays ignored across exec (the
    interpreter then installs no handler of its own); a started program's signal mask does
    not (Python's process start clears it), so the command ignores SIGINT for the moment of
    the server's fork and exec, the main thread holding it blocked meanwhile: a Ctrl-C then is
    kept pending and taken by the command's own handler as soon as it is restored -- unless
    another thread of the command (a progress bar's monitor) takes it in those milliseconds,
    where it is ignored: the one moment a Ctrl-C can be lost, against the tenths of a second
    in which it printed the server's traceback."""
    import tempfile
    from multiprocessing import forkserver

    from deck_emulator.files import own_temp_folder

    # multiprocessing's temporary folder (pymp-*, made once a process, the server's socket
    # in it) in the command's own, which a SIGKILL does not leave behind for ever
    # (files.own_temp_folder); tempfile's default is the system's again after it
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


class _Worker:
    def __init__(self, process, conn):
        self.process, self.conn = process, conn
        self.batch = None  # (key, payload) it runs, or None when idle


class WorkerPool:
    """``with WorkerPool(jobs, core=True) as pool: for key, answer in pool.run(batches)``:
    each batch ``(key, (callable, args))`` is run once by a worker, ``callable(*args)``; its
    answer is what the callable returned, or a :class:`WorkerDied` / :class:`BatchError`.
    Batches start in the order given; answers come as batches end."""

    def __init__(self, jobs: int, *, core: bool = False):
        self.jobs = max(1, int(jobs))
        self.context = multiprocessing.get_context("forkserver")
        self.context.set_forkserver_preload(list(CORE_PRELOAD if core else PRELOAD))
        self.workers: list[_Worker] = []

    def __enter__(self) -> WorkerPool:
        try:
            for _ in range(self.jobs):
                self._start()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _start(self) -> _Worker:
        """A new worker (OSError, or the server's own error, when none can start)."""
        _start_server()
        mine, theirs = self.context.Pipe()
        context = (dict(os.environ), list(sys.path), os.getcwd())
        process = self.context.Process(target=_serve, args=(theirs, context), daemon=True,
                                       name="deck-emulator-worker")
        try:
            process.start()
        finally:
            theirs.close()
        worker = _Worker(process, mine)
        self.workers.append(worker)
        return worker

    def close(self) -> None:
        """End every worker: its pipe closed (an idle worker ends at once), then SIGTERM for
        one still in a batch after a short wait, then SIGKILL."""
        for w in self.workers:
            with contextlib.suppress(OSError):
                w.conn.close()
        for w in self.workers:
            w.process.join(timeout=0.2 if w.batch is None else 0)
            if w.process.is_alive():
                w.process.terminate()
                w.process.join(timeout=2)
            if w.process.is_alive():
                w.process.kill()
                w.process.join()
        self.workers.clear()

    def run(self, batches: Iterable[tuple[object, tuple[Callable, tuple]]]
            ) -> Iterator[tuple[object, object]]:
        todo = collections.deque(batches)
        deaths: collections.Counter = collections.Counter()
        while todo or any(w.batch is not None for w in self.workers):
            for w in self.workers:
                if w.batch is None and todo:
                    key, payload = todo.popleft()
                    try:
                        data = pickle.dumps(payload, protocol=pickle.HIGHEST_PROTOCOL)
                    except Exception as exc:  # noqa: BLE001 - e.g. a lambda: said, not run
                        yield key, BatchError(f"the batch cannot be sent to a worker: "
                                              f"{type(exc).__name__}: {exc}")
                        continue
                    try:
                        w.conn.send_bytes(data)
                    except OSError:  # gone before it was given anything: not the batch's
                        todo.appendleft((key, payload))
                        self._replace(w)
                        break
                    w.batch = (key, payload)
            busy = [w for w in self.workers if w.batch is not None]
            if not busy:
                continue
            ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy]))
            for w in busy:
                if w.conn not in ready and w.process.sentinel not in ready:
                    continue
                key, payload = w.batch
                try:
                    kind, answer = pickle.loads(w.conn.recv_bytes())
                except (EOFError, OSError):  # died in the batch
                    deaths[key] += 1
                    how = self._replace(w)
                    if deaths[key] > defaults.WORKER_DEATHS_PER_BATCH:
                        yield key, WorkerDied(
                            f"WorkerDied: the worker running it died {deaths[key]} times "
                            f"(last {how}); not run again")
                    else:
                        todo.appendleft((key, payload))
                    continue
                w.batch = None
                yield key, (answer if kind == "done" else BatchError(answer))

    def _replace(self, worker: _Worker) -> str:
        """Take a dead worker out and start another in its place; how it ended."""
        worker.batch = None
        with contextlib.suppress(OSError):
            worker.conn.close()
        worker.process.join(timeout=5)
        code = worker.process.exitcode
        self.workers.remove(worker)
        try:
            self._start()  # (its batch, or another one's that dies next, needs it)
        except OSError as exc:  # the machine's limits: go on with the workers left, if any
            if not self.workers:
                raise RunFailed(f"no worker process could be started again ({exc}): the "
                                "scenes completed are stored; --resume runs the rest") from None
        if code is not None and code < 0:
            return f"killed by {signal.Signals(-code).name}"
        return f"exit status {code}"
