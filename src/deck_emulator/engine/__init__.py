"""The engine layer: the one road between the two paths and everything above them.

``scene -> engine -> outcome``: an :class:`EmulatorEngine` (the 1967 program on a card deck)
or a :class:`CoreEngine` (the modern core on a deck or a typed scene) turns its input into one
:class:`Outcome`; :mod:`.quantities` is the one registry of what is computed from an outcome
(names, units, definitions), :mod:`.safety` the occupant-risk and clearance readings it uses,
:mod:`.energy` the post's energies.  Studies, pictures and the CLI use engines only through
this package; the errata policy lives in :mod:`.errata`.

Names are imported when first used, so that the command line's start-up (which reads the
registry's definitions for its help) loads neither the engines nor numpy.
"""

import importlib

_WHERE = {
    "ENGINES": "engines", "CoreEngine": "core_engine", "EmulatorEngine": "engines",
    "core_events": "core_engine", "engine_for": "engines",
    "source_name": "sources", "core_keywords": "core_engine", "step_literals": "engines",
    "compile_core": "core_engine", "load_core": "core_engine", "Outcome": "outcome",
}
_MODULES = ("errata", "quantities", "safety", "energy", "assemblies", "leaf_spring", "attitude")

__all__ = ["ENGINES", "CoreEngine", "EmulatorEngine", "Limits", "Outcome", "compile_core",
           "core_events", "core_keywords", "engine_for", "errata", "load_core", "quantities",
           "source_name"]


def __getattr__(name: str):
    if name in _WHERE:
        return getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
    if name in _MODULES:
        return importlib.import_module(f".{name}", __name__)
    if name == "Limits":  # the emulator's bounds on what the listing leaves unbounded
        from deck_emulator.legacy.stops import Limits

        return Limits
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_WHERE) + list(_MODULES) + ["Limits"])
