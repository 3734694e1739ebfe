"""The kept made code of a program (:class:`.run.Program`): a trust boundary, checked like any
input from outside.

An entry is ``<SHA-256 of what the code was made from>.code`` in the user's cache folder's
``fortran/``; it holds a first line (:data:`MAGIC` and the SHA-256 of the code), what the
code was made from (compared whole with what is to run), and the code (marshal).  Read back
only

* from a folder that is the user's own: a real folder (not a symbolic link), owned by the
  user and writable by no one else, and so its parent (``deck_emulator/``), as ssh asks of
  its folder; any other is not used at all (said once on stderr; the run goes on, its code
  made again and kept nowhere);
* through the folder opened once (``O_NOFOLLOW``): its entries are named relative to it, so
  that nothing it does reaches through a link to somewhere else;
* from a regular file owned by the user, opened without following a link and without
  waiting (``O_NONBLOCK``: a FIFO in an entry's place is not read), of a bounded size;
* when its SHA-256 holds, what it was made from equals what is to run, and marshal loads a
  code object from it: anything else (cut, garbled, forged with a wrong digest, another
  program's) is a miss, and the code is made again and written over it.

An entry is written whole or not at all (a temporary file in the folder, renamed over the
name, which replaces whatever stood there without following it); the least recently used
beyond ``PROGRAM_CACHE_ENTRIES`` go, only entries this module wrote (named by a SHA-256,
regular files of the user's, starting with :data:`MAGIC`).  hashlib is imported only here,
when an entry is looked up.
"""

from __future__ import annotations

import contextlib
import os
import stat
import sys

from deck_emulator.legacy.deck import read_at_most
from deck_emulator.vocabulary.defaults import (PROGRAM_CACHE_ENTRIES, PROGRAM_CACHE_MAX_BYTES,
                                               user_cache_folder)

#: An entry's first bytes (the format's version in it): then the SHA-256 of its code, in hex
#: (what it was made from is compared whole, not hashed again).
MAGIC = b"deck_emulator fortran code sha256 "
_SUFFIX = ".code"
_said: set = set()  # the refused folders already named on stderr (once a process)


def folder() -> str:
    """Where a program's made code is kept: the package's user cache folder's fortran/ (named
    with os.path: a plain run imports no pathlib)."""
    return os.path.join(user_cache_folder(), "fortran")


def entry_name(identity: bytes) -> str:
    """The entry of the code made from ``identity``: its SHA-256, in hex."""
    import hashlib

    return hashlib.sha256(identity).hexdigest() + _SUFFIX


def _why_not(st: os.stat_result) -> str | None:
    """Why a folder (lstat) is not the user's own, or None."""
    if stat.S_ISLNK(st.st_mode):
        return "a symbolic link"
    if not stat.S_ISDIR(st.st_mode):
        return "not a folder"
    if st.st_uid != os.getuid():
        return f"owned by another user (uid {st.st_uid})"
    if st.st_mode & 0o022:
        who = {0o022: "its group and others", 0o020: "its group"}.get(st.st_mode & 0o022,
                                                                     "others")
        return f"writable by {who} (mode {stat.S_IMODE(st.st_mode):o})"
    return None


def _say(path: str, why: str) -> None:
    if path not in _said:
        _said.add(path)
        print(f"deck-emulator: the made-code cache folder {path!r} is {why}: not used (the "
              "program's code is made again and not kept)", file=sys.stderr)


def _open_folder(create: bool) -> int | None:
    """A descriptor of the cache folder if it is the user's own (created, mode 700, when
    ``create`` and missing), else None (said once on stderr when it exists and is not)."""
    inner = folder()
    outer = os.path.dirname(inner)
    for path in (outer, inner):
        try:
            st = os.lstat(path)
        except FileNotFoundError:
            if not create:
                return None
            try:
                if path == outer:  # (the user's cache folder itself, as any program makes it)
                    os.makedirs(os.path.dirname(outer), exist_ok=True)
                os.mkdir(path, 0o700)
                st = os.lstat(path)
            except OSError:
                return None
        except OSError:
            return None
        why = _why_not(st)
        if why is not None:
            _say(path, why)
            return None
    try:
        fd = os.open(inner, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC)
    except OSError:
        return None
    why = _why_not(os.fstat(fd))  # (the folder opened is the one checked)
    if why is not None:
        os.close(fd)
        _say(inner, why)
        return None
    return fd


