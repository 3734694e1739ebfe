"""Command line: ``deck-emulator COMMAND ...``.

Each subcommand is a function ``_cmd_<name>(args) -> int`` plus a small function that
adds its subparser, registered with ``@_subcommand``.  A command reports bad input by
raising :class:`~deck_emulator.legacy.deck.DeckError` (or another ``CLIError``); ``main`` turns
that into ``deck-emulator: error: <message>`` on stderr and exit status 2.  A command
builds its whole output before writing it, so an error leaves stdout empty.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from deck_emulator.legacy.arithmetic import ARITHMETICS, get_arithmetic
from deck_emulator.files import write_atomic
from deck_emulator.legacy.deck import READ_LIST, DeckError, field_columns, read_deck
from deck_emulator.legacy.emulator import ERRATA, EmulatorError, Limits, Program
from deck_emulator.legacy.extract import extract
from deck_emulator.legacy.printer import render_asa
from deck_emulator.legacy.cardcli import (add_card_options, add_pages_options, add_punch_parser,
                                          load_job, load_one_deck, write_pages)

PROG = "deck-emulator"
EXIT_BAD_INPUT = 2


class CLIError(Exception):
    """A user-facing error that is not about a deck's contents."""


class RunFailed(CLIError):
    """The program (emulated or core) could not run to its end: exit status 3."""


# Functions that add one subcommand's parser; main() calls each of them in order.
_SUBCOMMANDS: list[Callable[[argparse._SubParsersAction], None]] = []


def _subcommand(add: Callable[[argparse._SubParsersAction], None]):
    _SUBCOMMANDS.append(add)
    return add


# --------------------------------------------------------------------------- parse


def _cmd_parse(args: argparse.Namespace) -> int:
    deck = load_one_deck(args)
    if args.json:
        text = json.dumps(deck.values) + "\n"
    else:
        text = _deck_table(deck)
    sys.stdout.write(text)
    return 0


def _deck_table(deck) -> str:
    lines = [f"{deck.path}: 8 cards, FORMAT(8F10.5)"]
    for card_no, names in enumerate(READ_LIST, start=1):
        lines.append("")
        lines.append(f"card {card_no}   columns  name       value")
        for field_no, name in enumerate(names, start=1):
            first, last = field_columns(field_no)
            lines.append(f"         {first:2d}-{last:<2d}    {name:<8s} {deck[name]!r:>12s}")
    return "\n".join(lines) + "\n"


@_subcommand
def _add_parse(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "parse",
        help="read a card deck and print its 64 values",
        description="Read a $DATA card deck (8 cards, FORMAT(8F10.5)) with the 1967 input "
        "rules and print the values under their READ-list names.",
    )
    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    add_card_options(p)
    p.add_argument(
        "--json", action="store_true", help="print one JSON object, name -> value, in READ order"
    )
    p.set_defaults(func=_cmd_parse)


# --------------------------------------------------------------------------- run


EXIT_RUN_FAILED = 3


def _emit(args, text: str) -> None:
    if getattr(args, "out", None):
        write_atomic(args.out, text)
    else:
        sys.stdout.write(text)


def _arithmetic(args):
    options = {}
    if args.precision == "ibm7094":
        options = dict(sincos=args.sincos, decimal=args.decimal, output=args.output_rounding)
    elif any(x is not None for x in (args.sincos, args.decimal, args.output_rounding)):
        raise CLIError("--sincos, --decimal and --output-rounding are assumptions of --precision ibm7094")
    return get_arithmetic(args.precision, **{k: v for k, v in options.items() if v is not None})


def _run_emulator(args, deck):
    limits = Limits(ed_iterations=args.max_ed_iterations, halvings=args.max_halvings,
                    time_s=args.max_time)
    return Program(deck, _arithmetic(args), errata=tuple(args.erratum), step_scale_k=args.step_scale,
                   tha_start=args.tha_start, ed_tolerance=args.ed_tolerance, limits=limits).run()


def _describe(run) -> str:
    errata = ", ".join(run.errata) or "none (the listing as printed)"
    scale = f"; step literals / 2**{run.step_scale_k}" if run.step_scale_k else ""
    return f"arithmetic {run.arithmetic}; errata: {errata}{scale}"


def _cmd_run(args: argparse.Namespace) -> int:
    records, text, error = [], "", None
    for deck in load_job(args).decks:  # a job deck's $DATA sections, in turn
        try:
            run = _run_emulator(args, deck)
        except EmulatorError as exc:
            run, error = exc.run, exc
        records += run.records
        text += render_asa(run.records) if args.render else run.text()
        print(f"{PROG}: {deck.path}: {_describe(run)}", file=sys.stderr)
        if error is not None:
            break
    _emit(args, text)
    write_pages(args, records)
    if error is not None:
        print(f"{PROG}: error: {error}", file=sys.stderr)
        return EXIT_RUN_FAILED
    return 0


