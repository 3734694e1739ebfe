"""The card-deck reader: 1967 input semantics, bad input, the `parse` command."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from decimal import Decimal
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from deck_emulator.cli import main
from deck_emulator.legacy.deck import NAMES, READ_LIST, Deck, DeckError, parse_deck, read_deck

ROOT = Path(__file__).resolve().parents[2]
STEEL40 = ROOT / "decks" / "steel40.dat"


def card(*fields: str) -> str:
    """A card image from up to 8 field texts, each left-justified in its 10 columns."""
    return "".join(f.ljust(10) for f in fields).ljust(80)


def good_cards() -> list[str]:
    return [card("1.0", "2.0", "3.0", "4.0", "5.0", "6.0", "7.0", "8.0") for _ in range(8)]


def deck_text(cards, control=("$DATA",), end="\n") -> str:
    return end.join([*control, *cards]) + end


def with_field(text_field: str, card_no: int = 1, field_no: int = 4) -> str:
    """The good deck with one field (10 columns) replaced by ``text_field`` as is."""
    cards = good_cards()
    c = cards[card_no - 1]
    start = (field_no - 1) * 10
    cards[card_no - 1] = c[:start] + text_field.ljust(10)[:10] + c[start + 10 :]
    return deck_text(cards)


def value_of(field_text: str) -> float:
    return parse_deck(with_field(field_text))["VVB"]


# ----------------------------------------------------------------------------- API


def test_read_list_shape():
    assert len(READ_LIST) == 8 and all(len(c) == 8 for c in READ_LIST)
    assert len(NAMES) == 64 == len(set(NAMES))
    assert NAMES[3] == "VVB" and NAMES[-1] == "FCONST" and NAMES[-2] == "CT"
    assert READ_LIST[5][5] == "DELTA"


def test_deck_object():
    deck = read_deck(STEEL40)
    assert isinstance(deck, Deck)
    assert list(deck.values) == list(NAMES) == list(deck.fields)
    assert deck["VVB"] == -58.66
    assert deck.path == str(STEEL40)
    assert len(deck.cards) == 8 and all(len(c) == 80 for c in deck.cards)
    assert deck.fields["VVB"] == "-58.66000"
    assert deck.fields["CK"] == "33000.00000"
    with pytest.raises(KeyError):
        deck["NOPE"]


def test_to_text_reproduces_the_file():
    assert read_deck(STEEL40).to_text() == STEEL40.read_text()


# ------------------------------------------------------------------- 1967 semantics


@pytest.mark.parametrize(
    "field, expected, decimal_text",
    [
        ("     12345", 0.12345, "0.12345"),  # implied decimal point
        ("12345", 12345.0, "12345.00000"),  # trailing blanks are zeros: 1234500000
        ("1", 10000.0, "10000.00000"),  # '1' then nine zeros -> 1000000000 -> 10000.0
        ("    -58.66", -58.66, "-58.66000"),  # leading blanks ignored
        ("-58.66", -58.66, "-58.66000"),  # trailing blanks after a point: zeros
        ("1 2.5", 102.5, "102.50000"),  # embedded blank is a zero
        ("     12 45", 0.12045, "0.12045"),  # embedded blank, implied point
        ("  1 2", 102.0, "102.00000"),  # '1 2' then blanks: 10200000
        ("", 0.0, "0.00000"),  # all blank
        ("0.0", 0.0, "0.00000"),
        ("-", -0.0, "-0.00000"),  # '-000000000'
        (".", 0.0, "0.00000"),
        ("   12345E2", 12.345, "12.34500"),  # exponent applies to the implied point
        ("  1.5E+02", 1.5e20, "150000000000000000000.00000"),  # column 10 blank: E+020
        ("   1.5E+02", 150.0, "150.00000"),
        ("   1.5D+02", 150.0, "150.00000"),
        ("    1.5-02", 0.015, "0.01500"),  # bare-sign exponent
        ("1.23456789", 1.23456789, "1.23456789"),  # more digits than F10.5 shows
        (" 0.1463", 0.1463, "0.14630"),
    ],
)
def test_field_semantics(field, expected, decimal_text):
    deck = parse_deck(with_field(field))
    assert deck["VVB"] == expected
    assert math.copysign(1, deck["VVB"]) == math.copysign(1, expected)
    assert deck.fields["VVB"] == decimal_text
    assert float(Decimal(deck.fields["VVB"])) == deck["VVB"]


def test_exponent_trailing_blanks_are_zeros():
    # '1.5E2' left-justified: the blanks after it make the exponent 200000
    with pytest.raises(DeckError) as info:
        value_of("1.5E2")
    assert "out of range" in str(info.value) and "1.5E200000" in str(info.value)
    assert info.value.field == "VVB" and info.value.columns == (31, 40)


def test_value_is_correctly_rounded_from_the_exact_decimal():
    # fortranformat computes float('465E27')/1e5 and rounds twice (4.6500000000000004e24);
    # the READ means the decimal 4.65E24 exactly.
    deck = parse_deck(with_field("    465E27"))
    assert deck.fields["VVB"] == "4650000000000000000000000.00000"
    assert deck["VVB"] == 4.65e24


def test_short_lines_are_padded_with_blanks():
    cards = ["1.0", "", "0.0       2.5"] + ["3.0"] * 5
    deck = parse_deck("\n".join(cards) + "\n")
    assert deck["V1B"] == 1.0 and deck["V2B"] == 0.0 and deck["PSIDB"] == 0.0
    assert deck["THDB"] == 0.0  # card 2 is a blank card
    assert deck["XCMB"] == 0.0 and deck["YCMB"] == 2.5
    assert all(len(c) == 80 for c in deck.cards)


def test_all_eighty_columns_are_data():
    cards = good_cards()
    cards[0] = cards[0][:70] + "    -1.125"
    deck = parse_deck(deck_text(cards))
    assert deck["PSIDB"] == -1.125
    assert deck.cards[0][70:] == "    -1.125"


def test_control_cards_are_skipped():
    text = deck_text(good_cards(), control=("$JOB", "$EXECUTE      IBJOB", "$IBJOB", "$DATA"))
    assert parse_deck(text)["VVB"] == 4.0
    assert parse_deck(deck_text(good_cards(), control=()))["VVB"] == 4.0


def test_crlf_and_missing_final_newline():
    plain = parse_deck(deck_text(good_cards()))
    crlf = parse_deck(deck_text(good_cards(), end="\r\n"))
    no_end = parse_deck(deck_text(good_cards()).rstrip("\n"))
    assert plain.values == crlf.values == no_end.values
    assert crlf.cards == plain.cards


def test_bytes_input():
    assert parse_deck(deck_text(good_cards()).encode("ascii"))["G"] == 8.0


# ------------------------------------------------------------------------ with_values


def test_with_values_round_trip(tmp_path):
    deck = read_deck(STEEL40)
    changed = deck.with_values(VVB=-29.33, ALPHA=0.2618, CK=1.0e12, W=0.25, F1B=-0.0)
    assert changed["VVB"] == -29.33 and changed["ALPHA"] == 0.2618
    assert changed["CK"] == 1.0e12 and changed["W"] == 0.25
    assert math.copysign(1, changed["F1B"]) == -1
    assert changed.cards[0][30:40] == " -29.33000"  # right-justified, F10.5
    assert changed.cards[4][70:80] == "   0.26180"
    assert changed.fields["ALPHA"] == "0.26180"
    # untouched fields keep their punched text
    assert changed.cards[1][:20] == deck.cards[1][:20]
    assert deck["VVB"] == -58.66  # the original is unchanged
    # the text reads back to the same deck
    path = tmp_path / "changed.dat"
    path.write_text(changed.to_text())
    again = read_deck(path)
    assert again.values == changed.values and again.cards == changed.cards
    assert all(len(line) == 80 for line in path.read_text().splitlines())


@settings(max_examples=100, deadline=None)
@given(
    name=st.sampled_from(NAMES),
    value=st.decimals(min_value=-9999, max_value=99999, places=4).map(float),
)
def test_with_values_property(name, value):
    deck = parse_deck(deck_text(good_cards())).with_values(**{name: value})
    assert deck[name] == value
    again = parse_deck(deck.to_text())  # every field read again: as with_values keeps them
    assert (again.values, again.fields, again.cards, again.warnings) == (
        deck.values, deck.fields, deck.cards, deck.warnings)


def test_with_values_rejects_what_a_card_cannot_hold():
    deck = read_deck(STEEL40)
    with pytest.raises(DeckError) as info:
        deck.with_values(W=0.1 + 0.2)  # 0.30000000000000004: no 10-column decimal
    assert info.value.field == "W" and info.value.card == 2
    for bad in (math.inf, math.nan, "1.0"):
        with pytest.raises(DeckError):
            deck.with_values(W=bad)
    with pytest.raises(DeckError, match="unknown"):
        deck.with_values(NOPE=1.0)


# ------------------------------------------------------------------------- bad input


def bad(text, **kw) -> DeckError:
    with pytest.raises(DeckError) as info:
        parse_deck(text, path="bad.dat", **kw)
    err = info.value
    assert str(err).startswith("bad.dat: ")
    return err


def test_error_message_format():
    err = bad(with_field("-58.x6"))
    assert str(err) == "bad.dat: card 1, columns 31-40 (VVB): not a number: '-58.x6    '"
    assert (err.card, err.columns, err.field, err.path) == (1, (31, 40), "VVB", "bad.dat")
    assert isinstance(err, ValueError)


@pytest.mark.parametrize(
    "field, card_no, field_no, name, columns",
    [
        ("1.2.3", 1, 4, "VVB", (31, 40)),
        ("abc", 2, 3, "W", (21, 30)),
        ("1,5", 8, 8, "FCONST", (71, 80)),
        ("1.0Q3", 6, 6, "DELTA", (51, 60)),
        ("++1", 3, 1, "XCMB", (1, 10)),
        ("1e5", 5, 8, "ALPHA", (71, 80)),  # no lower case on a 1967 card
        ("     1.00E", 7, 2, "HTRV", (11, 20)),  # exponent without digits (column 20)
    ],
)
def test_not_a_number(field, card_no, field_no, name, columns):
    err = bad(with_field(field, card_no, field_no))
    assert (err.card, err.columns, err.field) == (card_no, columns, name)
    msg = str(err)
    assert f"card {card_no}" in msg and f"columns {columns[0]}-{columns[1]}" in msg
    assert f"({name})" in msg and "not a number" in msg and repr(field.ljust(10)[:10]) in msg


@pytest.mark.parametrize("position", [4, 9])
def test_control_card_among_or_after_the_data_cards_is_named(position):
    lines = good_cards()
    lines.insert(position - 1, "$DATA")
    err = bad(deck_text(lines))
    assert err.card == position and err.columns is None
    assert f": card {position}: $DATA control card " in str(err)
    assert "not a number" not in str(err) and "extra card" not in str(err)


def test_blanks_after_column_80_are_tolerated():
    lines = good_cards()
    lines[2] = lines[2] + "   "
    assert parse_deck(deck_text(lines)).cards == parse_deck(deck_text(good_cards())).cards


def test_implied_decimal_point_applies_before_the_range_check():
    # F10.5: '     1E309' means 1 x 10**-5 x 10**309 = 1E304, a finite REAL*8
    assert value_of("     1E309") == 1e304
    # and 1E314 means 1E309, which no double holds
    assert "out of range" in str(bad(with_field("     1E314")))


def test_a_blank_card_is_read_as_zeros_with_a_warning():
    # the last line of the file is empty: card 8 is a blank card
    text = deck_text(good_cards()[:7]) + "\n"
    deck = parse_deck(text)
    assert all(deck[name] == 0.0 for name in READ_LIST[7])
    assert len(deck.warnings) == 1 and deck.warnings[0].startswith("card 8 was blank")
    assert parse_deck(deck_text(good_cards())).warnings == ()


def test_missing_card():
    err = bad(deck_text(good_cards()[:5]))
    assert err.card == 6
    msg = str(err)
    assert "card 6: missing card" in msg
    assert "T1B, T2B, T3B, HLEN, TLEN, DELTA, YLFEN, YRFEN" in msg
    assert "only 5 data cards" in msg


def test_missing_last_card():
    err = bad(deck_text(good_cards()[:7]))
    assert err.card == 8 and "XCO" in str(err) and "FCONST" in str(err)


def test_extra_card():
    err = bad(deck_text(good_cards() + [card("9.0")]))
    assert err.card == 9 and "card 9" in str(err) and "extra card" in str(err)


def test_extra_blank_line_is_a_card():
    err = bad(deck_text(good_cards()) + "\n")
    assert err.card == 9 and "blank line" in str(err)


@pytest.mark.parametrize("text", ["", "$DATA\n", "$DATA\n$IBSYS\n", "\n\n", "   \n"])
def test_empty_deck(text):
    err = bad(text)
    assert "empty deck" in str(err) and err.card is None


def test_line_too_long():
    cards = good_cards()
    cards[2] = cards[2] + "123"
    err = bad(deck_text(cards))
    assert (err.card, err.columns) == (3, (81, 83))
    assert "card 3, columns 81-83" in str(err) and "83 columns" in str(err)


def test_tab():
    cards = good_cards()
    cards[1] = "1.0\t2.0"
    err = bad(deck_text(cards))
    assert (err.card, err.columns, err.field) == (2, (4, 4), "THDB")
    assert "card 2, column 4 (THDB)" in str(err) and "tab" in str(err)


def test_tab_in_a_later_field():
    cards = good_cards()
    cards[6] = cards[6][:44] + "\t" + cards[6][45:]
    err = bad(deck_text(cards))
    assert (err.card, err.columns, err.field) == (7, (45, 45), "HHV")


def test_non_ascii_character():
    cards = good_cards()
    cards[3] = cards[3][:52] + "é" + cards[3][53:]
    err = bad(deck_text(cards))
    assert (err.card, err.columns, err.field) == (4, (53, 53), "YYSO")
    assert "non-ASCII" in str(err) and "U+00E9" in str(err)


def test_undecodable_bytes(tmp_path):
    cards = good_cards()
    data = deck_text(cards).encode("ascii")
    # card 1 is line 2 (after $DATA); column 5 of it
    offset = len(b"$DATA\n") + 4
    data = data[:offset] + b"\xff" + data[offset + 1 :]
    path = tmp_path / "bytes.dat"
    path.write_bytes(data)
    with pytest.raises(DeckError) as info:
        read_deck(path)
    err = info.value
    assert (err.card, err.columns, err.field) == (1, (5, 5), "V1B")
    assert "0xFF" in str(err)


def test_byte_order_mark():
    err = bad("\ufeff" + deck_text(good_cards(), control=()))
    assert (err.card, err.columns) == (1, (1, 1)) and "byte-order mark" in str(err)


@pytest.mark.parametrize("ch, word", [("\x00", "NUL"), ("\x07", "0x07"), ("\x7f", "0x7F"),
                                      ("\x0c", "0x0C"), ("\r", "carriage return")])
def test_control_characters(ch, word):
    cards = good_cards()
    cards[7] = cards[7][:9] + ch + cards[7][10:]
    err = bad(deck_text(cards))
    assert (err.card, err.columns, err.field) == (8, (10, 10), "XCO")
    assert word in str(err)


def test_bad_character_in_a_control_card():
    err = bad(deck_text(good_cards(), control=("$DA\tTA",)))
    assert err.card is None and err.line == 1 and "line 1, column 4" in str(err)


def test_file_does_not_exist(tmp_path):
    with pytest.raises(DeckError) as info:
        read_deck(tmp_path / "nope.dat")
    assert "no such file" in str(info.value) and "nope.dat" in str(info.value)


def test_directory(tmp_path):
    with pytest.raises(DeckError, match="directory"):
        read_deck(tmp_path)


# ------------------------------------------------------------------------------- CLI


def run_cli(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(ROOT / "src"), *filter(None, [env.get("PYTHONPATH")])]
    )
    return subprocess.run(
        [sys.executable, "-m", "deck_emulator", *args],
        capture_output=True, text=True, env=env, timeout=60,
    )


def test_cli_parse_json():
    proc = run_cli("parse", str(STEEL40), "--json")
    assert proc.returncode == 0, proc.stderr
    answer = json.loads(proc.stdout)
    assert answer["command"] == "parse" and answer["source"] == str(STEEL40)
    values = answer["values"]
    assert list(values) == list(NAMES)
    assert values["VVB"] == -58.66 and values["CK"] == 33000.0
    assert values["DELTA"] == 0.1463 and values["FCONST"] == 1200.0
    assert '"VVB": -58.66' in proc.stdout and '"CK": 33000.0' in proc.stdout
    # each card's fields with the columns FORMAT(8F10.5) reads them from
    first = answer["cards"][0]["fields"][0]
    assert first["columns"] == [1, 10] and first["name"] == NAMES[0]
    assert proc.stderr == ""


def test_cli_parse_table(capsys):
    assert main(["parse", str(STEEL40)]) == 0
    out = capsys.readouterr().out
    assert "card 8" in out and "FCONST" in out and "-58.66" in out and "71-80" in out


def test_cli_usage_error(capsys):
    assert main([]) == 2
    assert main(["parse"]) == 2


def _bad_deck_files(tmp_path: Path) -> dict[str, tuple[Path, list[str]]]:
    """name -> (path, strings the message must contain)."""
    cases = {}

    def put(name, data, *needles):
        path = tmp_path / f"{name}.dat"
        if isinstance(data, str):
            data = data.encode("utf-8")
        path.write_bytes(data)
        cases[name] = (path, list(needles))

    put("missing", deck_text(good_cards()[:6]), "card 7: missing card", "TRLEN", "ZZRO")
    put("extra", deck_text(good_cards() + [card("1.0")]), "card 9", "extra card")
    put("nan", with_field("-58.x6"), "card 1, columns 31-40 (VVB)", "not a number")
    cards = good_cards()
    cards[4] = cards[4] + "X"
    put("long", deck_text(cards), "card 5, column 81", "81 columns")
    cards = good_cards()
    cards[5] = "\t0.0"
    put("tab", deck_text(cards), "card 6, column 1 (T1B)", "tab")
    cards = good_cards()
    cards[2] = cards[2][:35] + "µ" + cards[2][36:]
    put("nonascii", deck_text(cards), "card 3, column 36 (CK)", "non-ASCII")
    put("empty", "", "empty deck")
    cases["nofile"] = (tmp_path / "does-not-exist.dat", ["does-not-exist.dat", "no such file"])
    return cases


def test_cli_bad_input(tmp_path):
    for name, (path, needles) in _bad_deck_files(tmp_path).items():
        for extra in (["--json"], []) if name in ("nan", "nofile") else (["--json"],):
            proc = run_cli("parse", str(path), *extra)
            assert proc.returncode == 2, (name, proc)
            assert proc.stdout == "", name
            assert proc.stderr.startswith("deck-emulator: error: "), (name, proc.stderr)
            assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
            for needle in needles:
                assert needle in proc.stderr, (name, needle, proc.stderr)


# ------------------------------------------------------------------------ property


_CHARS = st.one_of(
    st.sampled_from(list("0123456789.-+ED $\t\r")),
    st.characters(min_codepoint=0, max_codepoint=0x7F),
    st.characters(),  # anything, non-ASCII included
    st.sampled_from(["\udcff", "\udc80", "\ud800", "\ufeff", "\x00", "\x85", "\u2028"]),
)
_LINE = st.one_of(
    st.text(_CHARS, max_size=90),
    st.lists(st.sampled_from(["", " ", "1", "-5.5", "12345", "1.5E2", "x", "   0.0"]),
             max_size=9).map(lambda fs: "".join(f.ljust(10) for f in fs)),
)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    lines=st.lists(_LINE, max_size=12),
    end=st.sampled_from(["\n", "\r\n"]),
    final=st.booleans(),
    control=st.booleans(),
)
def test_random_card_images_parse_or_raise_deck_error(lines, end, final, control):
    text = end.join((["$DATA"] if control else []) + lines) + (end if final else "")
    try:
        deck = parse_deck(text)
    except DeckError as err:
        assert str(err)
        return
    assert len(deck.values) == 64 and all(isinstance(v, float) for v in deck.values.values())
    assert all(len(c) == 80 for c in deck.cards)
    for name in NAMES:
        assert float(Decimal(deck.fields[name])) == deck[name]


@settings(max_examples=200, deadline=None)
@given(data=st.binary(max_size=900))
def test_random_bytes_parse_or_raise_deck_error(data):
    try:
        parse_deck(data)
    except DeckError:
        pass


@settings(max_examples=100, deadline=None)
@given(
    fields=st.lists(st.text(st.sampled_from(list("0123456789.-+ED ")), max_size=10),
                    min_size=64, max_size=64)
)
def test_random_numeric_fields(fields):
    cards = ["".join(f.ljust(10) for f in fields[i * 8 : i * 8 + 8]) for i in range(8)]
    try:
        deck = parse_deck("\n".join(cards))
    except DeckError as err:
        assert err.card is not None and err.field in NAMES and err.columns is not None
        return
    for name in NAMES:
        assert float(Decimal(deck.fields[name])) == deck[name]


def test_eight_blank_cards_are_a_deck_of_zeros():
    deck = parse_deck("\n" * 8)
    assert set(deck.values.values()) == {0.0}


# ------------------------------------------------------------------ files cut short


@pytest.mark.parametrize("size", [700, 690, 640, 600])
def test_a_deck_cut_short_is_refused_naming_the_card(size):
    # The shipped deck's 9 lines are 81 bytes each ($DATA and 8 cards of 80 columns, each
    # ended by LF): a cut at byte `size` stops inside data card (size // 81), column
    # size % 81 -- computed here from the file's layout, not from the reader.
    data = STEEL40.read_bytes()
    assert data.count(b"\n") == 9 and len(data) == 9 * 81
    cut = data[:size]
    card, column = size // 81, size % 81
    with pytest.raises(DeckError) as info:
        parse_deck(cut, path="cut.dat")
    message = str(info.value)
    assert f"card {card}" in message and f"after column {column}" in message
    assert "cut short" in message and "\n" not in message


def test_a_whole_last_card_without_a_line_end_still_reads():
    data = STEEL40.read_bytes()
    assert parse_deck(data.rstrip(b"\n")).values == parse_deck(data).values
    # a short card with its line end is a card padded with blanks (the documented rule)
    short = data.replace(b"1200.0    \n", b"1200.0\n")
    assert parse_deck(short)["FCONST"] == 1200.0


def test_a_utf8_byte_order_mark_is_named_by_every_reader():
    from deck_emulator.legacy.cardimage import detect_format
    from deck_emulator.legacy.jobdeck import parse_job

    data = b"\xef\xbb\xbf" + STEEL40.read_bytes()
    for read in (lambda: detect_format(data), lambda: parse_job(data), lambda: parse_deck(data)):
        with pytest.raises(DeckError, match="byte-order mark") as info:
            read()
        assert "parity" not in str(info.value)


def _read_by_decimal(raw: str, decimals: int = 5):
    """A field read through Python's decimal module, independently of read_field's digit
    arithmetic: (value, exact fixed-point text), or None where the field is no number or out
    of range."""
    import re
    from decimal import localcontext

    text = raw.lstrip(" ").replace(" ", "0")
    if text == "":
        return 0.0, "0.00000"
    m = re.fullmatch(r"(?P<m>[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+))"
                     r"(?:(?:[ED](?P<s1>[+-]?)|(?P<s2>[+-]))(?P<e>[0-9]+))?", text)
    if m is None:
        return None
    exact = Decimal(m["m"])
    if "." not in m["m"]:
        exact = exact.scaleb(-decimals)
    if m["e"] is not None and exact != 0:
        e = int((m["s1"] or m["s2"] or "+") + m["e"])
        if abs(e) > 400:
            return None
        exact = exact.scaleb(e)
    value = float(exact)
    if not math.isfinite(value) or (exact != 0 and value == 0.0):
        return None
    if exact == 0 and exact.is_signed():
        value = -0.0
    with localcontext() as ctx:
        ctx.prec = 1000
        whole, _, fraction = format(exact, "f").partition(".")
    return value, f"{whole}.{fraction.rstrip('0').ljust(5, '0')}"


@settings(max_examples=1500, deadline=None)
@given(raw=st.text(alphabet=" +-.0123456789ED", max_size=10)
       | st.from_regex(r" {0,3}[+-]?[0-9]{0,6}\.?[0-9]{0,6}([ED][+-]?[0-9]{1,3})?", fullmatch=True)
       .map(lambda t: t[:10]),
       decimals=st.integers(0, 9))
def test_a_field_reads_as_the_decimal_module_reads_it(raw, decimals):
    """read_field's exact value, by digits and a power of ten, is the decimal module's: the
    same float (sign of zero included) and the same fixed-point text, or both refuse."""
    from deck_emulator.legacy.deck import read_field

    expected = _read_by_decimal(raw, decimals)
    try:
        got = read_field(raw, name="X", card=1, columns=(1, 10), path=None, decimals=decimals)
    except DeckError:
        got = None
    if expected is None or got is None:
        assert got == expected
    else:
        assert got[1] == expected[1]
        assert math.copysign(1, got[0]) == math.copysign(1, expected[0])
        assert got[0] == expected[0]
