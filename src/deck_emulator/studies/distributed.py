"""Scenes on worker processes, with a store that survives interruption: :func:`run_scenes`.

A *task* is a dict of plain values (str, int, float, bool, None, lists and dicts of them) that
says everything one scene needs; ``fn(task) -> dict`` runs it and returns its outcomes as a flat
dict of plain values. :func:`run_scenes` runs every task once:

* by default on the embedded runner (:mod:`deck_emulator.studies.local_pool`): ``jobs`` worker
  processes forked from one that has loaded the compiled core, one batch at a time each,
  nothing to start, ended at the end;
* or on an existing ``dask.distributed`` cluster, given by its scheduler address
  (``scheduler="tcp://host:8786"``), whose scheduling (who runs what, retries when a worker
  dies) is Dask's.

This module only hands out batches, collects and stores.

The store
---------
Results are written **by the client** (the process that calls :func:`run_scenes`), so workers on
other machines need no shared file system. The store is a folder ``results/`` in ``store_dir``
holding small Parquet files (pyarrow), one per *batch* of completed scenes: a batch is what has
completed since the last write, written at most every ``flush_s`` seconds (default 1 s) or every
256 scenes, whichever comes first. Each file is written to a temporary name in the same folder and
then renamed, so a file is either whole or absent.

Why Parquet files written once, rather than one CSV appended to:

* an append cut short by ``kill -9`` (or a full disk) leaves half a row, which a reader must then
  detect and repair; a rename is atomic, so a crash at any instant leaves only whole files;
* a finished result is never rewritten: resuming adds files and touches no existing one, which is
  what "no finished result changed" needs;
* the columns keep their types (a float stays a float, a missing value stays null).

The cost is many small files for a big sweep (10^4 scenes at 1 s per file on 2 workers is a few
thousand files); :meth:`SceneStore.table` reads them into one table.

Safety stated exactly: after ``kill -9`` of the client, at most the last ``flush_s`` seconds of
completed scenes are lost (not stored) and will run again on resume; no scene is stored twice. The
files are not ``fsync``-ed: a process crash loses nothing written, a power cut may.

A worker is handed a *batch* of scenes (:func:`batch_size`: about four batches per worker, at
most :data:`BATCH_TASK_MAX` scenes each), run by ``fn`` one after another or, with ``many=True``,
by one call of ``fn`` on the whole list (how core scenes reach ``CoreEngine.run_batch``).  The
store, the progress bar and ``--resume`` still count scenes: each scene of a batch is its own
row.

Scene identity is :func:`scene_id`: a SHA-256 of the task as canonical JSON (sorted keys, floats
by ``repr``), so the same task dict gives the same id in any process or run. Tasks with the same id
are run once.

A scene whose ``fn`` raises is stored with ``status = "failed"`` and the error text; a scene whose
worker died more than :data:`~deck_emulator.vocabulary.defaults.WORKER_DEATHS_PER_BATCH` times
(the worker is replaced and the batch run again on another until then) is stored failed saying
so (``WorkerDied``; on a Dask cluster, after its ``allowed-failures``, Dask's ``KilledWorker``).
Neither stops the other scenes. Failed scenes count as stored: a
resume does not run them again (``retry_failed=True`` does).  A scene stopped by a bound of the
machine (``fn`` raised :class:`Stopped`: a core run past its wall time) is stored with
``status = "stopped"`` and why; it does not count as stored, so a resume runs it again.

What a store was made from
--------------------------
A task names its deck by its file, which the workers read; the scene id hashes the task, not
the file.  So the store keeps ``study.json`` (:data:`STUDY_NAME`), written before its first
scene runs: the SHA-256 of every file a task names (each string of a task that is a regular
file's path: the deck, a base deck, a scene).  A resume is refused, in one line
(:class:`StudyChanged`), when a file's contents changed since, naming the file, or when none
of the stored scenes is among those asked for (the engine or its settings changed: the grid,
the engine and its settings are in each task, so in its id; a grid made larger or smaller
keeps the scenes both share, which are the same scenes); a store without it (made before it
was kept) is resumed as before, and keeps it from then on.

Progress: a ``tqdm`` bar on stderr, only when stderr is a terminal: scenes done, failed, rate.

One run at a time on a store
----------------------------
A store folder is *locked* by the process that uses it (an exclusive ``flock`` on
``store_dir/.lock``, held by :func:`output_store` for the rest of the process when the store
exists, and by :func:`run_scenes` while it runs): a second process that asks for the same folder -- two
``--resume`` runs, or a new run on a folder a resume is filling -- is refused at once with
:class:`StoreBusy`, in one line naming the folder and the holder's pid; it does not wait.  The
kernel releases the lock when its process ends, however it ends (``kill -9`` included), so a
killed run never leaves a folder locked.  No command deletes a store another run holds:
:func:`output_store` takes the lock before it empties the folder.

Bounds
------
At most ``max_scenes`` (default :data:`MAX_SCENES`) scenes a call (:class:`SceneLimitError`,
before anything runs).  An external scheduler (``scheduler=``) must take the connection and
then answer Dask's handshake as a scheduler, each within ``SCHEDULER_CONNECT_S`` (a row of
:mod:`deck_emulator.vocabulary.defaults`); an address by a scheme this install cannot serve
(``ucx://`` without its library, ``tls://`` without Dask's TLS settings), one where nothing
listens, or something else (an HTTP server, a silent port), is a :class:`ClusterError` saying
what was found there, before anything runs.  The run then waits at most ``worker_wait_s``
(default ``WORKER_WAIT_S``, the defaults' row) for a worker: at the start, and whenever every
worker is gone while scenes remain; then it ends with :class:`~deck_emulator.errors.RunFailed`
naming the scheduler (the scenes completed so far stay stored; ``--resume`` runs the rest).
"""

