"""FORTRAN IV as ``legacy/luminaire.f`` writes it: source cards -> program units of statements.

The cards are read into statements by :func:`deck_emulator.legacy.jobdeck.statements` (columns
1-72, continuations in column 6, comments, blanks ignored outside Hollerith texts); this module
parses each statement of exactly the dialect below and refuses anything else with
:class:`DialectError`, one line naming the card, its columns and the statement kind, before
anything runs.  Names and labels are the program's own.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

#: The dialect, one row a statement kind: what the front end takes (anything else is refused).
STATEMENTS = {
    "assignment": "V = e: REAL or INTEGER by the implicit rule (I-N), mixed operands converted",
    "statement function": "F(a, ...) = e, before the unit's first executable statement",
    "CONTINUE": "does nothing; a label to go to",
    "GO TO n": "unconditional",
    "IF (e) n1, n2, n3": "arithmetic IF: to n1, n2, n3 as e < 0, = 0, > 0",
    "CALL s(a, ...)": "a SUBROUTINE of the program; arguments by reference (variables)",
    "SUBROUTINE s(a, ...)": "starts a subprogram; its locals are static and start at zero",
    "RETURN": "from a subroutine",
    "STOP": "ends the run",
    "END": "ends a unit (a RETURN in a subroutine, a STOP in the main program)",
    "READ (5, n) list": "unit 5: the next $DATA card, FORMAT n of Fw.d fields",
    "WRITE (6, n) list": "unit 6: the line printer, FORMAT n",
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

#: Statement kinds of FORTRAN IV outside the dialect, by the keyword they start with: named
#: in the refusal.
_OTHER_KINDS = ("DOUBLEPRECISION", "DIMENSION", "COMMON", "EQUIVALENCE", "FUNCTION",
                "REALFUNCTION", "INTEGERFUNCTION", "INTEGER", "REAL", "LOGICAL", "COMPLEX",
                "EXTERNAL", "DATA", "ASSIGN", "PAUSE", "PRINT", "PUNCH", "REWIND",
                "BACKSPACE", "ENDFILE", "BLOCKDATA", "ENTRY", "DO")


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
# Expressions: ("const", text, type) ("var", name, type) ("call", name, args, type)
# ("neg", e, type) ("bin", op, left, right, type) -- type "I" (INTEGER) or "R" (REAL).


def kind_of(name: str) -> str:
    """FORTRAN's implicit type of a name: INTEGER for I-N, else REAL."""
    return "I" if name[0] in "IJKLMN" else "R"


@dataclass
class Stmt:
    kind: str  # assign, sfun, continue, goto, if, call, return, stop, end, read, write, format
    label: int | None
    card: int  # the card it starts on
    text: str  # as punched, blanks removed (shown in generated code and messages)
    args: tuple = ()


@dataclass
class Unit:
    name: str  # MAIN or the subroutine's
    dummies: tuple[str, ...] = ()
    statements: list[Stmt] = field(default_factory=list)
    functions: dict[str, tuple[tuple[str, ...], tuple]] = field(default_factory=dict)
    formats: dict[int, str] = field(default_factory=dict)  # label -> normalised FORMAT text
    card: int = 0
    changed: set | None = None  # the variables it assigns (legacy.fortran.run)


# ----------------------------------------------------------------------------- expressions

_TOKEN = re.compile(r"""
    (?P<real>(\d+\.\d*|\.\d+)(E[+-]?\d+)?|\d+E[+-]?\d+)
  | (?P<int>\d+)
  | (?P<name>[A-Z][A-Z0-9]*)
  | (?P<op>\*\*|[-+*/(),=])
""", re.X)


