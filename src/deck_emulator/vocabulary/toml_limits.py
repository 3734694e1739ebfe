"""TOML read within bounds: what a scene or assembly file may hold, checked before it is
parsed (:func:`loads`).

Python's TOML parser follows nesting by recursion, builds a table for every part of a dotted
key and converts an integer of any length: a file of inline tables or arrays nested 1,000
deep ends in ``RecursionError``, a dotted key of 50,000 parts in ``MemoryError``, an integer
of 100,000 digits in ``ValueError`` (Python's digit limit).  A scene or a description needs
none of that (a few levels, keys of one to three parts, numbers of a few digits), so one pass
over the text, outside strings and comments, bounds its size, its nesting, its keys' parts and
the length of a run of digits (the rows of :mod:`deck_emulator.vocabulary.defaults`), and a
file past a bound is refused in one line naming the line and the bound.
"""

from __future__ import annotations

import tomllib

from deck_emulator.vocabulary.defaults import (MAX_SCENE_BYTES, MAX_TOML_DEPTH,
                                               MAX_TOML_DIGITS, MAX_TOML_KEY_PARTS)

__all__ = ["TomlLimitError", "check", "loads"]


class TomlLimitError(ValueError):
    """A TOML text past one of the bounds (one line)."""


def loads(text: str) -> dict:
    """``tomllib.loads`` of a text within the bounds (:func:`check` first)."""
    check(text)
    return tomllib.loads(text)


def _string_end(text: str, i: int) -> int:
    """The index after the string (basic, literal, multi-line) that starts at ``i``."""
    quote = text[i]
    triple = text.startswith(quote * 3, i)
    i += 3 if triple else 1
    n = len(text)
    while i < n:
        c = text[i]
        if c == "\\" and quote == '"':
            i += 2
            continue
        if c == quote and (not triple or text.startswith(quote * 3, i)):
            return i + (3 if triple else 1)
        if c == "\n" and not triple:
            return i  # an unended string: the parser names it
        i += 1
    return n


def check(text: str) -> None:
    """:class:`TomlLimitError` for a text past a bound: its size in bytes, its nesting of
    arrays and inline tables, the parts of a dotted key, a run of digits."""
    size = len(text.encode("utf-8", "surrogatepass"))
    if size > MAX_SCENE_BYTES:
        raise TomlLimitError(f"{size} bytes, more than {MAX_SCENE_BYTES}; a scene or "
                             "description is a few kB")
    stack: list[str] = []
    line, i, n = 1, 0, len(text)
    key, parts, digits = True, 1, 0  # at a key; the key's parts so far; the digits in a run
    key_from, name = 0, ""  # where the key being read began; the last key read (in full)
    table, header_from = "", -1  # the table the keys are in; where its header's name began
    while i < n:
        c = text[i]
        if c.isdigit() or (c == "_" and digits):
            digits += 1
            if digits > MAX_TOML_DIGITS:
                what = "a key" if key else f"{name}: a number"
                raise TomlLimitError(f"line {line}: {what} of more than {MAX_TOML_DIGITS} "
                                     "digits")
            i += 1
            continue
        digits = 0
        if c in "\"'":
            end = _string_end(text, i)
            line += text.count("\n", i, end)
            i = end
            continue
        if c == "#":
            end = text.find("\n", i)
            i = n if end < 0 else end
            continue
        if c == "\n":
            line += 1
            if not stack:
                key, parts, key_from = True, 1, i + 1
        elif c == "." and key:
            parts += 1
            if parts > MAX_TOML_KEY_PARTS:
                raise TomlLimitError(f"line {line}: a dotted key of more than "
                                     f"{MAX_TOML_KEY_PARTS} parts")
        elif c == "=" and key:
            here = text[key_from:i].strip()
            key, name = False, (f"{table}.{here}" if table and not stack else here)[:80]
        elif c in "[{":
            stack.append(c)
            if len(stack) > MAX_TOML_DEPTH:
                raise TomlLimitError(f"line {line}: arrays or inline tables nested more than "
                                     f"{MAX_TOML_DEPTH} deep")
            if key and len(stack) == 1 and c == "[":  # a table's header
                header_from = i + 1
            if c == "{" or key:  # an inline table's first key; a header's name ([a.b], [[a]])
                key, parts, key_from = True, 1, i + 1
        elif c in "]}":
            if stack:
                stack.pop()
            if header_from >= 0 and not stack:
                table, header_from = text[header_from:i].strip("[] \t"), -1
            key = False
        elif c == "," and stack and stack[-1] == "{":
            key, parts, key_from = True, 1, i + 1
        i += 1
