"""Runs a program of the dialect (:mod:`.parse`): each unit as Python source, statement for
statement, every value through an arithmetic of :mod:`deck_emulator.legacy.arithmetic`.

Each unit becomes a function that makes it (its variables, static as on IBSYS and gfortran's
``-fno-automatic -finit-local-zero``: zero at load, kept between calls) holding one function a
labelled block (``L125``: from label 125 to the next label; ``DO10_I``: a DO range's first
statement when unlabelled), which returns the label it goes to. Arrays are lists (a COMMON
block one list, by place); a DO's test ends its range's last statement. The program's
statements stay one a line, with their cards' text beside them (:meth:`Program.python` prints
it), so the source reads side by side with the cards. A program keeps its made code in the
user's cache folder, by its cards' SHA-256 (:meth:`Program._cache_file`): the listing, as a job
deck's own program, is parsed and made once a machine.

Arithmetic: the number type's ``+ - * /`` and unary ``-``, ``abs()``, the arithmetic's
``decimal`` for every REAL constant and card field, its ``sin``, ``cos`` and ``sign``; ``X**2``
is ``X*X`` (as gfortran and the 7094's FORTRAN expand it); INTEGERs are Python ints, converted
where they meet a REAL.  Output goes through :class:`deck_emulator.legacy.printer.Printer` with
the program's own FORMATs.

Stops (:class:`deck_emulator.legacy.stops.EmulatorError`):
an arithmetic fault or a non-finite value names the unit, the label, the variable and the
step; so does a subscript outside its array's storage and an assigned GO TO to a label not
in its list; a subprogram call that runs more than ``Limits.ed_iterations`` blocks; and, where the
program keeps the listing's labels, the listing's own guards (:data:`LISTING_WATCH`).  Binary64
runs check each block's values when it ends and, when one is not finite, run again from the
start checking every assignment, so the message names the statement (as the emulator does).
"""

from __future__ import annotations

import contextlib
import functools
import math
import zlib
from pathlib import Path

from deck_emulator.legacy.stops import (ERRATA, TRACE_ROWS, EmulatorError, Limits, Run,
                                        fault_reason, halving_error, time_error, trace_row)
from deck_emulator.legacy.printer import EVENT_FORMATS, Printer, event_for
from deck_emulator.vocabulary.events import EventKind
from deck_emulator.vocabulary.defaults import (PROGRAM_BLOCKS, PROGRAM_CACHE_ENTRIES,
                                               user_cache_folder)

from .parse import INTRINSICS, Unit, assigned, changed, common_blocks, kind_of, parse_units

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
@functools.cache
def _front_end_crc() -> int:
    """CRC-32 of this front end's text (parse.py, run.py): kept code names it."""
    here = Path(__file__).parent
    return zlib.crc32((here / "parse.py").read_bytes() + (here / "run.py").read_bytes())


#: The ways of running a program: (binary64, checked per assignment).
_MODES = ((True, False), (False, False), (False, True), (True, True))
_CACHE_MAGIC = b"deck_emulator fortran code "


def _cache_folder() -> Path:
    """Where a program's made code is kept: the package's user cache folder's fortran/."""
    return Path(user_cache_folder()) / "fortran"


def _kept(path: Path):
    """The code kept in ``path`` if its first line's SHA-256 is that of the rest, else None
    (a garbled or cut file is removed and made again)."""
    import hashlib
    import marshal
    import os

    try:
        data = path.read_bytes()
    except OSError:
        return None
    head, _, payload = data.partition(b"\n")
    if head != _CACHE_MAGIC + hashlib.sha256(payload).hexdigest().encode():
        with contextlib.suppress(OSError):
            path.unlink()
        return None
    with contextlib.suppress(OSError):
        os.utime(path)  # (recently used)
    return marshal.loads(payload)


