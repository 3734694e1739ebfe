"""A seeded generator of random, valid, terminating fixed-form FORTRAN IV programs in the front
end's dialect (``STATEMENTS``, ``EDIT_DESCRIPTORS``, ``INTRINSICS`` of
``deck_emulator.legacy.fortran``), each wrapped in an IBSYS job deck.

Every program is well defined by construction, so gfortran's build and the IBM FORTRAN IV rules
the front end follows give it one meaning:

* every DO runs at least once (``m1 <= m2``: constants, or a variable set just before the DO
  and assigned nowhere in its range; IBM runs a zero-trip range once, gfortran not at all);
* every value is bounded: each REAL variable keeps ``|x| <= REAL_BOUND`` and each INTEGER
  ``|k| <= INT_BOUND`` at all times (an assignment is drawn only if interval arithmetic bounds
  its expression within them), so nothing overflows, in binary64 or on the 7094; a divisor is a
  non-zero constant or ``(ABS(e) + c)`` with ``c >= 0.5``.  The exception: a data field
  punched without its point (:func:`_punch`) is read as up to six digits over ``10**d``, up to
  999999, and what is computed from it may exceed REAL_BOUND too;
* every variable is set before it is read (MAIN sets each of its own, a subprogram its locals
  on every call); COMMON is zeroed by MAIN's first statements;
* no argument is aliased: a CALL passes each variable or array at most once, never a COMMON
  variable, never an enclosing DO's variable to a dummy the callee assigns; a constant or an
  expression goes only to a dummy the callee does not assign; FUNCTIONs assign no dummy and
  no COMMON (no side effect inside an expression);
* every data field is punched in full (no blanks), every READ is on MAIN's straight line or in
  a subroutine MAIN calls once on its straight line, so the cards read are known;
* backward GO TOs only close counted loops on a counter nothing else assigns.

The weights (:data:`WEIGHTS`) draw every statement kind of ``STATEMENTS``, every edit
descriptor of ``EDIT_DESCRIPTORS`` and every intrinsic of ``INTRINSICS``; a generator that
cannot make one of a table's rows fails at import (:func:`_check_tables`), so a row added to a
table is a row the fuzzer must learn.

Switches (:data:`FEATURES`) turn off constructs whose meaning gfortran and IBM FORTRAN IV
give differently, or that gfortran folds at compile time (``const_fold``: ``**`` of a constant
base, ``SIN``/``COS`` of a constant, folded correctly rounded by gfortran; on by default off).
"""

from __future__ import annotations

import random
import re
from dataclasses import dataclass, field

from deck_emulator.legacy.fortran import EDIT_DESCRIPTORS, INTRINSICS, STATEMENTS

REAL_BOUND = 1000.0
INT_BOUND = 100
#: The FORTRAN character set of a Hollerith text (the 1967 keypunch's, less the blank at ends)
HOLLERITH_CHARS = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 =+-*/(),.$'"
#: Words a name must not start with, lest a blank-free statement read as another kind (the
#: fuzzer tests the dialect, not FORTRAN's keyword ambiguity), and names of gfortran's
#: intrinsics (a FUNCTION so named would be the intrinsic without EXTERNAL).
_KEYWORDS = ("IF", "DO", "GO", "CALL", "READ", "WRITE", "FORMAT", "ASSIGN", "RETURN", "STOP",
             "END", "CONTINUE", "COMMON", "DIMENSION", "FUNCTION", "SUBROUTINE", "DATA",
             "REAL", "INTEGER", "LOGICAL", "COMPLEX", "DOUBLE", "EXTERNAL", "EQUIVALENCE",
             "PAUSE", "PRINT", "PUNCH", "REWIND", "BACKSPACE", "ENDFILE", "BLOCK", "ENTRY",
             "PROGRAM", "SAVE", "PARAMETER", "IMPLICIT")
_GFORTRAN_INTRINSICS = set("""ABS ACOS AIMAG AINT ALOG ALOG10 AMAX0 AMAX1 AMIN0 AMIN1 AMOD ANINT
ASIN ATAN ATAN2 CABS CCOS CEXP CHAR CLOG CMPLX CONJG COS COSH CSIN CSQRT DABS DACOS DASIN DATAN
DBLE DCOS DCOSH DDIM DEXP DIM DINT DLOG DMAX1 DMIN1 DMOD DNINT DPROD DSIGN DSIN DSINH DSQRT DTAN
EXP FLOAT IABS ICHAR IDIM IDINT IDNINT IFIX INDEX INT ISIGN LEN LGE LGT LLE LLT LOG LOG10 MAX
MAX0 MAX1 MIN MIN0 MIN1 MOD NINT REAL SIGN SIN SINH SNGL SQRT TAN TANH ABORT EXIT SLEEP TIME
SIZE SHAPE SUM ALL ANY BTEST IAND IOR IEOR NOT LOC FREE DATE ERF ERFC GAMMA RAND IRAND SRAND
SECOND ETIME DTIME FDATE CTIME LSHIFT RSHIFT SHIFTL SHIFTR IBSET IBCLR IBITS HUGE TINY KIND
RANGE SCALE DIGITS EPSILON EXPONENT FRACTION SPACING RRSPACING NEAREST MERGE PACK SPREAD
UNPACK RESHAPE CSHIFT EOSHIFT DOT MATMUL MAXVAL MINVAL PRODUCT COUNT IDATE ITIME FLUSH GETARG
IARGC LNBLNK LSTAT STAT TRIM ADJUSTL ADJUSTR SCAN VERIFY REPEAT ACHAR IACHAR NULL PRESENT
SYSTEM SIGNAL UMASK UNLINK RENAME ALARM KILL HOSTNM GETCWD GETENV GETPID GETUID GETGID
ACCESS CHDIR CHMOD FSTAT FGET FPUT FGETC FPUTC FSEEK FTELL GERROR IERRNO ISATTY TTYNAM
PERROR MCLOCK TIME8 ACOSH ASINH ATANH BESJ0 BESJ1 BESY0 BESY1 HYPOT LGAMMA DLGAMA
CPU_TIME LOGICAL IMAG ATAN2D COSD SIND TAND ACOSD ASIND ATAND COTAN COTAND NORM2 PARITY
IALL IANY IPARITY POPCNT POPPAR LEADZ TRAILZ MASKL MASKR SELECTED_INT_KIND""".split())

