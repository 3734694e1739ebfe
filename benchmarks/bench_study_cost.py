#!/usr/bin/env python3
"""What a many-scene study costs beside the solve it runs, side by side in one run.

    python benchmarks/bench_study_cost.py [--scenes 256] [--repeat 7] [--commands [sensitivity|sweep]]
                                              [--src DIR]

Prints:

* in process, on ``--scenes`` scenes of the sensitivity study's own sample (steel40, the six
  default inputs, the core's legacy preset): the CPU time per scene of the solve alone
  (``deck_emulator.core.simulate_batch`` on the scenes the study prepares) and of the study's
  batch function (``studies.sensitivity.scene_tasks``: preparing the decks and scenes, the
  solve, the outcomes and the rows), their ratio; the same ratio against the solve's CPU
  timed inside the study's own run (``simulate_batch`` as the engine calls it: the machine's
  load weighs on both alike), and the parts outside the solve (the
  scenes prepared; the store's write of the rows, ``SceneStore.write_batch``, which the
  runner does in the client); medians of ``--repeat`` runs after a warm-up, the solve and
  the study timed in turn (the ratio: the median of the pairs' ratios); the solve again in
  two processes at once (forked: a many-scene command's two workers share the machine so);
* with ``--commands``, the whole commands as subprocesses, ``--jobs 2``:
  ``sensitivity --deck steel40 -N 1024`` (8,192 scenes) with the input that decides its
  contact ΔV (largest ST), and ``sweep`` of 10,000 core scenes: wall time, CPU time (the
  command and every process below it: its workers and the process they are forked from,
  sampled every 0.1 s), CPU per scene against the solve's, and the peak memory of the
  process tree: the sum of its processes' resident sizes (RSS: a shared library's pages
  counted once in each process), sampled every 0.1 s, and of their proportional sizes (PSS:
  each shared page split among the processes that map it), every 0.2 s (reading it costs
  the machine the command runs on: ``PSS_EVERY``).

Every figure is printed with the load average beside it: the times depend on the machine.
``--src DIR``: measure another checkout's ``src`` (the whole commands and the in-process part
both import it), for a before/after in the same conditions.  Nothing here passes or fails.
"""

from __future__ import annotations

import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SWEEP_GRID = ["--speeds", "10:59.5:0.5", "--angles", "0:49.5:0.5"]  # 100 x 100 core scenes
#: the tree's PSS is read every this many samples of its RSS (0.1 s apart): reading it every
#: sample took some 15 % of a core (4 ms a worker process), from the command it measured; every
#: second missed the sweep's peak, its last second (the command reading the store back)
PSS_EVERY = 2


def load() -> str:
    return "load %.1f %.1f %.1f" % os.getloadavg()


def _cpu(run) -> float:
    """The CPU seconds of one ``run()``."""
    t0 = time.process_time()
    run()
    return time.process_time() - t0


def side_by_side(run, procs: int, repeat: int) -> float:
    """The CPU seconds of one ``run()`` in each of ``procs`` processes running it at once
    (forked from this one, the compiled core already loaded): the median over ``repeat``
    rounds of the processes' mean.  What a scene costs where ``procs`` workers share the
    machine, as a many-scene command's do (caches and memory bandwidth shared)."""
    import multiprocessing

    ctx = multiprocessing.get_context("fork")
    rounds = []
    for _ in range(repeat):
        start = ctx.Barrier(procs)
        pipes = [ctx.Pipe(duplex=False) for _ in range(procs)]

        def child(send, start=start):
            start.wait()
            send.send(_cpu(run))

        kids = [ctx.Process(target=child, args=(w,)) for _, w in pipes]
        for k in kids:
            k.start()
        got = [r.recv() for r, _ in pipes]
        for k in kids:
            k.join()
        rounds.append(statistics.mean(got))
    return statistics.median(rounds)


