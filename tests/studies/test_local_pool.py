"""The embedded runner's workers (deck_emulator.studies.local_pool): forked from one process
that has loaded the compiled core, replaced when they die, gone when their command is."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from deck_emulator.studies.distributed import SceneStore, run_scenes, scene_id
from deck_emulator.errors import RunFailed
from deck_emulator.studies.local_pool import BatchError, WorkerDied, WorkerPool
from deck_emulator.vocabulary import defaults


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_a_batch_whose_worker_dies_every_time_is_stored_failed_and_the_rest_run(stub, tmp_path):
    tasks = [{"i": i} for i in range(6)] + [{"i": 6, "kill_always": True}]
    store = run_scenes(tasks, stub.work, store_dir=tmp_path / "s", jobs=2, chunk=1,
                       progress=False)
    rows = {r["scene_id"]: r for r in SceneStore(store.dir).rows()}
    assert len(rows) == 7
    bad = rows[scene_id(tasks[6])]
    assert bad["status"] == "failed"
    assert f"died {defaults.WORKER_DEATHS_PER_BATCH + 1} times" in bad["error"]
    assert "SIGKILL" in bad["error"]
    assert sorted(r["y"] for r in rows.values() if r["status"] == "ok") == [
        i * 0.5 for i in range(6)]


def test_a_worker_that_exits_in_its_batch_is_replaced_and_said_how_it_ended():
    with WorkerPool(1) as pool:
        got = dict(pool.run([(0, (os._exit, (3,))), (1, (abs, (-4,)))]))
    assert isinstance(got[0], WorkerDied)
    assert f"died {defaults.WORKER_DEATHS_PER_BATCH + 1} times (last exit status 3)" in str(got[0])
    assert got[1] == 4  # on the worker that replaced the last one


def test_when_no_worker_can_start_again_the_run_ends_saying_so(monkeypatch):
    with WorkerPool(1) as pool:
        def cannot():
            raise OSError(11, "Resource temporarily unavailable")

        monkeypatch.setattr(pool, "_start", cannot)
        with pytest.raises(RunFailed, match="no worker process could be started again .*"
                                            "--resume runs the rest"):
            list(pool.run([(0, (os._exit, (3,)))]))


@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="counts /proc/self/fd")
@pytest.mark.parametrize("n", [1, 2, 4])
def test_a_pool_holds_no_more_files_than_its_rows_count(n):
    """The rows the open-file check reads (POOL_FILES, POOL_WORKER_FILES) hold what a pool
    of n workers keeps open, its server's included."""
    before = len(os.listdir("/proc/self/fd"))
    with WorkerPool(n) as pool:
        assert dict(pool.run([(0, (abs, (-2,)))])) == {0: 2}
        held = len(os.listdir("/proc/self/fd")) - before
    assert 0 < held <= defaults.POOL_FILES + defaults.POOL_WORKER_FILES * n


def test_a_batch_that_cannot_travel_is_said_and_the_worker_goes_on(tmp_path, monkeypatch):
    (tmp_path / "late_module.py").write_text("def f():\n    return 1\n")
    with WorkerPool(1) as pool:
        monkeypatch.syspath_prepend(str(tmp_path))  # after the worker started: not in its path
        import late_module

        got = dict(pool.run([(0, (lambda: 1, ())), (1, (late_module.f, ())),
                             (2, (abs, (-3,)))]))
    assert isinstance(got[0], BatchError) and "cannot be sent to a worker" in str(got[0])
    assert isinstance(got[1], BatchError) and "cannot load the batch" in str(got[1])
    assert "late_module" in str(got[1])
    assert got[2] == 3


def test_a_worker_starts_in_its_commands_folder_and_environment(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("DECK_EMULATOR_TEST_SEEN", "yes")
    with WorkerPool(1) as pool:
        got = dict(pool.run([(0, (os.getcwd, ())),
                             (1, (os.getenv, ("DECK_EMULATOR_TEST_SEEN",)))]))
    assert got == {0: str(tmp_path), 1: "yes"}


def _script(tmp_path, body: str) -> list[str]:
    path = tmp_path / "script.py"
    path.write_text(textwrap.dedent(body))
    return [sys.executable, str(path)]


def test_a_core_pools_workers_have_the_compiled_core_before_their_first_batch(stub, tmp_path):
    """The server imports it (a preload's ImportError would pass unseen: multiprocessing
    ignores it), in a fresh process: the first pool of a process decides what its server
    holds."""
    pytest.importorskip("numba")
    out = subprocess.run(_script(tmp_path, """
        import stub_engine
        from deck_emulator.studies.local_pool import WorkerPool
        if __name__ == "__main__":
            with WorkerPool(1, core=True) as pool:
                got = dict(pool.run([(k, (stub_engine.loaded, (name,))) for k, name in
                                     enumerate(["deck_emulator.core.batch", "numba",
                                                "deck_emulator.studies.sweep"])]))
            print(got)
        """), capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "{0: True, 1: True, 2: True}"


def test_a_worker_ends_with_its_command(tmp_path):
    proc = subprocess.Popen(_script(tmp_path, """
        import time
        from deck_emulator.studies.local_pool import WorkerPool
        if __name__ == "__main__":
            with WorkerPool(1) as pool:
                print(pool.workers[0].process.pid, flush=True)
                for _ in pool.run([(0, (time.sleep, (120,)))]):
                    pass
        """), stdout=subprocess.PIPE, text=True, start_new_session=True)
    try:
        worker = int(proc.stdout.readline())
        assert _alive(worker)
        os.kill(proc.pid, signal.SIGKILL)  # the command only: kill -9
        proc.wait(timeout=30)
        deadline = time.monotonic() + 30
        while _alive(worker) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not _alive(worker), "the worker outlived its command, asleep in its batch"
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
