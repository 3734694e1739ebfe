"""The arithmetics the 1967 program can run in.

:mod:`.base` is the interface and the registry (it knows no implementation); importing this
package imports the IEEE implementations, which register themselves by name; the IBM 7094's
registers itself when :func:`get_arithmetic` first asks for it (its module and the fractions
it computes with are no part of a binary64 run's start).
"""

from .base import ARITHMETICS, Arithmetic, ArithmeticFault, get_arithmetic, register
from . import ieee as _ieee  # noqa: F401  (registers double, single)

__all__ = ["ARITHMETICS", "Arithmetic", "ArithmeticFault", "get_arithmetic", "register"]
