"""Command line: ``deck-emulator COMMAND ...`` -- the parsing, and nothing else.

Every parser is built from the application layer's table (:data:`deck_emulator.app.NAMES`,
:func:`deck_emulator.app.command_named`: a command's options dataclass, one field an option,
its help and spelling in the field's metadata); the parsed options become that dataclass, the
command's function answers (:class:`deck_emulator.app.Answer`), and this module writes the
answer to stdout (or ``--out``), what it says to stderr, and maps its status to the exit
status (:data:`deck_emulator.app.EXIT`).

Standard output and error are written here and only here (:func:`_streams`): a stream the
process was started without (``>&-``) is a sink, so that a command's answer is refused before
any work when it had to go to a closed standard output, and a refusal with standard error
closed still ends with its status; a stream whose encoding cannot spell a character (a bare
``C`` locale, ``PYTHONIOENCODING=ascii``) writes the character's ASCII spelling
(:data:`ASCII_SPELLINGS`) instead of failing.
"""

from __future__ import annotations

import argparse
import atexit
import codecs
import os
import re
import shlex
import sys
import warnings
from collections.abc import Sequence
from dataclasses import MISSING, fields

import deck_emulator
from deck_emulator import signals
from deck_emulator.app import EXIT, NAMES, PROG, command_named
from deck_emulator.app.options import PATH_OPTIONS
from deck_emulator.errors import (RunFailed, UsageError, address_space_mb, out_of_memory,
                                   process_limits)

EXIT_BAD_INPUT, EXIT_RUN_FAILED = EXIT["bad input"], EXIT["stopped"]  # the answers' table


#: what stdout and stderr write for a character their encoding has not got (one row a
#: character; any other is written as "?")
ASCII_SPELLINGS = {
    "·": "*", "²": "^2", "¹": "^1", "°": " deg", "±": "+/-", "—": "--", "–": "-", "−": "-",
    "α": "alpha", "Δ": "delta-", "é": "e", "×": "x", "≤": "<=", "≥": ">=", "’": "'",
    "…": "...", "→": "->", "δ": "delta", "ζ": "zeta", "η": "eta", "θ": "theta", "ξ": "xi",
    "φ": "phi", "χ": "chi", "ψ": "psi", "\u0307": "_dot",  # a dot above: a rate (psi_dot)
}
_SPELLING_ERRORS = "deck_emulator.ascii"


def _spell(exc: UnicodeError):
    """The codec error handler of :data:`ASCII_SPELLINGS`."""
    if not isinstance(exc, UnicodeEncodeError):
        raise exc
    text = exc.object[exc.start:exc.end]
    return "".join(ASCII_SPELLINGS.get(ch, "?") for ch in text), exc.end


class _Closed:
    """A standard stream the process was started without (its descriptor closed): what is
    written to it goes nowhere."""

    closed_stream = True
    encoding = "utf-8"

    def write(self, data):
        return len(data)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False

    @property
    def buffer(self):
        return self


def _streams() -> list[tuple[str, object]]:
    """Make stdout and stderr safe to write (the module docstring); the replaced, to restore."""

    try:
        codecs.lookup_error(_SPELLING_ERRORS)
    except LookupError:
        codecs.register_error(_SPELLING_ERRORS, _spell)
    replaced = []
    for name in ("stdout", "stderr"):
        stream = getattr(sys, name)
        if stream is None:
            replaced.append((name, stream))
            setattr(sys, name, _Closed())
            continue
        encoding = (getattr(stream, "encoding", None) or "utf-8").lower().replace("_", "-")
        if encoding not in ("utf-8", "utf8") and hasattr(stream, "reconfigure"):
            try:
                stream.reconfigure(errors=_SPELLING_ERRORS)
            except (ValueError, OSError, AttributeError):
                pass
    return replaced


def _closed(stream) -> bool:
    return getattr(stream, "closed_stream", False)


