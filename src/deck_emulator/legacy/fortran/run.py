"""Runs a program of the dialect (:mod:`.parse`): each unit made Python source (:mod:`.make`),
statement for statement, every value through an arithmetic of
:mod:`deck_emulator.legacy.arithmetic`, its WRITEs through
:class:`deck_emulator.legacy.printer.Printer` with the program's own FORMATs.

Each unit is a function holding one function a labelled block, which returns the label it
goes to; variables are static and start at zero (IBSYS; gfortran's ``-fno-automatic
-finit-local-zero``).  The made code is kept in the user's cache folder (:mod:`.cache`).
A run stops with :class:`~deck_emulator.legacy.stops.EmulatorError` naming the unit, the
label, the variable and the step: an arithmetic fault or a non-finite value (binary64 runs
check each block when it ends and, on a non-finite value, run again checking every
assignment, so that the message names the statement), a subscript outside its storage, a
runaway subprogram, a spent statement budget, and the listing's own guards
(:data:`LISTING_WATCH`).  The whole design: docs/emulator.md, "The one engine".
"""

from __future__ import annotations

import functools
import math
import os

from deck_emulator.legacy.stops import (ERRATA, TRACE_ROWS, EmulatorError, Limits, Run,
                                        fault_reason, trace_row)
from deck_emulator.legacy.printer import Printer, event_for
from deck_emulator.vocabulary import defaults

from . import cache

#: The listing's runaway guards, by its labels in MAIN: a step starts at 125 (contact) or 57
#: (free flight), which starts at 42; 108 halves the step (``Limits.halvings`` in a row at most) and 41 accepts one; time (Q in contact, T in
#: free flight) is bounded by ``Limits.time_s`` where 106 and 59 advance it.  A program that
#: lacks a label lacks that guard; the bound on a subroutine's blocks always holds.
#: The trace (``stops.TRACE_ROWS``) is recorded where a block starts at ``records``' labels;
#: the checks of the points P, R and C against the car start at ``points``' labels (a hit's
#: event names the point); a WRITE of a FORMAT of ``printer.EVENT_FORMATS`` reports its event
#: at the contact clock (Q), or the free-flight clock (T) for a hit; a ``search`` subroutine
#: (ED's root search) that does not return is the guard ``ed_iterations``, showing those values.
LISTING_WATCH = dict(steps=(125, 57), free_from=42, halving=108, accept=41,
                     clocks={(106, "Q"): "contact", (59, "T"): "free"}, time=("Q", "T"),
                     records={41: "contact", 42: "contact", 400: "free", 82: "free"},
                     points={500: "P", 112: "R", 300: "C"}, search=("ED", ("D", "DH", "H")))

#: The listing's literals that mean "one step" (0.0004 s), divided by 2**k by the option
#: ``step_scale_k``: (the statements, as punched without blanks, the literal, in words).  The
#: print intervals (0.0016 s in contact, 0.008 s in free flight) are times and stay.
STEP_LITERALS = (
    (("HI=0.0004", "H=0.0004"), "0.0004", "HI=0.0004, H=0.0004 (initial values)"),
    (("IF(Q-0.0004)123,44,44",), "0.0004",
     "IF(Q-0.0004) at label 125 (first step: the start-up at label 123)"),
    (("IF(Q-.0004)83,84,84",), ".0004", "IF(Q-.0004) before label 83 (first step: FSA=1320.0)"),
    ((f"THA={defaults.LISTING_THA_START}",), defaults.LISTING_THA_START,
     f"THA={defaults.LISTING_THA_START} at label 123 (the tilt after the first step: "
     "0.0545 rad/s * 0.0004 s, rounded)"),
    (("E=E+.0004",), ".0004", "E=E+.0004 (contact print counter: one step)"),
    (("IF(LL-20)600,501,501",), "20",
     "IF(LL-20) before label 501 (the FCONST cap after 20 steps = 8 ms: 20*2**k steps)"),
    (("H=0.0004", "HI=0.0004"), "0.0004", "H=0.0004, HI=0.0004 at labels 354 and 42 (step reset)"),
    (("E=E+0.0002",), "0.0002", "E=E+0.0002 (free-flight print counter: one step)"),
)
#: The start-up tilt THA (option ``tha_start``) and ED's |DF| tolerance at labels 15 and 16
#: (option ``ed_tolerance``): (unit, statements, the literal the option replaces).
OPTION_LITERALS = {
    "tha_start": ("MAIN", (f"THA={defaults.LISTING_THA_START}",), defaults.LISTING_THA_START),
    "ed_tolerance": ("ED", tuple(f"IF(ABS(DF(DH))-{defaults.LISTING_ED_TOLERANCE})20,20,{label}"
                                 for label in (4, 13)), defaults.LISTING_ED_TOLERANCE),
}

