"""A job deck's own program is parsed and made once: its made code is kept in the user's cache
folder, named by the SHA-256 of what it was made from (its cards, the front end's SHA-256, the
way of running, Python's bytecode tag), written whole or not at all, and read back only when its
own SHA-256 holds and what it was made from equals, whole, what is to run.  The cache is input
from outside: a folder not the user's own is not used, pruning touches only its own entries
and never follows a link, a special file in an entry's place is never waited on, a corrupt
entry is a miss that is made again."""

from __future__ import annotations

import hashlib
import marshal
import os
import threading

import pytest

from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.fortran import DialectError, Program
from deck_emulator.legacy.fortran import cache
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
    monkeypatch.setattr(cache, "PROGRAM_CACHE_ENTRIES", 2)
    for value in ("0.00040", "0.000400", "0.0004000"):
        _printed(Program(_respelled("      HI=0.0004", f"      HI={value}")))
    assert len(kept()) == 2


def test_an_entry_under_the_same_name_made_from_other_cards_is_not_run(kept, monkeypatch):
    """Two programs whose entries share a name (as two CRC-32s may): each runs its own code.
    The first divides by zero at its start; the second is the listing respelled."""
    same = "0" * 64 + ".code"
    monkeypatch.setattr(cache, "entry_name", lambda identity: same)
    faulty = _respelled("      HI=0.0004", "      HI=0.0004/(HI-HI)")
    with pytest.raises(EmulatorError):
        Program(faulty).runner(STEEL40, "double").run()
    assert [p.name for p in kept()] == [same]
    other = Program(_respelled())
    assert other._units is not None  # the entry was not taken for its code: parsed
    assert _printed(other) == (GOLDEN / "steel40.r8.txt").read_text()
    with pytest.raises(EmulatorError):  # and the first, made again over it, still faults
        Program(faulty).runner(STEEL40, "double").run()


# -------------------------------------------------------------- the cache as input from outside

MODE = (True, False)  # (binary64, checked per block: a plain run's way)


def _entry(program: Program):
    """The path of a program's entry: the SHA-256 (hashlib's, here) of what it is made from."""
    identity = program._identity(MODE)
    return hashlib.sha256(identity).hexdigest() + ".code", identity


def _forged(identity: bytes, code_bytes: bytes) -> bytes:
    """An entry of the cache's format around ``code_bytes``, its digest computed anew."""
    return (cache.MAGIC + hashlib.sha256(code_bytes).hexdigest().encode() + b"\n"
            + b"%d\n" % len(identity) + identity + code_bytes)


def test_an_entry_is_named_by_the_sha256_of_what_made_it(kept):
    program = Program(_respelled())
    _printed(program)
    name, _ = _entry(program)
    assert [p.name for p in kept()] == [name] and len(name) == 64 + len(".code")


