"""A front end for the FORTRAN IV of the listing's dialect: the 1967 path's one engine, running
the listing (``legacy/luminaire.f``: :func:`listing_program`, :func:`run_deck`) and a job deck's
own program alike.

:mod:`.parse` reads source cards into program units (the dialect as tables: ``STATEMENTS``,
``EDIT_DESCRIPTORS``, ``INTRINSICS``; anything else is a :class:`DialectError`), :mod:`.make`
makes them Python source, :mod:`.run` runs it on a deck through an arithmetic of
:mod:`deck_emulator.legacy.arithmetic` and the line printer of
:mod:`deck_emulator.legacy.printer`.  A program whose made code is kept runs without the parser:
its names here are imported when first asked for.
"""

from .run import LISTING_WATCH, STEP_LITERALS, Program, Runner, listing_program, run_deck

_PARSER_NAMES = ("DialectError", "EDIT_DESCRIPTORS", "INTRINSICS", "STATEMENTS")


def __getattr__(name: str):
    if name in _PARSER_NAMES:
        from . import parse

        return getattr(parse, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

__all__ = ["DialectError", "EDIT_DESCRIPTORS", "INTRINSICS", "LISTING_WATCH", "Program",
           "Runner", "STATEMENTS", "STEP_LITERALS", "listing_program", "run_deck"]
