"""The differential fuzzer of the FORTRAN front end (the checkout's oracle/fuzz, docs/fuzzing.md):
its programs are well defined (gfortran's checked build runs each to its end), cover the
dialect's tables, and the front end prints on each what gfortran's oracle build prints; the
IBM 7094's arithmetic ends on each and agrees with binary64 within single precision.

A few dozen programs run by default; thousands with ``pytest -m slow_corpus``."""

from __future__ import annotations

import operator
import re
import tempfile
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from deck_emulator.legacy.jobdeck import statements

from test_goldens import need_gfortran
from test_ibm7094 import chopped_27

#: the default suite's programs: seeds 0..DEFAULT-1 of campaign seed SEED
SEED, DEFAULT = 46, 24
#: the slow corpus's: campaign seed SLOW_SEED (other than SEED's)
SLOW_SEED, SLOW = 4600, 2000


@pytest.fixture(autouse=True)
def _made_code_kept_in_a_temporary_folder(tmp_path, monkeypatch):
    """(a program's made code is kept in the user's cache folder: here, a temporary one)"""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))


def _fuzz():
    from oracle import fuzz
    from oracle.fuzz import campaign, classes, judge, shrink, tolerance

    return fuzz, campaign, judge, shrink, tolerance, classes


def _program(index: int, seed: int = SEED):
    fuzz, campaign, *_ = _fuzz()
    return fuzz.generate(campaign.program_seed(seed, index))


# ------------------------------------------------------------------------- the generator


def test_the_same_seed_makes_the_same_program_and_others_differ():
    fuzz, campaign, *_ = _fuzz()
    a, b = fuzz.generate(7), fuzz.generate(7)
    assert a.job() == b.job() and a.data == b.data
    jobs = {"\n".join(fuzz.generate(s).job()) for s in range(30)}
    assert len(jobs) == 30


@pytest.mark.parametrize("seed, index", [(46, 1749), (4600, 1894)])
def test_a_call_whose_array_is_passed_whole_leaves_the_generator_an_element_or_none(seed, index):
    """Each of these programs had a SUBROUTINE call whose assigned scalar dummies the
    generator counted the whole-array argument's array for, then found nothing to pass (an
    IndexError before the slow corpus's program 1894 of seed 4600 could run)."""
    fuzz, campaign, *_ = _fuzz()
    program = fuzz.generate(campaign.program_seed(seed, index))
    assert any(line.lstrip().startswith("END") for line in program.source)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 10**6), st.integers(0, 10**4))
def test_every_seed_makes_a_program(seed, index):
    fuzz, campaign, *_ = _fuzz()
    program = fuzz.generate(campaign.program_seed(seed, index))
    assert program.job() and program.source


#: a statement kind of the dialect's table -> how a program's statement (blanks removed)
#: shows it, independently of the front end's parser
_KIND_PATTERNS = {
    "assignment": r"^[A-Z][A-Z0-9]*(\([^=]*\))?=(?!.*,\d)",
    "statement function": None,  # (checked below: before the first executable statement)
    "DIMENSION": r"^DIMENSION[A-Z]",
    "COMMON": r"^COMMON",
    "CONTINUE": r"^CONTINUE$",
    "GO TO n": r"^GOTO\d+$",
    "GO TO (n1, ...), i": r"^GOTO\([\d,]+\),?[A-Z]",
    "ASSIGN n TO i": r"^ASSIGN\d+TO[A-Z]",
    "GO TO i, (n1, ...)": r"^GOTO[A-Z][A-Z0-9]*,\(",
    "IF (e) n1, n2, n3": r"^IF\(.*\)\d+,\d+,\d+$",
    "IF (l) s": r"^IF\(.*\.(LT|LE|EQ|NE|GT|GE)\..*\)[A-Z]",
    "DO n i = m1, m2, m3": r"^DO\d+[A-Z][A-Z0-9]*=",
    "CALL s(a, ...)": r"^CALL[A-Z]",
    "SUBROUTINE s(a, ...)": r"^SUBROUTINE[A-Z]",
    "FUNCTION f(a, ...)": r"^FUNCTION[A-Z]",
    "RETURN": r"^RETURN$",
    "STOP": r"^STOP$",
    "END": r"^END$",
    "READ (5, n) list": r"^READ\(5,\d+\)",
    "WRITE (6, n) list": r"^WRITE\(6,\d+\)",
    "FORMAT (...)": r"^FORMAT\(",
}
_DESCRIPTOR_PATTERNS = {"Fw.d": r"[(,/]\d*F\d+\.\d+", "nX": r"[(,/]\d+X", "nHtext": r"[(,/]\d+H",
                        "/": r"/"}


