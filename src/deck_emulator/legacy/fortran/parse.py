"""FORTRAN IV as ``legacy/luminaire.f`` writes it: source cards -> program units of statements.

The cards are read into statements by :func:`deck_emulator.legacy.jobdeck.statements` (columns
1-72, continuations in column 6, comments, blanks ignored outside Hollerith texts); this module
parses each statement of exactly the dialect below and refuses anything else with
:class:`DialectError`, one line naming the card, its columns and the statement kind, before
anything runs.  Names and labels are the program's own.
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass, field

from deck_emulator.vocabulary import defaults
from deck_emulator.legacy.printer import format_fields, format_layout

#: The dialect, one row a statement kind: what the front end takes (anything else is refused).
STATEMENTS = {
    "assignment": "V = e or A(s, ...) = e: REAL or INTEGER by the implicit rule (I-N), mixed "
                  "operands converted",
    "statement function": "F(a, ...) = e, before the unit's first executable statement",
    "DIMENSION": "DIMENSION A(d, ...), ...: arrays of 1-3 constant bounds (a dummy array's may "
                 "be INTEGER dummies), stored by columns; subscripts INTEGER expressions",
    "COMMON": "COMMON a, ... and COMMON /B/ a, ...: storage shared by position among the units "
              "(names may differ, the types of a place may not)",
    "CONTINUE": "does nothing; a label to go to",
    "GO TO n": "unconditional",
    "GO TO (n1, ...), i": "computed: to the i-th label; i outside the list: the next statement",
    "ASSIGN n TO i": "i holds label n for an assigned GO TO",
    "GO TO i, (n1, ...)": "assigned: to the label i holds, one of the list",
    "IF (e) n1, n2, n3": "arithmetic IF: to n1, n2, n3 as e < 0, = 0, > 0",
    "IF (l) s": "logical IF: s (neither a DO nor a logical IF) when l holds; l of relations "
                ".LT. .LE. .EQ. .NE. .GT. .GE., .NOT., .AND., .OR.",
    "DO n i = m1, m2, m3": "IBM FORTRAN IV: i = m1; the statements up to n (not a transfer) run, "
                           "then i = i + m3 and again while i <= m2: at least once; i INTEGER, "
                           "m INTEGER constants or variables (m3 = 1 if left out)",
    "CALL s(a, ...)": "a SUBROUTINE of the program; arguments by reference (variables, array "
                      "elements, arrays)",
    "SUBROUTINE s(a, ...)": "starts a subprogram; its locals are static and start at zero",
    "FUNCTION f(a, ...)": "starts a function subprogram, f(a, ...) in an expression: its value "
                          "f, by the implicit rule; it does not assign its scalar dummies",
    "RETURN": "from a subprogram",
    "STOP": "ends the run",
    "END": "ends a unit (a RETURN in a subprogram, a STOP in the main program)",
    "READ (5, n) list": "unit 5: the next $DATA card, FORMAT n of Fw.d fields (of the unit's "
                        "own FORMATs), one REAL variable or array element a field",
    "WRITE (6, n) list": "unit 6: the line printer, FORMAT n, one REAL expression an F field",
    "FORMAT (...)": "the edit descriptors below",
}
#: Edit descriptors a FORMAT may hold.
EDIT_DESCRIPTORS = {
    "Fw.d": "a REAL field (rFw.d: r of them)",
    "nX": "n blanks",
    "nHtext": "Hollerith text, blanks kept",
    "/": "ends a record",
}
#: Intrinsic functions: FORTRAN name -> the arithmetic's (legacy/arithmetic: sin, cos; abs()).
INTRINSICS = {"SIN": "sin", "COS": "cos", "ABS": "abs"}
#: Units the program may READ and WRITE.
READ_UNIT, WRITE_UNIT = 5, 6
#: Relational operators -> Python's.
RELATIONS = {".LT.": "<", ".LE.": "<=", ".EQ.": "==", ".NE.": "!=", ".GT.": ">", ".GE.": ">="}

#: Statement kinds of FORTRAN IV outside the dialect, by the keyword they start with: named
#: in the refusal.
_OTHER_KINDS = ("DOUBLEPRECISION", "EQUIVALENCE", "REALFUNCTION", "INTEGERFUNCTION",
                "INTEGER", "REAL", "LOGICAL", "COMPLEX", "EXTERNAL", "DATA", "PAUSE", "PRINT",
                "PUNCH", "REWIND", "BACKSPACE", "ENDFILE", "BLOCKDATA", "ENTRY")


class DialectError(ValueError):
    """A statement outside the dialect, or one the dialect cannot run (one line)."""

    def __init__(self, reason: str, *, card: int | None = None, columns=None,
                 kind: str = "", path: str | None = None):
        self.reason, self.card, self.columns, self.kind = reason, card, columns, kind
        where = []
        if card is not None:
            where.append(f"card {card}")
        if columns is not None:
            where.append(f"columns {columns[0]}-{columns[1]}" if columns[0] != columns[1]
                         else f"column {columns[0]}")
        head = ", ".join(where)
        kind_text = f"{kind} statement: " if kind else ""
        super().__init__(f"{path + ': ' if path else ''}{head + ': ' if head else ''}"
                         f"{kind_text}{reason}")


# -------------------------------------------------------------------------------- the tree
# Expressions, each ending in its type: "I" (INTEGER), "R" (REAL) or "L" (a relation's):
# ("const", text, t) ("var", name, t) ("elem", array, subscripts, t) ("arr", array, t) (a whole
# array, as an argument) ("call", name, args, t) (an intrinsic, a statement function or a
# FUNCTION) ("neg", e, t) ("pow", e, n, t) ("bin", op, left, right, t) ("rel", op, l, r, "L")
# ("log", op, l, r, "L") (op .AND., .OR.) ("not", e, "L").


def kind_of(name: str) -> str:
    """FORTRAN's implicit type of a name: INTEGER for I-N, else REAL."""
    return "I" if name[0] in "IJKLMN" else "R"


