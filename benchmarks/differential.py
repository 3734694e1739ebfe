#!/usr/bin/env python3
"""The compiled listing as a standing oracle: seeded plausible decks (and some physically odd
ones), run through the compiled legacy/luminaire.f (REAL*8, built as scripts/make_goldens.py
builds it) and through the emulator in binary64, printouts compared byte for byte.

    python benchmarks/differential.py [--decks 500] [--seed 1] [--keep DIR]

A deck with ALPHA != 0 runs with the ``ed-direction`` erratum on both sides (as printed, ED
walks away from its root there: see legacy/CORRECTIONS.md). How a run ends is compared too:

* the compiled program ends normally  <-> the emulator ends normally: identical bytes;
* it traps (SIGFPE)                   <-> the emulator stops on an arithmetic error: the
  records printed up to the stop identical;
* it does not end within the goldens' time limit <-> one of the emulator's guards fires (ED
  without a root, endless halving, a post that never lands): the shorter record list is a
  prefix of the longer (the compiled program is cut off by the clock, the emulator by its
  guard, so either may have printed more).

tests/test_differential.py runs 20 decks in the default test run and this script's corpus
under the ``slow_corpus`` marker.
"""

from __future__ import annotations

import argparse
import importlib.util
import random
import shutil
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def make_goldens():
    """scripts/make_goldens.py as a module: its compile_program and run_program are reused."""
    spec = importlib.util.spec_from_file_location("make_goldens", ROOT / "scripts" / "make_goldens.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _r(x: float, places: int) -> float:
    return round(x, places)


def random_deck(rng: random.Random):
    """One deck: the 40 mph steel deck with speed, angle, post mass and inertias, springs,
    FCONST, car outline, height and DELTA drawn at random; about one deck in eight physically
    odd (car moving away, a very light or very flat post, stiff or no springs ...)."""
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.units import FT_S_PER_MPH

    base = read_deck(ROOT / "decks" / "steel40.dat")
    d = base.values  # each drawn value is the deck's own, scaled or shifted
    u = rng.uniform
    ch = {
        "VVB": _r(-u(10, 60) * FT_S_PER_MPH, 2),  # 10 to 60 mph towards the post
        "ALPHA": 0.0 if rng.random() < 0.6 else _r(u(0.03, 0.6), 4),
        "W": _r(d["W"] * u(0.5, 2.0), 2),  # the post's mass (before 2026-11: the car's, 100)
        "A": _r(d["A"] * u(0.5, 2.0), 2),
        "B": _r(d["B"] * u(0.5, 2.0), 2),
        "C": _r(d["C"] * u(0.5, 2.0), 2),
        "CK": _r(d["CK"] * u(0.3, 3.0), 1),
        "CT": _r(d["CT"] * u(0.3, 3.0), 1),
        "FCONST": _r(d["FCONST"] * u(0.3, 3.0), 1),
        "HLEN": _r(d["HLEN"] * u(0.6, 1.6), 3),
        "TLEN": _r(d["TLEN"] * u(0.6, 1.4), 3),
        "TRLEN": _r(d["TRLEN"] * u(0.6, 1.4), 3),
        "HHV": _r(d["HHV"] + u(-1.5, 1.5), 3),
        "HTV": _r(d["HTV"] + u(-1.5, 1.5), 3),
        "HTRV": _r(d["HTRV"] + u(-1.5, 1.5), 3),
        "YLFEN": _r(d["YLFEN"] + u(-2.0, 1.0), 3),
        "YRFEN": _r(d["YRFEN"] + u(-1.0, 2.0), 3),
        "HEIGHT": _r(d["HEIGHT"] * u(0.8, 1.2), 3),
        "DELTA": _r(d["DELTA"] + u(-0.1, 0.1), 4),
    }
    if rng.random() < 0.125:  # the physically odd
        odd = rng.choice(["away", "slow", "light", "flat", "stiff", "soft", "nocap", "low", "fast"])
        ch.update({
            "away": {"VVB": _r(u(1, 30), 2)},
            "slow": {"VVB": _r(-u(0.5, 5), 2)},
            "light": {"W": _r(u(1, 10), 2)},
            "flat": {"C": _r(u(1, 10), 2), "A": _r(u(100, 500), 2)},
            "stiff": {"CK": _r(u(3e5, 9e5), 1), "CT": _r(u(3e5, 9e5), 1)},
            "soft": {"CK": _r(u(100, 1000), 1), "CT": _r(u(100, 1000), 1)},
            "nocap": {"FCONST": _r(u(1e5, 9e5), 1)},
            "low": {"HEIGHT": _r(u(1, 5), 3)},
            "fast": {"VVB": _r(-u(120, 250), 2)},
        }[odd])
    return base.with_values(**ch)


def corpus(n: int, seed: int):
    rng = random.Random(seed)
    return [random_deck(rng) for _ in range(n)]


@dataclass
class Outcome:
    ending_compiled: str  # normal, trap, hang
    ending_emulator: str  # normal, arithmetic, or the guard's name
    agree: bool
    why: str = ""
    records: int = 0
    compiled_text: str = ""  # what the compiled program printed


GUARDS = ("ed_iterations", "halvings", "time_s")


def compare(deck, exe_for, workdir: Path, mg) -> Outcome:
    """Run one deck both ways and compare. ``exe_for(erratum)`` gives the compiled program."""
    from deck_emulator.legacy.emulator import EmulatorError, run_deck

    errata = ("ed-direction",) if deck["ALPHA"] != 0 else ()
    path = workdir / "deck.dat"
    path.write_text(deck.to_text())
    out, _err, ending = mg.run_program(exe_for(errata[0] if errata else None), path)
    theirs = out.splitlines()
    try:
        run = run_deck(deck, "double", errata=errata, trace=False)
        ours, ours_ending = run.records, "normal"
    except EmulatorError as exc:
        ours, ours_ending = exc.run.records, exc.guard or "error"
    o = Outcome(ending, ours_ending, False, records=len(theirs), compiled_text=out)
    if ending == "normal":
        if ours_ending != "normal":
            o.why = f"the compiled program ended normally, the emulator stopped ({ours_ending})"
        elif "".join(r + "\n" for r in ours) != out:
            o.why = _first_difference(ours, theirs)
        else:
            o.agree = True
    elif ending == "trap":
        if ours_ending != "arithmetic":
            o.why = f"the compiled program trapped, the emulator ended {ours_ending}"
        elif ours != theirs:
            o.why = _first_difference(ours, theirs)
        else:
            o.agree = True
    else:  # hang: cut off by the clock; its last line may be cut too
        if not out.endswith("\n") and theirs:
            theirs = theirs[:-1]
        n = min(len(ours), len(theirs))
        if ours_ending not in GUARDS:
            o.why = f"the compiled program did not end, the emulator ended {ours_ending}"
        elif ours[:n] != theirs[:n]:
            o.why = _first_difference(ours[:n], theirs[:n])
        else:
            o.agree = True
    return o


def _first_difference(ours, theirs) -> str:
    for i, (a, b) in enumerate(zip(ours, theirs), start=1):
        if a != b:
            return f"record {i}: emulator {a!r}, compiled {b!r}"
    return f"{len(ours)} records from the emulator, {len(theirs)} from the compiled program"


class Oracle:
    """The compiled listing, built once per erratum into a temporary directory."""

    def __init__(self, timeout_s: float | None = None):
        if shutil.which("gfortran") is None:
            raise RuntimeError("gfortran is not installed")
        self.mg = make_goldens()
        if timeout_s is not None:  # an honest run takes about 0.03 s; a hang is cut off here
            self.mg.TIMEOUT_S = timeout_s
        self._tmp = tempfile.TemporaryDirectory(prefix="oracle-")
        self.dir = Path(self._tmp.name)
        self._exes = {}

    def exe(self, erratum):
        if erratum not in self._exes:
            self._exes[erratum] = self.mg.compile_program(self.dir, "r8", erratum)
        return self._exes[erratum]

    def compare(self, deck) -> Outcome:
        return compare(deck, self.exe, self.dir, self.mg)

    def close(self):
        self._tmp.cleanup()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--decks", type=int, default=500)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", type=Path, help="write every deck that disagrees here")
    ap.add_argument("--timeout", type=float, default=2.0,
                    help="seconds after which the compiled program counts as not ending (default 2)")
    args = ap.parse_args(argv)
    oracle = Oracle(args.timeout)
    t0 = time.perf_counter()
    tally: dict[tuple[str, str], int] = {}
    bad = 0
    try:
        for i, deck in enumerate(corpus(args.decks, args.seed)):
            o = oracle.compare(deck)
            tally[(o.ending_compiled, o.ending_emulator)] = tally.get((o.ending_compiled, o.ending_emulator), 0) + 1
            if not o.agree:
                bad += 1
                print(f"deck {i}: {o.why}", file=sys.stderr)
                if args.keep:
                    args.keep.mkdir(parents=True, exist_ok=True)
                    (args.keep / f"deck{i:04d}.dat").write_text(deck.to_text())
    finally:
        oracle.close()
    print(f"{args.decks} decks (seed {args.seed}), {bad} disagree, {time.perf_counter() - t0:.1f} s")
    for (c, e), n in sorted(tally.items()):
        print(f"  compiled {c:6s} / emulator {e:13s}: {n}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT / "src"))
    raise SystemExit(main())
