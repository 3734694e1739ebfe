"""Command line: ``deck-emulator COMMAND ...`` -- all of the argument parsing, and nothing else.

Each subcommand is a function ``_cmd_<name>(args) -> int`` plus a small function that adds its
subparser, registered with ``@_subcommand``.  The work is done by the layers below (the engine
layer, the studies, the pictures); nothing imports this module.  Commands import what they
need inside their function, so ``parse`` and ``run`` start without scipy or matplotlib.

A command reports bad input by raising :class:`~deck_emulator.legacy.deck.DeckError` or a
:class:`~deck_emulator.errors.UsageError`; ``main`` turns that into ``deck-emulator: error:
<message>`` on stderr and exit status 2 (3 for :class:`~deck_emulator.errors.RunFailed`).  A
command builds its whole output before writing it, so an error leaves stdout empty.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.vocabulary import defaults

PROG = "deck-emulator"
EXIT_BAD_INPUT = 2
EXIT_RUN_FAILED = 3
#: The arithmetics and errata, named here so that building the parser imports nothing heavy
#: (tests check that these agree with the registry and with the emulator's ERRATA).
PRECISIONS = ("double", "single", "ibm7094")
ERRATA_NAMES = ("ed-direction",)
PRESETS = ("legacy", "physical")
VIEWS = ("side", "plan", "3d", "all")
CLIError = UsageError  # the name the commands below use

# Functions that add one subcommand's parser, by the subcommand's name (the function's
# ``_add_<name>``), in the order of the help; build_parser() calls each of them, or only the one
# a command line names.
_SUBCOMMANDS: dict[str, Callable[[argparse._SubParsersAction], None]] = {}


def _subcommand(add: Callable[[argparse._SubParsersAction], None]):
    _SUBCOMMANDS[add.__name__.removeprefix("_add_")] = add
    return add


def _say(message: str) -> None:
    print(f"{PROG}: {message}", file=sys.stderr)


def _emit(args, text: str) -> None:
    if getattr(args, "out", None):
        from deck_emulator.files import write_file

        write_file(args.out, text)
    else:
        sys.stdout.write(text)


def _json_text(answer: dict) -> str:
    """A command's JSON answer as text (json is imported only where an answer is one)."""
    import json

    return json.dumps(answer, indent=2) + "\n"


def _json(args, answer: dict) -> None:
    """A command's JSON answer (the envelope of :func:`deck_emulator.present.answers.envelope`)
    on stdout or in --out."""
    _emit(args, _json_text(answer))


def _add_json_option(p: argparse.ArgumentParser, what: str = "the answer") -> None:
    p.add_argument("--json", action="store_true",
                   help=f"print {what} as one JSON object (docs/json.md)")


def _add_trajectory_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--trajectory", metavar="FILE.csv|FILE.parquet",
                   help="also write the run's trajectory: time, every named point (road and "
                   "report axes), the shaft's tilt and heading, the car (pandas reads it)")


def _check_trajectory(args) -> None:
    path = getattr(args, "trajectory", None)
    if path:
        from deck_emulator.files import check_output_file

        if not path.endswith((".csv", ".parquet")):
            raise CLIError(f"--trajectory {path}: a .csv or .parquet file")
        check_output_file(path)


def _write_trajectory(args, out) -> None:
    """The outcome's :meth:`~deck_emulator.engine.Outcome.trajectory_frame` to --trajectory
    (written whole or not at all), what a stopped run computed included."""
    path = getattr(args, "trajectory", None)
    if not path:
        return
    import io

    from deck_emulator.files import write_file

    frame = out.trajectory_frame()
    if path.endswith(".parquet"):
        buffer = io.BytesIO()
        frame.to_parquet(buffer, index=False)
        write_file(path, buffer.getvalue())
    else:
        write_file(path, frame.to_csv(index=False))
    _say(f"wrote the trajectory ({len(frame)} samples) to {path}")


def _check_out(args) -> None:
    """The output file's folder must exist and be writable: checked before any work."""
    if getattr(args, "out", None):
        from deck_emulator.files import check_output_file

        check_output_file(args.out)


def _add_jobs_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--jobs", type=_positive_int, default=None, metavar="N",
                   help="worker processes of the embedded Dask cluster (default: every core, "
                   f"{os.cpu_count() or 1} here)")


def _add_cluster_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on an existing Dask cluster (its scheduler's address, "
                   "tcp://host:8786) instead of an embedded one of --jobs workers")
    p.add_argument("--worker-wait", type=_worker_wait, metavar="SECONDS",
                   help="with --scheduler: how long to wait for a worker, at the start and "
                   "whenever every worker is gone, before the run ends with exit status 3 "
                   "(default 60)")
    p.add_argument("--resume", action="store_true",
                   help="run only the scenes not yet stored in the output directory")


def _cluster(args):
    """The external cluster the options name (None: the embedded one); imported when asked,
    so that a command that runs no study does not load the scene runner."""
    from deck_emulator.studies.distributed import scheduler_of

    return scheduler_of(args)


def _worker_wait(text: str) -> float:
    value = _finite_float(text)
    if not 1.0 <= value <= 86400.0:
        raise argparse.ArgumentTypeError(f"{text}: from 1 to 86400 seconds")
    return value


#: What SOURCE may be, said once for every command's help.
SOURCE_HELP = ("a shipped deck's name (steel40), a deck file (text, or card images in any "
               "format), a job deck, or a scene file (.toml)")


def _add_source(p: argparse.ArgumentParser, help: str = SOURCE_HELP) -> None:
    """The one input argument: SOURCE, and how to read it."""
    p.add_argument("source", metavar="SOURCE", help=help)
    _add_card_options(p)
    p.add_argument("--section", type=_positive_int, metavar="N",
                   help="the Nth $DATA section of a job deck that holds several")
    p.add_argument("--listing-program", action="store_true",
                   help="run the listing's program on a job deck whose own FORTRAN differs "
                   "from it (refused otherwise; said on the first line)")


def _source(args, command: str, kinds=("deck", "scene"), given=None):
    """SOURCE read whole (:func:`deck_emulator.engine.sources.load_source`); what the reader
    says (the job deck's program, warnings) goes to stderr first."""
    from deck_emulator.engine.sources import load_source

    src = load_source(args.source if given is None else given,
                      card_format=getattr(args, "card_format", "auto"),
                      keypunch=getattr(args, "keypunch", None),
                      section=getattr(args, "section", None),
                      listing_program=getattr(args, "listing_program", False),
                      kinds=kinds, command=command)
    for note in src.notes:
        _say(note)
    return src


def _deck_file(given: str, command: str) -> str:
    """A deck that a study reads by its file in every worker: a text deck of one $DATA
    section (a shipped deck's name resolves to its file); card images and job decks are
    refused with the one conversion that makes a text deck."""
    from deck_emulator.legacy.deck import DeckError, read_deck

    from deck_emulator.engine.sources import load_source

    src = load_source(given, kinds=("deck",), command=command)  # refused or not: no notes yet
    try:
        plain = read_deck(src.path)
    except DeckError:
        plain = None
    if plain is None or len(src.decks) != 1 or plain.values != src.decks[0].values:
        kind = "job deck" if len(src.decks) > 1 or src.program else f"{src.card_format} deck"
        raise CLIError(f"{src.name}: a {kind}; {command} reads a text deck of one $DATA "
                       f"section: `{PROG} punch {given} --to text --out deck.dat` (with "
                       "--section N for a job deck) writes one")
    return given if Path(given).exists() else src.path


def _with_progress(args, engine, source, *, execute: bool = False):
    """``engine.run(source)`` with the progress display (stderr, a terminal only);
    ``execute``: the emulator's ``engine.execute(source)`` (the program's run, no Outcome)."""
    from deck_emulator.parallel import busy

    if engine.name != "emulator":
        with busy(f"{PROG}: {engine.name} running", quiet=getattr(args, "quiet", False)):
            return engine.run(source)
    programs = []

    def status() -> str:
        return f"step {programs[0].step}" if programs else ""

    with busy(f"{PROG}: emulator running", quiet=getattr(args, "quiet", False), status=status):
        return (engine.execute if execute else engine.run)(source, watch=programs.append)


