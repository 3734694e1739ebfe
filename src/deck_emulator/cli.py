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
import json
import os
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.present.answers import definitions_help
from deck_emulator.studies import SCENE_STORE
from deck_emulator.units import G_FT_S2

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

# Functions that add one subcommand's parser; main() calls each of them in order.
_SUBCOMMANDS: list[Callable[[argparse._SubParsersAction], None]] = []


def _subcommand(add: Callable[[argparse._SubParsersAction], None]):
    _SUBCOMMANDS.append(add)
    return add


def _say(message: str) -> None:
    print(f"{PROG}: {message}", file=sys.stderr)


def _emit(args, text: str) -> None:
    if getattr(args, "out", None):
        from deck_emulator.files import write_file

        write_file(args.out, text)
    else:
        sys.stdout.write(text)


def _check_out(args) -> None:
    """The output file's folder must exist and be writable: checked before any work."""
    if getattr(args, "out", None):
        from deck_emulator.files import check_output_file

        check_output_file(args.out)


def _add_cluster_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on an existing Dask cluster (its scheduler's address, "
                   "tcp://host:8786) instead of an embedded one of --jobs workers")
    p.add_argument("--resume", action="store_true",
                   help="run only the scenes not yet stored in the output directory")


def _is_scene(path) -> bool:
    """A scene file (TOML with tables), whatever its name; a card deck is never valid TOML."""
    import tomllib

    if str(path).endswith(".toml"):
        return os.path.isfile(path)
    try:
        with open(path, "rb") as fh:
            data = fh.read(1 << 20)
        parsed = tomllib.loads(data.decode("utf-8"))
    except (OSError, ValueError):
        return False
    return any(isinstance(v, dict) for v in parsed.values())


def _refuse_scene(path, command: str, why: str = "") -> None:
    """``run``/``parse``/``summary``/``diff`` need a card deck: say so, and what to do."""
    if _is_scene(path):
        raise CLIError(
            f"{path}: a scene file; {command} needs a card deck{why} (the emulator reads "
            f"8-card decks): run the scene with `{PROG} core {path}`, or give {command} the "
            f"deck it was made from ({PROG} scene DECK writes a deck's scene)")


def _with_progress(args, engine, source):
    """``engine.run(source)`` with the progress display (stderr, a terminal only)."""
    from deck_emulator.parallel import busy

    if engine.name != "emulator":
        with busy(f"{PROG}: {engine.name} running", quiet=getattr(args, "quiet", False)):
            return engine.run(source)
    programs = []

    def status() -> str:
        return f"step {programs[0].step}" if programs else ""

    with busy(f"{PROG}: emulator running", quiet=getattr(args, "quiet", False), status=status):
        return engine.run(source, watch=programs.append)


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


def _load_job(args):
    """``args.deck`` as a plain or a job deck; says on stderr what the source is and what the
    deck reader warns of."""
    from deck_emulator.legacy.jobdeck import read_job

    job = read_job(args.deck, getattr(args, "card_format", "auto"),
                   getattr(args, "keypunch", None))
    if job.source_verdict:
        _say(f"{job.path}: {job.source_verdict}")
    for deck in job.decks:
        for warning in deck.warnings:
            _say(f"{deck.path}: warning: {warning}")
    return job


def _load_one_deck(args):
    """The one data deck of ``args.deck``; DeckError if it holds several $DATA sections."""
    from deck_emulator.legacy.deck import DeckError

    job = _load_job(args)
    if len(job.decks) != 1:
        raise DeckError(f"this command takes one $DATA section and the deck holds "
                        f"{len(job.decks)}; `run` runs each in turn", path=job.path)
    return job.decks[0]