from __future__ import annotations

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
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.defaults import SCENE_STORE, WORKER_WAIT_S

__all__ = [
    "run_longest_first",
    "output_store",
    "scene_id",
    "SceneStore",
    "run_scenes",
    "StoreError",
    "StoreBusy",
    "SceneLimitError",
    "ClusterError",
    "store_lock",
    "META_COLUMNS",
    "MAX_SCENES",
    "WORKER_WAIT_S",
    "BATCH_TASK_MAX",
    "batch_size",
    "Scheduler",
    "Stopped",
    "temporary_store",
]

#: Columns every stored row has, before the outcome columns ``fn`` returns.
META_COLUMNS = ("scene_id", "task_json", "status", "error", "worker", "run_s", "stored_at")
RESULTS = "results"
BATCH_MAX = 256


#: Most scenes one call of :func:`run_scenes` takes.
MAX_SCENES = 1_000_000
LOCK_NAME = ".lock"
#: what a store's scenes were made from (the module docstring)
STUDY_NAME = "study.json"


class StoreError(UsageError, RuntimeError):
    """A store that cannot be used as asked (e.g. results exist and ``resume`` was not given):
    bad input, exit status 2, nothing run."""


class StudyChanged(StoreError):
    """A resume asked of a store made for another study (a changed deck, grid, engine or
    settings)."""


class StoreBusy(StoreError):
    """Another live process holds the store folder (:func:`store_lock`)."""


class SceneLimitError(UsageError, ValueError):
    """More scenes than a call takes (``max_scenes``)."""


class ClusterError(UsageError, ValueError):
    """The scheduler's address cannot be parsed or reached, or no Dask scheduler answers
    there: bad input, exit status 2."""


class LimitError(UsageError, RuntimeError):
    """The process's limits (ulimit) keep a worker or a library from starting: exit 2, in one
    line naming the limits and what to change."""


class Stopped(Exception):
    """Raised by a task's ``fn`` (or answered by a batch ``fn`` for one task): the scene
    stopped at a bound of the machine, not of the model (a core run past its wall time on a
    starved or suspended machine).  It is stored with status ``"stopped"`` and why, and a
    resume runs it again."""


@dataclasses.dataclass(frozen=True)
class Scheduler:
    """An external Dask cluster: its scheduler's address, and how long a run waits for a worker
    (at the start, and whenever every worker is gone while scenes remain).  Passed as
    ``scheduler=`` wherever an address is; printed, it is the address."""

    address: str
    worker_wait_s: float = WORKER_WAIT_S

    def __str__(self) -> str:
        return self.address


# ================================================================================ the lock

#: store folder (resolved) -> [open lock file descriptor, depth]: the locks this process holds
_HELD: dict[str, list[int]] = {}


def _acquire(store_dir) -> str:
    """Take (or take again: it counts) this process's lock on ``store_dir``; the folder is
    made if need be.  :class:`StoreBusy` when another process holds it."""

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
    if held is None:
        return
    held[1] -= 1
    if held[1] <= 0:
        del _HELD[key]
        os.close(held[0])  # closing the descriptor releases the flock


