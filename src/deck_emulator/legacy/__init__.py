"""The 1967 path: the card deck, the program (legacy/luminaire.f, run by the FORTRAN front end),
the line printer."""

from pathlib import Path


def listing_lines() -> list[str]:
    """The lines of the listing: the package's copy of ``legacy/luminaire.f``, package data
    beside this module (its folder is what ``importlib.resources`` would answer, without the 6
    ms of importing it at every run of the listing)."""
    return Path(__file__).with_name("luminaire.f").read_text("ascii").splitlines()