@dataclass
class Stmt:
    kind: str  # assign sfun continue goto cgoto agoto label if lif do call return stop end
    # read write
    label: int | None
    card: int  # the card it starts on
    text: str  # as punched, blanks removed (shown in generated code and messages)
    args: tuple = ()


@dataclass
class Unit:
    name: str  # MAIN or the subprogram's
    dummies: tuple[str, ...] = ()
    statements: list[Stmt] = field(default_factory=list)
    functions: dict[str, tuple[tuple[str, ...], tuple]] = field(default_factory=dict)
    formats: dict[int, str] = field(default_factory=dict)  # label -> normalised FORMAT text
    card: int = 0
    changed: set | None = None  # the variables it assigns (assigned())
    kind: str = "MAIN"  # MAIN, SUBROUTINE or FUNCTION
    arrays: dict[str, tuple] = field(default_factory=dict)  # name -> bounds (int or a name)
    #: name -> (COMMON block, its place there): see common_blocks()
    commons: dict[str, tuple[str, int]] = field(default_factory=dict)
    common_lists: list = field(default_factory=list)  # (block, [names], card) as declared
    externals: list = field(default_factory=list)  # (FUNCTION name, arguments, card, column)
    #: statement function -> the made code's frames a reference to it stands on (1 + those of
    #: the statement functions it refers to)
    levels: dict[str, int] = field(default_factory=dict)


# ----------------------------------------------------------------------------- expressions

_DOTS = r"\.(?:LT|LE|EQ|NE|GT|GE|AND|OR|NOT)\."
_TOKEN = rf"""
    (?P<real>(\d+\.(?!{_DOTS[2:]})\d*|\.\d+)(E[+-]?\d+)?|\d+E[+-]?\d+)
  | (?P<int>\d+)
  | (?P<name>[A-Z][A-Z0-9]*)
  | (?P<dot>{_DOTS})
  | (?P<op>\*\*|[-+*/(),=])
"""