@contextlib.contextmanager
def store_lock(store_dir):
    """Hold the exclusive lock of a store folder for the ``with`` block (re-entrant in one
    process); :class:`StoreBusy` at once when another process holds it."""
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
            if math.isnan(v) or math.isinf(v):
                return repr(v)
            return v
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
        elif isinstance(v, dict):
            for x in v.values():
                walk(x)
        elif isinstance(v, (list, tuple)):
            for x in v:
                walk(x)

    for t in tasks:
        walk(t)
    out = {}
    for name in sorted(strings):
        try:
            if os.path.isfile(name):
                with open(name, "rb") as fh:
                    out[name] = hashlib.sha256(fh.read()).hexdigest()
        except (OSError, ValueError):
            continue
    return out


def _made_from(unique: dict[str, dict]) -> dict:
    return {"files": _named_files(unique.values()), "scenes": len(unique)}


def _check_study(store_dir: Path, made_from: dict, stored: set[str], asked: Iterable[str]
                 ) -> None:
    """Keep what the store's scenes are made from; on a resume (``stored``: the ids of its
    scenes), :class:`StudyChanged` when the files the tasks name changed since, or when no
    stored scene is ``asked`` for (the module docstring)."""
    path = store_dir / STUDY_NAME
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
    if stored and stored.isdisjoint(asked):
        raise StudyChanged(
            f"--resume: none of the {len(stored)} scenes stored in {store_dir} is among the "
            f"{made_from['scenes']} asked for: the engine or its settings changed, so this is "
            "another study; run without --resume to start again, or use a new folder")
    kept = {**made_from, "files": {**files, **made_from["files"]}}  # a resume adds its files
    if not (stored and path.is_file() and kept["files"] == files):
        tmp = store_dir / f".{STUDY_NAME}.{os.getpid()}.tmp"  # as the store's batches are
        try:
            tmp.write_text(json.dumps(kept, indent=1, sort_keys=True) + "\n")
            os.replace(tmp, path)
        except BaseException:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)
            raise


def output_store(out_dir, resume: bool) -> Path:
    """The scene store of a command's output folder (:data:`deck_emulator.vocabulary.defaults.SCENE_STORE`
    in it).  An existing store is locked by this process until it ends (:func:`store_lock`;
    :class:`StoreBusy` when another run holds it) and, for a new run (no ``resume``), emptied;
    a store not made yet is left to :func:`run_scenes`, which locks it as it makes it."""

    store = Path(out_dir) / SCENE_STORE
    if not store.exists():
        return store  # nothing to keep or delete; run_scenes locks it when it makes it
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
    """The stored scenes of one sweep: ``store_dir/results/*.parquet``."""

    def __init__(self, store_dir: str | os.PathLike):
        self.dir = Path(store_dir)
        self.results = self.dir / RESULTS

    def files(self) -> list[Path]:
        if not self.results.is_dir():
            return []
        return sorted(p for p in self.results.glob("*.parquet") if not p.name.startswith("."))

    def rows(self, columns: Iterable[str] | None = None) -> list[dict]:
        """Every stored row (plain dicts), in the order the files were written; ``columns``:
        only these (a study that reads a few of them need not hold the rest; one a file does
        not have, as a file of failed scenes has no outcomes, is None in its rows)."""
        _, pq = _arrow()
        out: list[dict] = []
        for f in self.files():
            with open(f, "rb") as fh:  # (pyarrow takes a path only as UTF-8)
                if columns is None:
                    out.extend(pq.read_table(fh).to_pylist())
                    continue
                stored = pq.ParquetFile(fh)
                have = set(stored.schema_arrow.names)
                rows = stored.read(columns=[c for c in columns if c in have]).to_pylist()
                for row in rows:
                    out.append({c: row.get(c) for c in columns})
        return out

    def table(self):
        """All rows as one ``pyarrow.Table`` (columns unified; a column missing from a file is
        null there)."""
        pa, _ = _arrow()
        rows = self.rows()
        return pa.Table.from_pylist(rows) if rows else pa.table({c: [] for c in META_COLUMNS})

    def ids(self, *, include_failed: bool = True) -> set[str]:
        """The stored scenes a resume does not run again: those that ended (``ok``), and
        those that failed unless not ``include_failed``; never a :class:`Stopped` one."""
        _, pq = _arrow()
        keep = {"ok", "failed"} if include_failed else {"ok"}
        out: set[str] = set()
        for f in self.files():
            with open(f, "rb") as fh:
                t = pq.read_table(fh, columns=["scene_id", "status"])
            out.update(sid for sid, st in zip(t.column("scene_id").to_pylist(),
                                              t.column("status").to_pylist()) if st in keep)
        return out

    def by_id(self, columns: Iterable[str] | None = None) -> dict[str, dict]:
        """scene id -> row (the last stored row if a scene was re-run with ``retry_failed``);
        ``columns``: as :meth:`rows` (``scene_id`` always)."""
        if columns is not None:
            columns = ["scene_id", *(c for c in columns if c != "scene_id")]
        return {r["scene_id"]: r for r in self.rows(columns)}

    def outcomes(self, tasks: Iterable[dict], key: str) -> list:
        """The outcome ``key`` of each task, in the tasks' order (None if absent or failed)."""
        rows = self.by_id()
        out = []
        for t in tasks:
            r = rows.get(scene_id(t))
            out.append(None if r is None or r.get("status") != "ok" else r.get(key))
        return out

    def write_batch(self, rows: list[dict]) -> Path | None:
        """Write ``rows`` as one new Parquet file, atomically (temporary name, then rename)."""
        if not rows:
            return None
        pa, pq = _arrow()
        self.results.mkdir(parents=True, exist_ok=True)
        # named in the order written (to the nanosecond: a resume's rows of a scene re-run
        # in the same second as its stopped row come after it), as :meth:`rows` reads them
        name = f"batch-{time.time_ns():020d}-{os.getpid()}-{uuid.uuid4().hex[:8]}"
        final = self.results / f"{name}.parquet"
        tmp = self.results / f".{name}.parquet.tmp"
        table = pa.Table.from_pylist(_uniform(rows))
        try:
            with open(tmp, "wb") as fh:  # a path's undecodable bytes: pyarrow takes UTF-8 only
                pq.write_table(table, fh)
            os.replace(tmp, final)
        except BaseException:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)
            raise
        return final

    def clean_temporaries(self) -> int:
        """Remove temporaries a killed writer left behind (never a whole file)."""
        n = 0
        for p in self.dir.glob(f".{STUDY_NAME}.*.tmp"):
            with contextlib.suppress(FileNotFoundError):
                p.unlink()
                n += 1
        if self.results.is_dir():
            for p in self.results.glob(".*.tmp"):
                with contextlib.suppress(FileNotFoundError):
                    p.unlink()
                    n += 1
        return n


