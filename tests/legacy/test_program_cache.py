"""A job deck's own program is parsed and made once: its made code is kept in the user's cache
folder, named by the CRC-32 of what it was made from (its cards, the front end's CRC-32, the way
of running, Python's bytecode tag), written whole or not at all, and read back only when its
own CRC-32 holds and what it was made from equals, whole, what is to run."""

from __future__ import annotations

import pytest

from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.fortran import DialectError, Program
from deck_emulator.legacy.fortran import run as front_end
from deck_emulator.legacy import listing_lines
from deck_emulator.legacy.stops import EmulatorError

from test_emulator import GOLDEN, ROOT

STEEL40 = read_deck(ROOT / "decks" / "steel40.dat")


def _respelled(old="      HI=0.0004", new="      HI=0.00040") -> list[str]:
    """The listing with one statement respelled (HI=0.00040: the same value, so the r8
    golden is what it prints)."""
    lines = listing_lines()
    lines[lines.index(old)] = new
    return lines


@pytest.fixture
def kept(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    folder = tmp_path / "deck_emulator" / "fortran"

    def entries():
        return sorted(folder.glob("*.code"))
    entries.folder = folder
    return entries


def _printed(program: Program) -> str:
    return "".join(r + "\n" for r in program.runner(STEEL40, "double").run().records)


def test_a_programs_made_code_is_kept_and_used_without_parsing_again(kept):
    golden = (GOLDEN / "steel40.r8.txt").read_text()
    first = Program(_respelled())
    assert first._units is not None and _printed(first) == golden
    assert len(kept()) == 1
    again = Program(_respelled())
    assert again._units is None  # not parsed: its code was kept
    assert _printed(again) == golden
    Program(_respelled("      HI=0.0004", "      HI=.0004")).runner(STEEL40, "ibm7094")
    assert len(kept()) == 1  # (made only when run)


@pytest.mark.parametrize("damage", ["cut", "flipped"])
def test_a_damaged_entry_is_not_used_and_is_made_again(kept, damage):
    golden = (GOLDEN / "steel40.r8.txt").read_text()
    _printed(Program(_respelled()))
    entry = kept()[0]
    data = bytearray(entry.read_bytes())
    if damage == "cut":
        del data[len(data) // 2:]
    else:
        data[-100] ^= 0x01
    entry.write_bytes(bytes(data))
    program = Program(_respelled())
    assert program._units is not None  # parsed: the damaged code is not run
    assert _printed(program) == golden
    assert Program(_respelled())._units is None  # kept again, whole


def test_a_program_outside_the_dialect_keeps_nothing_and_a_fault_is_named_from_kept_code(kept):
    with pytest.raises(DialectError):
        Program(_respelled("      HI=0.0004", "      DOUBLE PRECISION HI"))
    assert kept() == []
    lines = _respelled("      HI=0.0004", "      HI=0.0004/(HI-HI)")
    messages = []
    for _ in range(2):  # made, then from the kept code
        with pytest.raises(EmulatorError) as info:
            Program(lines).runner(STEEL40, "double").run()
        messages.append(str(info.value))
    assert messages[0] == messages[1] and "division by zero at label START, assigning HI" in \
        messages[0]


def test_the_least_recently_used_entries_go_beyond_the_bound(kept, monkeypatch):
    monkeypatch.setattr(front_end, "PROGRAM_CACHE_ENTRIES", 2)
    for value in ("0.00040", "0.000400", "0.0004000"):
        _printed(Program(_respelled("      HI=0.0004", f"      HI={value}")))
    assert len(kept()) == 2


def test_an_entry_under_the_same_name_made_from_other_cards_is_not_run(kept, monkeypatch):
    """Two programs whose entries share a name (as two CRC-32s may): each runs its own code.
    The first divides by zero at its start; the second is the listing respelled."""
    monkeypatch.setattr(Program, "_cache_file", lambda self, key: kept.folder / "same.code")
    faulty = _respelled("      HI=0.0004", "      HI=0.0004/(HI-HI)")
    with pytest.raises(EmulatorError):
        Program(faulty).runner(STEEL40, "double").run()
    assert [p.name for p in kept()] == ["same.code"]
    other = Program(_respelled())
    assert other._units is not None  # the entry was not taken for its code: parsed
    assert _printed(other) == (GOLDEN / "steel40.r8.txt").read_text()
    with pytest.raises(EmulatorError):  # and the first, made again over it, still faults
        Program(faulty).runner(STEEL40, "double").run()
