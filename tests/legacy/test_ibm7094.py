"""Unit tests of the IBM 7094 single-precision arithmetic (deck_emulator.legacy.arithmetic.ibm7094).

Expected words are worked out by hand from the word format, written as IBM prints them: 12
octal digits, the first three being sign (400) + characteristic (exponent + 128, octal), the
last nine the 27-bit fraction f, value = f * 2**(characteristic - 128 - 27).
"""

from __future__ import annotations

import math
import pickle
import random
from fractions import Fraction

import pytest

from deck_emulator.legacy.arithmetic import ArithmeticFault, get_arithmetic
from deck_emulator.legacy.arithmetic.ibm7094 import (
    INDICATORS,
    MAX_WORD,
    MIN_WORD,
    ONE,
    ZERO,
    IBM7094Arithmetic,
    Word,
)

AR = IBM7094Arithmetic()


def W(octal: str) -> Word:
    return Word.from_octal(octal)


def same_word(a: Word, b: Word) -> bool:
    """Identical 36-bit words (unlike ==, tells +0 from -0)."""
    return a.octal() == b.octal()


# --- word format ----------------------------------------------------------------------------


def test_ten():
    # 10.0 = 0.625 * 2**4: characteristic 128 + 4 = 132 = octal 204;
    # f = 0.625 * 2**27 = 5 * 2**24 = octal 500000000 (binary .101 000 ...)
    w = AR.decimal("10.0")
    assert w.octal() == "204500000000"
    assert (w.sign, w.characteristic, w.fraction) == (0, 132, 5 * 2**24)
    assert float(w) == 10.0


def test_one_256th():
    # 1/256 = 0.5 * 2**-7: characteristic 121 = octal 171; f = 2**26 = octal 400000000
    assert AR.decimal("0.00390625").octal() == "171400000000"
    assert Word.from_fraction(Fraction(1, 256)).octal() == "171400000000"


def test_minus_58_66chopped_27():
    # 58.66 = 0.9165625 * 2**6: characteristic 134 = octal 206, with the sign bit 606;
    # f = floor(58.66 * 2**21) = floor(123018936.32) = 123018936 = octal 725217270
    assert int("725217270", 8) == 123018936
    w = AR.decimal("-58.66")
    assert w.octal() == "606725217270"
    assert w.exact() == -Fraction(123018936, 2**21)
    assert float(w) == -123018936 / 2**21  # -58.65999984741211: chopped toward zero


def test_one_minus_2_to_minus_30_chops_to_largest_word_below_one():
    # 1 - 2**-30 lies in [1/2, 1): characteristic 128 = octal 200;
    # f = floor((1 - 2**-30) * 2**27) = floor(2**27 - 1/8) = 2**27 - 1 = octal 777777777
    w = Word.from_fraction(1 - Fraction(1, 2**30))
    assert w.octal() == "200777777777"
    assert w.exact() == 1 - Fraction(1, 2**27)
    # rounding instead would give 1.0 = 0.5 * 2**1: 201 400000000
    assert Word.from_fraction(1 - Fraction(1, 2**30), mode="round").octal() == "201400000000"


def test_one():
    assert ONE.octal() == "201400000000"
    assert AR.decimal("1.") == ONE and AR.decimal("1") == ONE and AR.decimal("+1.0E0") == ONE


def test_largest_and_smallest_words():
    # largest: characteristic 255 (377), f = 2**27 - 1: (1 - 2**-27) * 2**127 ~ 1.70e38
    assert MAX_WORD.octal() == "377777777777"
    assert MAX_WORD.exact() == (1 - Fraction(1, 2**27)) * 2**127
    assert float(MAX_WORD) == pytest.approx(1.7014118e38, rel=1e-7)
    # smallest normalised: characteristic 0, f = 2**26: 0.5 * 2**-128 = 2**-129 ~ 1.47e-39
    assert MIN_WORD.octal() == "000400000000"
    assert MIN_WORD.exact() == Fraction(1, 2**129)
    assert float(MIN_WORD) == pytest.approx(1.4693679e-39, rel=1e-7)
    # the zero word is characteristic 0 *and* fraction 0
    assert ZERO.octal() == "000000000000" and float(ZERO) == 0.0