def _add_emulator_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("deck", metavar="DECK", help="deck file, e.g. decks/steel40.dat")
    add_card_options(p)
    p.add_argument("--precision", choices=ARITHMETICS, default="double",
                   help="arithmetic: double (IEEE binary64, as the r8 goldens), single (IEEE "
                   "binary32, as the r4 goldens, trapping), ibm7094 (the 1967 machine's 36-bit words)")
    p.add_argument("--erratum", action="append", default=[], choices=sorted(ERRATA),
                   help="apply a named erratum to the listing (default: none, as printed)")
    p.add_argument("--step-scale", type=int, default=0, metavar="K",
                   help="divide every literal that means one step (0.0004 s) by 2**K")
    p.add_argument("--tha-start", metavar="VALUE",
                   help="start-up THA at label 123 instead of the printed 0.000022")
    p.add_argument("--ed-tolerance", metavar="RAD", default=".0001",
                   help="ED's |DF| tolerance at labels 15 and 16 (printed: .0001)")
    p.add_argument("--max-time", type=float, default=Limits.time_s, metavar="S",
                   help="stop when simulated time passes S seconds (default %(default)s)")
    p.add_argument("--max-ed-iterations", type=int, default=Limits.ed_iterations, metavar="N",
                   help="stop when one call of ED iterates N times (default %(default)s)")
    p.add_argument("--max-halvings", type=int, default=Limits.halvings, metavar="N",
                   help="stop after N consecutive step halvings at label 108 (default %(default)s)")
    p.add_argument("--sincos", choices=("chop", "round"), help="ibm7094: how SIN/COS were rounded")
    p.add_argument("--decimal", choices=("chop", "round"),
                   help="ibm7094: how decimal constants and deck fields were converted")
    p.add_argument("--output-rounding", choices=("nearest", "truncate"),
                   help="ibm7094: how F-format output rounded")


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
    add_pages_options(p)
    p.add_argument("--render", action="store_true",
                   help="render ASA carriage control (1 = form feed, 0 = blank line, + = "
                   "overprint) as the POSIX asa utility does, instead of the raw records")
    p.set_defaults(func=_cmd_run)


# --------------------------------------------------------------------------- summary


def _cmd_summary(args: argparse.Namespace) -> int:
    deck = load_one_deck(args)
    try:
        run = _run_emulator(args, deck)
    except EmulatorError as exc:
        raise RunFailed(f"{exc}{_hint(exc)}") from None
    outcome = extract(run.records, deck)
    data = {"deck": str(deck.path), "arithmetic": run.arithmetic, "errata": list(run.errata),
            "assumptions": dict(getattr(_arithmetic(args), "assumptions", {}) or {}),
            **outcome.summary_dict()}
    from deck_emulator.studies.sweep import emulator_result, safety_summary

    data["safety"] = safety_summary(emulator_result(run, deck))
    if args.json:
        _emit(args, json.dumps(data, indent=2) + "\n")
    else:
        lines = [f"{k}: {v}" for k, v in data.items()]
        _emit(args, "\n".join(lines) + "\n")
    return 0


def _hint(exc: EmulatorError) -> str:
    if exc.guard == "ed_iterations":
        return " -- as printed, ED walks away from its root on this deck; try --erratum ed-direction"
    return ""


@_subcommand
def _add_summary(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "summary",
        help="run a deck and print its outcomes (events, hit, delta-V, deceleration, P/Q/R)",
        description="Run the emulated program and extract from its printout what the report's "
        "Tables 11 and 12 give: events with times, the hit message, the vehicle's speed change "
        "in mph, the largest printed deceleration in g, terminal P, Q, R in XL, YL, ZL.",
    )
    _add_emulator_options(p)
    p.add_argument("--json", action="store_true", help="one JSON object")
    p.add_argument("--out", metavar="FILE", help="write to FILE instead of stdout")
    p.set_defaults(func=_cmd_summary)


# --------------------------------------------------------------------------- diff, core, scene


