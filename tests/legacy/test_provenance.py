"""Provenance on every page: the banner page before the output, the PDF's metadata
and run --json say the same facts, computed once (engine.provenance); the same run gives the
same PDF bytes."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest

from deck_emulator.cli import main

#: process-level or document tests: the README's test command runs them, a bare pytest not
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
STEEL40 = ROOT / "decks" / "steel40.dat"


def _run_json(capsys, *argv) -> dict:
    assert main(["run", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_the_facts_are_the_decks_and_the_programs(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mine.dat").write_bytes(STEEL40.read_bytes())
    facts = _run_json(capsys, "mine.dat", "--erratum", "ed-direction")["provenance"]
    # checked against hashlib over the files themselves
    assert facts["deck sha256"] == hashlib.sha256(STEEL40.read_bytes()).hexdigest()
    listing = hashlib.sha256((ROOT / "legacy" / "luminaire.f").read_bytes()).hexdigest()
    assert listing in facts["program"]
    assert facts["deck"] == facts["deck file"] == "mine.dat"
    assert facts["cards"].startswith("9 in the file")  # $DATA and 8 data cards
    assert "ed-direction" in facts["run"] and "arithmetic double" in facts["run"]
    assert "reconstruction" in facts["note"]
    shipped = _run_json(capsys, "steel40")["provenance"]
    assert shipped["deck file"] == "steel40, shipped with the tool"  # no machine's path


def test_the_banner_page_and_the_metadata_say_what_json_says(tmp_path, capsys):
    pypdf = pytest.importorskip("pypdf")
    facts = _run_json(capsys, "steel40")["provenance"]
    pdf = tmp_path / "p.pdf"
    assert main(["run", "steel40", "--pages", str(pdf)]) == 0
    reader = pypdf.PdfReader(str(pdf))
    banner = " ".join(reader.pages[0].extract_text().split())
    for key, value in facts.items():
        assert f"{key.upper()} {value}" in banner, key
    assert "THE VALUE OF VVA" not in banner  # the output starts on the next form
    assert "THE VALUE OF VVA" in reader.pages[1].extract_text()
    info = reader.metadata
    assert info["/Creator"] == facts["tool"] and info["/Subject"] == facts["note"]
    assert facts["deck sha256"] in info["/Keywords"]


def test_two_runs_give_the_same_pdf(tmp_path, monkeypatch):
    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    for name in ("a.pdf", "b.pdf"):
        assert main(["run", "steel40", "--pages", str(tmp_path / name)]) == 0
    assert (tmp_path / "a.pdf").read_bytes() == (tmp_path / "b.pdf").read_bytes()


def test_the_listing_is_printed_before_the_output(tmp_path, capsys):
    """run --pages --listing: banner, then the compile listing (every card of the package's
    luminaire.f, statement numbers counting statements, not comments or continuations), then
    the output on a new form."""
    pypdf = pytest.importorskip("pypdf")
    from deck_emulator.legacy.listing import listing_records

    source = (ROOT / "legacy" / "luminaire.f").read_text().splitlines()
    records = listing_records()
    cards = [r for r in records if r[:1] != "1" and r.strip()]
    assert len(cards) == len([c for c in source if c.strip()])  # every card, once
    # statements counted by hand: not a comment (C in column 1), not a continuation
    statements = [c for c in source if c.strip() and c[:1] != "C"
                  and (len(c) < 6 or c[5] in " 0")]
    assert records[-1].split()[0] == str(len(statements))  # the last card (END) has the last ISN
    pdf = tmp_path / "l.pdf"
    assert main(["run", "steel40", "--pages", str(pdf), "--listing"]) == 0
    pages = [p.extract_text() for p in pypdf.PdfReader(str(pdf)).pages]
    forms = sum(r[:1] == "1" for r in records)
    assert "JOB SEPARATOR" in pages[0]
    assert "COMPILE LISTING" in pages[1] and "READ(5,1)V1B" in pages[1]
    assert "THE VALUE OF VVA" in pages[1 + forms] and "COMPILE" not in pages[1 + forms]
    assert main(["run", "steel40", "--listing"]) == 2  # the listing is printed on the pages
    assert "--listing is printed on the pages of --pages" in capsys.readouterr().err


def _job_deck(tmp_path, capsys, sections: int = 1, hi: str = "0.0002") -> Path:
    """The punched job deck of steel40 with HI=``hi`` in its FORTRAN and its $DATA section
    given ``sections`` times."""
    job = tmp_path / "steel40.job"
    assert main(["punch", "steel40", "--job", "--to", "text", "--out", str(job)]) == 0
    capsys.readouterr()
    cards = job.read_text().split("\n")
    assert "      HI=0.0004" in cards
    cards[cards.index("      HI=0.0004")] = f"      HI={hi}"
    data = cards.index("$DATA")
    cards[data + 9:data + 9] = cards[data:data + 9] * (sections - 1)
    mod = tmp_path / "mod.job"
    mod.write_text("\n".join(cards))
    return mod


def test_the_listing_of_a_job_deck_is_its_own_cards(tmp_path, capsys):
    """run mod.job --listing-program --pages m.pdf --listing: the compile listing lists the
    cards the deck carries (its control cards and its FORTRAN, its first HI=0.0004 punched
    HI=0.0002), not the shipped transcription, and the banner page says so."""
    pypdf = pytest.importorskip("pypdf")
    from deck_emulator.legacy.listing import listing_records

    mod = _job_deck(tmp_path, capsys)
    cards = mod.read_text().split("\n")
    program = cards[:cards.index("$DATA")]
    records = listing_records(program)
    listed = [r for r in records if r[:1] != "1" and r.strip()]
    # every card before $DATA, once, in order: a control card as punched, a FORTRAN card's
    # columns 1-72 after the statement number
    assert [r.strip() for r in listed if r.strip().startswith("$")] == \
        [c.strip() for c in program if c.startswith("$")]
    assert len(listed) == len([c for c in program if c.strip()])
    pdf = tmp_path / "m.pdf"
    assert main(["run", str(mod), "--listing-program", "--pages", str(pdf), "--listing"]) == 0
    pages = [p.extract_text() for p in pypdf.PdfReader(str(pdf)).pages]
    banner = " ".join(pages[0].split())
    assert "LISTING the job deck's own cards" in banner
    forms = sum(r[:1] == "1" for r in records)
    listing = "\n".join(pages[1:1 + forms])
    assert "$JOB" in listing and listing.count("HI=0.0002") == 1
    # the listing's other two HI=0.0004 cards, left as they were in the deck
    assert listing.count("HI=0.0004") == sum(c.strip() == "HI=0.0004" for c in program) == 2
    assert "THE JOB DECK'S OWN CARDS" in pages[1]
    assert "THE VALUE OF VVA" in pages[1 + forms]


def test_the_listing_of_a_plain_deck_is_the_shipped_transcription(tmp_path, capsys):
    pypdf = pytest.importorskip("pypdf")
    pdf = tmp_path / "s.pdf"
    assert main(["run", "steel40", "--pages", str(pdf), "--listing"]) == 0
    reader = pypdf.PdfReader(str(pdf))
    banner = " ".join(reader.pages[0].extract_text().split())
    assert "LISTING the transcribed listing shipped with the tool" in banner
    assert "THE TRANSCRIBED SOURCE" in reader.pages[1].extract_text()
    assert main(["run", "steel40", "--json"]) == 0
    assert "listing" not in json.loads(capsys.readouterr().out)["provenance"]  # no listing


def test_several_data_sections_give_one_banner_and_a_separator_page_per_run(tmp_path,
                                                                           capsys):
    pypdf = pytest.importorskip("pypdf")
    mod = _job_deck(tmp_path, capsys, sections=2, hi="0.0004")
    pdf = tmp_path / "two.pdf"
    assert main(["run", str(mod), "--pages", str(pdf)]) == 0
    pages = [p.extract_text() for p in pypdf.PdfReader(str(pdf)).pages]
    assert sum("JOB SEPARATOR" in p for p in pages) == 1 and "JOB SEPARATOR" in pages[0]
    separators = [i for i, p in enumerate(pages) if p.lstrip("-\n").startswith("RUN ")]
    assert [pages[i].split("\n")[1] for i in separators] == ["RUN 1 OF 2", "RUN 2 OF 2"]
    for k, i in enumerate(separators, start=1):
        assert f"$DATA section {k}" in pages[i]
        assert pages[i + 1].startswith("THE VALUE OF VVA")  # the run's output, a form on
    # each run prints the same pages (the same data): the forms between separators agree
    assert separators[1] - separators[0] == len(pages) - separators[1]
