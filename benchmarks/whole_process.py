"""What the whole-process benchmarks share: the environment each measured command runs in, and
one command's wall and CPU time."""

from __future__ import annotations

import os
import subprocess
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def environment(cache: str, src: Path = ROOT / "src") -> dict[str, str]:
    """The caller's environment with bytecode and the package's user cache kept in ``cache``
    (warm after a first run), ``src`` (default: the checkout's) first on the path, and no
    fixed SOURCE_DATE_EPOCH."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env.pop("SOURCE_DATE_EPOCH", None)
    env["PYTHONPYCACHEPREFIX"] = cache
    env["XDG_CACHE_HOME"] = cache  # (a job deck's made code is kept there, as the bytecode)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(src), env.get("PYTHONPATH")]))
    return env


def machine_line() -> str:
    """How loaded the machine was when the figures above were measured."""
    return (f"(load average at the end: {', '.join(f'{x:.2f}' for x in os.getloadavg())}; "
            f"{os.cpu_count()} CPUs)")


def measure(argv: list[str], env: dict[str, str]) -> tuple[float, float]:
    """(wall s, CPU s: user + system) of one whole process; a failed command ends the bench."""
    started = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    _, status, usage = os.wait4(proc.pid, 0)
    wall_s = time.perf_counter() - started
    code = os.waitstatus_to_exitcode(status)
    if code:
        raise SystemExit(f"{' '.join(argv)} exited {code}")
    return wall_s, usage.ru_utime + usage.ru_stime