class _Parser:
    """Recursive descent over one statement's blank-free text, FORTRAN's precedence:
    ``**`` (right to left) over ``* /`` over ``+ -`` (left to right), a sign before a term."""

    def __init__(self, text: str, start: int, fail, unit: Unit):
        self.text, self.fail, self.unit = text, fail, unit
        self.tokens: list[tuple[str, str, int]] = []  # (kind, text, position), read once
        at = 0
        while at < len(text):
            m = _TOKEN.match(text, at)
            if m is None:  # refused when the parse reaches it
                self.tokens.append(("bad", text[at], at))
                break
            self.tokens.append((m.lastgroup, m.group(), at))
            at = m.end()
        self.i = 0
        self.pos = start

    @property
    def pos(self) -> int:
        """The position in the text of the next token (its length at the end)."""
        return self.tokens[self.i][2] if self.i < len(self.tokens) else len(self.text)

    @pos.setter
    def pos(self, at: int):
        self.i = next((k for k, t in enumerate(self.tokens) if t[2] >= at), len(self.tokens))

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

    def expr(self):
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
        base = self.primary()
        if self.peek()[1] == "**":
            at = self.pos
            self.take()
            kind, tok = self.peek()
            if kind != "int":
                self.fail("an exponent other than an INTEGER constant is outside the dialect",
                          at)
            self.take()
            return ("pow", base, int(tok), base[-1])
        return base

    def primary(self):
        at = self.pos
        kind, tok = self.take()
        if kind == "real":
            return ("const", tok, "R")
        if kind == "int":
            return ("const", tok, "I")
        if tok == "(":
            e = self.expr()
            self.take(")")
            return e
        if kind != "name":
            self.fail(f"{tok!r} where a value was expected", at)
        if self.peek()[1] != "(":
            return ("var", tok, kind_of(tok))
        self.take("(")
        args = [self.expr()]
        while self.peek()[1] == ",":
            self.take()
            args.append(self.expr())
        self.take(")")
        if tok in self.unit.functions:
            dummies, _body = self.unit.functions[tok]
            if len(args) != len(dummies):
                self.fail(f"statement function {tok} takes {len(dummies)} arguments", at)
            return ("call", tok, tuple(args), kind_of(tok))
        if tok in INTRINSICS:
            if len(args) != 1:
                self.fail(f"{tok} takes one argument", at)
            if tok != "ABS" and args[0][-1] != "R":
                self.fail(f"{tok} of an INTEGER is outside the dialect", at)
            return ("call", tok, tuple(args), args[0][-1] if tok == "ABS" else "R")
        self.fail(f"{tok}(...): neither a statement function of the unit nor an intrinsic of "
                  f"the dialect ({', '.join(INTRINSICS)}); arrays are outside the dialect", at)


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
        if ch.isdigit():
            j, digits = i, ""
            while j < len(chars) and (chars[j][0].isdigit() or chars[j][0] == " "):
                digits += chars[j][0].strip()
                j += 1
            nxt = chars[j][0] if j < len(chars) else ""
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
            m = re.match(r"F(\d+)\.(\d+)", "".join(c for c, _, _ in chars[i:i + 12]
                                                   if c != " "))
            if m is None:
                bad("F without w.d", i)
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
    text = "".join(out)
    if depth != 0 or not (text.startswith("(") and text.endswith(")")):
        bad("unbalanced parentheses", len(chars) - 1)
    return text


def _split_top(text: str, sep: str) -> list[str]:
    parts, depth, cur = [], 0, ""
    for ch in text:
        depth += {"(": 1, ")": -1}.get(ch, 0)
        if ch == sep and depth == 0:
            parts.append(cur)
            cur = ""
        else:
            cur += ch
    return parts + [cur]


_NAME = re.compile(r"[A-Z][A-Z0-9]*")
_LABEL = re.compile(r"\d{1,5}")


