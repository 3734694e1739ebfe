"""A front end for the FORTRAN IV of the listing's dialect: a job deck runs its own program.

:mod:`.parse` reads source cards into program units (the dialect as tables: ``STATEMENTS``,
``EDIT_DESCRIPTORS``, ``INTRINSICS``; anything else is a :class:`DialectError`), :mod:`.run`
runs them on a deck through an arithmetic of :mod:`deck_emulator.legacy.arithmetic` and the
line printer of :mod:`deck_emulator.legacy.printer`.
"""

from .parse import EDIT_DESCRIPTORS, INTRINSICS, STATEMENTS, DialectError
from .run import LISTING_WATCH, STEP_LITERALS, Program, Runner, listing_program

__all__ = ["DialectError", "EDIT_DESCRIPTORS", "INTRINSICS", "LISTING_WATCH", "Program",
           "Runner", "STATEMENTS", "STEP_LITERALS", "listing_program"]
