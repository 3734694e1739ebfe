"""The IBM 7094's run of a program beside its binary64 run, operation by operation, with a
running bound on their difference: the judge of a 7094 printout that the plain tolerance
(tolerance.py) puts beyond.

The plain tolerance allows some 64 units of the 7094's last place of REAL_BOUND; a program may
legitimately need more.  An error of one operation is carried forward in absolute terms and
amplified: a data field of 45207.1 is chopped by 0.00039 to 27 bits, and ``28*SIN(COS(X))``
multiplies that by 6.9; a cancellation ``X - Y`` of values near 1000 leaves an error of
2**-17 that a product with 1000 makes 0.0076.  No bound on the printed value alone covers
that; this one is computed for each program along its run.

Each value is a :class:`Pair`: the 7094's word ``w`` (the package's arithmetic), the binary64
value ``f`` (Python floats and the C library's sin/cos, as ``--precision double``) and ``e``, a
bound on ``|w - f|`` (Wilkinson's running error analysis).  With ``a``, ``b`` the operands'
binary64 values, ``Da``, ``Db`` their bounds and ``r`` the result's:

* the error each machine makes in one operation, relative to the exact result of its own
  operands: the 7094's chop of a 27-bit fraction normalised to [1/2, 1) below 2**-26, its FAD
  of a wholly shifted-out operand below 2**-52, a result below 2**-129 set to zero (an absolute
  2**-129); binary64's rounding 2**-53 and glibc's sin/cos below one unit, 2**-52;
* the exact results of the two machines' operands differ by P: ``Da + Db`` for + and -,
  ``|a| Db + |b| Da + Da Db`` for *, ``(Da |b| + |a| Db) / (|b| (|b| - Db))`` for / (no bound
  where Db >= |b|), ``Da`` for SIN, COS (their slopes are at most 1), unary minus and ABS;
* so ``|w - f| <= P (1 + 2**-26) + (2**-26 + 2**-52) |r| (1 + 2**-52) + 2**-129``, the bound
  itself computed in binary64 and widened by 2**-40 for its own rounding.

A decimal constant or card field: ``(2**-26 + 2**-52) |r| + 2**-129``.  A printed field: the two
machines' printed numbers differ by at most ``e + 10**-d`` (each rounds to nearest).

Every operation's 7094 result is checked to lie within its bound (a word outside it is a
defect of the 7094's arithmetic or of this bound: the verdict ``beyond``).  Where a comparison,
an arithmetic IF or an INTEGER conversion decides otherwise on the 7094 than in binary64 (its
operands within their bounds of each other), the two runs part: the verdict is ``diverged``,
the 7094's printout is no longer comparable and no claim is made on it.  The run goes on with
binary64's decisions, so its every later bound still holds.
"""

from __future__ import annotations

import math
from collections import deque
from fractions import Fraction

from deck_emulator.legacy.arithmetic import Arithmetic
from deck_emulator.legacy.arithmetic.ibm7094 import IBM7094Arithmetic, Word

#: the 7094's chop, relative to the exact result of its operands (27-bit fraction in [1/2, 1))
U7094 = 2.0 ** -26
#: binary64's rounding (2**-53) and glibc's sin, cos (below one unit in the last place)
U64 = 2.0 ** -52
#: below the 7094's smallest word, 2**-129, a result is set to zero
UNDERFLOW = 2.0 ** -129
#: the bound's own binary64 rounding, a few units of 2**-53 per operation, covered
WIDEN = 1.0 + 2.0 ** -40


def rounding(r: float) -> float:
    """Both machines' error in one operation whose binary64 result is ``r``."""
    return ((U7094 + U64) * abs(r) * (1.0 + U64) + UNDERFLOW) * WIDEN


def carried(p: float, r: float) -> float:
    """The bound on a result ``r`` whose operands' exact results differ by at most ``p``."""
    return (p * (1.0 + U7094)) * WIDEN + rounding(r)


