"""The $DATA card deck of the 1967 program, read as FORTRAN IV on the IBM 7094 read it.

MAIN begins with eight ``READ(5,n)`` statements, each with ``FORMAT(8F10.5)``: eight
80-column cards, eight 10-column fields per card.  The input semantics reproduced here:

* every field is ``F10.5``: the exact decimal it means, correctly rounded to binary64, as
  gfortran's REAL*8 read converts it (which texts are numbers: ``_NUMBER_RE``);
* leading blanks are ignored, embedded and trailing blanks read as zeros (``-58.66    ``
  is ``-58.660000``; ``1.5E2     `` is ``1.5E200000``), an all-blank field is 0.0;
* a field without a decimal point gets the implied one: ``     12345`` reads 0.12345;
* all 80 columns are data (the eighth field is columns 71-80, no sequence field);
* a short line is a card padded with blanks;
* ``$`` control cards (``$DATA``, ``$IBJOB`` ...) before the first data card are skipped;
* LF or CRLF line ends, with or without a final newline.

The blanks are mapped here (fortranformat's own blank-as-zero mode, BZ, would also turn
*leading* blanks into zeros, so ``'    -58.66'`` would fail), and the field is read without
any blank in it.

Anything else is an error: :class:`DeckError`, naming the card, the columns and the
READ-list name where that applies.  No other exception escapes :func:`read_deck` or
:func:`parse_deck` for bad input.
"""

from __future__ import annotations

import functools
import math
import os
import re
import stat
import unicodedata
from dataclasses import dataclass
from dataclasses import field as _dc_field

__all__ = [
    "READ_LIST",
    "NAMES",
    "CARD_COLUMNS",
    "FIELD_WIDTH",
    "FIELDS_PER_CARD",
    "field_columns",
    "DeckError",
    "Deck",
    "read_deck",
    "parse_deck",
]

from deck_emulator.vocabulary.deck_fields import (
    CARD_COLUMNS,
    FIELD_WIDTH,
    FIELDS_PER_CARD,
    NAMES,
    READ_LIST,
    field_columns,
)
from deck_emulator.vocabulary import defaults

N_CARDS = len(READ_LIST)

# name -> (card number, field number), both 1-based
_POSITION = {
    name: (c + 1, f + 1) for c, card in enumerate(READ_LIST) for f, name in enumerate(card)
}

# Largest file read_deck accepts; a deck is 9 cards of 80 columns.
_MAX_BYTES = 1 << 20

_FORMAT = "(F10.5)"
_DECIMALS = 5  # the .5 of F10.5: implied decimal places, and the minimum in `fields`

# One number after the 1967 blank handling (no blank left in it): whether the text is a number
# FORTRAN IV accepts (every text fortranformat's reader accepts: tests/legacy/test_deck.py).
# Exponent: E or D with an optional sign, or a bare sign (``1.5+2`` is 1.5E+2).
_NUMBER_RE = re.compile(
    r"(?P<mantissa>[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+))"
    r"(?:(?:[ED](?P<esign1>[+-]?)|(?P<esign2>[+-]))(?P<exponent>[0-9]+))?"
)


class DeckError(ValueError):
    """Bad input in a card deck.

    ``card`` is the 1-based number of the data card ($ control cards not counted) or
    None, ``file_card`` the 1-based number of a card counting every card of the file,
    ``columns`` a (first, last) column range or None, ``field`` the READ-list name
    or None, ``path`` the deck's path or None.  ``reason`` is the bare message.
    """

    def __init__(
        self,
        reason: str,
        *,
        card: int | None = None,
        columns: tuple[int, int] | None = None,
        field: str | None = None,
        path: str | None = None,
        line: int | None = None,
        file_card: int | None = None,
    ) -> None:
        self.reason = reason
        self.card = card
        self.columns = columns
        self.field = field
        self.path = path
        self.line = line
        self.file_card = file_card
        where = []
        if card is not None:
            where.append(f"card {card}")
        elif file_card is not None:
            where.append(f"card {file_card} of the file")
        elif line is not None:
            where.append(f"line {line}")
        if columns is not None:
            first, last = columns
            where.append(f"column {first}" if first == last else f"columns {first}-{last}")
        location = ", ".join(where)
        if field is not None:
            location = f"{location} ({field})" if location else f"({field})"
        super().__init__(": ".join([p for p in (path, location) if p] + [reason]))


