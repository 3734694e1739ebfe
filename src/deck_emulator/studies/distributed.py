"""Scenes on worker processes, stored as they finish: :func:`run_scenes`.

A *task* is a dict of plain values saying everything one scene needs; ``fn(task) -> dict``
runs it on a worker (``many=True``: ``fn(tasks) -> [dict or exception]``, a batch at a time).
Tasks go in batches (:func:`batch_size`) to a ``concurrent.futures`` executor:
:class:`~deck_emulator.studies.local_pool.LocalPool` on this machine (``jobs`` workers sharing
the preloaded core), or Dask's executor of an existing cluster (``scheduler=``: its scheduling
and its retries).  One loop, :func:`run_batches`, serves both and stores each row in the
:mod:`~deck_emulator.studies.store` as its batch completes.  A scene whose ``fn`` raised, or
whose worker died too often, is stored ``failed`` and not run again on resume; one stopped
by a bound of the machine (:class:`Stopped`) is stored ``stopped`` and runs again.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import functools
import gc
import itertools
import json
import math
import os
import resource
import sys
import tempfile
import time
from collections.abc import Callable

from deck_emulator import SPAWNED_WORKER_ENV
from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.parallel import progress_bar
from deck_emulator.studies.cluster import Scheduler, dask_executor
from deck_emulator.studies.local_pool import LocalPool, WorkerDied
from deck_emulator.studies.store import (
    LimitError, SceneStore, StoreError, _cannot_load, _canonical, _check_study, _id_of,
    _missing_folders, _remove_if_unused, _row_of, scene_id, store_lock)
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.defaults import WORKER_WAIT_S

__all__ = ["BATCH_TASK_MAX", "MAX_SCENES", "SceneLimitError", "batch_size", "run_batches",
           "run_longest_first", "run_scenes", "temporary_store"]

#: Most rows one store file holds.
BATCH_MAX = 256
#: Most scenes one call of :func:`run_scenes` takes.
MAX_SCENES = 1_000_000
#: Most scenes in one batch: a worker holds one batch's solver records (docs/scale.md).
BATCH_TASK_MAX = 16
#: the progress bar of tasks of unequal cost run costliest first: no time left (it said 5 min
#: for a 55 s study)
ETA_LESS = "{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}{postfix}]"


class SceneLimitError(UsageError, ValueError):
    """More scenes than a call takes (``max_scenes``)."""


# ======================================================================= on the worker


def _call(fn: Callable[[dict], dict], task: dict) -> dict:
    started = time.perf_counter()
    try:
        out = fn(task)
    except Exception as exc:  # noqa: BLE001 - a scene that fails is a row
        out = exc
    return _row_of(out, time.perf_counter() - started)


def _call_many(fn: Callable, tasks: list[dict], many: bool = False) -> list[dict]:
    """A batch of tasks, one row each.  ``many``: ``fn`` takes the list; a batch it cannot
    take whole (it raised, or answered the wrong count) runs again a task at a time, so that
    one bad task fails alone; ``run_s`` is then the batch's time shared evenly."""
    try:
        if not many:
            return [_call(fn, t) for t in tasks]
        started = time.perf_counter()
        try:
            outs = list(fn(tasks))
            if len(outs) != len(tasks):
                raise ValueError(f"fn answered {len(outs)} rows for {len(tasks)} tasks")
        except Exception:  # noqa: BLE001 - the batch as a whole: each task again, alone
            return [_call(lambda t: _only(fn([t])), t) for t in tasks]
        share = (time.perf_counter() - started) / len(tasks)
        return [_row_of(out, share) for out in outs]
    finally:
        _settle()


_SETTLED: list[bool] = []


def _settle() -> None:
    """In a worker of the embedded runner, after its first batch: what it holds for good by
    then is put out of the garbage collector's way (``gc.freeze``; docs/scale.md)."""
    if _SETTLED or not os.environ.get(SPAWNED_WORKER_ENV):
        return
    _SETTLED.append(True)
    gc.collect()
    gc.freeze()


def _only(outs):
    (out,) = outs
    if isinstance(out, Exception):
        raise out
    return out


# =============================================================================== running


def batch_size(scenes: int, workers: int) -> int:
    """About four batches per worker, at most :data:`BATCH_TASK_MAX` scenes each:
    ``ceil(scenes / (4 workers))`` clipped to 1 .. :data:`BATCH_TASK_MAX`."""
    return max(1, min(BATCH_TASK_MAX, math.ceil(scenes / (4 * max(1, workers)))))


