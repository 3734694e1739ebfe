"""Makes a program of the dialect (:mod:`.parse`) Python source, statement for statement: one
function a unit, one function a labelled block in it (:mod:`.run`'s module docstring says how the
made code runs).  Only a program whose made code is not kept yet, or whose fault is named from
its statements, is made here: a plain run of kept code imports neither this nor the parser.
"""

from __future__ import annotations

import math

from deck_emulator.legacy.printer import EVENT_FORMATS
from deck_emulator.legacy.stops import TRACE_ROWS
from deck_emulator.vocabulary.events import EventKind

from .parse import INTRINSICS, Unit, _nodes, assigned, changed, common_blocks, kind_of


def made_lines(units: dict[str, Unit], made_from: tuple, *, native: bool, checking: bool,
               watch: dict | None, literals: dict, step_scale_k: int) -> list:
    """The made source's lines of a program's ``units``: (text, (unit, label, variable) or
    None), the header first: what it was made from (``made_from``: texts and numbers, the
    program's name among them, see :meth:`.run.Program.made_lines`) as one literal."""
    lines: list = [(_HEADER, None), (f"_MADE_FROM = {_literal(made_from)}", None)]
    consts: set[str] = set()
    steps: set[str] = set()
    # the units inside one function, _program(_G, _left): _left, what is left of the run's
    # statement budget, is one variable of it that every unit's blocks spend from (a cell,
    # as cheap to change as a block's own variable)
    body: list = []
    for unit in units.values():
        gen = _Gen(unit, units, native, checking, body, watch, literals)
        gen.unit_source()
        consts |= gen.consts
        steps |= gen.steps
    lines.append(("def _program(_G, _left):", None))
    lines += [("    " + text, where) for text, where in body]
    lines.append(("    return {" + ", ".join(f"{name!r}: make_{name}" for name in units)
                  + "}, lambda: _left", None))
    head = [(f"{_const_name(c)} = _K({c!r})", None) for c in sorted(consts)]
    for block, places in common_blocks(list(units.values())).items():
        runs = [[places[0], 0]]  # (a COMMON block: its places, zero)
        for t in places:
            runs[-1][1] += 1 if t == runs[-1][0] else runs.append([t, 1]) or 0
        head.append((f"_C{block} = " + " + ".join(
            f"[{'_Z' if t == 'R' else '0'}] * {n}" for t, n in runs), None))
    half = "".join("/_K('2.')" for _ in range(step_scale_k))
    head += [(f"s_{_const_name(c)} = {_const_name(c)}{half}  # one step / "
              f"2**{step_scale_k}", None) for c in sorted(steps)]
    lines[2:2] = head
    formats = {name: u.formats for name, u in units.items()}
    lines.append((f"_FORMATS = {formats!r}", None))  # the units' FORMATs
    lines.append((f"_WATCHED = {bool(watch)}", None))  # (run.watched)
    return lines


#: The made code's first line. Text from outside (the program's name or path, its cards,
#: its names, Hollerith texts and FORMATs, an option's constant) enters the made code only as
#: a literal made by repr (:func:`_literal`), as a name of ASCII letters and digits, or in a
#: comment as printable ASCII (:func:`_comment`): none can end a line or a literal.
_HEADER = ("# the Python of deck_emulator.legacy.fortran: _MADE_FROM is (the program, its "
           "cards' SHA-256, the front end's SHA-256, the way of running)")


def _literal(value) -> str:
    """``value`` (texts, numbers, tuples of them) as a Python literal (repr: its texts'
    line ends, quotes and backslashes escaped)."""
    if not isinstance(value, (str, int, tuple)) or isinstance(value, bool) or (
            isinstance(value, tuple) and not all(isinstance(v, (str, int)) for v in value)):
        raise TypeError(f"not a literal of texts and numbers: {type(value).__name__}")
    return repr(value)


def _comment(text: str) -> str:
    """A card's text as shown in a comment beside its statement: as punched when it is
    printable ASCII (which cannot end the comment), else its ascii() literal."""
    text = str(text)
    return text if all(" " <= ch <= "~" for ch in text) else ascii(text)