def _no_texts(fmt: str) -> str:
    """A FORMAT's text with each nH text's characters taken out (the nH kept)."""
    out, i = "", 0
    while i < len(fmt):
        m = re.match(r"(\d+)H", fmt[i:])
        if m and fmt[i - 1] in "(,/":
            out += m.group(0)
            i += m.end() + int(m.group(1))
            continue
        out += fmt[i]
        i += 1
    return out


def test_sixty_programs_draw_every_row_of_the_dialects_tables():
    """Every statement kind of STATEMENTS, edit descriptor of EDIT_DESCRIPTORS and intrinsic
    of INTRINSICS appears in the first sixty programs (read from the cards, not by the front
    end's parser)."""
    from deck_emulator.legacy.fortran import EDIT_DESCRIPTORS, INTRINSICS, STATEMENTS

    assert set(_KIND_PATTERNS) == set(STATEMENTS)  # (a new row: teach the generator and this)
    assert set(_DESCRIPTOR_PATTERNS) == set(EDIT_DESCRIPTORS)
    seen: set[str] = set()
    for k in range(60):
        texts = [s.text for s in statements(_program(k).source)]
        for kind, pattern in _KIND_PATTERNS.items():
            if pattern and any(re.search(pattern, t) for t in texts):
                seen.add(kind)
        seen |= {d for t in texts if t.startswith("FORMAT(")
                 for d, p in _DESCRIPTOR_PATTERNS.items() if re.search(p, _no_texts(t))}
        seen |= {n for t in texts for n in INTRINSICS if re.search(rf"\b{n}\(", t)}
        # a statement function: an assignment to NAME(...) before the unit's first executable
        # statement, NAME no array of the unit's DIMENSION or COMMON
        declared = ""
        for t in texts:
            if t.startswith(("DIMENSION", "COMMON", "SUBROUTINE", "FUNCTION")):
                declared += t
                continue
            m = re.match(r"^([A-Z][A-Z0-9]*)\([A-Z0-9,]*\)=", t)
            if m and not re.search(rf"[,/ NM]{m.group(1)}\(", declared):
                seen.add("statement function")
            if not m:
                declared = ""
    missing = (set(STATEMENTS) | set(EDIT_DESCRIPTORS) | set(INTRINSICS)) - seen
    assert not missing, f"no program of sixty holds {sorted(missing)}"


# --------------------------------------------------------------------- the checked build


def _checked(lines: list[str], data: list[str] = ()) -> str:
    judge = _fuzz()[2]
    with tempfile.TemporaryDirectory() as tmp:
        return judge.checked(Path(tmp), lines, list(data))


_HEAD = ["      X = 1.5", "    1 FORMAT(1X,F10.3)"]