class _Parser:
    """Recursive descent over one statement's blank-free text, FORTRAN's precedence:
    ``.OR.`` under ``.AND.`` under ``.NOT.`` under the relations under ``+ -`` (left to right,
    a sign before a term) under ``* /`` under ``**`` (an INTEGER constant exponent)."""

    def __init__(self, text: str, start: int, fail, unit: Unit):
        self.text, self.fail, self.unit = text, fail, unit
        self.pos = start

    @property
    def pos(self) -> int:
        """The position in the text of the next token (its length at the end)."""
        return self.tokens[self.i][2] if self.i < len(self.tokens) else len(self.text)

    @pos.setter
    def pos(self, at: int):
        """Read the text's tokens from ``at`` on (a keyword's end: FORTRAN has no blanks
        between a keyword and a name)."""
        self.tokens: list[tuple[str, str, int]] = []  # (kind, text, position)
        self.i = self.nest = 0
        while at < len(self.text):
            m = _syntax()[0].match(self.text, at)
            if m is None:  # refused when the parse reaches it
                self.tokens.append(("bad", self.text[at], at))
                break
            self.tokens.append((m.lastgroup, m.group(), at))
            at = m.end()

    def peek(self):
        if self.i >= len(self.tokens):
            return None, None
        kind, tok, at = self.tokens[self.i]
        if kind == "bad":
            self.fail(f"{tok!r} is outside the dialect", at)
        return kind, tok

    def take(self, want=None):
        kind, tok = self.peek()
        if tok is None or (want is not None and tok != want):
            self.fail(f"expected {want or 'more'} at {self.text[self.pos:] or 'the end'!r}",
                      self.pos)
        self.i += 1
        return kind, tok

    def typed(self, e, want: str, at: int):
        """``e`` if it is a relation's (``want`` "L") or a number's (else), or refused."""
        if (e[-1] == "L") != (want == "L"):
            self.fail("a relation where a number belongs" if want != "L" else
                      "a number where a relation (.GT. ...) belongs", at)
        return e

    def expr(self):
        return self.joined(".OR.", lambda: self.joined(".AND.", self.negation))

    def joined(self, op: str, operand):
        """Operands joined by the logical ``op``, left to right."""
        at = self.pos
        e = operand()
        while self.peek()[1] == op:
            self.typed(e, "L", at)
            self.take()
            e = ("log", op.strip(".").lower(), e, self.typed(operand(), "L", at), "L")
        return e

    def negation(self):
        at = self.pos
        if self.peek()[1] == ".NOT.":
            self.take()
            self.deeper(at)
            e = ("not", self.typed(self.negation(), "L", at), "L")
            self.nest -= 1
            return e
        e = self.arith()
        if self.peek()[1] in RELATIONS:
            _, op = self.take()
            right = self.typed(self.arith(), "R", self.pos)
            e = ("rel", RELATIONS[op], self.typed(e, "R", at), right, "L")
        return e

    def number(self):
        """An arithmetic expression (no relation)."""
        at = self.pos
        return self.typed(self.expr(), "R", at)

    def arith(self):
        kind, tok = self.peek()
        if tok in ("+", "-"):
            self.take()
            e = self.term()
            if tok == "-":
                e = ("neg", e, e[-1])
        else:
            e = self.term()
        while self.peek()[1] in ("+", "-"):
            _, op = self.take()
            e = _binary(op, e, self.term())
        return e

    def term(self):
        e = self.factor()
        while self.peek()[1] in ("*", "/"):
            _, op = self.take()
            e = _binary(op, e, self.factor())
        return e

    def factor(self):
        at = self.pos
        base = self.primary()
        if base[-1] == "L" and self.peek()[1] in ("**", "*", "/", "+", "-"):
            self.fail("arithmetic on a relation", at)
        if self.peek()[1] == "**":
            at = self.pos
            self.take()
            kind, tok = self.peek()
            if kind != "int":
                self.fail("an exponent other than an INTEGER constant is outside the dialect",
                          at)
            self.take()
            if int(tok) > 2147483647:
                self.fail(f"the exponent {tok} is beyond 32 bits", at)
            return ("pow", base, int(tok), base[-1])
        return base

    def listed(self, item) -> tuple:
        """``(item, item, ...)``"""
        self.deeper(self.pos)
        self.take("(")
        out = [item()]
        while self.peek()[1] == ",":
            self.take()
            out.append(item())
        self.take(")")
        self.nest -= 1
        return tuple(out)

    def deeper(self, at: int):
        """One more level of parentheses, arguments or .NOT.: refused beyond
        PROGRAM_NESTING."""
        self.nest += 1
        if self.nest > defaults.PROGRAM_NESTING:
            self.fail(f"parentheses, argument lists and .NOT. nested more than "
                      f"{defaults.PROGRAM_NESTING} deep (PROGRAM_NESTING)", at)

    def arguments(self, arrays: bool) -> tuple:
        """``(a, ...)``: expressions, and whole arrays where ``arrays``."""
        def argument():
            tok = self.peek()[1]
            if arrays and tok in self.unit.arrays and (
                    self.i + 1 >= len(self.tokens) or self.tokens[self.i + 1][1] in ",)"):
                self.take()
                return ("arr", tok, kind_of(tok))
            return self.number()
        return self.listed(argument)

    def primary(self):
        at = self.pos
        kind, tok = self.take()
        if kind == "real":
            if math.isinf(float(tok)):
                self.fail(f"the REAL constant {tok} overflows (gfortran refuses it too)", at)
            return ("const", tok, "R")
        if kind == "int":
            if int(tok) > 2147483647:
                self.fail(f"the INTEGER constant {tok} is beyond 32 bits (2147483647; gfortran "
                          "refuses it too)", at)
            return ("const", tok, "I")
        if tok == "(":
            self.deeper(at)
            e = self.expr()
            self.take(")")
            self.nest -= 1
            return e
        if kind != "name":
            self.fail(f"{tok!r} where a value was expected", at)
        if tok in self.unit.arrays:
            if self.peek()[1] != "(":
                self.fail(f"the array {tok} without a subscript (an argument only)", at)
            return ("elem", tok, self.subscripts(tok, at), kind_of(tok))
        if self.peek()[1] != "(":
            return ("var", tok, kind_of(tok))
        args = self.arguments(arrays=tok not in self.unit.functions and tok not in INTRINSICS)
        if tok in self.unit.functions:
            dummies, _body = self.unit.functions[tok]
            if len(args) != len(dummies):
                self.fail(f"statement function {tok} takes {len(dummies)} arguments", at)
            return ("call", tok, args, kind_of(tok))
        if tok in INTRINSICS:
            if len(args) != 1:
                self.fail(f"{tok} takes one argument", at)
            if tok != "ABS" and args[0][-1] != "R":
                self.fail(f"{tok} of an INTEGER is outside the dialect", at)
            return ("call", tok, args, args[0][-1] if tok == "ABS" else "R")
        if tok == self.unit.name:
            self.fail(f"{tok} calls itself: recursion is outside the dialect", at)
        self.unit.externals.append((tok, args, self.locate(at)))  # (looked for by _check)
        return ("call", tok, args, kind_of(tok))

    def subscripts(self, name: str, at: int) -> tuple:
        subs = self.arguments(arrays=False)
        if len(subs) != len(self.unit.arrays[name]):
            self.fail(f"{name} has {len(self.unit.arrays[name])} subscripts", at)
        if any(s[-1] != "I" for s in subs):
            self.fail(f"a subscript of {name} that is not INTEGER", at)
        return subs

    def target(self):
        """An assignment's or a READ's: a variable or an array element."""
        at = self.pos
        kind, tok = self.take()
        if kind != "name":
            self.fail(f"{tok!r} where a variable was expected", at)
        if tok in self.unit.arrays:
            return ("elem", tok, self.subscripts(tok, at), kind_of(tok))
        if self.peek()[1] == "(":
            self.fail(f"{tok}(...) where a variable was expected: {tok} is no array (no "
                      "DIMENSION)", at)
        return ("var", tok, kind_of(tok))

    def labels(self) -> tuple[int, ...]:
        """``(n1, n2, ...)``"""
        def label():
            at = self.pos
            kind, tok = self.take()
            if kind != "int":
                self.fail(f"{tok!r} where a statement label was expected", at)
            return int(tok)
        return self.listed(label)

    def end(self):
        if self.peek()[1] is not None:
            self.fail(f"unexpected text {self.text[self.pos:]!r} after the statement", self.pos)


def _nodes(e):
    """Every node of an expression (an explicit stack: no recursion)."""
    todo = [e]
    while todo:
        e = todo.pop()
        yield e
        todo += [x for x in e[1:] if isinstance(x, tuple) and x and isinstance(x[0], str)]
        if e[0] in ("call", "elem"):
            todo += e[2]


def _binary(op, left, right):
    return ("bin", op, left, right, "I" if left[-1] == right[-1] == "I" else "R")


# ------------------------------------------------------------------------------ statements


def _columns(cards, index: int) -> tuple[int, int]:
    """(card, column) of the ``index``-th non-blank character of a statement's columns 7-72."""
    n = 0
    for number, line in cards:
        for col in range(6, 72):
            if line[col] != " ":
                if n == index:
                    return number, col + 1
                n += 1
    number, line = cards[-1]
    return number, 72


