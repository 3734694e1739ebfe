"""A campaign: ``count`` programs from ``seed``, each judged (judge.py), counted per outcome and
per class, the disagreements written to a folder (and shrunk, if asked)."""

from __future__ import annotations

import argparse
import collections
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

from .generate import FEATURES, generate
from .judge import OUTCOMES, ROADS, judge


def program_seed(seed: int, index: int) -> int:
    """The seed of a campaign's ``index``-th program (campaigns of other seeds never meet
    for fewer than a million programs)."""
    return seed * 1_000_003 + index


@dataclass
class Result:
    index: int
    seed: int
    outcome: str
    why: str
    klass: str
    ibm7094: tuple
    job: list
    minimal: list | None = None
    minimal_why: str = ""


def one(args) -> Result:
    index, seed, features, ibm7094, env_path, shrink, road = args
    from .classes import classify

    p = generate(seed, features)
    with tempfile.TemporaryDirectory(prefix="fuzz-") as tmp:
        v = judge(Path(tmp), p.source, p.data, p.job(), ibm7094=ibm7094, env_path=env_path,
                  road=road)
    klass = classify(p.source, v)
    r = Result(index, seed, v.outcome, v.why, klass, v.precisions.get("ibm7094", ()), p.job())
    if shrink and v.outcome in ("differ", "refused", "traceback"):
        from .shrink import shrink_program

        r.minimal, r.minimal_why = shrink_program(p, v, env_path=env_path, road=road)
        if r.minimal:
            from .classes import classify_cards

            r.klass = classify_cards(r.minimal, v.outcome, r.minimal_why) or r.klass
    return r


def run_campaign(seed: int, count: int, *, jobs: int = 1, features: dict | None = None,
                 ibm7094: bool = True, env_path: str | None = None, shrink: bool = False,
                 out: Path | None = None, progress: bool = True, road: str = "job") -> list[Result]:
    tasks = [(i, program_seed(seed, i), features, ibm7094, env_path, shrink, road)
             for i in range(count)]
    results: list[Result] = []
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=count, file=sys.stderr, unit="program", disable=None)
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        for r in pool.map(one, tasks, chunksize=1):
            results.append(r)
            if out is not None and (r.outcome not in ("agree", "oracle-rejected")
                                    or r.ibm7094[:1] not in ((), ("within",))):
                write_reproducer(out, r)
            if bar is not None:
                bar.update()
                bar.set_postfix_str(" ".join(f"{o}={sum(x.outcome == o for x in results)}"
                                             for o in OUTCOMES))
    if bar is not None:
        bar.close()
    return results


def write_reproducer(out: Path, r: Result) -> None:
    out.mkdir(parents=True, exist_ok=True)
    stem = f"{r.outcome if r.outcome != 'agree' else 'ibm7094'}-{r.seed}"
    (out / f"{stem}.job").write_text("".join(c + "\n" for c in r.job))
    note = [f"outcome: {r.outcome}", f"why: {r.why}", f"class: {r.klass}", f"seed: {r.seed}",
            f"ibm7094: {' '.join(r.ibm7094) if r.ibm7094 else 'not run'}"]
    if r.minimal:
        (out / f"{stem}.min.job").write_text("".join(c + "\n" for c in r.minimal))
        note.append(f"minimal: {stem}.min.job ({r.minimal_why})")
    (out / f"{stem}.txt").write_text("\n".join(note) + "\n")


def report(results: list[Result]) -> list[str]:
    """The counts: per outcome, per class within each outcome, and the 7094's."""
    n = len(results)
    lines = [f"{n} programs"]
    by = collections.Counter(r.outcome for r in results)
    for o in OUTCOMES:
        lines.append(f"  {o:16} {by[o]:6}  ({100.0 * by[o] / n if n else 0:.1f} %)")
    classes = collections.Counter((r.outcome, r.klass) for r in results
                                  if r.outcome not in ("agree",))
    if classes:
        lines.append("per class:")
        for (o, k), c in sorted(classes.items(), key=lambda x: (OUTCOMES.index(x[0][0]), -x[1])):
            lines.append(f"  {o:16} {c:6}  {k}")
    ibm = collections.Counter(_ibm7094_count(r.ibm7094) for r in results
                              if r.outcome in ("agree", "differ"))
    if ibm:
        lines.append("ibm7094 (programs the oracle and binary64 front end ran): " + ", ".join(
            f"{k} {v}" for k, v in sorted(ibm.items())))
    return lines


def _ibm7094_count(verdict: tuple) -> str:
    """The 7094's verdict as the report counts it: ``within`` the plain tolerance and within
    the run's own bound (bound.py) apart."""
    if not verdict:
        return "not run"
    if verdict[0] == "within" and verdict[1].startswith("within the running error bound"):
        return "within its run's error bound"
    return verdict[0]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m oracle.fuzz", description=(
        "Differential fuzzing of the FORTRAN front end against gfortran: COUNT random programs "
        "from SEED, each compiled by gfortran's checked build (rejected if not well defined), "
        "then its binary64 oracle build against `deck-emulator run` on the job deck."))
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--count", type=int, required=True)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--shrink", action="store_true",
                    help="shrink each disagreement to a minimal program (slow)")
    ap.add_argument("--out", type=Path, help="write each disagreement's job deck here")
    ap.add_argument("--road", choices=ROADS, default="job", help=(
        "job (default): the user's command, deck-emulator run JOB; program: the front end's "
        "Python API on the deck's FORTRAN and data cards, past the job deck's reading"))
    ap.add_argument("--env-src", metavar="DIR", help=(
        "run the front end of another checkout's src/ folder (PYTHONPATH for its runs)"))
    ap.add_argument("--no-ibm7094", action="store_true",
                    help="skip the IBM 7094 arithmetic's run of each program")
    ap.add_argument("--off", action="append", default=[], choices=sorted(FEATURES),
                    help="switch a construct off (repeatable)")
    ap.add_argument("--on", action="append", default=[], choices=sorted(FEATURES),
                    help="switch a construct on (repeatable)")
    a = ap.parse_args(argv)
    if a.count < 1 or a.jobs < 1:
        ap.error("--count and --jobs are at least 1")
    import shutil

    if shutil.which("gfortran") is None:
        print("python -m oracle.fuzz: error: gfortran is not installed (it is the oracle)",
              file=sys.stderr)
        return 2
    features = {**{k: False for k in a.off}, **{k: True for k in a.on}}
    results = run_campaign(a.seed, a.count, jobs=a.jobs, features=features,
                           ibm7094=not a.no_ibm7094, shrink=a.shrink, out=a.out,
                           road=a.road, env_path=a.env_src)
    print("\n".join(report(results)))
    bad = sum(r.outcome in ("differ", "refused", "traceback") for r in results)
    return 1 if bad else 0