def run_scenes(tasks: list[dict], fn: Callable, *, store_dir: str | os.PathLike,
               jobs: int | None = None, scheduler: str | Scheduler | None = None,
               resume: bool = False, desc: str = "scenes", progress: bool | None = None,
               flush_s: float = 1.0, chunk: int | None = None,
               max_scenes: int = MAX_SCENES, worker_wait_s: float = WORKER_WAIT_S,
               eta: bool = True, many: bool = False, core: bool = False,
               files: dict[str, str] | None = None) -> SceneStore:
    """Run every task not yet stored with ``fn`` and store each result (the module
    docstring): on ``jobs`` local workers (``core``: sharing the compiled core), or on the
    Dask cluster at ``scheduler``.  ``resume``: only the tasks not stored yet (without it, a
    store that holds results is refused); ``chunk``: scenes per batch (default
    :func:`batch_size`); ``many``: ``fn`` takes a batch; ``eta``: the time left on the
    progress bar; ``files``: the SHA-256 of the files the tasks name, as the caller read them
    (None: read here).  Returns the :class:`SceneStore`."""
    if isinstance(scheduler, Scheduler):
        scheduler, worker_wait_s = scheduler.address, scheduler.worker_wait_s
    if len(tasks) > max_scenes:
        raise SceneLimitError(f"{len(tasks)} scenes asked for; at most {max_scenes} in one run")
    made = _missing_folders(store_dir)
    try:
        with store_lock(store_dir):
            store = SceneStore(store_dir)
            store.clean_temporaries()
            done = store.ids()
            if done and not resume:
                raise StoreError(f"{store.results} already holds {len(done)} scene(s): "
                                 "resume, or use a new folder")
            unique: dict[str, tuple[dict, str]] = {}
            for t in tasks:
                text = _canonical(t)
                unique.setdefault(_id_of(text), (t, text))
            _check_study(store.dir, {sid: t for sid, (t, _) in unique.items()},
                         done if resume else set(), files)
            todo = [(sid, t, text) for sid, (t, text) in unique.items() if sid not in done]
            if todo:
                with (dask_executor(scheduler, worker_wait_s) if scheduler else
                      _local_pool(jobs, core)) as (executor, workers, alive):
                    size = batch_size(len(todo), workers) if chunk is None else max(1, int(chunk))
                    bar = progress_bar(len(unique), desc=desc, unit="scene",
                                       quiet=progress is False, dynamic_ncols=True,
                                       initial=len(unique) - len(todo), smoothing=0.1,
                                       **({} if eta else {"bar_format": ETA_LESS}))
                    run_batches(executor, [todo[k:k + size] for k in range(0, len(todo), size)],
                                fn, many, store, bar, in_flight=4 * workers, flush_s=flush_s,
                                alive=alive, worker_wait_s=worker_wait_s, where=scheduler)
            return store
    except BaseException:
        _remove_if_unused(made)  # a run that stored nothing leaves no folder behind
        raise


def run_batches(executor: cf.Executor, batches: list[list[tuple]], fn: Callable, many: bool,
                store: SceneStore, bar, *, in_flight: int = 8, flush_s: float = 1.0,
                alive: Callable[[], bool] = lambda: True, worker_wait_s: float = WORKER_WAIT_S,
                where=None) -> None:
    """The one scheduling loop: each batch of ``(scene id, task, its canonical JSON)``
    submitted to ``executor`` as ``_call_many(fn, tasks, many)``, at most ``in_flight`` at a
    time (the executor holds no more than it soon runs), each row stored as its batch completes
    (a batch that raised: its scenes failed, with why), written at most every ``flush_s``
    seconds; ``alive()`` false for ``worker_wait_s`` ends the run."""
    pending: list[dict] = []
    last, alone_since, failed, left = time.monotonic(), None, 0, len(batches)
    queue, futures = iter(batches), {}

    def flush():
        nonlocal last
        if pending:  # out of pending before the write: a Ctrl-C in it cannot store it twice
            rows = pending[:]
            pending.clear()
            store.write_batch(rows)
        last = time.monotonic()

    try:
        for group in itertools.islice(queue, in_flight):
            futures[executor.submit(_call_many, fn, [t for _, t, _ in group], many)] = group
        while futures:
            done, _ = cf.wait(futures, timeout=1.0, return_when=cf.FIRST_COMPLETED)
            if not done:
                if alive():
                    alone_since = None
                elif alone_since is None:
                    alone_since = time.monotonic()
                elif time.monotonic() - alone_since >= worker_wait_s:
                    raise RunFailed(f"every worker of the scheduler at {where} is gone ("
                                    f"{worker_wait_s:g} s without one) with {left} "
                                    "task(s) left: the scenes completed are stored; --resume "
                                    "runs the rest")
            for fut in done:
                group, left = futures.pop(fut), left - 1
                for more in itertools.islice(queue, 1):
                    futures[executor.submit(_call_many, fn, [t for _, t, _ in more],
                                            many)] = more
                try:
                    rows = fut.result()
                except RunFailed:
                    raise
                except Exception as exc:  # noqa: BLE001 - WorkerDied, KilledWorker, pickling
                    why = str(exc) if isinstance(exc, WorkerDied) else \
                        f"{type(exc).__name__}: {exc}"
                    rows = [{"status": "failed", "error": why, "run_s": None, "worker": None}
                            for _ in group]
                for (sid, _, text), row in zip(group, rows):
                    row.update(scene_id=sid, task_json=text, stored_at=time.time())
                    pending.append(row)
                    failed += row["status"] != "ok"
                    bar.set_postfix(failed=failed, refresh=False)
                    bar.update(1)
                if len(pending) >= BATCH_MAX or time.monotonic() - last >= flush_s:
                    flush()
    finally:
        flush()  # Ctrl-C or any error: what has completed is stored
        bar.close()


