"""The package from Python: :func:`run`, the command line's defaults, one call.

    >>> import deck_emulator
    >>> out = deck_emulator.run("steel40")                  # the emulator, the listing as printed
    >>> out.hit_message
    'THE POST HAS HIT THE GROUND WITH POINT R'
    >>> core = deck_emulator.run("steel40", engine="core")  # the modern core, legacy preset
    >>> frame = core.trajectory_frame()                     # a pandas DataFrame

The outcome is an :class:`~deck_emulator.engine.outcome.Outcome`: its events, the registry's
quantities (:func:`deck_emulator.engine.quantities.value`), the typed scene that ran, and its
trajectory.
"""

from __future__ import annotations

from deck_emulator.errors import UsageError

from . import errata as errata_policy
from .engines import engine_for
from .outcome import Outcome
from .sources import kinds_for, load_source

__all__ = ["run"]


def run(source, engine: str = "emulator", *, section: int | None = None,
        card_format: str = "auto", keypunch: str | None = None,
        listing_program: bool = False, **options) -> Outcome:
    """Run SOURCE (a shipped deck's name, a deck or job deck file in any card format, a scene
    file, or a :class:`~deck_emulator.legacy.deck.Deck` or
    :class:`~deck_emulator.vocabulary.scene.Scene` object) on ``engine`` and return its outcome.

    ``options`` are the engine's (:class:`~deck_emulator.engine.EmulatorEngine`: ``precision``,
    ``errata`` ...;  the errata also as the command line names them, ``erratum=``, and either
    as one name or a list of names: ``erratum="ed-direction"``; :class:`~deck_emulator.engine.CoreEngine`: ``preset``, ``method``, ``rtol``,
    ``atol`` ...), with the engines' defaults, which are the command line's
    (:mod:`deck_emulator.vocabulary.defaults`). A run that cannot
    end is an outcome whose ``error`` says why; bad input raises
    :class:`~deck_emulator.legacy.deck.DeckError` or :class:`~deck_emulator.errors.UsageError`."""
    options = _command_line_names(options)
    if hasattr(source, "values") or hasattr(source, "post"):  # a Deck or a Scene already
        return engine_for(engine, **options).run(source)
    src = load_source(source, card_format=card_format, keypunch=keypunch, section=section,
                      listing_program=listing_program, kinds=kinds_for(engine),
                      command=f"the {engine}")
    return engine_for(engine, **options).run(src.for_engine(engine), name=src.stem)


def _command_line_names(options: dict) -> dict:
    """``erratum=`` (the command line's ``--erratum``) as the engine's ``errata``, and either
    as one name or a list of names (:func:`~deck_emulator.engine.errata.names`)."""
    options = dict(options)
    if "erratum" in options:
        given = errata_policy.names(options.pop("erratum"))
        if "errata" in options and errata_policy.names(options["errata"]) != given:
            raise UsageError("give the errata once: erratum= and errata= name the same thing")
        options["errata"] = given
    if "errata" in options:
        options["errata"] = errata_policy.names(options["errata"])
    return options