def _keep(path: Path, code) -> None:
    """Keep ``code`` in ``path`` (written whole or not at all: files.write_file); the oldest
    entries beyond PROGRAM_CACHE_ENTRIES go. A cache that cannot be written is left alone: the code
    is made again next time."""
    import hashlib
    import marshal

    from deck_emulator.files import write_file

    payload = marshal.dumps(code)
    with contextlib.suppress(OSError):
        path.parent.mkdir(parents=True, exist_ok=True)
        write_file(path, _CACHE_MAGIC + hashlib.sha256(payload).hexdigest().encode() + b"\n"
                   + payload)
        entries = sorted(path.parent.glob("*.code"), key=lambda p: p.stat().st_mtime)
        for old in entries[:-PROGRAM_CACHE_ENTRIES]:
            old.unlink()


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
        self.end = ""  # the block's check of its values where it ends (binary64, unchecked)
        self.label = None  # the label shown for the block being made
        self.body: dict = {}  # id of a DO -> the key of its range's first block
        self.names = _names(unit)  # its scalars not in COMMON
        self.ends: dict = {}  # label -> the DOs whose range ends there, innermost first
        for s in unit.statements:
            if s.kind == "do":
                self.ends.setdefault(s.args[0], []).insert(0, s)

    def emit(self, text: str, where=None):
        self.lines.append((text, where))

    # names ----------------------------------------------------------------------------------
    def ref(self, name: str) -> str:
        """A scalar variable's code: its name, or its place in a COMMON block."""
        at = self.u.commons.get(name)
        return f"_C{at[0]}[{at[1]}]" if at else name

    def store(self, name: str) -> tuple[str, str]:
        """An array's storage (a list) and the index of its first element there."""
        at = self.u.commons.get(name)
        if at:
            return f"_C{at[0]}", str(at[1])
        return name, (f"b_{name}" if name in self.u.dummies else "0")

    def place(self, name: str, subs) -> tuple[str, str]:
        """(storage, index) of an array element, by columns, the index checked to lie in the
        storage (gfortran's and the 7094's: an element of a COMMON block's or an actual
        argument's storage past the array's bounds is that storage's)."""
        lst, base = self.store(name)
        parts, scale = ([] if base == "0" else [base]), []
        for sub, bound in zip(subs, self.u.arrays[name]):
            one = str(int(sub[1]) - 1) if sub[0] == "const" else f"{self._expr(sub)}-1"
            parts.append(f"({one})*{'*'.join(scale)}" if scale else one)
            scale.append(str(bound))
        size = str(math.prod(self.u.arrays[name])) if base == "0" else f"len({lst})"
        return lst, f"_o if 0 <= (_o := {'+'.join(parts)}) < {size} else _sub({name!r}, _o)"

    def target(self, t) -> str:
        if t[0] == "var":
            return self.ref(t[1])
        lst, index = self.place(t[1], t[2])
        return f"{lst}[{index}]"

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
                return str(int(e[1]))  # (0010 is 10)
            self.consts.add(e[1])
            return _const_name(e[1])
        if tag == "var":
            return self.ref(e[1])
        if tag == "elem":
            return self.target(e)
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
        if tag == "rel":
            typ = "I" if e[2][-1] == e[3][-1] == "I" else "R"
            return f"{self.expr(e[2], typ)} {e[1]} {self.expr(e[3], typ)}"
        if tag == "log":
            return f"({self._expr(e[2])}) {e[1]} ({self._expr(e[3])})"
        if tag == "not":
            return f"not ({self._expr(e[1])})"
        if tag == "call":
            return self.call(e)
        _, op, left, right, typ = e
        if typ == "I" and op == "/":
            return f"_idiv({self._expr(left)}, {self._expr(right)})"
        lcode, rcode = self.expr(left, typ), self.expr(right, typ)
        if left[0] in ("bin", "neg") and _weaker(left, op, False):
            lcode = f"({lcode})"
        if right[0] in ("bin", "neg") and _weaker(right, op, True):
            rcode = f"({rcode})"
        return f"{lcode}{_PY_OPS[op]}{rcode}"

    def call(self, e) -> str:
        name, args = e[1], e[2]
        if name in INTRINSICS:
            call = f"{INTRINSICS[name]}({self.expr(args[0])})"
            if self.known is None or name not in ("SIN", "COS") or not self.pure(args[0]):
                return call
            if call not in self.known:  # its first in the block: kept in a local
                simple = args[0][0] == "var"
                self.kept += 1
                local = f"{INTRINSICS[name]}_{args[0][1] if simple else self.kept}"
                self.known[call] = (local, set(_variables(args[0])))
                return f"({local} := {call})"
            return self.known[call][0]
        if name in self.u.functions:
            dummies, body = self.u.functions[name]
            return f"{name}({', '.join(self.expr(a, kind_of(d)) for a, d in zip(args, dummies))})"
        return f"_G.call_{name}({self.actuals(name, args)})"  # a FUNCTION

    def pure(self, e) -> bool:
        """Whether ``e`` reads only the unit's own scalars (no COMMON, no array, no call but
        an intrinsic's): what a kept SIN or COS may stand on."""
        if e[0] == "var":
            return e[1] not in self.u.commons
        if e[0] == "call":
            return e[1] in INTRINSICS and self.pure(e[2][0])
        return e[0] != "elem" and all(self.pure(x) for x in e[1:-1] if isinstance(x, tuple))

    def actuals(self, name: str, args) -> str:
        """A subprogram's arguments: a scalar's value; an array's storage and first index."""
        sub, out = self.units[name], []
        for a, d in zip(args, sub.dummies):
            if d not in sub.arrays:
                out.append(self.expr(a))
            elif a[0] == "arr":
                out += self.store(a[1])
            else:
                out += self.place(a[1], a[2])
        return ", ".join(out)

    # statements ----------------------------------------------------------------------------
    def where(self, label, variable=None):
        return (self.u.name, label, variable)

    def unit_source(self):
        u, names = self.u, self.names
        reals = [n for n in names if kind_of(n) == "R"]
        ints = [n for n in names if kind_of(n) == "I"]
        arrays = [a for a in u.arrays if a not in u.commons]
        self.emit(f"def make_{u.name}(_G):")
        self.emit(f"    # {u.kind + ' ' + u.name if u.name != 'MAIN' else 'MAIN'}: its "
                  "variables, zero at load and kept between calls")
        for group, zero in ((reals, "_Z"), (ints, "0")):
            for i in range(0, len(group), 8):
                self.emit(f"    {' = '.join(group[i:i + 8])} = {zero}")
        for a in arrays:
            self.emit(f"    {a}, b_{a} = None, 0" if a in u.dummies else
                      f"    {a} = [{'_Z' if kind_of(a) == 'R' else '0'}] * "
                      f"{math.prod(u.arrays[a])}")
        for name, (dummies, body) in u.functions.items():
            self.emit(f"    def {name}({', '.join(dummies)}):  # statement function",
                      self.where(None, name))
            self.emit(f"        return {self.expr(body, kind_of(name))}", self.where(None, name))
        blocks = _blocks(u)
        for i, (key, label, stmts, nxt) in enumerate(blocks):
            if stmts[-1].kind == "do":
                self.body[id(stmts[-1])] = nxt
        for key, label, stmts, nxt in blocks:
            self.block(key, label, stmts, nxt)
        table = ", ".join(f"{_key(b[0])}: {_fname(b[0])}" for b in blocks)
        start = "" if blocks[0][0] is None else f"'START': {_fname(blocks[0][0])}, "
        self.emit(f"    _blocks = {{{start}{table}}}")
        self.emit("    def _vars():")
        shown_vars = [(n, self.ref(n)) for n in names + sorted(u.commons)
                      if n not in u.arrays] + [(a, self.store(a)[0]) for a in u.arrays]
        self.emit(f"        return {{{', '.join(f'{n!r}: {c}' for n, c in shown_vars)}}}")
        scalars = [d for d in u.dummies if d not in u.arrays]
        args = ", ".join(f"a_{d}" if d in scalars else f"a_{d}, a_b_{d}" for d in u.dummies)
        self.emit(f"    def _entry({args}):")
        rebound = names + [f"{p}{a}" for a in arrays if a in u.dummies for p in ("", "b_")]
        if rebound:
            self.emit(f"        nonlocal {', '.join(rebound)}")
        for d in u.dummies:
            self.emit(f"        {d} = a_{d}" if d in scalars else
                      f"        {d}, b_{d} = a_{d}, a_b_{d}")
        limit = "_G.limits.ed_iterations" if u.name != "MAIN" else "_G.program_blocks"
        self.emit(f"        lab, n, blocks, limit = 'START', 0, _blocks, {limit}")
        self.emit("        while lab is not None:")
        self.emit("            n += 1")
        self.emit("            if n > limit:")
        mine = changed(u, self.units)
        shown = [n for n in names if kind_of(n) == "R" and n in mine][:3]
        search = (self.program_watch or {}).get("search")
        if search and search[0] == u.name and set(search[1]) <= set(names):
            shown = list(search[1])
        self.emit(f"                _G.runaway({u.name!r}, lab, _vars(), {tuple(shown)!r})")
        self.emit("            lab = blocks[lab]()")
        if u.kind == "FUNCTION":
            self.emit(f"        return {self.ref(u.name)}")
        else:
            back = [d for d in scalars if d in mine]
            self.emit(f"        return ({''.join(d + ', ' for d in back)})")
        self.emit(f"    _G.units[{u.name!r}] = (_entry, _vars)")
        self.emit("    return _entry")

    def block(self, key, label, stmts, nxt):
        self.label = label
        self.emit(f"    def {_fname(key)}():  # "
                  f"{'label ' + str(key) if isinstance(key, int) else key or 'entry'}")
        names = assigned(stmts, self.units) | {do.args[1] for s in stmts if s.label is not None
                                               for do in self.ends.get(s.label, ())}
        local = set(self.names)
        if names & local:
            self.emit(f"        nonlocal {', '.join(sorted(names & local))}")
        w = self.watch if isinstance(key, int) else None
        if w and key in w["steps"]:
            self.emit("        _G.step += 1")
        if w and key == w["free_from"]:
            self.emit("        _G.free = True")
        if w and key == w["halving"]:
            self.emit("        _G.halve()")
        if w and key == w["accept"]:
            self.emit("        _G.halvings = 0")
        if w and key in w.get("points", ()):
            self.emit(f"        _G.point = {w['points'][key]!r}")
        if w and key in w.get("records", ()):
            phase = w["records"][key]
            rows = [n for n in TRACE_ROWS[phase].values() if n]
            if set(rows) <= local:  # (a program without them keeps no trace)
                self.emit(f"        _G.record({phase!r}, {', '.join(map(self.ref, rows))})",
                          self.where(key))
        checks = [self.ref(n) for n in sorted(names)
                  if kind_of(n) == "R" and n not in self.u.arrays]
        self.end = ""
        if self.native and not self.checking and checks:
            self.end = f"if not _fin({'+'.join(checks)}): raise _Replay"
        self.ended = False  # (what follows a jump, unlabelled, is never reached: no checks)
        self.known = {} if self.native else None
        for s in stmts:
            if self.known and s is not stmts[0]:
                self.forget(before)
            before = s
            self.text = s.text
            self.statement(s, "        ", f"  # {str(s.label) + ' ' if s.label else ''}{s.text}")
            self.ended = self.ended or s.kind in _JUMPS
            for do in self.ends.get(s.label, ()) if s.label is not None else ():
                n, var, _m1, m2, m3 = do.args
                where = self.where(label, var)
                self.emit(f"        {self.ref(var)} = {self.ref(var)}+{self.expr(m3)}  "
                          f"# DO {n} {var}: the next", where)
                self.emit(f"        if {self.ref(var)} <= {self.expr(m2)}:", where)
                if self.end:
                    self.emit(f"            {self.end}", where)
                self.emit(f"            return {_key(self.body[id(do)])}", where)
        if not self.ended:
            if self.end:
                self.emit(f"        {self.end}", self.where(label))
            self.emit(f"        return {_key(nxt)}", self.where(label))
        self.known = None

    def statement(self, s, ind: str, text: str):
        """A statement's lines, indented by ``ind``, ``text`` (its card's) beside the first."""
        label, w, kind = self.label, self.watch, s.kind
        if kind == "assign":
            t, e = s.args
            var, code, value = t[1], self.target(t), self.expr(e, t[-1])
            where = self.where(label, var)
            check = kind_of(var) == "R" and (self.checking or self.native)
            if t[0] == "elem" and check:  # (binary64: run again, checking every assignment)
                fault = f"_NonFinite({var!r})" if self.checking else "_Replay"
                self.emit(f"{ind}{code} = _v = {value}{text}", where)
                self.emit(f"{ind}if not _fin(_v): raise {fault}", where)
            else:
                self.emit(f"{ind}{code} = {value}{text}", where)
                if self.checking and check:
                    self.emit(f"{ind}if not _fin({code}): raise _NonFinite({var!r})", where)
            if w and (label, var) in w["clocks"] and t[0] == "var":
                self.emit(f"{ind}_G.clock({code}, {w['clocks'][label, var]!r}, {label})",
                          where)
        elif kind == "continue":
            self.emit(f"{ind}pass{text}", self.where(label))
        elif kind == "read":
            fmt, items = s.args
            self.emit(f"{ind}{''.join(self.target(t) + ', ' for t in items)}= _G.read({fmt})"
                      f"{text}", self.where(label, items[0][1] if items else None))
        elif kind == "write":
            fmt, items = s.args
            values = "".join(f", {self.expr(e)}" for e in items)
            self.emit(f"{ind}_G.write_{self.u.name}({fmt}{values}){text}", self.where(label))
            if w and fmt in EVENT_FORMATS:  # the event the FORMAT reports, at its clock
                clock = w["time"][EVENT_FORMATS[fmt][0] is EventKind.HIT]
                self.emit(f"{ind}_G.event({fmt}, {self.ref(clock)})", self.where(label))
        elif kind == "call":
            name, args = s.args
            sub = self.units[name]
            mine = changed(sub, self.units)
            back = [self.target(a) if a[0] in ("var", "elem") else "_"
                    for d, a in zip(sub.dummies, args) if d in mine and d not in sub.arrays]
            targets = "".join(v + ", " for v in back)
            call = f"_G.call_{name}({self.actuals(name, args)})"
            self.emit(f"{ind}{targets + '= ' if back else ''}{call}{text}",
                      self.where(label, next((a[1] for d, a in zip(sub.dummies, args)
                                              if d in mine and a[0] == "var"), None)))
        elif kind == "label":
            self.emit(f"{ind}{self.ref(s.args[1])} = {s.args[0]}{text}",
                      self.where(label, s.args[1]))
        elif kind == "do":
            n, var, m1, _m2, _m3 = s.args
            self.emit(f"{ind}{self.ref(var)} = {self.expr(m1)}{text}", self.where(label, var))
        elif kind == "lif":
            self.emit(f"{ind}if {self.expr(s.args[0])}:{text}", self.where(label))
            self.statement(s.args[1], ind + "    ", "")
        elif kind == "cgoto":
            labels, e = s.args
            self.emit(f"{ind}if 1 <= (_i := {self.expr(e)}) <= {len(labels)}:{text}",
                      self.where(label))
            if self.end:
                self.emit(f"{ind}    {self.end}", self.where(label))
            self.emit(f"{ind}    return {labels}[_i - 1]", self.where(label))
        else:  # GO TO, IF, RETURN, STOP, END: the block ends (what follows, unlabelled,
            # is never reached, and is kept as written: STOP then END)
            if self.end and not self.ended:
                self.emit(f"{ind}{self.end}", self.where(label))
            self.emit(f"{ind}{self.jump(s)}{text}", self.where(label))

    def forget(self, s):
        """Drop the kept SIN and COS whose arguments statement ``s`` assigned."""
        gone = assigned([s], self.units)
        self.known = {k: v for k, v in self.known.items() if not v[1] & gone}

    def jump(self, s) -> str:
        if s.kind == "goto":
            return f"return {s.args[0]}"
        if s.kind == "agoto":
            var, labels = s.args
            return (f"return {self.ref(var)} if {self.ref(var)} in {labels} else "
                    f"_lost({var!r}, {self.ref(var)})")
        if s.kind == "if":
            e, neg, zero, pos = s.args
            x = self.expr(e)
            if e[-1] == "R" and not self.native:
                x = f"sign({x})"
            return f"_x = {x}; return {neg} if _x < 0 else {pos} if _x > 0 else {zero}"
        if s.kind == "stop" and self.u.name != "MAIN":
            return "raise _Stop"
        return "return None"


