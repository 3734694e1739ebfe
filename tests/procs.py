"""Live processes by parent or by process group, read from /proc (for the tests that check
that no worker outlives its command)."""

from __future__ import annotations

from pathlib import Path


def _live(field: int, value: int) -> list[int]:
    """Pids of live (not zombie) processes whose /proc stat ``field`` (after the name:
    1 = parent, 2 = process group) is ``value``."""
    out = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                fields = (d / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[field]) == value and fields[0] != "Z":
                out.append(int(d.name))
    return out


def children(pid: int) -> list[int]:
    """Live child processes of ``pid``."""
    return _live(1, pid)


def group(pgid: int) -> list[int]:
    """Live processes of the process group ``pgid``."""
    return _live(2, pgid)


def sigint_as_on_a_terminal() -> None:
    """``preexec_fn`` for a child that a test will send SIGINT: its SIGINT back to the default
    (Python then raises KeyboardInterrupt for it). A command started in the background by a
    non-interactive shell inherits SIGINT ignored, and rightly keeps it; so would the test's
    child when the test suite itself runs that way, and a Ctrl-C test would wait for nothing."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)
