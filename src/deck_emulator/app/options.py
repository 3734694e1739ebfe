"""The commands' options, one row each: a typed field of a command's options dataclass whose
metadata says how the command line spells it (flag, help, choices, how its text is read).

The command line builds every parser from these rows (``deck_emulator.cli``); Python calls a
command with the same dataclass.  The converters read one option's text and raise
``ValueError`` with the reason, which the command line reports as a usage error (exit 2).
Nothing here imports anything heavy: the parsers are built at every start.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, field

from deck_emulator.vocabulary import choices, defaults

#: What SOURCE may be, said once for every command's help: a deck (the commands that run the
#: emulator or read cards take only a deck), or for the commands that also take a scene (``core``,
#: ``scene``, ``plot --engine core``) a deck or a scene file.
_DECKS = "a shipped deck's name (steel40), a deck file (text, or card images in any format)"
DECK_WORDS = _DECKS + " or a job deck"
DECK_HELP = DECK_WORDS + "; a scene file (.toml) is refused (`scene` and `core` take scenes)"
SOURCE_HELP = _DECKS + ", a job deck, or a scene file (.toml)"


def option(default=MISSING, *, help: str, flag: str | None = None, positional: bool = False,
           choices=None, parse=None, metavar: str | None = None, required: bool = False,
           many: bool = False, negatable: bool = False, cli: bool = True):
    """One option: its default and how the command line spells it.  ``flag``: the option's
    name on the command line (default ``--`` and the field's name with dashes); ``positional``
    (``nargs="?"`` when it has a default); ``parse``: text -> value, ``ValueError`` for bad
    text; ``many``: repeated, collected as a tuple; ``negatable``: ``--x``/``--no-x`` over a
    default of None; ``cli=False``: set by the command line itself, not an option."""
    meta = {"help": help, "flag": flag, "positional": positional, "choices": choices,
            "parse": parse, "metavar": metavar, "required": required, "many": many,
            "negatable": negatable, "cli": cli}
    if many:
        return field(default_factory=lambda: tuple(default or ()), metadata=meta)
    return field(default=default, metadata=meta)


#: How an options class is made: typed, keyword-only, immutable; options are read, never
#: compared or hashed, so no comparison is generated (they are made at every start).
options_class = dataclass(frozen=True, kw_only=True, eq=False)


# ------------------------------------------------------------------------------ converters


def whole_number(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise ValueError(f"not a whole number: {text!r}") from None


def positive_int(text: str) -> int:
    n = whole_number(text)
    if n < 1:
        raise ValueError(f"must be at least 1, not {n}")
    return n


def nonnegative_int(text: str) -> int:
    n = whole_number(text)
    if n < 0:
        raise ValueError(f"must be 0 or more, not {n}")
    return n


def max_k(text: str) -> int:
    k = nonnegative_int(text)
    if k > defaults.MAX_HALVINGS:
        raise ValueError(f"at most {defaults.MAX_HALVINGS} (2**{defaults.MAX_HALVINGS} times "
                         f"the listing's steps), not {k}")
    return k


def finite_float(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise ValueError(f"not a number: {text!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"must be a finite number, not {text}")
    return x


def positive_float(text: str) -> float:
    x = finite_float(text)
    if not x > 0:
        raise ValueError(f"must be a positive finite number, not {text}")
    return x


def speed_mph(text: str) -> float:
    x = positive_float(text)
    lo, hi = defaults.SPEED_RANGE_MPH
    if not lo <= x <= hi:
        raise ValueError(f"a speed from {lo:g} to {hi:g} mph, not {text}")
    return x


def angle_deg(text: str) -> float:
    x = finite_float(text)
    if not 0.0 <= x <= defaults.MAX_APPROACH_ANGLE_DEG:
        raise ValueError(f"an angle from 0 to {defaults.MAX_APPROACH_ANGLE_DEG:g} degrees, "
                         f"not {text}")
    return x


def tolerance(text: str) -> float:
    x = positive_float(text)
    if not defaults.MIN_TOLERANCE <= x < 1:
        raise ValueError(f"must be from {defaults.MIN_TOLERANCE:g} to below 1, not {text}")
    return x


def nonnegative_float(text: str) -> float:
    value = finite_float(text)
    if value < 0:
        raise ValueError(f"{text}: at least 0")
    return value


def number_text(text: str) -> str:
    """A decimal constant kept as text (the arithmetic converts it), checked to be a number."""
    try:
        ok = math.isfinite(float(text))
    except ValueError:
        ok = False
    if not ok:
        raise ValueError(f"not a finite number: {text!r}")
    return text


def positive_number_text(text: str) -> str:
    positive_float(text)
    return text


def worker_wait(text: str) -> float:
    value = finite_float(text)
    lo, hi = defaults.WORKER_WAIT_RANGE_S
    if not lo <= value <= hi:
        raise ValueError(f"{text}: from {lo:g} to {hi:g} seconds")
    return value


def quiet_option():
    """``--quiet``: every command that shows progress spells it alike."""
    return option(False, help="no progress display on stderr (shown only on a terminal)")


def trajectory_option():
    """``--trajectory FILE``: the run's trajectory as a table (``run``, ``summary``, ``core``)."""
    return option(None, metavar="FILE.csv|FILE.parquet",
                  help="also write the run's trajectory: time, every named point (road and "
                  "report axes), the shaft's tilt and heading, the car (pandas reads it)")


# ------------------------------------------------------------------------ the shared groups


@options_class
class Common:
    """What every command has: the command line as typed (for the pages a study writes)."""

    command_line: str = option("", help="the command as typed", cli=False)


@options_class
class Source(Common):
    """SOURCE (a deck: the commands that also take a scene say so in their own row), and how
    to read it."""

    source: str = option(positional=True, metavar="SOURCE", help=DECK_HELP)
    card_format: str = option("auto", choices=("auto", *choices.CARD_FORMATS),
                              help="the deck file's card image format (default: detected when "
                              "the file is unambiguous)")
    keypunch: str | None = option(None, choices=choices.KEYPUNCH_CODES,
                                  help="the code holes are read in: 026 (the 7090/7094 FORTRAN "
                                  "code, the default for binary images) or 029; text cards are "
                                  "taken as they stand")
    section: int | None = option(None, parse=positive_int, metavar="N",
                                 help="the Nth $DATA section of a job deck that holds several")
    listing_program: bool = option(False, help="run the listing's program on a job deck whose "
                                   "own FORTRAN differs from it (refused otherwise; said on the "
                                   "first line)")


@options_class
class Answering:
    """--json, --out and --quiet."""

    json: bool = option(False, help="print the answer as one JSON object (docs/json.md)")
    out: str | None = option(None, metavar="FILE", help="write to FILE instead of stdout")
    quiet: bool = quiet_option()


@options_class
class Errata:
    """The listing's errata a command applies (none: the listing as printed)."""

    erratum: tuple[str, ...] = option((), many=True, choices=tuple(choices.ERRATA),
                                      help="apply a named erratum to the listing (default: "
                                      "none, the listing as printed; ed-direction lets ED's "
                                      "root search end on the angled decks)")


@options_class
class Emulator(Source, Errata):
    """The emulator's options."""

    precision: str = option("double", choices=choices.ARITHMETICS,
                            help="arithmetic: double (IEEE binary64, as the r8 goldens), single "
                            "(IEEE binary32, as the r4 goldens, trapping), ibm7094 (the 1967 "
                            "machine's 36-bit words)")
    step_scale: int = option(0, parse=nonnegative_int, metavar="K",
                             help="divide every literal that means one step "
                             f"({defaults.LISTING_STEP_S:g} s) by 2**K")
    tha_start: str | None = option(None, parse=number_text, metavar="VALUE",
                                   help="start-up THA at label 123 instead of the printed "
                                   f"{defaults.LISTING_THA_START}")
    ed_tolerance: str = option(defaults.LISTING_ED_TOLERANCE, parse=positive_number_text,
                               metavar="RAD", help="ED's |DF| tolerance at labels 15 and 16 "
                               f"(printed: {defaults.LISTING_ED_TOLERANCE})")
    max_time: float = option(defaults.EMULATOR_T_MAX_S, parse=positive_float, metavar="S",
                             help="stop when simulated time passes S seconds (default "
                             "%(default)s)")
    max_ed_iterations: int = option(defaults.ED_ITERATIONS, parse=positive_int, metavar="N",
                                    help="stop when one call of ED iterates N times (default "
                                    "%(default)s)")
    max_halvings: int = option(defaults.HALVINGS, parse=nonnegative_int, metavar="N",
                               help="stop after N consecutive step halvings at label 108 "
                               "(default %(default)s)")
    sincos: str | None = option(None, choices=("chop", "round"),
                                help="ibm7094: how SIN/COS were rounded")
    decimal: str | None = option(None, choices=("chop", "round"),
                                 help="ibm7094: how decimal constants and deck fields were "
                                 "converted")
    output_rounding: str | None = option(None, choices=("nearest", "truncate"),
                                         help="ibm7094: how F-format output rounded")


#: the options that name a file or folder to write (an empty value is refused)
PATH_OPTIONS = ("out", "pages", "animate", "trajectory", "store")
