"""Scenes on worker processes, stored as they finish: :func:`run_scenes`.

A *task* is a dict of plain values saying everything one scene needs; ``fn(task) -> dict``
runs it on a worker (``many=True``: ``fn(tasks) -> [dict or exception]``, a batch at a time).
Tasks are handed out in batches (:func:`batch_size`) to a ``concurrent.futures`` executor:
:class:`~deck_emulator.studies.local_pool.LocalPool` on this machine (``jobs`` workers sharing
the preloaded core), or Dask's executor of an existing cluster (``scheduler=``: its scheduling
and its retries).  One loop, :func:`run_batches`, serves both.

The store (``store_dir``) is written by the client alone, so remote workers need no shared
file system: ``results/*.parquet``, one file per write (at most every ``flush_s`` seconds or
:data:`BATCH_MAX` rows), each written under a temporary name and renamed, so a file is whole or
absent; a finished file is never rewritten.  After ``kill -9`` at most the last ``flush_s``
seconds of results are lost and run again on resume; no scene is stored twice.  A scene's id is
:func:`scene_id` (SHA-256 of the task as canonical JSON).  A scene whose ``fn`` raised, or
whose worker died too often, is stored ``failed`` and not run again on resume (unless
``retry_failed``); one stopped by a bound of the machine (:class:`Stopped`) is stored
``stopped`` and runs again.  ``study.json`` keeps the SHA-256 of every file a task names, so
that a resume of a store made from another deck, grid or engine is refused
(:class:`StudyChanged`).  A store folder is locked (``flock``) by the process that uses it
(:class:`StoreBusy` for another); the kernel drops the lock however the process ends.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import dataclasses
import fcntl
import functools
import gc
import hashlib
import json
import math
import os
import resource
import shutil
import sys
import tempfile
import time
import traceback
import uuid
from collections.abc import Callable, Iterable
from pathlib import Path

from deck_emulator import SPAWNED_WORKER_ENV
from deck_emulator.errors import RunFailed, UsageError, process_limits
from deck_emulator.parallel import progress_bar
from deck_emulator.studies.local_pool import LocalPool, WorkerDied
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.defaults import SCENE_STORE, WORKER_WAIT_S

__all__ = [
    "BATCH_TASK_MAX", "META_COLUMNS", "MAX_SCENES", "WORKER_WAIT_S", "ClusterError",
    "SceneLimitError", "SceneStore", "Scheduler", "Stopped", "StoreBusy", "StoreError",
    "batch_size", "output_store", "run_batches", "run_longest_first", "run_scenes", "scene_id",
    "store_lock", "temporary_store",
]

#: Columns every stored row has, before the outcome columns ``fn`` returns.
META_COLUMNS = ("scene_id", "task_json", "status", "error", "worker", "run_s", "stored_at")
RESULTS = "results"
#: Most rows one store file holds.
BATCH_MAX = 256
#: Most scenes one call of :func:`run_scenes` takes.
MAX_SCENES = 1_000_000
LOCK_NAME = ".lock"
STUDY_NAME = "study.json"
#: Most scenes in one batch: a worker holds one batch's solver records (docs/scale.md).
BATCH_TASK_MAX = 16


class StoreError(UsageError, RuntimeError):
    """A store that cannot be used as asked: bad input, exit status 2, nothing run."""


class StudyChanged(StoreError):
    """A resume asked of a store made for another study."""


class StoreBusy(StoreError):
    """Another live process holds the store folder."""


class SceneLimitError(UsageError, ValueError):
    """More scenes than a call takes (``max_scenes``)."""


class ClusterError(UsageError, ValueError):
    """No Dask scheduler can be reached at the address given: exit status 2."""


class LimitError(UsageError, RuntimeError):
    """The process's limits keep a worker or a library from starting: exit 2."""


class Stopped(Exception):
    """A scene stopped at a bound of the machine, not of the model (a core run past its wall
    time): stored ``stopped``, run again on resume."""


@dataclasses.dataclass(frozen=True)
class Scheduler:
    """An external Dask cluster's address and how long a run waits for a worker."""

    address: str
    worker_wait_s: float = WORKER_WAIT_S

    def __str__(self) -> str:
        return self.address


# ================================================================================ the lock

#: store folder (resolved) -> [open lock file descriptor, depth]: the locks this process holds
_HELD: dict[str, list[int]] = {}