def _say(message: str) -> None:
    print(f"{PROG}: {message}", file=sys.stderr)


def _argument_type(parse):
    """An option's converter (``ValueError`` for bad text) as argparse's type."""
    def convert(text: str):
        try:
            return parse(text)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    convert.__name__ = parse.__name__
    return convert


def _add_option(p: argparse.ArgumentParser, f) -> None:
    """One field of an options dataclass as the argument its metadata describes."""
    m = f.metadata
    if not m.get("cli", True):
        return
    kw: dict = {"help": m["help"]}
    for key in ("choices", "metavar"):
        if m.get(key) is not None:
            kw[key] = m[key]
    if m.get("parse") is not None:
        kw["type"] = _argument_type(m["parse"])
    has_default = f.default is not MISSING or f.default_factory is not MISSING
    if m["positional"]:
        if has_default:
            kw.update(nargs="?", default=f.default)
        p.add_argument(f.name, **kw)
        return
    flag = m.get("flag") or "--" + f.name.replace("_", "-")
    if m["many"]:
        kw.update(action="append", default=[])
    elif m["negatable"]:
        kw.update(action=argparse.BooleanOptionalAction, default=None)
    elif f.type in ("bool", bool):
        kw.update(action="store_true")
    elif has_default:
        kw["default"] = f.default
    if m["required"] or not has_default:
        kw["required"] = True
    p.add_argument(flag, dest=f.name, **kw)


class _Parser(argparse.ArgumentParser):
    """argparse's parser, but a usage error is one line (and exit status 2), and a negative
    number (``--tha-start -1e-5``) is a value, not an option: argparse takes ``-1`` and ``-.5``
    after an option as its value but reads ``-1e-5`` and ``-1.`` as options, so a negative
    number is joined to the option before it (``--tha-start=-1e-5``, argparse's own spelling of
    a value that starts with a dash) when that option takes a value."""

    def __init__(self, *args, **kwargs):
        self.value_options: dict[str, bool] = {}  # an option string -> it takes one value
        kwargs.setdefault("formatter_class", _help_formatter)
        super().__init__(*args, **kwargs)

    def add_argument(self, *args, **kwargs):
        action = super().add_argument(*args, **kwargs)
        for flag in action.option_strings:
            self.value_options[flag] = action.nargs is None
        return action

    def parse_known_args(self, args=None, namespace=None):
        joined: list[str] = []
        for text in sys.argv[1:] if args is None else args:
            if (joined and _NEGATIVE_NUMBER.fullmatch(text) and "--" not in joined
                    and self._takes_a_value(joined[-1])):
                joined[-1] += "=" + text
            else:
                joined.append(text)
        return super().parse_known_args(joined, namespace)

    def _takes_a_value(self, flag: str) -> bool:
        """``flag`` is an option of this parser that takes a value, or a long option's
        abbreviation that names one such option only (argparse takes unique abbreviations)."""
        if flag in self.value_options:
            return self.value_options[flag]
        named = [f for f in self.value_options if flag.startswith("--") and f.startswith(flag)]
        return len(named) == 1 and self.value_options[named[0]]

    def error(self, message: str):
        self.exit(EXIT_BAD_INPUT, f"{PROG}: error: {message} (see {self.prog} --help)\n")