#: Statements after which the block's next statement is not reached (but by a label).
_JUMPS = ("goto", "agoto", "if", "return", "stop", "end")


def _integer(x: float) -> int:
    """A REAL's INTEGER (toward zero); NaN has none (gfortran's build traps: invalid)."""
    if x != x:
        raise FloatingPointError("invalid: NaN made INTEGER")
    return int(x)


def _sub(name, index):
    raise _Bad(f"a subscript of {name} outside its storage (element {index + 1})", name)


def _lost(name, value):
    raise _Bad(f"assigned GO TO {name}: {value} is no label of its list", name)


def _weaker(e, op: str, right: bool) -> bool:
    """Whether operand ``e`` of ``op`` needs parentheses to keep FORTRAN's order."""
    if e[0] == "neg":  # a sign: as the first operand of + or -, as written
        return right or op in "*/"
    inner = e[1]
    rank = {"+": 1, "-": 1, "*": 2, "/": 2}
    return rank[inner] < rank[op] or (right and rank[inner] == rank[op])


def _key(key) -> str:
    return "None" if key is False else "'START'" if key is None else repr(key)


def _fname(key) -> str:
    """A block's function: L125 for label 125, L0 for the unit's start, DO10_I for the range of
    DO 10 I where it starts without a label."""
    return f"L{key or 0}" if not isinstance(key, str) else key.replace(" ", "", 1).replace(" ", "_")


