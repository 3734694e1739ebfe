"""Runs a program of the dialect (:mod:`.parse`): each unit as Python source, statement for
statement, every value through an arithmetic of :mod:`deck_emulator.legacy.arithmetic`.

Each unit becomes a function that makes it (its variables, static as on IBSYS and gfortran's
``-fno-automatic -finit-local-zero``: zero at load, kept between calls) holding one function a
labelled block (``L125``: from label 125 to the next label), which returns the label it goes
to. The program's statements stay one a line, with their cards' text beside them
(:meth:`Program.python` prints it), so the source reads side by side with the cards.

Arithmetic: the number type's ``+ - * /`` and unary ``-``, ``abs()``, the arithmetic's
``decimal`` for every REAL constant and card field, its ``sin``, ``cos`` and ``sign``; ``X**2``
is ``X*X`` (as gfortran and the 7094's FORTRAN expand it); INTEGERs are Python ints, converted
where they meet a REAL.  Output goes through :class:`deck_emulator.legacy.printer.Printer` with
the program's own FORMATs.

Stops (:class:`deck_emulator.legacy.stops.EmulatorError`):
an arithmetic fault or a non-finite value names the unit, the label, the variable and the
step; a subroutine call that runs more than ``Limits.ed_iterations`` blocks; and, where the
program keeps the listing's labels, the listing's own guards (:data:`LISTING_WATCH`).  Binary64
runs check each block's values when it ends and, when one is not finite, run again from the
start checking every assignment, so the message names the statement (as the emulator does).
"""

from __future__ import annotations

import functools
import math
import zlib
from pathlib import Path

from deck_emulator.legacy.stops import (ERRATA, TRACE_ROWS, EmulatorError, Limits, Run,
                                        fault_reason, halving_error, time_error, trace_row)
from deck_emulator.legacy.printer import EVENT_FORMATS, Printer, event_for
from deck_emulator.vocabulary.events import EventKind
from deck_emulator.vocabulary.defaults import PROGRAM_BLOCKS

from .parse import INTRINSICS, Unit, kind_of, parse_units

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
    (("THA=0.000022",), "0.000022",
     "THA=0.000022 at label 123 (the tilt after the first step: 0.0545 rad/s * 0.0004 s, "
     "rounded)"),
    (("E=E+.0004",), ".0004", "E=E+.0004 (contact print counter: one step)"),
    (("IF(LL-20)600,501,501",), "20",
     "IF(LL-20) before label 501 (the FCONST cap after 20 steps = 8 ms: 20*2**k steps)"),
    (("H=0.0004", "HI=0.0004"), "0.0004", "H=0.0004, HI=0.0004 at labels 354 and 42 (step reset)"),
    (("E=E+0.0002",), "0.0002", "E=E+0.0002 (free-flight print counter: one step)"),
)
#: The start-up tilt THA (option ``tha_start``) and ED's |DF| tolerance at labels 15 and 16
#: (option ``ed_tolerance``): (unit, statements, the literal the option replaces).
OPTION_LITERALS = {
    "tha_start": ("MAIN", ("THA=0.000022",), "0.000022"),
    "ed_tolerance": ("ED", ("IF(ABS(DF(DH))-.0001)20,20,4", "IF(ABS(DF(DH))-.0001)20,20,13"),
                     ".0001"),
}

_FILE = "<fortran>"  # the generated code's file name in tracebacks
#: The listing's binary64 source as made (scripts/make_listing_source.py writes it).
MADE_LISTING = Path(__file__).with_name("listing_made.py")
#: The package's copy of the listing (what jobdeck.listing_lines reads), checked by its bytes.
LISTING_FILE = Path(__file__).parent.parent / "luminaire.f"


@functools.cache
def _front_end_crc() -> int:
    """CRC-32 of this front end's text (parse.py, run.py): a made file names it."""
    here = Path(__file__).parent
    return zlib.crc32((here / "parse.py").read_bytes() + (here / "run.py").read_bytes())


def _made_code(path: Path, header: str):
    """The code of a made file (from the bytecode cache, as an imported module's) if its
    first line is ``header`` (the same cards, the same front end), else None."""
    import importlib.util

    try:
        with open(path, encoding="ascii") as f:
            if f.readline().rstrip("\n") != header:
                return None
    except OSError:
        return None
    spec = importlib.util.spec_from_file_location(f"{__package__}.{path.stem}", path)
    return spec.loader.get_code(spec.name)


