"""Card image formats, keypunch codes, job decks, the punch and the printed pages.

Expected bytes are written out here from the formats' definitions (the simulator's card code:
binary = two bytes a column, rows 12..9 in the column's 12 low bits, shifted left 4; CBN =
six rows a byte, odd parity in bit 6, record mark in bit 7; BCD = one 6-bit character a
byte, even parity in bit 6, record mark on the first) and from the keypunch charts, not
from the module under test.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from deck_emulator.cli import build_parser, main
from deck_emulator.legacy.cardimage import FORMATS, detect_format, read_images, write_images
from deck_emulator.legacy.deck import NAMES, DeckError, read_deck
from deck_emulator.legacy.jobdeck import data_deck_texts, job_deck_texts, parse_job
from deck_emulator.legacy.keypunch import to_char, to_holes

ROOT = Path(__file__).resolve().parents[2]
STEEL40 = ROOT / "decks" / "steel40.dat"
CODES = ("026", "029")

# ------------------------------------------------------------- an independent encoder

# Rows of each character, typed from the IBM 026 (FORTRAN) and 029 charts.
_COMMON_ROWS = {
    " ": "", ".": "12-8-3", ",": "0-8-3", "-": "11", "$": "11-8-3", "*": "11-8-4", "/": "0-1",
    **{str(d): str(d) for d in range(10)},
    **{ch: f"12-{i}" for i, ch in enumerate("ABCDEFGHI", 1)},
    **{ch: f"11-{i}" for i, ch in enumerate("JKLMNOPQR", 1)},
    **{ch: f"0-{i}" for i, ch in enumerate("STUVWXYZ", 2)},
}
ROWS = {
    "026": {**_COMMON_ROWS, "+": "12", "=": "8-3", "(": "0-8-4", ")": "12-8-4", "'": "8-4"},
    "029": {**_COMMON_ROWS, "+": "12-8-6", "=": "8-6", "(": "12-8-5", ")": "11-8-5", "'": "8-5"},
}
_BIT = {"12": 11, "11": 10, "0": 9, **{str(r): 9 - r for r in range(1, 10)}}


def hol(ch: str, code: str) -> int:
    rows = ROWS[code][ch]
    return sum(1 << _BIT[r] for r in rows.split("-")) if rows else 0


def odd_parity(six: int) -> int:  # the byte with bit 6 set so that its 7 bits hold an odd count
    return six | (0 if bin(six).count("1") % 2 else 0x40)


def even_parity(six: int) -> int:
    return six | (0x40 if bin(six).count("1") % 2 else 0)


def bcd_of(column: int) -> int:
    """BCD character of a column: zone 12 = 060, 11 = 040, 0 = 020 (with a digit or 8),
    digits 1-9 as themselves, 8 adds 8; blank 020, digit 0 012, 0-8-2 032."""
    if column == 0:
        return 0o20
    if column == 1 << 9:
        return 0o12
    zone = {1 << 11: 0o60, 1 << 10: 0o40, 1 << 9: 0o20, 0: 0}[column & 0xE00]
    digit = 0
    for r in range(1, 10):
        if column & (1 << (9 - r)) and r != 8:
            digit = r
    if column & (1 << 1):
        digit += 8
    return zone | digit


def encode(texts: list[str], fmt: str, code: str) -> bytes:
    out = bytearray()
    for text in texts:
        cols = [hol(ch, code) for ch in text.ljust(80)]
        if fmt == "text":
            out += text.encode() + b"\n"
        elif fmt == "binary":
            for c in cols:
                out += bytes([(c & 0xF) << 4, c >> 4])
        elif fmt == "cbn":
            card = bytearray()
            for c in cols:
                card += bytes([odd_parity(c >> 6), odd_parity(c & 0x3F)])
            card[0] |= 0x80
            out += card
        elif fmt == "bcd":
            card = bytearray(even_parity(bcd_of(c)) for c in cols)
            card[0] |= 0x80
            out += card
    return bytes(out)


def steel40_texts() -> list[str]:
    return STEEL40.read_text().splitlines()


# ------------------------------------------------------------------ keypunch codes


def test_keypunch_tables_against_the_charts():
    for code in CODES:
        for ch, rows in ROWS[code].items():
            assert to_holes(ch, code) == hol(ch, code), (code, ch)
            assert to_char(hol(ch, code), code) == ch, (code, ch)
    assert to_holes("+", "026") == 0b1000_0000_0000  # row 12 alone
    assert to_holes("+", "029") == 0b1000_0000_1010  # 12-8-6
    assert to_char(0b1000_0000_0000, "029") == "&"


# ----------------------------------------------------- one card by hand, every format

CARD1 = "0.0       0.0       0.0       -58.66    0.0       0.0       0.0       0.0"
# each character's bytes, written out from the definitions
BIN = {"0": (0x00, 0x20), ".": (0x20, 0x84), " ": (0x00, 0x00), "-": (0x00, 0x40),
       "5": (0x00, 0x01), "8": (0x20, 0x00), "6": (0x80, 0x00)}
CBN = {"0": (0x08, 0x40), ".": (0x61, 0x02), " ": (0x40, 0x40), "-": (0x10, 0x40),
       "5": (0x40, 0x10), "8": (0x40, 0x02), "6": (0x40, 0x08)}
BCD = {"0": 0x0A, ".": 0x7B, " ": 0x50, "-": 0x60, "5": 0x05, "8": 0x48, "6": 0x06}


def hand_card(fmt: str) -> bytes:
    text = CARD1.ljust(80)
    if fmt == "text":
        return CARD1.encode() + b"\r\n"
    if fmt == "binary":
        return bytes(b for ch in text for b in BIN[ch])
    if fmt == "cbn":
        card = bytearray(b for ch in text for b in CBN[ch])
    else:
        card = bytearray(BCD[ch] for ch in text)
    card[0] |= 0x80
    return bytes(card)


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_card_written_by_hand_reads_in_every_format(fmt):
    card = hand_card(fmt)
    assert read_images(card, fmt).cards  # readable
    assert detect_format(card * 8) == fmt
    # the whole report deck: the hand card as card 1, the rest from the independent encoder
    texts = steel40_texts()
    data = encode(texts[:1], fmt, "026") + card + encode(texts[2:], fmt, "026")
    job = parse_job(data)
    assert job.card_format == fmt
    assert job.decks[0].values == read_deck(STEEL40).values
    assert job.decks[0]["VVB"] == -58.66 and job.decks[0]["CK"] == 33000.0


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("code", CODES)
def test_the_report_deck_in_every_format_and_code(fmt, code):
    texts = steel40_texts()
    by_hand = encode(texts, fmt, code)
    punched = write_images(data_deck_texts([read_deck(STEEL40)]), fmt, code)
    for data in (by_hand, punched):
        job = parse_job(data, keypunch=code)
        assert job.card_format == fmt and len(job.decks) == 1
        assert job.decks[0].values == read_deck(STEEL40).values
    if fmt in ("binary", "cbn"):  # fixed-length formats: the punch is the definition
        assert punched == by_hand


def test_026_and_029_read_the_plus_sign_differently():
    texts = steel40_texts()
    texts[1] = "+1.5" + texts[1][4:]
    for code in CODES:
        assert parse_job(encode(texts, "cbn", code), keypunch=code).decks[0]["V1B"] == 1.5
    # the 026 plus (12) is the 029 ampersand: not a number
    msg = error_of(encode(texts, "cbn", "026"), code="029")
    assert "card 1, columns 1-10 (V1B): not a number: '&1.5      '" in msg
    # the 029 plus (12-8-6) is no 026 character
    msg = error_of(encode(texts, "cbn", "029"), code="026")
    assert "card 2 of the file, column 1: rows 12-8-6 punched: no character of the 026" in msg


# ------------------------------------------------------------------ malformed images


def error_of(data: bytes, fmt: str = "auto", code=None) -> str:
    with pytest.raises(DeckError) as info:
        parse_job(data, path="deck", card_format=fmt, keypunch=code)
    return str(info.value)


def test_binary_of_odd_length():
    data = encode(steel40_texts(), "binary", "026")
    msg = error_of(data[:-1], "binary")
    assert "not a multiple of 160" in msg and "card 9 of the file" in msg


def test_cbn_parity_error_names_card_and_column():
    data = bytearray(encode(steel40_texts(), "cbn", "026"))
    data[160 * 2 + 2 * 33] ^= 0x40  # card 3, column 34, its first byte's parity bit
    msg = error_of(bytes(data), "cbn")
    assert "card 3 of the file, column 34" in msg and "parity" in msg


def test_bcd_parity_error_names_card_and_column():
    data = bytearray(encode(steel40_texts(), "bcd", "026"))
    data[80 * 4 + 12] ^= 0x40  # card 5, column 13
    msg = error_of(bytes(data), "bcd")
    assert "card 5 of the file, column 13" in msg and "parity" in msg


def test_a_punch_combination_no_code_allows_names_the_rows():
    data = bytearray(encode(steel40_texts(), "binary", "026"))
    column = (1 << 11) | (1 << 10) | (1 << 9)  # 12-11-0
    data[160 * 3 + 2 * 6: 160 * 3 + 2 * 6 + 2] = bytes([(column & 0xF) << 4, column >> 4])
    msg = error_of(bytes(data))
    assert "card 4 of the file, column 7" in msg and "rows 12-11-0" in msg and "026" in msg


def test_cbn_record_of_odd_length():
    data = encode(steel40_texts(), "cbn", "026")
    msg = error_of(data[:159] + data[160:], "cbn")
    assert "card 1 of the file" in msg and "159 bytes" in msg


@pytest.mark.parametrize("fmt", ["cbn", "bcd"])
@pytest.mark.parametrize("cut", [1, 2, 8, 79])
def test_a_card_image_cut_short_is_refused_naming_the_card_and_bytes(fmt, cut):
    data = encode(steel40_texts(), fmt, "026")  # nine whole cards, written by hand
    size = {"cbn": 160, "bcd": 80}[fmt]
    if fmt == "cbn" and cut % 2:
        return  # an odd record is refused as odd (test_cbn_record_of_odd_length)
    for card_format in (fmt, "auto"):
        msg = error_of(data[:-cut], card_format)
        assert "card 9 of the file" in msg and "cut short" in msg
        assert f"(bytes {8 * size}-{9 * size - cut - 1})" in msg
        assert f"{size - cut} bytes, not {size}" in msg


@pytest.mark.parametrize("fmt", ["cbn", "bcd"])
def test_a_short_record_is_a_card_when_something_follows_it(fmt):
    texts = steel40_texts()
    data = bytearray(encode(texts, fmt, "026"))
    size = {"cbn": 160, "bcd": 80}[fmt]
    # the last card's trailing blank columns (all its columns after 76) left out, with a
    # tape mark after it: read as blanks, the same deck
    short = bytes(data[:8 * size]) + bytes(data[8 * size:8 * size + 76 * size // 80])
    assert parse_job(short + bytes([0o217]), card_format=fmt).decks[0].values == \
        read_deck(STEEL40).values
    # the same bytes with nothing after: refused
    assert "cut short" in error_of(short, fmt)


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_job_deck_without_data_fails_in_one_line_with_status_2(tmp_path, capsys, fmt):
    texts = [t for t in job_deck_texts([read_deck(STEEL40)])]
    cut = texts.index("$ENTRY         MAIN")
    path = tmp_path / f"nodata.{fmt}"
    path.write_bytes(write_images(texts[:cut] + ["$IBSYS"], fmt, "026"))
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no data cards" in err and "$DATA" in err


@pytest.mark.parametrize("fmt", [*FORMATS, "auto"])
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.one_of(
    st.binary(max_size=700),
    st.lists(st.sampled_from([b"\x80", b"\xc0", b"\x40", b"\x0a", b"\x20", b"\x50", b"$DATA",
                              b"\n", b"0.0", b"\x8f"]), max_size=200).map(b"".join),
))
def test_random_bytes_raise_nothing_but_deck_error(fmt, data):
    try:
        parse_job(data, card_format=fmt)
    except DeckError as err:
        assert str(err)


# ------------------------------------------------------------------------- the punch

_FIELD_VALUES = st.one_of(
    st.integers(-99999, 999999).map(lambda n: n / 1000),
    st.floats(-1e6, 1e6, allow_nan=False).map(lambda x: round(x, 2)),
    st.sampled_from([0.0, -58.66, 0.1463, 33000.0, 1e-5, 123456789.0]),
)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(values=st.lists(_FIELD_VALUES, min_size=64, max_size=64),
       fmt=st.sampled_from(FORMATS), code=st.sampled_from(CODES))
def test_punched_decks_read_back_the_same_64_values(values, fmt, code):
    deck = read_deck(STEEL40).with_values(**dict(zip(NAMES, values)))
    for texts in (data_deck_texts([deck]), job_deck_texts([deck])):
        job = parse_job(write_images(texts, fmt, code), card_format="auto", keypunch=code)
        assert job.decks[0].values == deck.values


def test_punch_command_writes_every_format(tmp_path):
    for fmt in FORMATS:
        out = tmp_path / f"steel40.{fmt}"
        assert main(["punch", str(STEEL40), "--to", fmt, "--out", str(out)]) == 0
        expected = encode(steel40_texts(), fmt, "026")
        if fmt == "text":  # the simulator's text punch drops trailing blanks
            expected = b"".join(t.rstrip().encode() + b"\n" for t in steel40_texts())
        if fmt == "bcd":  # trailing blank columns (0x50) end a record early, but the last
            texts = steel40_texts()  # card's, which is whole, so that a cut can be told
            expected = b"".join(re.sub(rb"(?<=.)\x50+$", b"", encode([t], "bcd", "026"), flags=re.S)
                                for t in texts[:-1]) + encode(texts[-1:], "bcd", "026")
        assert out.read_bytes() == expected
        assert read_deck(STEEL40).values == parse_job(out.read_bytes()).decks[0].values


# ------------------------------------------------------------------------- job decks


def test_package_copy_of_the_listing_is_the_listing():
    copy = ROOT / "src" / "deck_emulator" / "legacy" / "luminaire.f"
    assert copy.read_bytes() == (ROOT / "legacy" / "luminaire.f").read_bytes()


def test_several_data_sections_are_decks_in_turn():
    d40 = read_deck(STEEL40)
    d20 = read_deck(ROOT / "decks" / "steel20.dat")
    job = parse_job(write_images(job_deck_texts([d40, d20]), "cbn", "026"))
    assert [d.values for d in job.decks] == [d40.values, d20.values]
    assert "same program" in job.source_verdict


def test_a_job_deck_cut_short_in_its_last_data_section_is_refused():
    """Cut inside the second $DATA section's last card (the file ends at its column 52, no line
    end): that card's missing fields are not read as zeros (a plain deck says the same)."""
    texts = job_deck_texts([read_deck(STEEL40), read_deck(ROOT / "decks" / "steel20.dat")])
    last = max(i for i, t in enumerate(texts) if t.strip() and not t.startswith("$"))
    cut = "\n".join(texts[:last]) + "\n" + texts[last][:52]
    with pytest.raises(DeckError, match=r"\$DATA section 2 .*card 8: .*cut short"):
        parse_job(cut.encode())
    whole = "\n".join(texts[:last] + [texts[last].ljust(80)])  # all 80 columns, no line end
    assert len(parse_job(whole.encode()).decks) == 2


