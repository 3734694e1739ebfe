"""The fault campaign kept: tests/campaign.py's generators of mutated decks, card
images, scene and assembly files, physically odd decks, printouts of every layout compare
reads (mutated, damaged as scans damage them, empty), job decks whose FORTRAN is mutated,
invalid options and output paths, schedulers that are not Dask's, core runs stopped by their
wall bound, resumes of a changed study (its deck, engine, preset, grid or seed), and the smaller
promises (long names, undecodable names, SOURCE_DATE_EPOCH),
each case held to the tool's promise (a documented exit status, no traceback, one line for a
refusal, nothing written by a refusal).  A seeded sample by default, with one slice of the
full corpus chosen by the commit (``campaign.commit_slice``: successive commits run the whole
of it; ``CAMPAIGN_SLICE=k`` runs slice k); the full corpus (about 4,600 cases) under
``-m slow_corpus``."""

from __future__ import annotations

import pytest

import campaign

FAST = campaign.corpus(fast=True)
FULL = campaign.corpus(fast=False)
SLICE = campaign.commit_slice()


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


def test_the_slices_cover_the_full_corpus_each_case_once():
    slices = [campaign.sliced(FULL, k) for k in range(campaign.SLICES)]
    assert sorted(id(c) for s in slices for c in s) == sorted(id(c) for c in FULL)
    large = {c for c in {c.category for c in FULL}
             if sum(x.category == c for x in FULL) >= campaign.SLICES}
    assert all({c.category for c in s} >= large for s in slices)


@pytest.mark.parametrize("case", campaign.sliced(FULL, SLICE),
                         ids=lambda c: f"slice {SLICE}: {c.category}: {c.name}")
def test_a_case_of_the_commits_slice_of_the_full_corpus_keeps_the_promise(case, tmp_path):
    _check(case, tmp_path)


@pytest.mark.slow_corpus
@pytest.mark.parametrize("case", FULL, ids=lambda c: f"{c.category}: {c.name}")
def test_a_case_of_the_full_corpus_keeps_the_promise(case, tmp_path):
    _check(case, tmp_path)
