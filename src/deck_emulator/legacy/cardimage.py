"""Card image files: the formats archives keep punched cards in (open-simh's ``sim_card.c``:
text, binary, column binary, BCD), read, detected and written; a file cut short is refused.
Each format's layout and where the package departs from the simulator: docs/emulator.md,
"Card image files".
"""

from __future__ import annotations

from dataclasses import dataclass

from deck_emulator.legacy.deck import CARD_COLUMNS, DeckError
from deck_emulator.vocabulary.choices import CARD_FORMATS

# (keypunch, the codes of binary cards, is imported where a binary card is read or punched:
# a text deck's run does not load it)

__all__ = [
    "FORMATS", "CardFile", "detect_format", "read_images", "card_texts", "write_images",
    "bcd_to_holes", "parity_bit",
]

FORMATS = CARD_FORMATS
BINARY_CARD_BYTES = 160
BCD_CARD_BYTES = 80
RECORD_MARK = 0x80
TAPE_MARK = 0o217

# The simulator's special end cards: one punched column, column 1.
END_CARDS = {"~eor": 0o7, "~eof": 0o15, "~eoi": 0o17}
_END_BY_HOLES = {v: k for k, v in END_CARDS.items()}


def parity_bit(six: int) -> int:
    """0o100 if the six-bit value has an odd number of ones (the bit that makes the
    seven-bit byte even), else 0: ``sim_parity_table``."""
    return 0o100 if bin(six & 0o77).count("1") % 2 else 0


def bcd_to_holes(bcd: int) -> int:
    """The 12-bit column of a six-bit BCD character (``sim_bcd_to_hol``)."""
    bcd &= 0o77
    if bcd == 0:
        return 0x82  # 8-2
    if bcd == 0o20:
        return 0  # blank
    hol = {0o00: 0x000, 0o20: 0x200, 0o40: 0x400, 0o60: 0x800}[bcd & 0o60]
    if (bcd & 0o17) == 10 and (bcd & 0o60) != 0o20:
        return hol | (1 << 9)
    low = bcd & 0o17
    if low > 9:
        hol |= 0x2  # row 8
        low -= 8
    if low != 0:
        hol |= 1 << (9 - low)
    return hol


#: The BCD character that reads back as a column, where one does (the inverse of the reader).
_HOLES_TO_BCD = {bcd_to_holes(b): b for b in range(64)}
assert len(_HOLES_TO_BCD) == 64


@dataclass(frozen=True)
class CardFile:
    """A card file read: its format and its cards.  A card is a ``str`` (text format, the
    line as it stands, at most 80 columns) or a tuple of 80 twelve-bit columns."""

    format: str
    cards: tuple[str | tuple[int, ...], ...]


def _err(reason: str, path, card=None, column=None) -> DeckError:
    return DeckError(reason, file_card=card, columns=(column, column) if column else None,
                     path=path)


# ------------------------------------------------------------------------- reading


def _read_text(data: bytes, path) -> list[str]:
    text = data.decode("utf-8", errors="surrogateescape")
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    cards: list[str] = []
    for number, line in enumerate(lines, start=1):
        if line.endswith("\r"):
            line = line[:-1]
        if line.startswith("~") and line[1:].strip(" \t") == "":
            break  # end of file
        if len(line) > CARD_COLUMNS and line[CARD_COLUMNS:].strip(" ") == "":
            line = line[:CARD_COLUMNS]
        cards.append(line)
    return cards


def _looks_text(data: bytes, path) -> None:
    """Raise DeckError unless every byte is printable ASCII, a line end or a tab."""
    for offset, byte in enumerate(data):
        if not (0x20 <= byte <= 0x7E or byte in (0x0A, 0x0D, 0x09)):
            raise _err(f"byte 0x{byte:02X} at offset {offset} is not text", path,
                       data.count(b"\n", 0, offset) + 1)


def _read_binary(data: bytes, path) -> list[tuple[int, ...]]:
    if len(data) % BINARY_CARD_BYTES:
        whole, rest = divmod(len(data), BINARY_CARD_BYTES)
        raise _err(f"file is {len(data)} bytes, not a multiple of {BINARY_CARD_BYTES}: "
                   f"binary card images are {BINARY_CARD_BYTES} bytes a card, and card "
                   f"{whole + 1} has only {rest}", path, whole + 1)
    cards = []
    for start in range(0, len(data), BINARY_CARD_BYTES):
        chunk = data[start:start + BINARY_CARD_BYTES]
        number = start // BINARY_CARD_BYTES + 1
        columns = []
        for c in range(CARD_COLUMNS):
            first, second = chunk[2 * c], chunk[2 * c + 1]
            if first & 0x0F:
                raise _err(f"byte 0x{first:02X} at offset {start + 2 * c}: the low four bits "
                           "of a column's first byte must be 0 in a binary card image",
                           path, number, c + 1)
            columns.append(((first >> 4) & 0xF) | (second << 4))
        cards.append(tuple(columns))
    return cards