def _blocks(u: Unit):
    """(key, the label shown for it, statements, the key it falls into) of each block: a block
    starts at the unit's first statement, at each labelled statement and after each DO (its
    range's first statement: key 'DO n i' if unlabelled)."""
    blocks, shown = [], None
    for s in u.statements:
        if s.label is not None:
            shown = s.label
        if not blocks or s.label is not None or blocks[-1][2][-1].kind == "do":
            do = blocks[-1][2][-1].args if blocks else None
            key = s.label if s.label is not None or not blocks else f"DO {do[0]} {do[1]}"
            blocks.append([key, shown, []])
        blocks[-1][2].append(s)
    return [(key, shown, stmts, blocks[i + 1][0] if i + 1 < len(blocks) else False)
            for i, (key, shown, stmts) in enumerate(blocks)]


def _variables(e, skip=()):
    """The scalar variables an expression (or an assignment's target) reads, in order."""
    tag = e[0]
    if tag == "var":
        if e[1] not in skip:
            yield e[1]
    elif tag in ("neg", "pow", "not"):
        yield from _variables(e[1], skip)
    elif tag in ("call", "elem"):
        for a in e[2]:
            yield from _variables(a, skip)
    elif tag in ("bin", "rel", "log"):
        yield from _variables(e[2], skip)
        yield from _variables(e[3], skip)


