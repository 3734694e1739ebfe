"""The one writer for every file the package and its scripts write: whole or not at all, and
never at the cost of something that is not ours.

Outputs are checked before any work (:func:`check_output_file`, :func:`check_output_dir`,
:func:`check_distinct`: a missing or read-only folder fails at once, naming the user's path),
then written by :func:`write_file` (one file) or an :class:`OutputSet` (several, committed as
one unit).  An existing device or FIFO (``/dev/null``, a named pipe) is written as a stream,
never replaced: it is not ours to replace.  A symbolic link is written *through*, as the
shell's ``>`` does, and stays a link (replacing it would destroy something that is not ours).
Permissions are those ``open(path, "w")`` would give: an existing file keeps its mode (and, if
we may, its owner and group); a new file gets ``0o666 & ~umask``.

Temporary names are hidden (``.NAME.~PID.XXXX.part...``) and carry the writer's process id: a
later writer into the same folder removes those a killed process left (SIGINT and SIGTERM
leave none: :mod:`deck_emulator.signals`).
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import os
import re
import shutil
import stat
import tempfile
import time
from pathlib import Path

from deck_emulator.signals import held

__all__ = [
    "OutputError",
    "OutputSet",
    "check_output_dir",
    "check_output_file",
    "check_distinct",
    "write_file",
]

_MARK = ".~"  # between a hidden name and the writer's pid in temporary names
_STALE = re.compile(r"^\..*\.~(\d+)\.[A-Za-z0-9_]+\.part")


class OutputError(OSError):
    """An output cannot be written; the message names the user's path, never a temporary."""

    def __init__(self, path, reason: str, errno_: int | None = None):
        self.path = str(path)
        self.reason = reason
        super().__init__(errno_ or 0, f"cannot write {path}: {reason}")
        self.filename = str(path)

    def __str__(self) -> str:
        return f"cannot write {self.path}: {self.reason}"


def _reason(exc: OSError) -> str:
    return exc.strerror or str(exc)


# --------------------------------------------------------------------------- checks


def _is_stream(st: os.stat_result) -> bool:
    """Existing outputs written as a stream, never replaced: anything but a regular file or a
    folder (character and block devices, FIFOs, sockets)."""
    return not stat.S_ISREG(st.st_mode) and not stat.S_ISDIR(st.st_mode)


def _resolve(path: Path) -> Path:
    """The path a write lands on: a symbolic link is followed to its target."""
    if path.is_symlink():
        return Path(os.path.realpath(path))
    return path


def _check_folder(folder: Path, user_path) -> None:
    if not folder.exists():
        raise OutputError(user_path, f"the folder {folder} does not exist", errno.ENOENT)
    if not folder.is_dir():
        raise OutputError(user_path, f"{folder} is not a folder", errno.ENOTDIR)
    if not os.access(folder, os.W_OK | os.X_OK):
        # access(2) answers for this user and for a read-only file system (EROFS, even for root)
        raise OutputError(user_path, f"the folder {folder} is not writable", errno.EACCES)


def _not_empty(path) -> None:
    """An empty path names nothing (``Path("")`` is the current folder): refused."""
    if os.fspath(path) in ("", b""):
        raise OutputError("''", "an empty path names no file or folder", errno.ENOENT)


def check_output_file(path) -> None:
    """Fail now (:class:`OutputError`) if ``path`` cannot be written later: its folder must
    exist and be writable and it must not be a folder.  An existing special file (character
    device, FIFO) is fine if writable; a symbolic link is checked at its target."""
    user = path
    _not_empty(path)
    target = _resolve(Path(path))
    st = _existing(target, user)
    if st is not None and _is_stream(st):
        if not os.access(target, os.W_OK):
            raise OutputError(user, "permission denied", errno.EACCES)
        return
    _check_folder(target.parent if str(target.parent) else Path("."), user)


