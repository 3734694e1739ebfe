"""What a command or a caller is given to run: one way to name it, every kind of input.

:func:`load_source` takes a SOURCE as the user writes it and reads it whole:

* a shipped deck's name (``steel40``, ``steel40.dat``: :mod:`deck_emulator.decks`), when no
  file of that name exists;
* a card deck file: text, or card images in any format (:mod:`deck_emulator.legacy.cardimage`,
  found or named with ``card_format``), a plain deck or a whole IBSYS job deck with one or more
  ``$DATA`` sections (``section`` picks one, counted from 1);
* a scene file (TOML with tables: :class:`~deck_emulator.vocabulary.scene.Scene`).

Each is read once, as a stream (:func:`deck_emulator.legacy.deck.read_bytes`), and told a
scene or a deck by its bytes: ``-`` is standard input; a FIFO, a process substitution and a
pipe are the file they carry; a terminal, a device or a socket is refused.

A job deck that carries its own FORTRAN, not the listing's, runs that FORTRAN where the caller
can run it (``own_program``: ``run``, through the FORTRAN front end, :mod:`deck_emulator.legacy.
fortran`; :attr:`Source.fortran` is the compiled program and :attr:`Source.notes` says so
first, with where it differs from the listing); a program outside the front end's dialect is
refused before anything runs. Elsewhere such a deck is refused: the emulator *is* the listing,
so running another program's deck through it would print the listing's answers under that
deck's name. ``listing_program=True`` runs the listing's program on the deck's data anyway,
and :attr:`Source.notes` says so first.

Every refusal is a :class:`~deck_emulator.legacy.deck.DeckError` or
:class:`~deck_emulator.errors.UsageError` with one line naming the file and what to do.
"""

from __future__ import annotations

import dataclasses
import os
import re
from dataclasses import dataclass, field

from deck_emulator import decks
from deck_emulator.errors import UsageError

#: the card reader of the 1967 path: how the studies read a text deck by its file (each
#: worker reads it) or from its cards' text, through this one way in
from deck_emulator.legacy.deck import (
    STDIN_NAME,
    Deck,
    DeckError,
    parse_deck,
    read_bytes,
    read_deck,
)
from deck_emulator.legacy.jobdeck import MAX_BYTES, parse_job
from deck_emulator.vocabulary.defaults import MAX_SCENE_BYTES

__all__ = ["Deck", "Source", "load_source", "parse_deck", "read_bytes", "read_deck"]



@dataclass(frozen=True)
class Source:
    """A SOURCE read whole. ``kind``: ``"deck"`` (``decks``: its ``$DATA`` sections, the
    chosen one alone with ``section``) or ``"scene"`` (``scene``). ``name``: what to call it
    in outputs (the file as given, or the shipped deck's name); ``path``: the file read.
    ``notes``: what the reader says the user must know (the job deck's program, warnings)."""

    given: str
    name: str
    path: str
    kind: str
    decks: tuple = ()
    scene: object = None
    card_format: str = ""
    program: str | None = None
    notes: tuple[str, ...] = field(default=())
    data: bytes | None = field(default=None, repr=False, compare=False)  # a deck file's, as read
    cards: int = 0  # a deck file's cards, control cards and source included
    #: a job deck's own program: its control cards and FORTRAN before its first $DATA
    #: section (() when it carries no source)
    program_cards: tuple[str, ...] = field(default=(), repr=False)
    #: the job deck's own FORTRAN, compiled by the front end, when it is what runs (None: the
    #: listing runs)
    fortran: object = field(default=None, repr=False, compare=False)

    @property
    def sha256(self) -> str:
        """Of the deck file as read ("" for a scene); computed when asked (provenance), so
        that a plain run does not load hashlib."""
        if self.data is None:
            return ""
        import hashlib

        return hashlib.sha256(self.data).hexdigest()

    @property
    def stem(self) -> str:
        return file_stem(self.path)

    def deck(self, command: str = "this command"):
        """The one data deck (a job deck with several sections needs ``section``)."""

        if self.kind != "deck":
            raise UsageError(self.refusal(command))
        if len(self.decks) != 1:
            raise DeckError(f"{command} takes one $DATA section and the deck holds "
                            f"{len(self.decks)}: choose one with --section N (1 to "
                            f"{len(self.decks)})", path=self.name)
        return self.decks[0]

    def scene_or_deck(self, command: str = "this command"):
        """What the core runs: the scene, or the one data deck."""
        return self.scene if self.kind == "scene" else self.deck(command)

    def for_engine(self, engine: str):
        """What ``engine`` runs of this SOURCE (:func:`kinds_for`)."""
        return self.deck("run") if engine == "emulator" else self.scene_or_deck(f"the {engine}")

    def refusal(self, command: str) -> str:
        """One line: why ``command`` (which runs the 1967 program) cannot take a scene, and
        the conversion that would let it."""
        return (f"{self.name}: a scene file; {command} runs the 1967 program, which reads card "
                f"decks: run the scene on the core (`deck-emulator core {self.given}`), or give "
                f"the deck it was made from (`deck-emulator scene DECK` writes a deck's scene)")


