"""All 18 columns of Tables 11 and 12 and Tables 8-10 in report_tables, against the scan."""

from pathlib import Path

import pytest

from deck_emulator.studies.report_tables import (
    CASES_ALL,
    NUMERIC_FIELDS_ALL,
    REPORT,
    REPORT_ALL,
    REPORT_TEXT_ALL,
    ROW_LABELS,
    TABLE8,
    TABLE9,
    TABLE10,
)

#: process-level or document tests: the README's test command runs them, a bare pytest not
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
SEED = ROOT.parent / "shared" / "seed" / "000_527dfe033c64384d.txt"
LABELS = {**ROW_LABELS, "XUL": "XUL (FT)", "YUL": "YUL (FT)", "ZUL": "ZUL (FT)"}
POSTS = ("aluminium", "steel", "twin")


def check_against_seed(lines):
    """Every cell of every column equals the scanned text; returns the number checked."""
    n = 0
    for col, (post, mph, alpha, _) in CASES_ALL.items():
        caption = "TABLE II A COMPARISON" if mph == 20 else "TABLE 12 A COMPARISON"
        end = next(i for i, s in enumerate(lines) if s.startswith(caption))
        start = max(i for i, s in enumerate(lines[:end]) if s.startswith("VEHICLE VELOCITY"))
        j = 3 * POSTS.index(post) + (0, 15, 30).index(alpha)
        for field, label in LABELS.items():
            if field not in REPORT_TEXT_ALL[col]:
                assert post != "twin" and field[1] == "U"
                continue
            row = next(s for s in lines[start:end] if s.startswith(label))
            cells = row.split("\t")[1:]
            cells += [""] * (9 - len(cells))
            cell = cells[j].strip()
            want = REPORT_TEXT_ALL[col][field]
            assert want == ("" if cell == "—" else cell), (col, field)
            n += 1
    return n


@pytest.mark.skipif(not SEED.exists(), reason="the report's text (../shared/seed) is not here")
def test_all_columns_match_the_seed():
    assert check_against_seed(SEED.read_text().splitlines()) == 12 * 14 + 6 * 17


def test_steel_columns_agree_with_the_steel_table():
    for deck, row in REPORT.items():
        for field, value in row.items():
            assert REPORT_ALL[deck][field] == value


def test_all_numbers_parse():
    for col, row in REPORT_ALL.items():
        for k in NUMERIC_FIELDS_ALL:
            if k in row:
                assert row[k] is None or isinstance(row[k], float)
    assert TABLE8["XCM_ft"] == (-1.50, -7.10) and TABLE9["XCM_ft"] == (7.61, 7.10)
    assert TABLE10["thetadot_rad_s"] == (12.50, 8.75)