def check_distinct(*paths) -> None:
    """Fail now (:class:`OutputError`) when two of a command's outputs name one file (the
    same path, or two paths that resolve to one file: a link, ``./x`` and ``x``); ``None``
    entries (an output not asked for) are skipped.  Special files (``/dev/null``) may be
    named twice: they are streams, not files replaced."""
    seen: dict[str, object] = {}
    for p in paths:
        if p is None:
            continue
        _not_empty(p)
        real = os.path.realpath(p)
        try:
            if _is_stream(os.stat(real)):
                continue
        except OSError:
            pass
        if real in seen:
            raise OutputError(p, f"it names the same file as {seen[real]}: two outputs "
                              "cannot share a path", errno.EEXIST)
        seen[real] = p


def check_output_dir(path) -> None:
    """Fail now (:class:`OutputError`) unless ``path`` is a writable folder, or does not exist
    and its parent is a writable folder (it will be created)."""
    _not_empty(path)
    p = Path(path)
    if p.exists():
        if not p.is_dir():
            raise OutputError(path, "it exists and is not a folder", errno.ENOTDIR)
        if not os.access(p, os.W_OK | os.X_OK):
            raise OutputError(path, "the folder is not writable", errno.EACCES)
        return
    _check_folder(p.absolute().parent, path)


# --------------------------------------------------------------------------- helpers


def _umask() -> int:
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _remove_stale(folder: Path) -> None:
    """Remove temporaries (files or staging folders) left in ``folder`` by a writer of ours
    that no longer runs (killed with SIGKILL).  Only our own naming pattern is touched."""
    try:
        names = os.listdir(folder)
    except OSError:
        return
    for name in names:
        m = _STALE.match(name)
        if not m or _alive(int(m.group(1))):
            continue
        p = folder / name
        with contextlib.suppress(OSError):
            if p.is_dir() and not p.is_symlink():
                shutil.rmtree(p)
            else:
                p.unlink()


_OWN_TEMP: list[str] = []  # this process's own temporary folder, once made
_SOCKET_PATH = 108  # the longest path of a Unix socket, bytes, with its NUL (Linux's sun_path)


def own_temp_folder() -> str:
    """A folder of this command's own for the temporary files of the libraries it runs
    (multiprocessing's ``pymp-*`` with the forkserver's socket): ``<temp>/deck_emulator-<uid>/
    <pid>``, removed when the command exits (:func:`remove_own_temp_folder`, called by the
    command line after every other exit handler) and, after a SIGKILL, by the next command
    that makes one (the folders of processes that no longer run).  When ``deck_emulator-<uid>``
    is not a real folder of the user's that no one else may write, the system's temporary
    folder itself (as before)."""
    if _OWN_TEMP:
        return _OWN_TEMP[0]
    base = os.path.join(tempfile.gettempdir(), f"deck_emulator-{os.getuid()}")
    try:
        with contextlib.suppress(FileExistsError):
            os.mkdir(base, 0o700)
        st = os.lstat(base)
        if (not stat.S_ISDIR(st.st_mode) or st.st_uid != os.getuid()
                or st.st_mode & 0o022):
            return tempfile.gettempdir()
        for name in os.listdir(base):  # (left by a command killed with SIGKILL)
            if name.isdigit() and not _alive(int(name)):
                with contextlib.suppress(OSError):
                    shutil.rmtree(os.path.join(base, name))
        mine = os.path.join(base, str(os.getpid()))
        if len(os.fsencode(mine)) + len("/pymp-12345678/listener-12345678") >= _SOCKET_PATH:
            return tempfile.gettempdir()  # (a socket's path in it would be too long)
        with contextlib.suppress(FileExistsError):
            os.mkdir(mine, 0o700)
    except OSError:
        return tempfile.gettempdir()
    _OWN_TEMP.append(mine)
    return mine


def remove_own_temp_folder() -> None:
    """Remove this process's own temporary folder (:func:`own_temp_folder`), if made."""
    while _OWN_TEMP:
        mine = _OWN_TEMP.pop()
        with contextlib.suppress(OSError):
            for name in os.listdir(mine):
                if not name.startswith("pymp-"):  # (multiprocessing's: its own exit removes it)
                    shutil.rmtree(os.path.join(mine, name), ignore_errors=True)
        with contextlib.suppress(OSError):  # (left, with a pymp-* still in it, to the next)
            os.rmdir(mine)
            os.rmdir(os.path.dirname(mine))  # (the user's folder too, when no other holds it)


