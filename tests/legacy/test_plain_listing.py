"""benchmarks/plain_listing.py, the speed reference of benchmarks/bench_emulator_start.py, is an
honest transcription: it prints what gfortran's REAL*8 build of the listing printed
(golden/*.r8.txt, made by scripts/make_goldens.py from legacy/luminaire.f, an independent
implementation of the same program) and what ``deck-emulator run`` prints, byte for byte."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PLAIN = ROOT / "benchmarks" / "plain_listing.py"


@pytest.mark.parametrize("deck", ["steel40", "steel20"])
def test_plain_transcription_prints_the_golden(deck):
    out = subprocess.run([sys.executable, str(PLAIN), str(ROOT / "decks" / f"{deck}.dat")],
                         capture_output=True, check=True).stdout
    assert out == (ROOT / "golden" / f"{deck}.r8.txt").read_bytes()


def test_plain_transcription_prints_what_the_emulator_prints():
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.legacy.fortran import run_deck

    deck = ROOT / "decks" / "steel40.dat"
    out = subprocess.run([sys.executable, str(PLAIN), str(deck)], capture_output=True,
                         check=True, text=True).stdout
    assert out == run_deck(read_deck(deck), trace=False).text()


def test_plain_transcription_imports_only_math_and_sys():
    """The reference must not carry the costs it is the reference against."""
    code = ("import sys; before = set(sys.modules); path = sys.argv[1]; sys.argv = sys.argv[1:]\n"
            "exec(compile(open(path).read(), path, 'exec'), {'__name__': '__main__'})\n"
            "print(sorted(set(sys.modules) - before), file=sys.stderr)")
    proc = subprocess.run([sys.executable, "-c", code, str(PLAIN), str(ROOT / "decks" / "steel40.dat")],
                          capture_output=True, text=True, check=True)
    assert proc.stderr.strip().splitlines()[-1] in ("[]", "['math']")