def test_octal_round_trip_and_validation():
    for text in ("204500000000", "606725217270", "000400000000", "377777777777",
                 "400000000000"):
        assert W(text).octal() == text
    assert W("204 500000000").octal() == "204500000000"  # blanks ignored
    with pytest.raises(ValueError):
        W("204100000000")  # fraction not normalised (bit 9 clear)
    with pytest.raises(ValueError):
        W("2045")
    with pytest.raises(ValueError):
        W("204500000008")


def test_word_is_immutable_and_pickles():
    w = AR.decimal("10.0")
    with pytest.raises(AttributeError):
        w.fraction = 1
    assert pickle.loads(pickle.dumps(w)).octal() == w.octal()


def test_repr_shows_value_and_octal():
    assert repr(AR.decimal("10.0")) == "Word(10.0, octal=204500000000)"
    assert format(AR.decimal("-58.66"), ".5f") == "-58.66000"


def test_float_is_exact():
    random.seed(7094)
    for _ in range(2000):
        w = Word(random.getrandbits(1), random.randint(0, 255),
                 random.randint(2**26, 2**27 - 1))
        assert Fraction(float(w)) == w.exact()


# --- comparisons and mixing -------------------------------------------------------------------


def test_comparisons_and_minus_zero():
    a, b = AR.decimal("1.5"), AR.decimal("-2.5")
    assert b < a and a > b and a != b and not a < b
    assert AR.decimal("-1.0") < AR.decimal("-0.5") < ZERO < MIN_WORD < ONE < MAX_WORD
    mzero = -ZERO
    assert mzero.octal() == "400000000000"
    assert mzero == ZERO and not mzero < ZERO and hash(mzero) == hash(ZERO)
    assert AR.sign(mzero) == 0 and AR.sign(ZERO) == 0
    assert AR.sign(b) == -1 and AR.sign(a) == 1


def test_no_silent_mixing_with_python_numbers():
    w = AR.decimal("2.")
    for other in (2, 2.0, Fraction(2)):
        with pytest.raises(TypeError):
            w + other
        with pytest.raises(TypeError):
            other * w
        with pytest.raises(TypeError):
            w / other
        with pytest.raises(TypeError):
            w < other
        with pytest.raises(TypeError):
            w == other
    np = pytest.importorskip("numpy")
    with pytest.raises(TypeError):
        np.float64(2.0) * w


# --- FAD / FSB ----------------------------------------------------------------------------------


def test_fad_gap_54_or_more_opposite_signs_is_one_unit_above_the_chop():
    # 1.0 - 2**-60: 1.0 is 201 400000000; 2**-60 = 0.5 * 2**-59 is characteristic 69 (105),
    # f = 2**26.  Gap 129 - 69 = 60.  In the 54-bit AC:MQ pair 2**-60 is the fraction 2**53
    # shifted right 60 places: nothing is left, so 1.0 - 0 = 1.0 exactly: 201 400000000.
    # The exact difference 1 - 2**-60 chopped is 1 - 2**-27: 200 777777777, one unit less.
    a, b = ONE, Word.from_fraction(Fraction(1, 2**60))
    assert b.octal() == "105400000000"
    machine = a - b
    plain_chop = Word.from_fraction(a.exact() - b.exact())
    assert machine.octal() == "201400000000"
    assert plain_chop.octal() == "200777777777"
    # the same with a fraction that is not a power of two, and as FAD with a negative operand:
    # 1.5 + (-2**-60): machine 1.5 = 201 600000000; chop of 1.5 - 2**-60 = 1.5 - 2**-26 =
    # 201 577777777
    c = AR.decimal("1.5")
    assert (c + (-b)).octal() == "201600000000"
    assert Word.from_fraction(c.exact() - b.exact()).octal() == "201577777777"