class Run:
    """What one run found: the first word outside its bound, the first parting of the
    two runs, the printed fields' pairs in print order."""

    def __init__(self):
        self.outside = ""
        self.parted = ""
        self.printed: list = []
        self.pending: deque = deque()  # values printed, to be read back by the run's writes

    def check(self, what: str, v: "Pair") -> "Pair":
        if not self.outside and not abs(float(v.w) - v.f) <= v.e * WIDEN:
            self.outside = (f"{what}: 7094 {float(v.w)!r} ({v.w.octal()}), binary64 {v.f!r}, "
                            f"bound {v.e:.3g}")
        return v

    def decide(self, what: str, on_7094, on_64):
        """binary64's decision; a 7094 decision that differs parts the runs."""
        if on_7094 != on_64 and not self.parted:
            self.parted = f"{what}: the 7094 decides {on_7094}, binary64 {on_64}"
        return on_64


class Pair:
    """A REAL of both runs: the 7094's word, the binary64 value, the bound on their difference."""

    __slots__ = ("w", "f", "e", "run")
    __array_ufunc__ = None

    def __init__(self, w: Word, f: float, e: float, run: Run):
        self.w, self.f, self.e, self.run = w, f, e, run

    def _new(self, what, w, f, p):
        return self.run.check(what, Pair(w, f, carried(p, f), self.run))

    def __add__(self, o):
        return self._new("+", self.w + o.w, self.f + o.f, self.e + o.e)

    def __sub__(self, o):
        return self._new("-", self.w - o.w, self.f - o.f, self.e + o.e)

    def __mul__(self, o):
        p = abs(self.f) * o.e + abs(o.f) * self.e + self.e * o.e
        return self._new("*", self.w * o.w, self.f * o.f, p)

    def __truediv__(self, o):
        b = abs(o.f)
        p = ((self.e * b + abs(self.f) * o.e) / (b * (b - o.e)) * WIDEN if o.e < b
             else math.inf)
        return self._new("/", self.w / o.w, self.f / o.f, p)

    def __neg__(self):
        return Pair(-self.w, -self.f, self.e, self.run)

    def __pos__(self):
        return self

    def __abs__(self):
        return Pair(abs(self.w), abs(self.f), self.e, self.run)

    def _compare(self, o, op: str, test):
        return self.run.decide(f"{self.f!r} {op} {o.f!r}", test(self.w, o.w), test(self.f, o.f))

    def __lt__(self, o):
        return self._compare(o, ".LT.", lambda x, y: x < y)

    def __le__(self, o):
        return self._compare(o, ".LE.", lambda x, y: x <= y)

    def __gt__(self, o):
        return self._compare(o, ".GT.", lambda x, y: x > y)

    def __ge__(self, o):
        return self._compare(o, ".GE.", lambda x, y: x >= y)

    def __eq__(self, o):
        return self._compare(o, ".EQ.", lambda x, y: x == y)

    def __ne__(self, o):
        return self._compare(o, ".NE.", lambda x, y: x != y)

    __hash__ = None


class Lockstep(Arithmetic):
    """The arithmetic of :class:`Pair` values: a run of the front end with it is the 7094's
    run and the binary64 run at once (module docstring); :attr:`run` is what it found."""

    name = "ibm7094+double"

    def __init__(self):
        self.ibm = IBM7094Arithmetic()
        self.run = Run()

    def decimal(self, text: str) -> Pair:
        f = float(text)  # as --precision double: correctly rounded
        return self.run.check(f"decimal {text}", Pair(self.ibm.decimal(text), f, rounding(f),
                                                      self.run))

    def sin(self, x: Pair) -> Pair:
        return x._new("SIN", self.ibm.sin(x.w), math.sin(x.f), x.e)

    def cos(self, x: Pair) -> Pair:
        return x._new("COS", self.ibm.cos(x.w), math.cos(x.f), x.e)

    def sign(self, x: Pair) -> int:
        return self.run.decide(f"IF ({x.f!r})", self.ibm.sign(x.w), (x.f > 0) - (x.f < 0))

    def isfinite(self, x) -> bool:
        return math.isfinite(x.f if type(x) is Pair else x)

    def exact(self, x) -> Fraction:
        """The binary64 value, for the printer; each printed value is kept in order."""
        self.run.printed.append(x)
        self.run.pending.append(x)
        return Fraction(x.f if type(x) is Pair else x)

    def to_float(self, x) -> float:
        """The binary64 value.  The run's writes read back what was just printed; any other
        read is a REAL made INTEGER (toward zero), whose two machines' INTEGERs must agree."""
        if self.run.pending and self.run.pending[0] is x:
            self.run.pending.popleft()
        elif type(x) is Pair:
            self.run.decide(f"INTEGER of {x.f!r}", int(float(x.w)), int(x.f))
        return x.f if type(x) is Pair else float(x)