def _cmd_punch(args: argparse.Namespace) -> int:
    from deck_emulator.legacy.cardimage import write_images
    from deck_emulator.legacy.deck import DeckError
    from deck_emulator.legacy.jobdeck import data_deck_texts, job_deck_texts

    job = _load_job(args)
    _check_out(args)
    texts = (job_deck_texts(list(job.decks)) if args.job else data_deck_texts(list(job.decks)))
    try:
        data = write_images(texts, args.to, args.code)
    except DeckError as err:
        raise DeckError(f"cannot punch in the {args.code} code: {err}") from None
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
    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    _add_card_options(p)
    p.add_argument("--to", choices=FORMATS, default="text", help="card format to punch")
    p.add_argument("--code", choices=sorted(CODES), default="026",
                   help="keypunch code of the punched holes (default 026)")
    p.add_argument("--job", action="store_true", help="punch a whole IBSYS job deck")
    p.add_argument("--out", metavar="FILE", help="write to FILE (default: stdout)")
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


def _positive_float(text: str) -> float:
    import math

    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not (math.isfinite(x) and x > 0):
        raise argparse.ArgumentTypeError(f"must be a positive finite number, not {text}")
    return x


def _tolerance(text: str) -> float:
    x = _positive_float(text)
    if x >= 1:
        raise argparse.ArgumentTypeError(f"must be below 1, not {text}")
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

    _refuse_scene(args.deck, "parse")
    deck = _load_one_deck(args)
    if args.json:  # name -> value, READ order (docs/json.md: the units are the table's)
        sys.stdout.write(json.dumps(deck.values) + "\n")
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
    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    _add_card_options(p)
    p.add_argument(
        "--json", action="store_true",
        help="print one JSON object, name -> value, in READ order (docs/json.md)")
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

    _refuse_scene(args.deck, "run")
    job = _load_job(args)
    _check_out(args)
    if args.pages:
        from deck_emulator.files import check_output_file

        check_output_file(args.pages)
    engine = _emulator(args, trace=False)
    records, text, failed = [], "", None
    for deck in job.decks:  # a job deck's $DATA sections, in turn
        out = _with_progress(args, engine, deck)
        run = out.raw
        records += run.records
        text += render_asa(run.records) if args.render else run.text()
        _say(f"{deck.path}: {_describe(run)}")
        if out.error is not None:
            failed = (out, deck.path)
            break
    _emit(args, text)
    if args.pages:
        from deck_emulator.legacy.pages import write_pdf

        write_pdf(records, args.pages, paper=args.paper)
    if failed is not None:
        _say(f"error: {_failed(*failed)}")
        return EXIT_RUN_FAILED
    return 0


def _add_emulator_options(p: argparse.ArgumentParser) -> None:
    from deck_emulator.legacy.emulator import Limits

    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    _add_card_options(p)
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
                   help="also lay the printout out as the line printer's pages, as PDF")
    p.add_argument("--paper", choices=("plain", "striped"), default="plain",
                   help="the fan-fold paper of --pages (default plain)")


    _add_quiet_option(p)
    p.add_argument("--render", action="store_true",
                   help="render ASA carriage control (1 = form feed, 0 = blank line, + = "
                   "overprint) as the POSIX asa utility does, instead of the raw records")
    p.set_defaults(func=_cmd_run)


# --------------------------------------------------------------------------- summary


def _cmd_summary(args: argparse.Namespace) -> int:
    from deck_emulator.present.answers import outcome_answer, render_outcome

    _refuse_scene(args.deck, "summary")
    deck = _load_one_deck(args)
    _check_out(args)
    engine = _emulator(args)
    out = _with_progress(args, engine, deck)
    if out.error is not None:
        raise _failed(out, deck.path)
    from deck_emulator.engine import errata

    settings = {"arithmetic": out.raw.arithmetic,
                "assumptions": dict(getattr(engine.arithmetic(), "assumptions", {}) or {}),
                "errata": errata.describe(out.errata)}
    if not settings["assumptions"]:
        settings.pop("assumptions")
    answer = outcome_answer(out, command="summary", source=str(deck.path), settings=settings)
    answer["notes"] += _odd_deck_notes(out) + list(out.flags)
    _emit(args, json.dumps(answer, indent=2) + "\n" if args.json else render_outcome(answer))
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
    _add_quiet_option(p)
    p.set_defaults(func=_cmd_summary)