class _NonFinite(ArithmeticError):
    def __init__(self, name):
        super().__init__(name)
        self.name = name


class _Replay(Exception):
    """A block left a value that is not finite: run again, checking every assignment."""


class _Stop(Exception):
    """STOP in a subroutine."""


def _nothing(*_):
    """A trace not kept."""


def _const_name(text: str) -> str:
    return "k_" + text.replace(".", "p").replace("-", "m").replace("+", "")


_PY_OPS = {"+": "+", "-": "-", "*": "*", "/": "/"}


class _Gen:
    """Python source of one unit (see the module docstring)."""

    def __init__(self, unit: Unit, units: dict[str, Unit], native: bool, checking: bool,
                 lines: list, watch: dict | None, literals: dict):
        self.u, self.units, self.native, self.checking = unit, units, native, checking
        self.lines = lines  # (python line, (unit, label, variable) or None)
        self.watch = watch if unit.name == "MAIN" else None
        self.program_watch = watch
        self.consts: set[str] = set()
        self.literals = literals  # (unit, statement text, literal) -> what stands for it
        self.steps: set[str] = set()  # literals divided by 2**k (Program.steps)
        self.text = None  # the statement being made
        #: binary64's SIN and COS of a block (pure: the C library's, no indicators): the
        #: call's code -> (the local that keeps its value, the variables it reads), while none
        #: of them is assigned again (the same value as calling it again, bit for bit)
        self.known: dict | None = None
        self.kept = 0

    def emit(self, text: str, where=None):
        self.lines.append((text, where))

    # expressions -------------------------------------------------------------------------
    def expr(self, e, want: str | None = None) -> str:
        code = self._expr(e)
        if want == "R" and e[-1] == "I":
            return f"_real({code})"
        if want == "I" and e[-1] == "R":
            return f"_int({code})"
        return code

    def _expr(self, e) -> str:
        tag = e[0]
        if tag == "const":
            instead = self.literals.get((self.u.name, self.text, e[1]))
            if instead is not None:  # an option of the listing's (Program.literals)
                how, value = instead
                if how == "step":
                    self.consts.add(value)
                    self.steps.add(value)
                    return "s_" + _const_name(value)
                if how == "int":
                    return value
                self.consts.add(value)
                return _const_name(value)
            if e[2] == "I":
                return e[1]
            self.consts.add(e[1])
            return _const_name(e[1])
        if tag == "var":
            return e[1]
        if tag == "neg":
            inner = self._expr(e[1])
            return f"-({inner})" if e[1][0] == "bin" else f"-{inner}"
        if tag == "pow":
            base = self._expr(e[1])
            if e[1][0] not in ("var", "const"):
                base = f"({base})"
            if e[2] == 2:
                return f"({base}*{base})"
            return f"_ipow({base}, {e[2]})"
        if tag == "call":
            name, args = e[1], e[2]
            if name in INTRINSICS:
                call = f"{INTRINSICS[name]}({self.expr(args[0])})"
                if self.known is None or name not in ("SIN", "COS"):
                    return call
                if call not in self.known:  # its first in the block: kept in a local
                    simple = args[0][0] == "var"
                    self.kept += 1
                    local = f"{INTRINSICS[name]}_{args[0][1] if simple else self.kept}"
                    self.known[call] = (local, set(_variables(args[0])))
                    return f"({local} := {call})"
                return self.known[call][0]
            dummies, body = self.u.functions[name]
            return f"{name}({', '.join(self.expr(a, kind_of(d)) for a, d in zip(args, dummies))})"
        _, op, left, right, typ = e
        if typ == "I" and op == "/":
            return f"_idiv({self._expr(left)}, {self._expr(right)})"
        lcode, rcode = self.expr(left, typ), self.expr(right, typ)
        if left[0] in ("bin", "neg") and _weaker(left, op, False):
            lcode = f"({lcode})"
        if right[0] in ("bin", "neg") and _weaker(right, op, True):
            rcode = f"({rcode})"
        return f"{lcode}{_PY_OPS[op]}{rcode}"

    # statements ----------------------------------------------------------------------------
    def where(self, label, variable=None):
        return (self.u.name, label, variable)

    def unit_source(self):
        u = self.u
        names = _names(u)
        reals = [n for n in names if kind_of(n) == "R"]
        ints = [n for n in names if kind_of(n) == "I"]
        self.emit(f"def make_{u.name}(_G):")
        self.emit(f"    # {'SUBROUTINE ' + u.name if u.name != 'MAIN' else 'MAIN'}: its "
                  "variables, zero at load and kept between calls")
        for group, zero in ((reals, "_Z"), (ints, "0")):
            for i in range(0, len(group), 8):
                self.emit(f"    {' = '.join(group[i:i + 8])} = {zero}")
        for name, (dummies, body) in u.functions.items():
            self.emit(f"    def {name}({', '.join(dummies)}):  # statement function",
                      self.where(None, name))
            self.emit(f"        return {self.expr(body, kind_of(name))}", self.where(None, name))
        blocks = _blocks(u)
        assigned_dummies = [d for d in u.dummies if d in _changed(u, self.units)]
        for label, stmts, nxt in blocks:
            self.block(label, stmts, nxt)
        self.emit(f"    _blocks = {{{', '.join(f'{_key(b[0])}: L{b[0] or 0}' for b in blocks)}}}")
        self.emit("    def _vars():")
        self.emit(f"        return {{{', '.join(f'{n!r}: {n}' for n in names)}}}")
        args = ", ".join(f"a_{d}" for d in u.dummies)
        self.emit(f"    def {u.name}({args}):")
        if names:
            self.emit(f"        nonlocal {', '.join(names)}")
        for d in u.dummies:
            self.emit(f"        {d} = a_{d}")
        limit = "_G.limits.ed_iterations" if u.name != "MAIN" else "_G.program_blocks"
        self.emit(f"        lab, n, blocks, limit = 'START', 0, _blocks, {limit}")
        self.emit("        while lab is not None:")
        self.emit("            n += 1")
        self.emit("            if n > limit:")
        shown = [n for n in names if kind_of(n) == "R" and n in _changed(u, self.units)][:3]
        search = (self.program_watch or {}).get("search")
        if search and search[0] == u.name and set(search[1]) <= set(names):
            shown = list(search[1])
        self.emit(f"                _G.runaway({u.name!r}, lab, _vars(), {tuple(shown)!r})")
        self.emit("            lab = blocks[lab]()")
        self.emit(f"        return ({''.join(d + ', ' for d in assigned_dummies)})")
        self.emit(f"    _G.units[{u.name!r}] = ({u.name}, _vars)")
        self.emit(f"    return {u.name}")

    def block(self, label, stmts, nxt):
        self.emit(f"    def L{label or 0}():  # {'label ' + str(label) if label else 'entry'}")
        assigned = _assigned(stmts, self.units)
        if assigned:
            self.emit(f"        nonlocal {', '.join(sorted(assigned))}")
        w = self.watch
        if w and label in w["steps"]:
            self.emit("        _G.step += 1")
        if w and label == w["free_from"]:
            self.emit("        _G.free = True")
        if w and label == w["halving"]:
            self.emit("        _G.halve()")
        if w and label == w["accept"]:
            self.emit("        _G.halvings = 0")
        if w and label in w.get("points", ()):
            self.emit(f"        _G.point = {w['points'][label]!r}")
        if w and label in w.get("records", ()):
            phase = w["records"][label]
            names = [n for n in TRACE_ROWS[phase].values() if n]
            if set(names) <= set(_names(self.u)):  # (a program without them keeps no trace)
                self.emit(f"        _G.record({phase!r}, {', '.join(names)})",
                          self.where(label))
        checks = [n for n in sorted(assigned) if kind_of(n) == "R"]
        end = ""  # the block's check of its values when it ends (binary64, unchecked)
        if self.native and not self.checking and checks:
            end = f"        if not _fin({'+'.join(checks)}): raise _Replay"
        ended = False
        self.known = {} if self.native else None
        for s in stmts:
            last = s is stmts[-1]
            self.text = s.text
            if self.known and s is not stmts[0]:
                self.forget(before)
            before = s
            text = f"  # {str(s.label) + ' ' if s.label else ''}{s.text}"
            if s.kind == "assign":
                var, e = s.args
                self.emit(f"        {var} = {self.expr(e, kind_of(var))}{text}",
                          self.where(label, var))
                if self.checking and kind_of(var) == "R":
                    self.emit(f"        if not _fin({var}): raise _NonFinite({var!r})",
                              self.where(label, var))
                if w and (label, var) in w["clocks"]:
                    self.emit(f"        _G.clock({var}, {w['clocks'][label, var]!r}, {label})",
                              self.where(label, var))
            elif s.kind == "continue":
                self.emit(f"        pass{text}", self.where(label))
            elif s.kind == "read":
                fmt, items = s.args
                self.emit(f"        {', '.join(items)}, = _G.read({fmt}){text}",
                          self.where(label, items[0] if items else None))
            elif s.kind == "write":
                fmt, items = s.args
                values = "".join(f", {self.expr(e)}" for e in items)
                self.emit(f"        _G.write_{self.u.name}({fmt}{values}){text}",
                          self.where(label))
                if w and fmt in EVENT_FORMATS:  # the event the FORMAT reports, at its clock
                    clock = w["time"][EVENT_FORMATS[fmt][0] is EventKind.HIT]
                    self.emit(f"        _G.event({fmt}, {clock})", self.where(label))
            elif s.kind == "call":
                name, args = s.args
                sub = self.units[name]
                changed = _changed(sub, self.units)
                back = [a[1] if a[0] == "var" else "_" for d, a in zip(sub.dummies, args)
                        if d in changed]
                targets = "".join(v + ", " for v in back)
                call = f"_G.call_{name}({', '.join(self.expr(a) for a in args)})"
                self.emit(f"        {targets + '= ' if back else ''}{call}{text}",
                          self.where(label, next((v for v in back if v != "_"), None)))
            else:  # GO TO, IF, RETURN, STOP, END: the block ends (what follows, unlabelled,
                # is never reached, and is kept as written: STOP then END)
                if end and not ended:
                    self.emit(end, self.where(label))
                self.emit(f"        {self.jump(s)}{text}", self.where(label))
                ended = True
            if last and not ended:
                if end:
                    self.emit(end, self.where(label))
                self.emit(f"        return {_key(nxt)}", self.where(label))
        self.known = None

    def forget(self, s):
        """Drop the kept SIN and COS whose arguments statement ``s`` assigned."""
        changed = _assigned([s], self.units)
        self.known = {k: v for k, v in self.known.items() if not v[1] & changed}

    def jump(self, s) -> str:
        if s.kind == "goto":
            return f"return {s.args[0]}"
        if s.kind == "if":
            e, neg, zero, pos = s.args
            x = self.expr(e)
            if e[-1] == "R" and not self.native:
                x = f"sign({x})"
            return f"_x = {x}; return {neg} if _x < 0 else {pos} if _x > 0 else {zero}"
        if s.kind == "stop" and self.u.name != "MAIN":
            return "raise _Stop"
        return "return None"


