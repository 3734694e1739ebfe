"""The compiled listing as a standing oracle (the checkout's oracle/): seeded random decks,
run through the compiled legacy/luminaire.f (REAL*8) and through the emulator in binary64,
printouts compared byte for byte, and how each run ended compared too.

20 decks run by default, and a slice of the 500-deck corpus and of the listing's 120 mutants
chosen by the checkout's commit (:func:`commit_slice`: successive commits take successive
slices, so CI covers the whole); the whole corpus runs with ``pytest -m slow_corpus``."""

from __future__ import annotations

import functools
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SMALL, SMALL_SEED = 20, 2026
LARGE, LARGE_SEED = 500, 1
#: the large corpus and the mutants in the default suite: one slice of each per commit
CORPUS_SLICE = 10
MUTANTS, MUTANT_SEED, SWAPS = 80, 3400, 40  # (test_fortran.py's larger corpus, the same)
MUTANT_SLICE = 4
#: an environment variable that names the slice to run instead of the commit's
SLICE_VARIABLE = "DECK_EMULATOR_TEST_SLICE"


@functools.cache
def commit_number() -> int:
    """The checkout's commit as a number: how many commits lead to HEAD (successive commits
    count on), or, in a shallow clone whose count says nothing, HEAD's hash read as a number;
    0 outside a git checkout."""
    def git(*args):
        return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True,
                              text=True).stdout.strip()

    if shutil.which("git") is None or not git("rev-parse", "HEAD"):
        return 0
    if git("rev-parse", "--is-shallow-repository") == "true":
        return int(git("rev-parse", "HEAD")[:12], 16)
    return int(git("rev-list", "--count", "HEAD"))


