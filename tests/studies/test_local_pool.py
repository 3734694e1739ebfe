"""The embedded runner (deck_emulator.studies.local_pool.LocalPool): a ProcessPoolExecutor on
workers forked from one process that has loaded the compiled core; a batch whose worker died
runs again, and one that kills its worker every time is said so; workers end with their
command."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from deck_emulator.studies.distributed import run_scenes
from deck_emulator.studies.store import SceneStore, scene_id
from deck_emulator.errors import RunFailed
import concurrent.futures as cf

from deck_emulator.studies.local_pool import LocalPool, WorkerDied
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


def _answers(pool, calls):
    futures = [pool.submit(fn, *args) for fn, args in calls]
    cf.wait(futures, timeout=120)
    return [f.exception() or f.result() for f in futures]


def test_a_worker_that_exits_in_its_batch_is_replaced_and_said_how_it_ended():
    pool = LocalPool(1)
    try:
        died, after = _answers(pool, [(os._exit, (3,)), (abs, (-4,))])
    finally:
        pool.shutdown()
    assert isinstance(died, WorkerDied)
    assert f"died {defaults.WORKER_DEATHS_PER_BATCH + 1} times (last exit status 3)" in str(died)
    assert after == 4  # on a worker that replaced the last one


def test_the_batches_beside_a_dying_one_run_once_more_and_are_not_blamed(tmp_path):
    """Two workers: a batch that kills its worker every time runs beside others; only it
    is answered WorkerDied, every other batch gives its answer."""
    pool = LocalPool(2)
    try:
        got = _answers(pool, [(abs, (-k,)) for k in range(3)] + [(os._exit, (9,))]
                       + [(abs, (-k,)) for k in range(3, 9)])
    finally:
        pool.shutdown()
    assert isinstance(got[3], WorkerDied)
    assert got[:3] + got[4:] == list(range(9))


def test_when_no_worker_can_start_again_the_run_ends_saying_so(monkeypatch):
    pool = LocalPool(1)
    try:
        def cannot():
            raise OSError(11, "Resource temporarily unavailable")

        monkeypatch.setattr(pool, "_new_pool", cannot)
        (got,) = _answers(pool, [(os._exit, (3,))])
    finally:
        pool.shutdown()
    assert isinstance(got, RunFailed)
    assert "no worker process could be started again" in str(got) and "--resume" in str(got)


@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="counts /proc/self/fd")
@pytest.mark.parametrize("n", [1, 2, 4])
def test_a_pool_holds_no_more_files_than_its_rows_count(n):
    """The rows the open-file check reads (POOL_FILES, POOL_WORKER_FILES) hold what a pool
    of n workers keeps open, its server's included.  Counted in a process of its own: in the
    test's, the pipes an earlier test's pool left to the garbage collector may close while
    this one runs, and cancel what it opens."""
    script = textwrap.dedent(f"""
        import concurrent.futures as cf, os
        from deck_emulator.studies.local_pool import LocalPool
        before = len(os.listdir("/proc/self/fd"))
        pool = LocalPool({n})
        futures = [pool.submit(abs, -2) for _ in range({2 * n})]
        cf.wait(futures, timeout=120)
        assert [f.result() for f in futures] == [2] * {2 * n}
        held = len(os.listdir("/proc/self/fd")) - before
        pool.shutdown()
        print(held)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=180)
    assert done.returncode == 0, done.stderr
    held = int(done.stdout)
    assert 0 < held <= defaults.POOL_FILES + defaults.POOL_WORKER_FILES * n


def test_a_batch_that_cannot_travel_is_said_and_the_worker_goes_on():
    pool = LocalPool(1)
    try:
        lam, after = _answers(pool, [(lambda: 1, ()), (abs, (-3,))])
    finally:
        pool.shutdown()
    assert isinstance(lam, Exception) and "pickle" in str(lam).lower()
    assert after == 3


def test_a_worker_starts_in_its_commands_folder_and_environment(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("DECK_EMULATOR_TEST_SEEN", "yes")
    pool = LocalPool(1)
    try:
        got = _answers(pool, [(os.getcwd, ()), (os.getenv, ("DECK_EMULATOR_TEST_SEEN",))])
    finally:
        pool.shutdown()
    assert got == [str(tmp_path), "yes"]


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
        from deck_emulator.studies.local_pool import LocalPool
        if __name__ == "__main__":
            pool = LocalPool(1, core=True)
            got = [pool.submit(stub_engine.loaded, name).result() for name in
                   ["deck_emulator.core.batch", "numba", "deck_emulator.studies.sweep"]]
            pool.shutdown()
            print(got)
        """), capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[True, True, True]"


def test_a_worker_ends_with_its_command(tmp_path):
    proc = subprocess.Popen(_script(tmp_path, """
        import os, time
        from deck_emulator.studies.local_pool import LocalPool
        if __name__ == "__main__":
            pool = LocalPool(1)
            print(pool.submit(os.getpid).result(), flush=True)
            pool.submit(time.sleep, 120).result()
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