def _add_quiet_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--quiet", action="store_true",
                   help="no progress display on stderr (shown only on a terminal)")


def _positive_int(text: str) -> int:
    n = _int(text)
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {n}")
    return n


# --------------------------------------------------------------------------- decks


def _add_card_options(p: argparse.ArgumentParser) -> None:
    """--card-format and --keypunch, for a command that reads a deck."""
    from deck_emulator.legacy.cardimage import FORMATS
    from deck_emulator.legacy.keypunch import CODES

    p.add_argument("--card-format", choices=("auto", *FORMATS), default="auto",
                   help="the deck file's card image format (default: detected when the file "
                   "is unambiguous)")
    p.add_argument("--keypunch", choices=sorted(CODES), default=None,
                   help="the code holes are read in: 026 (the 7090/7094 FORTRAN code, the "
                   "default for binary images) or 029; text cards are taken as they stand")


def _cmd_punch(args: argparse.Namespace) -> int:
    from deck_emulator.legacy.cardimage import write_images
    from deck_emulator.legacy.deck import DeckError
    from deck_emulator.legacy.jobdeck import data_deck_texts, job_deck_texts

    src = _source(args, "punch", kinds=("deck",))
    _check_out(args)
    texts = (job_deck_texts(list(src.decks)) if args.job else data_deck_texts(list(src.decks)))
    try:
        data = write_images(texts, args.to, args.code)
    except DeckError as err:
        raise DeckError(f"cannot punch in the {args.code} code: {err}") from None
    if args.json:  # the punched cards as text, whatever the format they were punched in
        from deck_emulator.present.answers import envelope

        _json(args, envelope("punch", src.name, settings={"to": args.to, "code": args.code,
                                                          "job": args.job},
                             notes=src.notes, cards=texts, bytes=len(data)))
        return 0
    if args.out:
        from deck_emulator.files import write_file

        write_file(args.out, data)
    else:
        sys.stdout.buffer.write(data)
        sys.stdout.flush()
    return 0


@_subcommand
def _add_punch(sub: argparse._SubParsersAction) -> None:
    from deck_emulator.legacy.cardimage import FORMATS
    from deck_emulator.legacy.keypunch import CODES

    p = sub.add_parser(
        "punch",
        help="punch a deck's data cards (or a whole job deck) in a card image format",
        description="Read a deck (any card format) and punch its data cards, in the report's "
        "layout (8F10.5, a $DATA card first), as text, binary, column binary (cbn) or BCD "
        "card images, in the 026 or 029 keypunch code.  --job punches a whole IBSYS job "
        "deck: control cards, the listing's FORTRAN source and the data.",
    )
    _add_source(p, help="a shipped deck's name (steel40), a deck file (text or card images), "
                "or a job deck; a scene file is refused (`scene` and `core` take scenes)")
    p.add_argument("--to", choices=FORMATS, default="text", help="card format to punch")
    p.add_argument("--code", choices=sorted(CODES), default="026",
                   help="keypunch code of the punched holes (default 026)")
    p.add_argument("--job", action="store_true", help="punch a whole IBSYS job deck")
    p.add_argument("--out", metavar="FILE", help="write to FILE (default: stdout)")
    _add_json_option(p, "the punched cards' texts")
    p.set_defaults(func=_cmd_punch)


def _int(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None


def _nonnegative_int(text: str) -> int:
    n = _int(text)
    if n < 0:
        raise argparse.ArgumentTypeError(f"must be 0 or more, not {n}")
    return n


def _max_k(text: str) -> int:
    k = _nonnegative_int(text)
    if k > 8:
        raise argparse.ArgumentTypeError(f"at most 8 (2**8 times the listing's steps), not {k}")
    return k


def _finite_float(text: str) -> float:
    import math

    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"must be a finite number, not {text}")
    return x


def _positive_float(text: str) -> float:
    x = _finite_float(text)
    if not x > 0:
        raise argparse.ArgumentTypeError(f"must be a positive finite number, not {text}")
    return x


def _speed_mph(text: str) -> float:
    x = _positive_float(text)
    if not 1.0 <= x <= 200.0:
        raise argparse.ArgumentTypeError(f"a speed from 1 to 200 mph, not {text}")
    return x


def _angle_deg(text: str) -> float:
    x = _finite_float(text)
    if not 0.0 <= x < 90.0:
        raise argparse.ArgumentTypeError(f"an angle from 0 to below 90 degrees, not {text}")
    return x


def _tolerance(text: str) -> float:
    x = _positive_float(text)
    if not defaults.MIN_TOLERANCE <= x < 1:
        raise argparse.ArgumentTypeError(
            f"must be from {defaults.MIN_TOLERANCE:g} to below 1, not {text}")
    return x


def _number_text(text: str) -> str:
    """A decimal constant kept as text (the arithmetic converts it), checked to be a number."""
    import math

    try:
        ok = math.isfinite(float(text))
    except ValueError:
        ok = False
    if not ok:
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return text


def _positive_number_text(text: str) -> str:
    _positive_float(text)
    return text


# --------------------------------------------------------------------------- parse


def _cmd_parse(args: argparse.Namespace) -> int:
    from deck_emulator.present.answers import parse_answer, render_parse

    deck = _source(args, "parse", kinds=("deck",)).deck("parse")
    if args.json:  # the envelope; values: name -> value in READ order, cards with units
        import json

        sys.stdout.write(json.dumps(parse_answer(deck), indent=2) + "\n")
        return 0
    sys.stdout.write(render_parse(parse_answer(deck)))
    return 0


@_subcommand
def _add_parse(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "parse",
        help="read a card deck and print its 64 values",
        description="Read a $DATA card deck (8 cards, FORMAT(8F10.5)) with the 1967 input "
        "rules and print the values under their READ-list names.",
    )
    _add_source(p)
    p.add_argument(
        "--json", action="store_true",
        help="print one JSON object: values (name -> value, READ order) and the cards' fields "
        "with their columns and units (docs/json.md)")
    p.set_defaults(func=_cmd_parse)


# --------------------------------------------------------------------------- run


def _emulator(args, *, trace: bool = True):
    """The emulator engine the options ask for."""
    from deck_emulator.engine import EmulatorEngine
    from deck_emulator.legacy.emulator import Limits

    options = {}
    if args.precision == "ibm7094":
        options = {k: v for k, v in dict(sincos=args.sincos, decimal=args.decimal,
                                         output=args.output_rounding).items() if v is not None}
    elif any(x is not None for x in (args.sincos, args.decimal, args.output_rounding)):
        raise CLIError("--sincos, --decimal and --output-rounding are assumptions of "
                       "--precision ibm7094")
    limits = Limits(ed_iterations=args.max_ed_iterations, halvings=args.max_halvings,
                    time_s=args.max_time)
    return EmulatorEngine(precision=args.precision, errata=tuple(args.erratum),
                          step_scale_k=args.step_scale, tha_start=args.tha_start,
                          ed_tolerance=args.ed_tolerance, limits=limits,
                          arithmetic_options=options, trace=trace)


def _stopped(out) -> str:
    return f"{out.error}" + (f" -- {out.hint}" if out.hint else "")


def _describe(run) -> str:
    from deck_emulator.engine import errata

    scale = f"; step literals / 2**{run.step_scale_k}" if run.step_scale_k else ""
    return f"arithmetic {run.arithmetic}; errata: {errata.describe(run.errata)}{scale}"


