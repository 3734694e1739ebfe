"""The report's card decks, shipped with the package (``steel40`` is the report's own deck;
the others are its variants, see ``README.md`` beside them).

Read them through :func:`path`, never through the checkout, so an installed package finds
them too: they are files beside this module (package data of the wheel), so their folder is
this module's (what ``importlib.resources`` would answer for an installed package, without
its cost, about 7 ms of every run that names a shipped deck).
"""

from __future__ import annotations

from pathlib import Path

_HERE = Path(__file__).resolve().parent

#: The deck the report's appendix prints: the steel post at 40 mph, 0 degrees.
REPORT_DECK = "steel40"


def names() -> list[str]:
    """The shipped decks' names (file names without ``.dat``), sorted."""
    return sorted(p.name[:-4] for p in _HERE.iterdir() if p.name.endswith(".dat"))


def path(name: str) -> Path:
    """The file of the shipped deck ``name`` (``"steel40"``); KeyError if there is none."""
    p = _HERE / f"{name}.dat"
    if not p.is_file():
        raise KeyError(name)
    return p