def _weaker(e, op: str, right: bool) -> bool:
    """Whether operand ``e`` of ``op`` needs parentheses to keep FORTRAN's order."""
    if e[0] == "neg":  # a sign: as the first operand of + or -, as written
        return right or op in "*/"
    inner = e[1]
    rank = {"+": 1, "-": 1, "*": 2, "/": 2}
    return rank[inner] < rank[op] or (right and rank[inner] == rank[op])


def _key(label) -> str:
    return "None" if label is False else "'START'" if label is None else str(label)


def _blocks(u: Unit):
    """(label, statements, the label it falls into) of each block: a block starts at the
    unit's first statement and at each labelled statement."""
    blocks = []
    for s in u.statements:
        if not blocks or s.label is not None:
            blocks.append([s.label, []])
        blocks[-1][1].append(s)
    out = []
    for i, (label, stmts) in enumerate(blocks):
        nxt = blocks[i + 1][0] if i + 1 < len(blocks) else False
        out.append((label, stmts, nxt))
    return out


def _assigned(stmts, units) -> set[str]:
    """The variables ``stmts`` assign (a CALL assigns the actual arguments its subroutine's
    assigned dummies stand for; a READ its list)."""
    out: set[str] = set()
    for s in stmts:
        if s.kind == "assign":
            out.add(s.args[0])
        elif s.kind == "read":
            out.update(s.args[1])
        elif s.kind == "call":
            sub = units[s.args[0]]
            mine = _changed(sub, units)
            out.update(a[1] for d, a in zip(sub.dummies, s.args[1])
                       if a[0] == "var" and d in mine)
    return out


