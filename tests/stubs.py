"""A stub engine for the scene runner's tests: a module the Dask workers import by name
(``stub_engine``), written into the test's folder, whose ``work(task)`` sleeps, fails or
kills its own worker as the task asks. The ``stub`` fixture (conftest.py) writes it."""

from __future__ import annotations

import textwrap
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "src"

STUB = textwrap.dedent(
    '''
    import os, signal, time
    def work(task):
        if task.get("fail"):
            raise ValueError(f"scene {task['i']} fails on purpose")
        if task.get("kill_always"):
            os.kill(os.getpid(), signal.SIGKILL)  # dies in this scene every time it runs it
        kill = task.get("kill_marker")
        if kill and not os.path.exists(kill):
            with open(kill, "w") as fh:
                fh.write(str(os.getpid()))
            os.kill(os.getpid(), signal.SIGKILL)  # this worker dies in the middle of the scene
        time.sleep(task.get("sleep", 0.0))
        return {"y": task["i"] * 0.5, "square": task["i"] ** 2}
    def loaded(name):
        """Whether this process has imported the module ``name``."""
        import sys
        return name in sys.modules
    def work_many(tasks):
        """A batch function (run_scenes(many=True)): one answer per task, an exception for
        a task that fails; a task with "spoils" makes the whole call raise."""
        if len(tasks) > 1 and any(t.get("spoils") for t in tasks):
            raise RuntimeError("this batch cannot be run together")
        out = []
        for t in tasks:
            try:
                out.append({**work(t), "batch": len(tasks)})
            except Exception as exc:
                out.append(exc)
        return out
    '''
)
