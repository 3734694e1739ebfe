"""A scene store two processes can share safely, and runs that end within their bounds: a
second run on a folder another live run holds is refused in one line (it does not wait), no
command deletes a store another run holds, a kill releases the folder; an external cluster
without workers ends the run with a named error after a bounded wait."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from collections import Counter

import pytest

from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.studies.cluster import ClusterError, Scheduler
from deck_emulator.studies.distributed import SceneLimitError, run_scenes
from deck_emulator.studies.store import SceneStore, StoreBusy, output_store, scene_id

#: process-level or document tests: the README's test command runs them, a bare pytest not
pytestmark = pytest.mark.slow


def _start(tmp_path, name: str, body: str) -> subprocess.Popen:
    script = tmp_path / f"{name}.py"
    script.write_text(textwrap.dedent(body))
    return subprocess.Popen([sys.executable, str(script)], start_new_session=True,
                            stdout=subprocess.PIPE, stderr=open(tmp_path / f"{name}.err", "w"),
                            text=True)


def _stop(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    proc.wait(timeout=30)


def test_a_store_another_run_holds_is_neither_used_nor_deleted(tmp_path):
    out = tmp_path / "out"
    SceneStore(out / ".scenes").write_batch([{"scene_id": "a", "task_json": "{}",
                                               "status": "ok"}])
    store = output_store(out, resume=True)  # an existing store: locked by this process
    kept = SceneStore(store).files()
    assert len(kept) == 1
    # this test's process holds the folder now: a second process must be refused
    holder = _start(tmp_path, "second", f"""
        import sys
        from deck_emulator.studies.store import StoreBusy, output_store
        try:
            output_store({str(out)!r}, resume=False)
        except StoreBusy as exc:
            print("busy:", exc, flush=True)
            sys.exit(2)
        print("deleted", flush=True)
        """)
    try:
        said, _ = holder.communicate(timeout=60)
    finally:
        _stop(holder)
    assert holder.returncode == 2, said
    assert said.startswith("busy:") and f"pid {os.getpid()}" in said
    assert len(said.strip().splitlines()) == 1
    assert SceneStore(store).files() == kept  # nothing deleted


def test_the_lock_is_released_when_its_holder_is_killed(tmp_path):
    out = tmp_path / "out"
    holder = _start(tmp_path, "holder", f"""
        import time
        from deck_emulator.studies.store import SceneStore, output_store
        SceneStore({str(out / ".scenes")!r}).write_batch(
            [{{"scene_id": "a", "task_json": "{{}}", "status": "ok"}}])
        output_store({str(out)!r}, resume=True)
        print("held", flush=True)
        time.sleep(120)
        """)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(StoreBusy, match=f"pid {holder.pid}") as info:
            output_store(out, resume=False)
        assert "\n" not in str(info.value)
        with pytest.raises(StoreBusy):
            run_scenes([{"i": 1}], len, store_dir=out / ".scenes", resume=True, progress=False)
        assert len(SceneStore(out / ".scenes").files()) == 1  # not deleted by the refusal
        os.kill(holder.pid, signal.SIGKILL)
        holder.wait(timeout=30)
    finally:
        _stop(holder)
    store = output_store(out, resume=False)  # the kernel released the kill -9'd run's lock
    assert SceneStore(store).files() == []


def test_two_resumes_on_one_folder_store_every_scene_once(stub, tmp_path):
    store_dir = tmp_path / "s"
    n = 24
    body = f"""
        import sys
        from deck_emulator.studies.distributed import run_scenes
        from deck_emulator.studies.store import StoreBusy
        import stub_engine
        if __name__ == "__main__":
            tasks = [{{"i": i, "sleep": 0.2}} for i in range({n})]
            try:
                run_scenes(tasks, stub_engine.work, store_dir={str(store_dir)!r}, jobs=1,
                           resume=True, flush_s=0.0, progress=False)
            except StoreBusy as exc:
                print("busy", flush=True)
                sys.exit(2)
            print("done", flush=True)
        """
    first = _start(tmp_path, "first", body)
    second = None
    try:
        deadline = time.monotonic() + 120
        while not SceneStore(store_dir).files():  # the first run is under way
            assert first.poll() is None and time.monotonic() < deadline
            time.sleep(0.05)
        second = _start(tmp_path, "second", body)
        said_second, _ = second.communicate(timeout=120)
        said_first, _ = first.communicate(timeout=120)
    finally:
        _stop(first)
        if second is not None:
            _stop(second)
    assert said_second.strip() == "busy" and second.returncode == 2
    assert said_first.strip() == "done" and first.returncode == 0
    counts = Counter(r["scene_id"] for r in SceneStore(store_dir).rows())
    tasks = [{"i": i, "sleep": 0.2} for i in range(n)]
    assert counts == Counter({scene_id(t): 1 for t in tasks})


def test_the_number_of_scenes_is_bounded_before_anything_runs(tmp_path):
    with pytest.raises(SceneLimitError, match="at most 3") as info:
        run_scenes([{"i": i} for i in range(4)], len, store_dir=tmp_path / "s", max_scenes=3)
    assert isinstance(info.value, UsageError)
    assert not (tmp_path / "s").exists()


def test_an_address_dask_cannot_use_is_a_cluster_error(tmp_path):
    with pytest.raises(ClusterError, match="nonsense") as info:
        run_scenes([{"i": 1}], len, store_dir=tmp_path / "s", scheduler="nonsense",
                   progress=False)
    assert isinstance(info.value, UsageError) and "\n" not in str(info.value)
    assert not (tmp_path / "s").exists()  # a run that stored nothing leaves no folder


def test_a_cluster_without_workers_ends_the_run_within_its_bound(stub, tmp_path):
    from distributed import LocalCluster

    with LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster:
        started = time.monotonic()
        with pytest.raises(RunFailed, match="no worker"):
            run_scenes([{"i": 1}], stub.work, store_dir=tmp_path / "s",
                       scheduler=cluster.scheduler_address, worker_wait_s=1.0, progress=False)
        assert time.monotonic() - started < 60
        # the command line's --worker-wait is the same bound, through the Scheduler value
        with pytest.raises(RunFailed, match="none joined in 1 s"):
            run_scenes([{"i": 1}], stub.work, store_dir=tmp_path / "t", progress=False,
                       scheduler=Scheduler(cluster.scheduler_address, worker_wait_s=1.0))


def test_a_cluster_whose_workers_all_go_ends_the_run_and_keeps_what_was_stored(stub, tmp_path):
    from distributed import LocalCluster

    tasks = [{"i": i, "sleep": 0.3} for i in range(40)]
    # the worker in its own process: an in-process worker shares this process's threads with
    # the client's IO loop, whose start then waited past distributed's 10 s on a loaded machine
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster:
        store = SceneStore(tmp_path / "s")

        def retire_when_some_are_stored():
            deadline = time.monotonic() + 60
            while not store.files() and time.monotonic() < deadline:
                time.sleep(0.05)
            cluster.scale(0)

        threading.Thread(target=retire_when_some_are_stored, daemon=True).start()
        started = time.monotonic()
        with pytest.raises(RunFailed, match="every worker .* is gone"):
            run_scenes(tasks, stub.work, store_dir=store.dir, scheduler=cluster.scheduler_address,
                       worker_wait_s=1.0, flush_s=0.0, progress=False)
        assert time.monotonic() - started < 90
    stored = Counter(r["scene_id"] for r in store.rows())
    assert 0 < len(stored) < len(tasks) and set(stored.values()) == {1}


SLOW_COMMAND = """
import sys
from deck_emulator import signals
from deck_emulator.studies.distributed import run_scenes
import stub_engine

