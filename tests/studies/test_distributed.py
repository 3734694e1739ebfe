"""Sweeps on Dask: every scene stored exactly once, through failures, killed workers and a
killed command (SIGKILL), and resumed without running or changing a finished scene."""

from __future__ import annotations

import hashlib
import os
import signal
import subprocess
import sys
import textwrap
import time
from collections import Counter

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from procs import sigint_as_on_a_terminal

from deck_emulator.studies.distributed import run_scenes
from deck_emulator.studies.store import SceneStore, StoreError, scene_id


# The stub "engine" lives in its own module so that Dask's worker processes can import it.
def _digests(store: SceneStore) -> dict:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in store.files()}


def _check_complete(store: SceneStore, tasks: list[dict]) -> list[dict]:
    rows = store.rows()
    counts = Counter(r["scene_id"] for r in rows)
    assert set(counts) == {scene_id(t) for t in tasks}
    assert max(counts.values()) == 1, "a scene is stored twice"
    return rows


def test_scene_id_is_the_task_not_its_key_order():
    a = scene_id({"deck": "steel40", "inputs": {"CK": 33000.0, "WV": 100.0}})
    b = scene_id({"inputs": {"WV": 100.0, "CK": 33000.0}, "deck": "steel40"})
    assert a == b and len(a) == 24
    assert a != scene_id({"deck": "steel40", "inputs": {"CK": 33000.0, "WV": 100.00000001}})
    # stable across processes and runs: pinned
    assert scene_id({"i": 1}) == hashlib.sha256(b'{"i":1}').hexdigest()[:24]


def test_a_failing_scene_is_stored_with_its_error_and_the_rest_run(stub, tmp_path):
    tasks = [{"i": i, "fail": i == 3} for i in range(8)]
    store = run_scenes(tasks, stub.work, store_dir=tmp_path / "s", jobs=1, progress=False)
    rows = {r["scene_id"]: r for r in _check_complete(store, tasks)}
    bad = rows[scene_id(tasks[3])]
    assert bad["status"] == "failed" and "fails on purpose" in bad["error"]
    assert all(rows[scene_id(t)]["status"] == "ok" for t in tasks if t["i"] != 3)
    assert rows[scene_id(tasks[5])]["y"] == 2.5
    with pytest.raises(StoreError):  # not mixed with an old store unless resuming
        run_scenes(tasks, stub.work, store_dir=tmp_path / "s", jobs=1, progress=False)
    # a resume with nothing missing runs nothing and writes nothing
    before = _digests(store)
    run_scenes(tasks, stub.work, store_dir=tmp_path / "s", resume=True, progress=False)
    assert _digests(store) == before


def test_a_killed_worker_loses_no_scene(stub, tmp_path):
    marker = tmp_path / "killed.pid"
    tasks = [{"i": i, "sleep": 0.05} for i in range(30)]
    tasks[10] = {"i": 10, "sleep": 0.05, "kill_marker": str(marker)}
    store = run_scenes(tasks, stub.work, store_dir=tmp_path / "s", jobs=2, progress=False)
    assert marker.exists(), "the worker was not killed"
    killed_pid = marker.read_text()
    rows = {r["scene_id"]: r for r in _check_complete(store, tasks)}
    assert all(r["status"] == "ok" for r in rows.values())
    redone = rows[scene_id(tasks[10])]
    assert redone["y"] == 5.0
    assert not redone["worker"].endswith(f":{killed_pid}")  # run again by another process


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT], ids=["kill-9", "ctrl-c"])
def test_killing_the_whole_command_then_resume(stub, tmp_path, sig):
    store_dir = tmp_path / "s"
    n = 60
    script = tmp_path / "sweep_script.py"
    script.write_text(
        textwrap.dedent(
            f"""
            from deck_emulator.studies.distributed import run_scenes
            import stub_engine
            if __name__ == "__main__":  # Dask starts its workers by spawning
                tasks = [{{"i": i, "sleep": 0.15}} for i in range({n})]
                run_scenes(tasks, stub_engine.work, store_dir={str(store_dir)!r}, jobs=2,
                           flush_s=0.0, progress=False)
            """
        )
    )
    proc = subprocess.Popen([sys.executable, str(script)], start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=open(tmp_path / "stderr.txt", "w"),
                            preexec_fn=sigint_as_on_a_terminal)
    store = SceneStore(store_dir)
    try:
        deadline = time.monotonic() + 120
        while len(store.rows()) < 10:
            assert proc.poll() is None, "the sweep ended before it could be killed: " + (
                tmp_path / "stderr.txt"
            ).read_text()[-2000:]
            assert time.monotonic() < deadline, "the sweep stored nothing in 120 s"
            time.sleep(0.1)
        os.kill(proc.pid, sig)  # kill -9 (or Ctrl-C) of the main process only
        proc.wait(timeout=60)
        if sig == signal.SIGINT:  # Ctrl-C: what had completed was written on the way out
            assert proc.returncode != 0
    finally:
        # the session's other processes (Dask's nanny and workers, if any are left)
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    time.sleep(0.5)
    before = _digests(store)
    stored_before = {r["scene_id"]: r for r in store.rows()}
    assert 10 <= len(stored_before) < n, "the kill did not land part-way"

    tasks = [{"i": i, "sleep": 0.15} for i in range(n)]
    store = run_scenes(tasks, stub.work, store_dir=store_dir, jobs=2, resume=True,
                       progress=False)
    rows = {r["scene_id"]: r for r in _check_complete(store, tasks)}
    after = _digests(store)
    assert {k: after[k] for k in before} == before, "a finished result's file changed"
    for sid, r in stored_before.items():
        assert rows[sid] == r
    assert not list((store_dir / "results").glob(".*.tmp"))
    assert sorted(r["y"] for r in rows.values()) == [i * 0.5 for i in range(n)]