_FILE = "<fortran>"  # the generated code's file name in tracebacks


def _front_end_text() -> bytes:
    """This front end's text: every module of it, in the order of their names."""
    here = os.path.dirname(__file__)
    text = []
    for name in sorted(os.listdir(here)):
        if name.endswith(".py"):
            with open(os.path.join(here, name), "rb") as fh:
                text.append(fh.read())
    return b"".join(text)


@functools.cache
def _front_end_sha256() -> str:
    """SHA-256 of this front end's text: the made code's header names it."""
    import hashlib

    return hashlib.sha256(_front_end_text()).hexdigest()


@functools.cache
def _front_end_identity() -> bytes:
    """What kept code holds of the front end that made it: the hash Python checks a source
    against its cached bytecode with (``importlib.util.source_hash``).  Any change of the text
    changes it; the entry itself is named and checked by the SHA-256 of the whole identity
    (cache.py), and a run that finds its code kept hashes no module of the front end."""
    from importlib.util import source_hash

    return source_hash(_front_end_text())


#: The ways of running a program: (binary64, checked per assignment).
_MODES = ((True, False), (False, False), (False, True), (True, True))


class _NonFinite(ArithmeticError):
    def __init__(self, name):
        super().__init__(name)
        self.name = name


class _Replay(Exception):
    """A block left a value that is not finite: run again, checking every assignment."""


class _Stop(Exception):
    """STOP in a subroutine."""


class _Bad(Exception):
    """A subscript outside its storage, an assigned GO TO to no label of its list: a stop."""

    def __init__(self, reason, name):
        super().__init__(reason)
        self.name = name


def _nothing(*_):
    """A trace not kept."""


def _integer(x: float) -> int:
    """A REAL's INTEGER (toward zero); NaN has none (gfortran's build traps: invalid)."""
    if x != x:
        raise FloatingPointError("invalid: NaN made INTEGER")
    if not -2147483649.0 < x < 2147483648.0:  # (gfortran's build traps: invalid)
        raise FloatingPointError(f"invalid: {x:.6g} is too large for an INTEGER (32 bits)")
    return int(x)


def _power(x, n: int):
    """``x**n`` for an INTEGER constant ``n`` > 2, multiplied as gfortran's build does (libgcc's
    ``__powidf2``, ``__powisf2``: squares, from the low bit up; checked against it by
    tests/legacy/test_front_end_bounds.py): about 2 log2(n) products, never n."""
    y = x if n & 1 else None
    n >>= 1
    while n:
        x = x * x
        if n & 1:
            y = x if y is None else y * x
        n >>= 1
    return y


def _sub(name, index):
    raise _Bad(f"a subscript of {name} outside its storage (element {index + 1})", name)


def _lost(name, value):
    raise _Bad(f"assigned GO TO {name}: {value} is no label of its list", name)


def watched(watch: dict | None, units: dict) -> dict | None:
    """``watch`` (:data:`LISTING_WATCH`) where the program is the listing's (its MAIN holds every
    label the watch names, and the clocks' variables), else None: the listing's guards, trace
    and events apply to the listing and its variants alone, through this one table."""
    main = units.get("MAIN")
    if not watch or main is None:
        return None
    labels = {s.label for s in main.statements}
    named = {*watch["steps"], watch["free_from"], watch["halving"], watch["accept"],
             *(label for label, _ in watch["clocks"]), *watch["records"], *watch["points"]}
    from .make import scalars

    return watch if named <= labels and set(watch["time"]) <= set(scalars(main)) else None


