"""The fault campaign kept: tests/campaign.py's generators of mutated decks, card
images, scene and assembly files, physically odd decks, printouts of every layout compare
reads (mutated, damaged as scans damage them, empty), job decks whose FORTRAN is mutated,
invalid options and output paths, schedulers that are not Dask's, core runs stopped by their
wall bound, resumes of a changed study (its deck, engine, preset, grid or seed), and the smaller
promises (long names, undecodable names, SOURCE_DATE_EPOCH),
each case held to the tool's promise (a documented exit status, no traceback, one line for a
refusal, nothing written by a refusal).  A seeded sample by default; the full corpus (about
2,900 cases) under ``-m slow_corpus``."""

from __future__ import annotations

import pytest

import campaign

FAST = campaign.corpus(fast=True)
FULL = campaign.corpus(fast=False)


def _check(case, tmp_path):
    result = campaign.run_case(case, tmp_path)
    assert not result.broken, (case.category, case.name, case.argv, result.broken)


def test_the_sample_covers_every_category():
    assert {c.category for c in FAST} == {c.category for c in FULL} == {
        "mutated decks", "physically odd decks", "mutated card images",
        "scene and assembly files", "printouts", "invalid options", "output paths",
        "card images cut short", "scene and assembly bombs", "closed streams and bare encodings",
        "sources that are not files", "mutated programs", "hostile schedulers",
        "stopped core runs", "smaller promises", "resumes of a changed study"}


@pytest.mark.parametrize("case", FAST, ids=lambda c: f"{c.category}: {c.name}")
def test_a_case_of_the_sample_keeps_the_promise(case, tmp_path):
    _check(case, tmp_path)


@pytest.mark.slow_corpus
@pytest.mark.parametrize("case", FULL, ids=lambda c: f"{c.category}: {c.name}")
def test_a_case_of_the_full_corpus_keeps_the_promise(case, tmp_path):
    _check(case, tmp_path)