def _arrow():
    """pyarrow and its Parquet module, on the system's allocator: pyarrow's own (mimalloc)
    crashed the process writing a batch under an address-space limit (ulimit -v); a library
    that cannot load under the process's limits is a :class:`LimitError`."""
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
    """Rows with the same keys (missing -> None) and ints that are also floats elsewhere as
    floats, so pyarrow finds one type per column."""
    keys: list[str] = list(META_COLUMNS)
    for r in rows:
        for k in r:
            if k not in keys:
                keys.append(k)
    floaty = {k for k in keys for r in rows if isinstance(r.get(k), float)}
    out = []
    for r in rows:
        row = {}
        for k in keys:
            v = r.get(k)
            if k in floaty and isinstance(v, int) and not isinstance(v, bool):
                v = float(v)
            row[k] = v
        out.append(row)
    return out


# =============================================================================== running


def _plain(v):
    if v is None or isinstance(v, (bool, int, float, str)):
        return v
    if hasattr(v, "item"):
        return v.item()
    return str(v)


def _call(fn: Callable[[dict], dict], task: dict) -> dict:
    """On the worker: run one task; an exception becomes a failed row, not a crash."""
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
        tb = traceback.format_exception_only(type(out), out)[-1].strip()
        row = {"status": "failed", "error": tb}
    elif not isinstance(out, dict):
        row = {"status": "failed", "error": f"TypeError: fn returned {type(out).__name__}, "
                                            "not a dict"}
    else:
        row = {f"{k}": _plain(v) for k, v in out.items() if k not in META_COLUMNS}
        row.update(status="ok", error=None)
    row["run_s"] = run_s
    row["worker"] = f"{os.uname().nodename}:{os.getpid()}"
    return row


def _call_many(fn: Callable, tasks: list[dict], many: bool = False) -> list[dict]:
    """On the worker: a batch of tasks, one row each.  ``many``: ``fn`` takes the whole list
    and returns one dict (or the exception that ended it) per task, in order; a batch it
    cannot take as a whole (it raised, or answered the wrong count) runs again one task at a
    time (``fn([task])``), so that one bad task fails alone.  A row's ``run_s`` is then the
    batch's time shared evenly."""
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
    """In a worker process of the embedded runner, once its first batch is done: what the
    process holds for good by then (the modules its first batch imported) is put
    out of the garbage collector's way (``gc.freeze``), whose full collections went through
    every one of those objects again and again while the scenes ran; what the scenes make is
    collected as before (the costs, and why the allocator's memory is not given back after
    each batch: docs/scale.md)."""
    if _SETTLED or not os.environ.get(SPAWNED_WORKER_ENV):
        return
    _SETTLED.append(True)
    gc.collect()
    gc.freeze()