def parse_units(statements, path: str | None = None) -> list[Unit]:
    """The program units of ``statements`` (:class:`deck_emulator.legacy.jobdeck.Statement`);
    :class:`DialectError` for the first statement outside the dialect."""
    units: list[Unit] = []
    unit: Unit | None = None
    executable_seen = False
    for st in statements:
        text = st.text.upper()

        def fail(why, at, kind=None, st=st):
            if isinstance(at, tuple):
                card, col = at
            else:
                card, col = _columns(st.cards, at) if st.cards else (st.line, None)
            raise DialectError(why, card=card, columns=(col, col) if col else None,
                               kind=kind or _kind_name(text), path=path)

        def whole(why, kind=None, st=st):
            card, col = _columns(st.cards, 0) if st.cards else (st.line, 7)
            raise DialectError(why, card=card, columns=(col, 72),
                               kind=kind or _kind_name(text), path=path)

        label = None
        if st.label:
            if not _LABEL.fullmatch(st.label) or int(st.label) == 0:
                raise DialectError(f"label {st.label!r} is not a statement number",
                                   card=st.line, columns=(1, 5), path=path)
            label = int(st.label)
        if unit is None:
            m = re.fullmatch(r"SUBROUTINE([A-Z][A-Z0-9]*)(?:\((.*)\))?", text)
            if m:
                dummies = tuple(m.group(2).split(",")) if m.group(2) else ()
                if not all(_NAME.fullmatch(d) for d in dummies):
                    whole("a dummy argument that is not a name")
                unit = Unit(m.group(1), dummies, card=st.line)
                executable_seen = False
                continue
            unit = Unit("MAIN", card=st.line)
            executable_seen = False
        p = _Parser(text, 0, fail, unit)
        stmt = None
        if text == "END":
            stmt = Stmt("end", label, st.line, text)
        elif text in ("CONTINUE", "RETURN", "STOP"):
            if text == "RETURN" and unit.name == "MAIN":
                whole("RETURN in the main program")
            stmt = Stmt(text.lower(), label, st.line, text)
        elif re.fullmatch(r"GOTO\d+", text):
            stmt = Stmt("goto", label, st.line, text, (int(text[4:]),))
        elif text.startswith("FORMAT("):
            if label is None:
                whole("a FORMAT without a label")
            unit.formats[label] = _format_text(st.cards, fail) if st.cards else text[6:]
            continue
        elif m := re.match(r"(READ|WRITE)\((\d+),(\d+)\)", text):
            which, io_unit, fmt = m.group(1), int(m.group(2)), int(m.group(3))
            want = READ_UNIT if which == "READ" else WRITE_UNIT
            if io_unit != want:
                fail(f"{which} from unit {io_unit}: the program has unit {want} only "
                     f"({'the $DATA cards' if which == 'READ' else 'the line printer'})",
                     len(which) + 1)
            items = []
            p.pos = m.end()
            if len(text) > m.end():
                while True:
                    if which == "READ":
                        at = p.pos
                        k, name = p.take()
                        if k != "name" or p.peek()[1] == "(":
                            fail("a READ list holds variables only", at)
                        items.append(name)
                    else:
                        items.append(p.expr())
                    if p.peek()[1] is None:
                        break
                    p.take(",")
            stmt = Stmt(which.lower(), label, st.line, text, (fmt, tuple(items)))
        elif text.startswith("IF("):
            p.pos = 2
            p.take("(")
            e = p.expr()
            p.take(")")
            rest = text[p.pos:]
            if not re.fullmatch(r"\d+,\d+,\d+", rest):
                whole("a logical IF (or an IF not followed by three labels) is outside the "
                      "dialect", kind="logical IF" if not rest[:1].isdigit() else None)
            stmt = Stmt("if", label, st.line, text, (e, *map(int, rest.split(","))))
            p.pos = len(text)
        elif m := re.fullmatch(r"CALL([A-Z][A-Z0-9]*)(?:\((.*)\))?", text):
            args = []
            if m.group(2):
                p.pos = m.start(2)
                while True:
                    args.append(p.expr())
                    if p.peek()[1] == ")":
                        p.take(")")
                        break
                    p.take(",")
            stmt = Stmt("call", label, st.line, text, (m.group(1), tuple(args)))
        else:
            parts = _split_top(text, "=")
            if len(parts) == 2 and (m := re.fullmatch(r"([A-Z][A-Z0-9]*)(?:\((.*)\))?",
                                                      parts[0])):
                if len(_split_top(parts[1], ",")) > 1:
                    whole("a DO loop is outside the dialect", kind="DO")
                if m.group(2) is not None:  # a statement function
                    if executable_seen:
                        whole(f"{m.group(1)}(...) = after the first executable statement: "
                              "arrays are outside the dialect, and a statement function "
                              "comes before", kind="array element or statement function")
                    dummies = tuple(m.group(2).split(","))
                    if not all(_NAME.fullmatch(d) for d in dummies):
                        whole("a statement function's dummy arguments are names")
                    p.pos = len(parts[0]) + 1
                    body = p.expr()
                    if p.peek()[1] is not None:
                        fail("unexpected text after the expression", p.pos)
                    unit.functions[m.group(1)] = (dummies, body)
                    continue
                p.pos = len(parts[0]) + 1
                e = p.expr()
                stmt = Stmt("assign", label, st.line, text, (m.group(1), e))
            else:
                whole(f"statement outside the dialect (the dialect: "
                      f"{'; '.join(STATEMENTS)})")
        if stmt.kind in ("assign", "if", "write", "read", "call") and p.peek()[1] is not None:
            fail(f"unexpected text {text[p.pos:]!r} after the statement", p.pos)
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


