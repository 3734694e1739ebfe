"""IBM 7094 single-precision floating point, as the 1967 program's REAL arithmetic ran.

A word is 36 bits, sign-magnitude: sign, an 8-bit characteristic (binary exponent + 128) and
a 27-bit fraction normalised to [1/2, 1) with no hidden bit; value = (-1)**s * f *
2**(characteristic - 155).  Printed as 12 octal digits: 10.0 is ``204 500000000``.  The
operators unpack into integers, work exactly, normalise, and :func:`_pack` checks the
characteristic and builds the result, as open-simh's ``i7094_cpu1.c`` does; no binary64
arithmetic is used for any result.

Sources, cited where used below: [SIMH] open-simh ``I7094/i7094_cpu1.c`` (``op_fad``,
``op_fmp``, ``op_fdv``, ``fp_norm``, ``fp_pack``), ``i7094_cpu.c`` (``fp_trap``),
``i7094_defs.h`` (the ``FP_*`` masks); [7090RM] the IBM 7090 reference manual, 5.3.13
"Floating Point Trap".  The word's layout, underflow (a signed zero, counted in
:data:`INDICATORS`), overflow and division by zero (:class:`ArithmeticFault`) and the sign of
a zero result, with what is and is not verified: docs/emulator.md, "The 1967 machine's
arithmetic".
"""

from __future__ import annotations

import functools
import math
import numbers
import re
from fractions import Fraction

from .base import Arithmetic, ArithmeticFault

__all__ = ["Word", "IBM7094Arithmetic", "INDICATORS", "ZERO", "ONE", "MAX_WORD", "MIN_WORD"]

# --- field widths, as i7094_defs.h [SIMH] -----------------------------------------------------
_N_FR = 27  # FP_N_FR: fraction bits
_BIAS = 128  # FP_BIAS (0200): excess of the characteristic
_M_CH = 255  # FP_M_CH (0377): largest characteristic a memory word holds
_FNORM = 1 << (_N_FR - 1)  # the normalised bit of a 27-bit fraction (2**26)
_FLIM = 1 << _N_FR  # 2**27
_DNORM = 1 << 53  # FP_FNORM: normalised bit of the 54-bit AC:MQ fraction
_DCRY = 1 << 54  # FP_FCRY: carry out of the 54-bit fraction
_SCALE = _BIAS + _N_FR  # value = f * 2**(ch - _SCALE)


class _Indicators:
    """Spill counts since the last :meth:`reset` (module-wide: the operators of :class:`Word`
    have no arithmetic object to report to).  ``underflows`` counts results set to zero by
    the underflow rule above."""

    __slots__ = ("underflows",)

    def __init__(self):
        self.underflows = 0

    def reset(self):
        self.underflows = 0


INDICATORS = _Indicators()