#: Statement kinds (rows of STATEMENTS) -> relative weight of drawing one in a body.
WEIGHTS = {
    "assignment": 10, "IF (l) s": 4, "IF (e) n1, n2, n3": 2, "GO TO (n1, ...), i": 2,
    "GO TO i, (n1, ...)": 1.5, "DO n i = m1, m2, m3": 3, "CALL s(a, ...)": 3,
    "WRITE (6, n) list": 3, "GO TO n": 1, "CONTINUE": 0.5,
}
#: Switches of constructs (all on except ``const_fold``): see the module docstring and
#: docs/fuzzing.md.
FEATURES = {
    "const_fold": False,  # ** of a constant base, SIN/COS of a constant (folded by gfortran)
    "zero_power": True,  # X**0, K**0
    "f_w0": True,  # Fw.0
    "trailing_x": True,  # nX after a record's last field, or a record of nX alone
    "split_fields": True,  # continuation cards cut anywhere outside a Hollerith text
    "sfun_intrinsic_names": True,  # a statement function named ABS, SIN or COS
    "shared_names": True,  # a statement function's dummy named like a variable of the unit
    "label_names": True,  # variables named like L10 in a unit with a label 10
    "sub_reads": True,  # a READ in a subroutine, its FORMAT's label used in MAIN too
    "element_and_index": True,  # CALL S(I, A(I)) where S assigns both
    "listing_labels": True,  # labels of the listing's own (97, 99, 106, 108, ...)
    "blank_noise": True,  # blanks inside keywords and names; comment cards; columns 73-80
    # off by default (each seed keeps the program it made before this row): INTEGER
    # FUNCTIONs and statement functions, and ABS of an INTEGER, inside INTEGER expressions
    "int_calls": False,
}
_LISTING_LABELS = (41, 42, 57, 59, 82, 97, 99, 100, 106, 108, 110, 112, 125, 134, 237, 239,
                   242, 248, 300, 355, 400, 500)


def _check_tables():
    """Every row of the dialect's tables is one the generator draws (see the module doc)."""
    drawn = set(WEIGHTS) | {"statement function", "DIMENSION", "COMMON", "ASSIGN n TO i",
                            "SUBROUTINE s(a, ...)", "FUNCTION f(a, ...)", "RETURN", "STOP",
                            "END", "READ (5, n) list", "FORMAT (...)"}
    missing = set(STATEMENTS) - drawn
    if missing:
        raise RuntimeError(f"the fuzzer draws no {sorted(missing)}: teach oracle/fuzz/generate.py")
    if set(EDIT_DESCRIPTORS) - {"Fw.d", "nX", "nHtext", "/"}:
        extra = sorted(set(EDIT_DESCRIPTORS) - {"Fw.d", "nX", "nHtext", "/"})
        raise RuntimeError(f"the fuzzer draws no {extra}")
    if set(INTRINSICS) - {"SIN", "COS", "ABS"}:
        raise RuntimeError(f"the fuzzer calls no {sorted(set(INTRINSICS) - {'SIN', 'COS', 'ABS'})}")


_check_tables()


# ------------------------------------------------------------------------------- the model


@dataclass
class Sub:
    """A subprogram as callers see it."""
    name: str
    kind: str  # SUBROUTINE or FUNCTION
    dummies: list  # (name, is_array dims or None)
    assigned: set = field(default_factory=set)  # dummies it (or a callee) assigns
    commons: set = field(default_factory=set)  # block names it declares
    reads: bool = False
    bound: float = 0.0  # |value| of a FUNCTION


@dataclass
class Block:
    """A COMMON block: its places (name in MAIN, type, dims or None)."""
    name: str  # '' for blank COMMON
    places: list


@dataclass
class Card:
    """One statement as the generator made it: label, text (blanks as the generator put
    them), and whether its text holds a Hollerith text (not cut at random)."""
    label: int | None
    text: str
    hollerith: bool = False


class Gen:
    def __init__(self, seed: int, features: dict | None = None):
        self.seed = seed
        self.rng = random.Random(seed)
        self.f = dict(FEATURES, **(features or {}))
        self.used_names: set[str] = set()
        self.subs: list[Sub] = []
        self.blocks: list[Block] = []
        self.data_cards: list[str] = []
        self.reader_cards: list[str] = []  # the reader subroutine's cards
        self.shared_label: int | None = None  # its FORMAT's label, MAIN's READ's too
        self.units: list[list[Card]] = []  # MAIN first
        self.unit_names: list[str] = []

    # names -----------------------------------------------------------------------------------
    def name(self, kind: str | None = None, length: int | None = None) -> str:
        r = self.rng
        for _ in range(1000):
            n = length or r.choice((1, 1, 2, 2, 3, 4, 5, 6))
            first = r.choice("IJKLMN" if kind == "I" else "ABCDEFGHOPQRSTUVWXYZ" if kind == "R"
                             else "ABCDEFGHIJKLMNOPQRSTUVWXYZ")
            rest = "".join(r.choice("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789") for _ in range(n - 1))
            name = first + rest
            if (name in self.used_names or name in _GFORTRAN_INTRINSICS
                    or name.startswith(_KEYWORDS) or name in INTRINSICS):
                continue
            self.used_names.add(name)
            return name
        raise RuntimeError("no name left")

    # numbers ---------------------------------------------------------------------------------
    def real_const(self, lo=0.01, hi=50.0) -> tuple[str, float]:
        r = self.rng
        v = round(r.uniform(lo, hi), r.choice((0, 1, 2, 3)))
        if v == 0:
            v = 1.0
        style = r.random()
        if style < 0.1 and v >= 1:
            text = f"{v:.0f}."  # 5.
        elif style < 0.2 and v < 1:
            text = f"{v:.3f}".lstrip("0") or ".5"  # .25
        elif style < 0.3 and "e" not in f"{v * 10:.4g}":  # 24.5E-1
            mantissa = f"{v * 10:.4g}"
            text = (mantissa if "." in mantissa else mantissa + ".0") + "E-1"
        else:
            text = repr(float(v))
        return text, abs(float(text))


# -------------------------------------------------------------------------------- programs