# --------------------------------------------------------------------------- diff, core, scene


def _cmd_diff(args: argparse.Namespace) -> int:
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.studies.diff import DiffStopped, diff_deck, format_diff

    _refuse_scene(args.deck, "diff", why=" (it runs both engines, and the emulator runs "
                  "only decks)")
    deck = read_deck(args.deck)
    _check_out(args)
    if args.resume and not args.store:
        raise CLIError("--resume needs --store DIR (the folder the runs were stored in)")
    try:
        data = diff_deck(deck, precision=args.precision, errata=tuple(args.erratum),
                         ks=range(args.max_k + 1), rtol=args.rtol, atol=args.rtol,
                         tighten_ed=not args.as_printed_ed, jobs=args.jobs,
                         scheduler=args.scheduler, store_dir=args.store, resume=args.resume,
                         quiet=args.quiet, desc=f"{PROG}: diff")
    except DiffStopped as exc:
        raise RunFailed(str(exc)) from None
    _emit(args, json.dumps(data, indent=2) + "\n" if args.json else format_diff(data))
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
    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    p.add_argument("--precision", default="double", choices=PRECISIONS,
                   help="the emulator's arithmetic at k = 0 (must run the deck to its end)")
    _add_erratum_option(p)
    p.add_argument("--max-k", type=_nonnegative_int, default=4, metavar="K",
                   help="halve the step up to K times, K >= 0 (default 4)")
    p.add_argument("--rtol", type=_tolerance, default=1e-10,
                   help="the core's tolerance, rtol = atol, 0 < RTOL < 1 (default 1e-10)")
    p.add_argument("--as-printed-ed", action="store_true",
                   help="keep ED's tolerance .0001 at every k (the scheme then does not converge)")
    p.add_argument("--jobs", type=_positive_int, metavar="N",
                   help="worker processes of the embedded cluster (default: every core)")
    p.add_argument("--store", metavar="DIR",
                   help="keep the runs in DIR as they finish (default: a temporary folder)")
    _add_cluster_options(p)
    _add_answer_options(p)
    _add_quiet_option(p)
    p.set_defaults(func=_cmd_diff)


def _load_scene(path: str):
    from deck_emulator.core.scene import Scene, SceneError
    from deck_emulator.legacy.deck import read_deck

    try:
        if _is_scene(path):
            try:
                text = Path(path).read_text()
                _finite_numbers(text)
                return Scene.from_toml(text)
            except (ValueError, KeyError, TypeError) as exc:
                import re

                message = str(exc)
                missing = (re.findall(r"'(\w+)'", message)
                           if "required positional" in message else [])
                if missing:
                    message = "missing " + ", ".join(f"[{m}]" for m in missing)
                raise CLIError(f"{path}: not a scene: {message}") from None
            except OSError as exc:
                raise CLIError(f"{path}: cannot read: {exc.strerror or exc}") from None
        return Scene.from_deck(read_deck(path), name=Path(path).stem)
    except SceneError as exc:
        raise CLIError(f"{path}: {exc}") from None


def _finite_numbers(text: str) -> None:
    """A scene's numbers must be finite (TOML allows inf and nan): ValueError naming the key."""
    import math
    import tomllib

    def walk(node, where):
        if isinstance(node, dict):
            for k, v in node.items():
                walk(v, f"{where}.{k}" if where else k)
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, f"{where}[{i}]")
        elif isinstance(node, float) and not math.isfinite(node):
            raise ValueError(f"{where} = {node}: not a finite number")

    try:
        walk(tomllib.loads(text), "")
    except tomllib.TOMLDecodeError:
        return  # Scene.from_toml says what is wrong with the TOML itself