@dataclass(frozen=True)
class Deck:
    """The eight data cards of a deck and the 64 values the READ statements give.

    ``values``: READ-list name -> value (a Python float, correctly rounded from the
    decimal the card holds).  ``fields``: name -> that decimal as plain fixed-point text,
    after the 1967 rules (blanks as zeros, implied decimal point, exponent applied),
    with at least five decimals (``'-58.66000'``, ``'0.12345'``, ``'0.00000'``); it is
    exactly the number the FORTRAN READ means, for arithmetics that convert decimals
    themselves.  ``cards``: the eight data card images, 80 columns each.  ``warnings``:
    what is legal but worth saying (a blank card: all its fields read as 0.0).
    """

    path: str | None
    values: dict[str, float]
    fields: dict[str, str] = _dc_field(repr=False)
    cards: tuple[str, ...] = _dc_field(repr=False)
    warnings: tuple[str, ...] = _dc_field(default=(), repr=False, compare=False)

    def __getitem__(self, name: str) -> float:
        return self.values[name]

    def with_values(self, **changes: float) -> "Deck":
        """A new deck with the named values replaced.

        A changed field is punched right-justified in ``F10.5`` style (fewer or more
        decimals, or an exponent, when the value needs them) and must read back to exactly
        the value given; otherwise :class:`DeckError`.  Unchanged fields keep their text and
        their values (only the changed fields are read again: a study makes a deck a scene).
        """
        cards = [list(card) for card in self.cards]
        values, fields = dict(self.values), dict(self.fields)
        for name, value in changes.items():
            if name not in _POSITION:
                raise DeckError(f"unknown READ-list name {name!r}", path=self.path)
            card_no, field_no = _POSITION[name]
            first, last = field_columns(field_no)
            where = dict(name=name, card=card_no, columns=(first, last), path=self.path)
            text = _punch(value, **where)
            cards[card_no - 1][first - 1 : last] = text
            values[name], fields[name] = read_field(text, **where)
        images = ["".join(card) for card in cards]
        return Deck(path=self.path, values=values, fields=fields, cards=tuple(images),
                    warnings=_blank_cards(images))

    def to_text(self) -> str:
        """The deck file: a ``$DATA`` card and the eight data cards, 80 columns each."""
        lines = ["$DATA".ljust(CARD_COLUMNS), *self.cards]
        return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------------------
# reading


def read_deck(path: str | os.PathLike[str]) -> Deck:
    """Read a deck file.  Raises :class:`DeckError` for any bad input."""
    shown, data = read_bytes(path, "a deck is 8 cards of 80 columns")
    return parse_deck(data, path=shown)


#: how SOURCE ``-`` (standard input) is shown in messages and outputs
STDIN_NAME = "stdin"


def read_bytes(path: str | os.PathLike[str], what: str = "",
               limit: int = _MAX_BYTES) -> tuple[str, bytes]:
    """A deck file's name as shown to the user, and its bytes (at most ``limit``), read once,
    as a stream: a regular file; ``-``, standard input; a FIFO, a process substitution or a
    pipe (``/dev/stdin``) as the file it carries, each wait for its next bytes bounded by
    :data:`~deck_emulator.vocabulary.defaults.SOURCE_WAIT_S`; a terminal, a
    device or a socket refused.  :class:`DeckError` naming the file for anything that stops
    the read."""
    try:
        shown = os.fsdecode(path)
    except TypeError:
        raise TypeError(f"read_deck needs a path, not {type(path).__name__}") from None
    stdin = shown == "-"
    if stdin:
        shown = STDIN_NAME
    try:
        if stdin:
            fd, opened = 0, False
        else:
            if stat.S_ISSOCK(os.stat(path).st_mode):  # which cannot be opened to say so
                raise DeckError("is a socket, not a deck file (give a file, a pipe or a FIFO)",
                                path=shown)
            # without blocking: a FIFO with no writer must not hold the open itself
            fd, opened = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0)), True
        try:
            mode = os.fstat(fd).st_mode
            if stat.S_ISDIR(mode):
                raise IsADirectoryError
            if stat.S_ISREG(mode):
                data = read_at_most(fd, limit)
            elif stat.S_ISFIFO(mode):
                data = _read_stream(fd, shown, limit, defaults.SOURCE_WAIT_S)
            else:
                kind = ("a terminal" if os.isatty(fd) else "a socket" if stat.S_ISSOCK(mode)
                        else "a device")
                raise DeckError(f"is {kind}, not a deck file (give a file, a pipe or a FIFO)",
                                path=shown)
        finally:
            if opened:
                os.close(fd)
    except DeckError:
        raise
    except FileNotFoundError:
        raise DeckError("no such file", path=shown) from None
    except IsADirectoryError:
        raise DeckError("is a directory, not a deck file", path=shown) from None
    except PermissionError:
        raise DeckError("permission denied", path=shown) from None
    except (OSError, ValueError) as exc:  # ValueError: e.g. a NUL byte in the path
        reason = getattr(exc, "strerror", None) or str(exc)
        raise DeckError(f"cannot read: {reason}", path=shown) from None
    if len(data) > limit:
        raise DeckError(f"file is larger than {limit} bytes" + (f"; {what}" if what else ""),
                        path=shown)
    return shown, data