class Unit:
    """A unit in making: its variables and their bounds, labels, FORMATs and statements."""

    def __init__(self, g: Gen, name: str, kind: str, dummies=()):
        self.g, self.name, self.kind = g, name, kind
        self.cards: list[Card] = []
        self.labels: set[int] = set()
        self.reals: list[str] = []  # scalar REAL variables that may be read (set)
        self.ints: list[str] = []
        self.arrays: dict[str, tuple[int, ...]] = {}
        self.protected: set[str] = set()  # not assigned here (DO variables of open DOs, ...)
        self.readonly: set[str] = set()  # dummies (of a FUNCTION) and COMMON (of a FUNCTION)
        self.common_names: set[str] = set()
        self.sfuns: list[tuple[str, list[str], float]] = []  # name, dummies, bound
        self.formats: dict[int, str] = {}
        self.dummies = list(dummies)
        self.assigned: set[str] = set()
        self.do_vars: list[tuple[str, int, int]] = []  # open DOs: var, lo, hi
        self.steps = 0  # statements drawn (a bound on the size)
        self.calls_left = 3
        self.blocks: list = []  # (Block, the unit's names of its places)
        self.label_name: int | None = None  # n of a variable L<n> (FEATURES label_names)

    # labels ----------------------------------------------------------------------------------
    def label(self) -> int:
        r = self.g.rng
        for _ in range(1000):
            x = r.random()
            if self.g.f["listing_labels"] and x < 0.08:
                n = r.choice(_LISTING_LABELS)
            elif x < 0.6:
                n = r.randint(1, 300)
            else:
                n = r.randint(1, 99999)
            if n not in self.labels:
                self.labels.add(n)
                return n
        raise RuntimeError("no label left")

    def emit(self, text: str, label: int | None = None, hollerith: bool = False):
        self.cards.append(Card(label, text, hollerith))

    # expressions -----------------------------------------------------------------------------
    def rexpr(self, depth: int, bound: float = REAL_BOUND, allow_calls: bool = True):
        """(text, |value| bound) of a REAL expression bounded by ``bound``."""
        for _ in range(30):
            t, b = self._r(depth, allow_calls)
            if b <= bound:
                return t, b
        return self._rleaf(bound)

    def _rleaf(self, bound=REAL_BOUND):
        r = self.g.rng
        choices = [v for v in self.reals] + [f"{a}({', '.join(self._subs(a))})"
                                             for a in self.arrays if a[0] not in "IJKLMN"]
        if choices and r.random() < 0.75:
            return r.choice(choices), REAL_BOUND
        t, v = self.g.real_const(0.01, min(bound, 50.0))
        return t, v

    def _subs(self, a):
        """In-bound subscripts of array ``a``: constants, or open DOs' variables in range."""
        r = self.g.rng
        out = []
        for d in self.arrays[a]:
            fits = [v for v, lo, hi in self.do_vars if 1 <= lo and hi <= d]
            if fits and r.random() < 0.6:
                v = r.choice(fits)
                if r.random() < 0.2:
                    lo_hi = [x for x in self.do_vars if x[0] == v][0]
                    if lo_hi[2] + 1 <= d:
                        out.append(f"{v}+1")
                        continue
                out.append(v)
            else:
                out.append(str(r.randint(1, d)))
        return out

    def _r(self, depth, allow_calls):
        r = self.g.rng
        f = self.g.f
        if depth <= 0 or r.random() < 0.25:
            return self._rleaf()
        x = r.random()
        if x < 0.40:
            op = r.choice("+-*")
            a, ab = self._r(depth - 1, allow_calls)
            b, bb = self._r(depth - 1, allow_calls)
            if op == "*" and ab * bb > REAL_BOUND:
                b, bb = self.g.real_const(0.01, 2.0)
            if op == "*":
                return f"{self._paren(a, '*')}*{self._paren(b, '*')}", ab * bb
            return f"{a} {op} {self._paren(b, op)}", ab + bb
        if x < 0.50:
            a, ab = self._r(depth - 1, allow_calls)
            if r.random() < 0.5:
                c, cv = self.g.real_const(0.5, 20.0)
                return f"{self._paren(a, '*')}/{c}", ab / cv
            d, db = self._r(depth - 1, allow_calls)
            c, cv = self.g.real_const(0.5, 5.0)
            return f"{self._paren(a, '*')}/(ABS({d}) + {c})", ab / cv
        if x < 0.58:
            a, ab = self._r(depth - 1, allow_calls)
            if not f["const_fold"] and _constant_only(a):
                a, ab = self._rvar_or(ab)
            n = r.choice((0,) * f["zero_power"] + (1, 2, 2, 3, 3, 4, 5, 6))
            if n and ab ** n > REAL_BOUND:
                a, ab = f"SIN({a})" if f["const_fold"] or not _constant_only(a) else "SIN(1.0)", 1.0
                if not f["const_fold"] and _constant_only(a):
                    a, ab = self._rvar_or(1.0)
                    if ab ** n > REAL_BOUND:
                        n = 1
            return f"{self._paren(a, '**')}**{n}", (ab ** n if n else 1.0)
        if x < 0.72:
            fn = r.choice(sorted(INTRINSICS))
            a, ab = self._r(depth - 1, allow_calls)
            if fn in ("SIN", "COS") and not f["const_fold"] and _constant_only(a):
                a, ab = self._rvar_or(ab)
            own = [b for n, _, b in self.sfuns if n == fn]
            return f"{fn}({a})", (own[0] if own else ab if fn == "ABS" else 1.0)
        if x < 0.78:
            a, ab = self._r(depth - 1, allow_calls)
            return f"-{self._paren(a, 'neg')}", ab
        if x < 0.84 and self.ints:  # (an INTEGER operand, the product REAL)
            i, ib = self.iexpr(depth - 1, INT_BOUND)
            return self._as_real(i, ib)
        sfuns = [x for x in self.sfuns if x[0] not in INTRINSICS]
        if x < 0.92 and allow_calls and sfuns:
            name, dummies, b = r.choice(sfuns)
            args = [self.rexpr(depth - 1)[0] if d[0] not in "IJKLMN"
                    else self.iexpr(depth - 1, INT_BOUND)[0] for d in dummies]
            call = f"{name}({', '.join(args)})"
            return (call, b) if _t(name) == "R" else self._as_real(call, b)
        if allow_calls:
            fns = [s for s in self.g.subs if s.kind == "FUNCTION" and self.can_call(s)]
            if fns:
                s = r.choice(fns)
                call = self.call_args(s, depth - 1, in_expr=True)
                return (call, s.bound) if _t(s.name) == "R" else self._as_real(call, s.bound)
        return self._rleaf()

    def _as_real(self, i, ib):
        """An INTEGER operand made a REAL product (a REAL expression is REAL as a whole)."""
        c, cv = self.g.real_const(0.1, 2.0)
        return f"{self._paren(i, '*')}*{c}", ib * cv

    def _rvar_or(self, ab):
        if self.reals:
            return self.g.rng.choice(self.reals), REAL_BOUND
        return "1.0", 1.0  # (no variable: constant-only stays, power of 1.0)

    @staticmethod
    def _paren(t, ctx):
        simple = t.replace("_", "").replace(".", "").isalnum() or (
            t.endswith(")") and t[0].isalpha() and _balanced_call(t))
        if ctx in ("+",) and not t.startswith("-"):
            return t
        if simple and not t.startswith("-"):
            return t
        return f"({t})"

    def iexpr(self, depth, bound=INT_BOUND):
        for _ in range(30):
            t, b = self._i(depth)
            if b <= bound:
                return t, b
        return self._ileaf()

    def _ileaf(self):
        r = self.g.rng
        if self.ints and r.random() < 0.7:
            return r.choice(self.ints), INT_BOUND
        v = r.randint(0, 20)
        return str(v), v

    def _i(self, depth):
        r = self.g.rng
        if self.g.f["int_calls"] and depth > 0 and r.random() < 0.2:
            call = self._icall(depth)
            if call:
                return call
        if depth <= 0 or r.random() < 0.3:
            return self._ileaf()
        x = r.random()
        if x < 0.5:
            op = r.choice("+-*")
            a, ab = self._i(depth - 1)
            b, bb = self._i(depth - 1)
            if op == "*":
                return f"{self._paren(a, '*')}*{self._paren(b, '*')}", ab * bb
            return f"{a} {op} {self._paren(b, op)}", ab + bb
        if x < 0.65:
            a, ab = self._i(depth - 1)
            c = r.choice((2, 3, 4, 5, 7, -3))
            return f"{self._paren(a, '*')}/{c if c > 0 else f'({c})'}", ab // abs(c) + 1
        if x < 0.75:
            a, ab = self._i(depth - 1)
            n = r.choice((0, 1, 2, 3) if self.g.f["zero_power"] else (1, 2, 3))
            return f"{self._paren(a, '**')}**{n}", (ab ** n if n else 1)
        return self._ileaf()

    def _icall(self, depth):
        """An INTEGER statement function's, FUNCTION's or ABS's value (FEATURES int_calls)."""
        r = self.g.rng
        sfuns = [x for x in self.sfuns if x[0] not in INTRINSICS and _t(x[0]) == "I"]
        fns = [s for s in self.g.subs if s.kind == "FUNCTION" and _t(s.name) == "I"
               and self.can_call(s)]
        x = r.random()
        if x < 0.35 and sfuns:
            name, dummies, b = r.choice(sfuns)
            args = [self.rexpr(depth - 1)[0] if _t(d) == "R" else self.iexpr(depth - 1)[0]
                    for d in dummies]
            return f"{name}({', '.join(args)})", b
        if x < 0.7 and fns:
            s = r.choice(fns)
            return self.call_args(s, depth - 1, in_expr=True), s.bound
        if "ABS" not in [n for n, _, _ in self.sfuns]:
            a, ab = self._i(depth - 1)
            return f"ABS({a})", ab
        return None

    def lexpr(self, depth):
        r = self.g.rng
        rel = r.choice((".LT.", ".LE.", ".EQ.", ".NE.", ".GT.", ".GE."))
        if self.ints and r.random() < 0.4:
            a, _ = self.iexpr(depth)
            b, _ = self.iexpr(depth)
        else:
            a, _ = self.rexpr(depth)
            b, _ = self.rexpr(depth)
        e = f"{a} {rel} {b}"
        x = r.random()
        if x < 0.15:
            e = f".NOT. {e}" if r.random() < 0.5 else f".NOT. ({e})"
        elif x < 0.35 and depth > 0:
            e = f"{e} {r.choice(('.AND.', '.OR.'))} {self.lexpr(depth - 1)}"
        elif x < 0.45 and depth > 0:
            e = f"({e}) {r.choice(('.AND.', '.OR.'))} .NOT. ({self.lexpr(depth - 1)})"
        return e

    # calls -----------------------------------------------------------------------------------
    def may_call(self, s: Sub) -> bool:
        """Only subprograms made after this one (no recursion); a FUNCTION calls FUNCTIONs."""
        names = self.g.unit_names
        if s.name == self.name:
            return False
        mine = names.index(self.name) if self.name in names else -1
        return names.index(s.name) > mine and not (self.kind == "FUNCTION" and s.kind != "FUNCTION")

    def call_args(self, s: Sub, depth: int, in_expr: bool = False) -> str:
        r = self.g.rng
        used: set[str] = set()
        whole = {}
        for d, dims in s.dummies:  # (arrays first: an element elsewhere may not alias them)
            if dims is not None:
                fits = [a for a in self.arrays if a not in used and a not in self.common_names
                        and _t(a) == _t(d) and self.arrays[a] == dims
                        and not (d in s.assigned and a in self.readonly)]
                whole[d] = r.choice(fits)
                used.add(whole[d])
        args = []
        for d, dims in s.dummies:
            t = _t(d)
            if dims is not None:
                args.append(whole[d])
                continue
            if d in s.assigned:
                pool = [v for v in (self.reals if t == "R" else self.ints)
                        if v not in used and v not in self.protected and v not in self.common_names
                        and v not in self.readonly]
                elems = [a for a in self.arrays if a not in used and a not in self.common_names
                         and a not in self.readonly and (a[0] in "IJKLMN") == (t == "I")]
                if elems and (r.random() < 0.3 or not pool):
                    a = r.choice(elems)
                    used.add(a)
                    args.append(f"{a}({', '.join(self._subs(a))})")
                    continue
                v = r.choice(pool)
                used.add(v)
                args.append(v)
            else:
                e = self.rexpr(depth)[0] if t == "R" else self.iexpr(depth)[0]
                args.append(e)
        # a bare variable or element (passed by reference) to a dummy the callee does not
        # assign may still change under it: through COMMON, or as another argument the
        # callee assigns -- an expression then (gfortran passes a copy)
        for k, (a, (d, dims)) in enumerate(zip(args, s.dummies)):
            m = re.fullmatch(r"([A-Z][A-Z0-9]*)(\(.*\))?", a)
            if (dims is None and d not in s.assigned and m and s.kind == "SUBROUTINE"
                    and (m.group(1) in self.common_names or m.group(1) in used)):
                args[k] = f"{a}*{'1.0' if _t(d) == 'R' else '1'}"
        return f"{s.name}({', '.join(args)})" if args or in_expr else s.name

    def can_call(self, s: Sub) -> bool:
        """Whether this unit may call ``s`` with arguments of its own that alias nothing."""
        if not self.may_call(s):
            return False
        arrays = [(d, dims) for d, dims in s.dummies if dims is not None]
        free = [a for a in self.arrays if a not in self.common_names]
        for d, dims in arrays:
            fits = [a for a in free if self.arrays[a] == dims and _t(a) == _t(d)
                    and not (d in s.assigned and a in self.readonly)]
            if not fits:
                return False
            free.remove(fits[0])
        for t in "RI":
            need = sum(1 for x, y in s.dummies if x in s.assigned and y is None and _t(x) == t)
            pool = [v for v in (self.reals if t == "R" else self.ints)
                    if v not in self.protected and v not in self.common_names
                    and v not in self.readonly]
            # the elements come from the arrays not passed whole, as in call_args
            elems = [a for a in free if a not in self.readonly and _t(a) == t]
            if len(pool) + len(elems) < need:
                return False
        return True

    def callable_subs(self):
        return [s for s in self.g.subs if s.kind == "SUBROUTINE" and not s.reads
                and self.can_call(s)]

    # statements ------------------------------------------------------------------------------
    def assignable(self, t):
        pool = [v for v in (self.reals if t == "R" else self.ints)
                if v not in self.protected and v not in self.readonly]
        return pool

    def assignment(self, depth=2) -> str | None:
        r = self.g.rng
        t = "I" if self.ints and r.random() < 0.3 else "R"
        arrays = [a for a in self.arrays if (a[0] in "IJKLMN") == (t == "I")
                  and a not in self.readonly]
        pool = self.assignable(t)
        if arrays and (r.random() < 0.3 or not pool):
            a = r.choice(arrays)
            target = f"{a}({', '.join(self._subs(a))})"
        elif pool:
            target = r.choice(pool)
        else:
            return None
        self.assigned.add(target.split("(")[0])
        if t == "R":
            return f"{target} = {self.rexpr(depth)[0]}"
        if r.random() < 0.25 and self.reals:
            return f"{target} = {self.rexpr(depth, INT_BOUND)[0]}"  # REAL made INTEGER
        return f"{target} = {self.iexpr(depth)[0]}"

    def fmt(self, n_fields: int, for_read: bool = False) -> int:
        """A FORMAT of ``n_fields`` F fields (READ: widths the data cards are punched to)."""
        r = self.g.rng
        f = self.g.f
        label = self.label()
        items: list[str] = []
        if not for_read:
            items.append(r.choice(("1X", "1H ", "1H0", f"{r.randint(1, 4)}X",
                                   self.htext(r.randint(1, 12), lead=" "))))
        k = 0
        while k < n_fields:
            if not for_read and r.random() < 0.25:
                items.append(self.htext(r.randint(1, 10)) if r.random() < 0.6
                             else f"{r.randint(1, 5)}X")
            if not for_read and r.random() < 0.08 and items and items[-1] != "/":
                items.append("/")
                items.append(r.choice(("1X", "1H ", self.htext(r.randint(1, 6), lead=" "))))
            rep = r.randint(1, n_fields - k) if r.random() < 0.3 else 1
            if for_read:
                w = r.randint(5, 12)
                d = r.randint(0, min(4, w - 3))
            else:
                w = r.randint(3, 20)
                dmax = max(0, min(10, w - 2))
                d = r.randint(0 if f["f_w0"] else min(1, dmax), dmax)
            items.append(f"{rep if rep > 1 else ''}F{w}.{d}")
            k += rep
        if not for_read and f["trailing_x"] and r.random() < 0.15:
            items.append(f"{r.randint(1, 6)}X")
        elif not for_read and r.random() < 0.15:
            items.append(self.htext(r.randint(1, 8)))
        text = "FORMAT(" + ",".join(items) + ")"
        if not for_read and r.random() < 0.1:
            text = "FORMAT(" + ",".join(items) + "/" + self.htext(r.randint(1, 8), lead=" ") + ")"
        self.formats[label] = text
        self.emit(text, label, hollerith="H" in text)
        return label

    def htext(self, n, lead=""):
        r = self.g.rng
        body = lead + "".join(r.choice(HOLLERITH_CHARS) for _ in range(n - len(lead)))
        if body.endswith(" "):
            body = body[:-1] + "X"  # (a trailing blank would be lost at the card's end)
        return f"{len(body)}H{body}"

    def write(self, depth=1):
        r = self.g.rng
        n = r.randint(1, 4)
        items = []
        for _ in range(n):
            x = r.random()
            arrays = [a for a in self.arrays if a[0] not in "IJKLMN"]
            if x < 0.55 and self.reals:
                items.append(r.choice(self.reals))
            elif x < 0.75 and arrays:
                a = r.choice(arrays)
                items.append(f"{a}({', '.join(self._subs(a))})")
            else:
                items.append(self.rexpr(depth)[0])
        label = self.fmt(len(items))
        # (the FORMAT is emitted where made: before the WRITE, any place in the unit is fine)
        return f"WRITE(6,{label}) {', '.join(items)}"

    def simple(self, depth) -> str | None:
        """A statement a logical IF may hold (no DO, no logical IF)."""
        r = self.g.rng
        x = r.random()
        if x < 0.55:
            return self.assignment(depth)
        if x < 0.75 and self.kind != "FUNCTION":
            return self.write(depth)
        if x < 0.9:
            subs = self.callable_subs()
            if subs and self.calls_left > 0:
                self.calls_left -= 1
                return "CALL " + self.call_args(r.choice(subs), depth)
        return self.assignment(depth)

    def body(self, n: int, depth: int):
        r = self.g.rng
        kinds = list(WEIGHTS)
        weights = [WEIGHTS[k] for k in kinds]
        for _ in range(n):
            self.steps += 1
            if self.steps > 60:
                return
            kind = r.choices(kinds, weights)[0]
            getattr(self, _METHODS[kind])(depth)

    # each kind (by :data:`_METHODS`) ---------------------------------------------------------
    def _assignment(self, depth):
        s = self.assignment(2)
        if s:
            self.emit(s)

    def _IFls(self, depth):  # IF (l) s
        s = self.simple(1)
        if s:
            self.emit(f"IF ({self.lexpr(1)}) {s}")

    def _IFn3(self, depth):  # IF (e) n1, n2, n3
        r = self.g.rng
        end = self.label()
        targets = [self.label() for _ in range(3)]
        e = self.rexpr(2)[0] if r.random() < 0.7 or not self.ints else self.iexpr(2)[0]
        pick = [r.choice(targets) for _ in range(3)]
        self.emit(f"IF ({e}) {pick[0]}, {pick[1]}, {pick[2]}")
        self.branches(targets, end, depth)

    def branches(self, targets, end, depth):
        r = self.g.rng
        for t in targets:
            self.emit("CONTINUE", t)
            self.body(r.randint(1, 2), depth - 1)
            self.emit(f"GO TO {end}")
        self.emit("CONTINUE", end)

    def _GOTOi(self, depth):  # computed GO TO
        r = self.g.rng
        if not self.ints:
            return
        end = self.label()
        targets = [self.label() for _ in range(r.randint(1, 3))]
        listed = [r.choice(targets) for _ in range(r.randint(1, 4))]
        i = r.choice([v for v in self.ints])
        self.emit(f"GO TO ({', '.join(map(str, listed))}), {i}")
        self.body(1, depth - 1)  # the list missed: the next statement
        self.emit(f"GO TO {end}")
        self.branches(targets, end, depth)

    def _GOTOn(self, depth):  # assigned GO TO (also: GO TO i, (n1, ...))
        r = self.g.rng
        var = self.g.name("I")
        end = self.label()
        targets = [self.label() for _ in range(r.randint(1, 3))]
        self.emit(f"ASSIGN {r.choice(targets)} TO {var}")
        if r.random() < 0.6:
            self.emit(f"IF ({self.lexpr(1)}) ASSIGN {r.choice(targets)} TO {var}")
        listed = list(dict.fromkeys(targets + [r.choice(targets)]))
        r.shuffle(listed)
        self.emit(f"GO TO {var}, ({', '.join(map(str, listed))})")
        self.branches(targets, end, depth)

    def _GOTO(self, depth):  # unconditional GO TO: forward over a block, or a counted loop back
        r = self.g.rng
        if r.random() < 0.5:
            end = self.label()
            self.emit(f"GO TO {end}")
            skipped = self.label()
            self.emit("CONTINUE", skipped)  # (unreached: only labelled statements follow a GO TO)
            self.emit(f"GO TO {end}")
            self.emit("CONTINUE", end)
            return
        counter = self.g.name("I")
        top = self.label()
        self.emit(f"{counter} = 0")
        self.emit(f"{counter} = {counter} + 1", top)
        self.protected.add(counter)
        self.body(r.randint(1, 2), depth - 1)
        self.emit(f"IF ({counter} .LT. {r.randint(1, 3)}) GO TO {top}")

    def _CONTINUE(self, depth):
        self.emit("CONTINUE", self.label())

    def _DOm3(self, depth):  # DO n i = m1, m2, m3
        r = self.g.rng
        if depth <= 0:
            return self._assignment(depth)
        var = r.choice([v for v in self.ints if v not in self.protected
                        and v not in self.common_names and v not in self.readonly] or [None])
        fresh = []  # (names made here are set on this path only: out of use after the DO)
        if var is None or r.random() < 0.5:
            var = self.g.name("I")
            self.ints.append(var)
            fresh.append(var)
        lo = r.randint(1, 3)
        hi = lo + r.randint(0, 4)
        step = r.choice((1, 1, 1, 2, 3))
        m1, m2 = str(lo), str(hi)
        if r.random() < 0.3:
            n = self.g.name("I")
            self.emit(f"{n} = {hi}")
            self.ints.append(n)
            fresh.append(n)
            self.protected.add(n)
            m2 = n
        term = self.label()
        text = f"DO {term} {var} = {m1}, {m2}"
        if step != 1 or r.random() < 0.2:
            text += f", {step}"
        self.emit(text)
        was = var in self.protected
        self.protected.add(var)
        self.do_vars.append((var, lo, hi))
        self.body(r.randint(1, 3), depth - 1)
        if r.random() < 0.3:  # out of the range early
            after = self.label()
            self.emit(f"IF ({self.lexpr(1)}) GO TO {after}")
            self.body(1, depth - 1)
            self._terminal(term, depth)
            self.emit("CONTINUE", after)
        else:
            self._terminal(term, depth)
        self.do_vars.pop()
        if not was:
            self.protected.discard(var)
        if m2 != str(hi):
            self.protected.discard(m2)
        self.ints = [v for v in self.ints if v not in fresh]

    def _terminal(self, term, depth):
        r = self.g.rng
        x = r.random()
        if x < 0.5:
            self.emit("CONTINUE", term)
        else:
            s = self.assignment(1) if x < 0.8 or self.kind == "FUNCTION" else self.write(1)
            self.emit(s or "CONTINUE", term)

    def _CALLa(self, depth):  # CALL s(a, ...)
        subs = self.callable_subs()
        if subs and self.calls_left > 0:
            self.calls_left -= 1
            self.emit("CALL " + self.call_args(self.g.rng.choice(subs), 1))

    def _WRITElist(self, depth):
        if self.kind == "FUNCTION":  # (a FUNCTION is called inside a WRITE's list: no I/O)
            return self._assignment(depth)
        self.emit(self.write(1))