@pytest.mark.parametrize("body, why", [
    (["      N = 0", "      DO 10 I = 1, N", "   10 X = X + 1.0", "      WRITE(6,1) X"],
     "a DO that would run no times"),
    (["      Y = Z + X", "      WRITE(6,1) Y"], "Floating-point exception"),
    (["      K = 2147483000", "      K = K + K", "      Y = K", "      WRITE(6,1) Y"],
     "Program received signal SIGABRT"),
    (["      DIMENSION A(3)", "      K = 4", "      A(K) = X", "      WRITE(6,1) A(1)"],
     "above upper bound of 3"),
    (["      IF (K .GT. 5) X = 2.0", "      WRITE(6,1) X"], "an INTEGER read before it is set"),
])
def test_the_checked_build_rejects_a_program_without_one_meaning(body, why):
    """Each construct the generator must never make: a zero-trip DO (IBM runs it once,
    gfortran not at all), a REAL read before it is set, an INTEGER overflow, a subscript out of
    bounds, an INTEGER read before it is set that decides what is printed."""
    need_gfortran()
    lines = ([b for b in body if "DIMENSION" in b] + _HEAD
             + [b for b in body if "DIMENSION" not in b] + ["      STOP", "      END"])
    assert why in _checked(lines)


def test_the_checked_build_accepts_a_well_defined_program():
    need_gfortran()
    lines = _HEAD + ["      DO 10 I = 1, 3", "   10 X = X*2.0", "      WRITE(6,1) X",
                     "      STOP", "      END"]
    assert _checked(lines) == ""


def test_the_zero_trip_guard_keeps_a_do_s_label_for_the_transfers_to_it():
    _fuzz_, _c, judge, *_ = _fuzz()
    lines = ["      N = 2", "   20 DO 10 I = 1, N", "   10 CONTINUE", "      STOP", "      END"]
    out = judge.guarded(lines)
    assert out[1] == "   20 IF((N).LT.(1))STOP 77" and out[2] == "      DO 10 I = 1, N"


@pytest.mark.parametrize("index", range(DEFAULT))
def test_a_generated_program_runs_to_its_end_in_the_checked_build(index):
    need_gfortran()
    p = _program(index)
    assert _checked(p.source, p.data) == "", "\n".join(p.job())


# ----------------------------------------------------------------------------- the verdict


def _judged(p, tmp: Path):
    judge = _fuzz()[2]
    return judge.judge(tmp, p.source, p.data, p.job(), in_process=True)


@pytest.mark.parametrize("index", range(DEFAULT))
def test_the_front_end_prints_what_gfortran_prints_on_a_generated_program(tmp_path, index):
    """The job deck through ``deck-emulator run`` (binary64) against gfortran's oracle build of
    its FORTRAN on its data cards: the same bytes; and the 7094's arithmetic ends and agrees
    within single precision (tolerance.py).  A failure shows the program's job deck:
    ``python -m oracle.fuzz.shrink`` on it gives a minimal one."""
    need_gfortran()
    p = _program(index)
    v = _judged(p, tmp_path)
    job = "\n".join(p.job())
    assert v.outcome == "agree", f"{v.outcome}: {v.why}\n{job}"
    assert v.precisions["ibm7094"] == ("within", ""), f"ibm7094: {v.precisions}\n{job}"


# --------------------------------------------------------------------- tolerance, shrinker


def test_the_7094_tolerance_is_single_precision_plus_one_printed_unit():
    tol = _fuzz()[4]
    same = " X=    12.3457  -0.50"
    assert tol.compare_within(same, same) == ("within", "")
    # 2**-20 * (12.35 + 1000) = 0.000965, plus 1e-4 (4 decimals): 0.0011 allowed
    assert tol.compare_within(" X=    12.3467  -0.50", same)[0] == "within"
    assert tol.compare_within(" X=    12.3477  -0.50", same)[0] == "beyond"
    assert tol.compare_within(" Y=    12.3457  -0.50", same)[0] == "beyond"  # a text
    assert tol.compare_within(" X=   ********  -0.50", same)[0] == "beyond"
    assert tol.compare_within(same + "\n", same + "\n X\n")[0] == "beyond"  # a record
    assert tol.compare_within(" X=    -0.0000", " X=     0.0000") == ("within", "")