def _only(outs):
    """The one answer of a batch function called with one task."""
    (out,) = outs
    if isinstance(out, Exception):
        raise out
    return out


#: Most scenes in one batch (:func:`batch_size`): a worker holds one batch's solver records
#: at a time (their size a scene: docs/scale.md, "Batches"), and the embedded runner's cost a
#: batch is a pickle and a pipe's round trip
BATCH_TASK_MAX = 16


def batch_size(scenes: int, workers: int) -> int:
    """Scenes per batch: about four batches per worker, so that the cost per batch (a Dask
    scheduler's: about a millisecond) is paid seldom while every worker still has work to the
    end, and a batch whose worker dies costs at most :data:`BATCH_TASK_MAX` scenes run again:
    ``ceil(scenes / (4 workers))`` clipped to 1 .. :data:`BATCH_TASK_MAX`."""
    return max(1, min(BATCH_TASK_MAX, math.ceil(scenes / (4 * max(1, workers)))))


class _Bar:
    """The package's progress display (:func:`deck_emulator.parallel.progress_bar`) with a
    count of failed scenes; ``enabled=False`` silences it."""

    def __init__(self, total: int, initial: int, desc: str, enabled: bool | None,
                 eta: bool = True):

        self.failed = 0
        # no time left shown where the scenes' costs differ and the costliest go first: the
        # rate of the first ones says nothing of the rest (it said 5 min for a 55 s study)
        shape = {} if eta else {"bar_format": "{l_bar}{bar}| {n_fmt}/{total_fmt} "
                                              "[{elapsed}{postfix}]"}
        self.bar = progress_bar(total, desc=desc, unit="scene", quiet=enabled is False,
                                initial=initial, dynamic_ncols=True, smoothing=0.1, **shape)

    def step(self, failed: bool):
        self.failed += failed
        self.bar.set_postfix(failed=self.failed, refresh=False)
        self.bar.update(1)

    def close(self):
        self.bar.close()


@contextlib.contextmanager
def _client(scheduler: str, worker_wait_s: float = WORKER_WAIT_S):
    """A Dask client of the cluster at ``scheduler`` (its own: left running), once it has a
    worker."""
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
        yield client
    finally:
        with contextlib.suppress(Exception):
            client.close()


@contextlib.contextmanager
def _pool(n: int, core: bool):
    """The embedded runner's ``n`` workers (:class:`~.local_pool.WorkerPool`), started in a
    folder that exists, within the open-file limit; ended on the way out, however it goes."""
    from deck_emulator.studies.local_pool import WorkerPool

    _files_for(n)
    try:  # the workers start in this process's folder: a deleted one failed every start
        os.getcwd()
    except FileNotFoundError:
        os.chdir(tempfile.gettempdir())  # a relative path named nothing already
        # '' on the import path meant the deleted folder: a worker would get it as None
        sys.path[:] = [entry for entry in sys.path if entry != ""]
    pool = WorkerPool(n, core=core)
    try:
        pool.__enter__()
    except Exception as exc:  # noqa: BLE001 - no process could start: the machine's limits
        raise LimitError(_no_workers(n, exc)) from None
    try:
        yield pool
    finally:
        pool.close()


def _files_for(n: int) -> None:
    """:class:`ClusterError` when the open-file limit cannot hold ``n`` workers (they failed
    to start one by one, each with a traceback: the rows ``POOL_FILES``, ``POOL_WORKER_FILES``
    of :mod:`deck_emulator.vocabulary.defaults`)."""
    soft = resource.getrlimit(resource.RLIMIT_NOFILE)[0]
    try:
        now = len(os.listdir("/proc/self/fd"))
    except OSError:  # no /proc: the limit is checked as the workers start
        return
    need = now + defaults.POOL_FILES + defaults.POOL_WORKER_FILES * n
    if soft != resource.RLIM_INFINITY and soft < need:
        fit = (soft - now - defaults.POOL_FILES) // defaults.POOL_WORKER_FILES
        raise LimitError(f"the open-file limit ({soft}, ulimit -n) is too low for {n} "
                           f"worker process(es), which need about {need}: "
                           + (f"give --jobs {fit}, or " if fit >= 1 else "")
                           + f"raise it (ulimit -n {max(need, 1024)})")


def _no_workers(n: int, exc: BaseException) -> str:
    """Why ``n`` workers did not start, in one line: the limits they may have hit."""
    return _cannot_load(f"{n} worker process(es)", exc, "or give fewer --jobs")