def test_an_existing_cluster_by_its_scheduler_address(stub, tmp_path):
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address=None) as cluster:
        tasks = [{"i": i} for i in range(12)]
        store = run_scenes(tasks, stub.work, store_dir=tmp_path / "s",
                           scheduler=cluster.scheduler_address, progress=False)
        rows = _check_complete(store, tasks)
        assert sorted(r["square"] for r in rows) == [i * i for i in range(12)]
        assert cluster.status.name == "running"  # the cluster is theirs: left running


def test_batch_size_is_about_four_tasks_a_worker_within_bounds():
    from deck_emulator.studies.distributed import BATCH_TASK_MAX, batch_size

    # ceil(n / (4 workers)), worked by hand
    assert batch_size(1, 2) == 1
    assert batch_size(8, 2) == 1
    assert batch_size(9, 2) == 2
    assert batch_size(100, 2) == 13
    assert batch_size(10_000, 2) == BATCH_TASK_MAX == 16
    assert batch_size(120, 2) == 15 and batch_size(121, 2) == 16 and batch_size(500, 2) == 16
    assert batch_size(0, 0) == 1


def test_scenes_run_in_batches_and_are_stored_one_row_each(stub, tmp_path):
    """23 tasks on one worker: batches of ceil(23 / 4) = 6 (6, 6, 6, 5), each given to the
    batch function in one call; a task that fails is its own failed row; a batch that cannot
    run together runs again one task at a time; the store holds one row per scene."""
    tasks = [{"i": i, "fail": i == 4, "spoils": i == 20} for i in range(23)]
    store = run_scenes(tasks, stub.work_many, store_dir=tmp_path / "s", jobs=1,
                       progress=False, many=True)
    rows = {r["scene_id"]: r for r in _check_complete(store, tasks)}
    got = [rows[scene_id(t)] for t in tasks]
    assert got[4]["status"] == "failed" and "scene 4 fails on purpose" in got[4]["error"]
    assert [r["status"] for r in got].count("ok") == 22
    assert [r["batch"] for r in got[:18] if r["status"] == "ok"] == [6] * 17
    assert [r["batch"] for r in got[18:]] == [1] * 5  # the spoilt batch, one at a time
    assert [r["y"] for r in got if r["status"] == "ok"] == [i * 0.5 for i in range(23) if i != 4]
    # resumed per scene: a lost scene runs again alone, the others are kept
    kept = SceneStore(tmp_path / "s").rows()
    before = _digests(store)
    run_scenes(tasks, stub.work_many, store_dir=tmp_path / "s", resume=True, progress=False,
               many=True)
    assert _digests(store) == before and SceneStore(tmp_path / "s").rows() == kept
    more = tasks + [{"i": 23}]
    run_scenes(more, stub.work_many, store_dir=tmp_path / "s", resume=True, progress=False,
               many=True, jobs=1)
    rows = {r["scene_id"]: r for r in _check_complete(store, more)}
    assert rows[scene_id(more[-1])]["batch"] == 1 and rows[scene_id(more[-1])]["y"] == 11.5


def test_a_plain_function_runs_in_batches_too(stub, tmp_path):
    tasks = [{"i": i} for i in range(9)]
    store = run_scenes(tasks, stub.work, store_dir=tmp_path / "s", jobs=1, progress=False,
                       chunk=4)
    rows = _check_complete(store, tasks)
    assert sorted(r["square"] for r in rows) == [i * i for i in range(9)]


def test_a_spawned_workers_first_batch_puts_what_it_holds_out_of_the_collectors_way(
        monkeypatch):
    """Only in a worker an embedded cluster spawned, and once: its objects frozen after its
    first batch (gc.freeze), so that the collector stops going through them."""
    import gc

    from deck_emulator import SPAWNED_WORKER_ENV
    from deck_emulator.studies import distributed

    monkeypatch.setattr(distributed, "_SETTLED", [])
    monkeypatch.delenv(SPAWNED_WORKER_ENV, raising=False)
    frozen = gc.get_freeze_count()
    rows = distributed._call_many(lambda tasks: [{"y": t["x"]} for t in tasks], [{"x": 1}], True)
    assert rows[0]["y"] == 1 and gc.get_freeze_count() == frozen  # not a worker: untouched
    monkeypatch.setenv(SPAWNED_WORKER_ENV, "1")
    try:
        for _ in range(2):
            distributed._call_many(lambda tasks: [{} for _ in tasks], [{"x": 1}], True)
        assert gc.get_freeze_count() > frozen and distributed._SETTLED == [True]  # once
    finally:
        gc.unfreeze()


_KINDS = (st.integers(-2**62, 2**62), st.floats(), st.text(max_size=5), st.booleans())


@given(values=st.sampled_from(_KINDS).flatmap(
    lambda kind: st.lists(st.one_of(st.none(), kind), min_size=1, max_size=8)))
@settings(max_examples=60, deadline=None)
def test_a_stored_column_reads_back_as_written_missing_values_included(tmp_path_factory, values):
    """A column of one kind (whole numbers, floats, text or booleans) with missing values is
    read back value for value and type for type: an int is not made a float by a None."""
    store = SceneStore(tmp_path_factory.mktemp("store"))
    store.write_batch([{"scene_id": str(i), "v": v} for i, v in enumerate(values)])
    got = [r["v"] for r in store.rows(("v",))]
    assert [type(v) for v in got] == [type(v) for v in values]
    assert all(a == b or (a != a and b != b) for a, b in zip(got, values))