def _format_text(cards, fail) -> str:
    """A FORMAT statement's text from its cards: blanks dropped outside Hollerith texts, kept
    in them (``20HTHE VALUE OF VVA IS `` is 20 characters, blanks and all), checked against
    :data:`EDIT_DESCRIPTORS`; returns ``(...)`` as :mod:`deck_emulator.legacy.printer` reads
    it."""
    chars = [(ch, number, col + 1) for number, line in cards for col, ch in enumerate(line)
             if col >= 6]
    # past the label field and the word FORMAT
    i, word = 0, ""
    while word != "FORMAT":
        if chars[i][0] != " ":
            word += chars[i][0]
        i += 1
    out, depth, item = [], 0, ""

    def bad(why, at):
        fail(why, chars[min(at, len(chars) - 1)][1:])

    while i < len(chars):
        ch = chars[i][0]
        if ch == " ":
            i += 1
            continue
        if ch in _DIGITS:
            j, digits = i, ""
            while j < len(chars) and chars[j][0] in _DIGITS + " ":
                digits += chars[j][0].strip()
                j += 1
            nxt = chars[j][0] if j < len(chars) else ""
            if len(digits) > 3 or (int(digits) == 0 and nxt in "HXF"):
                bad(f"{digits}{nxt}: a count or width of 1 to 999 is the dialect's", i)
            if nxt == "H":
                n = int(digits)
                text = "".join(c for c, _, _ in chars[j + 1:j + 1 + n])
                if len(text) < n:
                    bad(f"{n}H: the Hollerith text runs past the statement's last card", i)
                out.append(f"{n}H{text}")
                i = j + 1 + n
                continue
            if nxt == "X":
                out.append(f"{int(digits)}X")
                i = j + 1
                continue
            if nxt == "F":
                item, i = digits, j
                continue
            bad(f"{digits}{nxt}: an edit descriptor outside the dialect "
                f"({', '.join(EDIT_DESCRIPTORS)})", i)
        if ch == "F":
            ahead = "".join(c for c, _, _ in chars[i:] if c != " ")[:12]  # (over cards)
            m = re.match(r"F([0-9]{1,3})\.([0-9]{1,3})(?![0-9])", ahead)
            if m is None:
                bad("F without w.d (w of 1 to 999)", i)
            if int(m.group(1)) == 0:
                bad(f"{m.group()}: a field of width 0 is outside the dialect", i)
            seen, j = 0, i
            while seen < len(m.group()):
                if chars[j][0] != " ":
                    seen += 1
                j += 1
            out.append(",".join([m.group()] * int(item or 1)))
            item, i = "", j
            continue
        if ch in "(),/":
            depth += {"(": 1, ")": -1}.get(ch, 0)
            if ch == "(" and len(out) > 0:
                bad("a group in parentheses is outside the dialect", i)
            out.append(ch)
            i += 1
            continue
        bad(f"{ch!r}: an edit descriptor outside the dialect ({', '.join(EDIT_DESCRIPTORS)})", i)
    # an nX that ends a record writes nothing (gfortran's build: no blanks at the record's end)
    k = 0
    while k < len(out):
        j = k - 1
        while j >= 0 and out[j] == ",":
            j -= 1
        if out[k] in ("/", ")") and j >= 0 and re.fullmatch("[0-9]+X", out[j]):
            del out[j:k]  # (the nX and the commas after it)
            k = 0
            continue
        k += 1
    text = "".join(out)
    if depth != 0 or not (text.startswith("(") and text.endswith(")")):
        bad("unbalanced parentheses", len(chars) - 1)
    return text


_NAME = re.compile(r"[A-Z][A-Z0-9]*")
_DIGITS = "0123456789"
#: What a card may not hold (refused where it is punched): anything but printable ASCII (the
#: 1967 card code and more), such as a carriage return, a tab, a digit or a byte not ASCII
_OUTSIDE_CARD_CODE = re.compile(r"[^\x20-\x7e]")
_LABEL = re.compile(r"[0-9]{1,5}")
_N = r"([A-Z][A-Z0-9]*)"
#: How each statement kind (of STATEMENTS) is recognised on its blank-free text, and the method
#: of _Reader that reads it: tried in order, the first whose pattern matches reads it.
_SYNTAX = (  # (compiled when first read: _syntax(); the listing's made code reads none)
    ("END", r"END", "simple"),
    ("CONTINUE", r"CONTINUE", "simple"),
    ("RETURN", r"RETURN", "simple"),
    ("STOP", r"STOP", "simple"),
    ("GO TO n", r"GOTO(\d+)", "goto"),
    ("GO TO (n1, ...), i", r"GOTO(\(.*)", "computed_goto"),
    ("GO TO i, (n1, ...)", rf"GOTO{_N},?(\(.*)", "assigned_goto"),
    ("ASSIGN n TO i", rf"ASSIGN(\d+)TO{_N}", "assign_label"),
    ("IF (e) n1, n2, n3", r"IF(\(.*)", "if_"),
    ("DO n i = m1, m2, m3", rf"DO(\d+){_N}=([^=]*,[^=]*)", "do"),
    ("READ (5, n) list", r"(READ|WRITE)\((\d+),(\d+)\)(.*)", "io"),
    ("CALL s(a, ...)", rf"CALL{_N}(\(.*\))?", "call"),
    ("FORMAT (...)", r"FORMAT\(.*", "format"),
    ("DIMENSION", r"DIMENSION([^=]*)", "dimension"),
    ("COMMON", r"COMMON([^=]*)", "common"),
    ("assignment", rf"{_N}(\(.*\))?=(.*)", "assignment"),
)


@functools.cache
def _syntax():
    """(the token pattern, the kinds' table) compiled."""
    return re.compile(_TOKEN, re.X | re.A), tuple((kind, re.compile(pattern, re.A), method)
                                           for kind, pattern, method in _SYNTAX)
_DECLARATIONS = ("dimension", "common", "statement function")