def read_at_most(fd: int, limit: int) -> bytes:
    """A regular file's bytes, at most ``limit`` + 1 (one more tells that it is too large)."""
    chunks, size = [], 0
    while size <= limit:
        chunk = os.read(fd, min(1 << 20, limit + 1 - size))
        if not chunk:
            break
        chunks.append(chunk)
        size += len(chunk)
    return b"".join(chunks)


def _read_stream(fd: int, shown: str, limit: int, wait_s: float) -> bytes:
    """A FIFO's or a pipe's bytes up to its end (every writer gone), at most ``limit`` + 1;
    no byte for ``wait_s`` seconds (no writer yet, or one gone silent) is a DeckError."""
    import select

    poller = select.poll()
    poller.register(fd, select.POLLIN)  # the end (POLLHUP) is reported unasked
    chunks, size = [], 0
    while size <= limit:
        if not poller.poll(int(wait_s * 1000)):
            said = "nothing was written to it" if not size else "its writer stopped writing"
            raise DeckError(f"a FIFO or pipe: {said} in {wait_s:g} s (the bound on waiting "
                            f"for a SOURCE's next bytes); start its writer first", path=shown)
        try:
            chunk = os.read(fd, 1 << 16)
        except BlockingIOError:  # woken, but another reader took the bytes
            continue
        if not chunk:
            break
        chunks.append(chunk)
        size += len(chunk)
    return b"".join(chunks)


