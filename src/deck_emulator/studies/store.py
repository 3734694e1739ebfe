"""The scene store: what :func:`~deck_emulator.studies.distributed.run_scenes` keeps.

``store_dir/results/*.parquet``, written by the client alone (remote workers need no shared
file system), one file per write, each under a temporary name then renamed: a file is whole or
absent, and a finished one is never rewritten.  After ``kill -9`` at most the last writes'
results are lost and run again on resume; no scene is stored twice.  A scene's id is
:func:`scene_id` (SHA-256 of the task as canonical JSON).  ``study.json`` keeps the SHA-256 of
every file a task names, so that a resume of a store made from another deck, grid or engine is
refused (:class:`StudyChanged`).  A store folder is locked (``flock``) by the process that uses
it (:class:`StoreBusy` for another); the kernel drops the lock however the process ends.
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import math
import os
import shutil
import time
import traceback
import uuid
from collections.abc import Iterable
from pathlib import Path

from deck_emulator.errors import UsageError, process_limits
from deck_emulator.vocabulary.defaults import SCENE_STORE

#: Columns every stored row has, before the outcome columns ``fn`` returns.
META_COLUMNS = ("scene_id", "task_json", "status", "error", "worker", "run_s", "stored_at")
RESULTS = "results"
LOCK_NAME = ".lock"
STUDY_NAME = "study.json"


class StoreError(UsageError, RuntimeError):
    """A store that cannot be used as asked: bad input, exit status 2, nothing run."""


class StudyChanged(StoreError):
    """A resume asked of a store made for another study."""


class StoreBusy(StoreError):
    """Another live process holds the store folder."""


class Stopped(Exception):
    """A scene stopped at a bound of the machine, not of the model (a core run past its wall
    time): stored ``stopped``, run again on resume."""


class LimitError(UsageError, RuntimeError):
    """The process's limits keep a worker or a library from starting: exit 2."""


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


def _check_study(store_dir: Path, unique: dict[str, dict], stored: set[str],
                 files_read: dict[str, str] | None = None) -> None:
    """Keep what the store's scenes are made from; on a resume (``stored``: its scenes' ids),
    :class:`StudyChanged` when a file the tasks name changed, or no stored scene is asked.
    ``files_read``: the SHA-256 of the files the tasks name, by the caller who read them
    (None: each file is read here)."""
    path = store_dir / STUDY_NAME
    named = _named_files(unique.values()) if files_read is None else dict(files_read)
    made_from = {"files": named, "scenes": len(unique)}
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
        if columns is not None:
            got = self.columns(columns)
            return [dict(zip(got, values)) for values in zip(*got.values())]
        pq = _arrow()[1]
        out: list[dict] = []
        for f in self.files():
            with open(f, "rb") as fh:
                out.extend(pq.read_table(fh).to_pylist())
        return out

    def columns(self, names: Iterable[str]) -> dict[str, list]:
        """The stored values of the columns ``names``, each a list in the order written
        (None where a file lacks the column)."""
        pq = _arrow()[1]
        out: dict[str, list] = {c: [] for c in names}
        for f in self.files():
            with open(f, "rb") as fh:
                stored = pq.ParquetFile(fh)
                have = set(stored.schema_arrow.names)
                got = stored.read(columns=[c for c in out if c in have]).to_pydict()
                n = stored.metadata.num_rows
            for c, values in out.items():
                values.extend(got[c] if c in got else [None] * n)
        return out

    def ids(self) -> set[str]:
        """The scenes a resume does not run again: ended or failed; never a stopped one."""
        return {r["scene_id"] for r in self.rows(("scene_id", "status"))
                if r["status"] in ("ok", "failed")}

    def by_id(self, columns: Iterable[str] | None = None) -> dict[str, dict]:
        """scene id -> its last stored row (``columns``: as :meth:`rows`)."""
        if columns is not None:
            columns = ["scene_id", *(c for c in columns if c != "scene_id")]
        return {r["scene_id"]: r for r in self.rows(columns)}

    def write_batch(self, rows: list[dict]) -> Path | None:
        """``rows`` as one new Parquet file, named in the order written: a column a key of
        any row (None where a row lacks it; a column of ints and floats is of floats)."""
        if not rows:
            return None
        self.results.mkdir(parents=True, exist_ok=True)
        name = f"batch-{time.time_ns():020d}-{os.getpid()}-{uuid.uuid4().hex[:8]}.parquet"
        keys = dict.fromkeys([*META_COLUMNS, *(k for r in rows for k in r)])
        table = _arrow()[0].Table.from_pydict({k: [r.get(k) for r in rows] for k in keys})
        _write_atomic(self.results / name, None, table)
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


def _cannot_load(what: str, exc: BaseException, also: str = "") -> str:
    why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    limits = ", ".join(process_limits())
    return (f"could not start {what} ({why[:160]})" + (f" under the limits of {limits}: raise "
            f"them{', ' + also if also else ''}" if limits else f": {also or 'free memory'}"))


def _plain(v):
    if v is None or isinstance(v, (bool, int, float, str)):
        return v
    return v.item() if hasattr(v, "item") else str(v)


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
