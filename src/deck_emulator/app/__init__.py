"""The application layer: one function a command, typed options in, an :class:`Answer` out.

``COMMANDS`` is the table the command line builds its parsers from (``deck_emulator.cli``,
which only parses, maps an answer's status to an exit status and writes stdout and stderr);
Python calls the same functions with the same options::

    >>> from deck_emulator.app import call
    >>> answer = call("summary", source="steel40", json=True)
    >>> answer.status, answer.document()["quantities"]["hit_time_s"]     # doctest: +SKIP

A command reports bad input by raising :class:`~deck_emulator.errors.UsageError` or a deck's
``DeckError`` (exit 2), a run that could not end by returning a ``stopped`` answer (exit 3:
what it reached is answered, its ``error`` says why) or raising
:class:`~deck_emulator.errors.RunFailed` where nothing could be answered.  Output files are
written by the command (whole or not at all: :mod:`deck_emulator.files`); what goes to
stdout is the answer's.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, field

#: the command's name, as it is installed (pyproject.toml's [project.scripts]) and says itself
PROG = "deck-emulator"

#: exit statuses, one meaning each (README, "Commands")
EXIT = {"ok": 0, "differ": 1, "bad input": 2, "stopped": 3, "unreadable": 4}


@dataclass(eq=False)
class Answer:
    """What a command answers.  ``status``: ``ok``, ``stopped`` (a run could not end: exit 3),
    ``differ`` (compare: the printouts differ, exit 1) or ``unreadable`` (compare: nothing
    differs, but some record could not be read, so not every value was compared: exit 4).  ``text``: the answer as a person
    reads it (bytes for card images), ``None`` where the command writes only files;
    ``json``: print :meth:`document` instead; ``out``: the file the printed answer goes to
    (None: stdout).  ``command``, ``source``, ``settings``, ``notes`` and ``result`` make the
    JSON answer (:meth:`document`, the one envelope of docs/json.md).  ``said``: lines for
    stderr while it ran (what was run, what was written); ``error``: the one line of a stopped
    run, said last."""

    command: str
    source: object = ""
    status: str = "ok"
    settings: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    result: dict = field(default_factory=dict)
    text: str | bytes | None = None
    json: bool = False
    out: str | None = None
    said: list = field(default_factory=list)
    error: str | None = None

    def document(self) -> dict:
        """The JSON answer: the envelope's keys, then the command's own (docs/json.md)."""
        from deck_emulator.present.answers import envelope

        return envelope(self.command, self.source, settings=self.settings,
                        status="stopped" if self.status == "stopped" else "ok",
                        notes=self.notes, **self.result)

    def printed(self) -> str | bytes | None:
        """What goes to stdout (or ``out``): the JSON document or the text."""
        if self.json:
            import json

            return json.dumps(self.document(), indent=2) + "\n"
        return self.text

    @property
    def exit_status(self) -> int:
        return EXIT[self.status]


@dataclass(frozen=True, eq=False)
class Command:
    """One command: its name (``study error``: a command and its study), its options class,
    the function that answers, and its help (``description``: text, or a function that
    makes it when the help is built); ``core``: whether it may run the modern core (the
    command line then has numba keep the core's machine code in the core's folder, before
    anything imports numba: deck_emulator.core.configure_numba_cache); ``one_scene``: it
    solves a single scene in its own process, where numpy's BLAS has nothing to share out
    (the command line starts it with one thread, :func:`deck_emulator.cli._run`)."""

    name: str
    options: type
    run: Callable
    help: str
    description: str | Callable[[], str] = ""
    core: bool = True
    one_scene: bool = False


#: name -> :class:`Command`, as the modules holding them are loaded (:func:`command_named`,
#: :func:`all_commands`)
COMMANDS: dict[str, Command] = {}

#: every command's name, in the order of the help; each is the module of its name
#: (``study error``: ``study_error``), and a command line loads only its own
NAMES = ("parse", "run", "punch", "compare", "corrections", "summary", "core", "scene", "diff",
         "assembly", "plot", "sweep", "sensitivity", "study error", "study stability")


def command_named(name: str) -> Command:
    """The command ``name``, its module loaded if it is not yet."""
    if name not in COMMANDS:
        importlib.import_module(f".{name.replace(' ', '_')}", __name__)
    return COMMANDS[name]


def all_commands() -> dict[str, Command]:
    """Every command, in the order of the help (every module loaded)."""
    return {name: command_named(name) for name in NAMES}


def command(name: str, options: type, *, help: str, description: str | Callable = "",
            core: bool = True, one_scene: bool = False):
    """Register the decorated function as the command ``name`` (``core``, ``one_scene``:
    :class:`Command`)."""
    def register(fn):
        COMMANDS[name] = Command(name, options, fn, help, description, core, one_scene)
        return fn

    return register


def call(name: str, **options) -> Answer:
    """The command ``name`` with ``options`` (the command line's names, as Python values)."""
    cmd = command_named(name)
    return cmd.run(cmd.options(**options))