@contextlib.contextmanager
def _local_pool(jobs, core):
    """``(executor, its workers, alive())`` of a :class:`~.local_pool.LocalPool` of ``jobs``
    started in a folder that exists, within the open-file limit."""
    n = max(1, int(jobs or os.cpu_count() or 1))
    _files_for(n)
    try:  # the workers start in this process's folder: a deleted one failed every start
        os.getcwd()
    except FileNotFoundError:
        os.chdir(tempfile.gettempdir())
        sys.path[:] = [entry for entry in sys.path if entry != ""]
    try:
        pool = LocalPool(n, core=core)
    except Exception as exc:  # noqa: BLE001 - no process could start: the machine's limits
        raise LimitError(_cannot_load(f"{n} worker process(es)", exc,
                                      "or give fewer --jobs")) from None
    try:
        yield pool, n, lambda: True
    finally:
        pool.shutdown()


def _files_for(n: int) -> None:
    """:class:`LimitError` when the open-file limit cannot hold ``n`` workers (the rows
    ``POOL_FILES``, ``POOL_WORKER_FILES`` of the defaults)."""
    soft = resource.getrlimit(resource.RLIMIT_NOFILE)[0]
    try:
        now = len(os.listdir("/proc/self/fd"))
    except OSError:  # no /proc: the limit is met as the workers start
        return
    need = now + defaults.POOL_FILES + defaults.POOL_WORKER_FILES * n
    if soft != resource.RLIM_INFINITY and soft < need:
        fit = (soft - now - defaults.POOL_FILES) // defaults.POOL_WORKER_FILES
        raise LimitError(f"the open-file limit ({soft}, ulimit -n) is too low for {n} "
                         f"worker process(es), which need about {need}: "
                         + (f"give --jobs {fit}, or " if fit >= 1 else "")
                         + f"raise it (ulimit -n {max(need, 1024)})")


# ======================================================================== the studies' use


def run_longest_first(fn, tasks: list[dict], *, jobs: int | None, desc: str, store_dir,
                      quiet: bool = False, scheduler: str | Scheduler | None = None,
                      resume: bool = False, worker_wait_s: float = WORKER_WAIT_S,
                      many: bool = False, core: bool = False,
                      files: dict[str, str] | None = None) -> list[dict]:
    """``[fn(t) for t in tasks]`` by :func:`run_scenes`, the costliest tasks (``cost``)
    first, stored in ``store_dir`` (None: a temporary folder); rows in the tasks' order, each
    travelled as JSON.  ``files``: as :func:`run_scenes` (the files the tasks name, hashed by
    the caller who read them).  A task that could not run is an error naming it."""
    order = sorted(tasks, key=lambda t: -t["cost"])
    with temporary_store("scenes-") if store_dir is None else contextlib.nullcontext(
            store_dir) as where:
        stored = run_scenes(order, functools.partial(_json_rows if many else _json_row, fn),
                            store_dir=where, jobs=jobs, scheduler=scheduler, resume=resume,
                            desc=desc, progress=False if quiet else None,
                            worker_wait_s=worker_wait_s, eta=False, many=many,
                            core=core, files=files).by_id()
    rows = []
    for t in tasks:
        got = stored.get(scene_id(t))
        if got is None or got.get("status") != "ok":
            why = "not run" if got is None else got.get("error")
            if got is not None and got.get("status") == "stopped":
                raise RunFailed(f"{desc}: the run {_label(t)} stopped: {why}; the runs that "
                                "ended are stored, --resume runs it again")
            raise RunFailed(f"{desc}: the run {_label(t)} failed: {why}")
        rows.append(json.loads(got["row_json"]))
    return rows


@contextlib.contextmanager
def temporary_store(prefix: str):
    """A store no one asked to keep: a temporary folder in the command's own temporary
    folder (``files.own_temp_folder``: a killed command's is removed by the next)."""
    from deck_emulator.files import own_temp_folder

    with tempfile.TemporaryDirectory(prefix=prefix, dir=own_temp_folder()) as tmp:
        yield tmp


def _label(task: dict) -> str:
    return ", ".join(f"{k} {task[k]}" for k in ("kind", "column", "post", "variant", "engine",
                                                 "series", "label", "k", "method", "rtol")
                     if task.get(k) is not None)


def _json_row(fn, task: dict) -> dict:
    return {"row_json": json.dumps(fn(task), default=_plain_json)}


def _json_rows(fn, tasks: list[dict]) -> list:
    return [out if isinstance(out, Exception) else
            {"row_json": json.dumps(out, default=_plain_json)} for out in fn(tasks)]


def _plain_json(v):
    if hasattr(v, "tolist"):  # numpy arrays and scalars
        return v.tolist()
    raise TypeError(f"{type(v).__name__} is not a plain value")
