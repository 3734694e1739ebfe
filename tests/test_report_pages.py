"""The report's pages, written by package functions (the scripts only call them)."""

from __future__ import annotations

import re
import shutil

import pytest

from deck_emulator.studies.report_tables import CASES_ALL, REPORT_ALL


@pytest.fixture(scope="module")
def report_page(tmp_path_factory):
    from deck_emulator.studies.report_page import write_page

    page = tmp_path_factory.mktemp("report") / "report_full.md"
    fig = write_page(page)
    return page.read_text(), fig


def test_the_report_page_has_every_column_and_its_figure(report_page):
    text, fig = report_page
    assert fig.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and fig.name in text
    for col, (post, mph, alpha, table) in CASES_ALL.items():
        assert f"### `{col}` — {post}, {mph} mph, α = {alpha}° (Table {table})" in text
    for section in ("## Tables 11 and 12, all 18 columns", "## Chapter V: the crash test",
                    "## The report's statements, checked"):
        assert section in text


def test_the_report_column_carries_the_reports_values_and_both_engines(report_page):
    """Each column's ΔV row: the report's value (report_tables, an independent transcription)
    and, for the steel 40 mph column, the emulator's and the core's as the engines give them."""
    from deck_emulator.studies.report_full import run_column

    text, _ = report_page
    section = text.split("### `steel40` —", 1)[1].split("### ", 1)[0]
    row = next(line for line in section.splitlines() if line.startswith("| ΔV, mph |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert float(cells[1]) == REPORT_ALL["steel40"]["delta_v_crush_mph"]
    run = run_column("steel40")
    assert cells[2] == f"{run['emulator']['delta_v_crush_mph']:.2f}"
    assert cells[4] == f"{run['core']['delta_v_crush_mph']:.2f}"
    # the core's ΔV is the crush pulse's, not the whole contact's (which is larger)
    assert run["core"]["delta_v_crush_mph"] < run["core"]["delta_v_contact_mph"]


@pytest.mark.skipif(shutil.which("gfortran") is None, reason="reads the goldens of gfortran")
def test_the_comparison_page_sets_each_deck_beside_the_report(tmp_path):
    from deck_emulator.studies.report_comparison import DECKS, write_comparison

    out = tmp_path / "comparison.md"
    write_comparison(out)
    text = out.read_text()
    for deck in DECKS:
        assert re.search(rf"^### `{deck}` — ", text, re.M), deck
    assert "## ΔV: four candidate definitions" in text