# ------------------------------------------------------------ the running error bound


_CONSTANTS = st.builds(lambda k, d: f"{k / 10 ** d:.{d}f}", st.integers(-999_999, 999_999),
                       st.integers(0, 4))
_OPS = st.lists(st.tuples(st.sampled_from("+-*/"), st.integers(0, 99), st.integers(0, 99)),
                min_size=1, max_size=12)


@settings(max_examples=200, deadline=None)
@given(st.lists(_CONSTANTS, min_size=2, max_size=5), _OPS)
def test_the_running_bound_holds_for_any_27_bit_chopped_run(texts, ops):
    """Chains of + - * / on decimal constants (up to 10**6, as card fields): the lockstep's
    binary64 side is plain binary64, and its bound covers both the package's 7094 words and an
    independent 27-bit chopped computation (exact rationals, each result chopped)."""
    from oracle.fuzz.bound import Lockstep

    ar = Lockstep()
    pairs = [ar.decimal(t) for t in texts]
    floats = [float(t) for t in texts]
    chopped = [chopped_27(Fraction(t)) for t in texts]
    for op, i, j in ops:
        a, b = i % len(pairs), j % len(pairs)
        if op == "/" and not (abs(floats[b]) > 2 * pairs[b].e and chopped[b] and pairs[b].w):
            continue
        apply = {"+": operator.add, "-": operator.sub, "*": operator.mul,
                 "/": operator.truediv}[op]
        f = apply(floats[a], floats[b])
        if f and not 1e-30 < abs(f) < 1e30:  # (within the 7094's words: no overflow)
            continue
        pair = apply(pairs[a], pairs[b])
        pairs.append(pair)
        floats.append(f)
        chopped.append(chopped_27(apply(chopped[a], chopped[b])))
        assert pair.f == f
        assert abs(chopped[-1] - Fraction(f)) <= Fraction(pair.e), (op, chopped[a], chopped[b])
    assert ar.run.outside == ""