def in_process(n: int, repeat: int) -> tuple[float, float]:
    """The in-process figures; returns the solve's CPU seconds per scene, alone and with two
    processes solving side by side."""
    from deck_emulator.core import simulate_batch
    from deck_emulator.studies import sensitivity as sa
    from deck_emulator.studies.store import SceneStore

    problem = sa.problem_for(sa.DEFAULT_INPUTS)
    base = 1 << max(1, (n // (len(sa.DEFAULT_INPUTS) + 2) - 1).bit_length())
    tasks = sa.tasks_for(problem, sa.sample(problem, base),
                         {"deck": "steel40", "engine": "core", "preset": "legacy"})[:n]
    sa.scene_tasks(tasks[:4])  # warm-up: the compiled laws loaded
    def prep():
        for kept in ("_deck_with", "_deck_scene"):  # a batch's own reuse only, none across runs
            if hasattr(sa, kept):
                getattr(sa, kept).cache_clear()
        return [sa._prepare(t["inputs"], "core", "legacy", "steel40") for t in tasks]

    prepared = prep()
    scenes = [p[0].scene(p[3] if p[3] is not None else p[1]) for p in prepared]
    options = [p[0].model_options() for p in prepared]
    kw = dict(rtol=prepared[0][0].rtol, atol=prepared[0][0].atol, t_max_s=prepared[0][0].t_max_s)
    import deck_emulator.core as core

    inside = []  # the solve's CPU inside the study's own run (the engine calls core's)

    def timed_solve(*a, **k):
        t0 = time.process_time()
        try:
            return simulate_batch(*a, **k)
        finally:
            inside.append(time.process_time() - t0)

    pairs = []  # (solve alone, study, solve inside the study), timed in turn
    core.simulate_batch = timed_solve
    try:
        for _ in range(repeat):
            alone = _cpu(lambda: simulate_batch(scenes, options, **kw)) / n
            inside.clear()
            pairs.append((alone, _cpu(lambda: sa.scene_tasks(tasks)) / n, sum(inside) / n))
    finally:
        core.simulate_batch = simulate_batch
    solve = statistics.median(p[0] for p in pairs)
    solve2 = side_by_side(lambda: simulate_batch(scenes, options, **kw), 2, repeat) / n
    study = statistics.median(p[1] for p in pairs)
    ratio = statistics.median(p[1] / p[0] for p in pairs)
    own = statistics.median(p[1] / p[2] for p in pairs)
    rows = sa.scene_tasks(tasks)
    prepare = statistics.median(_cpu(prep) for _ in range(repeat)) / n
    with tempfile.TemporaryDirectory() as tmp:
        store = SceneStore(Path(tmp) / "s")
        ids = [f"{i:064x}" for i in range(n)]
        stored = [{"id": i, "status": "ok", "error": "", **r} for i, r in zip(ids, rows)]
        t0 = time.process_time()
        w0 = time.perf_counter()
        for k in range(0, n, 64):  # as the runner writes: a file per flush
            store.write_batch(stored[k:k + 64])
        write_cpu, write_wall = time.process_time() - t0, time.perf_counter() - w0
    print(f"In process, {n} scenes of the sensitivity sample (steel40, legacy; {load()}):")
    print(f"  solve alone (simulate_batch)      {1e3 * solve:7.2f} ms CPU a scene")
    print(f"    the same, two processes at once {1e3 * solve2:7.2f} ms CPU a scene (as a "
          f"command's two workers run; {solve2 / solve:.2f}x)")
    print(f"  study (scene_tasks)               {1e3 * study:7.2f} ms CPU a scene")
    print(f"  ratio study / solve               {ratio:7.2f} (median of {repeat} pairs "
          f"timed in turn; {min(p[1] / p[0] for p in pairs):.2f}-"
          f"{max(p[1] / p[0] for p in pairs):.2f})")
    print(f"  ratio study / its own solve       {own:7.2f} (the solve timed inside the same "
          f"run: {min(p[1] / p[2] for p in pairs):.2f}-{max(p[1] / p[2] for p in pairs):.2f})")
    print(f"    of which preparing decks/scenes {1e3 * prepare:7.2f} ms CPU a scene")
    print(f"  store: write_batch, 64 rows a file {1e3 * write_cpu / n:6.2f} ms CPU, "
          f"{1e3 * write_wall / n:.2f} ms wall a scene (in the client)")
    return solve, solve2


def _tree(proc, cpu: dict, pss: bool) -> tuple[int, int | None]:
    """The tree's resident bytes now (RSS) and, with ``pss``, its proportional bytes (PSS;
    else None); ``cpu``: pid -> (is the command itself, CPU seconds so far), updated (a
    worker's last reading stays when it has gone)."""
    import psutil

    rss, prop = 0, 0 if pss else None
    try:
        procs = [proc, *proc.children(recursive=True)]
    except psutil.Error:
        return 0, prop
    for p in procs:
        try:
            with p.oneshot():
                rss += p.memory_info().rss
                if pss:  # reads the process's smaps: ~4 ms of CPU for a 300 MB worker
                    prop += p.memory_full_info().pss
                t = p.cpu_times()
                cpu[p.pid] = (p.pid == proc.pid, t.user + t.system)
        except psutil.Error:
            pass
    return rss, prop


def timed(cmd: list[str], env: dict) -> dict:
    """Wall, CPU (the command and every process below it, sampled: the workers are the
    children of the command's forkserver, which it never waits for, so the kernel's count of
    its waited-for children leaves them out) and peak tree memory."""
    import psutil

    la0 = load()
    w0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    ps = psutil.Process(proc.pid)
    peak, peak_pss, cpu, k = 0, 0, {}, 0
    while proc.poll() is None:
        rss, pss = _tree(ps, cpu, pss=k % PSS_EVERY == 0)
        peak, peak_pss, k = max(peak, rss), max(peak_pss, pss or 0), k + 1
        time.sleep(0.1)
    wall = time.perf_counter() - w0
    out, err = proc.communicate()
    return {"wall": wall, "cpu": sum(c for _, c in cpu.values()), "peak_mb": peak / 2**20, "pss_mb": peak_pss / 2**20,
            "status": proc.returncode,
            "client": sum(c for own, c in cpu.values() if own),
            "workers": sum(c for own, c in cpu.values() if not own),
            "err": err.strip().splitlines()[-1:] if proc.returncode else [],
            "load": f"{la0} -> {load()}"}


def deciding_input(path: Path) -> str:
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["output"] == "delta_v_contact_mph"
                and r["ST"] and r["N"] == "1024"]
    if not rows:
        return "no indices"
    best = max(rows, key=lambda r: float(r["ST"]))
    return f"{best['input']} (ST {float(best['ST']):.2f} ± {float(best['ST_conf']):.2f})"


def commands(env: dict, which: str = "both") -> list:
    """Run the whole commands; what :func:`report` prints.  Run before anything in this
    process loads numpy or the core: a page this process maps too is counted partly here,
    not in the commands' PSS (the tree's came out some 60 MB lower after the in-process
    part)."""
    cli = [sys.executable, "-m", "deck_emulator"]
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, cmd, count in (
            ("sensitivity --deck steel40 -N 1024 (8,192 scenes)",
             [*cli, "sensitivity", "--deck", "steel40", "-N", "1024", "--engine", "core",
              "--jobs", "2", "--quiet", "--out", f"{tmp}/sensitivity"], 8_192),
            ("sweep, 10,000 core scenes",
             [*cli, "sweep", *SWEEP_GRID, "--engine", "core", "--jobs", "2", "--quiet",
              "--out", f"{tmp}/sweep"], 10_000),
        ):
            if which != "both" and not label.startswith(which):
                continue
            got = timed(cmd, env)
            if "sensitivity" in label and got["status"] == 0:
                got["decided"] = deciding_input(Path(tmp) / "sensitivity" / "sensitivity.csv")
            out.append((label, count, got))
    return out


def report(done: list, solve: float, solve2: float) -> None:
    print("\nWhole commands (subprocesses, --jobs 2, the workers' start and the store "
          "included; run before the in-process part):")
    for label, count, got in done:
        print(f"* {label}: {got['wall']:.1f} s wall, {got['cpu']:.1f} s CPU "
              f"({1e3 * got['cpu'] / count:.2f} ms a scene, "
              f"{got['cpu'] / count / solve:.2f}x the solve alone, "
              f"{got['cpu'] / count / solve2:.2f}x it in two processes at once), "
              f"peak {got['peak_mb']:.0f} MB RSS, {got['pss_mb']:.0f} MB PSS (the process "
              f"tree), exit {got['status']} "
              f"{' '.join(got['err'])}; {got['load']}")
        print(f"  CPU by process (sampled every 0.1 s, each process up to its last sample, "
              f"as the total above): the command {got['client']:.1f} s, its workers (and "
              f"their server) {got['workers']:.1f} s")
        if "decided" in got:
            print("  contact ΔV decided by " + got["decided"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", type=int, default=256)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--commands", nargs="?", const="both", choices=("both", "sensitivity",
                                                                    "sweep"),
                    help="time the whole commands too (or only one of them)")
    ap.add_argument("--src", type=Path, default=ROOT / "src",
                    help="the package's source folder to measure (default: this checkout's)")
    a = ap.parse_args()
    src = str(a.src.resolve())
    sys.path.insert(0, src)
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [src, env.get("PYTHONPATH")]))
    import deck_emulator

    print(f"deck_emulator from {Path(deck_emulator.__file__).parent}")
    done = commands(env, a.commands) if a.commands else []
    solve, solve2 = in_process(a.scenes, a.repeat)
    if done:
        report(done, solve, solve2)


if __name__ == "__main__":
    main()
