"""The IBM 7094's printout against the binary64 oracle's: equal within single precision, a
first and cheap screen; a printout beyond it is judged by its own run's error bound (bound.py).

The 7094 keeps a 27-bit fraction and truncates (each operation off by less than 2**-26 of its
result); binary64 keeps 53 bits.  The tolerance, per printed number ``a`` (the 7094's) against
``b`` (the oracle's), printed with ``d`` decimals:

    |a - b| <= 2**-20 * (max(|a|, |b|) + REAL_BOUND) + 10**-d

-- 2**-20 is 64 of the 7094's units (room for some 60 truncations in a chain, or one
cancellation against a value as large as REAL_BOUND), and 10**-d is one unit of the last
printed place (a value near a rounding boundary prints one unit apart).  Everything but the
numbers (Hollerith texts, blanks, the record count) must be equal, and a field of asterisks
(too wide a value) must be asterisks in both.

It is no bound: an error carried forward is amplified by what follows (a cancellation, then a
product; SIN or COS of a large argument, whose absolute error is the argument's), and a data
field punched without its point is read as large as 999999 (generate.py), beyond REAL_BOUND.
And it finds the numbers by their look: two fields printed without a blank between them are
read as other numbers (``0.4`` then ``794061.6`` as 0.4794061 and .6).
A printout beyond the tolerance goes to bound.py, which runs the program on both machines at
once with a running bound on their difference: ``within`` it, ``beyond`` it (a defect), or
``withheld`` where the 7094 takes another branch than binary64 (its printout then compares
with nothing).
"""

from __future__ import annotations

import re

from .generate import REAL_BOUND

RELATIVE = 2.0 ** -20
_NUMBER = re.compile(r" *(?:-?\d*\.\d*|\*+)")  # (with the blanks before: a sign takes one)


def tolerance(a: float, b: float, decimals: int) -> float:
    return RELATIVE * (max(abs(a), abs(b)) + REAL_BOUND) + 10.0 ** -decimals


def compare_within(ours: str, theirs: str) -> tuple[str, str]:
    """('within', '') or ('beyond', the first difference) for the 7094's printout ``ours``
    against the oracle's ``theirs``."""
    a_lines, b_lines = ours.splitlines(), theirs.splitlines()
    if len(a_lines) != len(b_lines):
        return "beyond", f"{len(a_lines)} records on the 7094, {len(b_lines)} from gfortran"
    for n, (a, b) in enumerate(zip(a_lines, b_lines), start=1):
        if a == b:
            continue
        a_parts, b_parts = _NUMBER.split(a), _NUMBER.split(b)
        a_nums, b_nums = _NUMBER.findall(a), _NUMBER.findall(b)
        if a_parts != b_parts or len(a_nums) != len(b_nums):
            return "beyond", f"record {n}: 7094 {a!r}, gfortran {b!r}"
        for x, y in zip(a_nums, b_nums):
            x, y = x.strip(), y.strip()
            if x == y:
                continue
            if "*" in x + y or {x, y} & {"-", ".", "-."}:
                return "beyond", f"record {n}: 7094 {x!r}, gfortran {y!r}"
            d = len(y.split(".")[1]) if "." in y else 0
            fx, fy = float(x if x not in ("", "-") else 0), float(y)
            if abs(fx - fy) > tolerance(fx, fy, d):
                return "beyond", (f"record {n}: 7094 {x}, gfortran {y} (|difference| "
                                  f"{abs(fx - fy):.3g} > {tolerance(fx, fy, d):.3g})")
    return "within", ""