def test_fad_gap_28_to_53_equals_the_chop():
    # With a gap of 28..53 a non-zero bit of the smaller operand stays in the MQ and acts
    # as a sticky bit: the high 27 bits equal the exact result chopped.  1.0 - 2**-40
    # (gap 40): exact 1 - 2**-40 chops to 200 777777777, and so does the machine.
    b = Word.from_fraction(Fraction(1, 2**40))
    assert (ONE - b).octal() == "200777777777"


def test_fad_matches_chop_of_exact_except_wholly_shifted_out():
    random.seed(94)
    for gap in range(0, 70):
        for _ in range(40):
            c2 = random.randint(100, 200)
            a = Word(random.getrandbits(1), c2, random.randint(2**26, 2**27 - 1))
            b = Word(random.getrandbits(1), c2 - gap, random.randint(2**26, 2**27 - 1))
            if random.getrandbits(1):
                a, b = b, a
            exact = a.exact() + b.exact()
            chop = Word.from_fraction(exact) if exact else ZERO
            if a.sign != b.sign and gap >= 54:
                # the larger operand unchanged, one unit above the chop in magnitude
                big = a if a.characteristic > b.characteristic else b
                assert same_word(a + b, big)
                unit = Fraction(2) ** (big.characteristic - 128 - 27)
                assert abs(big.exact()) - abs(chop.exact()) == unit
            else:
                assert a + b == chop


def test_one_plus_tiny():
    # 1.0 + 2**-30: exact 1 + 2**-30 chops to 1.0 (one unit at 1.0 is 2**-26)
    assert (ONE + Word.from_fraction(Fraction(1, 2**30))).octal() == "201400000000"
    # 1.0 + 2**-26 is exactly representable: f = 2**26 + 1: 201 400000001
    assert (ONE + Word.from_fraction(Fraction(1, 2**26))).octal() == "201400000001"
    # 1.0 + 3 * 2**-28 = 1 + 0.75 unit: chopped to 1.0
    assert (ONE + Word.from_fraction(Fraction(3, 2**28))).octal() == "201400000000"


def test_exact_cancellation_gives_zero_with_the_sign_of_the_ac():
    one, mone = ONE, -ONE
    assert (one - one).octal() == "000000000000"  # +0
    assert (mone - mone).octal() == "400000000000"  # -0: the AC (left operand) was minus
    assert (one + mone).octal() == "000000000000"
    assert (mone + one).octal() == "400000000000"
    assert (mone - mone) == ZERO and AR.sign(mone - mone) == 0


def test_add_carry_renormalises():
    # 0.75 + 0.75 = 1.5: f = 3 * 2**25 + 3 * 2**25 carries out; shift right, characteristic+1
    x = AR.decimal("0.75")
    assert (x + x).octal() == "201600000000"


# --- FMP / FDP ----------------------------------------------------------------------------------


def test_fmp_chops_where_rounding_differs():
    # 3.0 = 202 600000000 (f = 3 * 2**25); 0.7 chopped: f = floor(0.7 * 2**27) =
    # floor(93952409.6) = 93952409 = 546314631, characteristic 200.
    # product of fractions 3 * 2**25 * 93952409 = 9457559157080064 >= 2**53: no shift;
    # characteristic 130 + 128 - 128 = 130; f = floor(3 * 93952409 / 4) = floor(70464306.75)
    # = 70464306 = 414631462.  Rounding would give 70464307 = 414631463.
    a, b = AR.decimal("3.0"), AR.decimal("0.7")
    assert b.octal() == "200546314631"
    assert (a * b).octal() == "202414631462"
    assert Word.from_fraction(a.exact() * b.exact(), mode="round").octal() == "202414631463"
    assert (a * b) == (b * a)


def test_fmp_normalising_shift():
    # (1 - 2**-27)**2: f = (2**27 - 1)**2 = 2**54 - 2**28 + 1 >= 2**53, no shift;
    # high 27 bits: 2**27 - 2: 200 777777776
    c = W("200777777777")
    assert (c * c).octal() == "200777777776"
    # 0.5 * 0.5: f = 2**52 < 2**53: shift left once, characteristic 128+128-128-1 = 127
    h = AR.decimal("0.5")
    assert (h * h).octal() == "177400000000"