@pytest.mark.parametrize("damage", ["bad marshal data", "not code", "truncated marshal"])
def test_an_entry_whose_digest_holds_but_whose_code_is_unreadable_is_made_again(kept, damage,
                                                                                 capsys):
    golden = (GOLDEN / "steel40.r8.txt").read_text()
    _printed(Program(_respelled()))
    name, identity = _entry(Program(_respelled()))
    good = marshal.dumps(Program(_respelled())._make(*MODE)[0])
    body = {"bad marshal data": b"\xff\x00garbage", "not code": marshal.dumps((1, "x")),
            "truncated marshal": good[:len(good) // 3]}[damage]
    (kept.folder / name).write_bytes(_forged(identity, body))
    program = Program(_respelled())
    assert program._units is not None  # a miss: parsed and made again
    assert _printed(program) == golden
    assert Program(_respelled())._units is None  # and kept again, whole
    assert capsys.readouterr().err == ""


def test_an_entry_with_a_wrong_digest_is_not_run(kept):
    """A forged entry (another program's code under this program's identity) whose digest is
    not that of its content: not run."""
    _printed(Program(_respelled()))
    name, identity = _entry(Program(_respelled()))
    faulty = Program(_respelled("      HI=0.0004", "      HI=0.0004/(HI-HI)"), cache=False)
    data = bytearray(_forged(identity, marshal.dumps(faulty._make(*MODE)[0])))
    data[len(cache.MAGIC)] ^= 0x01  # (one hex digit of the digest)
    (kept.folder / name).write_bytes(bytes(data))
    assert _printed(Program(_respelled())) == (GOLDEN / "steel40.r8.txt").read_text()


@pytest.mark.parametrize("mode", [0o777, 0o775, 0o757])
def test_a_folder_writable_by_others_is_not_used_and_said_once(kept, mode, capsys):
    golden = (GOLDEN / "steel40.r8.txt").read_text()
    kept.folder.mkdir(parents=True)
    kept.folder.chmod(mode)
    _printed(Program(_respelled()))  # made, not kept
    assert kept() == []
    name, identity = _entry(Program(_respelled(), cache=False))
    faulty = Program(_respelled("      HI=0.0004", "      HI=0.0004/(HI-HI)"), cache=False)
    (kept.folder / name).write_bytes(_forged(identity, marshal.dumps(faulty._make(*MODE)[0])))
    for _ in range(2):  # a planted entry with a good digest is not read either
        program = Program(_respelled())
        assert program._units is not None and _printed(program) == golden
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "writable by" in err[0] and "not used" in err[0]


def test_a_folder_owned_by_another_user_is_not_used(kept, monkeypatch, capsys):
    kept.folder.mkdir(parents=True, mode=0o700)
    _printed(Program(_respelled()))
    assert len(kept()) == 1
    uid = os.getuid()
    monkeypatch.setattr(cache.os, "getuid", lambda: uid + 1)  # (the folder: another's)
    program = Program(_respelled())
    assert program._units is not None  # its entry is not read
    assert _printed(program) == (GOLDEN / "steel40.r8.txt").read_text()
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and f"owned by another user (uid {uid})" in err[0]


def test_a_symlinked_folder_is_not_used_and_nothing_where_it_points_is_removed(
        kept, monkeypatch, tmp_path, capsys):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir(mode=0o700)
    theirs = [elsewhere / f"{n:08x}.code" for n in range(3)] + [elsewhere / ("a" * 64 + ".code")]
    for path in theirs:
        path.write_bytes(b"deck_emulator fortran code someone else's")
    kept.folder.parent.mkdir(parents=True, mode=0o700)
    kept.folder.symlink_to(elsewhere)
    monkeypatch.setattr(cache, "PROGRAM_CACHE_ENTRIES", 1)
    for value in ("0.00040", "0.000400"):
        _printed(Program(_respelled("      HI=0.0004", f"      HI={value}")))
    assert sorted(elsewhere.iterdir()) == sorted(theirs)
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "a symbolic link" in err[0]


def test_pruning_removes_only_its_own_entries(kept, monkeypatch, tmp_path):
    outside = tmp_path / "outside.code"
    outside.write_bytes(cache.MAGIC + b"not the cache's")
    kept.folder.mkdir(parents=True, mode=0o700)
    others = {"notes.code": b"a user's file", "b" * 64 + ".code": b"not an entry",
              "C" * 64 + ".code": cache.MAGIC + b"upper case: not a name it writes"}
    for name, data in others.items():
        (kept.folder / name).write_bytes(data)
    link = kept.folder / ("c" * 64 + ".code")
    link.symlink_to(outside)
    monkeypatch.setattr(cache, "PROGRAM_CACHE_ENTRIES", 1)
    for value in ("0.00040", "0.000400", "0.0004000"):
        _printed(Program(_respelled("      HI=0.0004", f"      HI={value}")))
    left = {p.name for p in kept.folder.iterdir()}
    assert set(others) | {link.name} <= left and len(left - set(others) - {link.name}) == 1
    assert outside.read_bytes() == cache.MAGIC + b"not the cache's" and link.is_symlink()


@pytest.mark.parametrize("kind", ["fifo", "symlink to a fifo", "folder"])
def test_a_special_file_in_an_entrys_place_is_never_waited_on(kept, tmp_path, kind):
    kept.folder.mkdir(parents=True, mode=0o700)
    name, _ = _entry(Program(_respelled(), cache=False))
    place = kept.folder / name
    if kind == "fifo":
        os.mkfifo(place)
    elif kind == "symlink to a fifo":
        os.mkfifo(tmp_path / "fifo")
        place.symlink_to(tmp_path / "fifo")
    else:
        place.mkdir()
    printed = []
    worker = threading.Thread(target=lambda: printed.append(_printed(Program(_respelled()))),
                              daemon=True)
    worker.start()
    worker.join(60)
    if worker.is_alive():  # (unblock it: a writer opens the FIFO)
        with open(tmp_path / "fifo" if kind != "fifo" else place, "wb"):
            pass
        pytest.fail("the run waited on a FIFO in its cache entry's place")
    assert printed == [(GOLDEN / "steel40.r8.txt").read_text()]
    if kind != "folder":  # replaced by the entry, the FIFO it pointed to untouched
        assert place.is_file() and not place.is_symlink() and Program(_respelled())._units is None