def test_a_changed_statement_is_named():
    texts = job_deck_texts([read_deck(STEEL40)])
    i = texts.index("      HI=0.0004")
    texts[i] = "      HI=0.0002"
    verdict = parse_job(write_images(texts, "text", "026")).source_verdict
    assert "NOT the listing's program" in verdict and "HI=0.0002" in verdict
    assert "HI=0.0004" in verdict and f"deck card {i + 1}" in verdict


def test_sequence_columns_and_blanks_do_not_count():
    texts = job_deck_texts([read_deck(STEEL40)])
    i = texts.index("      HI=0.0004")
    texts[i] = "      HI = 0.0004".ljust(72) + "LUM00123"
    data = write_images(texts, "bcd", "029")
    assert "same program" in parse_job(data, keypunch="029").source_verdict
    # read in the other code, the 029 '(' (12-8-5) is no 026 character
    assert "rows 12-8-5 punched" in error_of(data, code="026")


GOLDEN = ROOT / "golden" / "steel40.r8.txt"


def test_run_a_job_deck_in_text_with_pages(tmp_path, capsys):
    job = tmp_path / "steel40.job"
    pdf = tmp_path / "steel40.pdf"
    out = tmp_path / "out.txt"
    assert main(["punch", str(STEEL40), "--job", "--to", "text", "--out", str(job)]) == 0
    assert main(["run", str(job), "--out", str(out), "--pages", str(pdf), "--paper",
                 "striped"]) == 0
    err = capsys.readouterr().err
    assert "source: the same program as the listing" in err
    assert out.read_text() == GOLDEN.read_text()
    check_first_page(pdf, GOLDEN.read_text().splitlines())


