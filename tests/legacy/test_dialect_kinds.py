"""The statement kinds of the dialect beyond the listing's own (logical IF, computed and assigned
GO TO, DO and CONTINUE, FUNCTION, COMMON, DIMENSION), each in a small program run by the FORTRAN
front end and by gfortran's build of the same source with the goldens' flags: binary64 against
the REAL*8 build, binary32 against the default-REAL build, and the 7094's arithmetic against the
REAL*8 build too (every value of these programs, 1.25 and 0.5 and what they make, is exact in
the 7094's 27-bit fraction as in binary64, so the printouts must be the same)."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import pytest

from deck_emulator.cli import main
import oracle
from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.fortran import Program
from deck_emulator.legacy.jobdeck import job_deck_texts
from deck_emulator.legacy.stops import EmulatorError

from test_emulator import ROOT
from test_goldens import need_gfortran


@pytest.fixture(autouse=True)
def _made_code_kept_in_a_temporary_folder(tmp_path, monkeypatch):
    """(a program's made code is kept in the user's cache folder: here, a temporary one)"""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))

CARD = "      1.25       0.5"  # P and Q by FORMAT 1
HEAD = """\
      READ(5,1) P, Q
    1 FORMAT(2F10.3)
    2 FORMAT(1X,3F12.4)
"""

PROGRAMS = {
    "logical IF": HEAD + """\
      X = 0.0
    5 X = X + P
      IF (X .LT. 10.0 .AND. .NOT. X .EQ. Q) GO TO 5
      IF (X .GE. 10.0) Y = X - Q
      IF (X .LT. 0.0 .OR. P .GT. Q) Y = Y*2.0
      IF (.NOT. (P .NE. 1.25)) WRITE(6,2) X, Y, P
      K = 3
      IF (K .GT. 2) CALL S(X)
      IF (K .LE. 2) CALL S(Y)
      WRITE(6,2) X, Y, Q
      STOP
      END
      SUBROUTINE S(X)
      IF (X .GT. 0.0) X = -X
      RETURN
      END
""",
    "computed GO TO": HEAD + """\
      X = 0.0
      K = 0
   10 K = K + 1
      GO TO (20, 30, 40), K
      X = X + 100.0
      GO TO 50
   20 X = X + P
      GO TO 10
   30 X = X*Q
      GO TO 10
   40 X = X - 1.0
      GO TO 10
   50 K = 0
      GO TO (60, 70), K
      WRITE(6,2) X, P, Q
   60 WRITE(6,2) Q, P, X
   70 STOP
      END
""",
    "assigned GO TO": HEAD + """\
      ASSIGN 20 TO L
      X = P
   10 X = X + Q
      GO TO L, (20, 30)
   20 WRITE(6,2) X, P, Q
      ASSIGN 30 TO L
      GO TO 10
   30 WRITE(6,2) X, Q, P
      STOP
      END
""",
    "DO": HEAD + """\
      X = 0.0
      DO 10 I = 1, 4
      X = X + P
   10 CONTINUE
      Y = 0.0
      DO 20 I = 1, 3
      DO 20 J = I, 3, 2
      IF (J .EQ. 3) GO TO 20
      Y = Y + Q
   20 Y = Y + 1.0
      WRITE(6,2) X, Y, P
      N = 5
      DO 30 K = 2, N
      IF (Z .GT. 2.0) GO TO 40
      Z = Z + P
   30 CONTINUE
   40 DO 50 I = 1, 10, 3
   50 IF (I .GT. 5) W = W + Q
      A = I
      B = K
      WRITE(6,2) Z, W, A
      WRITE(6,2) B, Q, P
      STOP
      END
""",
    "FUNCTION": HEAD + """\
      X = F(P, Q) + F(Q, P)
      K = KSQ(3)
      Y = K
      Z = G(P)*2.0
      WRITE(6,2) X, Y, Z
      WRITE(6,2) F(1.0, P), Q, G(Q)
      STOP
      END
      FUNCTION F(A, B)
      F = A*B + A
      IF (F .GT. 1.0) F = F - 1.0
      RETURN
      END
      FUNCTION KSQ(N)
      KSQ = N*N
      END
      FUNCTION G(A)
      G = F(A, 2.0) - A
      END
""",
    "COMMON": """\
      COMMON X, Y, K
      COMMON /PAIR/ U, V
