"""The second fault campaign's reproducers (issue 37), each held to the tool's promise: a
documented exit status (0 computed, 2 bad input and nothing written, 3 a run that could not
end), one line for a refusal, no traceback, no hang."""

from __future__ import annotations

from pathlib import Path

import pytest

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[2]
STEEL40 = ROOT / "decks" / "steel40.dat"


def _one_line(err: str) -> str:
    assert "Traceback" not in err, err
    lines = [x for x in err.splitlines() if x.startswith("deck-emulator: error:")]
    assert len(lines) == 1, err
    return lines[0]


# ------------------------------------------------------- a card image cut short (item 2)


@pytest.mark.parametrize("fmt", ["binary", "cbn", "bcd"])
@pytest.mark.parametrize("cut", [2, 8])
@pytest.mark.parametrize("command", [["parse"], ["summary", "--quiet"], ["run"]])
def test_a_punched_card_image_cut_short_is_refused(tmp_path, capsys, fmt, cut, command):
    whole = tmp_path / f"s.{fmt}"
    assert main(["punch", "steel40", "--to", fmt, "--out", str(whole)]) == 0
    data = whole.read_bytes()
    cut_file = tmp_path / f"t.{fmt}"
    cut_file.write_bytes(data[:-cut])
    capsys.readouterr()
    assert main([command[0], str(cut_file), *command[1:]]) == 2
    out, err = capsys.readouterr()
    line = _one_line(err)
    assert out == ""
    assert "card 9 of the file" in line  # steel40 is nine cards: the cut is in the last
    if fmt == "binary":
        assert f"card 9 has only {160 - cut}" in line
    else:
        size = {"cbn": 160, "bcd": 80}[fmt]
        last = len(data) - size  # the punch writes the last card whole
        assert f"(bytes {last}-{len(data) - cut - 1})" in line and "cut short" in line
    # the whole image reads as the deck (1200.0 lb, the report's FCONST)
    assert main(["parse", str(whole), "--json"]) == 0
    assert '"FCONST": 1200.0' in capsys.readouterr().out.replace("\n", "").replace("  ", " ")