def _is_scene(name: str, data: bytes) -> bool:
    """Bytes read from ``name`` are a scene: its name ends in .toml, or they are TOML with a
    table."""
    if name.endswith(".toml"):
        return True
    # A table in TOML needs a '[' (a header) or an '=' (a key): bytes with neither (a card
    # deck of numbers) are no scene, and are told so without loading the TOML parser.
    if b"=" not in data and b"[" not in data:
        return False
    from deck_emulator.vocabulary.toml_limits import loads

    try:
        parsed = loads(data.decode("utf-8"))  # within the bounds: else no scene
    except ValueError:
        return False
    return any(isinstance(v, dict) for v in parsed.values())


def file_stem(path) -> str:
    """A file's name without its last suffix ('steel40' for decks/steel40.dat), as
    ``pathlib.PurePath.stem``, without importing pathlib in a plain run."""
    return os.path.splitext(os.path.basename(os.fspath(path)))[0]


def _shipped(given: str) -> str | None:
    name = given[:-4] if given.endswith(".dat") else given
    if "/" in name or os.sep in name:
        return None
    try:
        return decks.path(name)
    except KeyError:
        return None


def _resolve(given: str) -> tuple[str, str]:
    """(name shown, file) of a SOURCE: the file if it exists, else a shipped deck."""

    if not given:
        raise UsageError("an empty SOURCE: give a deck or scene file, or a shipped deck's name")
    if given == "-":

        return STDIN_NAME, given
    if os.path.exists(given):
        return given, given
    shipped = _shipped(given)
    if shipped is not None:
        return file_stem(given), shipped

    raise DeckError(f"no such file, and no shipped deck of that name (shipped: "
                    f"{', '.join(decks.names())})", path=given)


def _read_scene(name: str, data: bytes):
    from deck_emulator.vocabulary.scene import SceneError, scene_from_bytes

    try:
        return scene_from_bytes(data)  # size-capped, UTF-8, every key checked
    except (SceneError, ValueError, KeyError, TypeError, OverflowError) as exc:

        message = str(exc)
        missing = re.findall(r"'(\w+)'", message) if "required positional" in message else []
        if missing:
            message = "missing " + ", ".join(f"[{m}]" for m in missing)
        raise UsageError(f"{name}: not a scene: {message}") from None


def kinds_for(engine: str) -> tuple[str, ...]:
    """What ``engine`` runs: the emulator a deck, the core a deck or a scene."""
    return ("deck",) if engine == "emulator" else ("deck", "scene")