def parse_deck(text: str | bytes, path: str | None = None) -> Deck:
    """Parse the text of a deck file (str, or bytes expected to be ASCII)."""
    if isinstance(text, (bytes, bytearray)):
        # undecodable bytes become lone surrogates U+DC80..U+DCFF, reported per column
        text = bytes(text).decode("utf-8", errors="surrogateescape")
    elif not isinstance(text, str):
        raise TypeError(f"parse_deck needs str or bytes, not {type(text).__name__}")

    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()  # the final newline ends the last card; it is not a card
        unended = None
    else:
        unended = len(lines)  # the last line has no line end (or the text is empty)

    data_cards: list[str] = []
    last_is_data = False
    for line_no, line in enumerate(lines, start=1):
        if line.endswith("\r"):
            line = line[:-1]
        is_control = not data_cards and line.startswith("$")
        card_no = None if is_control else len(data_cards) + 1
        if len(line) > CARD_COLUMNS and line[CARD_COLUMNS:].strip(" ") == "":
            line = line[:CARD_COLUMNS]  # blanks after column 80 are no holes
        if card_no is not None and line.startswith("$"):
            word = line.split()[0]
            where = (
                "after the 8 data cards" if card_no > N_CARDS
                else f"among the data cards, where READ takes data card {card_no}"
            )
            raise DeckError(
                f"{word} control card {where} (a deck with several $DATA sections is a job deck: each section is run "
                "in turn by `deck-emulator run`)",
                card=card_no,
                path=path,
            )
        if card_no is not None and card_no > N_CARDS:
            if line.strip(" \r\t") == "":
                what = "a blank line"
            else:
                what = "a deck holds exactly 8 data cards"
            raise DeckError(
                f"extra card ({what}; the 8 READ statements take cards 1-8)",
                card=card_no,
                path=path,
            )
        _check_characters(line, card_no=card_no, line_no=line_no, control=is_control, path=path)
        if not is_control:
            data_cards.append(line)
        last_is_data = not is_control

    if len(data_cards) < N_CARDS and not any(card.strip(" ") for card in data_cards):
        if not data_cards:
            detail = "no data cards" + (" (only $ control cards)" if lines else "")
        else:
            detail = "only blank lines"
        raise DeckError(
            f"empty deck: {detail}; expected 8 cards in FORMAT(8F10.5), "
            f"card 1 holding {', '.join(READ_LIST[0])}",
            path=path,
        )
    if unended and last_is_data and len(data_cards[-1]) < CARD_COLUMNS:
        # A short card is a card padded with blanks -- when its line ends.  A last line that
        # stops short of column 80 with no line end is a file cut short: its missing
        # columns (and cards) would read as zeros, or worse (trailing blanks are zeros).
        number, columns = len(data_cards), len(data_cards[-1])
        field_no = min(columns // FIELD_WIDTH + 1, FIELDS_PER_CARD)
        raise DeckError(
            f"the file ends after column {columns} with no line end, so "
            f"{READ_LIST[number - 1][field_no - 1]} and the fields after it are incomplete: "
            f"it looks cut short (end a short card with a line end, or give all 80 columns)",
            card=number,
            line=unended,
            path=path,
        )
    if len(data_cards) < N_CARDS:
        missing = len(data_cards) + 1
        have = len(data_cards)
        raise DeckError(
            f"missing card: it should hold {', '.join(READ_LIST[missing - 1])} "
            f"(the deck has only {have} data card{'s' if have != 1 else ''}, 8 are read)",
            card=missing,
            path=path,
        )
    return _build([card.ljust(CARD_COLUMNS) for card in data_cards], path)


def _describe_character(ch: str) -> str | None:
    """Why ``ch`` cannot be on a card, or None if it can."""
    code = ord(ch)
    if ch == "\t":
        return "tab character: cards have no tabs, pad with blanks to the column"
    if ch == "\r":
        return "carriage return inside a line (line ends must be LF or CRLF)"
    if 0xDC80 <= code <= 0xDCFF:
        return f"undecodable byte 0x{code - 0xDC00:02X} (not ASCII text)"
    if code < 0x20 or code == 0x7F:
        name = "NUL" if code == 0 else f"control character 0x{code:02X}"
        return f"{name}: not a card character"
    if code > 0x7E:
        if ch == "\ufeff":
            return "byte-order mark (U+FEFF): save the deck as plain ASCII"
        try:
            uname = unicodedata.name(ch)
        except ValueError:
            uname = "unnamed"
        return f"non-ASCII character {ch!r} (U+{code:04X} {uname}): cards are ASCII"
    return None


def _check_characters(
    line: str, *, card_no: int | None, line_no: int, control: bool, path: str | None
) -> None:
    where = dict(card=card_no, line=line_no, path=path)
    kind = " of the $ control card" if control else ""
    head = line[:CARD_COLUMNS]
    fine = head.isascii() and head.isprintable()  # blank to '~' only: nothing to report
    for index, ch in enumerate(() if fine else head):
        reason = _describe_character(ch)
        if reason is not None:
            column = index + 1
            name = None
            if not control:
                name = READ_LIST[card_no - 1][(column - 1) // FIELD_WIDTH]
            raise DeckError(reason + kind, columns=(column, column), field=name, **where)
    if len(line) > CARD_COLUMNS:
        extra = line[CARD_COLUMNS:]
        shown = extra if len(extra) <= 20 else extra[:20] + "..."
        raise DeckError(
            f"line is {len(line)} columns long; a card holds {CARD_COLUMNS} "
            f"(beyond column {CARD_COLUMNS}: {shown!r})" + kind,
            columns=(CARD_COLUMNS + 1, len(line)),
            **where,
        )


def _build(cards: list[str], path: str | None) -> Deck:
    values: dict[str, float] = {}
    fields: dict[str, str] = {}
    for card_no, (card, names) in enumerate(zip(cards, READ_LIST), start=1):
        for field_no, name in enumerate(names, start=1):
            first, last = field_columns(field_no)
            raw = card[first - 1 : last]
            value, decimal_text = read_field(
                raw, name=name, card=card_no, columns=(first, last), path=path
            )
            values[name] = value
            fields[name] = decimal_text
    return Deck(path=path, values=values, fields=fields, cards=tuple(cards),
                warnings=_blank_cards(cards))


def _blank_cards(cards: list[str]) -> tuple[str, ...]:
    """A deck's warnings: each blank card, whose 8 fields read as 0.0."""
    return tuple(f"card {n} was blank: its 8 fields ({', '.join(READ_LIST[n - 1])}) read as 0.0"
                 for n, card in enumerate(cards, start=1) if not card.strip(" "))


def read_field(raw: str, *, name: str, card: int, columns, path,
               decimals: int = _DECIMALS) -> tuple[float, str]:
    """Value and exact decimal text of one field, 1967 rules (``decimals``: the d of its
    Fw.d, the implied decimal places of a field without a point)."""
    where = dict(card=card, columns=columns, field=name, path=path)
    text = raw.lstrip(" ").replace(" ", "0")  # leading blanks ignored, the rest are zeros
    if text == "":
        return 0.0, "0.00000"
    match = _NUMBER_RE.fullmatch(text)
    if match is None:
        raise DeckError(f"not a number: {raw!r}", **where)

    # the number FORTRAN means, exactly: sign * int(digits) * 10**power (the mantissa's digits,
    # its point or the implied one, the exponent)
    mantissa = match["mantissa"]
    negative = mantissa.startswith("-")
    whole, point, fraction = mantissa.lstrip("+-").partition(".")
    digits = (whole + fraction).lstrip("0") or "0"
    power = -len(fraction) if point else -decimals
    exponent_digits = match["exponent"]
    if exponent_digits is not None and digits != "0":
        exponent = int((match["esign1"] or match["esign2"] or "+") + exponent_digits)
        # at most 10 digits in the mantissa: beyond 10**+-400 no double is left
        if abs(exponent) > 400:
            raise _out_of_range(raw, text, where)
        power += exponent

    # The range is that of the number the field means, the implied decimal point applied
    # first, as gfortran's REAL*8 read does: '     1E309' is 1E304, in range.  fortranformat
    # converts first and divides by 10**5 after (overflowing on 1E309, and rounding twice),
    # so the value is the correctly rounded one of the exact decimal (float() of a decimal
    # text rounds correctly; a minus zero keeps its sign).
    value = float(f"{'-' if negative else ''}{digits}e{power}")
    if not math.isfinite(value) or (digits != "0" and value == 0.0):
        raise _out_of_range(raw, text, where)
    return value, _fixed(negative, digits, power)


def _out_of_range(raw: str, text: str, where: dict) -> DeckError:
    note = f" (blanks read as zeros: {text})" if text != raw.strip(" ") else ""
    return DeckError(f"number out of range: {raw!r}{note}", **where)


def _fixed(negative: bool, digits: str, power: int) -> str:
    """Plain fixed-point text of sign * int(``digits``) * 10**``power``: at least five
    decimals, no extra zeros (a minus zero keeps its sign, as the card has it)."""
    if digits == "0":
        whole, fraction = "0", ""
    elif power >= 0:
        whole, fraction = digits + "0" * power, ""
    elif len(digits) > -power:
        whole, fraction = digits[:power], digits[power:]
    else:
        whole, fraction = "0", digits.rjust(-power, "0")
    fraction = fraction.rstrip("0").ljust(_DECIMALS, "0")
    return f"{'-' if negative else ''}{whole}.{fraction}"


# --------------------------------------------------------------------------------------
# writing a changed field

# Tried in this order; the first whose text reads back to exactly the value is punched.
_PUNCH_FORMATS = (
    "(F10.5)", "(F10.4)", "(F10.3)", "(F10.2)", "(F10.1)", "(F10.0)",
    "(F10.6)", "(F10.7)", "(F10.8)", "(F10.9)",
    "(E10.4)", "(E10.3)", "(E10.2)", "(E10.1)",
)


@functools.cache
def _writer(fmt: str):
    """fortranformat's writer of ``fmt`` (imported here: only punching a changed field needs
    it)."""
    from fortranformat import FortranRecordWriter

    return FortranRecordWriter(fmt)


def _same(a: float, b: float) -> bool:
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


def _punch(value, *, name: str, card: int, columns, path) -> str:
    where = dict(card=card, columns=columns, field=name, path=path)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DeckError(f"value must be a number, not {type(value).__name__}", **where)
    try:
        value = float(value)
    except OverflowError:
        raise DeckError(f"value {value!r} is out of range", **where) from None
    if not math.isfinite(value):
        raise DeckError(f"value {value!r} cannot be punched", **where)
    if value == 0.0:
        return ("-0.00000" if math.copysign(1.0, value) < 0 else "0.00000").rjust(FIELD_WIDTH)
    for fmt in _PUNCH_FORMATS:
        text = _writer(fmt).write([value])
        if len(text) != FIELD_WIDTH or "*" in text:
            continue
        try:
            back, _ = read_field(text, name=name, card=card, columns=columns, path=path)
        except DeckError:
            continue
        if _same(back, value):
            return text
    raise DeckError(
        f"value {value!r} cannot be punched exactly in a 10-column field "
        f"(F10.5 gives {_writer(_FORMAT).write([value]).strip()!r})",
        **where,
    )