def _changed(unit: Unit, units) -> set[str]:
    """What a unit assigns (worked out once a unit)."""
    if unit.changed is None:
        unit.changed = _assigned(unit.statements, units)
    return unit.changed


def _variables(e, skip=()):
    """The variables an expression reads, in order."""
    if e[0] == "var":
        if e[1] not in skip:
            yield e[1]
    elif e[0] in ("neg", "pow"):
        yield from _variables(e[1], skip)
    elif e[0] == "call":
        for a in e[2]:
            yield from _variables(a, skip)
    elif e[0] == "bin":
        yield from _variables(e[2], skip)
        yield from _variables(e[3], skip)


def _names(u: Unit) -> list[str]:
    """Every variable of a unit, in order of first appearance (dummies first)."""
    seen = dict.fromkeys(u.dummies)
    for dummies, body in u.functions.values():
        seen.update(dict.fromkeys(_variables(body, set(dummies))))
    for s in u.statements:
        if s.kind == "assign":
            seen.setdefault(s.args[0])
            seen.update(dict.fromkeys(_variables(s.args[1])))
        elif s.kind == "read":
            seen.update(dict.fromkeys(s.args[1]))
        elif s.kind in ("write", "call"):
            for e in s.args[1]:
                seen.update(dict.fromkeys(_variables(e)))
        elif s.kind == "if":
            seen.update(dict.fromkeys(_variables(s.args[0])))
    return [n for n in seen if n not in u.functions]