def _decimal_text(q: Fraction) -> str:
    """A decimal fraction's exact text (its denominator divides a power of ten)."""
    places = 0
    while (q * 10 ** places).denominator != 1:
        places += 1
    whole = abs(q.numerator * 10 ** places // q.denominator)
    digits = str(whole).rjust(places + 1, "0")
    point = len(digits) - places
    return ("-" if q < 0 else "") + digits[:point] + "." + digits[point:]


@settings(max_examples=300, deadline=None)
@given(_CONSTANTS, _CONSTANTS, st.sampled_from("+*"), _CONSTANTS, st.booleans())
def test_the_runs_part_where_the_7094_decides_otherwise(t1, t2, op, t3, exact_third):
    """A comparison ``(t1 op t2) .LT. t3``, t3 drawn or the exact result itself (where the two
    machines' roundings decide): the lockstep follows binary64 and says the runs part exactly
    where the 7094's decision, computed independently, is another."""
    from oracle.fuzz.bound import Lockstep

    if exact_third:
        q1, q2 = Fraction(t1), Fraction(t2)
        t3 = _decimal_text(q1 + q2 if op == "+" else q1 * q2)
    ar = Lockstep()
    a, b, c = (ar.decimal(t) for t in (t1, t2, t3))
    x, y, z = (chopped_27(Fraction(t)) for t in (t1, t2, t3))
    left = chopped_27(x + y if op == "+" else x * y)
    binary64 = (float(t1) + float(t2) if op == "+" else float(t1) * float(t2)) < float(t3)
    assert ((a + b if op == "+" else a * b) < c) is binary64
    assert bool(ar.run.parted) == ((left < z) != binary64)


def test_a_7094_word_off_by_64_units_is_outside_its_bound(monkeypatch):
    """The bound bites: a product one part in 2**20 off (what the plain tolerance allows)."""
    from deck_emulator.legacy.arithmetic.ibm7094 import Word

    from oracle.fuzz.bound import Lockstep

    real_mul = Word.__mul__

    def off(self, other):
        w = real_mul(self, other)
        return Word(w.sign, w.characteristic, w.fraction - 64)

    ar = Lockstep()
    a, b = ar.decimal("123.456"), ar.decimal("7.89")
    assert (a * b).e < 64 * 2.0 ** -27 * 1024 and ar.run.outside == ""
    monkeypatch.setattr(Word, "__mul__", off)
    a * b
    assert ar.run.outside.startswith("*: 7094 974.06")


def test_the_bound_maps_each_printed_field_past_hollerith_digits():
    """A record with a Hollerith text holding digits and a point: the fields are found by the
    FORMAT's layout, not by the look of the text."""
    from oracle.fuzz.bound import lockstep

    source = ["      X = 2.5", "      Y = X*4.0", "    1 FORMAT(1X,5H3.5 A,F8.3,2X,F6.1)",
              "      WRITE(6,1) X, Y", "      STOP", "      END"]
    job = _fuzz()[0].job_deck([("MAIN", source)], [])
    found, records, fields = lockstep(job)
    assert records == [" 3.5 A   2.500    10.0"]
    assert [(n, col, w, d, v.f) for n, col, w, d, v in fields] == [(0, 6, 8, 3, 2.5),
                                                                   (0, 16, 6, 1, 10.0)]
    assert not found.outside and not found.parted



@pytest.mark.parametrize("then, stops", [("Y = 2.0", False), ("Y = 1.0/(C - D)", True)])
def test_a_branch_the_7094_takes_otherwise_withholds_the_verdict(then, stops):
    """0.1 + 0.2 .NE. 0.3: true in binary64, false on the 7094 (independently: both sums
    chopped to 27 bits are equal).  The runs part; the verdict is withheld, also where the
    7094's words, carried on binary64's branch, divide by zero."""
    from oracle.fuzz.bound import compare_bounded, lockstep

    x, y, z = (chopped_27(Fraction(t)) for t in ("0.1", "0.2", "0.3"))
    assert chopped_27(x + y) == z and 0.1 + 0.2 != 0.3
    source = ["      A = 0.1", "      B = 0.2", "      C = A + B", "      D = 0.3",
              "      Y = 1.0", f"      IF (C .NE. D) {then}", "    1 FORMAT(1X,F30.3)",
              "      WRITE(6,1) Y", "      STOP", "      END"]
    found, records, fields = lockstep(_fuzz()[0].job_deck([("MAIN", source)], []))
    assert ".NE." in found.parted
    assert (records is None) is stops
    theirs = "".join(r + "\n" for r in records or ["?"])  # (binary64's, as gfortran's)
    status, why = compare_bounded(" " * 26 + "1.000\n", theirs, records, found, fields)
    assert status == "withheld" and why.endswith("then stops") is stops


def test_a_7094_printout_beyond_the_plain_tolerance_is_judged_by_its_bound(tmp_path):
    """Program 120 of the slow corpus (campaign seed 4600): its record 7 is 0.00272 from
    gfortran's, beyond the plain tolerance (0.000976), and within the run's bound: the 7094's
    chop of the data field 45207.1 carried through COS and SIN (test_ibm7094.py computes the
    digits independently)."""
    need_gfortran()
    p = _program(120, SLOW_SEED)
    v = _judged(p, tmp_path)
    assert v.outcome == "agree"
    status, why = v.precisions["ibm7094"]
    assert status == "within" and "running error bound" in why, why
    assert "record 7: 7094 22.168307, gfortran 22.171022" in why



def test_the_report_counts_the_7094_within_its_bound_apart():
    campaign = _fuzz()[1]
    verdicts = [("within", ""), ("within", "within the running error bound (largest 0.02)"),
                ("withheld", "the 7094's run parts ..."), ("beyond", "record 1: ..."), ()]
    results = [campaign.Result(k, k, "agree", "", "", v, []) for k, v in enumerate(verdicts)]
    assert campaign.report(results)[-1].endswith(
        "beyond 1, not run 1, withheld 1, within 1, within its run's error bound 1")


def test_ddmin_finds_a_one_minimal_sublist():
    shrink = _fuzz()[3]
    calls = []

    def needs_3_and_7(xs):
        calls.append(1)
        return 3 in xs and 7 in xs

    assert shrink.ddmin(list(range(20)), needs_3_and_7) == [3, 7]
    assert len(shrink.ddmin(list(range(20)), lambda xs: len(xs) > 4, max_tests=1000)) == 5


def test_the_shrinker_gives_a_one_minimal_well_defined_program(monkeypatch):
    """A front end that prints the last digit of its last record wrong whenever the program
    holds a ``**2``: the shrinker's program still holds it, drops what the failure does not
    need (STOP, an unread WRITE), and is 1-minimal -- without any one more statement, gfortran's
    checked build rejects it (a REAL printed or used before it is set) or it no longer
    fails."""
    need_gfortran()
    shrink = _fuzz()[3]
    judge = _fuzz()[2]
    real_front = judge.front_end

    def wrong_on_squares(tmp, job, precision="double", **kw):
        ending, text, why = real_front(tmp, job, precision, in_process=True,
                                       **{k: v for k, v in kw.items() if k != "in_process"})
        if any("**2" in line for line in job) and text:
            text = text[:-2] + ("1" if text[-2] != "1" else "2") + "\n"
        return ending, text, why

    monkeypatch.setattr(judge, "front_end", wrong_on_squares)
    source = ["      X = 1.5", "      Y = 2.0", "      Z = X + Y", "      W = Y**2",
              "    1 FORMAT(1X,F10.3)", "      WRITE(6,1) Z", "      WRITE(6,1) W", "      STOP",
              "      END"]
    src, data, v = shrink.shrink(source, [], "differ", "printed: last digits of a value",
                                 road="program")
    assert v is not None and v.outcome == "differ" and data == []
    assert "      W = Y**2" in src and "      STOP" not in src and len(src) < len(source)
    for k in range(len(src)):
        fewer = src[:k] + src[k + 1:]
        with tempfile.TemporaryDirectory() as tmp:
            w = judge.judge(Path(tmp), fewer, [], _fuzz()[0].job_deck([("MAIN", fewer)], []),
                            ibm7094=False, road="program")
        assert w.outcome != "differ", f"{src[k]!r} could go too"


# --------------------------------------------------------------------------- the large runs


@pytest.mark.slow_corpus
def test_thousands_of_generated_programs_print_what_gfortran_prints():
    need_gfortran()
    _f, campaign, *_ = _fuzz()
    results = campaign.run_campaign(SLOW_SEED, SLOW, jobs=2, progress=False)
    bad = [r for r in results if r.outcome != "agree"]
    ibm = [r for r in results if r.outcome == "agree" and r.ibm7094[:1] != ("within",)]
    summary = "\n".join(campaign.report(results))
    assert not bad and not ibm, summary


def test_the_program_road_refuses_a_data_card_in_one_line(tmp_path, capsys):
    """--road program: a data card the program's READ cannot take is refused as the command
    refuses it (exit 2, one line naming card and columns), not a traceback."""
    from oracle.fuzz import front

    job = tmp_path / "bad.job"
    job.write_text("$IBFTC MAIN\n      READ(5,1) X\n    1 FORMAT(F10.5)\n      WRITE(6,1) X\n"
                   "      STOP\n      END\n$ENTRY\n$DATA\n  ABC\n")
    assert front.main([str(job), "double", str(tmp_path / "out")]) == 2
    said = capsys.readouterr().err.strip().splitlines()
    assert len(said) == 1 and "card 1, columns 1-10" in said[0] and "not a number" in said[0]
