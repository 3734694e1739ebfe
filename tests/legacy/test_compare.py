"""Printouts compared: the emulator's printout against the compiled listing's of
every golden deck agrees; one value changed is named by its record and variable; a printout
typed with other spacing agrees; what is not a printout is refused."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = ROOT / "golden"


def _goldens():
    """(deck, errata, golden) for the binary64 goldens: the compiled listing's printouts."""
    for path in sorted(GOLDEN.glob("*.r8.txt")):
        parts = path.name.split(".")
        yield pytest.param(parts[0], parts[1:-2], path, id=path.name)


@pytest.mark.parametrize("deck, errata, golden", list(_goldens()))
def test_the_emulators_printout_agrees_with_the_compiled_listings(deck, errata, golden,
                                                                  tmp_path, capsys):
    ours = tmp_path / "ours.txt"
    argv = ["run", deck, "--out", str(ours)] + [a for e in errata for a in ("--erratum", e)]
    assert main(argv) == 0
    capsys.readouterr()
    assert main(["compare", str(ours), str(golden)]) == 0
    assert "agree (exactly as printed)" in capsys.readouterr().out


def test_one_value_changed_is_named_by_record_and_variable(tmp_path, capsys):
    lines = (GOLDEN / "steel40.r8.txt").read_text().splitlines()
    k = next(i for i, line in enumerate(lines) if "THE VALUE OF XPFA IS" in line)
    changed = lines[:]
    old = changed[k].split()[-1]
    changed[k] = changed[k][: -len(old)] + f"{float(old) + 0.25:.5f}".rjust(len(old))
    theirs = tmp_path / "typed.txt"
    theirs.write_text("\n".join(changed) + "\n")
    assert main(["compare", str(GOLDEN / "steel40.r8.txt"), str(theirs), "--json"]) == 1
    answer = json.loads(capsys.readouterr().out)
    (d,) = answer["differences"]
    assert (d["record_a"], d["record_b"], d["what"]) == (k + 1, k + 1, "XPFA")
    assert d["size"] == pytest.approx(0.25)
    assert main(["compare", str(GOLDEN / "steel40.r8.txt"), str(theirs),
                 "--tolerance", "0.3"]) == 0  # within a stated tolerance


def test_a_printout_typed_with_other_spacing_agrees(tmp_path, capsys):
    """Another source's printout: its blank lines dropped and its fields re-spaced."""
    text = (GOLDEN / "steel20.r8.txt").read_text()
    typed = "\n".join(" ".join(line.split()) if "THE" in line else line
                      for line in text.splitlines() if line.strip() or line[:1] == "1")
    (tmp_path / "typed.txt").write_text(typed + "\n")
    assert main(["compare", str(GOLDEN / "steel20.r8.txt"), str(tmp_path / "typed.txt")]) == 0


def test_a_message_missing_is_a_difference(tmp_path, capsys):
    text = (GOLDEN / "steel40.r8.txt").read_text()
    cut = text.replace("THE POST HAS LOST CONTACT WITH FIRST SPRING", "", 1)
    (tmp_path / "cut.txt").write_text(cut)
    assert main(["compare", str(GOLDEN / "steel40.r8.txt"), str(tmp_path / "cut.txt")]) == 1
    assert "printed item" in capsys.readouterr().out


def test_what_is_not_a_printout_is_refused(capsys):
    assert main(["compare", str(ROOT / "decks" / "steel40.dat"),
                 str(GOLDEN / "steel40.r8.txt")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "not a printout" in err[0]