def _temp_prefix(name: str) -> str:
    """The hidden name of a temporary beside ``name``: the name cut to leave room for the
    pid, mkstemp's 8 characters and the suffix within a file name's 255 bytes, so that any
    legal name can be written."""
    room = 255 - len(f".{_MARK}{os.getpid()}.") - 8 - len(".part") - 16  # 16: an extension
    cut = os.fsencode(name)[:room].decode(errors="ignore") if len(os.fsencode(name)) > room \
        else name
    return f".{cut}{_MARK}{os.getpid()}."


def _fsync_dir(folder: Path) -> None:
    try:
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass  # some file systems cannot fsync a folder; the rename itself is still atomic
    finally:
        os.close(fd)


def _fsync_file(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _mode_as_open(tmp: Path, existing: os.stat_result | None) -> None:
    """Give ``tmp`` the permissions (and owner) that ``open(target, "w")`` would have left."""
    if existing is not None:
        os.chmod(tmp, stat.S_IMODE(existing.st_mode))
        if existing.st_uid != os.geteuid() or existing.st_gid != os.getegid():
            with contextlib.suppress(OSError):
                os.chown(tmp, existing.st_uid, existing.st_gid)
    else:
        os.chmod(tmp, 0o666 & ~_umask())


#: Longest wait (s) for a reader to open a FIFO named as an output.
FIFO_WAIT_S = 10.0


def _open_stream(target: Path, user) -> int:
    """A write descriptor on an existing special file.  A FIFO is opened without blocking,
    retried until a reader has it open, for at most :data:`FIFO_WAIT_S` (an ``open`` of a
    FIFO without a reader would block for ever)."""

    flags = os.O_WRONLY | getattr(os, "O_CLOEXEC", 0)
    try:
        fifo = stat.S_ISFIFO(os.stat(target).st_mode)
    except OSError as exc:
        raise OutputError(user, _reason(exc), exc.errno) from None
    deadline = time.monotonic() + FIFO_WAIT_S
    while True:
        try:
            fd = os.open(target, flags | (os.O_NONBLOCK if fifo else 0))
            break
        except OSError as exc:
            if fifo and exc.errno == errno.ENXIO and time.monotonic() < deadline:
                time.sleep(0.02)
                continue
            if fifo and exc.errno == errno.ENXIO:
                raise OutputError(user, f"no reader opened the FIFO in {FIFO_WAIT_S:g} s",
                                  errno.ENXIO) from None
            raise OutputError(user, _reason(exc), exc.errno) from None
    if fifo:  # a reader is there: write as usual, waiting when the pipe is full
        fcntl.fcntl(fd, fcntl.F_SETFL, fcntl.fcntl(fd, fcntl.F_GETFL) & ~os.O_NONBLOCK)
    return fd


def _stream_copy(src: Path, target: Path, user) -> None:
    fd = _open_stream(target, user)
    try:
        with open(src, "rb") as fh, os.fdopen(fd, "wb", closefd=False) as out:
            shutil.copyfileobj(fh, out, 1 << 20)
    except OSError as exc:
        raise OutputError(user, _reason(exc), exc.errno) from None
    finally:
        os.close(fd)


def _existing(target: Path, user) -> os.stat_result | None:
    try:
        st = os.stat(target)
    except FileNotFoundError:
        return None
    except OSError as exc:
        raise OutputError(user, _reason(exc), exc.errno) from None
    if stat.S_ISDIR(st.st_mode):
        raise OutputError(user, "it is a folder", errno.EISDIR)
    return st


def _as_bytes(data: str | bytes) -> bytes:
    """Text as UTF-8; a path's undecodable bytes in it (held as surrogates) as they were."""
    return data.encode(errors="surrogateescape") if isinstance(data, str) else bytes(data)


# --------------------------------------------------------------------------- one file


def write_file(path, data: str | bytes) -> None:
    """Write ``data`` (text is UTF-8 encoded) to ``path``, whole or not at all: a set of one
    (:class:`OutputSet`). A regular file or a new path is written to a temporary beside it,
    fsynced and renamed over the target, the folder fsynced (a reader, a crash or a kill sees
    the old file or the new one); a device or a FIFO is written as a stream (a FIFO no reader
    opens within :data:`FIFO_WAIT_S` is an error, not a wait for ever). Errors raise
    :class:`OutputError` naming ``path``."""
    _not_empty(path)
    with OutputSet() as files:
        files.write(path, data)


# --------------------------------------------------------------------------- a set of files


class OutputSet:
    """Several outputs committed as one unit.

    ::

        with OutputSet() as out:                       # files anywhere
            fig.savefig(out.path("fall.png"))          # a staging path for a library
            out.write("fall.txt", text)
        # here both are in place; after an exception neither was touched

        with OutputSet(directory="results") as out:    # a study's folder
            out.write("study.csv", csv_text)           # names relative to the folder
            fig.savefig(out.path("map.png"))

    Staging paths keep the target's suffix (matplotlib and Pillow choose the format from it).

    * Files anywhere (no ``directory``): each regular target is staged beside itself and, at the
      end of the ``with``, renamed over it as :func:`write_file` does; a special file (device,
      FIFO) target is staged in the system's temporary folder and streamed into it.
    * A **new** ``directory``: the files are staged in a hidden sibling folder which is
      renamed to ``directory`` at the end: the folder appears only with all its contents, and an
      interrupted run leaves no folder.
    * An **existing** ``directory``: the files are staged in a hidden folder inside it and
      renamed over their targets one after the other; files of the folder that the set does
      not name are left alone.  Each file is always old-whole or new-whole.  The set as a whole
      is old or new except in one window: the few ``rename()`` calls at the commit (micro-
      seconds).  SIGINT, SIGTERM and SIGHUP are held over that window, so only a SIGKILL or a
      power cut inside it can leave a mix of whole old and whole new files.  Closing it would
      take swapping the folder itself (``renameat2(RENAME_EXCHANGE)``), which would move files
      that are not ours and change the folder under anyone inside it; we do not do that.

    On an exception (including KeyboardInterrupt and :class:`deck_emulator.signals.Terminated`)
    nothing is moved and everything staged is removed.
    """

    def __init__(self, directory=None):
        self.directory = None if directory is None else Path(directory)
        self._staged: dict[Path, tuple[Path, object]] = {}  # staging path -> (target, user)
        self._order: list[Path] = []
        self._stage_dir: Path | None = None
        self._new_dir = False
        self._open = False

    # -- context manager

    def __enter__(self) -> OutputSet:
        if self.directory is not None:
            check_output_dir(self.directory)
            d = self.directory
            self._new_dir = not d.exists()
            home = d.absolute().parent if self._new_dir else d
            _remove_stale(home)
            try:
                self._stage_dir = Path(tempfile.mkdtemp(dir=home, prefix=_temp_prefix(d.absolute().name),
                                                        suffix=".part"))
            except OSError as exc:
                raise OutputError(self.directory, _reason(exc), exc.errno) from None
        self._open = True
        return self

    def __exit__(self, exc_type, exc, tb) -> bool:
        self._open = False
        if exc_type is not None:
            self._discard()
            return False
        try:
            self._commit()
        except BaseException:
            self._discard()
            raise
        return False

    # -- staging

    def _relative(self, target) -> Path:
        t = Path(target)
        if t.is_absolute():
            try:
                t = t.relative_to(self.directory.absolute())
            except ValueError:
                raise ValueError(f"{target} is not inside {self.directory}") from None
        if ".." in t.parts or not t.parts:
            raise ValueError(f"{target}: a name inside the output folder is needed")
        return t

    def path(self, target) -> Path:
        """A staging path for ``target`` (which a library may write to, with the same suffix);
        it is moved to ``target`` when the set commits."""
        if not self._open:
            raise RuntimeError("OutputSet.path() outside its with block")
        if self.directory is not None:
            rel = self._relative(target)
            stage = self._stage_dir / rel
            if stage in self._staged:
                return stage
            stage.parent.mkdir(parents=True, exist_ok=True)
            self._staged[stage] = (self.directory / rel, self.directory / rel)
            self._order.append(stage)
            return stage
        user = target
        real = _resolve(Path(target))
        for stage, (t, _) in self._staged.items():
            if t == real:
                return stage
        st = _existing(real, user)
        suffix = "".join(real.suffixes[-1:])
        if st is not None and _is_stream(st):
            fd, name = tempfile.mkstemp(prefix=_temp_prefix(real.name), suffix=f".part{suffix}")
        else:
            _check_folder(real.parent, user)
            _remove_stale(real.parent)
            try:
                fd, name = tempfile.mkstemp(dir=real.parent, prefix=_temp_prefix(real.name),
                                            suffix=f".part{suffix}")
            except OSError as exc:
                raise OutputError(user, _reason(exc), exc.errno) from None
        os.close(fd)
        stage = Path(name)
        self._staged[stage] = (real, user)
        self._order.append(stage)
        return stage

    def write(self, target, data: str | bytes) -> None:
        """Stage ``data`` (text is UTF-8 encoded) for ``target``."""
        stage = self.path(target)
        try:
            with open(stage, "wb") as fh:
                fh.write(_as_bytes(data))
        except OSError as exc:
            raise OutputError(target, _reason(exc), exc.errno) from None

    # -- commit / discard

    def _commit(self) -> None:
        for stage in self._order:  # everything on disk before anything is renamed
            if not stage.exists():
                target = self._staged[stage][1]
                raise OutputError(target, "nothing was written to it")
            _fsync_file(stage)
        if self.directory is not None and self._new_dir:
            self._commit_new_dir()
            return
        plans = []
        for stage in self._order:
            real, user = self._staged[stage]
            real = _resolve(real)  # a link named in a folder is written through, as write_file
            st = _existing(real, user)
            plans.append((stage, real, user, st))
            if st is None or not _is_stream(st):
                _mode_as_open(stage, st)
        # Devices and FIFOs first: they are what fails (a full device, a FIFO nobody reads;
        # see _open_stream), and a stream cannot be taken back -- so no regular file of the
        # set is replaced unless every stream took its bytes.
        for stage, real, user, st in plans:
            if st is not None and _is_stream(st):
                _stream_copy(stage, real, user)
        folders = set()
        with held():
            for stage, real, user, st in plans:
                if st is not None and _is_stream(st):
                    continue
                try:
                    os.replace(stage, real)
                except OSError as exc:
                    if exc.errno != errno.EXDEV:  # EXDEV: a link to another file system
                        raise OutputError(user, _reason(exc), exc.errno) from None
                    write_file(real, stage.read_bytes())
                folders.add(real.parent)
        for folder in folders:
            _fsync_dir(folder)
        for stage, real, user, st in plans:
            if st is not None and _is_stream(st):
                with contextlib.suppress(OSError):
                    stage.unlink()
        self._remove_stage_dir()

    def _commit_new_dir(self) -> None:
        umask = _umask()
        for stage in self._order:
            _mode_as_open(stage, None)
        for sub in [p for p in self._stage_dir.rglob("*") if p.is_dir()] + [self._stage_dir]:
            os.chmod(sub, 0o777 & ~umask)
        _fsync_dir(self._stage_dir)
        with held():
            if self.directory.exists():
                raise OutputError(self.directory, "it appeared while the outputs were being made",
                                  errno.EEXIST)
            try:
                os.rename(self._stage_dir, self.directory)
            except OSError as exc:
                raise OutputError(self.directory, _reason(exc), exc.errno) from None
        self._stage_dir = None
        _fsync_dir(self.directory.absolute().parent)

    def _remove_stage_dir(self) -> None:
        if self._stage_dir is not None:
            with contextlib.suppress(OSError):
                shutil.rmtree(self._stage_dir)
            self._stage_dir = None

    def _discard(self) -> None:
        for stage in self._order:
            with contextlib.suppress(OSError):
                stage.unlink()
        self._remove_stage_dir()
        self._staged.clear()
        self._order.clear()