#: STATEMENTS' rows drawn in a body -> the method of :class:`Unit` that makes one
_METHODS = {"assignment": "_assignment", "IF (l) s": "_IFls", "IF (e) n1, n2, n3": "_IFn3",
            "GO TO (n1, ...), i": "_GOTOi", "GO TO i, (n1, ...)": "_GOTOn",
            "DO n i = m1, m2, m3": "_DOm3", "CALL s(a, ...)": "_CALLa",
            "WRITE (6, n) list": "_WRITElist", "GO TO n": "_GOTO", "CONTINUE": "_CONTINUE"}


_NUMBER = re.compile(r"(\d+\.?\d*|\.\d+)(E[+-]?\d+)?")


def _constant_only(t: str) -> bool:
    """No variable in expression ``t`` (only constants and the intrinsics' names)."""
    return all(n in INTRINSICS for n in re.findall(r"[A-Z][A-Z0-9]*", _NUMBER.sub("0", t)))


def _balanced_call(t: str) -> bool:
    depth = 0
    for i, c in enumerate(t):
        if c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
            if depth == 0 and i != len(t) - 1:
                return False
    return depth == 0


# ------------------------------------------------------------------------------- assembling

_SHAPES = ((3,), (4,), (5,), (2, 3), (3, 2), (2, 2, 2))