def test_fdp_chops_where_rounding_differs():
    # 1.0 / 7.0: 1.0 = 201 400000000 (f = 2**26); 7.0 = 203 700000000 (f = 7 * 2**24).
    # f1 < f2, so the dividend fraction is 2**26 * 2**27 and the quotient
    # floor(2**53 / (7 * 2**24)) = floor(2**29 / 7) = floor(76695844.571) = 76695844
    # = 444444444; characteristic 129 - 131 + 128 = 126 = 176.  Rounded: 444444445.
    q = ONE / AR.decimal("7.0")
    assert q.octal() == "176444444444"
    assert Word.from_fraction(Fraction(1, 7), mode="round").octal() == "176444444445"
    # |AC| >= |SR|: 7.0 / 2.0 shifts the dividend right first: 3.5 = 202 700000000
    assert (AR.decimal("7.0") / AR.decimal("2.0")).octal() == "202700000000"


def test_fmp_fdp_are_exact_resultschopped_27():
    random.seed(7090)
    for _ in range(3000):
        a = Word(random.getrandbits(1), random.randint(70, 186), random.randint(2**26, 2**27 - 1))
        b = Word(random.getrandbits(1), random.randint(70, 186), random.randint(2**26, 2**27 - 1))
        assert a * b == Word.from_fraction(a.exact() * b.exact())
        assert a / b == Word.from_fraction(a.exact() / b.exact())


def test_zero_operands():
    x = AR.decimal("-3.0")
    assert (ZERO * x).octal() == "400000000000"  # sign: exclusive or
    assert (ZERO / x).octal() == "400000000000"
    assert (x + ZERO).octal() == x.octal() and (ZERO + x).octal() == x.octal()
    with pytest.raises(ArithmeticFault, match="divide check"):
        x / ZERO
    with pytest.raises(ArithmeticFault):
        ZERO / ZERO


# --- underflow and overflow ---------------------------------------------------------------------


def test_underflow_gives_zero_and_is_counted():
    INDICATORS.reset()
    # 2**-129 * 2**-129: characteristic 0 + 0 - 128 - 1 < 0: underflow -> 0
    assert (MIN_WORD * MIN_WORD).octal() == "000000000000"
    assert AR.indicators.underflows == 1
    # 2**-129 / 2.0 = 2**-130: characteristic 0 - 130 + 128 = -2... (f1 < f2: no shift)
    assert (-MIN_WORD / AR.decimal("2.0")).octal() == "400000000000"  # signed zero
    # (smallest + one unit) - smallest = 2**-155: normalising shift takes it below 0
    assert (W("000400000001") - MIN_WORD).octal() == "000000000000"
    assert AR.indicators.underflows == 3
    # decimal constants below the range underflow too
    assert AR.decimal("1E-40") == ZERO
    assert INDICATORS.underflows == 4
    INDICATORS.reset()
    assert AR.indicators.underflows == 0
    # just inside: 2 * 2**-129 / 2 = 2**-129 is fine
    assert (MIN_WORD * AR.decimal("2.0") / AR.decimal("2.0")).octal() == "000400000000"
    assert AR.indicators.underflows == 0


def test_overflow_raises():
    two = AR.decimal("2.0")
    with pytest.raises(ArithmeticFault, match="overflow"):
        MAX_WORD * two
    with pytest.raises(ArithmeticFault, match="overflow"):
        MAX_WORD + MAX_WORD  # carry out: characteristic 256
    with pytest.raises(ArithmeticFault, match="overflow"):
        MAX_WORD / AR.decimal("0.5")
    with pytest.raises(ArithmeticFault, match="overflow"):
        AR.decimal("1.8E38")
    # the largest word itself is fine
    assert (MAX_WORD * ONE).octal() == "377777777777"
    assert AR.decimal("1.7E38").characteristic == 255