def _cmd_run(args: argparse.Namespace) -> int:
    from deck_emulator.legacy.printer import render_asa

    src = _source(args, "run", kinds=("deck",))
    _check_out(args)
    _check_trajectory(args)
    if args.trajectory and len(src.decks) != 1:
        raise CLIError(f"--trajectory writes one run's trajectory and {src.name} holds "
                       f"{len(src.decks)} $DATA sections: choose one with --section N")
    if args.pages:
        from deck_emulator.files import check_output_file

        if not args.pages.lower().endswith(".pdf"):
            raise CLIError(f"--pages {args.pages}: the pages are a PDF; name a .pdf file")
        from deck_emulator.files import check_distinct

        check_distinct(args.out, args.pages)  # --out X --pages X: refused before any work
        check_output_file(args.pages)
    elif args.paper != "plain" or args.listing:
        which = ("--paper is the paper of --pages" if args.paper != "plain"
                 else "--listing is printed on the pages of --pages")
        raise CLIError(f"{which}: give --pages FILE.pdf")
    engine = _emulator(args, trace=bool(args.trajectory))
    records, text, failed, sections = [], "", None, []
    for deck in src.decks:  # a job deck's $DATA sections, in turn (or --section's)
        done = _with_progress(args, engine, deck, execute=True)
        run = done.run
        # the Outcome only where it is used (a trajectory, a stopped run's reasons): a plain
        # run prints the program's records and loads no numpy
        out = engine.outcome_of(done, deck) if args.trajectory or done.stopped else None
        records += run.records
        text += render_asa(run.records) if args.render else run.text()
        _say(f"{deck.path}: {_describe(run)}")
        sections.append({"deck": str(deck.path), "settings": _describe(run),
                         "records": list(run.records), "stopped": out and out.error})
        if out is not None:
            _write_trajectory(args, out)
        if done.stopped:
            failed = (out, deck.path)
            break
    # what produced the printout: for the JSON answer and the pages (the version costs an
    # importlib.metadata read, and the module importlib.resources, so a plain run asks neither)
    facts = None
    if args.json or args.pages:
        from deck_emulator.engine import provenance

        facts = provenance.facts(src, [s["settings"] for s in sections])
    if args.json:
        import json

        from deck_emulator.present.answers import envelope

        text = json.dumps(envelope(
            "run", src.name, settings={"precision": args.precision,
                                       "errata": list(args.erratum)},
            status="stopped" if failed else "ok", notes=src.notes, provenance=facts,
            sections=sections), indent=2) + "\n"
    if not args.pages:
        _emit(args, text)
    else:  # the printout (if asked for) and its pages: one set, both written or neither
        from deck_emulator.files import OutputSet
        from deck_emulator.legacy.pages import write_pdf

        with OutputSet() as outputs:
            if args.out:
                outputs.write(args.out, text)
            elif args.json:
                sys.stdout.write(text)
            # the banner page (the job separator) first, the compile listing if asked for,
            # then the output as printed
            listing = []
            if args.listing:
                from deck_emulator.legacy.listing import listing_records

                listing = listing_records()
            write_pdf(provenance.banner_records(facts) + listing + records, args.pages,
                      paper=args.paper, outputs=outputs,
                      metadata=provenance.pdf_metadata(facts))
        _say(f"wrote the line printer's pages to {args.pages}")
    if failed is not None:
        _say(f"error: {_failed(*failed)}")
        return EXIT_RUN_FAILED
    return 0


def _add_emulator_options(p: argparse.ArgumentParser) -> None:
    from deck_emulator.legacy.emulator import Limits

    _add_source(p)
    p.add_argument("--precision", choices=PRECISIONS, default="double",
                   help="arithmetic: double (IEEE binary64, as the r8 goldens), single (IEEE "
                   "binary32, as the r4 goldens, trapping), ibm7094 (the 1967 machine's 36-bit words)")
    _add_erratum_option(p)
    p.add_argument("--step-scale", type=_nonnegative_int, default=0, metavar="K",
                   help="divide every literal that means one step (0.0004 s) by 2**K")
    p.add_argument("--tha-start", metavar="VALUE", type=_number_text,
                   help="start-up THA at label 123 instead of the printed 0.000022")
    p.add_argument("--ed-tolerance", metavar="RAD", default=".0001", type=_positive_number_text,
                   help="ED's |DF| tolerance at labels 15 and 16 (printed: .0001)")
    p.add_argument("--max-time", type=_positive_float, default=Limits.time_s, metavar="S",
                   help="stop when simulated time passes S seconds (default %(default)s)")
    p.add_argument("--max-ed-iterations", type=_positive_int, default=Limits.ed_iterations,
                   metavar="N",
                   help="stop when one call of ED iterates N times (default %(default)s)")
    p.add_argument("--max-halvings", type=_nonnegative_int, default=Limits.halvings, metavar="N",
                   help="stop after N consecutive step halvings at label 108 (default %(default)s)")
    p.add_argument("--sincos", choices=("chop", "round"), help="ibm7094: how SIN/COS were rounded")
    p.add_argument("--decimal", choices=("chop", "round"),
                   help="ibm7094: how decimal constants and deck fields were converted")
    p.add_argument("--output-rounding", choices=("nearest", "truncate"),
                   help="ibm7094: how F-format output rounded")


def _add_answer_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true", help="one JSON object")
    p.add_argument("--out", metavar="FILE", help="write to FILE instead of stdout")


def _add_erratum_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--erratum", action="append", default=[], choices=ERRATA_NAMES,
                   help="apply a named erratum to the listing (default: none, the listing as "
                   "printed; ed-direction lets ED's root search end on the angled decks)")


def _add_preset_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--preset", choices=PRESETS, default="legacy",
                   help="core model options: legacy (the listing's quirks, the default) or "
                   "physical (none)")
    p.add_argument("--shaft-contact", action=argparse.BooleanOptionalAction, default=None,
                   help="check the shaft Q-P and the arms as segments against the car, not "
                   "only the points P, R, C (default: the preset's, on in physical, off in "
                   "legacy: the listing never did it)")


def _core_keywords(args: argparse.Namespace) -> dict:
    """--preset and --shaft-contact as the core engine's keywords."""
    from deck_emulator.engine import core_keywords

    return core_keywords(args.preset, args.shaft_contact)


@_subcommand
def _add_run(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "run",
        help="run the 1967 program on a deck and write its line-printer output",
        description="Run the emulated 1967 program on a deck. The printout goes to stdout (or "
        "--out FILE, written whole or not at all); what was run (arithmetic, its assumptions, "
        "errata) is said on stderr. If the run stops early (a trap or a guard), the records "
        "printed until then are written and the exit status is 3.",
    )
    _add_emulator_options(p)
    p.add_argument("--out", metavar="FILE", help="write the printout to FILE")
    p.add_argument("--pages", metavar="FILE.pdf",
                   help="lay the printout out as the line printer's pages, as PDF (the text "
                   "goes to --out if given, and not to the terminal)")
    p.add_argument("--paper", choices=("plain", "striped"), default="plain",
                   help="the fan-fold paper of --pages (default plain)")
    p.add_argument("--listing", action="store_true",
                   help="with --pages: the program's FORTRAN source as a compile listing "
                   "(cards, sequence columns, statement numbers) before the output")


    _add_quiet_option(p)
    p.add_argument("--render", action="store_true",
                   help="render ASA carriage control (1 = form feed, 0 = blank line, + = "
                   "overprint) as the POSIX asa utility does, instead of the raw records")
    _add_json_option(p, "the printout's records, per $DATA section,")
    _add_trajectory_option(p)
    p.set_defaults(func=_cmd_run)


# --------------------------------------------------------------------------- summary


def _cmd_summary(args: argparse.Namespace) -> int:
    from deck_emulator.present.answers import outcome_answer, render_outcome

    deck = _source(args, "summary", kinds=("deck",)).deck("summary")
    _check_out(args)
    _check_trajectory(args)
    engine = _emulator(args)
    out = _with_progress(args, engine, deck)
    _write_trajectory(args, out)
    from deck_emulator.engine import errata

    settings = {"arithmetic": engine.arithmetic().describe(),
                "assumptions": dict(getattr(engine.arithmetic(), "assumptions", {}) or {}),
                "errata": errata.describe(out.errata)}
    if not settings["assumptions"]:
        settings.pop("assumptions")
    answer = outcome_answer(out, command="summary", source=str(deck.path), settings=settings)
    answer["notes"] += _odd_deck_notes(out) + list(out.flags)
    _emit(args, _json_text(answer) if args.json else render_outcome(answer))
    if out.error is not None:  # what it reached is answered; the status says it stopped
        raise _failed(out, deck.path)
    return 0


