"""The modern core: the 1967 model (TTI Research Report 75-9, chapter III) solved cleanly.

Newton-Euler equations of the rigid post in its principal axes (eq. 3.16-3.17), the car's
single degree of freedom (eq. 3.18), attitude as a unit quaternion, ``solve_ivp`` with
located events.  The model is assembled from the components the scene has.

    >>> from deck_emulator.legacy.deck import read_deck
    >>> from deck_emulator.vocabulary.scene import Scene, LEGACY  # the shared vocabulary
    >>> from deck_emulator.core import simulate
    >>> result = simulate(Scene.from_deck(read_deck("decks/steel40.dat")), LEGACY)
    >>> result.hit.message                                       # doctest: +SKIP
"""

import importlib
import os
import sys

from deck_emulator.vocabulary.defaults import user_cache_folder

#: public name -> the submodule that defines it, imported on first use (no scipy until then)
_WHERE = {
    "ContactMode": "model", "Model": "model", "assemble": "model",
    "CoreEvent": "result", "CoreResult": "result", "Hit": "result", "Trajectory": "result",
    "angular_momentum_world": "rigid", "attitude_angle_between": "rigid",
    "kinetic_energy": "rigid",
    "CoreError": "solve",
    "free_flight": "solve", "simulate": "solve",
    "check_outcome": "checks", "check_summary": "checks",
    "simulate_batch": "batch",
}


#: the core's entries: each runs again once, compiled anew, after an unreadable numba cache
#: (:func:`deck_emulator.core.laws.recompiling`)
_ENTRIES = ("simulate", "free_flight", "simulate_batch")


#: the modules whose compiled functions call one another (their cache is one)
COMPILED_MODULES = ("laws.py", "dop853.py", "batch.py")


def compiled_cache_folder() -> str:
    """Where the command line's processes have numba keep the core's machine code (without
    importing numba).  numba stamps a cached function with its own file only, so a function
    of dop853.py would keep an old copy of a law of laws.py: the folder is named by the
    content of all of :data:`COMPILED_MODULES`, below the user's NUMBA_CACHE_DIR when set
    (or that folder itself, in a worker that inherited it), else the package's
    ``__pycache__`` where writable, else the user's cache folder."""
    import hashlib

    here = os.path.dirname(os.path.abspath(__file__))
    h = hashlib.sha256()
    for name in sorted(COMPILED_MODULES):
        with open(os.path.join(here, name), "rb") as f:
            h.update(f.read())
    stamp = f"deck_emulator-{h.hexdigest()[:16]}"
    user = os.environ.get("NUMBA_CACHE_DIR")
    if user:
        return user if os.path.basename(os.path.normpath(user)) == stamp else \
            os.path.join(user, stamp)
    in_tree = os.path.join(here, "__pycache__")
    try:
        os.makedirs(in_tree, exist_ok=True)
        writable = os.access(in_tree, os.W_OK)
    except OSError:
        writable = False
    return os.path.join(in_tree if writable else user_cache_folder(), stamp)


def configure_numba_cache() -> bool:
    """Point numba's documented NUMBA_CACHE_DIR (read when numba is imported; workers inherit
    it) at :func:`compiled_cache_folder`.  Called where the package's own processes start,
    and only before numba is imported, so a host application's numba keeps its own setting.
    True when the setting was made (or was already this one)."""
    folder = compiled_cache_folder()
    if os.environ.get("NUMBA_CACHE_DIR") == folder:
        return True
    if "numba" in sys.modules:
        return False
    os.environ["NUMBA_CACHE_DIR"] = folder
    return True


def __getattr__(name: str):
    try:
        module = _WHERE[name]
    except KeyError:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    found = getattr(importlib.import_module(f".{module}", __name__), name)
    if name in _ENTRIES:
        from .laws import recompiling

        found = globals()[name] = recompiling(found)
    return found


def __dir__():
    return sorted(list(globals()) + list(_WHERE))


__all__ = list(_WHERE)
