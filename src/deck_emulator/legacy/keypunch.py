"""Keypunch codes: which holes in a card column stand for which character.

A column is a 12-bit Hollerith value as open-simh's ``sim_card.c`` holds it: bit 11 = row 12,
bit 10 = row 11, bit 9 = row 0, bit 8 = row 1, ... bit 0 = row 9.  Two codes, each restricted
to the characters a column stands for without ambiguity (the combinations: :data:`CODES`):

* ``026``: the IBM 026 code as the 7090/7094 used it for FORTRAN (the 48-character set):
  ``sim_card.c``'s ``ascii_to_hol_026`` without its entries that share a combination with
  another (``&`` with ``+``, ``%`` with ``(``, ``@`` with ``'``);
* ``029``: the IBM 029 (System/360) code: ``sim_card.c``'s ``ascii_to_hol_ebcdic`` (its
  ``ascii_to_hol_029`` is a Burroughs variant, as its comment says), except ``+``, which that
  table gives as 12 alone but the same file's ``ebcdic_to_hol`` gives, for EBCDIC ``+``
  (0x4E), as 12-8-6, the 029's combination.
"""

from __future__ import annotations

from deck_emulator.vocabulary.choices import KEYPUNCH_CODES

__all__ = ["CODES", "ROWS", "rows_text", "to_holes", "to_char"]

#: Row names in card order, top to bottom, with their bit in the 12-bit column.
ROWS: tuple[tuple[str, int], ...] = (
    ("12", 11), ("11", 10), ("0", 9),
    *((str(r), 9 - r) for r in range(1, 10)),
)


def holes(*rows: str) -> int:
    """The 12-bit column value with the given rows ('12', '11', '0' ... '9') punched."""
    return sum(1 << dict(ROWS)[row] for row in set(rows))


def rows_text(column: int) -> str:
    """The rows punched in a column as the code charts write them: zone rows first, then
    the digit rows top to bottom, except that 8 goes before one other digit (``12-8-4``,
    ``7-8-9``); ``no punch`` for a blank column."""
    names = [name for name, bit in ROWS if column & (1 << bit)]
    zones = [n for n in names if n in ("12", "11", "0")]
    digits = [n for n in names if n not in zones]
    if len(digits) == 2 and "8" in digits and "9" not in digits:
        digits = ["8"] + [d for d in digits if d != "8"]  # 12-8-4, not 12-4-8
    names = zones + digits
    return "-".join(names) if names else "no punch"


def _letters_and_digits() -> dict[str, int]:
    table = {" ": 0}
    for d in range(10):
        table[str(d)] = holes(str(d))
    for i, ch in enumerate("ABCDEFGHI", start=1):
        table[ch] = holes("12", str(i))
    for i, ch in enumerate("JKLMNOPQR", start=1):
        table[ch] = holes("11", str(i))
    for i, ch in enumerate("STUVWXYZ", start=2):
        table[ch] = holes("0", str(i))
    return table


_SHARED_SPECIALS = {
    "-": holes("11"),
    "/": holes("0", "1"),
    ".": holes("12", "8", "3"),
    ",": holes("0", "8", "3"),
    "$": holes("11", "8", "3"),
    "*": holes("11", "8", "4"),
}

_026 = {
    **_letters_and_digits(),
    **_SHARED_SPECIALS,
    "+": holes("12"),
    "=": holes("8", "3"),
    "(": holes("0", "8", "4"),
    ")": holes("12", "8", "4"),
    "'": holes("8", "4"),
}

_029 = {
    **_letters_and_digits(),
    **_SHARED_SPECIALS,
    "+": holes("12", "8", "6"),
    "&": holes("12"),
    "=": holes("8", "6"),
    "(": holes("12", "8", "5"),
    ")": holes("11", "8", "5"),
    "'": holes("8", "5"),
    "!": holes("11", "8", "2"),
    '"': holes("8", "7"),
    "#": holes("8", "3"),
    "%": holes("0", "8", "4"),
    ":": holes("8", "2"),
    ";": holes("11", "8", "6"),
    "<": holes("12", "8", "4"),
    ">": holes("0", "8", "6"),
    "?": holes("0", "8", "7"),
    "@": holes("8", "4"),
    "_": holes("0", "8", "5"),
}

#: code name -> (character -> 12-bit column, 12-bit column -> character)
CODES: dict[str, tuple[dict[str, int], dict[int, str]]] = {}
for _name, _table in zip(KEYPUNCH_CODES, (_026, _029), strict=True):
    _back = {v: k for k, v in _table.items()}
    assert len(_back) == len(_table), f"{_name}: two characters share a combination"
    CODES[_name] = (dict(_table), _back)
del _name, _table, _back


def to_holes(ch: str, code: str) -> int | None:
    """The column punched for ``ch`` in ``code`` ('026' or '029'), or None if it has none.
    Lower-case letters are punched as capitals (a keypunch has no lower case)."""
    return CODES[code][0].get(ch.upper() if ch.islower() and ch.isascii() else ch)


def to_char(column: int, code: str) -> str | None:
    """The character a 12-bit column stands for in ``code``, or None if none does."""
    return CODES[code][1].get(column)
