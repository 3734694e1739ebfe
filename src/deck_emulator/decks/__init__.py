"""The report's card decks, shipped with the package (``steel40`` is the report's own deck;
the others are its variants, see ``README.md`` beside them).

Read them through :func:`path`, never through the checkout, so an installed package finds
them too: they are files beside this module (package data of the wheel), so their folder is
this module's (what ``importlib.resources`` would answer for an installed package, without
its cost, about 7 ms of every run that names a shipped deck).
"""

from __future__ import annotations

import os

_HERE = os.path.dirname(os.path.realpath(__file__))

#: The deck the report's appendix prints: the steel post at 40 mph, 0 degrees.
REPORT_DECK = "steel40"


def names() -> list[str]:
    """The shipped decks' names (file names without ``.dat``), sorted."""
    return sorted(n[:-4] for n in os.listdir(_HERE) if n.endswith(".dat"))


def path(name: str) -> str:
    """The file of the shipped deck ``name`` (``"steel40"``); KeyError if there is none."""
    p = os.path.join(_HERE, f"{name}.dat")
    if not os.path.isfile(p):
        raise KeyError(name)
    return p
