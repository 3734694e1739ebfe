"""IEEE binary64 and binary32, as gfortran's REAL*8 and REAL builds of the listing."""

from __future__ import annotations

import math

from .base import Arithmetic

np = None  # numpy, bound by SingleArithmetic() (see there)


class DoubleArithmetic(Arithmetic):
    """IEEE binary64, as gfortran's REAL with ``-fdefault-real-8``: Python floats and the C
    library's ``sin``/``cos`` (the same calls gfortran's code makes)."""

    name = "double"
    #: The values are Python floats: the emulator may use the operators and comparisons of
    #: the float type directly and check finiteness once per block (see emulator.Program).
    native_float = True
    #: Values print from their binary64 value (printer.Printer(binary=True)).
    binary = True

    def decimal(self, text: str) -> float:
        return float(text)  # correctly rounded, as gfortran's compile-time conversion

    # the C library's functions themselves, with no Python call in between
    sin = staticmethod(math.sin)
    cos = staticmethod(math.cos)
    isfinite = staticmethod(math.isfinite)
    to_float = staticmethod(float)


def _libm():
    import ctypes  # here: only binary32 calls sinf/cosf (a binary64 run imports no ctypes)
    import ctypes.util

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
    binary = True  # a binary32 value converts to binary64 exactly: prints from its float

    def __init__(self):
        global np
        import numpy as np  # binary32 scalars; imported here so that double costs no numpy

        self._m = _libm()

    def decimal(self, text: str):
        # (binary32's rounding only: fractions is no part of a double run)
        from fractions import Fraction

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