# --- SIN and COS --------------------------------------------------------------------------------


def test_cos_squared_minus_one_is_a_tiny_negative_number():
    # THA = 4.4E-5 chopped: 4.4e-5 = 0.72090 * 2**-14, characteristic 114 = 162;
    # f = floor(4.4e-5 * 2**41) = floor(96757023.24) = 96757023 = 561062437.
    tha = AR.decimal("4.4E-5")
    assert tha.octal() == "162561062437"
    # cos(THA) = 1 - THA**2/2 + ... = 1 - 9.68e-10: below 1 by less than one unit (2**-27 =
    # 7.45e-9 in [1/2, 1)), so chopped it is the largest word below 1: 200 777777777.
    c = AR.cos(tha)
    assert c.octal() == "200777777777"
    # c*c: f = (2**27 - 1)**2 = 2**54 - 2**28 + 1, high 27 bits 2**27 - 2: 200 777777776
    cc = c * c
    assert cc.octal() == "200777777776"
    # cc - 1.0: gap 1; AC:MQ fractions (2**27 - 2) * 2**27 >> 1 = (2**26 - 1) * 2**27 and
    # 2**26 * 2**27; difference 2**27 (the sign of 1.0's minus); normalise: shift 26
    # places, characteristic 129 - 26 = 103 = 147, f = 2**26: -2**-26 = 547 400000000
    d = cc - AR.decimal("1.0")
    assert d.octal() == "547400000000"
    assert d.exact() == -Fraction(1, 2**26)  # -1.49e-8, not zero
    assert AR.sign(d) == -1
    # (in IEEE binary32 cos(4.4e-5) rounds to 1.0 and the same expression is exactly 0)
    np = pytest.importorskip("numpy")
    c32 = np.cos(np.float32(4.4e-5))
    assert c32 * c32 - np.float32(1.0) == 0.0


def test_sin_of_small_argument_chops_below_the_argument():
    # sin x = x - x**3/6 + ...: just below x, so chopped it is the word below THA
    tha = AR.decimal("4.4E-5")
    assert AR.sin(tha).octal() == "162561062436"
    assert AR.sin(-tha).octal() == "562561062436"


def test_sin_cos_of_zero_and_exact_points():
    assert same_word(AR.sin(ZERO), ZERO) and same_word(AR.sin(-ZERO), -ZERO)
    assert AR.cos(ZERO) == ONE and AR.cos(-ZERO) == ONE


def test_sin_cos_are_the_exact_valuechopped_27():
    # independent check against binary64 libm (error ~1e-16): wherever sin(x) lies
    # clearly inside one 27-bit interval, the word must be its lower end (toward zero)
    random.seed(1967)
    checked = 0
    for _ in range(3000):
        x = Word(random.getrandbits(1), random.randint(110, 140), random.randint(2**26, 2**27 - 1))
        xf = float(x)
        for f, ref in ((AR.sin, math.sin(xf)), (AR.cos, math.cos(xf))):
            w = f(x)
            if ref == 0:
                continue
            m, e = math.frexp(abs(ref))  # |ref| = m * 2**e, m in [1/2, 1): the word's scale
            scaled = m * 2**27
            if abs(scaled - round(scaled)) < 1e-6 or abs(ref) < 1e-30:
                continue  # too close to a boundary for a binary64 reference
            assert w.sign == (ref < 0)
            assert w.characteristic == e + 128
            assert w.fraction == math.floor(scaled)
            checked += 1
    assert checked > 5000


def _ref_sin_cos(x: Fraction, want_cos: bool) -> Fraction:
    # independent reference: reduction by a 100-digit decimal pi, Taylor series in Fractions
    pi = Fraction("3.141592653589793238462643383279502884197169399375105820974944592307816406286"
                  "208998628034825342117068")
    k = round(x / (2 * pi))
    r = x - k * 2 * pi
    s, t, n = Fraction(0), (Fraction(1) if want_cos else r), (0 if want_cos else 1)
    for _ in range(40):
        s += t
        n += 2
        t = -t * r * r / ((n - 1) * n)
    return s


