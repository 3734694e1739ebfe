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