@contextlib.contextmanager
def _open_own(dir_fd: int, name: str):
    """An entry opened for reading without following a link or waiting for a writer: (its
    descriptor, its status) where it is a regular file of the user's, else None."""
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | os.O_NOFOLLOW | os.O_CLOEXEC,
                     dir_fd=dir_fd)
    except OSError:
        yield None
        return
    try:
        st = os.fstat(fd)
        yield (fd, st) if stat.S_ISREG(st.st_mode) and st.st_uid == os.getuid() else None
    finally:
        os.close(fd)


def _read_entry(dir_fd: int, name: str) -> bytes | None:
    """An entry's bytes: a regular file of the user's (:func:`_open_own`), of at most
    PROGRAM_CACHE_MAX_BYTES; else None."""
    with _open_own(dir_fd, name) as opened:
        if opened is None or opened[1].st_size > PROGRAM_CACHE_MAX_BYTES:
            return None
        try:
            data = read_at_most(opened[0], PROGRAM_CACHE_MAX_BYTES)
        except OSError:
            return None
        return data if len(data) <= PROGRAM_CACHE_MAX_BYTES else None


def _unpack(data: bytes, identity: bytes):
    """The code of an entry's bytes if it was made from ``identity``, the SHA-256 of its code
    holds and marshal reads a code object from it; else None."""
    import hashlib
    import marshal
    import types

    head, _, rest = data.partition(b"\n")
    size, _, rest = rest.partition(b"\n")
    if not size.isdigit() or rest[:int(size)] != identity:
        return None
    code_bytes = rest[int(size):]
    if head != MAGIC + hashlib.sha256(code_bytes).hexdigest().encode():
        return None
    try:
        code = marshal.loads(code_bytes)
    except (ValueError, EOFError, TypeError):
        return None
    return code if isinstance(code, types.CodeType) else None


def kept(identity: bytes):
    """The code kept for ``identity``, or None (a bad entry is removed: made again)."""
    fd = _open_folder(create=False)
    if fd is None:
        return None
    try:
        name = entry_name(identity)
        data = _read_entry(fd, name)
        code = None if data is None else _unpack(data, identity)
        if code is None:
            if data is not None and not data.startswith(MAGIC):
                pass  # (not an entry of this format: left for its writer)
            elif data is not None:
                with contextlib.suppress(OSError):
                    os.unlink(name, dir_fd=fd)
            return None
        with contextlib.suppress(OSError):
            os.utime(name, dir_fd=fd, follow_symlinks=False)  # (recently used)
        return code
    finally:
        os.close(fd)


def keep(identity: bytes, code) -> None:
    """Keep ``code``, made from ``identity`` (whole or not at all); the least recently used of
    this module's entries beyond PROGRAM_CACHE_ENTRIES go. A cache that cannot be written, or
    a folder that is not the user's own, is left alone: the code is made again next time."""
    import hashlib
    import marshal

    fd = _open_folder(create=True)
    if fd is None:
        return
    try:
        code_bytes = marshal.dumps(code)
        data = (MAGIC + hashlib.sha256(code_bytes).hexdigest().encode() + b"\n"
                + b"%d\n" % len(identity) + identity + code_bytes)
        name = entry_name(identity)
        tmp = f".{name}.{os.urandom(6).hex()}.part"
        try:
            out = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW
                          | os.O_CLOEXEC, 0o600, dir_fd=fd)
        except OSError:
            return
        try:
            with os.fdopen(out, "wb") as fh:
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, name, src_dir_fd=fd, dst_dir_fd=fd)
        except OSError:
            with contextlib.suppress(OSError):
                os.unlink(tmp, dir_fd=fd)
            return
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp, dir_fd=fd)
            raise
        _prune(fd)
    finally:
        os.close(fd)


def _ours(dir_fd: int, name: str) -> os.stat_result | None:
    """The status of an entry this module wrote (named by a SHA-256, a regular file of the
    user's, starting with MAGIC), else None."""
    stem = name[:-len(_SUFFIX)] if name.endswith(_SUFFIX) else ""
    if len(stem) != 64 or stem.strip("0123456789abcdef"):
        return None
    with _open_own(dir_fd, name) as opened:
        if opened is None:
            return None
        fd, st = opened
        try:
            return st if os.read(fd, len(MAGIC)) == MAGIC else None
        except OSError:
            return None


def _prune(dir_fd: int) -> None:
    with contextlib.suppress(OSError):
        entries = sorted((st.st_mtime, name) for name in os.listdir(dir_fd)
                         if (st := _ours(dir_fd, name)) is not None)
        for _, name in entries[:max(len(entries) - PROGRAM_CACHE_ENTRIES, 0)]:
            with contextlib.suppress(OSError):
                os.unlink(name, dir_fd=dir_fd)