class Program:
    """A FORTRAN program of the dialect, from its source lines (cards): parsed once, its Python
    source made once per way of running (binary64 checked per block or per assignment, or an
    arithmetic that traps or never leaves the finite numbers), run on any deck."""

    def __init__(self, lines: list[str], numbers: list[int] | None = None, *,
                 path: str | None = None, name: str = "", watch: dict | None = LISTING_WATCH,
                 literals: dict | None = None, step_scale_k: int = 0, errata=(),
                 cache: bool | None = None):
        #: ``lines``: the cards' text, or a function that reads them (when first asked for)
        self._cards_text = lines if callable(lines) else list(lines)
        self.name = name or path or "the program"
        self._cards = (numbers, path)
        #: the units, parsed when first asked for: at once unless the code of every way of
        #: running asked for is kept (then only for a fault's statement, another way)
        self._units = None
        self.watch = watch
        #: (unit, statement text, literal) -> ("step", literal): divided by 2**step_scale_k;
        #: ("const", text): that literal instead; ("int", text): that INTEGER instead
        self.literals = literals or {}
        self.step_scale_k, self.errata = step_scale_k, tuple(errata)
        self._made: dict = {}
        self._identities: dict = {}
        self._lines: dict = {}
        #: ``cache``: keep the made code in the user's cache folder (:func:`_kept`; default:
        #: a program without literals, the listing's or a job deck's own; not the listing's
        #: variants with respelled literals, made once a process)
        self.cache = not literals if cache is None else cache
        if not (self.cache and any(self._cached(mode) for mode in _MODES)):
            self.units  # noqa: B018  (parsed now: a statement outside the dialect is refused)

    @property
    def lines(self) -> list[str]:
        if callable(self._cards_text):
            self._cards_text = list(self._cards_text())
        return self._cards_text

    @property
    def units(self) -> dict:
        if self._units is None:
            from deck_emulator.legacy.jobdeck import statements

            from .parse import parse_units

            numbers, path = self._cards
            self._units = {u.name: u for u in parse_units(statements(self.lines, numbers), path)}
        return self._units

    @functools.cached_property
    def sha256(self) -> str:
        """Of the program's cards: their text, one line each, as read (what the notes, the
        provenance and the made code's header name the program by; a lone surrogate, as
        UTF-8 would write it)."""
        import hashlib

        text = "".join(line + "\n" for line in self.lines)
        return hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()

    @property
    def keeps_trace(self) -> bool:
        """Whether a run records the trace (a trajectory): its MAIN has the listing's labels
        where the trace is recorded (``watch["records"]``), each with the variables its row
        reads."""
        main = self.units.get("MAIN") if watched(self.watch, self.units) else None
        if main is None:
            return False
        from .make import scalars

        labels, names = {s.label for s in main.statements}, set(scalars(main))
        return all(label in labels and {n for n in TRACE_ROWS[phase].values() if n} <= names
                   for label, phase in self.watch["records"].items())

    def python(self, *, native: bool = True, checking: bool = False) -> str:
        """The generated Python source (one FORTRAN statement a line, its text beside it)."""
        return "\n".join(text for text, _ in self.made_lines(native, checking)) + "\n"

    def _make(self, native: bool, checking: bool):
        """(code, its lines or None: :meth:`made_lines`) of the source for a way of running."""
        key = (native, checking)
        if key not in self._made:
            code = self._cached(key) if self.cache else None
            if code is None:
                lines = self.made_lines(native, checking)
                code = compile("\n".join(t for t, _ in lines) + "\n", _FILE, "exec")
                if self.cache:
                    cache.keep(self._identity(key), code)
            self._made[key] = code
        return self._made[key], self._lines.get(key)

    def _identity(self, key) -> bytes:
        """What the made code of a way of running is made from: the cards, this front end's
        text (its hash: :func:`_front_end_identity`), the watch, the way and Python's bytecode tag (a kept entry is named by its
        SHA-256 and checked against it whole: legacy/fortran/cache.py; made once a way)."""
        if key not in self._identities:
            import sys

            self._identities[key] = repr((self.lines, _front_end_identity(), self.watch, key,
                                          sys.implementation.cache_tag)).encode()
        return self._identities[key]

    def _cached(self, key):
        """The kept code of a way of running (checked: legacy/fortran/cache.py), or None."""
        if key not in self._made:
            code = cache.kept(self._identity(key))
            if code is None:
                return None
            self._made[key] = code
        return self._made[key]

    def _made_from(self, native: bool, checking: bool) -> tuple:
        """What the made code's header names (as one literal: make.made_lines)."""
        how = ("binary64, checked per block" if native and not checking else
               "checked per assignment" if checking else "an arithmetic that traps")
        return (str(self.name), self.sha256, _front_end_sha256(), how)

    def made_lines(self, native: bool, checking: bool) -> list:
        """The generated source's lines: (text, (unit, label, variable) or None)."""
        key = (native, checking)
        if key not in self._lines:
            from .make import made_lines

            self._lines[key] = made_lines(self.units, self._made_from(native, checking),
                                          native=native, checking=checking,
                                          watch=watched(self.watch, self.units),
                                          literals=self.literals, step_scale_k=self.step_scale_k)
        return self._lines[key]

    def runner(self, deck, arithmetic, *, limits: Limits = Limits(), checking: bool = False,
               trace: bool = True) -> "Runner":
        return Runner(self, deck, arithmetic, limits=limits, checking=checking, trace=trace)