class Word:
    """One IBM 7094 single-precision floating-point word (immutable).

    ``Word(sign, characteristic, fraction)``: ``sign`` 0 or 1, ``characteristic`` 0..255,
    ``fraction`` a 27-bit integer, normalised (``2**26 <= fraction < 2**27``) or, with
    characteristic 0, zero.  Usually made by :meth:`from_octal`, :meth:`from_fraction` or an
    arithmetic's ``decimal()``.

    ``+ - * /`` are FAD, FSB, FMP and FDP (left operand in the AC -- in the MQ for FMP);
    mixing a Word with a Python or NumPy number raises ``TypeError``.
    """

    # The fields live in private slots, read-only from outside through the properties below;
    # the operators build their results by setting the slots directly (faster than a guarded
    # __setattr__; the one place words are made: _make, _pack).
    __slots__ = ("_s", "_c", "_f")
    __array_ufunc__ = None  # NumPy: refuse mixed operations instead of making object arrays

    def __init__(self, sign: int, characteristic: int, fraction: int):
        sign, characteristic, fraction = int(sign), int(characteristic), int(fraction)
        if sign not in (0, 1):
            raise ValueError(f"sign must be 0 or 1, not {sign}")
        if not 0 <= characteristic <= _M_CH:
            raise ValueError(f"characteristic {characteristic} outside 0..255")
        if fraction == 0:
            if characteristic != 0:
                raise ValueError("a zero fraction needs characteristic 0 (the normal zero)")
        elif not _FNORM <= fraction < _FLIM:
            raise ValueError(f"fraction {fraction:o} (octal) is not a normalised 27-bit fraction")
        self._s = sign
        self._c = characteristic
        self._f = fraction

    sign = property(lambda self: self._s, doc="0 or 1 (1 for minus)")
    characteristic = property(lambda self: self._c, doc="0..255: the binary exponent + 128")
    fraction = property(lambda self: self._f, doc="the 27-bit fraction, normalised, or 0")

    def __reduce__(self):
        return (Word, (self._s, self._c, self._f))

    # --- octal: the word as IBM listings print it ------------------------------------------
    def octal(self) -> str:
        """The 36-bit word as 12 octal digits: three of sign and characteristic, nine of
        fraction."""
        return f"{(self._s << 8) | self._c:03o}{self._f:09o}"

    @classmethod
    def from_octal(cls, text: str) -> "Word":
        """The word whose 36 bits are the 12 octal digits ``text`` (blanks ignored).  Only
        normalised words and the two zeros are accepted."""
        digits = "".join(str(text).split())
        if not re.fullmatch(r"[0-7]{12}", digits):
            raise ValueError(f"{text!r} is not 12 octal digits")
        bits = int(digits, 8)
        return cls(bits >> 35, (bits >> _N_FR) & _M_CH, bits & (_FLIM - 1))

    @classmethod
    def from_fraction(cls, value, mode: str = "chop") -> "Word":
        """The word for the exact rational ``value`` (int or Fraction), its magnitude chopped
        (``mode="chop"``) or rounded to nearest, ties away from zero (``mode="round"``) to 27
        bits.  Raises :class:`ArithmeticFault` above the largest word; below the smallest it
        gives zero and counts an underflow."""
        q = Fraction(value)
        if q == 0:
            return ZERO
        return _from_ratio(abs(q.numerator), q.denominator, q < 0, mode == "round")

    # --- conversions --------------------------------------------------------------------------
    def __float__(self) -> float:
        # exact: 27 significant bits and exponents -155..+100 fit in binary64
        v = math.ldexp(self._f, self._c - _SCALE)
        return -v if self._s else v

    def exact(self) -> Fraction:
        """The exact value (a minus zero gives 0)."""
        e = self._c - _SCALE
        q = Fraction(self._f << e) if e >= 0 else Fraction(self._f, 1 << -e)
        return -q if self._s else q

    def __repr__(self) -> str:
        return f"Word({float(self)!r}, octal={self.octal()})"

    def __format__(self, spec: str) -> str:
        # float(self) is exact, so Python's formatting rounds the exact value (to nearest,
        # ties to even, as gfortran's F and E editing do)
        return format(float(self), spec)

    def __bool__(self) -> bool:
        return self._f != 0

    # --- ordering: by value, minus zero equal to zero -----------------------------------------
    def _key(self) -> int:
        # normalised words order by (characteristic, fraction) within a sign
        k = (self._c << _N_FR) | self._f if self._f else 0
        return -k if self._s else k

    def __eq__(self, other):
        if type(other) is Word:
            return self._key() == other._key()
        if isinstance(other, numbers.Number):
            raise TypeError(f"comparing a Word with {type(other).__name__}: convert explicitly")
        return NotImplemented

    def __lt__(self, other):
        if type(other) is not Word:
            return NotImplemented
        return self._key() < other._key()

    def __le__(self, other):
        if type(other) is not Word:
            return NotImplemented
        return self._key() <= other._key()

    def __gt__(self, other):
        if type(other) is not Word:
            return NotImplemented
        return self._key() > other._key()

    def __ge__(self, other):
        if type(other) is not Word:
            return NotImplemented
        return self._key() >= other._key()

    def __hash__(self):
        return hash(self._key())

    # --- sign operations: CHS/CLS and SSP only touch the sign bit [SIMH op_pse] ------------------
    def __neg__(self):
        return _make(self._s ^ 1, self._c, self._f)

    def __pos__(self):
        return self

    def __abs__(self):
        return _make(0, self._c, self._f) if self._s else self

    # --- FAD / FSB -------------------------------------------------------------------------------
    def __add__(self, other):
        if type(other) is not Word:
            return NotImplemented
        return _fad(self._s, self._c, self._f,
                    other._s, other._c, other._f)

    def __sub__(self, other):
        if type(other) is not Word:
            return NotImplemented
        # FSB is FAD with the storage operand's sign inverted [SIMH i7094_cpu.c, case 00302]
        return _fad(self._s, self._c, self._f,
                    other._s ^ 1, other._c, other._f)

    # --- FMP -------------------------------------------------------------------------------------
    def __mul__(self, other):
        if type(other) is not Word:
            return NotImplemented
        # [SIMH op_fmp] the MQ operand (self: LDQ A; FMP B) times the storage operand
        s = self._s ^ other._s
        f1, f2 = self._f, other._f
        if not f1 or not f2:
            # SR a normal zero: signed zero at once; MQ zero: the product's high part is
            # zero and the characteristic is cleared -- no spill either way
            return _ZEROS[s]
        p = f1 * f2  # the exact 54-bit product of two fractions in [1/2, 1): in [1/4, 1)
        ch = self._c + other._c - _BIAS
        if p < _DNORM:  # at most one normalising shift
            p <<= 1
            ch -= 1
        # AC keeps the high 27 bits: the exact product chopped (the MQ gets the rest)
        if 0 <= ch <= _M_CH:  # _pack's common case, inline
            w = _new(Word)
            w._s = s
            w._c = ch
            w._f = p >> _N_FR
            return w
        return _pack(s, ch, p >> _N_FR)

    # --- FDP -------------------------------------------------------------------------------------
    def __truediv__(self, other):
        if type(other) is not Word:
            return NotImplemented
        # [SIMH op_fdv] AC (self) divided by the storage operand; the quotient goes to the MQ
        s = self._s ^ other._s
        f2 = other._f
        if not f2:
            # |AC| >= 2|SR|: divide check.  The hardware sets the indicator and leaves a
            # signed-zero quotient (see the module docstring); here it is a fault.
            raise ArithmeticFault("IBM 7094 FDP divide check: division by zero")
        f1 = self._f
        if not f1:
            return _ZEROS[s]  # MQ = sign only
        ch = self._c
        if f1 >= f2:  # |AC| >= |SR|: AC fraction shifted right one place first
            num = f1 << (_N_FR - 1)
            ch += 1
        else:
            num = f1 << _N_FR
        # fp_fracdiv: 54-bit dividend / 27-bit divisor; the quotient is the exact quotient
        # chopped, already normalised because both fractions are
        return _pack(s, ch - other._c + _BIAS, num // f2)


# Fast construction: a bare object, its private slots set (no __init__ checks).
_new = object.__new__


def _make(s: int, ch: int, f: int) -> Word:
    w = _new(Word)
    w._s = s
    w._c = ch
    w._f = f
    return w


ZERO = _make(0, 0, 0)  # the machine's normal zero
_MZERO = _make(1, 0, 0)  # minus zero: sign bit alone
_ZEROS = (ZERO, _MZERO)
ONE = _make(0, _BIAS + 1, _FNORM)  # 201400000000
MAX_WORD = _make(0, _M_CH, _FLIM - 1)  # 377777777777 = (1 - 2**-27) * 2**127, ~1.70e38
MIN_WORD = _make(0, 0, _FNORM)  # 000400000000 = 2**-129, ~1.47e-39


def _pack(s: int, ch: int, f: int) -> Word:
    """Check the result characteristic and build the word (``fp_pack`` [SIMH]); ``f`` is a
    normalised 27-bit fraction."""
    if ch > _M_CH:
        # overflow: the hardware wraps the characteristic and spills (floating-point trap
        # with an overflow spill code [7090RM]); FORTRAN reported it as an error
        raise ArithmeticFault(
            f"IBM 7094 floating-point overflow: characteristic {ch} > 255 "
            f"(magnitude {math.ldexp(f, ch - _SCALE):.3e} > 1.70e38)"
        )
    if ch < 0:
        # underflow: the characteristic would wrap; the FORTRAN trap routine set the
        # register to zero (see the module docstring)
        INDICATORS.underflows += 1
        return _ZEROS[s]
    w = _new(Word)
    w._s = s
    w._c = ch
    w._f = f
    return w


def _fad(s1: int, c1: int, f1: int, s2: int, c2: int, f2: int) -> Word:
    """FAD of the AC operand (s1, c1, f1) and the storage operand (s2, c2, f2), normalised --
    ``op_fad`` [SIMH], step by step."""
    # The operand with the smaller characteristic is the one shifted.  If the AC's is the
    # larger they are swapped, so with equal characteristics op1 stays the AC.
    if c1 > c2:
        s1, c1, f1, s2, c2, f2 = s2, c2, f2, s1, c1, f1
    if s1 == s2:
        # Like signs, the common case, in 27-bit integers: the high 27 bits of the AC:MQ sum
        # below are f2 + (f1 >> gap) exactly (the low 27 bits of f2's place are zero, so the
        # bits of the shifted operand below the AC never carry into it), and at most one
        # carry shift follows; no normalising shift can (f2 is normalised, or both are zero).
        f = f2 + (f1 >> (c2 - c1))
        if f >= _FLIM:  # carry out of the pair: shift right once
            f >>= 1
            c2 += 1
        if not f:
            return _ZEROS[s2]  # both operands zero: "true zero" with the sign
        if c2 <= _M_CH:  # _pack's common case, inline (c2 >= c1 >= 0)
            w = _new(Word)
            w._s = s2
            w._c = c2
            w._f = f
            return w
        return _pack(s2, c2, f)
    # Both fractions sit in the 54-bit AC:MQ pair (MQ cleared first), the high 27 bits
    # holding the fraction.  The smaller operand is shifted right through the pair; bits
    # shifted past its low end are lost -- the one place FAD is not "exact then chop":
    # when the operand is shifted wholly out (a gap of 54 or more) an opposite-signed
    # subtraction leaves the larger operand untouched, one unit above the chopped exact
    # difference.  For gaps up to 53 a non-zero bit survives in the MQ and acts as a sticky
    # bit, so the high 27 bits equal the chopped exact result.  Shifts over 63 give zero.
    d1 = f1 << _N_FR
    d2 = f2 << _N_FR
    diff = c2 - c1
    if diff:
        d1 = d1 >> diff if diff <= 0o77 else 0
    if s1 != s2:
        # magnitudes subtracted; on a tie (exact cancellation) the result keeps op1's sign,
        # i.e. the AC's, because equal magnitudes mean equal characteristics and no swap
        if d1 >= d2:
            d = d1 - d2
            s = s1
        else:
            d = d2 - d1
            s = s2
    else:
        d = d1 + d2
        s = s2
        if d & _DCRY:  # carry out of the pair: shift right once
            d >>= 1
            c2 += 1
    if not d:
        return _ZEROS[s]  # "true zero": characteristic cleared, the sign kept
    # fp_norm: shift the pair left until bit 1 of the AC fraction is set
    sh = 54 - d.bit_length()
    if sh:
        d <<= sh
        c2 -= sh
    # the AC keeps the high 27 bits: chopped
    if 0 <= c2 <= _M_CH:  # _pack's common case, inline
        w = _new(Word)
        w._s = s
        w._c = c2
        w._f = d >> _N_FR
        return w
    return _pack(s, c2, d >> _N_FR)


def _from_ratio(n: int, d: int, negative: bool, nearest: bool) -> Word:
    """The word nearest below (``nearest`` false: magnitude chopped) or nearest to
    (ties away from zero) the exact value n/d, n > 0, d > 0."""
    e = n.bit_length() - d.bit_length()  # n/d in (2**(e-1), 2**(e+1))
    if (n >= (d << e)) if e >= 0 else ((n << -e) >= d):  # n/d >= 2**e ?
        e += 1  # now 2**(e-1) <= n/d < 2**e
    sh = _N_FR - e  # fraction = n/d * 2**(27-e), in [2**26, 2**27)
    if sh >= 0:
        f, rem = divmod(n << sh, d)
        den = d
    else:
        den = d << -sh
        f, rem = divmod(n, den)
    if nearest and 2 * rem >= den:
        f += 1
        if f == _FLIM:
            f = _FNORM
            e += 1
    return _pack(1 if negative else 0, e + _BIAS, f)


# --- SIN and COS: exact values, chopped or rounded to 27 bits --------------------------------
#
# How the IBSYS FORTRAN IV library computed SIN/COS is not known (reference-facts.md), so the
# model is an assumption: the exact value chopped (default) or rounded.  The exact value is
# computed in integer fixed point at W fractional bits with a rigorous error bound E (in units
# of 2**-W); if the interval [V-E, V+E] does not chop (round) to a single word, W grows and it
# is done again (Ziv's strategy).  For a non-zero argument sin and cos are irrational
# (Lindemann), so the loop ends; the zero argument is taken apart.

_pi_cache = [0, 0]  # [P, approximation of pi * 2**P with error <= 2 units]


def _atan_inv(x: int, g: int) -> int:
    """atan(1/x) * 2**g, error below one unit per term."""
    term = (1 << g) // x
    total = term
    x2 = x * x
    n = 1
    neg = True
    while term:
        term //= x2
        n += 2
        total = total - term // n if neg else total + term // n
        neg = not neg
    return total


def _pi_fixed(p: int) -> int:
    """pi * 2**p, within 2 units (Machin's formula in integers, 24 guard bits)."""
    have_p, have = _pi_cache
    if p > have_p:
        q = max(p, 2 * have_p, 512)
        g = q + 24
        approx = 16 * _atan_inv(5, g) - 4 * _atan_inv(239, g)  # error < g units of 2**-g
        _pi_cache[:] = [q, approx >> 24]
        have_p, have = _pi_cache
    return have >> (have_p - p)


def _taylor_fixed(r: int, w: int, first: int, n: int) -> tuple[int, int]:
    """The alternating Taylor series of sin (first term r, n = 1) or cos (first term 1, n = 0)
    at x = r / 2**w, 0 <= x < 0.8, in fixed point with w fraction bits; and its term count."""
    r2 = (r * r) >> w
    t = s = first
    k = 0
    while t:
        n += 2
        t = ((t * r2) >> w) // (n * (n - 1))
        s = s - t if k % 2 == 0 else s + t
        k += 1
    return s, k


def _sincos_scaled(f: int, ch: int, want_cos: bool, w: int) -> tuple[int, int]:
    """(V, E): V / 2**w approximates sin or cos of f * 2**(ch-155) (the magnitude of the
    argument) to within E / 2**w."""
    e = ch - _SCALE
    extra = max(0, ch - _BIAS) + 10  # bits of the quadrant count, plus guard bits
    p = w + extra
    xp = f << (e + p) if e + p >= 0 else f >> -(e + p)  # |X| * 2**p, error < 1
    h = _pi_fixed(p - 1)  # pi/2 * 2**p, error <= 2
    j = (xp + (h >> 1)) // h  # nearest multiple of pi/2
    # r = X - j*pi/2, |r| <= pi/4 + tiny; error (1 + 2j) / 2**extra + 1 <= 2 units of 2**-w
    r = (xp - j * h) >> extra
    neg_r = r < 0
    if neg_r:
        r = -r
    q = j & 3
    use_cos = want_cos ^ (q & 1)  # odd quadrants swap sin and cos
    if use_cos:
        v, k = _taylor_fixed(r, w, 1 << w, 0)
        neg = False
    else:
        v, k = _taylor_fixed(r, w, r, 1)
        neg = neg_r
    # quadrant signs: sin: +sin r, +cos r, -sin r, -cos r; cos: +cos r, -sin r, -cos r, +sin r
    if want_cos:
        if q in (1, 2):
            neg = not neg
    elif q >= 2:
        neg = not neg
    # error: 2 units from r (|sin'|, |cos'| <= 1) plus at most 3 units per series term
    # (each term's truncations, plus the r**2 error scaled by a factor < 0.11) plus the tail
    return (-v if neg else v), 4 * k + 8


def _sincos_word(x: Word, want_cos: bool, nearest: bool) -> Word:
    if not x._f:
        return ONE if want_cos else x  # cos 0 = 1 and sin(+-0) = +-0 exactly
    w = 64 + max(0, _BIAS - x._c)  # ~64 significant bits even for tiny x
    while True:
        v, err = _sincos_scaled(x._f, x._c, want_cos, w)
        lo, hi = v - err, v + err
        if (lo > 0) == (hi > 0) and lo != 0 and hi != 0:
            a = _from_ratio(abs(lo), 1 << w, lo < 0, nearest)
            b = _from_ratio(abs(hi), 1 << w, hi < 0, nearest)
            if a._s == b._s and a._c == b._c \
                    and a._f == b._f:
                if x._s and not want_cos:
                    return -a  # sin is odd
                return a
        w *= 2


#: Relative width of the interval put around the C library's binary64 sin/cos before it is
#: trusted to decide the word: 2**-36, some 10**5 times the library's error (below 2 units of
#: 2**-52 for glibc's sin and cos, whose argument reduction is exact for every argument).
_LIBM_MARGIN = 2.0**-36


def _sincos_libm(x: Word, want_cos: bool, nearest: bool) -> Word | None:
    """The word for sin or cos of x decided from the binary64 library value, or None when the
    interval of relative width _LIBM_MARGIN around it does not chop (round) to one word: then
    the exact computation decides (the same Ziv test as _sincos_word, with a cheaper first
    approximation; tests/legacy/test_ibm7094.py checks the two against each other)."""
    xf = float(x)  # exact
    v = math.cos(xf) if want_cos else math.sin(xf)
    if not 2.0**-120 < abs(v) < 2.0**120:  # near the words' range (and 0): the exact way
        return None
    a = abs(v)
    c1, f1 = _float_word(a * (1.0 - _LIBM_MARGIN), nearest)
    c2, f2 = _float_word(a * (1.0 + _LIBM_MARGIN), nearest)
    if c1 == c2 and f1 == f2:
        return _make(1 if v < 0 else 0, c1, f1)
    return None


def _float_word(y: float, nearest: bool) -> tuple[int, int]:
    """(characteristic, fraction) of the word for the positive binary64 ``y`` (2**-120 < y <
    2**120), chopped or rounded to nearest with ties away from zero: what :func:`_from_ratio`
    gives for y's exact ratio, read off ``math.frexp`` (y = m * 2**e, 1/2 <= m < 1, so the
    fraction is m * 2**27, exact in binary64, chopped; its remainder is exact too)."""
    m, e = math.frexp(y)
    t = m * _FLIM
    f = int(t)
    if nearest and t - f >= 0.5:
        f += 1
        if f == _FLIM:
            f = _FNORM
            e += 1
    return e + _BIAS, f


@functools.lru_cache(maxsize=1 << 15)
def _sincos_cached(s: int, ch: int, f: int, want_cos: bool, nearest: bool) -> Word:
    x = _make(s, ch, f)
    w = _sincos_libm(x, want_cos, nearest) if f else None
    return w if w is not None else _sincos_word(x, want_cos, nearest)


# --- decimal text -> word ----------------------------------------------------------------------

_DECIMAL_RE = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([ED][+-]?\d+)?", re.IGNORECASE)


@functools.lru_cache(maxsize=1 << 12)
def _decimal_word(text: str, nearest: bool) -> Word:
    t = text.strip()
    if not _DECIMAL_RE.fullmatch(t):
        raise ValueError(f"not a decimal constant: {text!r}")
    return Word.from_fraction(Fraction(t.upper().replace("D", "E")), "round" if nearest else "chop")


_CHOICES = {
    "sincos": ("chop", "round"),
    "decimal": ("chop", "round"),
    "output": ("nearest", "truncate"),
}


class IBM7094Arithmetic(Arithmetic):
    """REAL as the IBM 7094 computed it: :class:`Word` values, FAD/FSB/FMP/FDP semantics.

    What is not known about the 1967 software is a named assumption, chosen here and listed
    in :attr:`assumptions` (printed with the run):

    * ``sincos`` -- the FORTRAN IV library's SIN/COS: ``"chop"`` (default) the exact value
      chopped to 27 bits, or ``"round"`` rounded to nearest;
    * ``decimal`` -- conversion of decimal constants and deck fields to binary: ``"chop"``
      (default) or ``"round"`` (nearest, ties away from zero);
    * ``output`` -- F-format output: ``"nearest"`` (default, as gfortran: the exact value
      rounded to nearest) or ``"truncate"``; the printer asks :meth:`format_rounding`.
    """

    name = "ibm7094"
    #: Every word is a finite number (overflow faults instead): the emulator need not check.
    always_finite = True

    def __init__(self, *, sincos: str = "chop", decimal: str = "chop", output: str = "nearest"):
        chosen = {"sincos": sincos, "decimal": decimal, "output": output}
        for key, value in chosen.items():
            if value not in _CHOICES[key]:
                raise ValueError(
                    f"ibm7094 {key}={value!r}: choose one of {', '.join(_CHOICES[key])}"
                )
        self.assumptions = chosen
        self._sin_nearest = sincos == "round"
        self._dec_nearest = decimal == "round"
        self.indicators = INDICATORS

    # --- the interface -----------------------------------------------------------------------
    def decimal(self, text: str) -> Word:
        """The word for a decimal constant or card field (``"-58.66"``, ``"0.0004"``,
        ``"4.4E-5"``), chopped or rounded as the ``decimal`` assumption says."""
        return _decimal_word(text, self._dec_nearest)

    def sin(self, x: Word) -> Word:
        if type(x) is not Word:
            raise TypeError(f"sin of {type(x).__name__}, not Word")
        return _sincos_cached(x._s, x._c, x._f, False, self._sin_nearest)

    def cos(self, x: Word) -> Word:
        if type(x) is not Word:
            raise TypeError(f"cos of {type(x).__name__}, not Word")
        return _sincos_cached(0, x._c, x._f, True, self._sin_nearest)  # cos is even

    def sign(self, x: Word) -> int:
        if not x._f:
            return 0  # either zero
        return -1 if x._s else 1

    def isfinite(self, x) -> bool:
        if type(x) is not Word:
            raise TypeError(f"isfinite of {type(x).__name__}, not Word")
        return True  # every word is a finite number; overflow raises instead

    def exact(self, x: Word) -> Fraction:
        return x.exact()

    def to_float(self, x: Word) -> float:
        return float(x)  # exact

    def format_rounding(self) -> str:
        """How F-format output rounds, per the ``output`` assumption: ``"nearest"`` or
        ``"truncate"``."""
        return self.assumptions["output"]
