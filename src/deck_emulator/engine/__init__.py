"""The engine layer: the one road between the two paths and everything above them.

``scene -> engine -> outcome``: an :class:`EmulatorEngine` (the 1967 program on a card deck)
or a :class:`CoreEngine` (the modern core on a deck or a typed scene) turns its input into one
:class:`Outcome`.  Studies, pictures and the CLI use engines only through this package; the
errata policy lives in :mod:`.errata`.
"""

from . import errata
from .engines import (ENGINES, CoreEngine, EmulatorEngine, core_events, engine_for, run_engine,
                      source_name)
from .outcome import Outcome

__all__ = ["ENGINES", "CoreEngine", "EmulatorEngine", "Outcome", "core_events", "engine_for",
           "errata", "run_engine", "source_name"]