def _acquire(store_dir) -> str:
    folder = Path(store_dir)
    folder.mkdir(parents=True, exist_ok=True)
    key = os.path.realpath(folder)
    if key in _HELD:
        _HELD[key][1] += 1
        return key
    fd = os.open(folder / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        holder = os.pread(fd, 32, 0).decode("ascii", "replace").strip() or "?"
        os.close(fd)
        raise StoreBusy(f"{store_dir} is in use by another run (pid {holder}): wait for it to "
                        "end, or use another folder") from None
    except BaseException:
        os.close(fd)
        raise
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
    _HELD[key] = [fd, 1]
    return key


def _release(key: str) -> None:
    held = _HELD.get(key)
    if held is not None:
        held[1] -= 1
        if held[1] <= 0:
            del _HELD[key]
            os.close(held[0])  # closing the descriptor releases the flock


@contextlib.contextmanager
def store_lock(store_dir):
    """The exclusive lock of a store folder for the block (re-entrant in one process)."""
    key = _acquire(store_dir)
    try:
        yield Path(store_dir)
    finally:
        _release(key)


def _canonical(task: dict) -> str:
    def norm(v):
        if isinstance(v, bool) or v is None or isinstance(v, (int, str)):
            return v
        if isinstance(v, float):
            return repr(v) if math.isnan(v) or math.isinf(v) else v
        if isinstance(v, dict):
            return {str(k): norm(x) for k, x in v.items()}
        if isinstance(v, (list, tuple)):
            return [norm(x) for x in v]
        if hasattr(v, "item"):  # numpy scalar
            return norm(v.item())
        raise TypeError(f"task value {v!r} ({type(v).__name__}) is not a plain value")

    return json.dumps(norm(task), sort_keys=True, separators=(",", ":"), allow_nan=False)


def scene_id(task: dict) -> str:
    """The scene's identity: the first 24 hex digits of SHA-256 of the task as canonical JSON."""
    return _id_of(_canonical(task))


def _id_of(canonical: str) -> str:
    return hashlib.sha256(canonical.encode()).hexdigest()[:24]


# ================================================================================ the store


def _named_files(tasks: Iterable[dict]) -> dict[str, str]:
    """SHA-256 of every regular file a task's string values name (a deck, a scene)."""
    strings: set[str] = set()

    def walk(v):
        if isinstance(v, str):
            if v and len(v) < 4096 and "\n" not in v and "\0" not in v:
                strings.add(v)
        elif isinstance(v, (dict, list, tuple)):
            for x in (v.values() if isinstance(v, dict) else v):
                walk(x)

    for t in tasks:
        walk(t)
    out = {}
    for name in sorted(strings):
        with contextlib.suppress(OSError, ValueError):
            if os.path.isfile(name):
                with open(name, "rb") as fh:
                    out[name] = hashlib.sha256(fh.read()).hexdigest()
    return out


def _check_study(store_dir: Path, unique: dict[str, dict], stored: set[str]) -> None:
    """Keep what the store's scenes are made from; on a resume (``stored``: its scenes' ids),
    :class:`StudyChanged` when a file the tasks name changed, or no stored scene is asked."""
    path = store_dir / STUDY_NAME
    made_from = {"files": _named_files(unique.values()), "scenes": len(unique)}
    files: dict[str, str] = {}
    if stored and path.is_file():
        try:
            files = dict(json.loads(path.read_text())["files"])
        except (OSError, ValueError, KeyError, TypeError):
            raise StudyChanged(f"{path}: unreadable, so the stored scenes cannot be matched to "
                               "this study: run without --resume to start again") from None
        for name, sha in sorted(files.items()):
            now = made_from["files"].get(name)
            if now is not None and now != sha:
                raise StudyChanged(
                    f"--resume: {name} changed since {store_dir} was made from it (SHA-256 "
                    f"{sha[:12]}... then, {now[:12]}... now): its stored scenes are another "
                    "deck's; run without --resume to start again, or use a new folder")
    if stored and stored.isdisjoint(unique):
        raise StudyChanged(
            f"--resume: none of the {len(stored)} scenes stored in {store_dir} is among the "
            f"{len(unique)} asked for: the engine or its settings changed, so this is "
            "another study; run without --resume to start again, or use a new folder")
    kept = {**made_from, "files": {**files, **made_from["files"]}}  # a resume adds its files
    if not (stored and path.is_file() and kept["files"] == files):
        _write_atomic(path, (json.dumps(kept, indent=1, sort_keys=True) + "\n").encode())


def _write_atomic(path: Path, data: bytes | None, table=None) -> None:
    """``data`` (or a pyarrow ``table`` as Parquet) to ``path`` by a temporary name and a
    rename: the file is whole or absent."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb") as fh:  # (pyarrow takes a path only as UTF-8)
            if table is None:
                fh.write(data)
            else:
                _arrow()[1].write_table(table, fh)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def output_store(out_dir, resume: bool) -> Path:
    """The scene store of a command's output folder; an existing one is locked for the rest
    of the process and, without ``resume``, emptied (a new one is locked by run_scenes)."""
    store = Path(out_dir) / SCENE_STORE
    if not store.exists():
        return store
    _acquire(store)  # held for the rest of the process: the command's runs go in it
    if not resume:
        for child in store.iterdir():
            if child.name == LOCK_NAME:
                continue
            if child.is_dir() and not child.is_symlink():
                shutil.rmtree(child)
            else:
                child.unlink()
    return store


class SceneStore:
    """The stored scenes of one run: ``store_dir/results/*.parquet``."""

    def __init__(self, store_dir: str | os.PathLike):
        self.dir = Path(store_dir)
        self.results = self.dir / RESULTS

    def files(self) -> list[Path]:
        if not self.results.is_dir():
            return []
        return sorted(p for p in self.results.glob("*.parquet") if not p.name.startswith("."))

    def rows(self, columns: Iterable[str] | None = None) -> list[dict]:
        """Every stored row, in the order written; ``columns``: only these (None where a
        file lacks one)."""
        pq = _arrow()[1]
        out: list[dict] = []
        for f in self.files():
            with open(f, "rb") as fh:
                if columns is None:
                    out.extend(pq.read_table(fh).to_pylist())
                    continue
                stored = pq.ParquetFile(fh)
                have = set(stored.schema_arrow.names)
                rows = stored.read(columns=[c for c in columns if c in have]).to_pylist()
                out.extend({c: row.get(c) for c in columns} for row in rows)
        return out

    def table(self):
        """All rows as one ``pyarrow.Table``."""
        pa, rows = _arrow()[0], self.rows()
        return pa.Table.from_pylist(rows) if rows else pa.table({c: [] for c in META_COLUMNS})

    def ids(self, *, include_failed: bool = True) -> set[str]:
        """The scenes a resume does not run again: ended, and failed unless not
        ``include_failed``; never a stopped one."""
        keep = {"ok", "failed"} if include_failed else {"ok"}
        return {r["scene_id"] for r in self.rows(("scene_id", "status")) if r["status"] in keep}

    def by_id(self, columns: Iterable[str] | None = None) -> dict[str, dict]:
        """scene id -> its last stored row (``columns``: as :meth:`rows`)."""
        if columns is not None:
            columns = ["scene_id", *(c for c in columns if c != "scene_id")]
        return {r["scene_id"]: r for r in self.rows(columns)}

    def outcomes(self, tasks: Iterable[dict], key: str) -> list:
        """The outcome ``key`` of each task, in order (None if absent or failed)."""
        rows = self.by_id()
        return [None if (r := rows.get(scene_id(t))) is None or r.get("status") != "ok"
                else r.get(key) for t in tasks]

    def write_batch(self, rows: list[dict]) -> Path | None:
        """``rows`` as one new Parquet file, named in the order written."""
        if not rows:
            return None
        self.results.mkdir(parents=True, exist_ok=True)
        name = f"batch-{time.time_ns():020d}-{os.getpid()}-{uuid.uuid4().hex[:8]}.parquet"
        _write_atomic(self.results / name, None, _arrow()[0].Table.from_pylist(_uniform(rows)))
        return self.results / name

    def clean_temporaries(self) -> None:
        """Remove the temporaries a killed writer left behind (never a whole file)."""
        for p in [*self.dir.glob(".*.tmp"), *self.results.glob(".*.tmp")]:
            with contextlib.suppress(FileNotFoundError):
                p.unlink()


def _arrow():
    """pyarrow and its Parquet module, on the system's allocator (pyarrow's own crashed the
    process under ``ulimit -v``); one that cannot load is a :class:`LimitError`."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ModuleNotFoundError:
        raise
    except ImportError as exc:  # a library found but not loaded: "failed to map segment"
        raise LimitError(_cannot_load("pyarrow", exc)) from None
    pa.set_memory_pool(pa.system_memory_pool())
    return pa, pq


def _uniform(rows: list[dict]) -> list[dict]:
    """Rows with the same keys (missing: None), an int in a column of floats as a float."""
    keys = list(dict.fromkeys([*META_COLUMNS, *(k for r in rows for k in r)]))
    floaty = {k for r in rows for k, v in r.items() if isinstance(v, float)}
    return [{k: float(v) if k in floaty and type(v) is int else v
             for k in keys for v in (r.get(k),)} for r in rows]


# ======================================================================= on the worker


def _plain(v):
    if v is None or isinstance(v, (bool, int, float, str)):
        return v
    return v.item() if hasattr(v, "item") else str(v)


def _call(fn: Callable[[dict], dict], task: dict) -> dict:
    started = time.perf_counter()
    try:
        out = fn(task)
    except Exception as exc:  # noqa: BLE001 - a scene that fails is a row
        out = exc
    return _row_of(out, time.perf_counter() - started)


def _row_of(out, run_s: float) -> dict:
    """One task's stored row: ``out`` (its outcomes, or the exception that ended it)."""
    if isinstance(out, Stopped):
        row = {"status": "stopped", "error": str(out)}
    elif isinstance(out, Exception):
        row = {"status": "failed",
               "error": traceback.format_exception_only(type(out), out)[-1].strip()}
    elif not isinstance(out, dict):
        row = {"status": "failed",
               "error": f"TypeError: fn returned {type(out).__name__}, not a dict"}
    else:
        row = {f"{k}": _plain(v) for k, v in out.items() if k not in META_COLUMNS}
        row.update(status="ok", error=None)
    row["run_s"] = run_s
    row["worker"] = f"{os.uname().nodename}:{os.getpid()}"
    return row


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
               retry_failed: bool = False, flush_s: float = 1.0, chunk: int | None = None,
               max_scenes: int = MAX_SCENES, worker_wait_s: float = WORKER_WAIT_S,
               eta: bool = True, many: bool = False, core: bool = False) -> SceneStore:
    """Run every task not yet stored with ``fn`` and store each result (the module
    docstring): on ``jobs`` local workers (``core``: sharing the compiled core), or on the
    Dask cluster at ``scheduler``.  ``resume``: only the tasks not stored yet (without it, a
    store that holds results is refused); ``chunk``: scenes per batch (default
    :func:`batch_size`); ``many``: ``fn`` takes a batch; ``eta``: the time left on the
    progress bar.  Returns the :class:`SceneStore`."""
    if isinstance(scheduler, Scheduler):
        scheduler, worker_wait_s = scheduler.address, scheduler.worker_wait_s
    if len(tasks) > max_scenes:
        raise SceneLimitError(f"{len(tasks)} scenes asked for; at most {max_scenes} in one run")
    made = _missing_folders(store_dir)
    try:
        with store_lock(store_dir):
            store = SceneStore(store_dir)
            store.clean_temporaries()
            done = store.ids(include_failed=not retry_failed)
            if done and not resume:
                raise StoreError(f"{store.results} already holds {len(done)} scene(s): "
                                 "resume, or use a new folder")
            unique: dict[str, tuple[dict, str]] = {}
            for t in tasks:
                text = _canonical(t)
                unique.setdefault(_id_of(text), (t, text))
            _check_study(store.dir, unique, store.ids() if resume else set())
            todo = [(sid, t, text) for sid, (t, text) in unique.items() if sid not in done]
            if todo:
                with _executor(scheduler, jobs, core, worker_wait_s) as (executor, workers,
                                                                            alive):
                    size = batch_size(len(todo), workers) if chunk is None else max(1, int(chunk))
                    run_batches(executor, [todo[k:k + size] for k in range(0, len(todo), size)],
                                fn, many, store, progress_bar(
                                    len(unique), desc=desc, unit="scene",
                                    quiet=progress is False, initial=len(unique) - len(todo),
                                    dynamic_ncols=True, smoothing=0.1, **({} if eta else {
                                        "bar_format": "{l_bar}{bar}| {n_fmt}/{total_fmt} "
                                                      "[{elapsed}{postfix}]"})),
                                flush_s=flush_s, alive=alive, worker_wait_s=worker_wait_s,
                                where=scheduler)
            return store
    except BaseException:
        _remove_if_unused(made)  # a run that stored nothing leaves no folder behind
        raise


def run_batches(executor: cf.Executor, batches: list[list[tuple]], fn: Callable, many: bool,
                store: SceneStore, bar, *, flush_s: float = 1.0,
                alive: Callable[[], bool] = lambda: True, worker_wait_s: float = WORKER_WAIT_S,
                where=None) -> None:
    """The one scheduling loop: every batch of ``(scene id, task, its canonical JSON)``
    submitted to ``executor`` as ``_call_many(fn, tasks, many)``, each row stored as its batch
    completes (a batch that raised, its scenes failed with why), written at most every
    ``flush_s`` seconds; ``alive()`` false for ``worker_wait_s`` ends the run."""
    pending: list[dict] = []
    last, alone_since, failed = time.monotonic(), None, 0

    def flush():
        nonlocal last
        if pending:  # out of pending before the write: a Ctrl-C in it cannot store it twice
            rows = pending[:]
            pending.clear()
            store.write_batch(rows)
        last = time.monotonic()

    futures = {executor.submit(_call_many, fn, [t for _, t, _ in group], many): group
               for group in batches}
    try:
        while futures:
            done, _ = cf.wait(futures, timeout=1.0, return_when=cf.FIRST_COMPLETED)
            if not done:
                if alive():
                    alone_since = None
                elif alone_since is None:
                    alone_since = time.monotonic()
                elif time.monotonic() - alone_since >= worker_wait_s:
                    raise RunFailed(f"every worker of the scheduler at {where} is gone ("
                                    f"{worker_wait_s:g} s without one) with {len(futures)} "
                                    "task(s) left: the scenes completed are stored; --resume "
                                    "runs the rest")
            for fut in done:
                group = futures.pop(fut)
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
def _executor(scheduler, jobs, core, worker_wait_s):
    """``(executor, its workers, alive())``: a :class:`~.local_pool.LocalPool` of ``jobs``,
    or Dask's executor of the cluster at ``scheduler`` once it has a worker."""
    if not scheduler:
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
        return
    from distributed import Client

    _reach(scheduler)
    try:
        client = Client(scheduler, timeout=defaults.SCHEDULER_CONNECT_S)
    except (ValueError, OSError, TimeoutError) as exc:
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ClusterError(f"--scheduler {scheduler}: cannot reach the scheduler: "
                           f"{why}") from None
    try:
        try:
            client.wait_for_workers(1, timeout=worker_wait_s)
        except (TimeoutError, OSError):
            raise RunFailed(f"the scheduler at {scheduler} has no worker: none joined in "
                            f"{worker_wait_s:g} s") from None
        executor = client.get_executor(pure=False)
        try:
            yield executor, _workers(client) or 1, lambda: _workers(client) > 0
        finally:
            executor.shutdown(wait=False)  # what is left (an error, a Ctrl-C) is cancelled
    finally:
        with contextlib.suppress(Exception):
            client.close()


def _workers(client) -> int:
    """The cluster's workers now; a scheduler gone (Dask's errors are OSErrors) has none."""
    try:
        return len(client.nthreads())
    except OSError:
        return 0


def _missing_folders(folder) -> list[Path]:
    missing, path = [], Path(folder).absolute()
    while not path.exists():
        missing.append(path)
        path = path.parent
    return missing


def _remove_if_unused(folders: list[Path]) -> None:
    """Remove the folders a failed run made while they hold no stored scene."""
    for folder in folders:
        try:
            results = folder / RESULTS
            if results.is_dir() and not any(results.iterdir()):
                results.rmdir()
            if not results.exists():
                (folder / STUDY_NAME).unlink(missing_ok=True)
            (folder / LOCK_NAME).unlink(missing_ok=True)
            folder.rmdir()  # OSError when anything else is in it: kept
        except OSError:
            return


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


def _cannot_load(what: str, exc: BaseException, also: str = "") -> str:
    why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    limits = ", ".join(process_limits())
    return (f"could not start {what} ({why[:160]})" + (f" under the limits of {limits}: raise "
            f"them{', ' + also if also else ''}" if limits else f": {also or 'free memory'}"))


def _reach(address: str) -> None:
    """:class:`ClusterError` in one line unless a Dask scheduler answers at ``address``: a
    plain TCP connection first (a refusal is told at once, whatever the load; Dask's connect
    retries it until its time-out), then Dask's ``connect`` and handshake, bounded (Dask
    leaves the handshake unbounded: a silent port held a sweep for ever), then the
    scheduler's identity.  ``inproc://`` is this process's own cluster: not asked."""
    import asyncio
    import socket

    from distributed.comm import connect, parse_address, parse_host_port
    from distributed.security import Security

    where, bound = f"--scheduler {address}", defaults.SCHEDULER_CONNECT_S
    try:
        scheme, location = parse_address(address)
    except (ValueError, TypeError) as exc:
        raise ClusterError(f"{where}: this install cannot connect so ({exc}); give "
                           "tcp://HOST:PORT") from None
    if scheme == "inproc":
        return
    args = Security().get_connection_args("client")  # Dask's TLS settings, if any
    if scheme in ("tls", "wss") and args.get("ssl_context") is None:
        raise ClusterError(f"{where}: {scheme}:// needs Dask's TLS settings (distributed.comm."
                           "tls.ca-file, .client.cert, .client.key) and none are set")
    if scheme in ("tcp", "tls", "ws", "wss"):
        try:
            with socket.create_connection(parse_host_port(location), timeout=bound):
                pass
        except TimeoutError:
            raise ClusterError(f"{where}: no connection in {bound:g} s") from None
        except (OSError, ValueError) as exc:  # refused, no such host, not HOST:PORT
            raise ClusterError(f"{where}: nothing listens there ({exc})") from None

    async def identity():
        comm = await connect(address, timeout=bound, deserialize=True, **args)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    async def bounded():
        return await asyncio.wait_for(identity(), 2 * bound)

    with cf.ThreadPoolExecutor(1) as pool:  # its own event loop, in any caller
        try:
            who = pool.submit(asyncio.run, bounded()).result()
        except asyncio.TimeoutError:  # connected, then nothing
            raise ClusterError(f"{where}: something took the connection and said nothing a "
                               f"Dask scheduler says in {2 * bound:g} s") from None
        except (TypeError, ImportError) as exc:  # ucx:// without its library: no connector
            raise ClusterError(f"{where}: this install cannot connect so ({exc}); give "
                               "tcp://HOST:PORT") from None
        except (OSError, ValueError) as exc:  # refused, reset, no connection in the bound
            cause = exc.__cause__ or exc
            why = str(cause).splitlines()[0][:120] if str(cause) else type(cause).__name__
            if isinstance(cause, (asyncio.TimeoutError, TimeoutError)):
                raise ClusterError(f"{where}: no connection in {bound:g} s") from None
            raise ClusterError(f"{where}: {'not an address' if isinstance(cause, ValueError) else 'nothing listens there'} ({why})") from None
        except Exception:  # noqa: BLE001 - bytes that are not Dask's, whatever they raise
            raise ClusterError(f"{where}: something answered there, not in Dask's protocol "
                               "(not a Dask scheduler)") from None
    kind = who.get("type") if isinstance(who, dict) else None
    if kind != "Scheduler":
        raise ClusterError(f"{where}: {'a Dask ' + kind if kind else 'something'} answered "
                           "there, not a Dask scheduler")


# ======================================================================== the studies' use


def run_longest_first(fn, tasks: list[dict], *, jobs: int | None, desc: str, store_dir,
                      quiet: bool = False, scheduler: str | Scheduler | None = None,
                      resume: bool = False, worker_wait_s: float = WORKER_WAIT_S,
                      many: bool = False, core: bool = False) -> list[dict]:
    """``[fn(t) for t in tasks]`` by :func:`run_scenes`, the costliest tasks (``cost``)
    first, stored in ``store_dir`` (None: a temporary folder); rows in the tasks' order, each
    travelled as JSON.  A task that could not run is an error naming it."""
    order = sorted(tasks, key=lambda t: -t["cost"])
    with temporary_store("scenes-") if store_dir is None else contextlib.nullcontext(
            store_dir) as where:
        stored = run_scenes(order, functools.partial(_json_rows if many else _json_row, fn),
                            store_dir=where, jobs=jobs, scheduler=scheduler, resume=resume,
                            desc=desc, progress=False if quiet else None,
                            worker_wait_s=worker_wait_s, eta=False, many=many,
                            core=core).by_id()
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
