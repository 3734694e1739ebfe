"""The errors a command reports to its user (the CLI maps them to exit statuses)."""

from __future__ import annotations


class UsageError(Exception):
    """Bad input that is not about a deck's contents (an option, a path): exit status 2."""


class RunFailed(UsageError):
    """The program (emulated or core) could not run to its end: exit status 3."""


#: the process limits a start or an allocation can fail under: resource, what, unit, ulimit's flag
LIMITS = (("RLIMIT_NOFILE", "open files", "", "-n"), ("RLIMIT_AS", "address space", "MB", "-v"),
          ("RLIMIT_DATA", "data", "MB", "-d"), ("RLIMIT_NPROC", "processes", "", "-u"))


def process_limits() -> list[str]:
    """The limits set on this process that a start or an allocation may have hit, in words
    (the memory limits when set; open files and processes when below 4096)."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not a POSIX system
        return []
    out = []
    for name, what, unit, flag in LIMITS:
        soft = resource.getrlimit(getattr(resource, name))[0]
        if soft != resource.RLIM_INFINITY and (unit or soft < 4096):
            out.append(f"{what} {soft >> 20 if unit else soft}{' ' + unit if unit else ''} "
                       f"(ulimit {flag})")
    return out


def address_space_mb() -> int | None:
    """The address space this process may use (ulimit -v), MB; None: no limit."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not a POSIX system
        return None
    soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    return None if soft == resource.RLIM_INFINITY else soft >> 20


def out_of_memory(exc: BaseException | None = None) -> str | None:
    """What a command says when memory ran out (``exc``: a library that did not load, which
    is said only under a memory limit, else None): the limits, and what to change."""
    limits = ", ".join(process_limits())
    if exc is not None:
        if "MB" not in limits:
            return None
        why = str(exc).splitlines()[0][:160] if str(exc) else type(exc).__name__
        return f"could not load a library ({why}) under the limits of {limits}: raise them"
    return ("out of memory" + (f" under the limits of {limits}: raise them" if limits else
                               ": free memory, or run fewer --jobs"))