class _Reader:
    """Reads one statement (:meth:`read`) of ``unit``; refuses with the card and column."""

    def __init__(self, st, label, unit: Unit, executable_seen: bool, path):
        self.st, self.label, self.unit, self.path = st, label, unit, path
        self.text = st.text.upper()
        self.executable_seen = executable_seen
        self.p = _Parser(self.text, 0, self.fail, unit)
        self.p.locate = self.locate

    def locate(self, at: int) -> tuple[int, int | None]:
        return _columns(self.st.cards, at) if self.st.cards else (self.st.line, None)

    def fail(self, why, at, kind=None):
        card, col = at if isinstance(at, tuple) else self.locate(at)
        raise DialectError(why, card=card, columns=(col, col) if col else None,
                           kind=kind or _kind_name(self.text), path=self.path)

    def whole(self, why, kind=None):
        card, col = _columns(self.st.cards, 0) if self.st.cards else (self.st.line, 7)
        raise DialectError(why, card=card, columns=(col, 72), kind=kind or _kind_name(self.text),
                           path=self.path)

    def read(self, at: int = 0, inner: bool = False):
        """The statement from ``at`` on: a Stmt, or None for a declaration or a FORMAT (kept
        in the unit)."""
        for kind, pattern, method in _syntax()[1]:
            m = pattern.fullmatch(self.text, at)
            if m is not None:
                break
        else:
            self.whole(f"statement outside the dialect (the dialect: {'; '.join(STATEMENTS)})")
        stmt = getattr(self, method)(m, inner)
        if stmt is None or stmt in _DECLARATIONS:
            if inner:
                self.fail(f"a logical IF's statement is executable, not a {kind}", at)
            if stmt is not None and self.executable_seen:
                self.whole(f"a {kind} after the unit's first executable statement",
                           kind=kind if stmt != "statement function" else
                           "array element or statement function")
            return None
        return stmt

    def stmt(self, kind, *args):
        return Stmt(kind, self.label, self.st.line, self.text, args)

    # the kinds ---------------------------------------------------------------------------
    def simple(self, m, inner):
        word = m.group()
        if word == "RETURN" and self.unit.kind == "MAIN":
            self.whole("RETURN in the main program")
        if word == "END" and inner:
            self.fail("END in a logical IF", m.start())
        return self.stmt(word.lower())

    def goto(self, m, inner):
        return self.stmt("goto", int(m.group(1)))

    def computed_goto(self, m, inner):
        p = self.p
        p.pos = m.start(1)
        labels = p.labels()
        if p.peek()[1] == ",":
            p.take()
        at = p.pos
        e = p.number()
        if e[-1] != "I":
            p.fail("a computed GO TO's index is INTEGER", at)
        p.end()
        return self.stmt("cgoto", labels, e)

    def assigned_goto(self, m, inner):
        if kind_of(m.group(1)) != "I":
            self.fail(f"{m.group(1)} is no INTEGER variable", m.start(1))
        self.p.pos = m.start(2)
        labels = self.p.labels()
        self.p.end()
        return self.stmt("agoto", m.group(1), labels)

    def assign_label(self, m, inner):
        if kind_of(m.group(2)) != "I" or m.group(2) in self.unit.arrays:
            self.fail(f"{m.group(2)} is no INTEGER variable", m.start(2))
        return self.stmt("label", int(m.group(1)), m.group(2))

    def if_(self, m, inner):
        p = self.p
        p.pos = m.start(1)
        p.take("(")
        at = p.pos
        e = p.expr()
        p.take(")")
        rest = self.text[p.pos:]
        if re.fullmatch(r"[0-9]+,[0-9]+,[0-9]+", rest):
            p.typed(e, "R", at)
            return self.stmt("if", e, *map(int, rest.split(",")))
        p.typed(e, "L", at)
        if inner:
            self.fail("a logical IF in a logical IF", m.start())
        if not rest:
            self.fail("a logical IF without its statement", len(self.text))
        at = p.pos
        then = self.read(at, inner=True)
        if then.kind == "do":
            self.fail("a DO in a logical IF", at)
        return self.stmt("lif", e, then)

    def do(self, m, inner):
        var = m.group(2)
        if kind_of(var) != "I" or var in self.unit.arrays:
            self.fail(f"the DO variable {var} is no INTEGER variable", m.start(2))
        p = self.p
        p.pos = m.start(3)
        bounds = []
        while True:
            at = p.pos
            e = p.number()
            if e[0] not in ("const", "var") or e[-1] != "I":
                p.fail("a DO's m1, m2, m3 are INTEGER constants or variables", at)
            bounds.append(e)
            if p.peek()[1] != ",":
                break
            p.take()
        p.end()
        if len(bounds) not in (2, 3):
            self.whole("a DO takes m1, m2 and m3 (or m1, m2)")
        return self.stmt("do", int(m.group(1)), var, *bounds, *(("const", "1", "I"),)[
            :3 - len(bounds)])

    def io(self, m, inner):
        which, io_unit, fmt = m.group(1), int(m.group(2)), int(m.group(3))
        want = READ_UNIT if which == "READ" else WRITE_UNIT
        if io_unit != want:
            self.fail(f"{which} from unit {io_unit}: the program has unit {want} only "
                      f"({'the $DATA cards' if which == 'READ' else 'the line printer'})",
                      m.start(2), kind=which)
        p, items = self.p, []
        p.pos = m.start(4)
        while m.group(4) and p.peek()[1] is not None:
            items.append(p.target() if which == "READ" else p.number())
            if p.peek()[1] is not None:
                p.take(",")
        return self.stmt(which.lower(), fmt, tuple(items))

    def call(self, m, inner):
        args = ()
        if m.group(2):
            self.p.pos = m.start(2)
            args = self.p.arguments(arrays=True)
            self.p.end()
        return self.stmt("call", m.group(1), args)

    def format(self, m, inner):
        if self.label is None:
            self.whole("a FORMAT without a label")
        self.unit.formats[self.label] = (_format_text(self.st.cards, self.fail)
                                         if self.st.cards else self.text[6:])

    def dimension(self, m, inner):
        self.declare(m.start(1), common=None)
        return "dimension"

    def common(self, m, inner):
        block, p = "", self.p
        p.pos = m.start(1)
        while p.peek()[1] is not None:
            if p.peek()[1] == "/":
                p.take()
                block = p.take()[1] if p.peek()[1] != "/" else ""
                if not _NAME.fullmatch(block or "A"):
                    p.fail("a COMMON block's name", p.pos)
                p.take("/")
            names = self.declare(p.pos, common=block)
            self.unit.common_lists.append((block, names, self.st.line))
        return "common"

    def declare(self, at, common):
        """Names (arrays with their bounds) from ``at`` up to the end or a COMMON's ``/``:
        their names; a bound is an INTEGER constant or, for a dummy array, an INTEGER dummy."""
        p, u, names = self.p, self.unit, []
        p.pos = at
        while True:
            at = p.pos
            kind, name = p.take()
            if kind != "name":
                p.fail(f"{name!r} where a name was expected", at)
            if name in names or (common is not None and (name in u.commons or name in
                                                         u.dummies)):
                p.fail(f"{name} twice in COMMON, or a dummy in COMMON", at)
            if p.peek()[1] == "(":
                if name in u.arrays:
                    p.fail(f"{name}'s bounds declared twice", at)
                def bound():
                    at = p.pos
                    kind, tok = p.take()
                    if not (kind == "int" and int(tok) > 0 or kind == "name" and tok in
                            u.dummies and name in u.dummies and kind_of(tok) == "I"
                            and common is None):
                        p.fail("a bound is a positive INTEGER constant (a dummy array's: "
                               "or an INTEGER dummy)", at)
                    return int(tok) if kind == "int" else tok
                bounds = p.listed(bound)
                if len(bounds) > 3:
                    p.fail("more than 3 bounds", at)
                u.arrays[name] = bounds
                held = sum(math.prod(b for b in bs if isinstance(b, int))
                           for a, bs in u.arrays.items() if a not in u.dummies)
                if held > defaults.PROGRAM_ARRAY_ELEMENTS:
                    p.fail(f"the unit's arrays hold {held} elements, more than "
                           f"{defaults.PROGRAM_ARRAY_ELEMENTS} (PROGRAM_ARRAY_ELEMENTS)", at)
            elif common is None:
                p.fail(f"DIMENSION {name} without bounds", at)
            if common is not None:
                u.commons[name] = (common, -1)  # (its place: common_blocks())
            names.append(name)
            if p.peek()[1] != ",":
                break
            p.take()
        if common is None:
            p.end()
        elif p.peek()[1] not in (None, "/"):
            p.fail(f"unexpected text {p.text[p.pos:]!r}", p.pos)
        return names

    def assignment(self, m, inner):
        name, p = m.group(1), self.p
        if m.group(2) is not None and name not in self.unit.arrays:  # a statement function
            if self.executable_seen or inner:
                self.whole(f"{name}(...) = after the first executable statement: {name} is no "
                           "array (DIMENSION), and a statement function comes before",
                           kind="array element or statement function")
            dummies = tuple(m.group(2)[1:-1].split(","))
            if not all(_NAME.fullmatch(d) for d in dummies):
                self.whole("a statement function's dummy arguments are names")
            p.pos = m.start(3)
            body = p.number()
            p.end()
            level = 1 + max((self.unit.levels.get(e[1], 0) for e in _nodes(body)
                             if e[0] == "call"), default=0)
            if level > defaults.PROGRAM_CALL_DEPTH:
                self.whole(f"statement functions referring to each other {level} deep: beyond "
                           f"PROGRAM_CALL_DEPTH ({defaults.PROGRAM_CALL_DEPTH})",
                           kind="statement function")
            self.unit.functions[name] = (dummies, body)
            self.unit.levels[name] = level
            return "statement function"
        target = p.target()
        p.take("=")
        e = p.number()
        p.end()
        return self.stmt("assign", target, e)