def _const_name(text: str) -> str:
    """The made code's name of a REAL constant's text: k_0p0004 for 0.0004 (m for -, + left
    out); a text of other characters than ASCII digits, letters, . + and - (an option's
    constant, a digit of another script) by its UTF-8 bytes in hex: k_x3..."""
    if text.isascii() and all(ch.isalnum() or ch in ".+-" for ch in text):
        return "k_" + text.replace(".", "p").replace("-", "m").replace("+", "")
    return "k_x" + text.encode("utf-8", "surrogatepass").hex()


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
        self.dummies: tuple = ()  # the statement function's being made: they are its own
        #: binary64's SIN and COS of a block (pure: the C library's, no indicators): the
        #: call's code -> (the local that keeps its value, the variables it reads), while none
        #: of them is assigned again (the same value as calling it again, bit for bit)
        self.known: dict | None = None
        self.kept = 0
        self.end = ""  # the block's check of its values where it ends (binary64, unchecked)
        self.label = None  # the label shown for the block being made
        self.body: dict = {}  # id of a DO -> the key of its range's first block
        self.names = scalars(unit)  # its scalars not in COMMON
        self.ends: dict = {}  # label -> the DOs whose range ends there, innermost first
        for s in unit.statements:
            if s.kind == "do":
                self.ends.setdefault(s.args[0], []).insert(0, s)

    def emit(self, text: str, where=None):
        self.lines.append((text, where))

    # names ----------------------------------------------------------------------------------
    def ref(self, name: str) -> str:
        """A scalar variable's code: its name, or its place in a COMMON block."""
        at = None if name in self.dummies else self.u.commons.get(name)
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
                    return str(int(value))
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
            code = f"-({inner})" if e[1][0] == "bin" else f"-{inner}"
            return _wrap(code) if e[-1] == "I" else code
        if tag == "pow":
            base = self._expr(e[1])
            if e[1][0] not in ("var", "const"):
                base = f"({base})"
            # (a FUNCTION in the base is called once, as gfortran: F(X)**2, F(X)**0)
            once = any(x[0] == "call" and (x[1] not in INTRINSICS or x[1] in self.u.functions)
                       for x in _nodes(e[1]))
            if e[2] == 0:  # (gfortran's: 1 of the base's type)
                one = "1" if e[-1] == "I" else self._expr(("const", "1.", "R"))
                return f"({base}, {one})[1]" if once else one
            if e[2] == 1:
                return base
            square = f"(_p := {base})*_p" if once else f"{base}*{base}"
            if e[-1] == "I":
                return _wrap(f"pow({base}, {e[2]}, 4294967296)" if e[2] > 2 else square)
            if e[2] == 2:
                return f"({square})"
            return f"_ipow({base}, {e[2]})"
        if tag == "rel":
            typ = "I" if e[2][-1] == e[3][-1] == "I" else "R"
            return f"{self.expr(e[2], typ)} {e[1]} {self.expr(e[3], typ)}"
        if tag == "log":  # (its right operand may not be evaluated: nothing kept from it)
            left = self._expr(e[2])
            return f"({left}) {e[1]} ({self.maybe(self._expr, e[3])})"
        if tag == "not":
            return f"not ({self._expr(e[1])})"
        if tag == "call":
            return self.call(e)
        if e[-1] == "I" and _ring(e):  # INTEGER + - *: 32 bits, wrapped (module docstring)
            return _wrap(self.arith(e))
        return self.arith(e)

    def arith(self, e) -> str:
        """A binary operation's code, a chain of them on its left (``A+B-C+...``, as long
        as 20 cards make it) made in a loop, FORTRAN's order kept by Python's."""
        if e[-1] == "I" and e[1] == "/":
            return f"_idiv({self._expr(e[2])}, {self._expr(e[3])})"
        spine = [e]
        while True:
            left = spine[-1][2]
            if not (left[0] == "bin" and left[-1] == e[-1] and not _weaker(left, spine[-1][1],
                                                                             False)
                    and not (left[-1] == "I" and left[1] == "/")):
                break
            spine.append(left)
        code = None
        for node in reversed(spine):
            _, op, left, right, typ = node
            lcode = code if code is not None else self._operand(left, typ)
            if code is None and left[0] in ("bin", "neg") and _weaker(left, op, False):
                lcode = f"({lcode})"
            rcode = self._operand(right, typ)
            if right[0] in ("bin", "neg") and _weaker(right, op, True):
                rcode = f"({rcode})"
            code = f"{lcode}{op}{rcode}"
        return code

    def _operand(self, e, typ: str) -> str:
        """An operand's code in an operation of type ``typ``: an INTEGER + - * chain inside
        another is wrapped once, where the outer one ends."""
        if typ == "I" and e[-1] == "I" and _ring(e):
            return self.arith(e)
        return self.expr(e, typ)

    def call(self, e) -> str:
        name, args = e[1], e[2]
        if name in INTRINSICS and name not in self.u.functions:  # (a statement function
            # named SIN, COS or ABS is the unit's own)
            if self.known is None or name not in ("SIN", "COS") or not self.pure(args[0]):
                return f"{INTRINSICS[name]}({self.expr(args[0])})"
            # kept by what they compute (the source's expression): SIN and COS of one angle,
            # and the angle itself when it is an expression, are computed once
            arg = args[0]
            call, angle = (name, repr(arg)), ("angle", repr(arg))
            if call in self.known:
                return self.known[call][0]
            self.kept += 1
            k, reads, simple = self.kept, set(_variables(arg)), arg[0] == "var"
            local = f"{INTRINSICS[name]}_{arg[1] if simple else k}"
            if simple:
                code = self.expr(arg)
            elif angle in self.known:
                code = self.known[angle][0]
            else:
                code = f"(x_{k} := {self.expr(arg)})"
                self.known[angle] = (f"x_{k}", reads)
            self.known[call] = (local, reads)
            return f"({local} := {INTRINSICS[name]}({code}))"
        if name in self.u.functions:
            dummies, body = self.u.functions[name]
            return f"{name}({', '.join(self.expr(a, kind_of(d)) for a, d in zip(args, dummies))})"
        return f"_G.call_{name}({self.actuals(name, args)})"  # a FUNCTION

    def maybe(self, make, *args):
        """``make(*args)`` for code that may not run (a logical IF's statement, the right
        operand of .AND. and .OR.): a SIN or COS first kept there is not used after it."""
        known = None if self.known is None else dict(self.known)
        try:
            return make(*args)
        finally:
            self.known = known

    def pure(self, e) -> bool:
        """Whether ``e`` reads only the unit's own scalars (no COMMON, no array, no call but
        an intrinsic's): what a kept SIN or COS may stand on."""
        for x in _nodes(e):
            if x[0] == "call" and (x[1] not in INTRINSICS or x[1] in self.u.functions):
                return False
            if x[0] == "elem" or (x[0] == "var" and x[1] in self.u.commons
                                  and x[1] not in self.dummies):
                return False
        return True

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
        self.emit(f"    # {_comment(u.kind + ' ' + u.name if u.name != 'MAIN' else 'MAIN')}: "
                  "its variables, zero at load and kept between calls")
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
            self.known = {} if self.native else None  # (its SIN and COS: as in a block's)
            self.dummies = dummies
            self.emit(f"        return {self.expr(body, kind_of(name))}", self.where(None, name))
            self.known, self.dummies = None, ()
        blocks = _blocks(u)
        for i, (key, label, stmts, nxt) in enumerate(blocks):
            if stmts[-1].kind == "do":
                self.body[id(stmts[-1])] = nxt
        # each block's function under one name (the unit's names stay its own, and Python
        # compiles a unit of many labels in linear time), with its statements: what it spends
        # of the run's budget when it starts
        self.emit("    _blocks = {}")
        for key, label, stmts, nxt in blocks:
            self.block(key, label, stmts, nxt)
            self.emit(f"    _blocks[{_key(key)}] = _block")
        if blocks[0][0] is not None:
            self.emit(f"    _blocks['START'] = _blocks[{_key(blocks[0][0])}]")
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
        self.emit("        lab, n, blocks, limit = 'START', 0, _blocks, _G.limits.ed_iterations")
        self.emit("        while lab is not None:")
        mine = changed(u, self.units)
        if u.name != "MAIN":  # (a subprogram's call: Limits.ed_iterations blocks at most)
            self.emit("            n += 1")
            self.emit("            if n > limit:")
            shown = [n for n in names if kind_of(n) == "R" and n in mine][:3]
            search = (self.program_watch or {}).get("search")
            if search and search[0] == u.name and set(search[1]) <= set(names):
                shown = list(search[1])
            self.emit(f"                _G.runaway({u.name!r}, lab, _vars(), "
                      f"{tuple(shown)!r})")
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
        self.emit("    def _block():  # "
                  f"{_comment('label ' + str(key) if isinstance(key, int) else key or 'entry')}")
        names = assigned(stmts, self.units) | {do.args[1] for s in stmts if s.label is not None
                                               for do in self.ends.get(s.label, ())}
        local = set(self.names)
        if names & local:
            self.emit(f"        nonlocal {', '.join(sorted(names & local))}")
        # the block's statements spent from the run's budget as it starts: a stop naming its
        # first statement where the budget is gone (Runner.spent)
        self.emit("        nonlocal _left")
        self.emit(f"        _left -= {len(stmts)}")
        self.emit(f"        if _left < 0: _G.spent({self.u.name!r}, {_key(key)})")
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
            self.statement(s, "        ",
                           f"  # {_comment((str(s.label) + ' ' if s.label else '') + s.text)}")
            self.ended = self.ended or s.kind in _JUMPS
            for do in self.ends.get(s.label, ()) if s.label is not None else ():
                n, var, _m1, m2, m3 = do.args
                where = self.where(label, var)
                self.emit(f"        {self.ref(var)} = {self.ref(var)}+{self.expr(m3)}  "
                          f"# {_comment(f'DO {n} {var}')}: the next", where)
                if self.known:  # (a SIN or COS of the DO variable is computed again after)
                    self.known = {k: v for k, v in self.known.items() if var not in v[1]}
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
            self.emit(f"{ind}{''.join(self.target(t) + ', ' for t in items)}= _G.read({fmt}, "
                      f"{self.u.name!r})"
                      f"{text}", self.where(label, items[0][1] if items else None))
        elif kind == "write":
            fmt, items = s.args
            values = "".join(f", {self.expr(e)}" for e in items)
            # the WRITE's card goes with it: the run keeps, per record, the statement that
            # printed it (Run.writes)
            self.emit(f"{ind}_G.write_{self.u.name}({s.card}, {fmt}{values}){text}",
                      self.where(label))
            if w and fmt in EVENT_FORMATS:  # the event the FORMAT reports, at its clock
                clock = w["time"][EVENT_FORMATS[fmt][0] is EventKind.HIT]
                self.emit(f"{ind}_G.event({fmt}, {self.ref(clock)})", self.where(label))
        elif kind == "call":
            name, args = s.args
            sub = self.units[name]
            mine = changed(sub, self.units)
            back = []
            for d, a in zip(sub.dummies, args):
                if d in mine and d not in sub.arrays:
                    if a[0] == "elem":  # (its place where the call starts, as gfortran's)
                        lst, index = self.place(a[1], a[2])
                        self.emit(f"{ind}_e{len(back)} = {index}", self.where(label))
                        back.append(f"{lst}[_e{len(back)}]")
                    else:
                        back.append(self.target(a) if a[0] == "var" else "_")
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
            self.maybe(self.statement, s.args[1], ind + "    ", "")
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