def main():
    tasks = [{{"i": i, "sleep": 0.2}} for i in range(400)]
    run_scenes(tasks, stub_engine.work, store_dir={store!r}, jobs=2, flush_s=0.0,
               progress=False)
    return 0

if __name__ == "__main__":  # Dask starts its workers by spawning
    sys.exit(signals.run(main))
"""


def test_a_terminal_ctrl_c_prints_no_worker_traceback(stub, tmp_path):
    """Ctrl-C at a terminal reaches the whole process group, the workers included: the
    command ends with 130 and one line, and no worker prints a KeyboardInterrupt traceback."""
    from procs import sigint_as_on_a_terminal

    store_dir = tmp_path / "s"
    script = tmp_path / "command.py"
    script.write_text(SLOW_COMMAND.format(store=str(store_dir)))
    err_path = tmp_path / "stderr.txt"
    proc = subprocess.Popen([sys.executable, str(script)], start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=open(err_path, "w"),
                            preexec_fn=sigint_as_on_a_terminal)
    try:
        deadline = time.monotonic() + 120
        while len(SceneStore(store_dir).rows()) < 4:  # the workers are busy
            assert proc.poll() is None, err_path.read_text()[-2000:]
            assert time.monotonic() < deadline
            time.sleep(0.05)
        os.killpg(proc.pid, signal.SIGINT)  # as a terminal's Ctrl-C: the whole group
        proc.wait(timeout=60)
        time.sleep(1.0)  # what the workers print on their way out
    finally:
        _stop(proc)
    err = err_path.read_text()
    assert proc.returncode == 130, err[-2000:]
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err[-3000:]