class Runner:
    """One run of a :class:`Program` on a deck: ``run()`` gives its
    :class:`~deck_emulator.legacy.stops.Run` or raises ``EmulatorError`` (``.run``: the records
    so far); ``step`` may be read while it runs (progress), ``label`` once it stopped (where)."""

    def __init__(self, program: Program, deck, arithmetic, *, limits: Limits = Limits(),
                 checking: bool = False, trace: bool = True):
        from deck_emulator.legacy.arithmetic import get_arithmetic

        self.program, self.deck = program, deck
        self.ar = get_arithmetic(arithmetic) if isinstance(arithmetic, str) else arithmetic
        self.limits, self.errata, self.keep_trace = limits, program.errata, trace
        native = bool(getattr(self.ar, "native_float", False))
        finite = bool(getattr(self.ar, "always_finite", False))
        self.native = native
        self.checking = checking or not (native or finite)
        self._underflows_at_start = getattr(getattr(self.ar, "indicators", None), "underflows", 0)
        rounding = getattr(self.ar, "format_rounding", lambda: "nearest")()
        self.run_ = Run(records=[], arithmetic=self.ar.describe(), errata=self.errata,
                        step_scale_k=program.step_scale_k)
        self._printer = lambda formats: Printer(
            self.ar.exact, rounding, binary=getattr(self.ar, "binary", False), formats=formats)
        self.formats: dict = {}
        self.step, self.free, self.halvings, self.card = 0, False, 0, 0
        self.point = None  # the point the checks against the car are on: P, R or C
        if not trace:
            self.record = _nothing
        self.label = "START"
        self.units: dict = {}
        self.watch = None  # the listing's guards, where the program is the listing (run())
        #: the statement budget (Limits.budget: scaled with the program's step); what is left
        #: of it is the made code's (_program's _left), read by _left()
        self.budget = limits.budget(program.step_scale_k)
        self._left = lambda: self.budget
        #: keep which WRITE printed which records (Run.writes: what a dossier links); set
        #: before run(), off by default (a study's thousands of runs keep none)
        self.keep_writes = False

    @property
    def statements_run(self) -> int:
        """The statements the run has executed (each block's when it starts)."""
        return self.budget - self._left()

    # what the generated code calls -----------------------------------------------------------
    def read(self, fmt: int, unit: str):
        """READ(5,fmt) in ``unit``: the next data card's fields, by the unit's FORMAT fmt,
        through the arithmetic."""
        from deck_emulator.legacy.deck import read_field
        from deck_emulator.legacy.printer import format_layout

        values = []
        for n, pieces in enumerate(format_layout(self.formats[unit][fmt])):
            if self.card >= len(self.deck.cards):
                slash = f" (FORMAT {fmt}'s /)" if n else ""
                raise EmulatorError(f"READ{slash} past the last of the deck's "
                                    f"{len(self.deck.cards)} data cards", label=self.label,
                                    step=self.step, guard="read")
            card, col = self.deck.cards[self.card], 0
            for piece in pieces:
                if type(piece) is str:  # nX, or a Hollerith text the card would overwrite
                    col += len(piece)
                    continue
                w, d = piece
                raw = card[col:col + w].ljust(w)
                _, exact = read_field(raw, name=f"field {len(values) + 1}", card=self.card + 1,
                                      columns=(col + 1, col + w), path=self.deck.path,
                                      decimals=d)
                values.append(self.ar.decimal(exact))
                col += w
            self.card += 1
        return values

    def record(self, phase: str, *values):
        self.run_.trace.append(trace_row(phase, values, self.ar.to_float))

    def event(self, fmt: int, t):
        self.run_.events.append(event_for(fmt, self.ar.to_float(t), self.point))

    def halve(self):
        self.halvings += 1
        if self.halvings > self.limits.halvings:
            v, f, label = self.units["MAIN"][1](), self.ar.to_float, self.watch["halving"]
            raise EmulatorError(
                f"step halved {self.limits.halvings} times in a row at label {label} (H = "
                f"{f(v['H']):.3g} s, DIFF = {f(v.get('DIFF', 0.0)):.3g} ft, DIFFT = "
                f"{f(v.get('DIFFT', 0.0)):.3g} ft)", label=label, step=self.step,
                time=self.time(), guard="halvings")

    def clock(self, value, phase: str, label: int):
        t = self.ar.to_float(value)
        if t > self.limits.time_s:
            where = ("in free flight: the post has not landed" if phase == "free"
                     else "in contact with the vehicle")
            raise EmulatorError(f"simulated time passed the limit of {self.limits.time_s:g} s "
                                f"{where}", label=label, step=self.step, time=t, guard="time_s")

    def runaway(self, unit: str, label, values: dict, shown: tuple):
        shown = ", ".join(f"{n} = {self.ar.to_float(values[n]):.6g}" for n in shown)
        search = (self.watch or {}).get("search")
        if search and unit == search[0]:  # as the listing's emulator names it
            raise EmulatorError(f"{unit}'s root search did not converge in "
                                f"{self.limits.ed_iterations} iterations ({shown})",
                                label=f"{unit} {label}", step=self.step, time=self.time(),
                                guard="ed_iterations")
        raise EmulatorError(f"{unit} did not return in {self.limits.ed_iterations} iterations "
                            f"({shown})", label=f"{unit} {label}", step=self.step,
                            time=self.time(), guard="runaway")

    def spent(self, unit: str, key):
        """The statement budget (``Limits.statements``) is spent: a stop naming the statement
        the block ``key`` of ``unit`` starts with."""
        from .make import _blocks

        first = next((stmts[0] for k, _, stmts, _ in _blocks(self.program.units[unit])
                      if k == key or (key == "START" and k is None)), None)
        what = (f"card {first.card}: {first.text}" if first is not None else "")
        raise EmulatorError(f"the program ran its budget of {self.budget} statements "
                            f"(Limits.budget) without STOP, at {what}",
                            label=key if unit == "MAIN" else f"{unit} {key}", step=self.step,
                            time=self.time(), guard="statements")

    def time(self) -> float | None:
        """Simulated time (the listing's: Q in contact, T in free flight), if it has them."""
        if "MAIN" not in self.units or not self.watch:
            return None
        v = self.units["MAIN"][1]()
        name = self.watch["time"][1 if self.free else 0]
        return self.ar.to_float(v[name]) if name in v else None

    # running ------------------------------------------------------------------------------------
    def run(self) -> Run:
        """Run to STOP (see the module docstring)."""
        code, lines = self.program._make(self.native, self.checking)
        ar = self.ar
        zero = ar.decimal("0.0")
        namespace = dict(
            _K=ar.decimal, _Z=zero, _fin=ar.isfinite, _NonFinite=_NonFinite, _Replay=_Replay,
            _Stop=_Stop, _sub=_sub, _lost=_lost, sin=ar.sin, cos=ar.cos, sign=ar.sign,
            _ipow=_power,
            _real=lambda i: ar.decimal(f"{i}.0"), _int=lambda x: _integer(ar.to_float(x)),
            _idiv=lambda a, b: abs(a) // abs(b) * (1 if (a < 0) == (b < 0) else -1),
        )
        if self.native:
            namespace.update(sin=math.sin, cos=math.cos, _fin=math.isfinite)
        try:
            with ar.trapping():
                exec(code, namespace)
                self.formats = namespace["_FORMATS"]
                self.watch = self.program.watch if namespace["_WATCHED"] else None
                for name, formats in self.formats.items():
                    printer = self._printer(formats)
                    printer.records = self.run_.records
                    setattr(self, f"write_{name}", self._writer(name, printer))
                makers, self._left = namespace["_program"](self, self.budget)
                mains = {name: makers[name](self) for name in self.formats}
                for name in self.formats:
                    if name != "MAIN":
                        setattr(self, f"call_{name}", mains[name])
                try:
                    mains["MAIN"]()
                except _Stop:
                    pass
        except _Replay:
            return self._replay()
        except EmulatorError as exc:
            if not self.checking and self.native and not self._all_finite():
                return self._replay()
            self._fail(exc)
        except Exception as exc:
            if lines is None:  # (a made file's code: its lines, made again, are the same)
                lines = self.program.made_lines(self.native, self.checking)
            unit, label, variable = self._where(exc, lines, code.co_filename)
            if unit is not None:  # where it stopped (a defect's message names it too)
                self.label = (("START" if label is None else label) if unit == "MAIN"
                              else f"{unit} {label or 0}")
            if isinstance(exc, _Bad):
                error = EmulatorError(str(exc), label=self.label, variable=exc.name,
                                      step=self.step, time=self.time(), guard="program")
            elif not isinstance(exc, (ArithmeticError, ValueError)) or (
                    isinstance(exc, ValueError) and "math domain" not in str(exc)):
                raise  # a defect of ours, not the program's arithmetic
            else:
                error = EmulatorError(fault_reason(exc), label=self.label, variable=(
                    exc.name if isinstance(exc, _NonFinite) else variable), step=self.step,
                    time=self.time(), guard="arithmetic")
            if not self.checking and self.native and not self._all_finite():
                return self._replay()  # (a value went non-finite before: where, replayed)
            self._fail(error)
        return self.run_

    def _writer(self, unit: str, printer):
        """``WRITE(6,fmt) list`` of ``unit``, on its card: the printer's records, and which
        statement printed them with the values of its list (:attr:`Run.writes`)."""
        records, writes, to_float = self.run_.records, self.run_.writes, self.ar.to_float
        if not self.keep_writes:
            return lambda card, fmt, *values: printer.write(fmt, *values)

        def write(card: int, fmt: int, *values) -> None:
            first = len(records)
            printer.write(fmt, *values)
            writes.append((first, unit, card, fmt, tuple(map(to_float, values))))

        return write

    def _all_finite(self) -> bool:
        return all(self.ar.isfinite(x) for _, get in self.units.values()
                   for v in get().values() for x in (v if type(v) is list else (v,))
                   if type(x) is not int and x is not None)

    def _replay(self) -> Run:
        indicators = getattr(self.ar, "indicators", None)
        if indicators is not None:
            indicators.underflows = self._underflows_at_start
        again = Runner(self.program, self.deck, self.ar, limits=self.limits, checking=True,
                       trace=self.keep_trace)
        again.keep_writes = self.keep_writes
        try:
            return again.run()
        finally:  # (what a progress display or a defect's message reads)
            self.run_, self.step, self.label = again.run_, again.step, again.label

    def _fail(self, exc: EmulatorError):
        self.run_.error = exc
        exc.run = self.run_
        raise exc

    @staticmethod
    def _where(exc, lines, filename):
        """(unit, label, variable) of the statement that raised, from the traceback's lines
        of the generated code; a statement function's name is the variable when it raised."""
        import traceback

        frames = [f for f in traceback.extract_tb(exc.__traceback__) if f.filename == filename]
        found, function = (None, None, None), None
        for f in frames:
            where = lines[f.lineno - 1][1]
            if where is None:
                continue
            if where[1] is None and where[2] is not None and f.name == where[2]:
                function = where[2]  # inside a statement function
                continue
            found = where
        unit, label, variable = found
        return unit, label, function or variable