def _t(name: str) -> str:
    return "I" if name[0] in "IJKLMN" else "R"


@dataclass
class FuzzProgram:
    """One generated program: its FORTRAN cards (each unit's), its data cards, its job deck."""
    seed: int
    units: list  # [(unit name, [card text, ...])]
    data: list  # data cards
    features: dict

    @property
    def source(self) -> list[str]:
        return [c for _, cards in self.units for c in cards]

    def job(self) -> list[str]:
        return job_deck(self.units, self.data, f"FZ{self.seed % 10000:04d}")


def job_deck(units, data, name="FUZZ") -> list[str]:
    """An IBSYS job deck of the units' cards and the data cards, laid out as
    ``legacy/jobdeck.py`` reads one: control cards, a ``$IBFTC`` per unit, ``$ENTRY``, one
    ``$DATA`` section, ``$IBSYS``."""
    texts = [f"$JOB           {name}", "$EXECUTE       IBJOB", "$IBJOB"]
    for unit, cards in units:
        texts.append(f"$IBFTC {unit[:6]}")
        texts += cards
    texts += ["$ENTRY         MAIN", "$DATA", *data, "$IBSYS"]
    return texts


def generate(seed: int, features: dict | None = None) -> FuzzProgram:
    """The program of ``seed`` (the same seed, the same program)."""
    g = Gen(seed, features)
    r = g.rng
    f = g.f
    # COMMON blocks: blank and named, each place a type and maybe an array shape
    for bname in ([""] if r.random() < 0.6 else []) + [g.name(length=r.randint(1, 6))
                                                        for _ in range(r.randint(0, 2))]:
        places = []
        for _ in range(r.randint(1, 4)):
            places.append((r.choice("RRRI"), r.choice(_SHAPES) if r.random() < 0.25 else None))
        g.blocks.append(Block(bname, places))
    # subprograms, made last first (a unit calls only those after it: no recursion)
    n_subs = r.randint(0, 4)
    kinds = [r.choice(("SUBROUTINE", "SUBROUTINE", "FUNCTION")) for _ in range(n_subs)]
    names = ["MAIN"] + [g.name("R" if k == "SUBROUTINE" and r.random() < 0.5 else None,
                               length=r.randint(1, 6)) for k in kinds]
    g.unit_names = names
    reader = None
    if f["sub_reads"] and "SUBROUTINE" in kinds and r.random() < 0.4:
        reader = names[1 + kinds.index("SUBROUTINE")]
    made: dict[str, list[Card]] = {}
    for k in range(n_subs, 0, -1):
        made[names[k]] = _subprogram(g, names[k], kinds[k - 1], reader == names[k])
    made["MAIN"] = _main(g, reader)
    units = [(n, _render(g, made[n])) for n in names]
    return FuzzProgram(seed, units, g.data_cards, f)