""" + HEAD + """\
      X = P
      Y = Q
      K = 4
      CALL S
      WRITE(6,2) X, Y, U
      CALL T
      WRITE(6,2) U, V, X
      STOP
      END
      SUBROUTINE S
      COMMON A, B, N
      COMMON /PAIR/ C, D
      C = A + B
      D = N
      A = A*2.0
      END
      SUBROUTINE T
      COMMON /PAIR/ C(2)
      C(1) = C(2) - C(1)
      END
""",
    "DIMENSION": """\
      DIMENSION A(4), B(2,3), K(3)
""" + HEAD + """\
      DO 10 I = 1, 4
      A(I) = I
   10 A(I) = A(I)*P
      DO 20 J = 1, 3
      K(J) = 4 - J
      DO 20 I = 1, 2
   20 B(I,J) = A(I+J-1) + Q
      CALL SUM(B, 6, S)
      X = A(K(1))
      WRITE(6,2) A(4), B(2,3), S
      WRITE(6,2) X, B(1,1), B(2,1)
      CALL TWICE(A(2), 2)
      WRITE(6,2) A(1), A(2), A(3)
      STOP
      END
      SUBROUTINE SUM(V, N, S)
      DIMENSION V(N)
      S = 0.0
      DO 5 I = 1, N
    5 S = S + V(I)
      END
      SUBROUTINE TWICE(V, N)
      DIMENSION V(N)
      DO 5 I = 1, N
    5 V(I) = V(I)*2.0
      END
""",
}


@dataclass
class _Cards:
    """Data cards, as the runner reads a deck's."""
    cards: list[str]
    path: str = "data"


def _gfortran(tmp: Path, lines: list[str], build: str, cards: list[str]):
    exe = oracle.compile_source(tmp, lines, build, f"p-{build}")
    data = tmp / "data.dat"
    data.write_text("".join(c + "\n" for c in cards))
    return oracle.run_program(exe, data, timeout_s=5.0)


def _ours(lines: list[str], precision: str, cards: list[str]):
    try:
        return Program(lines).runner(_Cards(cards), precision).run(), None
    except EmulatorError as exc:
        return exc.run, exc


@pytest.mark.parametrize("precision, build", [("double", "r8"), ("single", "r4"),
                                              ("ibm7094", "r8")])
@pytest.mark.parametrize("kind", sorted(PROGRAMS))
def test_each_kind_prints_what_gfortran_prints(tmp_path, kind, precision, build):
    need_gfortran()
    lines = PROGRAMS[kind].splitlines()
    theirs, _err, ending = _gfortran(tmp_path, lines, build, [CARD])
    run, stop = _ours(lines, precision, [CARD])
    assert ending == "normal" and stop is None, stop
    assert "".join(r + "\n" for r in run.records) == theirs
    assert len(run.records) >= 2


#: SIN and COS of one angle are computed once in binary64 (kept in a local while the angle's
#: variables stand): here the first of each is in a logical IF's statement or in the right
#: operand of .AND., which do not run, and the same SIN is asked again after them
KEPT_SIN_COS = HEAD + """\
      A = -P
      B = 0.0
      IF (A .GT. 0.0) B = SIN(A)
      C = SIN(A)
      D = COS(A + Q)
      IF (A .GT. 0.0 .AND. SIN(A + Q) .GT. 0.0) B = 1.0
      E = SIN(A + Q)*COS(A + Q) + COS(A)
      WRITE(6,2) B, C, D
      WRITE(6,2) E, P, Q
      STOP
      END
"""


def test_a_sin_first_met_where_it_may_not_run_is_computed_where_it_runs(tmp_path):
    need_gfortran()
    lines = KEPT_SIN_COS.splitlines()
    theirs, _err, ending = _gfortran(tmp_path, lines, "r8", [CARD])
    run, stop = _ours(lines, "double", [CARD])
    assert ending == "normal" and stop is None, stop
    assert "".join(r + "\n" for r in run.records) == theirs


def test_a_do_range_runs_at_least_once_as_on_ibm_fortran_iv():
    """IBM 7090/7094 FORTRAN IV tests the DO variable after the range, so DO 10 I = 5, 1 runs
    its range once (gfortran's Fortran 77 rule runs it no times: no oracle here; the expected
    value is the IBM rule's: Y = 0.5 + 1.0, and I = 5 + 1)."""
    lines = (HEAD + """\
      Y = Q
      DO 10 I = 5, 1
      Y = Y + 1.0
   10 CONTINUE
      A = I
      WRITE(6,2) Y, A, P
      STOP
      END
""").splitlines()
    run, stop = _ours(lines, "double", [CARD])
    assert stop is None and run.records == ["       1.5000      6.0000      1.2500"]