#: a negative number (argparse reads -1e-5 and -1. as options; -1 and -.5 as values)
_NEGATIVE_NUMBER = re.compile(r"-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def _help_formatter(prog: str) -> argparse.HelpFormatter:
    """argparse's help formatter at the terminal's width, found as shutil.get_terminal_size
    finds it (COLUMNS, else the terminal of stdout, else 80 columns) but without importing
    shutil, and with it zlib, bz2 and lzma, at a plain run's start."""
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
        print(f"{parser.prog} {deck_emulator.__version__}")
        parser.exit(0)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The whole command line's parser, built from the application layer's table; with
    ``command`` (a first word), one that holds only that command's parsers (a command line
    starting with it parses alike, and the other commands' help costs nothing)."""

    parser = _Parser(prog=PROG, description="Emulator of the 1967 TTI luminaire-support impact "
                     "program (Report 75-9).")
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="print the installed version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    groups: dict[str, argparse.Action] = {}  # a first word -> its subcommands' action
    for name in NAMES:
        first, *rest = name.split()
        if command is not None and first != command:
            continue
        cmd = command_named(name)
        target = sub
        if rest:  # a command of two words (study error): the first word's own subcommands
            if first not in groups:
                group = sub.add_parser(first, help=f"{first} commands: "
                                       + ", ".join(n.split()[1] for n in NAMES
                                                   if n.startswith(first + " ")))
                groups[first] = group.add_subparsers(dest="which", metavar=first.upper(),
                                                     required=True)
            target = groups[first]
        description = cmd.description() if callable(cmd.description) else cmd.description
        p = target.add_parser(rest[0] if rest else first, help=cmd.help,
                              description=description or None)
        for f in fields(cmd.options):
            _add_option(p, f)
        p.set_defaults(_command=name, func=_run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """The command line; SIGINT and SIGTERM end it with 130 and 143 after every temporary
    file is removed and every worker stopped (:mod:`deck_emulator.signals`)."""
    if "OPENBLAS_NUM_THREADS" not in os.environ and " MB " in " ".join(process_limits()):
        os.environ["OPENBLAS_NUM_THREADS"] = "1"  # its threads' buffers spun under ulimit -v
    replaced = _streams()
    try:
        return signals.run(_main, argv)
    finally:
        for name, stream in replaced:
            setattr(sys, name, stream)


def _at_last_exit() -> None:
    """At the process's exit, after multiprocessing's own exit handler (registered when it is
    first imported, after this, so run before it): the command's own temporary folder removed
    (files.own_temp_folder)."""
    files = sys.modules.get("deck_emulator.files")
    if files is not None:
        files.remove_own_temp_folder()


atexit.register(_at_last_exit)  # (when the command line is imported: before multiprocessing)


def _main(argv: Sequence[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(argv[0] if argv and argv[0] in {n.split()[0] for n in NAMES}
                          else None)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (2) and --help (0)
        return exc.code if isinstance(exc.code, int) else 2
    return args.func(args, argv)


def _run(args: argparse.Namespace, argv: Sequence[str] = ()) -> int:
    """The parsed command line as its command's options; the command's answer written."""
    from deck_emulator.legacy.deck import DeckError

    cmd = command_named(args._command)
    if cmd.core:  # this process is the package's own: numba's cache is the core's
        from deck_emulator.core import configure_numba_cache

        configure_numba_cache()
    if cmd.one_scene and "OPENBLAS_NUM_THREADS" not in os.environ and "numpy" not in sys.modules:
        # (OpenBLAS's documented setting, read as numpy loads it) one scene shares no linear
        # algebra out: its thread pool's start would be CPU spent for nothing
        os.environ["OPENBLAS_NUM_THREADS"] = "1"
    given = {f.name: getattr(args, f.name) for f in fields(cmd.options)
             if f.metadata.get("cli", True)}
    for name in PATH_OPTIONS:  # '--out ""' would name the current folder or stdout
        value = given.get(name)
        if value == "" or (isinstance(value, str) and "\0" in value):
            why = "an empty path names no file" if value == "" else "a path holds no NUL byte"
            _say(f"error: --{name}: {why}")
            return EXIT_BAD_INPUT
    if given.get("worker_wait") is not None and not given.get("scheduler"):
        _say("error: --worker-wait: only with --scheduler (the embedded runner's workers start "
             "with it)")
        return EXIT_BAD_INPUT
    if _closed(sys.stdout) and given.get("out") is None:  # (a folder --out: the files hold it)
        _say("error: standard output is closed, and the answer goes there: "
             + ("give --out FILE, or open it" if "out" in given else "open it"))
        return EXIT_BAD_INPUT
    if given.get("pages") and address_space_mb() is not None and not _linear_algebra_starts():
        _say(f"error: {cmd.name}: --pages: numpy's linear algebra library could not take its "
             f"memory: {out_of_memory()}")
        return EXIT_BAD_INPUT
    given = {k: tuple(v) if isinstance(v, list) else v for k, v in given.items()}
    options = cmd.options(**given, command_line=shlex.join([PROG, *argv]) if argv else "")
    try:
        with warnings.catch_warnings():  # numpy's divide-by-zero and the like: the notes say why
            warnings.simplefilter("ignore", RuntimeWarning)
            answer = cmd.run(options)
        return _write(answer)
    except (DeckError, UsageError, OSError) as exc:  # (a library that cannot load: OSError)
        _say(f"error: {(_could_not_load(exc) and out_of_memory(exc)) or exc}")
        return EXIT_RUN_FAILED if isinstance(exc, RunFailed) else EXIT_BAD_INPUT
    except ImportError as exc:  # an optional part of the install is missing: which to add
        from deck_emulator.extras import missing_extra

        message = missing_extra(exc) or out_of_memory(exc)
        if message is None:
            raise
        _say(f"error: {cmd.name}: {message}")
        return EXIT_BAD_INPUT
    except MemoryError:  # an address-space limit (ulimit -v) the work or a library hit
        _say(f"error: {cmd.name}: {out_of_memory()}")
        return EXIT_BAD_INPUT


def _linear_algebra_starts() -> bool:
    """Whether numpy and its BLAS can start under this process's address-space limit, asked
    before any output is begun: OpenBLAS that cannot take its buffers ends the process with
    exit(1), past every handler (a ``.part`` file left, its own message).  Tried first in a
    forked child; when it starts there, it is started here too (its buffers taken now, so
    that what runs out later is Python's memory: a MemoryError, said in one line)."""
    def start():
        import numpy

        a = numpy.ones((4, 4))
        return a @ a

    pid = os.fork()
    if pid == 0:  # (the child: only this, then out, with no cleanup of the parent's)
        code = 1
        try:
            quiet = os.open(os.devnull, os.O_WRONLY)  # (OpenBLAS's own message: not said)
            os.dup2(quiet, 1)
            os.dup2(quiet, 2)
            start()
            code = 0
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        return False
    try:
        start()
    except (ImportError, MemoryError):
        return False
    return True


def _could_not_load(exc: BaseException) -> bool:
    """Whether an OSError is memory that could not be had or a library that could not load
    (ENOMEM; no errno: the dynamic loader's "failed to map segment"), which a memory limit
    may explain; not an input or output error (a full disk, a closed pipe, a missing file)."""
    import errno

    from deck_emulator.files import OutputError

    return (isinstance(exc, OSError) and not isinstance(exc, OutputError)
            and exc.errno in (None, errno.ENOMEM))


def _write(answer) -> int:
    """The answer to stdout (or its ``out`` file), what it says to stderr, its exit status."""
    for line in answer.said:
        _say(line)
    printed = answer.printed()
    if printed is not None:
        if answer.out:
            from deck_emulator.files import write_file

            write_file(answer.out, printed)
        elif _closed(sys.stdout):
            _say(f"standard output is closed: the text for it was not written (the files in "
                 f"{answer.out or 'the --out folder'} were)")
        else:
            try:
                if isinstance(printed, bytes):
                    sys.stdout.buffer.write(printed)
                else:
                    sys.stdout.write(printed)
                sys.stdout.flush()
            except OSError as exc:  # (a full disk, a closed pipe: said as what it is)
                from deck_emulator.files import OutputError

                raise OutputError("standard output", exc.strerror or str(exc),
                                  exc.errno) from None
    if answer.error:
        _say(f"error: {answer.error}")
    return answer.exit_status


if __name__ == "__main__":
    raise SystemExit(main())