def test_run_a_job_deck_in_column_binary(tmp_path, capsys):
    job = tmp_path / "steel40.cbn"
    out = tmp_path / "out.txt"
    assert main(["punch", str(STEEL40), "--job", "--to", "cbn", "--out", str(out.with_suffix(".x"))]) == 0
    job.write_bytes(encode(job_deck_texts([read_deck(STEEL40)]), "cbn", "026"))
    assert (out.with_suffix(".x")).read_bytes() == job.read_bytes()
    assert main(["run", str(job), "--out", str(out)]) == 0
    assert "source: the same program as the listing" in capsys.readouterr().err
    assert out.read_text() == GOLDEN.read_text()


# ------------------------------------------------------------------------- pages

def check_first_page(pdf: Path, records: list[str]) -> None:
    """The output's first form: the PDF's second page (the first is the banner page)."""
    pypdf = pytest.importorskip("pypdf")
    page = pypdf.PdfReader(str(pdf)).pages[1]
    assert (float(page.mediabox.width), float(page.mediabox.height)) == (14.875 * 72, 11 * 72)
    seen = []

    def visit(text, cm, tm, font, size):
        if text.strip():  # the text origin: the text matrix, then the current matrix
            x = tm[4] * cm[0] + tm[5] * cm[2] + cm[4]
            y = tm[4] * cm[1] + tm[5] * cm[3] + cm[5]
            seen.append((text, x, y, size * tm[0] * cm[0]))

    page.extract_text(visitor_text=visit)
    # expected by hand: the first record is '1' (skip to channel 1, line 1, nothing printed),
    # then ' ' (line 2), '' = blank control (line 3, nothing), ' ' (line 4) ...
    assert records[0] == "1" and records[1].startswith("     THE VALUE OF VVA")
    line, expected = 1, []
    for rec in records[1:]:
        if rec[:1] == "1":
            break
        line += {"0": 2, "-": 3, "+": 0}.get(rec[:1], 1)
        if line > 66:
            break
        if rec[1:].strip():
            first = len(rec[1:]) - len(rec[1:].lstrip())
            expected.append((rec[1:].strip(), line, first + 1))
    assert len(seen) == len(expected) > 5
    margin = (14.875 - 13.2) / 2 * 72  # 132 positions at 10 an inch, centred
    for (text, x, y, size), (want, line, position) in zip(seen, expected):
        assert text.strip() == want
        assert x == pytest.approx(margin + (position - 1) * 7.2, abs=0.01)  # 10 to the inch
        assert y == pytest.approx(792 - line * 12 + 0.04 * 72, abs=0.01)  # 6 lines an inch
    # the face, embedded: DejaVu Sans Mono's glyphs advance 1233/2048 em (read from the font
    # file below), so 1/10 inch at 72 / 10 / (1233/2048) points
    fonts = [ref.get_object() for ref in page["/Resources"]["/Font"].values()]
    assert [f["/BaseFont"].split("+")[-1] for f in fonts] == ["DejaVuSansMono"]
    descendant = fonts[0]["/DescendantFonts"][0].get_object()
    assert "/FontFile2" in descendant["/FontDescriptor"].get_object()  # embedded, TrueType
    assert {round(size, 4) for *_, size in seen} == {round(7.2 * 2048 / 1233, 4)}