def _kind_name(text: str) -> str:
    """The statement kind a refused statement starts with, as a refusal names it."""
    for word in _OTHER_KINDS:
        if text.startswith(word):
            return {"DOUBLEPRECISION": "DOUBLE PRECISION", "BLOCKDATA": "BLOCK DATA",
                    "REALFUNCTION": "REAL FUNCTION",
                    "INTEGERFUNCTION": "INTEGER FUNCTION"}.get(word, word)
    for word in ("READ", "WRITE", "IF", "GOTO", "CALL", "FORMAT", "SUBROUTINE"):
        if text.startswith(word):
            return {"GOTO": "GO TO"}.get(word, word)
    return "assignment" if "=" in text else "unknown"


def _check(units: list[Unit], path) -> None:
    """What the statements must agree on: labels defined once and gone to where they are,
    FORMATs and subroutines that exist, a main program, READ and WRITE lists against their
    FORMATs' fields."""
    names = [u.name for u in units]
    if names.count("MAIN") != 1:
        raise DialectError("the program needs exactly one main program", path=path)
    subs = {u.name: u for u in units if u.name != "MAIN"}
    for u in units:
        labels = {}
        for s in u.statements:
            if s.label is not None:
                if s.label in labels or s.label in u.formats:
                    raise DialectError(f"label {s.label} defined twice in {u.name}",
                                       card=s.card, columns=(1, 5), path=path)
                labels[s.label] = s
        for s in u.statements:
            where = dict(card=s.card, path=path, kind=s.kind.upper())
            targets = {"goto": s.args[:1], "if": s.args[1:]}.get(s.kind, ())
            for t in targets:
                if t not in labels:
                    raise DialectError(f"no executable statement {t} in {u.name}", **where)
            if s.kind in ("read", "write"):
                fmt, items = s.args
                if fmt not in u.formats:
                    raise DialectError(f"no FORMAT {fmt} in {u.name}", **where)
                fields = len(re.findall(r"F\d+\.\d+", _strip_hollerith(u.formats[fmt])))
                if fields != len(items):
                    raise DialectError(f"{len(items)} items against the {fields} F fields of "
                                       f"FORMAT {fmt}", **where)
                if any((item if isinstance(item, str) else None) and kind_of(item) == "I"
                       or (not isinstance(item, str) and item[-1] == "I") for item in items):
                    raise DialectError("an INTEGER item against an F field", **where)
            if s.kind == "call":
                name, args = s.args
                if name not in subs:
                    raise DialectError(f"CALL {name}: no SUBROUTINE {name} in the program",
                                       **where)
                if len(args) != len(subs[name].dummies):
                    raise DialectError(f"CALL {name} with {len(args)} arguments, the "
                                       f"SUBROUTINE has {len(subs[name].dummies)}", **where)


def _strip_hollerith(fmt: str) -> str:
    """A FORMAT's text with its Hollerith texts left out (their letters are no fields)."""
    out, i = "", 0
    while i < len(fmt):
        m = re.match(r"(\d+)H", fmt[i:])
        if m and (i == 0 or fmt[i - 1] in "(,/"):
            i += m.end() + int(m.group(1))
            continue
        out += fmt[i]
        i += 1
    return out
