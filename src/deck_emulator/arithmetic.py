"""Pluggable arithmetics for the emulator.

The emulator's program text is written once, over an object of one of these classes.  An
arithmetic supplies:

* ``decimal(text)``  -- the machine value of a decimal literal or deck field, given as text
  (``"0.0004"``, ``"-58.66"``): compile-time constants and card fields both come through here;
* the number type's own ``+ - * /``, unary ``-`` and ``abs()``;
* ``ipow(x, n)`` for ``X**n`` with a small integer constant ``n`` (FORTRAN expands it into
  repeated multiplication);
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
import ctypes
import ctypes.util
import math
from fractions import Fraction

import numpy as np


class ArithmeticFault(ArithmeticError):
    """An operation the machine would trap on (division by zero, overflow, invalid)."""


class Arithmetic:
    """Interface shared by every arithmetic (see the module docstring)."""

    name = "abstract"
    #: Unknowns of the machine model, as ``{name: chosen value}``; printed with the run.
    assumptions: dict[str, str] = {}

    def decimal(self, text: str):
        raise NotImplementedError

    def ipow(self, x, n: int):
        r = x
        for _ in range(n - 1):
            r = r * x
        return r

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

    def exact(self, x) -> Fraction:
        return Fraction(float(x))

    def to_float(self, x) -> float:
        return float(x)

    def describe(self) -> str:
        if not self.assumptions:
            return self.name
        opts = ", ".join(f"{k}={v}" for k, v in self.assumptions.items())
        return f"{self.name} ({opts})"


class DoubleArithmetic(Arithmetic):
    """IEEE binary64, as gfortran's REAL with ``-fdefault-real-8``: Python floats and the C
    library's ``sin``/``cos`` (the same calls gfortran's code makes)."""

    name = "double"

    def decimal(self, text: str) -> float:
        return float(text)  # correctly rounded, as gfortran's compile-time conversion

    def sin(self, x):
        return math.sin(x)

    def cos(self, x):
        return math.cos(x)


def _libm():
    path = ctypes.util.find_library("m")
    lib = ctypes.CDLL(path)
    for fn in ("sinf", "cosf"):
        getattr(lib, fn).restype = ctypes.c_float
        getattr(lib, fn).argtypes = [ctypes.c_float]
    return lib


class SingleArithmetic(Arithmetic):
    """IEEE binary32, as gfortran's default REAL: every operation and constant rounded to
    binary32 (numpy ``float32`` scalars, with floating-point exceptions raised, as the
    trapping build stops), ``SIN``/``COS`` from the C library's ``sinf``/``cosf``, the very
    functions gfortran's REAL*4 intrinsics call."""

    name = "single"

    def __init__(self):
        self._m = _libm()

    def decimal(self, text: str) -> np.float32:
        exact = Fraction(text)
        c = np.float32(float(exact))
        # decimal -> binary64 -> binary32 can round twice; pick the truly nearest binary32
        best = min(
            (np.nextafter(c, np.float32(-np.inf)), c, np.nextafter(c, np.float32(np.inf))),
            key=lambda v: (abs(Fraction(float(v)) - exact), int(np.float32(v).view(np.int32)) & 1),
        )
        return np.float32(best)

    def sin(self, x):
        return np.float32(self._m.sinf(float(x)))

    def cos(self, x):
        return np.float32(self._m.cosf(float(x)))

    def isfinite(self, x) -> bool:
        return bool(np.isfinite(x))

    def trapping(self):
        # as gfortran's -ffpe-trap=invalid,zero,overflow: underflow goes on quietly
        return np.errstate(divide="raise", over="raise", invalid="raise", under="ignore")


def get_arithmetic(name: str, **options) -> Arithmetic:
    """The arithmetic called ``name`` (``double``, ``single`` or ``ibm7094``)."""
    if name == "double":
        return DoubleArithmetic()
    if name == "single":
        return SingleArithmetic()
    if name == "ibm7094":
        from deck_emulator.ibm7094 import IBM7094Arithmetic

        return IBM7094Arithmetic(**options)
    raise ValueError(f"unknown arithmetic {name!r}: choose double, single or ibm7094")


ARITHMETICS = ("double", "single", "ibm7094")