def _expressions(s):
    """A statement's expressions and targets, as variables ("var") where it names one."""
    k, a = s.kind, s.args
    if k == "lif":
        return (a[0], *_expressions(a[1]))
    return {"assign": lambda: a, "read": lambda: a[1], "write": lambda: a[1],
            "call": lambda: a[1], "if": lambda: a[:1], "cgoto": lambda: a[1:],
            "agoto": lambda: (("var", a[0], "I"),), "label": lambda: (("var", a[1], "I"),),
            "do": lambda: (("var", a[1], "I"), *a[2:])}.get(k, tuple)()


def _names(u: Unit) -> list[str]:
    """Every scalar variable of a unit, not in COMMON, in order of first appearance (dummies
    first; a FUNCTION's name, its value)."""
    seen = dict.fromkeys(u.dummies)
    if u.kind == "FUNCTION":
        seen.setdefault(u.name)
    for dummies, body in u.functions.values():
        seen.update(dict.fromkeys(_variables(body, set(dummies))))
    for s in u.statements:
        for e in _expressions(s):
            seen.update(dict.fromkeys(_variables(e)))
    return [n for n in seen if n not in u.functions and n not in u.arrays
            and n not in u.commons]


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

    def _cards_crc(self) -> int:
        """CRC-32 of the cards' text, one line each."""
        return zlib.crc32("".join(line + "\n" for line in self.lines).encode())

    @property
    def units(self) -> dict:
        if self._units is None:
            from deck_emulator.legacy.jobdeck import statements

            numbers, path = self._cards
            self._units = {u.name: u for u in parse_units(statements(self.lines, numbers), path)}
        return self._units

    @functools.cached_property
    def sha256(self) -> str:
        """Of the program's cards: their text, one line each, as read (hashed once: the name
        of every way of running's kept code reads it)."""
        import hashlib

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
            code = self._cached(key) if self.cache else None
            if code is None:
                lines = self.made_lines(native, checking)
                code = compile("\n".join(t for t, _ in lines) + "\n", _FILE, "exec")
                if self.cache:
                    _keep(self._cache_file(key), code)
            self._made[key] = code
        return self._made[key], self._lines.get(key)

    def _cache_file(self, key) -> Path:
        """Where the made code of a way of running is kept: named by the SHA-256 of the cards,
        this front end's CRC-32, the watch, the way and Python's bytecode tag."""
        import hashlib
        import sys

        name = hashlib.sha256(repr((self.sha256, _front_end_crc(), self.watch, key,
                                    sys.implementation.cache_tag)).encode()).hexdigest()
        return _cache_folder() / f"{name}.code"

    def _cached(self, key):
        """The kept code of a way of running (checked by its SHA-256), or None."""
        if key not in self._made:
            code = _kept(self._cache_file(key))
            if code is None:
                return None
            self._made[key] = code
        return self._made[key]

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
            for block, places in common_blocks(list(self.units.values())).items():
                runs = [[places[0], 0]]  # (a COMMON block: its places, zero)
                for t in places:
                    runs[-1][1] += 1 if t == runs[-1][0] else runs.append([t, 1]) or 0
                head.append((f"_C{block} = " + " + ".join(
                    f"[{'_Z' if t == 'R' else '0'}] * {n}" for t, n in runs), None))
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
            _Stop=_Stop, _sub=_sub, _lost=_lost, sin=ar.sin, cos=ar.cos, sign=ar.sign,
            _ipow=ar.ipow,
            _real=lambda i: ar.decimal(f"{i}.0"), _int=lambda x: _integer(ar.to_float(x)),
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