def _weaker(e, op: str, right: bool) -> bool:
    """Whether operand ``e`` of ``op`` needs parentheses to keep FORTRAN's order."""
    if e[0] == "neg":  # a sign: as the first operand of + or -, as written
        return right or op in "*/"
    inner = e[1]
    rank = {"+": 1, "-": 1, "*": 2, "/": 2}
    return rank[inner] < rank[op] or (right and rank[inner] == rank[op])


def _wrap(code: str) -> str:
    """INTEGER ``code``'s value in 32 bits, two's complement (gfortran's on x86-64: the
    oracle's build, no -ftrapv), as arithmetic in the made line (no call)."""
    return f"(({code})+2147483648&4294967295)-2147483648"


def _ring(e) -> bool:
    """Whether ``e`` is an INTEGER ``+``, ``-`` or ``*`` (wrapped to 32 bits where it ends)."""
    return e[0] == "bin" and e[1] != "/"


def _key(key) -> str:
    return "None" if key is False else "'START'" if key is None else repr(key)


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
    """The scalar variables an expression (or an assignment's target) reads, in order (an
    explicit stack: a chain of 20 cards' operations is deeper than Python's recursion)."""
    todo = [e]
    while todo:
        e = todo.pop()
        tag = e[0]
        if tag == "var":
            if e[1] not in skip:
                yield e[1]
        elif tag in ("neg", "pow", "not"):
            todo.append(e[1])
        elif tag in ("call", "elem"):
            todo.extend(reversed(e[2]))
        elif tag in ("bin", "rel", "log"):
            todo += (e[3], e[2])


def _expressions(s):
    """A statement's expressions and targets, as variables ("var") where it names one."""
    k, a = s.kind, s.args
    if k == "lif":
        return (a[0], *_expressions(a[1]))
    return {"assign": lambda: a, "read": lambda: a[1], "write": lambda: a[1],
            "call": lambda: a[1], "if": lambda: a[:1], "cgoto": lambda: a[1:],
            "agoto": lambda: (("var", a[0], "I"),), "label": lambda: (("var", a[1], "I"),),
            "do": lambda: (("var", a[1], "I"), *a[2:])}.get(k, tuple)()


def scalars(u: Unit) -> list[str]:
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