def _declare(g: Gen, u: Unit, main: bool):
    """DIMENSION and COMMON cards of unit ``u``; its COMMON names and arrays."""
    r = g.rng
    decl = []
    for b in g.blocks:
        if not main and r.random() < 0.4:
            continue
        names = []
        for t, dims in b.places:
            n = g.name(t)
            names.append(n)
            u.common_names.add(n)
            if dims:
                u.arrays[n] = dims
                decl.append(f"{n}({', '.join(map(str, dims))})")
            else:
                (u.reals if t == "R" else u.ints).append(n)
        u.emit(f"COMMON {'/' + b.name + '/ ' if b.name else ''}{', '.join(names)}")
        if b.name:
            r.random()  # (a draw kept so that each seed makes the program it made before)
        u.blocks.append((b, names))
    for _ in range(r.randint(0, 2)):
        t = r.choice("RRI")
        n = g.name(t)
        dims = r.choice(_SHAPES)
        u.arrays[n] = dims
        decl.append(f"{n}({', '.join(map(str, dims))})")
    return decl


def _locals(g: Gen, u: Unit):
    r = g.rng
    for _ in range(r.randint(1, 4)):
        u.reals.append(g.name("R"))
    for _ in range(r.randint(0, 3)):
        u.ints.append(g.name("I"))
    if g.f["label_names"] and r.random() < 0.3:
        n = f"L{r.randint(1, 300)}"
        if n not in g.used_names:
            g.used_names.add(n)
            u.ints.append(n)
            u.labels.add(int(n[1:]))  # (its label is drawn later, by name)
            u.label_name = int(n[1:])


