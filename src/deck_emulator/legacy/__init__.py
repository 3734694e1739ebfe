"""The 1967 path: the card deck, the program (legacy/luminaire.f, run by the FORTRAN front end),
the line printer."""

import os


def listing_lines() -> list[str]:
    """The lines of the listing: the package's copy of ``legacy/luminaire.f``, package data
    beside this module (its folder is what ``importlib.resources`` would answer, without the 6
    ms of importing it at every run of the listing)."""
    with open(os.path.join(os.path.dirname(__file__), "luminaire.f"), encoding="ascii") as fh:
        return fh.read().splitlines()