# ----------------------------------------------------------------------------------- stops


def _stopped(lines, precision):
    run, stop = _ours(lines, precision, [CARD])
    assert stop is not None and "\n" not in str(stop)
    return run, stop


@pytest.mark.parametrize("precision", ["double", "single", "ibm7094"])
def test_a_value_that_overflows_in_a_do_range_of_a_function_stops_naming_it(tmp_path,
                                                                            precision):
    """X doubles 2000 times in FUNCTION BIG's DO range: gfortran's build traps on the overflow,
    after the first line; the front end stops there, naming the unit, the label and X."""
    lines = (HEAD + """\
      WRITE(6,2) P, Q, P
      Y = BIG(P)
      WRITE(6,2) Y, P, Q
      STOP
      END
      FUNCTION BIG(X)
      Z = X
    7 DO 10 I = 1, 2000
      Z = Z*2.0
   10 CONTINUE
      BIG = Z
      END
""").splitlines()
    run, stop = _stopped(lines, precision)
    assert stop.guard == "arithmetic" and stop.variable == "Z" and "BIG 7" in str(stop)
    need_gfortran()
    theirs, _err, ending = _gfortran(tmp_path, lines, "r8" if precision == "double" else "r4",
                                     [CARD])
    if precision != "ibm7094":  # (the 7094 overflows at 2**127, as binary32 does)
        assert ending == "trap"
    assert "".join(r + "\n" for r in run.records) == theirs


def test_a_nan_made_integer_stops_where_gfortran_traps(tmp_path):
    """inf - inf inside one expression, assigned to an INTEGER: gfortran's build traps
    (invalid), after the first line; the front end stops at that statement."""
    lines = (HEAD + """\
      WRITE(6,2) P, Q, P
      X = 1.0E300
      K = X*P*1.0E10 - X*Q*1.0E10
      WRITE(6,2) P, Q, P
      STOP
      END
""").splitlines()
    run, stop = _stopped(lines, "double")
    assert stop.guard == "arithmetic" and stop.variable == "K"
    need_gfortran()
    theirs, _err, ending = _gfortran(tmp_path, lines, "r8", [CARD])
    assert ending == "trap" and "".join(r + "\n" for r in run.records) == theirs


def test_a_loop_that_never_returns_stops_as_a_runaway_where_gfortran_hangs(tmp_path):
    lines = (HEAD + """\
      WRITE(6,2) P, Q, P
      K = LOOP(P)
      STOP
      END
      FUNCTION LOOP(A)
    5 LOOP = LOOP + 1
      IF (A .GT. 0.0) GO TO 5
      END
""").splitlines()
    run, stop = _stopped(lines, "double")
    assert stop.guard == "runaway" and "LOOP did not return" in str(stop)
    assert "label LOOP 5" in str(stop) and "step 0" in str(stop)
    need_gfortran()
    theirs, _err, ending = _gfortran(tmp_path, lines, "r8", [CARD])
    assert ending == "hang" and theirs.splitlines() == run.records


def test_a_subscript_outside_the_arrays_storage_stops_naming_the_array():
    """gfortran's build (no bounds checks) writes past A, the 7094 too: the front end stops."""
    lines = ["      DIMENSION A(3)", *HEAD.splitlines(), "      DO 10 I = 1, 4",
             "   10 A(I) = P", "      STOP", "      END"]
    _run, stop = _stopped(lines, "double")
    assert stop.guard == "program" and stop.variable == "A"
    assert re.search(r"a subscript of A outside its storage \(element 4\) at label 10", str(stop))


# ----------------------------------------------------------------------------- a job deck