def test_the_printers_face_advances_a_tenth_of_an_inch():
    """The advance pages.py writes down, read from the font file the package ships."""
    from fontTools.ttLib import TTFont

    from deck_emulator.legacy import pages

    with pages.face_file().open("rb") as file:
        font = TTFont(file)
        cmap, hmtx = font.getBestCmap(), font["hmtx"]
        advances = {hmtx[cmap[ord(c)]][0] for c in "0123456789.-+ ABCXYZ*"}
        assert advances == {1233} and font["head"].unitsPerEm == 2048
    assert pages.FONT_SIZE_PT * pages._ADVANCE_EM == pytest.approx(7.2)


def test_the_same_printout_gives_the_same_pdf_bytes(tmp_path, monkeypatch):
    from deck_emulator.legacy.pages import write_pdf

    records = ["1", " THE VALUE OF VVA IS       -58.60262", "0", " T = 0.0016"] * 30
    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    write_pdf(records, tmp_path / "a.pdf", metadata={"Title": "t"})
    write_pdf(records, tmp_path / "b.pdf", metadata={"Title": "t"})
    assert (tmp_path / "a.pdf").read_bytes() == (tmp_path / "b.pdf").read_bytes()
    assert b"/CreationDate" not in (tmp_path / "a.pdf").read_bytes()
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "0")  # reproducible builds' date: 1970-01-01
    write_pdf(records, tmp_path / "c.pdf")
    assert b"/CreationDate (D:19700101000000Z)" in (tmp_path / "c.pdf").read_bytes()