def _odd_deck_notes(out) -> list[str]:
    """Why a well-formed but physically odd deck gives odd numbers (or stops): the run's
    scene, in the deck's names."""
    values = out.scene.deck_values() if out.scene is not None else {}
    notes = []
    for name, what in (("W", "the post's mass"), ("WV", "the car's mass")):
        if values.get(name, 1.0) <= 0:
            notes.append(f"{name} = {values[name]:g} slug: {what} is not positive; what follows "
                         "is what the equations give, not physics")
    for name in ("A", "B", "C"):
        if values.get(name, 1.0) <= 0:
            notes.append(f"{name} = {values[name]:g} slug ft^2: a principal moment of inertia of "
                         "the post is not positive, so the run is not physical")
    if values.get("G", 1.0) <= 0:
        from deck_emulator.vocabulary.units import G_FT_S2

        notes.append(f"G = {values['G']:g} ft/s^2: no gravity (the report's is {G_FT_S2:g}); a "
                     "deceleration in g divides by WV*G, so the printed ones are not given, and "
                     "the post comes down only by the motion the car gave it")
    if values.get("VVB", -1.0) == 0:
        notes.append("VVB = 0: the car does not move, so nothing strikes the post")
    return notes


def _failed(out, source) -> RunFailed:
    """A stopped run: the engine's line, its hint, and why the deck is odd if it is."""
    notes = _odd_deck_notes(out)
    if out.settings.startswith("arithmetic single") and "PHIA" in (out.error or ""):
        notes.append("in binary32 COS(THA) rounds to 1.0 at step 2 and the listing divides "
                     "by zero, where gfortran's trapping single-precision build stops too "
                     "(golden/*.r4.trap; README, 'Single precision')")
    return RunFailed(f"{source}: {_stopped(out)}" + "".join(f"; {n}" for n in notes))


@_subcommand
def _add_summary(sub: argparse._SubParsersAction) -> None:
    from deck_emulator.present.answers import definitions_help

    p = sub.add_parser(
        "summary",
        help="run a deck and print its outcomes (events, hit, delta-V, deceleration, P/Q/R)",
        description="Run the emulated program and print what the report's Tables 11 and 12 "
        "give: the events as sentences, the hit, the car's speed change in mph, the largest "
        "printed deceleration in g, P, Q, R at the hit in XL, YL, ZL; then the occupant-risk "
        "numbers and the cited limits they are judged by. The two speed changes: "
        + definitions_help() + ". --json: the same as one JSON object (docs/json.md).",
    )
    _add_emulator_options(p)
    _add_answer_options(p)
    _add_trajectory_option(p)
    _add_quiet_option(p)
    p.set_defaults(func=_cmd_summary)


# --------------------------------------------------------------------------- diff, core, scene


def _cmd_diff(args: argparse.Namespace) -> int:
    from deck_emulator.studies.diff import DiffStopped, diff_deck, format_diff

    src = _source(args, "diff", kinds=("deck",))
    deck = src.deck("diff")
    engine_scene(deck, name=src.name)  # the core must be able to solve it: exit 2 before work
    _check_out(args)
    if args.resume and not args.store:
        raise CLIError("--resume needs --store DIR (the folder the runs were stored in)")
    try:
        data = diff_deck(deck, precision=args.precision, errata=tuple(args.erratum),
                         ks=range(args.max_k + 1), rtol=args.rtol, atol=args.rtol,
                         tighten_ed=not args.as_printed_ed, jobs=args.jobs,
                         scheduler=_cluster(args), store_dir=args.store, resume=args.resume,
                         quiet=args.quiet, desc=f"{PROG}: diff")
    except DiffStopped as exc:
        raise RunFailed(str(exc)) from None
    if args.json:
        from deck_emulator.present.answers import envelope

        settings = {k: data.pop(k) for k in ("precision", "errata", "core_method", "core_rtol",
                                             "ed_tolerance_scaled")}
        data.pop("deck")
        _json(args, envelope("diff", src.name, settings=settings, **data))
        return 0
    _emit(args, format_diff(data))
    return 0


@_subcommand
def _add_diff(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "diff",
        help="run the emulator and the modern core on a deck and compare them",
        description="Side by side: the emulator (the listing as printed, or with errata) and the "
        "core's legacy preset; then both again as the step is halved k = 0..K times, with the "
        "observed order of convergence.",
    )
    _add_source(p)
    p.add_argument("--precision", default="double", choices=PRECISIONS,
                   help="the emulator's arithmetic at k = 0 (must run the deck to its end)")
    _add_erratum_option(p)
    p.add_argument("--max-k", type=_max_k, default=4, metavar="K",
                   help="halve the step up to K times, 0 <= K <= 8 (default 4; K = 8 runs "
                   "the listing's 2,054 steps 256 times over)")
    p.add_argument("--rtol", type=_tolerance, default=defaults.CORE_RTOL,
                   help="the core's tolerance, rtol = atol, 0 < RTOL < 1 (default %(default)g)")
    p.add_argument("--as-printed-ed", action="store_true",
                   help="keep ED's tolerance .0001 at every k (the scheme then does not converge)")
    _add_jobs_option(p)
    p.add_argument("--store", metavar="DIR",
                   help="keep the runs in DIR as they finish (default: a temporary folder)")
    _add_cluster_options(p)
    _add_answer_options(p)
    _add_quiet_option(p)
    p.set_defaults(func=_cmd_diff)


def engine_scene(source, name: str = ""):
    """The scene the core would solve for ``source`` (a scene or a deck); a deck or scene the
    core cannot solve (a zero mass, no impact point S ...) is bad input: one line, exit 2."""
    from deck_emulator.core.scene import Scene, SceneError

    try:
        if isinstance(source, Scene):
            return source.checked()
        return Scene.from_deck(source, name=name)
    except SceneError as exc:
        where = name or getattr(source, "path", None) or "the deck"
        raise CLIError(f"{where}: the core cannot solve it: {exc}") from None


def _cmd_core(args: argparse.Namespace) -> int:
    from deck_emulator.engine import CoreEngine
    from deck_emulator.present.answers import outcome_answer, render_outcome

    src = _source(args, "core")
    source = src.scene_or_deck("core")
    engine_scene(source)  # a deck the core cannot solve: exit 2 before any work
    _check_out(args)
    _check_trajectory(args)
    engine = CoreEngine(**_core_keywords(args), method=args.method, rtol=args.rtol, atol=args.atol,
                        t_max_s=args.max_time, max_wall_s=args.max_wall)
    out = _with_progress(args, engine, source)
    _write_trajectory(args, out)
    used = out.method or args.method
    settings = {**_core_keywords(args),
                "method": f"{used} (auto)" if args.method == "auto" and out.method else used,
                "rtol": args.rtol, "atol": args.atol}
    answer = outcome_answer(out, command="core", source=src.name, settings=settings)
    answer["notes"] += _odd_deck_notes(out) + list(out.notes)
    if out.error is not None:  # what it reached is answered; the status says it stopped
        _emit(args, _json_text(answer) if args.json else render_outcome(answer))
        raise _failed(out, src.name)
    landed = out.hit_message is not None
    if not landed:  # as the emulator says it: a run that could not end (exit status 3)
        stop = (f"{src.name}: simulated time passed the limit of {args.max_time:g} s "
                "(--max-time) with no hit: the post has not landed")
        answer["status"] = "stopped"
        answer["notes"].append(stop)
    _emit(args, _json_text(answer) if args.json else render_outcome(answer))
    if not landed:
        raise RunFailed(stop)
    return 0