class Program:
    """A FORTRAN program of the dialect, from its source lines (cards): parsed once, its Python
    source made once per way of running (binary64 checked per block or per assignment, or an
    arithmetic that traps or never leaves the finite numbers), run on any deck."""

    def __init__(self, lines: list[str], numbers: list[int] | None = None, *,
                 path: str | None = None, name: str = "", watch: dict | None = LISTING_WATCH,
                 literals: dict | None = None, step_scale_k: int = 0, errata=(),
                 made: Path | None = None, cards_file: Path | None = None):
        #: ``lines``: the cards' text, or a function that reads them (when first asked for:
        #: ``cards_file``, the file they are read from, is then what a made file is checked on)
        self._cards_text = lines if callable(lines) else list(lines)
        self.cards_file = cards_file
        self.name = name or path or "the program"
        self._cards = (numbers, path)
        #: ``made``: a file holding this program's binary64 source as made (MADE_LISTING),
        #: used while it says it was made from these cards by this front end; the units are
        #: then parsed only when asked for (the source of another mode, a fault's statement)
        self.made = made
        self._units = None
        if made is None:
            self.units  # noqa: B018  (parsed now: a statement outside the dialect is refused)
        self.watch = watch
        #: (unit, statement text, literal) -> ("step", literal): divided by 2**step_scale_k;
        #: ("const", text): that literal instead; ("int", text): that INTEGER instead
        self.literals = literals or {}
        self.step_scale_k, self.errata = step_scale_k, tuple(errata)
        self._made: dict = {}
        self._lines: dict = {}

    @property
    def lines(self) -> list[str]:
        if callable(self._cards_text):
            self._cards_text = list(self._cards_text())
        return self._cards_text

    def _cards_crc(self) -> int:
        """CRC-32 of the cards' text, one line each (read from ``cards_file`` if not yet read:
        the same when the file is those lines, each ended by a newline)."""
        if callable(self._cards_text) and self.cards_file is not None:
            return zlib.crc32(self.cards_file.read_bytes())
        return zlib.crc32("".join(line + "\n" for line in self.lines).encode())

    @property
    def units(self) -> dict:
        if self._units is None:
            from deck_emulator.legacy.jobdeck import statements

            numbers, path = self._cards
            self._units = {u.name: u for u in parse_units(statements(self.lines, numbers), path)}
        return self._units

    @property
    def sha256(self) -> str:
        """Of the program's cards: their text, one line each, as read."""
        import hashlib  # (here: a plain run never asks)

        return hashlib.sha256("".join(line + "\n" for line in self.lines).encode()).hexdigest()

    @property
    def keeps_trace(self) -> bool:
        """Whether a run records the trace (a trajectory): its MAIN has the listing's labels
        where the trace is recorded (``watch["records"]``), each with the variables its row
        reads."""
        main = self.units.get("MAIN") if self.watch else None
        if main is None:
            return False
        labels, names = {s.label for s in main.statements}, set(_names(main))
        return all(label in labels and {n for n in TRACE_ROWS[phase].values() if n} <= names
                   for label, phase in self.watch["records"].items())

    def python(self, *, native: bool = True, checking: bool = False) -> str:
        """The generated Python source (one FORTRAN statement a line, its text beside it)."""
        return "\n".join(text for text, _ in self.made_lines(native, checking)) + "\n"

    def _make(self, native: bool, checking: bool):
        """(code, its lines or None: :meth:`made_lines`) of the source for a way of running."""
        key = (native, checking)
        if key not in self._made:
            code = None
            if self.made is not None and key == (True, False):
                code = _made_code(self.made, self._header(native, checking))
            if code is None:
                lines = self.made_lines(native, checking)
                code = compile("\n".join(t for t, _ in lines) + "\n", _FILE, "exec")
            self._made[key] = code
        return self._made[key], self._lines.get(key)

    def _header(self, native: bool, checking: bool) -> str:
        how = ("binary64, checked per block" if native and not checking else
               "checked per assignment" if checking else "an arithmetic that traps")
        return (f"# {self.name} (its cards' CRC-32 {self._cards_crc()}): the Python of "
                f"deck_emulator.legacy.fortran (its CRC-32 {_front_end_crc()}), {how}")

    def made_lines(self, native: bool, checking: bool) -> list:
        """The generated source's lines: (text, (unit, label, variable) or None)."""
        key = (native, checking)
        if key not in self._lines:
            lines: list = [(self._header(native, checking), None)]
            consts: set[str] = set()
            steps: set[str] = set()
            for unit in self.units.values():
                gen = _Gen(unit, self.units, native, checking, lines, self.watch, self.literals)
                gen.unit_source()
                consts |= gen.consts
                steps |= gen.steps
            head = [(f"{_const_name(c)} = _K({c!r})", None) for c in sorted(consts)]
            half = "".join("/_K('2.')" for _ in range(self.step_scale_k))
            head += [(f"s_{_const_name(c)} = {_const_name(c)}{half}  # one step / "
                      f"2**{self.step_scale_k}", None) for c in sorted(steps)]
            lines[1:1] = head
            formats = {name: u.formats for name, u in self.units.items()}
            lines.append((f"_FORMATS = {formats!r}", None))  # the units' FORMATs
            self._lines[key] = lines
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
        self.program_blocks = PROGRAM_BLOCKS

    # what the generated code calls -----------------------------------------------------------
    def read(self, fmt: int):
        """READ(5,fmt): the next data card's fields, by FORMAT fmt, through the arithmetic."""
        import re

        from deck_emulator.legacy.deck import read_field

        if self.card >= len(self.deck.cards):
            raise EmulatorError(f"READ past the last of the deck's {len(self.deck.cards)} data "
                                "cards", label=self.label, step=self.step, guard="read")
        values = []
        col = 0
        text = self._format_of(fmt)
        card = self.deck.cards[self.card]
        for m in re.finditer(r"(\d+)H|(\d+)X|F(\d+)\.(\d+)|/", text[1:-1]):
            if m.group(1):  # (a Hollerith text would be overwritten by the card: skipped)
                col += int(m.group(1))
            elif m.group(2):
                col += int(m.group(2))
            elif m.group(3):
                w, d = int(m.group(3)), int(m.group(4))
                raw = card[col:col + w].ljust(w)
                _, exact = read_field(raw, name=f"field {len(values) + 1}", card=self.card + 1,
                                      columns=(col + 1, col + w), path=self.deck.path,
                                      decimals=d)
                values.append(self.ar.decimal(exact))
                col += w
            else:
                self.card += 1
                card, col = self.deck.cards[self.card], 0
        self.card += 1
        return values

    def _format_of(self, fmt: int) -> str:
        return next(formats[fmt] for formats in self.formats.values() if fmt in formats)

    def record(self, phase: str, *values):
        self.run_.trace.append(trace_row(phase, values, self.ar.to_float))

    def event(self, fmt: int, t):
        self.run_.events.append(event_for(fmt, self.ar.to_float(t), self.point))

    def halve(self):
        self.halvings += 1
        if self.halvings > self.limits.halvings:
            v = self.units["MAIN"][1]()
            f = self.ar.to_float
            raise halving_error(self.limits.halvings, f(v["H"]), f(v.get("DIFF", 0.0)),
                                f(v.get("DIFFT", 0.0)), self.program.watch["halving"],
                                self.step, self.time())

    def clock(self, value, phase: str, label: int):
        t = self.ar.to_float(value)
        if t > self.limits.time_s:
            raise time_error(self.limits.time_s, phase, label, self.step, t)

    def runaway(self, unit: str, label, values: dict, shown: tuple):
        shown = ", ".join(f"{n} = {self.ar.to_float(values[n]):.6g}" for n in shown)
        search = (self.program.watch or {}).get("search")
        if search and unit == search[0]:  # as the listing's emulator names it
            raise EmulatorError(f"{unit}'s root search did not converge in "
                                f"{self.limits.ed_iterations} iterations ({shown})",
                                label=f"{unit} {label}", step=self.step, time=self.time(),
                                guard="ed_iterations")
        if unit == "MAIN":
            raise EmulatorError(f"the main program ran {self.program_blocks} labelled blocks "
                                f"without STOP ({shown})", label=label, step=self.step,
                                time=self.time(), guard="runaway")
        raise EmulatorError(f"{unit} did not return in {self.limits.ed_iterations} iterations "
                            f"({shown})", label=f"{unit} {label}", step=self.step,
                            time=self.time(), guard="runaway")

    def time(self) -> float | None:
        """Simulated time (the listing's: Q in contact, T in free flight), if it has them."""
        if "MAIN" not in self.units or not self.program.watch:
            return None
        v = self.units["MAIN"][1]()
        name = self.program.watch["time"][1 if self.free else 0]
        return self.ar.to_float(v[name]) if name in v else None

    # running ------------------------------------------------------------------------------------
    def run(self) -> Run:
        """Run to STOP (see the module docstring)."""
        code, lines = self.program._make(self.native, self.checking)
        ar = self.ar
        zero = ar.decimal("0.0")
        namespace = dict(
            _K=ar.decimal, _Z=zero, _fin=ar.isfinite, _NonFinite=_NonFinite, _Replay=_Replay,
            _Stop=_Stop, sin=ar.sin, cos=ar.cos, sign=ar.sign, _ipow=ar.ipow,
            _real=lambda i: ar.decimal(f"{i}.0"), _int=lambda x: int(ar.to_float(x)),
            _idiv=lambda a, b: abs(a) // abs(b) * (1 if (a < 0) == (b < 0) else -1),
        )
        if self.native:
            namespace.update(sin=math.sin, cos=math.cos, _fin=math.isfinite)
        try:
            with ar.trapping():
                exec(code, namespace)
                self.formats = namespace["_FORMATS"]
                for name, formats in self.formats.items():
                    printer = self._printer(formats)
                    printer.records = self.run_.records
                    setattr(self, f"write_{name}", printer.write)
                mains = {name: namespace[f"make_{name}"](self) for name in self.formats}
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
            if not isinstance(exc, (ArithmeticError, ValueError)) or (
                    isinstance(exc, ValueError) and "math domain" not in str(exc)):
                raise  # a defect of ours, not the program's arithmetic
            if isinstance(exc, _NonFinite):
                variable = exc.name
            self._fail(EmulatorError(fault_reason(exc), label=self.label, variable=variable,
                                     step=self.step, time=self.time(), guard="arithmetic"))
        return self.run_

    def _all_finite(self) -> bool:
        return all(self.ar.isfinite(x) for _, get in self.units.values()
                   for x in get().values() if type(x) is not int)

    def _replay(self) -> Run:
        indicators = getattr(self.ar, "indicators", None)
        if indicators is not None:
            indicators.underflows = self._underflows_at_start
        again = Runner(self.program, self.deck, self.ar, limits=self.limits, checking=True,
                       trace=self.keep_trace)
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
                    ed_tolerance: str = ".0001") -> Program:
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
    from deck_emulator.legacy.jobdeck import listing_lines

    literals = _literals(k, tha_start, ed_tolerance)
    name = "legacy/luminaire.f" + "".join(f" + {e}" for e in errata)
    if not errata and not literals:  # the listing as printed: its made source
        return Program(listing_lines, name=name, made=MADE_LISTING, cards_file=LISTING_FILE)
    from importlib import resources

    lines = listing_lines()
    for erratum in errata:
        patch = resources.files("deck_emulator.legacy").joinpath(
            "errata", f"{erratum}.patch").read_text("ascii").splitlines()
        lines = _apply(lines, patch, erratum)
    return Program(lines, name=name, literals=literals, step_scale_k=k, errata=errata)


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