def _cannot_load(what: str, exc: BaseException, also: str = "") -> str:
    why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    limits = ", ".join(process_limits())
    return (f"could not start {what} ({why[:160]})" + (f" under the limits of {limits}: raise "
            f"them{', ' + also if also else ''}" if limits else f": {also or 'free memory'}"))


def _reach(address: str) -> None:
    """:class:`ClusterError` in one line unless a Dask scheduler answers at ``address`` by a
    scheme this install serves: Dask's public ``distributed.comm.connect`` (its connection
    bounded by ``SCHEDULER_CONNECT_S``), the whole handshake by twice that (Dask leaves the
    handshake unbounded: a port that accepts and says nothing held a sweep for ever, one that
    answers HTTP a traceback), then the scheduler's "identity".  An in-process address
    (``inproc://``) is this process's own cluster: not asked."""
    import asyncio
    import concurrent.futures

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
        # the TCP connection first, once: a port nobody listens on refuses at once, whatever
        # the machine's load (Dask's connect retries a refusal until its time-out, and then
        # says a refusal or a time-out by which attempt the bound cut)
        try:
            with socket.create_connection(parse_host_port(location), timeout=bound):
                pass
        except ConnectionRefusedError as exc:
            raise ClusterError(f"{where}: nothing listens there ({exc})") from None
        except TimeoutError:
            raise ClusterError(f"{where}: no connection in {bound:g} s") from None
        except (OSError, ValueError) as exc:  # no such host, no route, not HOST:PORT
            raise ClusterError(f"{where}: nothing listens there ({exc})") from None

    async def identity():  # Dask's connection and handshake, then the scheduler's "identity"
        comm = await connect(address, timeout=bound, deserialize=True, **args)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    async def bounded():
        return await asyncio.wait_for(identity(), 2 * bound)

    with concurrent.futures.ThreadPoolExecutor(1) as pool:  # its own event loop, in any caller
        try:
            who = pool.submit(asyncio.run, bounded()).result()
        except asyncio.TimeoutError:  # connected (else connect says so), then nothing
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


def run_scenes(
    tasks: list[dict],
    fn: Callable[[dict], dict],
    *,
    store_dir: str | os.PathLike,
    jobs: int | None = None,
    scheduler: str | Scheduler | None = None,
    resume: bool = False,
    desc: str = "scenes",
    progress: bool | None = None,
    retry_failed: bool = False,
    flush_s: float = 1.0,
    chunk: int | None = None,
    max_scenes: int = MAX_SCENES,
    worker_wait_s: float = WORKER_WAIT_S,
    eta: bool = True,
    many: bool = False,
    core: bool = False,
) -> SceneStore:
    """Run every task not yet in the store with ``fn`` on worker processes and store each
    result.

    ``fn`` must be importable by the workers (a module-level function); it gets the task dict
    and returns a flat dict of plain values. ``jobs``: workers of the embedded runner (default:
    all cores); ignored when ``scheduler`` (a Dask scheduler's address) is given. ``resume``: run only the tasks
    whose :func:`scene_id` is not stored yet; without it, a store that already holds results is
    refused (:class:`StoreError`) rather than mixed with. ``chunk``: scenes per batch
    (default: :func:`batch_size` of the scenes to run and the workers; a batch whose
    worker dies is run again whole); each scene is still stored, counted and resumed on its
    own. ``many``: ``fn`` takes a task's whole batch, a list of task dicts, and returns one
    dict (or exception) per task, in order (:func:`_call_many`): how a batch of core scenes
    reaches ``CoreEngine.run_batch`` in one call.
    ``max_scenes``, ``worker_wait_s``: the bounds of the module docstring.  The store folder is
    locked for the call (:class:`StoreBusy` when another process holds it). ``eta``: show
    the time left on the progress bar (not for tasks of unequal cost run costliest first).
    ``core``: the tasks run the compiled core, which the embedded runner's workers then share
    (:mod:`~deck_emulator.studies.local_pool`).  Returns the :class:`SceneStore`.
    """
    if isinstance(scheduler, Scheduler):
        scheduler, worker_wait_s = scheduler.address, scheduler.worker_wait_s
    if len(tasks) > max_scenes:
        raise SceneLimitError(f"{len(tasks)} scenes asked for; at most {max_scenes} in one run")
    made = _missing_folders(store_dir)
    try:
        with store_lock(store_dir):
            return _run_locked(tasks, fn, store_dir=store_dir, jobs=jobs, scheduler=scheduler,
                               resume=resume, desc=desc, progress=progress,
                               retry_failed=retry_failed, flush_s=flush_s, chunk=chunk,
                               worker_wait_s=worker_wait_s, eta=eta, many=many, core=core)
    except BaseException:
        _remove_if_unused(made)  # a run that stored nothing leaves no folder behind
        raise