@pytest.mark.parametrize("text", ["1.0", "3.14159265", "-2.5", "6.2831853", "1.5707963",
                                  "100.0", "-0.7853982", "12345.678"])
def test_sin_cos_against_exact_reference(text):
    x = AR.decimal(text)
    for want_cos, f in ((False, AR.sin), (True, AR.cos)):
        exact = _ref_sin_cos(x.exact(), want_cos)
        assert f(x) == Word.from_fraction(exact)
        assert IBM7094Arithmetic(sincos="round").cos(x) == Word.from_fraction(
            _ref_sin_cos(x.exact(), True), mode="round")



def chopped_27(q: Fraction) -> Fraction:
    """q chopped to a 27-bit fraction in [1/2, 1) times a power of two (independently of the
    module: the word format alone); the fuzz tests' reference too."""
    if q == 0:
        return q
    e = abs(q).numerator.bit_length() - abs(q).denominator.bit_length()
    while abs(q) >= Fraction(2) ** e:
        e += 1
    while abs(q) < Fraction(2) ** (e - 1):
        e -= 1
    f = math.floor(abs(q) * Fraction(2) ** (27 - e))
    return (1 if q > 0 else -1) * Fraction(f) / Fraction(2) ** (27 - e)


def test_a_large_card_field_through_cos_and_sin_is_what_27_bit_chopping_gives():
    """The fuzz campaign's program 120 of seed 4600, record 7: a data field read as 45207.1,
    Q = COS(ABS(X)), then 28.0*SIN(Q) printed F9.6.  Computed independently (exact rationals,
    each result chopped to 27 bits, sin and cos by the reference above): 22.168307, where
    binary64 prints 22.171022.  The 7094 is right: 45207.1 chops by 2**-11 * 0.8 (0.00039)
    and d(28 sin(cos x))/dx there is 6.9."""
    x = chopped_27(Fraction("45207.1"))
    assert Fraction("45207.1") - x == Fraction(1, 2560)  # 0.1 - 204/2048
    q = chopped_27(_ref_sin_cos(x, True))
    s = chopped_27(_ref_sin_cos(q, False))
    product = chopped_27(28 * s)
    w = AR.decimal("28.0") * AR.sin(AR.cos(abs(AR.decimal("45207.1"))))
    assert w.exact() == product
    assert f"{float(product):9.6f}" == "22.168307"
    assert f"{28 * math.sin(math.cos(45207.1)):9.6f}" == "22.171022"


def test_sin_of_a_value_within_1000_then_a_product_is_what_27_bit_chopping_gives():
    """Program 352 of the fuzz campaign's seed 4600, record 4: card fields 779.705 and -850.9,
    then UF*SIN(S68), both within the generator's bound of 1000.  Independently: -850.9 chops
    by 6.1e-6, SIN passes that on and the product multiplies it by 780; the 7094 prints
    -354.2400741577 against binary64's -354.2358417342, 0.0042 apart (the fuzzer's plain
    tolerance, 2**-20 * (354 + 1000), is 0.0013)."""
    x = chopped_27(Fraction("-850.9"))
    assert float(Fraction("-850.9") - x) == -6.103515625e-06
    product = chopped_27(chopped_27(Fraction("779.705")) * chopped_27(_ref_sin_cos(x, False)))
    w = AR.decimal("779.705") * AR.sin(AR.decimal("-850.9"))
    assert w.exact() == product
    assert f"{float(product):.10f}" == "-354.2400741577"
    assert f"{779.705 * math.sin(-850.9):.10f}" == "-354.2358417342"

# --- the named assumptions ---------------------------------------------------------------------


def test_assumptions_are_recorded_and_printed():
    assert AR.assumptions == {"sincos": "chop", "decimal": "chop", "output": "nearest"}
    assert AR.describe() == "ibm7094 (sincos=chop, decimal=chop, output=nearest)"
    ar = get_arithmetic("ibm7094", sincos="round", decimal="round", output="truncate")
    assert isinstance(ar, IBM7094Arithmetic) and ar.name == "ibm7094"
    assert ar.assumptions == {"sincos": "round", "decimal": "round", "output": "truncate"}
    with pytest.raises(ValueError):
        IBM7094Arithmetic(sincos="nearest")
    with pytest.raises(TypeError):
        IBM7094Arithmetic(rounding="chop")


