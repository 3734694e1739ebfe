"""The arithmetics the 1967 program can run in.

:mod:`.base` is the interface; :func:`get_arithmetic` imports an arithmetic's module when it is
first asked for (the IBM 7094's and the fractions it computes with are no part of a binary64
run's start).
"""

from .base import ARITHMETICS, Arithmetic, ArithmeticFault, get_arithmetic

__all__ = ["ARITHMETICS", "Arithmetic", "ArithmeticFault", "get_arithmetic"]