def parse_units(statements, path: str | None = None) -> list[Unit]:
    """The program units of ``statements`` (:class:`deck_emulator.legacy.jobdeck.Statement`);
    :class:`DialectError` for the first statement outside the dialect."""
    units: list[Unit] = []
    unit: Unit | None = None
    executable_seen = False
    for st in statements:
        _card_check(st, path)
        text = st.text.upper()
        label = None
        if st.label:
            if not _LABEL.fullmatch(st.label) or int(st.label) == 0:
                raise DialectError(f"label {st.label!r} is not a statement number",
                                   card=st.line, columns=(1, 5), path=path)
            label = int(st.label)
        if unit is None:
            executable_seen = False
            m = re.fullmatch(rf"(SUBROUTINE|FUNCTION){_N}(?:\((.*)\))?", text)
            if m:
                dummies = tuple(m.group(3).split(",")) if m.group(3) else ()
                if not all(_NAME.fullmatch(d) for d in dummies) or (
                        m.group(1) == "FUNCTION" and not dummies):
                    _Reader(st, label, Unit("MAIN"), False, path).whole(
                        "a subprogram's dummy arguments are names (a FUNCTION's: one or more)")
                unit = Unit(m.group(2), dummies, card=st.line, kind=m.group(1))
                continue
            unit = Unit("MAIN", card=st.line)
        stmt = _Reader(st, label, unit, executable_seen, path).read()
        if stmt is None:
            continue
        executable_seen = True
        unit.statements.append(stmt)
        if stmt.kind == "end":
            units.append(unit)
            unit = None
    if unit is not None:
        raise DialectError(f"the program unit {unit.name} has no END", card=unit.card,
                           path=path)
    _check(units, path)
    return units