def test_sincos_assumption_is_used():
    # sin(1.0) * 2**27 = 112940323.7588...: chopped 112940323 = 656652443,
    # rounded 112940324 = 656652444 (characteristic 128)
    one = AR.decimal("1.0")
    assert IBM7094Arithmetic(sincos="chop").sin(one).octal() == "200656652443"
    assert IBM7094Arithmetic(sincos="round").sin(one).octal() == "200656652444"
    # cos(1.0) * 2**27 = 72518144.69...: 200 424505003 chopped, 200 424505004 rounded
    assert IBM7094Arithmetic(sincos="chop").cos(one).octal() == "200424505003"
    assert IBM7094Arithmetic(sincos="round").cos(one).octal() == "200424505004"


def test_decimal_assumption_is_used():
    # 0.3 = 0.6 * 2**-1: characteristic 127 = 177; 0.6 * 2**27 = 80530636.8:
    # chopped 80530636 = 463146314, rounded 80530637 = 463146315
    assert IBM7094Arithmetic(decimal="chop").decimal("0.3").octal() == "177463146314"
    assert IBM7094Arithmetic(decimal="round").decimal("0.3").octal() == "177463146315"
    # (0.1 does not tell them apart at 27 bits: 0.8 * 2**27 = 107374182.4, both 175631463146)
    assert IBM7094Arithmetic(decimal="chop").decimal("0.1").octal() == "175631463146"
    assert IBM7094Arithmetic(decimal="round").decimal("0.1").octal() == "175631463146"
    # negative fields chop toward zero, round to nearest magnitude
    assert IBM7094Arithmetic(decimal="round").decimal("-0.3").octal() == "577463146315"


def test_output_assumption_is_used():
    assert IBM7094Arithmetic().format_rounding() == "nearest"
    assert IBM7094Arithmetic(output="truncate").format_rounding() == "truncate"


def test_decimal_text_forms():
    assert AR.decimal(" 12345E2 ") == AR.decimal("1234500.")
    assert AR.decimal("1.5D0") == AR.decimal("1.5")
    assert AR.decimal(".5") == AR.decimal("0.5")
    assert AR.decimal("-0.0") == ZERO
    for bad in ("", "1.2.3", "abc", "1E", "--1"):
        with pytest.raises(ValueError):
            AR.decimal(bad)


def test_interface_helpers():
    w = AR.decimal("-58.66")
    assert AR.exact(w) == w.exact() and isinstance(AR.exact(w), Fraction)
    assert AR.to_float(w) == float(w)
    assert AR.isfinite(w) and AR.isfinite(MAX_WORD)
    assert abs(w).octal() == "206725217270" and (-w).octal() == "206725217270"


def test_sin_cos_from_the_library_value_agree_with_the_exact_computation():
    """The fast way (binary64 libm value with a 2**-36 interval) decides the same word as the
    exact fixed-point computation, or declines; over words of every size and sign."""
    import random

    from deck_emulator.legacy.arithmetic.ibm7094 import _sincos_libm, _sincos_word

    rng = random.Random(7094)
    decided = 0
    for _ in range(3000):
        ch = rng.choice([rng.randint(1, 255), rng.randint(100, 140)])
        x = Word(rng.randint(0, 1), ch, rng.randint(1 << 26, (1 << 27) - 1))
        for want_cos in (False, True):
            for nearest in (False, True):
                fast = _sincos_libm(x, want_cos, nearest)
                if fast is not None:
                    decided += 1
                    assert same_word(fast, _sincos_word(x, want_cos, nearest)), (x, want_cos, nearest)
    assert decided > 9000  # of 12000: it declines cos near 1 (tiny x) and sin of x < 2**-120
