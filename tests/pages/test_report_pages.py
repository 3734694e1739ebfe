"""The report's pages, written by package functions (the scripts only call them)."""

from __future__ import annotations

import re
import shutil

import pytest

from deck_emulator.studies.report_tables import CASES_ALL, REPORT_ALL

#: process-level or document tests: the README's test command runs them, a bare pytest not
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def report_page(tmp_path_factory):
    from report.page import write_page

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
    from report.full import run_column

    text, _ = report_page
    section = text.split("### `steel40` —", 1)[1].split("### ", 1)[0]
    row = next(line for line in section.splitlines()
               if line.startswith("| ΔV (crush pulse), mph |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert float(cells[1]) == REPORT_ALL["steel40"]["delta_v_crush_mph"]
    run = run_column("steel40")
    assert cells[2] == f"{run['emulator']['delta_v_crush_mph']:.2f}"
    assert cells[4] == f"{run['core']['delta_v_crush_mph']:.2f}"
    # the core's ΔV is the crush pulse's, not the whole contact's (which is larger)
    assert run["core"]["delta_v_crush_mph"] < run["core"]["delta_v_contact_mph"]


def _table_after(text, heading):
    """The rows of the first markdown table after ``heading``, as lists of cells."""
    part = text.split(heading, 1)[1]
    rows = []
    for line in part.splitlines():
        if line.startswith("|"):
            rows.append([c.strip() for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]])
        elif rows:
            break
    return rows[2:]


def test_the_provenance_table_lists_every_column_and_the_crash_test(report_page):
    text, _ = report_page
    rows = _table_after(text, "## Provenance: what each column's inputs come from")
    listed = " ".join(r[0] for r in rows)
    for col in CASES_ALL:
        assert f"`{col}`" in listed, col
    assert any(r[0].startswith("crash test") for r in rows)
    # every steel, aluminium and twin column says it is not a prediction, and why
    assert all(r[-1].startswith(("no: ", "yes: ")) for r in rows)
    assert "Genuine predictions: **0 of 18** columns" in text
    # the old one-sentence provenance is gone: the table replaced it
    assert "Fitted to the report: no column" not in text


def test_the_readings_tables_carry_every_column(report_page):
    text, _ = report_page
    for heading in ("### ΔV, mph: ours (ours − report)",
                    "### Maximum deceleration, g: ours (ours − report)"):
        rows = _table_after(text, heading)
        assert [r[0] for r in rows] == list(CASES_ALL)
        # the report's value beside each reading is the transcription's (report_tables)
        key = "delta_v_crush_mph" if heading.startswith("### ΔV") else "max_decel_g"
        assert [float(r[1]) for r in rows] == [REPORT_ALL[c][key] for c in CASES_ALL]


def test_no_cause_is_a_program_version_and_symmetric_cells_are_not_matches(report_page):
    """The summary names no 'program version' (the twin columns' deceleration, below the
    report, contradicts it); twin 0°'s YRL, YUL, YPL, YQL are marked as inputs or symmetry
    (the report's printed -10.50, 10.50, 0.00, 0.00: the reach and the mirror plane)."""
    text, _ = report_page
    assert "program version" not in text
    for col in ("twin20", "twin40"):
        section = text.split(f"### `{col}` —", 1)[1].split("### ", 1)[0]
        for key in ("YRL", "YUL", "YPL", "YQL"):
            row = next(line for line in section.splitlines() if line.startswith(f"| {key} |"))
            assert "not a test" in row, (col, key)


@pytest.mark.skipif(shutil.which("gfortran") is None, reason="reads the goldens of gfortran")
def test_the_comparison_page_sets_each_deck_beside_the_report(tmp_path):
    from report.comparison import DECKS, write_comparison

    out = tmp_path / "comparison.md"
    write_comparison(out)
    text = out.read_text()
    for deck in DECKS:
        assert re.search(rf"^### `{deck}` — ", text, re.M), deck
    assert "## ΔV: four candidate definitions" in text