def _card_check(st, path) -> None:
    """Refuses a statement of more than PROGRAM_CONTINUATIONS continuation cards, a character
    outside the card code (where it is punched) and a constant of more digits than
    PROGRAM_CONSTANT_DIGITS."""
    if len(st.cards) > 1 + defaults.PROGRAM_CONTINUATIONS:
        raise DialectError(f"more than {defaults.PROGRAM_CONTINUATIONS} continuation cards "
                           "(IBM FORTRAN IV's limit: PROGRAM_CONTINUATIONS)",
                           card=st.cards[1 + defaults.PROGRAM_CONTINUATIONS][0], columns=(6, 6),
                           kind=_kind_name(st.text.upper()), path=path)
    for number, line in st.cards or ((st.line, " " * 6 + st.text),):
        bad = _OUTSIDE_CARD_CODE.search(line, 0, 72)
        if bad:
            raise DialectError(f"the character {bad.group()!r} is outside the card code "
                               "(printable ASCII)", card=number,
                               columns=(bad.start() + 1, bad.start() + 1),
                               kind=_kind_name(st.text.upper()), path=path)
    if not st.text.upper().startswith("FORMAT("):
        run = re.search(rf"[0-9]{{{defaults.PROGRAM_CONSTANT_DIGITS + 1},}}", st.text)
        if run:
            raise DialectError(f"a constant or label of more than "
                               f"{defaults.PROGRAM_CONSTANT_DIGITS} digits "
                               "(PROGRAM_CONSTANT_DIGITS)", card=st.line, columns=(7, 72),
                               kind=_kind_name(st.text.upper()), path=path)


def _kind_name(text: str) -> str:
    """The statement kind a refused statement starts with, as a refusal names it: the kind
    :meth:`_Reader.read` takes it for, when one of :data:`_SYNTAX`'s patterns matches (so that a
    ``=``, ``(`` or ``,`` inside a FORMAT's Hollerith text, or a name such as ``DATA1`` or
    ``DO10I``, names no other kind), else the word it starts with."""
    for kind, pattern, _method in _syntax()[1]:
        if pattern.fullmatch(text):
            if kind == "assignment":
                return "assignment"
            break  # a keyword's kind: named by its word below
    else:
        for word in _OTHER_KINDS:
            if text.startswith(word):
                return {"DOUBLEPRECISION": "DOUBLE PRECISION", "BLOCKDATA": "BLOCK DATA",
                        "REALFUNCTION": "REAL FUNCTION",
                        "INTEGERFUNCTION": "INTEGER FUNCTION"}.get(word, word)
        if "=" in text and not text.startswith(("IF(", "DO")):
            return "assignment"
    for word in ("READ", "WRITE", "IF", "GOTO", "CALL", "FORMAT", "SUBROUTINE", "FUNCTION",
                 "DIMENSION", "COMMON", "ASSIGN", "DO", "CONTINUE", "RETURN", "STOP", "END"):
        if text.startswith(word):
            return {"GOTO": "GO TO"}.get(word, word)
    return "assignment" if "=" in text else "unknown"


def assigned(stmts, units) -> set[str]:
    """The names ``stmts`` assign: variables, arrays (an element of them), DO variables, READ
    lists; a CALL the actual arguments its subroutine's assigned scalar dummies stand for."""
    out: set[str] = set()
    for s in stmts:
        if s.kind == "lif":
            s = s.args[1]
        if s.kind == "assign":
            out.add(s.args[0][1])
        elif s.kind == "read":
            out.update(t[1] for t in s.args[1])
        elif s.kind == "do":
            out.add(s.args[1])
        elif s.kind == "label":
            out.add(s.args[1])
        elif s.kind == "call":
            sub = units[s.args[0]]
            mine = changed(sub, units)
            out.update(a[1] for d, a in zip(sub.dummies, s.args[1])
                       if a[0] in ("var", "elem") and d in mine and d not in sub.arrays)
    return out


def changed(unit: Unit, units) -> set[str]:
    """What a unit assigns (worked out once a unit)."""
    if unit.changed is None:
        unit.changed = set()  # (a CALL of itself: refused by _check)
        unit.changed = assigned(unit.statements, units)
    return unit.changed


def common_blocks(units, path=None) -> dict[str, list[str]]:
    """Each COMMON block's places, by type ("R" or "I"); sets each unit's ``commons`` (name ->
    (block, place)). A place's type must be the same in every unit (else DialectError)."""
    blocks: dict[str, list[str]] = {}
    for u in units:
        at: dict[str, int] = {}
        for block, names, card in u.common_lists:
            places = blocks.setdefault(block, [])
            for name in names:
                start = at.get(block, 0)
                size = math.prod(u.arrays.get(name, ()))
                for k in range(start, start + size):
                    if k < len(places) and places[k] != kind_of(name):
                        raise DialectError(f"COMMON /{block}/: place {k + 1} is "
                                           f"{kind_of(name)} as {name} in {u.name}, "
                                           f"{places[k]} elsewhere", card=card,
                                           columns=(7, 72), kind="COMMON", path=path)
                    if k >= len(places):
                        places.append(kind_of(name))
                u.commons[name] = (block, start)
                at[block] = start + size
    return blocks