def test_pages_layout_obeys_carriage_control(tmp_path):
    from deck_emulator.legacy.pages import layout

    records = ["1", " A", "0B", "-C", "+D", " E", "1F"] + [" x"] * 70
    forms = layout(records)
    assert forms[0][:6] == [(1, ""), (2, "A"), (4, "B"), (7, "C"), (7, "D"), (8, "E")]
    assert forms[1][0] == (1, "F") and forms[1][65] == (66, "x") and forms[2][0] == (1, "x")


# ------------------------------------------------------------------------- README

def readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    section = text.split("## Decks from the archive", 1)[1].split("\n## ", 1)[0]
    return [line.strip() for line in re.findall(r"^deck-emulator .*$", section, re.M)]


def test_readme_archive_commands_run(tmp_path):
    commands = readme_commands()
    assert {c.split()[1] for c in commands} >= {"punch", "run", "parse"}
    for fmt in FORMATS:
        assert any(f"--to {fmt}" in c for c in commands), fmt
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), *filter(None, [env.get("PYTHONPATH")])])
    (tmp_path / "decks").mkdir()
    (tmp_path / "decks" / "steel40.dat").write_bytes(STEEL40.read_bytes())
    for command in commands:
        argv = shlex.split(command)[1:]
        if argv[0] == "run":  # a full run is tested above; here: the options and the deck
            args = build_parser().parse_args(argv)
            assert args.source
            continue
        proc = subprocess.run([sys.executable, "-m", "deck_emulator", *argv], cwd=tmp_path,
                              capture_output=True, text=True, env=env, timeout=120)
        assert proc.returncode == 0, (command, proc.stderr)