def test_a_job_deck_whose_program_uses_the_kinds_runs_as_gfortran_runs_it(tmp_path, capsys):
    """punch --job's steel40, its FORTRAN replaced by a program of DO, DIMENSION, COMMON, a
    FUNCTION and logical IFs reading the deck's 8 data cards: run prints what gfortran's build
    of the same FORTRAN prints for the same data."""
    program = """\
      DIMENSION V(8), S(8)
      COMMON N
      N = 8
      DO 10 K = 1, 8
      READ(5,1) V(1), V(2), V(3), V(4), V(5), V(6), V(7), V(8)
    1 FORMAT(8F10.5)
   10 S(K) = TOTAL(V)
      DO 20 K = 1, 8
      IF (S(K) .GT. 100.0) S(K) = S(K)/100.0
      IF (S(K) .LT. 0.0 .AND. K .NE. 1) S(K) = -S(K)
   20 CONTINUE
      WRITE(6,2) S(1), S(2), S(3), S(4), S(5), S(6), S(7), S(8)
    2 FORMAT(6H SUMS ,8F12.4)
      STOP
      END
      FUNCTION TOTAL(A)
      DIMENSION A(8)
      COMMON M
      TOTAL = 0.0
      DO 5 I = 1, M
    5 TOTAL = TOTAL + A(I)
      END
""".splitlines()
    texts = job_deck_texts([read_deck(ROOT / "decks" / "steel40.dat")])
    first, last = texts.index("$IBFTC MAIN") + 1, texts.index("$ENTRY         MAIN")
    job = tmp_path / "kinds.job"
    job.write_text("\n".join(texts[:first] + program + texts[last:]) + "\n")
    out = tmp_path / "out.txt"
    assert main(["run", str(job), "--out", str(out), "--quiet"]) == 0
    assert "the job deck's own FORTRAN runs" in capsys.readouterr().err.splitlines()[0]
    need_gfortran()
    data = texts[texts.index("$DATA") + 1:texts.index("$IBSYS")]
    theirs, _err, ending = _gfortran(tmp_path, program, "r8", data)
    assert ending == "normal" and out.read_text() == theirs and theirs.startswith(" SUMS ")


# -------------------------------------------------------------------------------- refusals


@pytest.mark.parametrize("text, where", [
    ("      X = F(1.0)\n      END\n      FUNCTION F(A)\n      A = 2.0\n      F = A\n      END",
     "card 3, columns 7-72: FUNCTION statement: FUNCTION F assigns its dummy A"),
    ("      COMMON X\n      X = 1.0\n      END\n      SUBROUTINE S\n      COMMON K\n      END",
     "card 5, columns 7-72: COMMON statement: COMMON //: place 1 is I as K in S, R elsewhere"),
    ("      CALL S\n      END\n      SUBROUTINE S\n      CALL T\n      END\n"
     "      SUBROUTINE T\n      CALL S\n      END",
     "card 3, columns 7-72: SUBROUTINE statement: S calls itself"),
    ("      DO 10 I = 1, 2\n   10 GO TO 20\n   20 STOP\n      END",
     "card 2, columns 7-72: GO TO statement: a DO's range ends at 10, a transfer or a DO"),
    ("      DO 10 I = 1, 2\n      DO 20 J = 1, 2\n   10 CONTINUE\n   20 CONTINUE\n      END",
     "card 3, columns 7-72: CONTINUE statement: the DO ranges ending at 10 cross"),
    ("      CALL S(1.0)\n      END\n      SUBROUTINE S(A)\n      COMMON A\n      END",
     "card 4, column 14: COMMON statement: A twice in COMMON, or a dummy in COMMON"),
    ("      DIMENSION A(2)\n      CALL S(A)\n      END\n      SUBROUTINE S(X)\n      END",
     "card 2, columns 7-72: CALL statement: argument 1 of S: an array against a scalar"),
    ("      X = 1.0\n      DIMENSION A(2)\n      END",
     "card 2, columns 7-72: DIMENSION statement: a DIMENSION after the unit's first"),
    ("      ASSIGN 10 TO X\n   10 STOP\n      END",
     "card 1, column 20: ASSIGN statement: X is no INTEGER variable"),
])
def test_what_the_kinds_refuse_is_refused_in_one_line_naming_card_and_kind(text, where):
    from deck_emulator.legacy.fortran import DialectError

    with pytest.raises(DialectError) as info:
        Program(text.splitlines())
    assert "\n" not in str(info.value) and str(info.value).startswith(where), str(info.value)


def test_every_kind_read_is_a_kind_of_the_dialects_table():
    from deck_emulator.legacy.fortran import STATEMENTS
    from deck_emulator.legacy.fortran.parse import _SYNTAX

    assert {kind for kind, _, _ in _SYNTAX} <= set(STATEMENTS)