def _records(data: bytes, path, name: str) -> list[tuple[int, bytes]]:
    """Split at record marks: (offset, record) pairs, record marks cleared."""
    if data and not data[0] & RECORD_MARK:
        raise _err(f"the first byte (0x{data[0]:02X}) has no record mark (bit 7): not a "
                   f"{name} card file", path, 1)
    records = []
    start = 0
    for i in range(1, len(data) + 1):
        if i == len(data) or data[i] & RECORD_MARK:
            records.append((start, bytes([data[start] & 0x7F]) + data[start + 1:i]))
            start = i
    return records


def _cut_short(path, number: int, offset: int, record: bytes, full: int) -> DeckError:
    return _err(f"its record (bytes {offset}-{offset + len(record) - 1}) is the file's last "
                f"and {len(record)} bytes, not {full}: the file looks cut short (give the last card all "
                f"{full} bytes, or end the file with a tape mark, byte 0x8F)", path, number)


def _read_cbn(data: bytes, path) -> list[tuple[int, ...]]:
    cards = []
    for number, (offset, record) in enumerate(_records(data, path, "CBN"), start=1):
        if data[offset] == TAPE_MARK and len(record) == 1:
            break
        if offset + len(record) == len(data) and len(record) < BINARY_CARD_BYTES:
            raise _cut_short(path, number, offset, record, BINARY_CARD_BYTES)
        if len(record) > BINARY_CARD_BYTES or len(record) % 2:
            raise _err(f"record of {len(record)} bytes at offset {offset}: a CBN card is "
                       f"{BINARY_CARD_BYTES} bytes (two a column) or a shorter even number",
                       path, number)
        columns = [0] * CARD_COLUMNS
        for i, byte in enumerate(record):
            six = byte & 0o77
            if parity_bit(six) == (byte & 0o100):
                raise _err(f"parity error in byte 0x{data[offset + i]:02X} at offset "
                           f"{offset + i} (CBN bytes have odd parity, bit 6)",
                           path, number, i // 2 + 1)
            columns[i // 2] |= six << 6 if i % 2 == 0 else six
        cards.append(tuple(columns))
    return cards


def _read_bcd(data: bytes, path) -> list[tuple[int, ...]]:
    cards = []
    for number, (offset, record) in enumerate(_records(data, path, "BCD"), start=1):
        if data[offset] == TAPE_MARK and len(record) == 1:
            break
        if len(record) > BCD_CARD_BYTES:
            raise _err(f"record of {len(record)} bytes at offset {offset}: a BCD card holds "
                       f"at most {BCD_CARD_BYTES} characters", path, number, BCD_CARD_BYTES + 1)
        if offset + len(record) == len(data) and len(record) < BCD_CARD_BYTES:
            raise _cut_short(path, number, offset, record, BCD_CARD_BYTES)
        columns = [0] * CARD_COLUMNS
        for i, byte in enumerate(record):
            six = byte & 0o77
            if parity_bit(six) != (byte & 0o100):
                raise _err(f"parity error in byte 0x{data[offset + i]:02X} at offset "
                           f"{offset + i} (BCD bytes have even parity, bit 6)",
                           path, number, i + 1)
            columns[i] = bcd_to_holes(six)
        cards.append(tuple(columns))
    return cards


_READERS = {"text": _read_text, "binary": _read_binary, "cbn": _read_cbn, "bcd": _read_bcd}


_UTF8_BOM = b"\xef\xbb\xbf"


def detect_format(data: bytes, path=None) -> str:
    """The card format of ``data``, when it is unambiguous; else :class:`DeckError`."""
    if not data:
        return "text"
    fits = []
    for name in FORMATS:
        try:
            (_looks_text if name == "text" else _READERS[name])(data, path)
        except DeckError:
            continue
        fits.append(name)
    if len(fits) == 1:
        return fits[0]
    if data.startswith(_UTF8_BOM):
        raise DeckError("the file starts with a UTF-8 byte-order mark (bytes EF BB BF): save "
                        "the deck as plain ASCII", path=path)
    if len(fits) > 1:
        raise DeckError(f"the card format is ambiguous: the file reads as {' and as '.join(fits)}"
                        "; say which with --card-format", path=path)
    return _nearest_format(data)  # reading it in that format names the error


def _nearest_format(data: bytes) -> str:
    """The format a file that reads in none most resembles: with a record mark on its first
    byte, CBN or BCD by the parity most of the first record's bytes have (a parity error then
    names its card and column); else the simulator's pick (``_sim_parse_card``, MODE_AUTO):
    binary when the first card's first bytes have their low four bits clear, else text."""
    if data[0] & RECORD_MARK:
        end = next((i for i in range(1, len(data)) if data[i] & RECORD_MARK), len(data))
        odd = sum(1 for b in data[:end] if parity_bit(b & 0o77) != (b & 0o100))
        return "cbn" if 2 * odd > end else "bcd"
    if len(data) >= BINARY_CARD_BYTES and not any(
            data[i] & 0x0F for i in range(0, BINARY_CARD_BYTES, 2)):
        return "binary"
    return "text"


def read_images(data: bytes, card_format: str = "auto", path=None) -> CardFile:
    """Read a card file's bytes in ``card_format`` ('auto', 'text', 'binary', 'cbn', 'bcd')."""
    if card_format == "auto":
        card_format = detect_format(data, path)
    if card_format not in _READERS:
        raise DeckError(f"unknown card format {card_format!r} (one of {', '.join(FORMATS)})",
                        path=path)
    cards = _READERS[card_format](data, path)
    return CardFile(card_format, tuple(cards))


def card_texts(card_file: CardFile, keypunch: str | None = None, path=None) -> list[str]:
    """Every card as text: text cards as they stand, binary ones through ``keypunch``
    ('026', the default, or '029').  A column no character of the code stands for is a
    :class:`DeckError` naming the card, the column and the rows punched."""
    from deck_emulator.legacy.keypunch import rows_text, to_char  # (binary cards only)

    code = keypunch or "026"
    texts = []
    for number, card in enumerate(card_file.cards, start=1):
        if isinstance(card, str):
            texts.append(card)
            continue
        if card[0] in _END_BY_HOLES and not any(card[1:]):
            texts.append(_END_BY_HOLES[card[0]])
            continue
        chars = []
        for column, holes in enumerate(card, start=1):
            ch = to_char(holes, code)
            if ch is None:
                hint = ""
                if holes == 0x82 and card_file.format == "bcd":
                    hint = " (BCD character 00, which the simulator's punch writes for a blank)"
                raise _err(f"rows {rows_text(holes)} punched: no character of the {code} "
                           f"keypunch code{hint}", path, number, column)
            chars.append(ch)
        texts.append("".join(chars))
    return texts


# ------------------------------------------------------------------------- writing


def _card_holes(text: str, number: int, code: str) -> list[int]:
    from deck_emulator.legacy.keypunch import to_holes

    if len(text) > CARD_COLUMNS:
        raise _err(f"card text is {len(text)} columns; a card holds {CARD_COLUMNS}",
                   None, number, CARD_COLUMNS + 1)
    if text in END_CARDS:
        return [END_CARDS[text]] + [0] * (CARD_COLUMNS - 1)
    columns = []
    for column, ch in enumerate(text.ljust(CARD_COLUMNS), start=1):
        holes = to_holes(ch, code)
        if holes is None:
            raise _err(f"{ch!r} has no punch in the {code} keypunch code", None, number, column)
        columns.append(holes)
    return columns


def write_images(texts: list[str], card_format: str, keypunch: str | None = None) -> bytes:
    """Punch the card texts in ``card_format`` with ``keypunch`` ('026' default, '029')."""
    from deck_emulator.legacy.keypunch import rows_text

    code = keypunch or "026"
    out = bytearray()
    for number, text in enumerate(texts, start=1):
        if card_format == "text":
            if len(text) > CARD_COLUMNS or not all(" " <= ch <= "~" for ch in text):
                raise _err("not a text card (printable ASCII, at most 80 columns)", None, number)
            out += text.rstrip(" ").encode("ascii") + b"\n"
            continue
        columns = _card_holes(text, number, code)
        if card_format == "binary":
            for col in columns:
                out += bytes([(col & 0x00F) << 4, (col & 0xFF0) >> 4])
        elif card_format == "cbn":
            card = bytearray()
            for col in columns:
                card += bytes([(col >> 6) & 0o77, col & 0o77])
            for i, six in enumerate(card):
                card[i] = six | (0o100 ^ parity_bit(six))
            card[0] |= RECORD_MARK
            out += card
        elif card_format == "bcd":
            card = bytearray()
            for column, col in enumerate(columns, start=1):
                bcd = _HOLES_TO_BCD.get(col)
                if bcd is None:
                    raise _err(f"rows {rows_text(col)} have no BCD character", None, number,
                               column)
                card.append(bcd | parity_bit(bcd))
            blank = 0o20 | parity_bit(0o20)
            last = number == len(texts)
            while not last and len(card) > 1 and card[-1] == blank:
                card.pop()  # trailing blanks: a short record (the last card is whole)
            card[0] |= RECORD_MARK
            out += card
        else:
            raise DeckError(f"unknown card format {card_format!r} (one of {', '.join(FORMATS)})")
    return bytes(out)
