"""The one errata policy, used by every command, study and script.

The listing runs **as printed** unless the user names an erratum (``--erratum NAME``).  Nothing
applies an erratum on its own: a run that stops where an erratum would let it go on says so
in one line (:func:`hint`), and the user decides.
"""

from __future__ import annotations

from collections.abc import Iterable

#: The erratum that lets ED's root search end on the angled decks.
ED_DIRECTION = "ed-direction"


def names(requested: str | Iterable[str] | None) -> tuple[str, ...]:
    """The errata named, as the command line names them: one name (``"ed-direction"``), or a
    list or tuple of names; none: ``()``.  A string is one name, never its letters."""
    if requested is None:
        return ()
    if isinstance(requested, str):
        return (requested,)
    return tuple(requested)


def resolve(requested: str | Iterable[str] | None) -> tuple[str, ...]:
    """The errata a run uses: exactly those requested (none: the listing as printed)."""
    return tuple(dict.fromkeys(names(requested)))


def describe(errata: Iterable[str]) -> str:
    """'none (the listing as printed)' or 'ed-direction'."""
    errata = tuple(errata)
    return "+".join(errata) if errata else "none (the listing as printed)"


def hint(guard: str | None, errata: Iterable[str]) -> str:
    """A sentence naming the erratum that would let a stopped run go on, or ''."""
    if guard == "ed_iterations" and ED_DIRECTION not in tuple(errata):
        return (f"as printed, SUBROUTINE ED walks away from its root on this deck; "
                f"--erratum {ED_DIRECTION} lets it run (deck-emulator corrections {ED_DIRECTION} "
                "says why)")
    return ""