def load_source(given, *, card_format: str = "auto", keypunch: str | None = None,
                section: int | None = None, listing_program: bool = False,
                kinds: tuple[str, ...] = ("deck", "scene"), command: str = "this command",
                own_program: bool = False) -> Source:
    """Read SOURCE ``given`` (see the module docstring). ``kinds``: what the caller can use;
    a scene given where only decks are meant is refused with :meth:`Source.refusal`."""

    given = os.fspath(given)
    name, path = _resolve(given)
    # read once, as a stream (a FIFO or a pipe has no second reading): told a scene or a
    # deck by its bytes, parsed, and hashed if asked
    shown, data = read_bytes(path, limit=max(MAX_BYTES, MAX_SCENE_BYTES))
    if _is_scene(path, data):
        if section is not None:
            raise UsageError(f"{name}: --section chooses a $DATA section of a job deck; "
                             "a scene file has none")
        src = Source(given, name, path, "scene", scene=_read_scene(name, data))
        if "scene" not in kinds:
            raise UsageError(src.refusal(command))
        return src
    if len(data) > MAX_BYTES:
        raise DeckError(f"file is larger than {MAX_BYTES} bytes", path=shown)
    job = parse_job(data, path=shown, card_format=card_format, keypunch=keypunch)
    notes = []
    fortran = None
    if job.source_verdict:
        if job.program_differs and not listing_program and own_program:
            fortran = _compile(job, name)
            notes.append(f"{name}: the job deck's own FORTRAN runs (sha256 {fortran.sha256}), "
                         f"not the listing's: {job.source_verdict.removeprefix('source: ')}; "
                         "--listing-program runs the listing's instead")
        elif job.program_differs and not listing_program:
            raise DeckError(f"{job.source_verdict}. {command} runs only the listing's "
                            "program (`run` runs the deck's own); --listing-program runs the "
                            "listing's on this deck's data anyway", path=name)
        elif job.program_differs:
            notes.append(f"{name}: --listing-program: the LISTING's program runs on this job "
                         f"deck's data, not the deck's own FORTRAN ({job.source_verdict})")
        else:
            notes.append(f"{name}: {job.source_verdict}")
    decks_ = job.decks
    if given != path:  # a shipped deck, named by its name

        decks_ = tuple(dataclasses.replace(d, path=name) for d in decks_)
    if section is not None:
        if not 1 <= section <= len(decks_):
            raise DeckError(f"--section {section}: the deck holds {len(decks_)} $DATA "
                            f"section(s)", path=name)
        decks_ = (decks_[section - 1],)
    for deck in decks_:
        notes += [f"{deck.path}: warning: {w}" for w in deck.warnings]
    if "deck" not in kinds:
        raise UsageError(f"{name}: a card deck; this command takes a scene file")
    return Source(given, name, path, "deck", decks=tuple(decks_),
                  card_format=job.card_format, program=job.source_verdict, notes=tuple(notes),
                  data=data, cards=job.cards, program_cards=job.program_cards, fortran=fortran)


def _compile(job, name: str):
    """The job deck's own FORTRAN as a front-end program; outside the dialect: refused."""
    from deck_emulator.legacy.fortran import DialectError, Program

    cards = list(job.program_cards)
    try:
        return Program(cards, list(range(1, len(cards) + 1)), name=f"{name}'s own FORTRAN")
    except DialectError as exc:
        raise DeckError(f"the deck's own FORTRAN cannot run, nothing was run: {exc} (the "
                        "FORTRAN front end runs the listing's dialect; --listing-program runs "
                        "the listing's program on this deck's data)", path=name) from None


def given(source, engine: str) -> tuple[object, str]:
    """``source`` as ``engine`` runs it, and its name: a deck or a scene object as it is (no
    name); a shipped deck's name or a file read as :func:`deck_emulator.run` reads it."""
    if not isinstance(source, (str, os.PathLike)):
        return source, ""
    src = load_source(source, kinds=kinds_for(engine), command=f"the {engine}")
    return src.for_engine(engine), src.stem


def source_name(source) -> str:
    """'steel40' for decks/steel40.dat; a scene's own name; else 'scene'."""
    path = getattr(source, "path", None)
    if path:
        return file_stem(str(path))
    return getattr(source, "name", "") or "scene"
