"""The report's card decks, shipped with the package (``steel40`` is the report's own deck;
the others are its variants, see ``README.md`` beside them).

Read them through :func:`path` (``importlib.resources``), never through the checkout, so an
installed package finds them too.
"""

from __future__ import annotations

import importlib.resources
from pathlib import Path

#: The deck the report's appendix prints: the steel post at 40 mph, 0 degrees.
REPORT_DECK = "steel40"


def names() -> list[str]:
    """The shipped decks' names (file names without ``.dat``), sorted."""
    return sorted(p.name[:-4] for p in importlib.resources.files(__name__).iterdir()
                  if p.name.endswith(".dat"))


def path(name: str) -> Path:
    """The file of the shipped deck ``name`` (``"steel40"``); KeyError if there is none."""
    p = importlib.resources.files(__name__) / f"{name}.dat"
    if not p.is_file():
        raise KeyError(name)
    return Path(str(p))
