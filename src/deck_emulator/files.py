"""Files written whole or not at all: the one writer of the package."""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import tempfile
from pathlib import Path


class OutputError(OSError):
    """An output that cannot be written; the message names the user's path."""


def check_output_file(path) -> None:
    """Before any work: ``path``'s folder exists and is writable, and ``path`` is no folder."""
    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    if target.is_dir():
        raise OutputError(f"{path}: is a directory")
    if not parent.is_dir():
        raise OutputError(f"{path}: no such directory: {parent}")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"{path}: directory not writable: {parent}")


def check_output_dir(path) -> None:
    """Before any work: ``path`` is a writable folder, or can be made in a writable one."""
    target = Path(path)
    if target.exists():
        if not target.is_dir():
            raise OutputError(f"{path}: not a directory")
        if not os.access(target, os.W_OK | os.X_OK):
            raise OutputError(f"{path}: directory not writable")
        return
    check_output_file(target)


def write_file(path, data: str | bytes) -> None:
    """Write ``data`` to ``path``: a regular file (or a new path) through a temporary file in
    the same folder and a rename; an existing special file (a device, a FIFO) as a stream,
    never replaced."""
    target = Path(path)
    raw = data.encode() if isinstance(data, str) else data
    with contextlib.suppress(FileNotFoundError):
        mode = os.stat(target).st_mode
        if not stat.S_ISREG(mode) and not stat.S_ISDIR(mode):
            with open(target, "wb") as fh:
                fh.write(raw)
            return
    check_output_file(target)
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(raw)
            fh.flush()
            os.fsync(fh.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, target.resolve() if target.is_symlink() else target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


write_atomic = write_file


class OutputSet:
    """A set of output files moved into place together when the block ends without error."""

    def __init__(self, directory=None):
        self.directory = Path(directory) if directory is not None else None
        self._staged: dict[Path, Path] = {}
        self._tmp = None

    def __enter__(self):
        base = self.directory.parent if self.directory is not None else Path(".")
        self._tmp = Path(tempfile.mkdtemp(dir=base if base.is_dir() else None, prefix=".staging."))
        return self

    def _target(self, name) -> Path:
        p = Path(name)
        return self.directory / p if self.directory is not None and not p.is_absolute() else p

    def path(self, name) -> Path:
        target = self._target(name)
        staged = self._tmp / f"{len(self._staged)}-{target.name}"
        self._staged[target] = staged
        return staged

    def write(self, name, data: str | bytes) -> None:
        raw = data.encode() if isinstance(data, str) else data
        self.path(name).write_bytes(raw)

    def __exit__(self, exc_type, exc, tb):
        try:
            if exc_type is None:
                if self.directory is not None:
                    self.directory.mkdir(parents=True, exist_ok=True)
                for target, staged in self._staged.items():
                    write_file(target, staged.read_bytes())
        finally:
            shutil.rmtree(self._tmp, ignore_errors=True)
        return False