@_subcommand
def _add_core(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("core", help="solve a deck or a scene (.toml) with the modern core",
                       description="The same model solved with quaternions, solve_ivp and located "
                       "events. Presets: legacy (the listing's quirks) or physical (none).")
    _add_source(p)
    _add_preset_option(p)
    p.add_argument("--method", default="auto",
                   choices=("auto", "DOP853", "RK45", "Radau", "BDF", "LSODA"),
                   help="solve_ivp's method; auto (the default): DOP853, or Radau for the "
                   "contact when the scene's springs make it stiff (the outcome says which)")
    p.add_argument("--rtol", type=_tolerance, default=defaults.CORE_RTOL,
                   help="relative tolerance, 0 < RTOL < 1 (default %(default)g)")
    p.add_argument("--atol", type=_tolerance, default=defaults.CORE_ATOL,
                   help="absolute tolerance, 0 < ATOL < 1 (default %(default)g)")
    p.add_argument("--max-time", type=_positive_float, default=defaults.T_MAX_S, metavar="S",
                   help="stop when simulated time passes S seconds (default %(default)s)")
    p.add_argument("--max-wall", type=_positive_float, default=defaults.MAX_WALL_S, metavar="S",
                   help="stop when the run has taken S seconds of wall time (default "
                   "%(default)s)")
    _add_answer_options(p)
    _add_trajectory_option(p)
    _add_quiet_option(p)
    p.set_defaults(func=_cmd_core)


def _cmd_scene(args: argparse.Namespace) -> int:
    src = _source(args, "scene")
    scene = engine_scene(src.scene_or_deck("scene"), name=src.stem)
    _check_out(args)
    if args.json:
        import tomllib

        from deck_emulator.present.answers import envelope

        _json(args, envelope("scene", src.name, notes=src.notes,
                             scene=tomllib.loads(scene.to_toml())))
        return 0
    _emit(args, scene.to_toml())
    return 0


@_subcommand
def _add_scene(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("scene", help="write a deck's scene as TOML (to edit by hand, then `core`)")
    _add_source(p)
    p.add_argument("--out", metavar="FILE", help="write to FILE instead of stdout")
    _add_json_option(p, "the scene (the TOML's tables)")
    p.set_defaults(func=_cmd_scene)


# --------------------------------------------------------------------------- compare


def _printout_text(path: str) -> str:
    from deck_emulator.legacy.deck import read_bytes

    shown, data = read_bytes(path, limit=1 << 26)  # DeckError naming the file
    return data.decode("ascii", errors="replace")


def _cmd_compare(args: argparse.Namespace) -> int:
    from deck_emulator.legacy.compare import compare
    from deck_emulator.legacy.extract import ExtractError, parse_printout

    texts = []
    for path in (args.a, args.b):
        text = _printout_text(path)
        try:
            items = parse_printout(text)
        except ExtractError as exc:
            raise CLIError(f"{path}: {exc}") from None
        if not items and text.strip():  # (an empty file: a run that printed nothing)
            raise CLIError(f"{path}: not a printout of the program: no 'THE VALUE OF' line "
                           "and no 'THE POST HAS' message")
        texts.append(text)
    differences = compare(*texts, tolerance=args.tolerance)
    status = 1 if differences else 0
    shown = differences if args.max is None else differences[:args.max]
    if args.json:
        from deck_emulator.present.answers import envelope

        _json(args, envelope(
            "compare", f"{args.a} {args.b}", settings={"tolerance": args.tolerance},
            status="ok", agree=not differences, differences=[vars(d) for d in shown],
            differences_total=len(differences)))
        return status
    tol = "exactly as printed" if args.tolerance == 0 else f"within {args.tolerance:g}"
    if not differences:
        _emit(args, f"A {args.a} and B {args.b} agree ({tol}).\n")
        return 0
    lines = [d.line() for d in shown]
    more = len(differences) - len(shown)
    lines.append(f"{len(differences)} difference(s) between A {args.a} and B {args.b} "
                 f"(values compared {tol})" + (f"; {more} not shown (--max)" if more else ""))
    _emit(args, "\n".join(lines) + "\n")
    return status


def _tolerance_value(text: str) -> float:
    value = _finite_float(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"{text}: at least 0")
    return value


@_subcommand
def _add_compare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "compare", help="compare two printouts of the program, value by value",
        description="Read two printouts of the program (this tool's, the compiled listing's, or "
        "one typed or scanned from another source), line them up page by page and value by "
        "value, and print each difference with its record, variable and size. Exit status 0 "
        "when they agree (exactly as printed, or within --tolerance), 1 when they differ, 2 "
        "for input that is not a printout.")
    p.add_argument("a", metavar="A", help="a printout (text, carriage control in column 1)")
    p.add_argument("b", metavar="B", help="the printout to compare it with")
    p.add_argument("--tolerance", type=_tolerance_value, default=0.0, metavar="X",
                   help="values agree when they differ by at most X (default 0: exactly)")
    p.add_argument("--max", type=_positive_int, metavar="N",
                   help="show at most N differences (all are counted)")
    _add_answer_options(p)
    p.set_defaults(func=_cmd_compare)


# --------------------------------------------------------------------------- corrections


def _cmd_corrections(args: argparse.Namespace) -> int:
    from deck_emulator.legacy import corrections

    if args.all and args.key:
        raise CLIError("corrections: give an entry's KEY or --all, not both")
    entries = corrections.entries()
    if args.key:
        try:
            entries = [corrections.find(args.key)]
        except KeyError:
            keys = ", ".join(e.key for e in entries)
            raise CLIError(f"corrections {args.key}: no such entry (there are: {keys})") from None
    if args.json:
        from deck_emulator.present.answers import envelope

        listed = not (args.key or args.all)  # the list: keys and titles, not the full texts
        _json(args, envelope("corrections", "luminaire.f", entries=[
            {k: v for k, v in vars(e).items() if not (listed and k == "text")}
            for e in entries]))
    elif args.all:
        _emit(args, corrections.document() + "".join(
            f"\n## errata/{n}.patch\n\n{corrections.patch(n)}" for n in corrections.ERRATA))
    elif args.key:
        _emit(args, entries[0].text.rstrip("\n") + "\n")
    else:
        _emit(args, _corrections_list(entries))
    return 0


def _corrections_list(entries) -> str:
    kinds = {"departure": "Departures of luminaire.f from the scanned listing",
             "kept": "Kept as printed, although an equation differs",
             "section": "Notes", "erratum": "Errata (applied only with --erratum NAME)"}
    lines = []
    for kind, heading in kinds.items():
        chosen = [e for e in entries if e.kind == kind]
        if chosen:
            lines += ["", heading]
            width = max(len(e.key) for e in chosen)
            lines += [f"  {e.key:<{width}}  {_shorten(e.title, 100 - width)}" for e in chosen]
    lines += ["", "deck-emulator corrections KEY shows one in full; --all the whole record."]
    return "\n".join(lines[1:]) + "\n"


def _shorten(text: str, width: int) -> str:
    import textwrap

    return textwrap.shorten(text.replace("**", ""), width, placeholder=" ...")


@_subcommand
def _add_corrections(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "corrections", help="the corrections to the scanned listing and the named errata",
        description="Every place where the transcribed listing (luminaire.f) departs from the "
        "report's scanned listing, with its reason; what is kept as printed; the named errata "
        "and their patches. Read from the installed package.")
    p.add_argument("key", nargs="?", metavar="KEY",
                   help="show one entry in full: a departure's number (8), an erratum's name "
                   "(ed-direction) or a note's key")
    p.add_argument("--all", action="store_true", help="the whole record and every patch")
    _add_answer_options(p)
    p.set_defaults(func=_cmd_corrections)


# --------------------------------------------------------------------------- assembly


def _ms(t_s) -> str:
    return "no time" if t_s is None else f"{1000.0 * t_s:.1f} ms"


def _cmd_assembly(args: argparse.Namespace) -> int:
    """Build a support assembly (or the crash test) from a description file and print its
    mass properties, its deck, its scene, or run it."""
    import math as _m

    from deck_emulator.core import assembly as asm
    from deck_emulator.engine import assemblies as bridge

    from deck_emulator.present.answers import envelope

    def answer(status="ok", notes=(), **result):
        _json(args, envelope("assembly", args.description, status=status, notes=notes,
                             settings={"what": args.what, "speed_mph": args.speed_mph,
                                       "alpha_deg": args.alpha_deg}, **result))

    try:
        a, extra, _ = asm.load_assembly(args.description)
    except (asm.AssemblyError, OSError) as exc:
        raise CLIError(str(exc)) from None
    if a is None:  # the crash test
        from deck_emulator.studies import crash_test as ct

        scene = ct.crash_scene(extra["crash_test"])  # the description's own crash test
        if args.what == "scene":
            if args.json:
                import tomllib

                answer(scene=tomllib.loads(scene.to_toml()))
                return 0
            _emit(args, scene.to_toml())
            return 0
        if args.what in ("deck", "emulator"):
            raise CLIError(f"cannot run on the listing: {asm.scene_runs_on_listing(scene)}")
        res, loss, r70 = ct.table10(scene)  # res: the run's Outcome
        if args.json:
            answer(hit={"message": res.hit_message, "time_s": res.hit_time_s},
                   at_loss_of_contact=loss, at_70_ms=r70)
            return 0
        rows = [f"{k}: at loss of contact {loss[k]:.4f}, at 70 ms {r70[k]:.4f}" for k in loss]
        _emit(args, f"hit: {res.hit_message} at {_ms(res.hit_time_s)}\n" + "\n".join(rows) + "\n")
        return 0
    # the car: the report's deck of that speed and angle where there is one, else steel40's
    # car with VVB and ALPHA set by the sweep's rules (the report's deck's decimals)
    from deck_emulator.studies.sweep import car_at

    template, car = car_at(args.speed_mph, args.alpha_deg)
    mp = asm.mass_properties(a)
    if args.what == "props" and args.json:
        answer(name=a.name, weight_lb=mp.weight_lb, mass_slug=mp.mass_slug, wall_in=mp.wall_in,
               inertia_slug_ft2=[mp.A, mp.B, mp.C], delta_rad=mp.delta_rad,
               cm_height_ft=mp.cm_height_ft, cm_offset_ft=mp.cm_offset_ft,
               points_ft={k: list(p) for k, p in mp.points.items()})
        return 0
    if args.what == "props":
        lines = [f"{a.name}: weight {mp.weight_lb:.2f} lb, W {mp.mass_slug:.5f} slug, wall "
                 f"{mp.wall_in:.4f} in, A {mp.A:.2f}, B {mp.B:.2f}, C {mp.C:.3f} slug ft^2, "
                 f"delta {mp.delta_rad:.5f} rad ({_m.degrees(mp.delta_rad):.3f} deg), mass centre "
                 f"{mp.cm_height_ft:.3f} ft above Q, {mp.cm_offset_ft:.3f} ft in YY from the axis"]
        lines += [f"  {k}: ({p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f}) ft" for k, p in mp.points.items()]
        _emit(args, "\n".join(lines) + "\n")
        return 0
    scene = bridge.to_scene(a, mp, template=template, **car)
    if args.what == "scene":
        if args.json:
            import tomllib

            answer(scene=tomllib.loads(scene.to_toml()))
            return 0
        _emit(args, scene.to_toml())
        return 0
    reason = asm.scene_runs_on_listing(scene)
    if args.what in ("deck", "emulator") and reason is not None:
        raise CLIError(f"cannot run on the listing: {reason}")
    if args.what == "deck":
        values = bridge.to_deck_values(a, mp, template=template, **car)
        if args.json:
            answer(values=values, cards=bridge.to_deck_text(values).splitlines())
            return 0
        _emit(args, bridge.to_deck_text(values))
        return 0
    if args.what == "emulator":
        from deck_emulator.engine import EmulatorEngine
        from deck_emulator.legacy.deck import parse_deck

        deck = parse_deck(bridge.to_deck_text(bridge.to_deck_values(a, mp, template=template,
                                                                    **car)))
        out = EmulatorEngine(errata=tuple(args.erratum), trace=False).run(deck)
        if args.json:
            answer(status="stopped" if out.error else "ok",
                   notes=[_stopped(out)] if out.error else [], records=list(out.raw.records))
        else:
            _emit(args, out.raw.text())
        if out.error:
            _say(f"error: {_stopped(out)}")
            return EXIT_RUN_FAILED
        return 0
    from deck_emulator.engine import CoreEngine
    from deck_emulator.present.answers import outcome_answer, render_outcome

    out = CoreEngine(**_core_keywords(args)).run(scene, name=a.name)
    settings = {**_core_keywords(args), "method": out.method,
                "car": f"{args.speed_mph:g} mph at {args.alpha_deg:g} deg ({template}'s car"
                       + (", VVB and ALPHA set)" if car else ")")}
    answer = outcome_answer(out, command="assembly", source=a.name, settings=settings)
    answer["notes"] += list(out.notes)
    _emit(args, _json_text(answer) if args.json else render_outcome(answer))
    if out.error is not None:  # what it reached is answered; the status says it stopped
        raise _failed(out, args.description)
    return 0


@_subcommand
def _add_assembly(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "assembly", help="build, print or run a support assembly from a description file",
        description="NAME is a shipped description (steel, aluminium, twin, crash_test) or a "
        ".toml file. WHAT: props (mass properties and points), deck (the 8-card deck; one "
        "arm only), scene (TOML), core (run the core), emulator (run the listing).")
    p.add_argument("description", metavar="NAME_OR_TOML",
                   help="steel, aluminium, twin, crash_test, or a description file (.toml)")
    p.add_argument("what", nargs="?", default="props",
                   choices=("props", "deck", "scene", "core", "emulator"),
                   help="what to print or run (default props)")
    p.add_argument("--speed-mph", type=_speed_mph, default=40.0, metavar="MPH",
                   help="the car's speed in mph, any from 1 to 200 (default 40; the report's "
                   "20 and 40 take its own decks' car)")
    p.add_argument("--alpha-deg", type=_angle_deg, default=0.0, metavar="DEG",
                   help="the approach angle in degrees, 0 to 89 (default 0; the report ran 0, "
                   "15 and 30)")
    _add_erratum_option(p)
    _add_preset_option(p)
    _add_json_option(p, "what it prints (with core: the outcome, as deck-emulator core --json)")
    p.add_argument("--out", metavar="FILE", help="write to FILE instead of stdout")
    p.set_defaults(func=_cmd_assembly)


# --------------------------------------------------------------------------- plot, sweep, study


# --------------------------------------------------------------------------- plot


def _cmd_plot(args: argparse.Namespace) -> int:
    from deck_emulator.parallel import busy
    from deck_emulator.present.plot import _cmd_plot as plot, check_plot_outputs

    check_plot_outputs(args.out, args.animate)
    if args.animate and (args.view in ("3d", "all") or args.pulse):
        raise CLIError(f"--animate draws the side or the plan view, not "
                       f"{'the pulse' if args.pulse else '--view ' + args.view}: give "
                       "--view side or --view plan")
    command = "plot" + (" --pulse" if args.pulse else "")
    emulator = args.engine != "core" or args.pulse
    src = _source(args, command, kinds=("deck",) if emulator else ("deck", "scene"))
    args.source = src.scene_or_deck(command)
    args.name = src.name
    with busy(f"{PROG}: plot", quiet=args.quiet):
        status = plot(args)
    if args.json:
        import json

        from deck_emulator.present.answers import envelope

        sys.stdout.write(json.dumps(envelope(
            "plot", src.name, settings={"engine": args.engine, "view": args.view,
                                        "pulse": args.pulse, "errata": list(args.erratum),
                                        "preset": args.preset},
            status="stopped" if status else "ok", notes=src.notes,
            outputs=[args.out] + ([args.animate] if args.animate else [])), indent=2) + "\n")
    return status


@_subcommand
def _add_plot(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "plot",
        help="draw the post's fall (side, plan, 3-d), the vehicle pulse, or an animation",
        description="Draw the post as a line through its named points at regular instants in "
        "the report's XL, YL, ZL axes, with the ground, the car at the hit and the hit point "
        "(--view side|plan|3d|all); or, with --pulse, the car's deceleration and speed over the "
        "contact for both engines. The emulator runs the listing as printed unless --erratum "
        "names an erratum. Exit status 3 if a run stopped early (the picture shows what it "
        "computed).",
    )
    _add_source(p, help=SOURCE_HELP + "; a scene with --engine core")
    p.add_argument("--out", required=True, metavar="FILE.png",
                   help="the picture to write: .png, .svg, .pdf (any format matplotlib writes)")
    p.add_argument("--engine", choices=("emulator", "core"), default="emulator",
                   help="which engine's run to draw (default emulator)")
    p.add_argument("--view", choices=VIEWS, default="side", help="which view (default side)")
    p.add_argument("--pulse", action="store_true",
                   help="draw the vehicle pulse (both engines) instead of the trajectory")
    p.add_argument("--animate", metavar="FILE.gif",
                   help="also write the fall as an animated GIF (.mp4 if ffmpeg is installed)")
    _add_erratum_option(p)
    _add_preset_option(p)
    p.add_argument("--every", type=_positive_float, metavar="MS",
                   help="draw the post every MS milliseconds (default: about 20 instants)")
    _add_quiet_option(p)
    _add_json_option(p, "what was drawn and written")

    p.set_defaults(func=_cmd_plot)


# --------------------------------------------------------------------------- sweep


def _cmd_sweep(args: argparse.Namespace) -> int:
    import time

    from deck_emulator.files import OutputSet, check_output_dir
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.studies.distributed import output_store
    from deck_emulator.studies.sweep import (POSTS, parse_grid, render_markdown, scene_deck,
                                             sweep, write_csv)

    try:
        speeds = parse_grid(args.speeds)
        angles = parse_grid(args.angles)
    except ValueError as exc:
        raise CLIError(f"--speeds/--angles: {exc}") from None
    if any(s <= 0 for s in speeds):
        raise CLIError("--speeds must be positive (mph)")
    if any(not (0 <= a < 90) for a in angles):
        raise CLIError("--angles must be in [0, 90) degrees")
    if not 0 <= args.vvb_decimals <= 5:
        raise CLIError("--vvb-decimals must be 0 to 5")
    base = (Path(_deck_file(args.base_deck, "sweep --base-deck")) if args.base_deck
            else POSTS[args.post])
    base_deck = read_deck(base)  # bad deck -> DeckError, before any work
    for s in speeds:  # every VVB/ALPHA must punch: fail before running anything
        for a in angles:
            scene_deck(base_deck, s, a, args.vvb_decimals)
    check_output_dir(args.out)
    options = (dict(errata=tuple(args.erratum)) if args.engine == "emulator"
               else _core_keywords(args))
    store = output_store(args.out, args.resume)  # a new sweep: the scenes of the last one go
    started = time.perf_counter()
    rows = sweep(speeds, angles, engine=args.engine, options=options, post=args.post,
                 base=base, jobs=args.jobs, vvb_decimals=args.vvb_decimals, quiet=args.quiet,
                 store_dir=store, scheduler=_cluster(args), resume=args.resume)
    wall = time.perf_counter() - started
    command = "deck-emulator sweep " + " ".join(sys.argv[2:]) if sys.argv[1:2] == ["sweep"] else ""
    with OutputSet(directory=args.out) as outputs:
        outputs.write("sweep.csv", write_csv(rows))
        outputs.write("sweep.md", render_markdown(rows, command=command, engine=args.engine))
    failed = [r for r in rows if r["error"]]
    where = f"on {args.scheduler}" if args.scheduler else f"on {args.jobs or os.cpu_count()} job(s)"
    _say(f"{len(rows)} scenes ({args.engine}) in {wall:.1f} s {where}; {len(failed)} stopped "
         f"early; wrote {Path(args.out) / 'sweep.csv'} and {Path(args.out) / 'sweep.md'}")
    if args.json:
        from deck_emulator.present.answers import envelope

        _json(argparse.Namespace(), envelope(
            "sweep", str(args.base_deck or args.post), settings={
                "engine": args.engine, **{k: list(v) if isinstance(v, tuple) else v
                                          for k, v in options.items()},
                "speeds_mph": list(speeds), "angles_deg": list(angles)},
            status="stopped" if failed else "ok",
            notes=[r["stopped_hint"] for r in failed if r["stopped_hint"]][:1],
            outputs=[str(Path(args.out) / "sweep.csv"), str(Path(args.out) / "sweep.md")],
            scenes=len(rows), stopped=[r["scene"] for r in failed]))
    if failed:  # the tables are written, the stopped rows marked and not rated: exit 3
        for hint in dict.fromkeys(r["stopped_hint"] for r in failed if r["stopped_hint"]):
            _say(f"stopped scenes: {hint}")
        _say("error: " + ", ".join(r["scene"] for r in failed) + " stopped early (their rows "
             "say why; no ratings for them)")
        return EXIT_RUN_FAILED
    return 0


@_subcommand
def _add_sweep(sub: argparse._SubParsersAction) -> None:
    from deck_emulator.studies import SCENE_STORE

    p = sub.add_parser(
        "sweep",
        help="run a grid of speeds and approach angles and tabulate it like Tables 11 and 12",
        description="Regenerate the report's parameter study: every speed x angle of the grid "
        "is the base deck with VVB and ALPHA changed, run in parallel. Writes DIR/sweep.csv (one "
        "row per scene, every output, the report's value and the difference) and DIR/sweep.md "
        "(one table per speed, laid out like Tables 11 and 12). The emulator runs the listing as "
        "printed unless --erratum names an erratum (the angled scenes need ed-direction).",
    )
    p.add_argument("--post", choices=("steel",), default="steel",
                   help="the post (the report's steel post: its deck steel40, shipped with the "
                   "package)")
    p.add_argument("--base-deck", metavar="SOURCE",
                   help="another base deck instead of --post's: a shipped deck's name or a "
                   "text deck file")
    p.add_argument("--speeds", required=True, metavar="MPH,...",
                   help="vehicle speeds in mph: 20,40 or 10:60:10 (stop included)")
    p.add_argument("--angles", required=True, metavar="DEG,...",
                   help="approach angles in degrees: 0,15,30 or 0:45:5")
    p.add_argument("--engine", choices=("emulator", "core"), default="emulator",
                   help="which engine runs the scenes (default emulator)")
    _add_erratum_option(p)
    _add_preset_option(p)
    _add_jobs_option(p)
    p.add_argument("--vvb-decimals", type=int, default=2, metavar="N",
                   help="decimals VVB is cut to (default 2, as the report's deck: -58.66)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    _add_json_option(p, "what ran and what was written")
    _add_cluster_options(p)
    p.add_argument("--out", required=True, metavar="DIR",
                   help="directory for sweep.csv and sweep.md (and the scene store, "
                   f"DIR/{SCENE_STORE}, kept for --resume)")
    p.set_defaults(func=_cmd_sweep)


# --------------------------------------------------------------------------- sensitivity


@_subcommand
def _add_sensitivity(sub: argparse._SubParsersAction) -> None:
    from deck_emulator.studies import SCENE_STORE

    p = sub.add_parser(
        "sensitivity",
        help="Sobol indices of the outcome over the report's uncertain inputs",
        description="Sample the inputs the report takes as estimates (base friction and its "
        "travel, CK, CT, FCONST, WV; and any --input NAME=LO:HI), run every sample on one "
        "engine on a Dask cluster, and write DIR/sensitivity.csv and .md (Sobol S1 and ST with "
        "95% confidence, for N and N/2), a bar chart of the indices and a map of what the post "
        "hits first over the two most influential inputs. Scenes are stored as they finish in "
        f"DIR/{SCENE_STORE}/; --resume runs only the missing ones.",
    )
    p.add_argument("--deck", action="append", metavar="SOURCE",
                   help="a shipped deck's name or a text deck file; repeat for several "
                   "(default steel40)")
    p.add_argument("--engine", choices=("core", "emulator"), default="core",
                   help="default core: the emulator's deck has no base-friction field")
    _add_preset_option(p)
    p.add_argument("--input", action="append", metavar="NAME=LO:HI",
                   help="add or re-range an input (a READ-list name, or friction_lb, "
                   "friction_travel_ft on the core)")
    p.add_argument("--only", action="store_true", help="only the --input inputs")
    p.add_argument("-N", dest="n", type=int, metavar="N",
                   help="base sample size, a power of two (default 256; 16 with --quick)")
    p.add_argument("--quick", action="store_true",
                   help="N = 16 (128 scenes with the default inputs): a first look in about a "
                   "minute on two cores; wide intervals")
    p.add_argument("--seed", type=int, default=0, help="the sample's seed (default 0)")
    _add_json_option(p, "what ran and what was written")
    _add_quiet_option(p)
    _add_jobs_option(p)
    _add_cluster_options(p)
    p.add_argument("--out", required=True, metavar="DIR", help="directory for the results")

    def run(args):
        from deck_emulator.studies.sensitivity import run_command

        for deck in args.deck or ():  # shipped names stay names (the outputs are named by them)
            _deck_file(deck, "sensitivity --deck")
        try:
            status = run_command(args)
        except RunFailed as exc:  # said as every command says it; the JSON still answers
            print(f"{PROG}: error: {exc}", file=sys.stderr)
            status = EXIT_RUN_FAILED
        if args.json and status in (0, EXIT_RUN_FAILED):
            _json(argparse.Namespace(), _outputs_answer("sensitivity", args.deck or ["steel40"],
                                                        args.out, status))
        return status

    p.set_defaults(func=run)


# --------------------------------------------------------------------------- study


@_subcommand
def _add_study(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "study",
        help="work-precision and stability studies (CSV, PNG and Markdown into --out)",
        description="Numerical studies of the 1967 scheme (the emulator) and the modern core. "
        "Each writes a CSV of every run, PNG figures and a README.md report into --out.",
    )
    studies = p.add_subparsers(dest="study", metavar="STUDY", required=True)

    def run(args):
        from deck_emulator.files import check_output_dir
        from deck_emulator.studies.study_cli import _cmd_study

        if getattr(args, "deck", None):
            from deck_emulator.legacy.deck import read_deck

            args.deck = _deck_file(args.deck, f"study {args.study}")
            engine_scene(read_deck(args.deck), name=args.deck)  # both engines run it: exit 2
        check_output_dir(args.out)  # before any work, and before the study makes the folder
        status = _cmd_study(args)
        if args.json:
            _json(argparse.Namespace(), _outputs_answer(f"study {args.study}",
                                                        getattr(args, "deck", None) or "steel40",
                                                        args.out, status))
        return status

    def common(q):
        q.add_argument("--out", required=True, metavar="DIR", help="directory for the outputs")
        q.add_argument("--quick", action="store_true",
                       help="a small grid (seconds, for tests) instead of the full study")
        _add_jobs_option(q)
        _add_cluster_options(q)
        _add_quiet_option(q)
        _add_json_option(q, "what ran and what was written")
        q.set_defaults(func=run)

    e = studies.add_parser(
        "error", help="error against run time: the emulator at H = 0.0004/2**k, the core at "
        "rtol 1e-3 ... 1e-11, against a 1e-12 reference",
        description="Work-precision study on DECK: the emulator in double precision at H = "
        "0.0004/2**k (k = 0..6; the listing's ED tolerance and a tightened one), in the IBM 7094 "
        "arithmetic at k = 0, and the core with DOP853, RK45 and Radau at rtol 1e-3 ... 1e-11, "
        "all against the core at rtol 1e-12 (itself checked with Radau and LSODA at 1e-13).")
    e.add_argument("deck", metavar="SOURCE",
                   help="a shipped deck's name (steel40) or a text deck file")
    common(e)
    s = studies.add_parser(
        "stability", help="stiff springs against H, and extreme scenes, for the emulator and "
        "the core",
        description="Stability study: a grid of scenes derived from steel40 (CK = CT from "
        "3.3e4 to 1e10 lb/ft against H; speeds 5-120 mph; approach angles to 90 deg; delta = 0; "
        "the start-up THA; A = B = C; light and heavy posts; base friction; THB near 90 deg), "
        "each run by the emulator and the core, with how it ended.")
    s.add_argument("--deck", metavar="SOURCE", default=None,
                   help="base deck: a shipped deck's name or a text deck file (default: the "
                   "report's deck steel40)")
    common(s)




def _outputs_answer(command: str, source, out_dir, status: int) -> dict:
    """The JSON answer of a command that writes a folder: the files it holds."""
    from deck_emulator.present.answers import envelope

    files = sorted(str(p) for p in Path(out_dir).iterdir() if p.is_file()
                   and not p.name.startswith("."))
    return envelope(command, source, status="stopped" if status else "ok", outputs=files)


# --------------------------------------------------------------------------- main


class _Parser(argparse.ArgumentParser):
    """argparse's parser, but a usage error is one line (and exit status 2), and a negative
    number in exponent form (``--tha-start -1e-5``) is a value, not an option."""

    def __init__(self, *args, **kwargs):
        import re

        kwargs.setdefault("formatter_class", _help_formatter)
        super().__init__(*args, **kwargs)
        # argparse's own pattern knows -1 and -.5 but not -1e-5
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")

    def error(self, message: str):
        self.exit(EXIT_BAD_INPUT, f"{PROG}: error: {message} (see {self.prog} --help)\n")


def _help_formatter(prog: str) -> argparse.HelpFormatter:
    """argparse's help formatter at the terminal's width, found as shutil.get_terminal_size
    finds it (COLUMNS, else the terminal of stdout, else 80 columns) but without importing
    shutil: argparse makes a formatter for every option it adds, and its own way imports shutil
    (with zlib, bz2 and lzma) into every run, about 2.5 ms of a plain run's start."""
    try:
        columns = int(os.environ.get("COLUMNS", "0"))
    except ValueError:
        columns = 0
    if columns <= 0:
        try:
            columns = os.get_terminal_size(sys.__stdout__.fileno()).columns
        except (AttributeError, ValueError, OSError):
            columns = 0
    return argparse.HelpFormatter(prog, width=(columns or 80) - 2)


class _Version(argparse.Action):
    """``--version``: the installed package's metadata, read only when asked."""

    def __call__(self, parser, namespace, values, option_string=None):
        import deck_emulator

        print(f"{parser.prog} {deck_emulator.__version__}")
        parser.exit(0)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The whole command line's parser; with ``command`` (a subcommand's name), one whose
    only subcommand is that one: it parses a command line that starts with that name as the
    whole parser does (argparse gives everything after the name to its subparser), and
    building it skips the other subcommands' parsers and what they import (about 10 ms of
    every start).  The top-level help and usage errors need the whole parser."""
    parser = _Parser(
        prog=PROG,
        description="Emulator of the 1967 TTI luminaire-support impact program (Report 75-9).",
    )
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="print the installed version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, add in _SUBCOMMANDS.items():
        if command is None or name == command:
            add(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """The command line; SIGINT and SIGTERM end it with 130 and 143 after every temporary
    file is removed and every worker stopped (:mod:`deck_emulator.signals`)."""
    from deck_emulator import signals

    return signals.run(_main, argv)


#: the options that name a file or folder to write (an empty value is refused)
_PATH_OPTIONS = ("out", "pages", "animate", "trajectory", "store")


def _main(argv: Sequence[str] | None = None) -> int:
    from deck_emulator.legacy.deck import DeckError

    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(argv[0] if argv and argv[0] in _SUBCOMMANDS else None)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (2) and --help (0)
        return exc.code if isinstance(exc.code, int) else 2
    for option in _PATH_OPTIONS:  # '--out ""' would name the current folder or stdout
        value = getattr(args, option, None)
        if value == "" or (isinstance(value, str) and "\0" in value):
            why = "an empty path names no file" if value == "" else "a path holds no NUL byte"
            print(f"{PROG}: error: --{option}: {why}", file=sys.stderr)
            return EXIT_BAD_INPUT
    if getattr(args, "worker_wait", None) is not None and not getattr(args, "scheduler", None):
        print(f"{PROG}: error: --worker-wait: only with --scheduler (the embedded cluster's "
              "workers start with it)", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        with warnings.catch_warnings():  # numpy's divide-by-zero and the like: the notes say why
            warnings.simplefilter("ignore", RuntimeWarning)
            return args.func(args)
    except (DeckError, UsageError, OSError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_RUN_FAILED if isinstance(exc, RunFailed) else EXIT_BAD_INPUT
    except ImportError as exc:  # an optional part of the install is missing: which to add
        from deck_emulator.extras import missing_extra

        message = missing_extra(exc)
        if message is None:
            raise
        print(f"{PROG}: error: {args.command}: {message}", file=sys.stderr)
        return EXIT_BAD_INPUT


if __name__ == "__main__":
    raise SystemExit(main())
