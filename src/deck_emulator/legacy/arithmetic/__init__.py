"""The arithmetics the 1967 program can run in.

:mod:`.base` is the interface and the registry (it knows no implementation); importing this
package imports the implementations, each of which registers itself by name.
"""

from .base import ARITHMETICS, Arithmetic, ArithmeticFault, get_arithmetic, register
from . import ieee as _ieee  # noqa: F401  (registers double, single)
from . import ibm7094 as _ibm7094  # noqa: F401  (registers ibm7094)

__all__ = ["ARITHMETICS", "Arithmetic", "ArithmeticFault", "get_arithmetic", "register"]