def run_deck(deck, precision="double", *, errata=(), limits: Limits = Limits(),
             trace: bool = True, **options) -> Run:
    """The listing (:func:`listing_program` with ``errata`` and ``options``) run on ``deck`` in
    ``precision`` (an arithmetic's name or the arithmetic): its :class:`Run`; raises
    :class:`EmulatorError` (its ``run``: the records printed up to then) when a guard fires or
    the arithmetic traps."""
    return listing_program(errata, **options).runner(deck, precision, limits=limits,
                                                     trace=trace).run()


def listing_program(errata=(), *, step_scale_k: int = 0, tha_start: str | None = None,
                    ed_tolerance: str = defaults.LISTING_ED_TOLERANCE) -> Program:
    """The listing (the package's ``luminaire.f``) as a :class:`Program`, with ``errata``
    applied (legacy/errata/*.patch: their lines replaced, checked against the listing's) and
    the options of its literals: ``step_scale_k`` divides each of :data:`STEP_LITERALS` by
    2**k, ``tha_start`` and ``ed_tolerance`` replace those of :data:`OPTION_LITERALS`.  Made
    once a process for each set of arguments."""
    unknown = set(errata) - set(ERRATA)
    if unknown:
        raise ValueError(f"unknown erratum {sorted(unknown)}: known are {sorted(ERRATA)}")
    if int(step_scale_k) < 0:
        raise ValueError("step_scale_k must be >= 0")
    return _listing(tuple(errata), int(step_scale_k), tha_start, ed_tolerance)