def _cmd_diff(args: argparse.Namespace) -> int:
    from deck_emulator.studies.diff import diff_deck, format_diff

    deck = read_deck(args.deck)
    progress = (lambda m: print(f"{PROG}: {m}", file=sys.stderr)) if sys.stderr.isatty() else None
    try:
        data = diff_deck(deck, precision=args.precision, errata=tuple(args.erratum),
                         ks=range(args.max_k + 1), rtol=args.rtol, atol=args.rtol,
                         tighten_ed=not args.as_printed_ed, progress=progress)
    except EmulatorError as exc:
        raise RunFailed(f"{exc}{_hint(exc)}") from None
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
    p.add_argument("deck", metavar="DECK")
    p.add_argument("--precision", default="double", choices=ARITHMETICS,
                   help="the emulator's arithmetic at k = 0 (must run the deck to its end)")
    p.add_argument("--erratum", action="append", default=[], choices=sorted(ERRATA))
    p.add_argument("--max-k", type=int, default=4, help="halve the step up to K times (default 4)")
    p.add_argument("--rtol", type=float, default=1e-10, help="core tolerance (rtol = atol)")
    p.add_argument("--as-printed-ed", action="store_true",
                   help="keep ED's tolerance .0001 at every k (the scheme then does not converge)")
    p.add_argument("--json", action="store_true", help="one JSON object")
    p.add_argument("--out", metavar="FILE")
    p.set_defaults(func=_cmd_diff)


def _load_scene(path: str):
    from deck_emulator.core.scene import Scene

    if path.endswith(".toml"):
        try:
            return Scene.from_toml(Path(path).read_text())
        except (ValueError, KeyError, TypeError) as exc:
            raise CLIError(f"{path}: not a scene: {exc}") from None
    return Scene.from_deck(read_deck(path), name=Path(path).stem)


def _cmd_core(args: argparse.Namespace) -> int:
    from deck_emulator.core import PRESETS, CoreError, simulate

    scene = _load_scene(args.scene)
    try:
        result = simulate(scene, PRESETS[args.preset], method=args.method, rtol=args.rtol,
                          atol=args.atol)
    except CoreError as exc:
        raise RunFailed(str(exc)) from None
    data = result.summary()
    text = json.dumps(data, indent=2) + "\n" if args.json else "".join(
        f"{k}: {v}\n" for k, v in data.items() if k != "events") + "".join(
        f"  {e['time_s']:.9f} s  {e['name']}  {e['message']}\n" for e in data["events"])
    _emit(args, text)
    return 0


@_subcommand
def _add_core(sub: argparse._SubParsersAction) -> None:
    from deck_emulator.core import PRESETS

    p = sub.add_parser("core", help="solve a deck or a scene (.toml) with the modern core",
                       description="The same model solved with quaternions, solve_ivp and located "
                       "events. Presets: legacy (the listing's quirks) or physical (none).")
    p.add_argument("scene", metavar="DECK_OR_TOML")
    p.add_argument("--preset", choices=sorted(PRESETS), default="legacy")
    p.add_argument("--method", default="DOP853", choices=("DOP853", "RK45", "Radau", "LSODA"))
    p.add_argument("--rtol", type=float, default=1e-10)
    p.add_argument("--atol", type=float, default=1e-10)
    p.add_argument("--json", action="store_true")
    p.add_argument("--out", metavar="FILE")
    p.set_defaults(func=_cmd_core)


def _cmd_scene(args: argparse.Namespace) -> int:
    _emit(args, _load_scene(args.deck).to_toml())
    return 0


@_subcommand
def _add_scene(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("scene", help="write a deck's scene as TOML (to edit by hand, then `core`)")
    p.add_argument("deck", metavar="DECK")
    p.add_argument("--out", metavar="FILE")
    p.set_defaults(func=_cmd_scene)


# --------------------------------------------------------------------------- plot, sweep, study


@_subcommand
def _add_plot(sub: argparse._SubParsersAction) -> None:
    from deck_emulator.present.plot import add_parser

    add_parser(sub)


@_subcommand
def _add_sweep(sub: argparse._SubParsersAction) -> None:
    from deck_emulator.studies.sweep import add_parser

    add_parser(sub)


@_subcommand
def _add_study(sub: argparse._SubParsersAction) -> None:
    from deck_emulator.studies.study_cli import add_parser

    add_parser(sub)


_subcommand(add_punch_parser)


# --------------------------------------------------------------------------- main


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Emulator of the 1967 TTI luminaire-support impact program (Report 75-9).",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for add in _SUBCOMMANDS:
        add(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (2) and --help (0)
        return exc.code if isinstance(exc.code, int) else 2
    try:
        return args.func(args)
    except (DeckError, CLIError, OSError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_RUN_FAILED if isinstance(exc, RunFailed) else EXIT_BAD_INPUT


if __name__ == "__main__":
    raise SystemExit(main())