def _init(u: Unit, names, arrays):
    """Statements that set every one of ``names`` and ``arrays`` (each call of a unit)."""
    g = u.g
    r = g.rng
    for n in names:
        if _t(n) == "R":
            u.emit(f"{n} = {'-' if r.random() < 0.3 else ''}{g.real_const(0.01, 40.0)[0]}")
        else:
            u.emit(f"{n} = {r.randint(-5, 12)}")
    for a in arrays:
        dims = u.arrays[a]
        idx = [g.name("I") for _ in dims]
        term = u.label()
        for i, d in zip(idx, dims):
            u.emit(f"DO {term} {i} = 1, {d}")
        set_ = [n for n in names if _t(n) == "R"]
        k = r.choice(set_) if set_ and _t(a) == "R" else None
        value = (f"{idx[0]}*{g.real_const(0.1, 3.0)[0]}" + (f" - {k}/100.0" if k else "")
                 if _t(a) == "R" else f"{idx[-1]} - {r.randint(0, 3)}")
        u.emit(f"{a}({', '.join(idx)}) = {value}", term)


def _sfuns(g: Gen, u: Unit):
    """Statement functions: maybe one named like an intrinsic first (one REAL dummy, a body
    without intrinsics: later ones call it where they write its name), then others of 1-3
    dummies, each over its dummies, some variables of the unit and the ones before it."""
    r = g.rng
    n = r.choice((0, 0, 1, 1, 2))
    if n and g.f["sfun_intrinsic_names"] and r.random() < 0.25:
        name = r.choice(sorted(INTRINSICS))
        d = g.name("R", length=r.randint(1, 3))
        c = g.real_const(1.0, 4.0)[0]
        body = {"ABS": f"{d}*{d}/({d}*{d} + {c})",  # (a divisor's ABS(e) + c stays >= c)
                "SIN": f"{d}/({d}*{d} + {c})", "COS": f"{c}/({d}*{d} + {c}) - 0.5"}[name]
        u.emit(f"{name}({d}) = {body}")
        u.sfuns.append((name, [d], 1.0))
        n -= 1
    for _ in range(n):
        name = g.name()
        dummies = []
        for _ in range(r.randint(1, 3)):
            pool = [v for v in u.reals + u.ints if v not in dummies]
            if g.f["shared_names"] and pool and r.random() < 0.3:
                dummies.append(r.choice(pool))
            else:
                dummies.append(g.name(r.choice("RRI")))
        saved = (u.reals, u.ints)
        u.reals = ([d for d in dummies if _t(d) == "R"]
                   + [v for v in saved[0] if v not in dummies][:2])
        u.ints = ([d for d in dummies if _t(d) == "I"]
                  + [v for v in saved[1] if v not in dummies][:1])
        arrays, u.arrays = u.arrays, {}
        if _t(name) == "R":
            body, b = u.rexpr(2, allow_calls=True)
        else:
            body, b = u.iexpr(2)
        u.reals, u.ints = saved
        u.arrays = arrays
        u.emit(f"{name}({', '.join(dummies)}) = {body}")
        u.sfuns.append((name, dummies, b))


def _subprogram(g: Gen, name: str, kind: str, reads: bool) -> list[Card]:
    r = g.rng
    u = Unit(g, name, kind)
    dummies = []
    for _ in range(0 if reads else r.randint(0 if kind == "SUBROUTINE" else 1, 3)):
        t = r.choice("RRI")
        d = g.name(t)
        dims = r.choice(_SHAPES) if r.random() < 0.25 else None
        dummies.append((d, dims))
    sub = Sub(name, kind, dummies, reads=reads)
    head = f"{kind} {name}"
    if dummies or kind == "FUNCTION":
        head += f"({', '.join(d for d, _ in dummies)})"
    u.emit(head)
    decl = [f"{d}({', '.join(map(str, dims))})" for d, dims in dummies if dims]
    for d, dims in dummies:
        if dims:
            u.arrays[d] = dims
        else:
            (u.reals if _t(d) == "R" else u.ints).append(d)
    decl += _declare(g, u, main=False)
    if decl:
        u.cards.insert(1, Card(None, "DIMENSION " + ", ".join(decl)))
    if kind == "FUNCTION":
        u.readonly |= {d for d, _ in dummies} | u.common_names
    else:
        assigned = {d for d, _ in dummies if r.random() < 0.5}
        u.readonly |= {d for d, _ in dummies} - assigned
    before = set(u.reals + u.ints)
    _locals(g, u)
    locals_ = [v for v in u.reals + u.ints if v not in before]
    local_arrays = [a for a in u.arrays if a not in u.common_names and a not in dict(dummies)]
    _sfuns(g, u)
    _init(u, locals_, local_arrays)
    if reads:
        targets = [v for v in u.reals if v not in u.readonly][:r.randint(1, 3)] or None
        if targets:
            _read(g, u, targets, share_label=True)
    u.body(r.randint(2, 6), depth=2)
    if kind == "FUNCTION":
        e, b = (u.rexpr(2) if _t(name) == "R" else u.iexpr(2))
        u.emit(f"{name} = {e}")
        sub.bound = b
    if r.random() < 0.5:
        u.emit("RETURN")
    u.emit("END")
    if kind == "SUBROUTINE":
        sub.assigned = {d for d, _ in dummies if d not in u.readonly}
    sub.commons = {b.name for b, _ in u.blocks}
    g.subs.append(sub)
    _label_named(u)
    return u.cards


def _label_named(u: Unit):
    """A variable named L<n> gets a statement labelled n in its unit (FEATURES label_names)."""
    n = u.label_name
    if n is not None:
        end = next(i for i, c in enumerate(u.cards) if c.text in ("END", "RETURN", "STOP")
                   and c.label is None)
        u.cards.insert(end, Card(n, "CONTINUE"))