def _missing_folders(folder) -> list[Path]:
    """The folders from ``folder`` up that do not exist yet (the deepest first)."""
    missing = []
    path = Path(folder).absolute()
    while not path.exists():
        missing.append(path)
        path = path.parent
    return missing


def _remove_if_unused(folders: list[Path]) -> None:
    """Remove the folders a failed run made, deepest first, while each holds nothing but its
    lock file, what its scenes were to be made from and an empty results folder (a stored
    scene keeps it: --resume runs the rest)."""
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


def _workers(client) -> int:
    """How many workers the client's scheduler has now. A question the scheduler cannot answer
    because it is gone (Dask's CommClosedError and time-outs are OSErrors) counts as none: the
    caller then waits for workers and ends in an error that says so; any other failure is
    raised."""
    try:
        return len(client.nthreads())
    except OSError:
        return 0


def _run_locked(tasks, fn, *, store_dir, jobs, scheduler, resume, desc, progress, retry_failed,
                flush_s, chunk, worker_wait_s, eta=True, many=False, core=False) -> SceneStore:
    from deck_emulator.studies.local_pool import BatchError, WorkerDied

    store = SceneStore(store_dir)
    store.dir.mkdir(parents=True, exist_ok=True)
    store.clean_temporaries()
    done_ids = store.ids(include_failed=not retry_failed)
    if done_ids and not resume:
        raise StoreError(
            f"{store.results} already holds {len(done_ids)} scene(s): resume, or use a new folder"
        )
    unique: dict[str, dict] = {}
    texts: dict[str, str] = {}  # scene id -> the task as canonical JSON (stored with its row)
    for t in tasks:
        text = _canonical(t)
        sid = _id_of(text)
        if sid not in unique:
            unique[sid], texts[sid] = t, text
    _check_study(store.dir, _made_from(unique), store.ids() if resume else set(), unique)
    todo = [(sid, t) for sid, t in unique.items() if sid not in done_ids]
    bar = _Bar(len(unique), len(unique) - len(todo), desc, progress, eta=eta)
    if not todo:
        bar.close()
        return store

    pending: list[dict] = []
    last = time.monotonic()

    def flush():
        nonlocal last
        if pending:
            # taken out of pending before the write: a Ctrl-C inside it loses the batch (it
            # runs again on resume) but can never have the finally's flush store it twice
            batch = pending[:]
            pending.clear()
            store.write_batch(batch)
        last = time.monotonic()

    def completed(client, ac):
        """The futures as they complete; a run whose every worker has been gone for
        ``worker_wait_s`` ends (RunFailed) instead of waiting for ever."""
        alone_since = None
        checked = time.monotonic()
        while not ac.is_empty():
            if ac.has_ready():
                yield from ac.next_batch(block=False)
                alone_since = None
                continue
            time.sleep(0.05)
            now = time.monotonic()
            if now - checked < 1.0:
                continue
            checked = now
            if _workers(client):
                alone_since = None
            elif alone_since is None:
                alone_since = now
            elif now - alone_since >= worker_wait_s:
                raise RunFailed(f"every worker of the scheduler at {scheduler} is gone ("
                                f"{worker_wait_s:g} s without one) with {len(futures)} "
                                "task(s) left: the scenes completed are stored; --resume "
                                "runs the rest")

    def keep(group, rows):
        for (sid, _), row in zip(group, rows):
            row["scene_id"] = sid
            row["task_json"] = texts[sid]
            row["stored_at"] = time.time()
            pending.append(row)
            bar.step(row["status"] != "ok")
        if len(pending) >= BATCH_MAX or time.monotonic() - last >= flush_s:
            flush()

    def failed(group, exc):
        return [{"status": "failed", "error": str(exc) if isinstance(exc, (WorkerDied,
                 BatchError)) else f"{type(exc).__name__}: {exc}", "run_s": None,
                 "worker": None} for _ in group]

    try:
        if not scheduler:  # the embedded runner: worker processes forked from a loaded core
            n = max(1, int(jobs or os.cpu_count() or 1))
            size = batch_size(len(todo), n) if chunk is None else max(1, int(chunk))
            groups = [todo[k : k + size] for k in range(0, len(todo), size)]
            with _pool(n, core) as pool:
                for k, answer in pool.run((k, (_call_many, (fn, [t for _, t in g], many)))
                                          for k, g in enumerate(groups)):
                    keep(groups[k], failed(groups[k], answer)
                         if isinstance(answer, Exception) else answer)
            return store
        with _client(scheduler, worker_wait_s) as client:
            from distributed import as_completed

            futures = {}
            size = (batch_size(len(todo), _workers(client) or 1) if chunk is None
                    else max(1, int(chunk)))
            for k in range(0, len(todo), size):
                group = todo[k : k + size]
                fut = client.submit(_call_many, fn, [t for _, t in group], many,
                                    key=f"scenes-{group[0][0]}-{len(group)}", pure=False)
                futures[fut] = group
            for fut in completed(client, as_completed(list(futures))):
                group = futures.pop(fut)
                try:
                    rows = fut.result()
                except Exception as exc:  # noqa: BLE001 - KilledWorker and the like
                    rows = failed(group, exc)
                keep(group, rows)
                fut.release()
    finally:
        flush()  # Ctrl-C or any error: what has completed is stored
        bar.close()
    return store


