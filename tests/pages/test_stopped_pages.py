"""The pages of a run that stopped say so: the banner and the PDF's metadata name where, when
and why, a closing page after the printout gives them in full, and the printout itself is
exactly the records the program printed (legacy/pages.py, app/run.py)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from deck_emulator.cli import main

#: document tests (PDFs): the README's test command runs them, a bare pytest not
pytestmark = pytest.mark.slow


def _pages(pdf: Path) -> tuple[list[str], dict]:
    pypdf = pytest.importorskip("pypdf")
    reader = pypdf.PdfReader(str(pdf))
    return [" ".join(p.extract_text().split()) for p in reader.pages], reader.metadata


def _records(capsys, *argv) -> tuple[int, list[str]]:
    code = main(["run", *argv, "--json"])
    sections = json.loads(capsys.readouterr().out)["sections"]
    return code, sections


def test_a_stopped_run_says_where_when_and_why_on_its_banner_and_last_page(tmp_path, capsys):
    """steel40_a15 as printed stops in ED at step 16 (t = 0.006 s): exit 3, and the pages say
    it on the banner, in the metadata and on a closing page, with the program's own label,
    step and time, and what would let it go on."""
    code, (section,) = _records(capsys, "steel40_a15")
    assert code == 3
    records = section["records"]
    pdf = tmp_path / "a15.pdf"
    assert main(["run", "steel40_a15", "--pages", str(pdf), "--quiet"]) == 3
    pages, info = _pages(pdf)
    banner, closing = pages[0], pages[-1]
    for page in (banner, closing):
        assert "label ED 1" in page and "step 16, t = 0.006000 s" in page
        assert "root search did not converge" in page and "--erratum ed-direction" in page
    assert "STOPPED at label ED 1" in banner
    assert "THE RUN STOPPED" in closing and f"ends with record {len(records)}" in closing
    assert "the run stopped" in info["/Title"] and "label ED 1" in info["/Keywords"]
    # the printout between them: the records as printed, none added, none changed
    printed = " ".join(" ".join(r[1:].split()) for r in records if r[1:].strip())
    assert " ".join(pages[1:-1]) == printed


def test_a_run_that_ended_has_no_closing_page(tmp_path, capsys):
    pdf = tmp_path / "s40.pdf"
    assert main(["run", "steel40", "--pages", str(pdf), "--quiet"]) == 0
    pages, info = _pages(pdf)
    assert not any("STOPPED" in p for p in pages)
    assert "stopped" not in info["/Title"]


def test_a_stopped_data_section_of_a_job_deck_is_named(tmp_path, capsys):
    """A job deck whose second $DATA section (steel40_a15's cards) stops: the banner and the
    closing page name the section (2 of 2)."""
    cards = {}
    for name in ("steel40", "steel40_a15"):
        job = tmp_path / f"{name}.job"
        assert main(["punch", name, "--job", "--to", "text", "--out", str(job)]) == 0
        cards[name] = job.read_text().split("\n")
    capsys.readouterr()
    first, second = cards["steel40"], cards["steel40_a15"]
    at = second.index("$DATA")
    both = first[:first.index("$DATA") + 9] + second[at:at + 9]
    deck = tmp_path / "two.job"
    deck.write_text("\n".join(both) + "\n")
    pdf = tmp_path / "two.pdf"
    assert main(["run", str(deck), "--pages", str(pdf), "--quiet"]) == 3
    pages, _ = _pages(pdf)
    assert "STOPPED section 2 of 2" in pages[0]
    assert "SECTION 2 of 2" in pages[-1] and "label ED 1" in pages[-1]