def lockstep(job: list[str]):
    """(what the run found, the run's records, each printed field as (record, column, w, d,
    value)) of the job deck's program on its data cards, through the front end's Python API
    (front.py); raises the front end's errors, but where the 7094's words, parted from their
    run, stop it (the records then None)."""
    from deck_emulator.legacy.fortran import Program
    from deck_emulator.legacy.printer import format_layout
    from deck_emulator.legacy.stops import EmulatorError

    from .front import Cards, split_job

    source, data = split_job(job)
    program = Program(source, list(range(1, len(source) + 1)), name="the fuzzed program")
    ar = Lockstep()
    runner = program.runner(Cards(data), ar)
    runner.keep_writes = True
    try:
        run = runner.run()
    except EmulatorError:
        if ar.run.parted:
            return ar.run, None, []
        raise
    fields, printed = [], iter(ar.run.printed)
    for first, unit, _card, fmt, _values in run.writes:
        for k, pieces in enumerate(format_layout(runner.formats[unit][fmt])):
            col = 0
            for piece in pieces:
                if type(piece) is str:
                    col += len(piece)
                    continue
                w, d = piece
                fields.append((first + k, col, w, d, next(printed)))
                col += w
    if next(printed, None) is not None:
        raise AssertionError("a printed value no WRITE's field accounts for")
    return ar.run, run.records, fields


def _number(text: str) -> Fraction | None:
    t = text.strip()
    return Fraction(t) if any(c.isdigit() for c in t) and "*" not in t else None


def compare_bounded(ours: str, theirs: str, records: list[str], found: Run,
                    fields: list) -> tuple[str, str]:
    """The 7094's printout ``ours`` against the oracle's ``theirs``, each printed field within
    its bound: ('within', the largest bound used), ('beyond', the first difference) or
    ('withheld', why no claim is made)."""
    if found.outside:
        return "beyond", f"a 7094 word outside its bound: {found.outside}"
    if records is None:
        return "withheld", f"the 7094's run parts from binary64's at {found.parted}, then stops"
    if records != theirs.splitlines():
        return "beyond", "the lockstep run's binary64 printout is not gfortran's"
    if found.parted:
        return "withheld", f"the 7094's run parts from binary64's at {found.parted}"
    a_lines, b_lines = ours.splitlines(), theirs.splitlines()
    if len(a_lines) != len(b_lines):
        return "beyond", f"{len(a_lines)} records on the 7094, {len(b_lines)} from gfortran"
    by_record: dict[int, list] = {}
    for n, col, w, d, value in fields:
        by_record.setdefault(n, []).append((col, w, d, value))
    widest = 0.0
    for n, (a, b) in enumerate(zip(a_lines, b_lines)):
        if a == b:
            continue
        spans = by_record.get(n, [])
        a_text, b_text = list(a), list(b)
        for col, w, _d, _v in spans:
            a_text[col:col + w] = b_text[col:col + w] = " " * w
        if len(a) != len(b) or a_text != b_text:
            return "beyond", f"record {n + 1}: 7094 {a!r}, gfortran {b!r} (outside the fields)"
        for col, w, d, value in spans:
            x, y = a[col:col + w], b[col:col + w]
            if x == y:
                continue
            fx, fy = _number(x), _number(y)
            e = value.e if type(value) is Pair else 0.0
            if fx is None or fy is None:
                return "beyond", f"record {n + 1}: 7094 {x.strip()!r}, gfortran {y.strip()!r}"
            if not math.isfinite(e):
                return "withheld", f"record {n + 1}: no bound (a divisor within its own bound)"
            if abs(fx - fy) > Fraction(e) + Fraction(1, 10 ** d):
                return "beyond", (f"record {n + 1}: 7094 {x.strip()}, gfortran {y.strip()} "
                                  f"(|difference| {float(abs(fx - fy)):.3g} > bound {e:.3g} "
                                  f"+ 1e-{d})")
            widest = max(widest, e)
    return "within", f"within the running error bound (largest {widest:.3g})"