def run_longest_first(fn, tasks: list[dict], *, jobs: int | None, desc: str, store_dir,
                      quiet: bool = False, scheduler: str | Scheduler | None = None,
                      resume: bool = False, worker_wait_s: float = WORKER_WAIT_S,
                      many: bool = False, core: bool = False) -> list[dict]:
    """``[fn(t) for t in tasks]`` on the one scene runner
    (:func:`deck_emulator.studies.distributed.run_scenes`: the embedded runner's ``jobs``
    workers, or the Dask cluster at ``scheduler``), the costliest tasks (their ``cost``) submitted first
    so that no long run is left for last, every row stored in ``store_dir`` as it finishes
    (``resume``: only the tasks not stored yet run; ``None``: a temporary folder, gone at the
    end; ``worker_wait_s``: as :func:`run_scenes`); rows in the tasks' order. A row travels
    as JSON (its arrays as lists). A task that could not run (its ``fn`` raised, its worker
    died) is an error naming it: a study cannot make its tables without it.  ``many``: ``fn``
    takes a list of tasks and returns one row (or exception) per task, as :func:`run_scenes`'s
    ``many`` (the studies' core scenes reach ``CoreEngine.run_batch`` so); ``core``: as
    :func:`run_scenes`'s."""

    order = sorted(tasks, key=lambda t: -t["cost"])
    with temporary_store("scenes-") as tmp:
        store = run_scenes(order, functools.partial(_json_rows if many else _json_row, fn),
                           store_dir=tmp if store_dir is None else store_dir, jobs=jobs,
                           scheduler=scheduler, resume=resume, desc=desc,
                           progress=False if quiet else None, worker_wait_s=worker_wait_s,
                           eta=False, many=many, core=core)
        stored = store.by_id()
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
    """A temporary folder for a store no one asked to keep (``tempfile.TemporaryDirectory``),
    after removing those of earlier runs killed with SIGKILL: a ``prefix`` folder of the
    temporary folder older than a minute whose lock no process holds (:func:`store_lock`,
    held here for the block)."""
    home = Path(tempfile.gettempdir())
    for old in home.glob(f"{prefix}*"):
        with contextlib.suppress(OSError):
            if time.time() - old.stat().st_mtime < 60 or old.is_symlink() or not old.is_dir():
                continue
            fd = os.open(old / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o666)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # BlockingIOError: in use
                shutil.rmtree(old)
            finally:
                os.close(fd)
    with tempfile.TemporaryDirectory(prefix=prefix) as tmp, store_lock(tmp):
        yield tmp


def _label(task: dict) -> str:
    return ", ".join(f"{k} {task[k]}" for k in ("kind", "column", "post", "variant", "engine",
                                                 "series", "label", "k",
                                                 "method", "rtol") if task.get(k) is not None)


def _json_row(fn, task: dict) -> dict:
    """On a worker: one task's row as JSON (numpy arrays and scalars as plain values)."""
    return {"row_json": json.dumps(fn(task), default=_plain_json)}


def _json_rows(fn, tasks: list[dict]) -> list:
    """On a worker: a batch's rows as JSON, by one call of ``fn`` on the batch (an exception
    in its answer stays the failure of its task)."""
    return [out if isinstance(out, Exception) else
            {"row_json": json.dumps(out, default=_plain_json)} for out in fn(tasks)]


def _plain_json(v):
    if hasattr(v, "tolist"):  # numpy arrays and scalars
        return v.tolist()
    raise TypeError(f"{type(v).__name__} is not a plain value")