# ------------------------------------------------------------------------- the CLI


def malformed_files(tmp_path) -> dict[str, tuple[Path, str]]:
    texts = steel40_texts()
    cases = {}

    def put(name, data, needle):
        path = tmp_path / name
        path.write_bytes(data)
        cases[name] = (path, needle)

    put("odd.bin", encode(texts, "binary", "026")[:-3], "not a multiple of 160")
    cbn = bytearray(encode(texts, "cbn", "026"))
    cbn[5] ^= 0x40
    put("parity.cbn", bytes(cbn), "card 1 of the file, column 3: parity error")
    bcd = bytearray(encode(texts, "bcd", "026"))
    bcd[80 * 8 + 79] ^= 0x40
    put("parity.bcd", bytes(bcd), "card 9 of the file, column 80: parity error")
    bad = bytearray(encode(texts, "binary", "026"))
    bad[160 * 2 + 10: 160 * 2 + 12] = bytes([0x30, 0x00])  # column 6: rows 8-9
    put("rows.bin", bytes(bad), "card 3 of the file, column 6: rows 8-9 punched")
    return cases


def test_malformed_images_end_in_one_line_with_status_2(tmp_path, capsys):
    for name, (path, needle) in malformed_files(tmp_path).items():
        for command in ("parse", "run"):
            assert main([command, str(path)]) == 2, name
            captured = capsys.readouterr()
            assert captured.out == "" and captured.err.count("\n") == 1, (name, captured.err)
            assert captured.err.startswith("deck-emulator: error: ") and needle in captured.err


def test_a_blank_card_is_said_on_stderr(tmp_path, capsys):
    path = tmp_path / "blank8.dat"
    path.write_text("\n".join(steel40_texts()[:8]) + "\n\n")
    assert main(["parse", str(path), "--json"]) == 0
    err = capsys.readouterr().err
    assert "warning: card 8 was blank" in err


def test_several_data_sections_run_in_turn(tmp_path, capsys):
    path = tmp_path / "twice.dat"
    path.write_text(STEEL40.read_text() * 2)  # two $DATA sections
    out = tmp_path / "out.txt"
    assert main(["run", str(path), "--out", str(out)]) == 0
    assert out.read_text() == GOLDEN.read_text() * 2
    err = capsys.readouterr().err
    assert "$DATA section 1 (card 1 of the file)" in err
    assert "$DATA section 2 (card 10 of the file)" in err


def test_a_tilde_card_ends_a_text_file():
    data = STEEL40.read_bytes() + b"~\nanything after the end of file\n"
    assert parse_job(data).decks[0].values == read_deck(STEEL40).values


def test_a_file_that_reads_in_two_formats_is_refused_as_ambiguous():
    # blank cards in column binary: every byte 0x40 (odd parity), the first 0xC0 -- whose
    # even bytes also have low nibbles 0, as a binary card image's have
    blank_cbn = bytes([0xC0] + [0x40] * 159)
    with pytest.raises(DeckError) as info:
        detect_format(blank_cbn * 8)
    assert "ambiguous" in str(info.value) and "--card-format" in str(info.value)
    assert read_images(blank_cbn * 8, "cbn").cards == ((0,) * 80,) * 8
