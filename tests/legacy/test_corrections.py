"""The corrections record and the errata from the installed tool: listed with their
reasons, one shown in full, the whole record; read from the package's one copy (the checkout's
legacy/CORRECTIONS.md and legacy/errata are links to it)."""

from __future__ import annotations

import json
import re
from pathlib import Path

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_the_checkouts_record_is_the_packages_one():
    for name in ("CORRECTIONS.md", "errata"):
        link = ROOT / "legacy" / name
        assert link.is_symlink()
        assert link.resolve() == (ROOT / "src" / "deck_emulator" / "legacy" / name).resolve()


def test_every_departure_and_erratum_is_listed(capsys):
    record = (ROOT / "legacy" / "CORRECTIONS.md").read_text()
    numbers = re.findall(r"^\| (\d+) \|", record, re.M)  # the record's table, counted here
    assert numbers == [str(k) for k in range(1, len(numbers) + 1)] and len(numbers) >= 19
    assert main(["corrections", "--json"]) == 0
    answer = json.loads(capsys.readouterr().out)
    keys = [e["key"] for e in answer["entries"]]
    assert keys[:len(numbers)] == numbers
    assert "ed-direction" in keys
    assert main(["corrections"]) == 0
    listing = capsys.readouterr().out
    assert "  8   `DIRC1X=`, `DIRC2X=` -- GUESS" in listing
    assert "ed-direction" in listing


def test_an_erratum_is_shown_with_its_patch(capsys):
    assert main(["corrections", "ed-direction"]) == 0
    out = capsys.readouterr().out
    assert "walks away from it" in out  # its reason
    assert "+    1 DH=D-H" in out and "-    1 DH=D+H" in out  # the patch's lines


def test_the_hint_of_a_stopped_run_names_a_command_that_answers(capsys):
    from deck_emulator.engine import errata

    hint = errata.hint("ed_iterations", ())
    command = re.search(r"deck-emulator (corrections [\w-]+)", hint).group(1).split()
    assert main(command) == 0 and "ED" in capsys.readouterr().out


def test_an_unknown_entry_is_refused_in_one_line(capsys):
    assert main(["corrections", "99"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no such entry" in err[0] and "ed-direction" in err[0]