@functools.lru_cache(maxsize=16)
def _listing(errata, k, tha_start, ed_tolerance) -> Program:
    from deck_emulator.legacy import listing_lines

    literals = _literals(k, tha_start, ed_tolerance)
    name = "legacy/luminaire.f" + "".join(f" + {e}" for e in errata)
    if not errata and not literals:  # the listing as printed: its made source
        return Program(listing_lines, name=name)
    from importlib import resources

    lines = listing_lines()
    for erratum in errata:
        patch = resources.files("deck_emulator.legacy").joinpath(
            "errata", f"{erratum}.patch").read_text("ascii").splitlines()
        lines = _apply(lines, patch, erratum)
    return Program(lines, name=name, literals=literals, step_scale_k=k, errata=errata,
                   cache=False)


def _literals(k, tha_start, ed_tolerance) -> dict:
    """Program.literals of the listing's options."""
    literals = {}
    if k:
        for texts, literal, _ in STEP_LITERALS:
            for text in texts:
                literals["MAIN", text, literal] = (("int", str(int(literal) * 2**k))
                                                   if literal.isdigit() else ("step", literal))
    for option, value in (("tha_start", tha_start), ("ed_tolerance", ed_tolerance)):
        unit, texts, literal = OPTION_LITERALS[option]
        if value is not None and value != literal:
            literals.update({(unit, text, literal): ("const", value) for text in texts})
    return literals


def _apply(lines: list[str], patch: list[str], name: str) -> list[str]:
    """A unified diff's hunks applied to ``lines`` (context and removed lines must match)."""
    import re

    out = list(lines)
    offset = 0
    i = 0
    while i < len(patch):
        m = re.match(r"@@ -(\d+)(?:,\d+)? \+\d+(?:,\d+)? @@", patch[i])
        i += 1
        if not m:
            continue
        at = int(m.group(1)) - 1 + offset
        new: list[str] = []
        old_n = 0
        while i < len(patch) and not patch[i].startswith("@@"):
            tag, text = patch[i][:1], patch[i][1:]
            if tag in (" ", "-"):
                if out[at + old_n].rstrip() != text.rstrip():
                    raise ValueError(f"erratum {name} does not apply at line {at + old_n + 1}")
                old_n += 1
            if tag in (" ", "+"):
                new.append(text)
            i += 1
        out[at:at + old_n] = new
        offset += len(new) - old_n
    return out
