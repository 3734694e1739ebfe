"""Pluggable arithmetics for the emulator.

The emulator's program text is written once, over an object of one of these classes.  An
arithmetic supplies:

* ``decimal(text)``  -- the machine value of a decimal literal or deck field, given as text
  (``"0.0004"``, ``"-58.66"``): compile-time constants and card fields both come through here;
* the number type's own ``+ - * /``, unary ``-`` and ``abs()`` (``X**n`` is products of
  these: the front end's ``run._power``);
* the intrinsics ``sin``, ``cos``;
* ``sign(x)`` -> -1, 0 or 1, the three-way test of an arithmetic IF (a minus zero is zero);
* ``isfinite(x)``, ``exact(x)`` (the exact value as a :class:`fractions.Fraction`, used by the
  printer) and ``to_float(x)`` (nearest binary64, for summaries and diffs).

Operations that divide by zero or overflow raise :class:`ArithmeticFault`, or produce a value
for which ``isfinite`` is false; the emulator turns either into an error that names the
statement.
"""

from __future__ import annotations

import contextlib
import importlib
import math

from deck_emulator.vocabulary.choices import ARITHMETICS


class ArithmeticFault(ArithmeticError):
    """An operation the machine would trap on (division by zero, overflow, invalid)."""


class Arithmetic:
    """Interface shared by every arithmetic (see the module docstring)."""

    name = "abstract"
    #: Unknowns of the machine model, as ``{name: chosen value}``; printed with the run.
    assumptions: dict[str, str] = {}

    def decimal(self, text: str):
        raise NotImplementedError

    def sin(self, x):
        raise NotImplementedError

    def cos(self, x):
        raise NotImplementedError

    def sign(self, x) -> int:
        return int(x > 0) - int(x < 0)

    def trapping(self):
        """Context in which the number type raises on division by zero, overflow, invalid."""
        return contextlib.nullcontext()

    def isfinite(self, x) -> bool:
        return math.isfinite(x)

    def exact(self, x):
        """``x``'s exact value, a :class:`fractions.Fraction` (imported here: a run that never
        asks does not load it)."""
        from fractions import Fraction

        return Fraction(float(x))

    def to_float(self, x) -> float:
        return float(x)

    def describe(self) -> str:
        if not self.assumptions:
            return self.name
        opts = ", ".join(f"{k}={v}" for k, v in self.assumptions.items())
        return f"{self.name} ({opts})"


#: Each arithmetic's module of this package and class, by its name (vocabulary/choices.py); the
#: module is imported when the arithmetic is first asked for.
_CLASSES = {"double": ("ieee", "DoubleArithmetic"), "single": ("ieee", "SingleArithmetic"),
            "ibm7094": ("ibm7094", "IBM7094Arithmetic")}
assert tuple(_CLASSES) == ARITHMETICS, "an arithmetic without its class, or the other way"


def get_arithmetic(name: str, **options) -> Arithmetic:
    """The arithmetic called ``name`` (``double``, ``single`` or ``ibm7094``)."""
    if name not in _CLASSES:
        raise ValueError(f"unknown arithmetic {name!r}: choose double, single or ibm7094")
    module, cls = _CLASSES[name]
    return getattr(importlib.import_module(f"{__package__}.{module}"), cls)(**options)