def commit_slice(total: int, size: int) -> tuple[int, range]:
    """(slice number, indices) of the slice of ``total`` items, ``size`` a slice, that this
    commit runs: the commit's number modulo the number of slices (``DECK_EMULATOR_TEST_SLICE``
    names another)."""
    slices = -(-total // size)
    chosen = os.environ.get(SLICE_VARIABLE)
    k = (int(chosen) if chosen else commit_number()) % slices
    return k, range(k * size, min(total, (k + 1) * size))

pytestmark = pytest.mark.skipif(shutil.which("gfortran") is None,
                                reason="gfortran is not installed: the compiled listing is the oracle")


def _differential():
    import oracle

    return oracle


@pytest.fixture(scope="module")
def oracle():
    diff = _differential()
    o = diff.Oracle(timeout_s=2.0)
    yield diff, o
    o.close()


@pytest.fixture(scope="module")
def small(oracle):
    """The small corpus's comparisons, each made once (index -> Comparison)."""
    diff, o = oracle
    decks = diff.corpus(SMALL, SMALL_SEED)
    return functools.cache(lambda index: o.compare(decks[index]))


@pytest.mark.parametrize("index", range(SMALL))
def test_random_deck_prints_as_the_compiled_listing(small, index):
    outcome = small(index)
    assert outcome.agree, outcome.why
    if outcome.ending_compiled == "normal":
        assert outcome.records > 100  # a whole printout, compared byte for byte


#: Hand-made decks for the lines of MAIN the random corpus does not reach (docs/oracle.md), and
#: the message the compiled program ends with on each.
HAND_MADE = {
    "hit_top.dat": "THE POST HAS HIT THE TOP OF THE VEHICLE",  # labels 240, 242
    "hit_trunk.dat": "THE POST HAS HIT THE TRUNK OF THE VEHICLE",  # labels 247, 248
    "ground_q.dat": "THE POST HAS HIT THE GROUND WITH POINT Q",  # labels 96, 97; 253
    "c_past_roof.dat": "THE POST HAS HIT THE GROUND WITH POINT R",  # point C: labels 459-461
}


@pytest.mark.parametrize("name", sorted(HAND_MADE))
def test_hand_made_deck_prints_as_the_compiled_listing(oracle, name):
    from deck_emulator.legacy.deck import read_deck

    diff, o = oracle
    outcome = o.compare(read_deck(ROOT / "tests" / "decks" / name))
    assert outcome.ending_compiled == "normal" and outcome.agree, outcome.why
    messages = [r.strip() for r in outcome.compiled_text.splitlines() if "THE POST HAS" in r]
    assert messages[-1] == HAND_MADE[name]  # then the last printout (label 98) and STOP


#: how the compiled listing ends -> how the emulator ends on the same deck (oracle.compare)
ENDINGS = {"normal": {"normal"}, "trap": {"arithmetic"}, "hang": {"ed_iterations", "halvings",
                                                                  "time_s", "runaway"}}
_LAST_EVENT = "THE POST HAS"


def test_small_corpus_reaches_normal_ends_and_stops_as_the_compiled_listing(small):
    """How each of the 20 decks ends, read from the compiled listing's run: a normal end
    (its last event message, then STOP) or a stop (a trap, or no end within the time limit);
    the emulator ends each the same way -- the same last event where the listing ends
    normally, the matching kind of stop otherwise -- and the corpus holds both."""
    diff = _differential()
    decks = diff.corpus(SMALL, SMALL_SEED)
    assert len({d.to_text() for d in decks}) == SMALL  # all different
    assert any(d["ALPHA"] != 0 for d in decks) and any(d["ALPHA"] == 0 for d in decks)
    seen = set()
    for index in range(SMALL):
        o = small(index)
        seen.add(o.ending_compiled)
        assert o.ending_emulator in ENDINGS[o.ending_compiled], (index, o.ending_compiled,
                                                                 o.ending_emulator)
        if o.ending_compiled == "normal":
            theirs = [r.strip() for r in o.compiled_text.splitlines() if _LAST_EVENT in r]
            ours = _emulator_events(decks[index])
            assert theirs and ours[-1:] == theirs[-1:], (index, theirs[-1:], ours[-1:])
    assert "normal" in seen and seen - {"normal"}, f"the corpus ends only {sorted(seen)}"


def _emulator_events(deck) -> list[str]:
    """The emulator's event messages on ``deck`` (binary64, the oracle's errata)."""
    diff = _differential()
    errata = ("ed-direction",) if deck["ALPHA"] != 0 else ()
    run = diff._listing_run(deck, errata)
    return [r.strip() for r in run.records if _LAST_EVENT in r]


def test_the_commit_picks_a_slice_and_successive_commits_cover_the_whole(monkeypatch):
    covered = set()
    for k in range(-(-LARGE // CORPUS_SLICE)):
        monkeypatch.setenv(SLICE_VARIABLE, str(k))
        number, indices = commit_slice(LARGE, CORPUS_SLICE)
        assert number == k and len(indices) == CORPUS_SLICE
        covered |= set(indices)
    assert covered == set(range(LARGE))
    monkeypatch.delenv(SLICE_VARIABLE)
    assert commit_slice(LARGE, CORPUS_SLICE)[0] == commit_number() % (LARGE // CORPUS_SLICE)


_CORPUS_K, _CORPUS_INDICES = commit_slice(LARGE, CORPUS_SLICE)


@pytest.mark.parametrize("index", _CORPUS_INDICES,
                         ids=lambda i: f"slice{_CORPUS_K}-deck{i}")
def test_this_commits_slice_of_the_large_corpus_prints_as_the_compiled_listing(oracle, index):
    diff, o = oracle
    outcome = o.compare(_large_corpus()[index])
    assert outcome.agree, f"deck {index} of the large corpus: {outcome.why}"


@functools.cache
def _large_corpus():
    return _differential().corpus(LARGE, LARGE_SEED)


@functools.cache
def _mutants():
    return _differential().mutants(MUTANTS, MUTANT_SEED, swaps=SWAPS)


_MUTANT_K, _MUTANT_INDICES = commit_slice(MUTANTS + SWAPS, MUTANT_SLICE)


@pytest.mark.parametrize("index", _MUTANT_INDICES,
                         ids=lambda i: f"slice{_MUTANT_K}-mutant{i}")
def test_this_commits_slice_of_the_mutants_prints_what_gfortran_prints(tmp_path, monkeypatch,
                                                                       index):
    """test_fortran.py's larger corpus of mutants (80 changed, 40 reordered), one slice: each
    mutant on steel40 or steel20 as there, against gfortran's build of it."""
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.legacy.fortran import Program

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    diff = _differential()
    what, lines = _mutants()[index]
    deck = read_deck(ROOT / "decks" / ("steel40.dat", "steel20.dat")[index % 2])
    exe = diff.compile_source(tmp_path, lines, "r8", f"m{index}")
    program = Program(lines)
    o = diff.compare(deck, lambda erratum: exe, tmp_path, timeout_s=3.0,
                     ours=lambda deck, errata: program.runner(deck, "double").run(), errata=())
    assert o.agree, f"mutant {index} ({what}): {o.why}"


@pytest.mark.slow_corpus
def test_large_corpus_prints_as_the_compiled_listing(oracle):
    diff, o = oracle
    bad = []
    endings = set()
    for i, deck in enumerate(diff.corpus(LARGE, LARGE_SEED)):
        outcome = o.compare(deck)
        endings.add((outcome.ending_compiled, outcome.ending_emulator))
        if not outcome.agree:
            bad.append((i, outcome.why))
    assert not bad, f"{len(bad)} of {LARGE} decks disagree, first: {bad[:3]}"
    assert ("normal", "normal") in endings
