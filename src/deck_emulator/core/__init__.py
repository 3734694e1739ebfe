"""The modern core: the 1967 model (TTI Research Report 75-9, chapter III) solved cleanly.

Newton-Euler equations of the rigid post in its principal axes (eq. 3.16-3.17), the car's
single degree of freedom (eq. 3.18), attitude as a unit quaternion, ``solve_ivp`` with
located events.  The model is assembled from the components the scene has.

    >>> from deck_emulator.legacy.deck import read_deck
    >>> from deck_emulator.core.scene import Scene, LEGACY
    >>> from deck_emulator.core import simulate
    >>> result = simulate(Scene.from_deck(read_deck("decks/steel40.dat")), LEGACY)
    >>> result.hit.message                                       # doctest: +SKIP
"""

from .scene import LEGACY, PHYSICAL, PRESETS, ModelOptions, StartupKick
from .model import ContactMode, Model, assemble
from .regions import HIT_MESSAGES
from .result import CoreEvent, CoreResult, Hit, Trajectory
from .rigid import angular_momentum_world, attitude_angle_between, kinetic_energy
from .solve import DEFAULT_ATOL, DEFAULT_RTOL, CoreError, free_flight, simulate
from .checks import check_outcome, check_summary

__all__ = [
    "simulate",
    "free_flight",
    "assemble",
    "Model",
    "ContactMode",
    "ModelOptions",
    "StartupKick",
    "LEGACY",
    "PHYSICAL",
    "PRESETS",
    "CoreResult",
    "CoreEvent",
    "Hit",
    "Trajectory",
    "CoreError",
    "check_outcome",
    "check_summary",
    "HIT_MESSAGES",
    "DEFAULT_RTOL",
    "DEFAULT_ATOL",
    "kinetic_energy",
    "angular_momentum_world",
    "attitude_angle_between",
]