def _check(units: list[Unit], path) -> None:
    """What the statements must agree on: labels defined once and gone to where they are, DO
    ranges nested and ended, FORMATs and subprograms that exist and are called as declared,
    a main program, READ and WRITE lists against their FORMATs' fields, COMMON's places."""
    names = [u.name for u in units]
    if names.count("MAIN") != 1 or len(set(names)) != len(names):
        raise DialectError("the program needs exactly one main program and units of "
                           "different names", path=path)
    by_name = {u.name: u for u in units}
    for u in units:
        labels = {}
        for s in u.statements:
            if s.label is not None:
                if s.label in labels or s.label in u.formats:
                    raise DialectError(f"label {s.label} defined twice in {u.name}",
                                       card=s.card, columns=(1, 5), path=path)
                labels[s.label] = s
        open_do: list[Stmt] = []
        for s in u.statements:
            where = dict(card=s.card, columns=(7, 72), path=path, kind=_kind_name(s.text))
            while open_do and open_do[-1].args[0] == s.label:
                open_do.pop()
                if s.kind in ("goto", "cgoto", "agoto", "if", "return", "stop", "end", "do"):
                    raise DialectError(f"a DO's range ends at {s.label}, a transfer or a DO",
                                       **where)
            if any(d.args[0] == s.label for d in open_do):
                raise DialectError(f"the DO ranges ending at {s.label} cross", **where)
            if s.kind == "do":
                open_do.append(s)
            inner = s.args[1] if s.kind == "lif" else s
            for t in _targets(inner):
                if t not in labels:
                    raise DialectError(f"no executable statement {t} in {u.name}", **where)
            if inner.kind in ("read", "write"):
                fmt, items = inner.args
                if fmt not in u.formats:
                    raise DialectError(f"no FORMAT {fmt} in {u.name}", **where)
                fields = len(format_fields(format_layout(u.formats[fmt])))
                if fields != len(items):
                    raise DialectError(f"{len(items)} items against the {fields} F fields of "
                                       f"FORMAT {fmt}", **where)
                if any(item[-1] == "I" for item in items):
                    raise DialectError("an INTEGER item against an F field", **where)
            if inner.kind == "call":
                _arguments(by_name, inner.args[0], inner.args[1], "SUBROUTINE",
                           dict(where, kind="CALL"))
        if open_do:
            raise DialectError(f"no statement {open_do[-1].args[0]} ends the DO's range",
                               card=open_do[-1].card, columns=(7, 72), kind="DO", path=path)
        for name, args, (card, col) in u.externals:
            _arguments(by_name, name, args, "FUNCTION", dict(
                card=card, columns=(col, col) if col else None, path=path, kind="assignment"))
    _no_recursion(units, by_name, path)
    for u in units:
        if u.kind == "FUNCTION":
            bad = [d for d in u.dummies if d in changed(u, by_name) and d not in u.arrays]
            if bad:
                raise DialectError(f"FUNCTION {u.name} assigns its dummy {bad[0]}: outside the "
                                   "dialect", card=u.card, columns=(7, 72), kind="FUNCTION",
                                   path=path)
    common_blocks(units, path)


def _targets(s: Stmt) -> tuple:
    """The labels a statement may go to."""
    return {"goto": lambda a: a[:1], "if": lambda a: a[1:], "cgoto": lambda a: a[0],
            "agoto": lambda a: a[1], "label": lambda a: a[:1]}.get(s.kind, lambda a: ())(s.args)


def _calls(u: Unit) -> set[str]:
    """The subprograms a unit calls (CALL, a FUNCTION reference)."""
    return ({s.args[0] for s in u.statements if s.kind == "call"}
            | {s.args[1].args[0] for s in u.statements if s.kind == "lif"
               and s.args[1].kind == "call"} | {e[0] for e in u.externals})


def _no_recursion(units, by_name, path) -> None:
    """Refuses a unit that calls itself, directly or through others."""
    for u in units:
        seen, todo = set(), list(_calls(u))
        while todo:
            name = todo.pop()
            if name == u.name:
                raise DialectError(f"{u.name} calls itself: recursion is outside the dialect",
                                   card=u.card, columns=(7, 72), kind=u.kind, path=path)
            if name not in seen:
                seen.add(name)
                todo += _calls(by_name[name])
    # the made code's frames, one inside the next: a subprogram's call stands on 2 (its entry
    # and its block), a statement function's reference on its level
    depth: dict[str, int] = {}
    for u in units:
        todo = [u.name]
        while todo:
            name = todo[-1]
            callees = [c for c in _calls(by_name[name]) if c not in depth]
            if callees:
                todo += callees
                continue
            todo.pop()
            unit = by_name[name]
            depth[name] = 2 + max(unit.levels.values(), default=0) + max(
                (depth[c] for c in _calls(unit)), default=0)
            if depth[name] > defaults.PROGRAM_CALL_DEPTH:
                raise DialectError(f"subprograms calling each other {depth[name]} frames deep "
                                   f"(2 a call, 1 a statement function): beyond "
                                   f"PROGRAM_CALL_DEPTH ({defaults.PROGRAM_CALL_DEPTH})",
                                   card=unit.card, columns=(7, 72), kind=unit.kind, path=path)


def _arguments(units, name, args, kind, where) -> None:
    """A CALL's or a FUNCTION reference's arguments against the subprogram's dummies."""
    sub = units.get(name)
    if sub is None or sub.kind != kind:
        what = ("neither a statement function of the unit, an array, an intrinsic of the "
                f"dialect ({', '.join(INTRINSICS)}) nor" if kind == "FUNCTION" else "no")
        raise DialectError(f"{name}(...): {what} a {kind} of the program", **where)
    if len(args) != len(sub.dummies):
        raise DialectError(f"{name} with {len(args)} arguments, the {kind} has "
                           f"{len(sub.dummies)}", **where)
    for k, (a, d) in enumerate(zip(args, sub.dummies), start=1):
        if (a[0] == "arr") > (d in sub.arrays) or (a[0] not in ("arr", "elem")
                                                  and d in sub.arrays):
            raise DialectError(f"argument {k} of {name}: an array against a scalar dummy, or "
                               "an expression against an array", **where)
        if a[-1] != kind_of(d):
            raise DialectError(f"argument {k} of {name} is "
                               f"{'INTEGER' if a[-1] == 'I' else 'REAL'}, the dummy {d} is not",
                               **where)