def _punch(g: Gen, w: int, d: int) -> str:
    """A data field of width w punched in full (no blank): with its decimal point or without
    (then its last d digits are the fraction)."""
    r = g.rng
    neg = r.random() < 0.3
    if r.random() < 0.7:
        digits = w - 1 - neg
        frac = r.randint(0, min(3, digits - 1))
        ip = r.randint(0, 10 ** min(3, digits - frac - 1) - 1) if digits - frac - 1 > 0 else 0
        fp = r.randint(0, 10 ** frac - 1) if frac else 0
        body = f"{ip}." + (f"{fp:0{frac}d}" if frac else "")
        body = body.rjust(w - neg, "0")
    else:
        body = str(r.randint(0, 10 ** min(w - neg, 6) - 1)).rjust(w - neg, "0")
    return ("-" if neg else "") + body


def _read(g: Gen, u: Unit, targets, share_label=False):
    """READ(5, n) targets with a FORMAT of as many F fields (and X, maybe a slash): its data
    cards appended to the deck."""
    r = g.rng
    label = None
    if share_label:
        label = r.randint(1, 30)
        if label in u.labels:
            label = None
        else:
            u.labels.add(label)
            g.shared_label = label
    if label is None:
        label = u.label()
    items, cards, card, k = [], [], "", 0
    for t in targets:
        if r.random() < 0.2:
            x = r.randint(1, 4)
            items.append(f"{x}X")
            card += "".join(r.choice("0123456789") for _ in range(x))
        if r.random() < 0.1 and card:
            items.append("/")
            cards.append(card)
            card = ""
        w = r.randint(5, 12)
        d = r.randint(0, min(4, w - 3))
        items.append(f"F{w}.{d}")
        card += _punch(g, w, d)
        k += 1
    cards.append(card)
    text = "FORMAT(" + ",".join(items) + ")"
    u.formats[label] = text
    u.emit(f"READ(5,{label}) {', '.join(targets)}")
    u.emit(text, label)
    if u.kind == "MAIN":
        g.data_cards += cards
    else:  # (read when MAIN calls the reader, after MAIN's own READs)
        g.reader_cards = cards


def _main(g: Gen, reader: str | None) -> list[Card]:
    r = g.rng
    u = Unit(g, "MAIN", "MAIN")
    decl = _declare(g, u, main=True)
    if decl:
        u.cards.insert(0, Card(None, "DIMENSION " + ", ".join(decl)))
    _locals(g, u)
    while len(u.reals) < 2:
        u.reals.append(g.name("R"))
    _sfuns(g, u)
    shared = g.shared_label
    if shared is not None and shared not in u.labels:  # MAIN's own FORMAT with that label
        u.labels.add(shared)
        targets = r.sample(u.reals, min(len(u.reals), r.randint(1, 2)))
        _read_label(g, u, targets, shared)
    reads = r.sample(u.reals, min(len(u.reals), r.randint(1, 3)))
    others = [v for v in u.reals + u.ints if v not in reads]
    _init(u, others, list(u.arrays))
    _read(g, u, reads)
    if reader:
        s = next(s for s in g.subs if s.name == reader)
        u.emit("CALL " + u.call_args(s, 1))
        g.data_cards += g.reader_cards
    u.body(r.randint(4, 10), depth=3)
    u.emit(u.write(1))
    u.emit("STOP")
    u.emit("END")
    _label_named(u)
    return u.cards


def _read_label(g: Gen, u: Unit, targets, label):
    r = g.rng
    items, card = [], ""
    for _ in targets:
        w = r.randint(5, 12)
        d = r.randint(0, min(4, w - 3))
        items.append(f"F{w}.{d}")
        card += _punch(g, w, d)
    text = "FORMAT(" + ",".join(items) + ")"
    u.formats[label] = text
    u.emit(f"READ(5,{label}) {', '.join(targets)}")
    u.emit(text, label)
    g.data_cards.append(card)


# ---------------------------------------------------------------------------------- cards


def _hollerith_spans(text: str) -> list[tuple[int, int]]:
    """(start of the count, end of the text) of each nH text of a FORMAT statement's text."""
    spans, i = [], 0
    while i < len(text) and text.replace(" ", "").startswith("FORMAT"):
        m = re.match(r"(\d+)H", text[i:])
        if m and i > 0 and text[:i].rstrip()[-1:] in ("(", ",", "/"):
            end = i + m.end() + int(m.group(1))
            spans.append((i, end))
            i = end
            continue
        i += 1
    return spans


def _noisy(g: Gen, text: str) -> str:
    """The statement with blanks taken out or put in outside its Hollerith texts (FORTRAN
    ignores them)."""
    r = g.rng
    if not g.f["blank_noise"] or r.random() < 0.6:
        return text
    inside = {k for a, b in _hollerith_spans(text) for k in range(a, b)}
    mode = r.random()
    out = []
    for k, ch in enumerate(text):
        if k in inside:
            out.append(ch)
        elif ch == " " and mode < 0.5:
            continue  # all blanks out
        else:
            out.append(ch)
            if mode >= 0.5 and r.random() < 0.08:
                out.append(" ")
    return "".join(out)


def _render(g: Gen, cards: list[Card]) -> list[str]:
    """Card images: label in columns 1-5, the text from column 7, continuation cards (column 6)
    cut at random places outside Hollerith texts, comment cards, columns 73-80 at times."""
    r = g.rng
    out = []
    for c in cards:
        if g.f["blank_noise"] and r.random() < 0.05:
            words = "".join(r.choice(HOLLERITH_CHARS) for _ in range(r.randint(0, 40)))
            out.append(("C" + words).rstrip())
        text = _noisy(g, c.text)
        # a cut may not fall inside a Hollerith text or its count (the short card's blanks
        # up to column 72 would be text)
        bad = {p for a, b in _hollerith_spans(text) for p in range(a + 1, b)}
        pieces, at = [], 0
        while len(text) - at > 66 or (g.f["split_fields"] and r.random() < 0.04
                                        and len(text) - at > 3):
            cuts = [p for p in range(at + 1, min(at + 66, len(text) - 1) + 1) if p not in bad]
            if len(text) - at > 66:
                cut = r.choice(cuts[len(cuts) // 2:])
            else:
                cut = r.choice(cuts)
            pieces.append(text[at:cut])
            at = cut
        pieces.append(text[at:])
        for k, p in enumerate(pieces):
            head = (f"{c.label:>5}" if c.label is not None and k == 0 else "     ")
            mark = " " if k == 0 else r.choice("123456789*+ABX")
            line = head + mark + p
            if g.f["blank_noise"] and r.random() < 0.05:
                line = line.ljust(72) + f"FZ{r.randint(0, 999999):06d}"
            out.append(line.rstrip() if len(line) <= 72 else line)
        if any(len(line) > 80 for line in out):
            raise RuntimeError("a card longer than 80 columns")
    return out