def _cmd_core(args: argparse.Namespace) -> int:
    from deck_emulator.engine import CoreEngine
    from deck_emulator.present.answers import outcome_answer, render_outcome

    scene = _load_scene(args.scene)  # a bad scene or deck: exit 2 before any work
    source = scene
    if not _is_scene(args.scene):
        from deck_emulator.legacy.deck import read_deck

        source = read_deck(args.scene)  # the deck's 64 values: the occupant risk, XL axes
    _check_out(args)
    engine = CoreEngine(preset=args.preset, method=args.method, rtol=args.rtol, atol=args.atol)
    out = _with_progress(args, engine, source)
    if out.error is not None:
        raise _failed(out, args.scene)
    used = out.raw.method
    settings = {"preset": args.preset,
                "method": f"{used} (auto)" if args.method == "auto" else used,
                "rtol": args.rtol, "atol": args.atol}
    answer = outcome_answer(out, command="core", source=args.scene, settings=settings)
    answer["notes"] += _odd_deck_notes(out) + list(getattr(out.raw, "notes", ()) or ())
    _emit(args, json.dumps(answer, indent=2) + "\n" if args.json else render_outcome(answer))
    return 0


@_subcommand
def _add_core(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("core", help="solve a deck or a scene (.toml) with the modern core",
                       description="The same model solved with quaternions, solve_ivp and located "
                       "events. Presets: legacy (the listing's quirks) or physical (none).")
    p.add_argument("scene", metavar="DECK_OR_TOML", help="a card deck or a scene file (.toml)")
    _add_preset_option(p)
    p.add_argument("--method", default="auto",
                   choices=("auto", "DOP853", "RK45", "Radau", "BDF", "LSODA"),
                   help="solve_ivp's method; auto (the default): DOP853, or Radau for the "
                   "contact when the scene's springs make it stiff (the outcome says which)")
    p.add_argument("--rtol", type=_tolerance, default=1e-10,
                   help="relative tolerance, 0 < RTOL < 1 (default 1e-10)")
    p.add_argument("--atol", type=_tolerance, default=1e-10,
                   help="absolute tolerance, 0 < ATOL < 1 (default 1e-10)")
    _add_answer_options(p)
    _add_quiet_option(p)
    p.set_defaults(func=_cmd_core)


def _cmd_scene(args: argparse.Namespace) -> int:
    scene = _load_scene(args.deck)
    _check_out(args)
    _emit(args, scene.to_toml())
    return 0


@_subcommand
def _add_scene(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("scene", help="write a deck's scene as TOML (to edit by hand, then `core`)")
    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    p.add_argument("--out", metavar="FILE", help="write to FILE instead of stdout")
    p.set_defaults(func=_cmd_scene)


# --------------------------------------------------------------------------- assembly


def _ms(t_s) -> str:
    return "no time" if t_s is None else f"{1000.0 * t_s:.1f} ms"


def _cmd_assembly(args: argparse.Namespace) -> int:
    """Build a support assembly (or the crash test) from a description file and print its
    mass properties, its deck, its scene, or run it."""
    import math as _m

    from deck_emulator.core import assembly as asm
    from deck_emulator.engine import assemblies as bridge

    if args.json and args.what != "core":
        raise CLIError(f"--json goes with 'core' (a run's outcome), not with '{args.what}'")

    try:
        a, extra, _ = asm.load_assembly(args.description)
    except (asm.AssemblyError, OSError) as exc:
        raise CLIError(str(exc)) from None
    if a is None:  # the crash test
        from deck_emulator.studies import crash_test as ct

        scene = ct.crash_scene()
        if args.what == "scene":
            _emit(args, scene.to_toml())
            return 0
        if args.what in ("deck", "emulator"):
            raise CLIError(f"cannot run on the listing: {asm.scene_runs_on_listing(scene)}")
        res, loss, r70 = ct.table10(scene)  # res: the run's Outcome
        rows = [f"{k}: at loss of contact {loss[k]:.4f}, at 70 ms {r70[k]:.4f}" for k in loss]
        _emit(args, f"hit: {res.hit_message} at {_ms(res.hit_time_s)}\n" + "\n".join(rows) + "\n")
        return 0
    template = (f"steel{args.speed_mph}" + ("" if args.alpha_deg == 0 else f"_a{args.alpha_deg}"))
    mp = asm.mass_properties(a)
    if args.what == "props":
        lines = [f"{a.name}: weight {mp.weight_lb:.2f} lb, W {mp.mass_slug:.5f} slug, wall "
                 f"{mp.wall_in:.4f} in, A {mp.A:.2f}, B {mp.B:.2f}, C {mp.C:.3f} slug ft^2, "
                 f"delta {mp.delta_rad:.5f} rad ({_m.degrees(mp.delta_rad):.3f} deg), mass centre "
                 f"{mp.cm_height_ft:.3f} ft above Q, {mp.cm_offset_ft:.3f} ft in YY from the axis"]
        lines += [f"  {k}: ({p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f}) ft" for k, p in mp.points.items()]
        _emit(args, "\n".join(lines) + "\n")
        return 0
    scene = bridge.to_scene(a, mp, template=template)
    if args.what == "scene":
        _emit(args, scene.to_toml())
        return 0
    reason = asm.scene_runs_on_listing(scene)
    if args.what in ("deck", "emulator") and reason is not None:
        raise CLIError(f"cannot run on the listing: {reason}")
    if args.what == "deck":
        _emit(args, bridge.to_deck_text(bridge.to_deck_values(a, mp, template=template)))
        return 0
    if args.what == "emulator":
        from deck_emulator.engine import EmulatorEngine
        from deck_emulator.legacy.deck import parse_deck

        deck = parse_deck(bridge.to_deck_text(bridge.to_deck_values(a, mp, template=template)))
        out = EmulatorEngine(errata=tuple(args.erratum), trace=False).run(deck)
        _emit(args, out.raw.text())
        if out.error:
            _say(f"error: {_stopped(out)}")
            return EXIT_RUN_FAILED
        return 0
    from deck_emulator.engine import CoreEngine
    from deck_emulator.present.answers import outcome_answer, render_outcome

    out = CoreEngine(preset=args.preset).run(scene, name=a.name)
    if out.error is not None:
        raise _failed(out, args.description)
    settings = {"preset": args.preset, "method": out.raw.method,
                "car": f"{args.speed_mph} mph at {args.alpha_deg} deg ({template}'s car)"}
    answer = outcome_answer(out, command="assembly", source=a.name, settings=settings)
    answer["notes"] += list(out.raw.notes)
    _emit(args, json.dumps(answer, indent=2) + "\n" if args.json else render_outcome(answer))
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
    p.add_argument("--speed-mph", type=int, choices=(20, 40), default=40,
                   help="the car's speed: one of the report's two (default 40)")
    p.add_argument("--alpha-deg", type=int, choices=(0, 15, 30), default=0,
                   help="the approach angle: one of the report's three (default 0)")
    _add_erratum_option(p)
    _add_preset_option(p)
    p.add_argument("--json", action="store_true",
                   help="with core: the outcome as one JSON object (as deck-emulator core --json)")
    p.add_argument("--out", metavar="FILE", help="write to FILE instead of stdout")
    p.set_defaults(func=_cmd_assembly)


# --------------------------------------------------------------------------- plot, sweep, study


# --------------------------------------------------------------------------- plot


def _cmd_plot(args: argparse.Namespace) -> int:
    from deck_emulator.parallel import busy
    from deck_emulator.present.plot import _cmd_plot as plot, check_plot_outputs

    check_plot_outputs(args.out, args.animate)
    args.source = None
    if args.engine != "core" or args.pulse:
        _refuse_scene(args.deck, "plot" + (" --pulse" if args.pulse else ""),
                      why=" (the emulator draws only decks; --engine core draws a scene)")
    elif _is_scene(args.deck):
        args.source = _load_scene(args.deck)
    with busy(f"{PROG}: plot", quiet=args.quiet):
        return plot(args)


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
    p.add_argument("deck", metavar="DECK_OR_SCENE",
                   help="deck file, e.g. decks/steel40.dat; a scene file with --engine core")
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
    if args.base_deck:
        _refuse_scene(args.base_deck, "sweep --base-deck")
    base = Path(args.base_deck) if args.base_deck else POSTS[args.post]
    base_deck = read_deck(base)  # bad deck -> DeckError, before any work
    for s in speeds:  # every VVB/ALPHA must punch: fail before running anything
        for a in angles:
            scene_deck(base_deck, s, a, args.vvb_decimals)
    check_output_dir(args.out)
    options = (dict(errata=tuple(args.erratum)) if args.engine == "emulator"
               else dict(preset=args.preset))
    store = output_store(args.out, args.resume)  # a new sweep: the scenes of the last one go
    started = time.perf_counter()
    rows = sweep(speeds, angles, engine=args.engine, options=options, post=args.post,
                 base=base, jobs=args.jobs, vvb_decimals=args.vvb_decimals, quiet=args.quiet,
                 store_dir=store, scheduler=args.scheduler, resume=args.resume)
    wall = time.perf_counter() - started
    command = "deck-emulator sweep " + " ".join(sys.argv[2:]) if sys.argv[1:2] == ["sweep"] else ""
    with OutputSet(directory=args.out) as outputs:
        outputs.write("sweep.csv", write_csv(rows))
        outputs.write("sweep.md", render_markdown(rows, command=command, engine=args.engine))
    failed = sum(bool(r["error"]) for r in rows)
    _say(f"{len(rows)} scenes ({args.engine}) in {wall:.1f} s on "
         f"{args.jobs or os.cpu_count()} job(s); {failed} stopped early; wrote "
         f"{Path(args.out) / 'sweep.csv'} and {Path(args.out) / 'sweep.md'}")
    return 0


@_subcommand
def _add_sweep(sub: argparse._SubParsersAction) -> None:
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
    p.add_argument("--base-deck", metavar="DECK", help="another base deck instead of --post's")
    p.add_argument("--speeds", required=True, metavar="MPH,...",
                   help="vehicle speeds in mph: 20,40 or 10:60:10 (stop included)")
    p.add_argument("--angles", required=True, metavar="DEG,...",
                   help="approach angles in degrees: 0,15,30 or 0:45:5")
    p.add_argument("--engine", choices=("emulator", "core"), default="emulator",
                   help="which engine runs the scenes (default emulator)")
    _add_erratum_option(p)
    _add_preset_option(p)
    p.add_argument("--jobs", type=_positive_int, metavar="N",
                   help="worker processes (default: all cores, %d here)" % (os.cpu_count() or 1))
    p.add_argument("--vvb-decimals", type=int, default=2, metavar="N",
                   help="decimals VVB is cut to (default 2, as the report's deck: -58.66)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    _add_cluster_options(p)
    p.add_argument("--out", required=True, metavar="DIR",
                   help="directory for sweep.csv and sweep.md (and the scene store, "
                   f"DIR/{SCENE_STORE}, kept for --resume)")
    p.set_defaults(func=_cmd_sweep)


# --------------------------------------------------------------------------- sensitivity


@_subcommand
def _add_sensitivity(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "sensitivity",
        help="Sobol indices of the outcome over the report's uncertain inputs",
        description="Sample the inputs the report takes as estimates (base friction and its "
        "travel, CK, CT, FCONST, WV; and any --input NAME=LO:HI), run every sample on one "
        "engine on a Dask cluster, and write DIR/sensitivity.csv and .md (Sobol S1 and ST with "
        "95%% confidence, for N and N/2), a bar chart of the indices and a map of what the post "
        "hits first over the two most influential inputs. Scenes are stored as they finish in "
        "DIR/scenes/; --resume runs only the missing ones.",
    )
    p.add_argument("--deck", action="append", metavar="DECK",
                   help="shipped deck name or path; repeat for several (default steel40)")
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
    p.add_argument("--jobs", type=_positive_int, metavar="N",
                   help="workers of the embedded cluster (default: all cores)")
    _add_cluster_options(p)
    p.add_argument("--out", required=True, metavar="DIR", help="directory for the results")

    def run(args):
        from deck_emulator.studies.sensitivity import run_command

        return run_command(args)

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
        from deck_emulator.legacy.deck import read_deck
        from deck_emulator.studies.study_cli import _cmd_study

        if getattr(args, "deck", None):
            _refuse_scene(args.deck, f"study {args.study}")
            read_deck(args.deck)
        check_output_dir(args.out)  # before any work, and before the study makes the folder
        return _cmd_study(args)

    def common(q):
        q.add_argument("--out", required=True, metavar="DIR", help="directory for the outputs")
        q.add_argument("--quick", action="store_true",
                       help="a small grid (seconds, for tests) instead of the full study")
        q.add_argument("--jobs", type=_positive_int, default=None, metavar="N",
                       help="worker processes (default: os.cpu_count())")
        _add_cluster_options(q)
        _add_quiet_option(q)
        q.set_defaults(func=run)

    e = studies.add_parser(
        "error", help="error against run time: the emulator at H = 0.0004/2**k, the core at "
        "rtol 1e-3 ... 1e-11, against a 1e-12 reference",
        description="Work-precision study on DECK: the emulator in double precision at H = "
        "0.0004/2**k (k = 0..6; the listing's ED tolerance and a tightened one), in the IBM 7094 "
        "arithmetic at k = 0, and the core with DOP853, RK45 and Radau at rtol 1e-3 ... 1e-11, "
        "all against the core at rtol 1e-12 (itself checked with Radau and LSODA at 1e-13).")
    e.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    common(e)
    s = studies.add_parser(
        "stability", help="stiff springs against H, and extreme scenes, for the emulator and "
        "the core",
        description="Stability study: a grid of scenes derived from steel40 (CK = CT from "
        "3.3e4 to 1e10 lb/ft against H; speeds 5-120 mph; approach angles to 90 deg; delta = 0; "
        "the start-up THA; A = B = C; light and heavy posts; base friction; THB near 90 deg), "
        "each run by the emulator and the core, with how it ended.")
    s.add_argument("--deck", metavar="DECK", default=None,
                   help="base deck (default: the report's deck steel40, shipped with the package)")
    common(s)




# --------------------------------------------------------------------------- main


class _Parser(argparse.ArgumentParser):
    """argparse's parser, but a usage error is one line (and exit status 2)."""

    def error(self, message: str):
        self.exit(EXIT_BAD_INPUT, f"{PROG}: error: {message} (see {self.prog} --help)\n")


class _Version(argparse.Action):
    """``--version``: the installed package's metadata, read only when asked."""

    def __call__(self, parser, namespace, values, option_string=None):
        import deck_emulator

        print(f"{parser.prog} {deck_emulator.__version__}")
        parser.exit(0)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog=PROG,
        description="Emulator of the 1967 TTI luminaire-support impact program (Report 75-9).",
    )
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="print the installed version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for add in _SUBCOMMANDS:
        add(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """The command line; SIGINT and SIGTERM end it with 130 and 143 after every temporary
    file is removed and every worker stopped (:mod:`deck_emulator.signals`)."""
    from deck_emulator import signals

    return signals.run(_main, argv)


def _main(argv: Sequence[str] | None = None) -> int:
    from deck_emulator.legacy.deck import DeckError

    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (2) and --help (0)
        return exc.code if isinstance(exc.code, int) else 2
    try:
        with warnings.catch_warnings():  # numpy's divide-by-zero and the like: the notes say why
            warnings.simplefilter("ignore", RuntimeWarning)
            return args.func(args)
    except (DeckError, UsageError, OSError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_RUN_FAILED if isinstance(exc, RunFailed) else EXIT_BAD_INPUT


if __name__ == "__main__":
    raise SystemExit(main())
