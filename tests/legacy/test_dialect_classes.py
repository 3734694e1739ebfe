"""The classes of disagreement with gfortran that issue 46's differential campaign found, each in
a program of a few cards: the front end prints what gfortran's build prints (binary64 against
the REAL*8 build, binary32 against the default-REAL build, the goldens' flags)."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from deck_emulator.legacy.fortran import Program
from deck_emulator.legacy.fortran.run import LISTING_WATCH, watched

from test_dialect_kinds import CARD, HEAD, _gfortran, _ours
from test_goldens import need_gfortran


@pytest.fixture(autouse=True)
def _made_code_kept_in_a_temporary_folder(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))


CLASSES = {
    "Fw.0": HEAD + """\
      X = P + Q
      Y = -Q*0.6
    3 FORMAT(1X,F5.0,F4.0,F3.0,F2.0,F5.0,F2.0)
      WRITE(6,3) X, X, Q, Y, Y, P
      STOP
      END
""",
    "trailing nX": HEAD + """\
    3 FORMAT(1X,F8.3,4X)
    4 FORMAT(1X)
    5 FORMAT(1H0,2X,/,1X,F6.2,2X,/,3X)
      WRITE(6,3) P
      WRITE(6,4)
      WRITE(6,5) Q
      STOP
      END
""",
    "F over a continuation card after a short card": HEAD + """\
    3 FORMAT(1X,F
     1 8.3, F6
     2 .2)
      WRITE(6,3) P, Q
      STOP
      END
""",
    "SIN and COS of a DO variable after the loop": HEAD + """\
      Y = 0.0
      DO 10 I = 1, 3
   10 Y = Y + SIN(P*I) + COS(P*I)
      Z = SIN(P*I) + COS(P*I)
      X = I
      WRITE(6,2) Y, Z, X
      STOP
      END
""",
    "CALL S(I, A(I))": """\
      DIMENSION A(3)
""" + HEAD + """\
      I = 1
      A(1) = P
      A(2) = Q
      CALL S(I, A(I))
      WRITE(6,2) A(1), A(2), A(3)
      STOP
      END
      SUBROUTINE S(K, B)
      K = 2
      B = 7.5
      END
""",
    "a READ in a subprogram": HEAD + """\
      CALL S(X, Y)
      WRITE(6,2) X, Y, P
      STOP
      END
      SUBROUTINE S(A, B)
      READ(5,1) A, B
    1 FORMAT(F4.0,F5.1)
      END
""",
    "a statement-function dummy named like COMMON": """\
      COMMON X
      F(X) = X*2.0
""" + HEAD + """\
      X = Q
      Y = F(P)
      WRITE(6,2) X, Y, P
      STOP
      END
""",
    "a variable named like a block's label function": HEAD + """\
      K = 0
   10 X = L10
      L10 = 4
      K = K + 1
      IF (K .LT. 2) GO TO 10
      WRITE(6,2) X, P, Q
      STOP
      END
""",
    "watched labels of the listing in another program": HEAD + """\
      T = 0.0
      Q = 5.0
  108 T = T + 1.0
      IF (T .LT. 45.0) GO TO 108
  106 Q = 6.0
   97 FORMAT(1X,F8.2)
   99 FORMAT(1X,F8.2)
      WRITE(6,97) T
      WRITE(6,99) Q
      STOP
      END
""",
    "a statement function named ABS, SIN or COS": """\
      SIN(A) = A + 1.0
      ABS(A) = A*3.0
      COS(A) = A - 1.0
""" + HEAD + """\
      X = SIN(P) + ABS(Q)
      Y = COS(P)
      WRITE(6,2) X, Y, P
      STOP
      END
""",
    "F(X)**2 calls F once, F(X)**0 too": """\
      COMMON N
""" + HEAD + """\
      X = F(P)**2 + F(Q)**0
      Y = N
      WRITE(6,2) X, Y, P
      STOP
      END
      FUNCTION F(A)
      COMMON N
      N = N + 1
      F = A + N
      END
""",
    "X**0, K**0 and X**4 to X**6": HEAD + """\
      X = P + Q*0.0123
      K = 7
    3 FORMAT(1X,3F24.19)
      WRITE(6,3) X**0, X**4, X**5
      L = K**0 + K**5
      Y = L
      WRITE(6,3) X**6, Y, X**1
      STOP
      END
""",
}


#: the data cards of a class that reads more than HEAD's card
CARDS = {"a READ in a subprogram": [CARD, "1234567.5"]}


@pytest.mark.parametrize("precision, build", [("double", "r8"), ("single", "r4")])
@pytest.mark.parametrize("name", sorted(CLASSES))
def test_each_class_prints_what_gfortran_prints(tmp_path, name, precision, build):
    need_gfortran()
    lines, cards = CLASSES[name].splitlines(), CARDS.get(name, [CARD])
    theirs, _err, ending = _gfortran(tmp_path, lines, build, cards)
    run, stop = _ours(lines, precision, cards)
    assert ending == "normal" and stop is None, stop
    assert "".join(r + "\n" for r in run.records) == theirs


def test_the_listings_watch_applies_to_the_listing_alone():
    """One table (LISTING_WATCH): the listing's MAIN holds every label it names; a program
    with some of them (108, 106, 97, 99) is not the listing."""
    from deck_emulator.legacy.fortran import listing_program

    assert watched(LISTING_WATCH, listing_program().units) is LISTING_WATCH
    other = Program(CLASSES["watched labels of the listing in another program"].splitlines(),
                    cache=False)
    assert watched(LISTING_WATCH, other.units) is None and not other.keeps_trace


# ------------------------------------------------------------ a refusal is a promise

#: one statement of each kind of the dialect's table (STATEMENTS), in a program that uses it
KIND_SAMPLES = {
    "assignment": "      X = P + 1",
    "statement function": None,  # (FUN below: before the first executable statement)
    "DIMENSION": None,  # (DECLARED below)
    "COMMON": None,
    "CONTINUE": "    7 CONTINUE",
    "GO TO n": "      GO TO 8\n    8 CONTINUE",
    "GO TO (n1, ...), i": "      K = 1\n      GO TO (9), K\n    9 CONTINUE",
    "ASSIGN n TO i": "      ASSIGN 11 TO M",
    "GO TO i, (n1, ...)": "      GO TO M, (11)\n   11 CONTINUE",
    "IF (e) n1, n2, n3": "      IF (P) 12, 12, 12\n   12 CONTINUE",
    "IF (l) s": "      IF (P .GT. 0.0 .AND. .NOT. Q .LT. 0.0) X = 2.0",
    "DO n i = m1, m2, m3": "      DO 13 I = 1, 3, 2\n   13 A(I) = F(P)",
    "CALL s(a, ...)": "      CALL S(X, A)",
    "SUBROUTINE s(a, ...)": None,
    "FUNCTION f(a, ...)": "      X = G(X)",
    "RETURN": None,
    "STOP": None,
    "END": None,
    "READ (5, n) list": None,  # (HEAD)
    "WRITE (6, n) list": "      WRITE(6,2) X, A(1), B",
    "FORMAT (...)": "    3 FORMAT(1H ,F6.2,2X,/,1X,2F6.1)\n      WRITE(6,3) X, X, X",
}
PROMISE = """\
      DIMENSION A(3)
      COMMON B
      F(Z) = ABS(Z) + SIN(Z) + COS(Z)
""" + HEAD + "\n".join(v for v in KIND_SAMPLES.values() if v) + """
      STOP
      END
      SUBROUTINE S(Y, V)
      DIMENSION V(3)
      COMMON C
      Y = V(1) + C
      RETURN
      END
      FUNCTION G(Y)
      G = Y*2.0
      END
"""


def test_every_kind_of_the_table_is_taken_and_runs_as_gfortran_runs_it(tmp_path):
    from deck_emulator.legacy.fortran import EDIT_DESCRIPTORS, INTRINSICS, STATEMENTS

    assert set(KIND_SAMPLES) == set(STATEMENTS)  # (a row added needs its sample here)
    assert all(f"{name}(" in PROMISE for name in INTRINSICS)
    assert {"Fw.d", "nX", "nHtext", "/"} == set(EDIT_DESCRIPTORS)
    need_gfortran()
    lines = PROMISE.splitlines()
    theirs, _err, ending = _gfortran(tmp_path, lines, "r8", [CARD])
    run, stop = _ours(lines, "double", [CARD])
    assert ending == "normal" and stop is None, stop
    assert "".join(r + "\n" for r in run.records) == theirs and len(run.records) >= 3


@pytest.mark.parametrize("kind", ["DOUBLE PRECISION", "EQUIVALENCE", "REAL FUNCTION",
                                  "INTEGER FUNCTION", "INTEGER", "REAL", "LOGICAL", "COMPLEX",
                                  "EXTERNAL", "DATA", "PAUSE", "PRINT", "PUNCH", "REWIND",
                                  "BACKSPACE", "ENDFILE", "BLOCK DATA", "ENTRY"])
def test_every_kind_outside_the_table_is_refused_naming_it(kind):
    """The kinds of FORTRAN IV the table leaves out (parse._OTHER_KINDS), each refused in one
    line naming the card, its columns and the kind."""
    from deck_emulator.legacy.fortran import DialectError
    from deck_emulator.legacy.fortran.parse import _OTHER_KINDS

    assert kind.replace(" ", "") in _OTHER_KINDS
    with pytest.raises(DialectError) as info:
        Program([f"      {kind} X", "      END"], cache=False)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"card 1, column"), message
    assert f": {kind} statement: " in message, message


@pytest.mark.parametrize("card", ["      X = SQRT(P)", "    3 FORMAT(1X,E12.4)",
                                  "    3 FORMAT(1X,I5)", "    3 FORMAT(1X,2(F6.2))"])
def test_an_intrinsic_or_descriptor_outside_the_table_is_refused(card):
    from deck_emulator.legacy.fortran import DialectError

    with pytest.raises(DialectError) as info:
        Program(HEAD.splitlines() + [card, "      END"], cache=False)
    assert "\n" not in str(info.value) and str(info.value).startswith("card 4, column")


# ------------------------------------------------- Hollerith texts name no other kind

#: what a FORMAT's Hollerith text may hold: the card code (printable ASCII), blanks among it
_HOLLERITH = st.text(alphabet=st.characters(min_codepoint=0x20, max_codepoint=0x7E),
                     min_size=1, max_size=40)
#: texts that look like other statements' parts (found by the differential campaign: `=`)
_LOOKALIKES = ["A=B ", "X(1)=2.0", "DO 10 I=1,", "DO10I=1,3", "GO TO (1,2), I", "IF (X) 1,2,3",
               "CALL S(A, B)", "'A'", '"', "A,B)(", "3HABC", "E10.3", "DATA X/1./", "C=",
               "REAL X", "READ(5,1) X"]


def _ours_uncached(lines, cards):
    from deck_emulator.legacy.stops import EmulatorError

    from test_dialect_kinds import _Cards

    try:
        return Program(lines, cache=False).runner(_Cards(cards), "double").run(), None
    except EmulatorError as exc:
        return exc.run, exc


def test_a_refused_format_with_an_equals_sign_in_its_hollerith_text_is_named_a_format(
        tmp_path, capsys):
    """The campaign's reproducer, as a user runs it: the refusal names the FORMAT statement, not
    an assignment (the `=` is inside the Hollerith text `4HA=B `)."""
    from deck_emulator.cli import main

    job = tmp_path / "fuzz.job"
    job.write_text("$JOB           FUZZ\n$EXECUTE       IBJOB\n$IBJOB\n$IBFTC MAIN\n"
                   "      X = 1.5\n    1 FORMAT(1X,4HA=B ,E10.3)\n      WRITE(6,1) X\n"
                   "      STOP\n      END\n$ENTRY         MAIN\n$DATA\n$IBSYS\n")
    assert main(["run", str(job), "--out", str(tmp_path / "out.txt")]) == 2
    err = capsys.readouterr().err
    assert "card 6, column 24: FORMAT statement: 'E': an edit descriptor outside" in err, err
    assert len(err.splitlines()) == 1


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(text=st.one_of(st.sampled_from(_LOOKALIKES), _HOLLERITH))
def test_a_refused_format_is_named_a_format_whatever_its_hollerith_text_holds(text):
    """A FORMAT outside the dialect (an E field) is refused naming the FORMAT statement, at the
    E's card and column, whatever its Hollerith text holds before it."""
    from deck_emulator.legacy.fortran import DialectError

    card = f"    3 FORMAT(1X,{len(text)}H{text},E10.3)"
    with pytest.raises(DialectError) as info:
        Program(HEAD.splitlines() + [card, "      WRITE(6,3) P", "      STOP", "      END"],
                cache=False)
    column = card.index(",E10.3") + 2
    assert str(info.value).startswith(f"card 4, column {column}: FORMAT statement: 'E': "), (
        str(info.value))


@pytest.mark.parametrize("card, kind", [
    ("      DATA1 = P +", "assignment"), ("      DO10I = P +", "assignment"),
    ("      REALX = P +", "assignment"), ("      IF (P .GT. 0.0) X = P +", "IF"),
    ("      DO 10 I = 1, 3 +", "DO")])
def test_a_refusal_names_the_kind_the_statement_is_read_as(card, kind):
    """`DATA1 = ...` and `DO10I = ...` are assignments (FORTRAN reads them so), not DATA or DO."""
    from deck_emulator.legacy.fortran import DialectError

    with pytest.raises(DialectError) as info:
        Program(HEAD.splitlines() + [card, "   10 CONTINUE", "      END"], cache=False)
    assert f": {kind} statement: " in str(info.value), str(info.value)


@settings(max_examples=6, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(texts=st.lists(_HOLLERITH, min_size=4, max_size=4))
def test_formats_with_any_hollerith_text_print_what_gfortran_prints(texts):
    """FORMATs of the dialect whose Hollerith texts hold anything of the card code (`=`, `(`,
    `,`, quotes, a DO's shape ...), also split over a continuation card, run and print what
    gfortran's REAL*8 build prints."""
    import tempfile
    from pathlib import Path

    need_gfortran()
    texts = _LOOKALIKES + texts
    lines = HEAD.splitlines()
    for k, text in enumerate(texts, start=3):
        lines += [f"{k:5d} FORMAT(1X,{len(text)}H{text},F10.3)", f"      WRITE(6,{k}) P"]
    # a Hollerith text over a continuation card after a short card (its blanks to column 72)
    lines += ["   99 FORMAT(1X,56HA=B", "     1C=D,F10.3)", "      WRITE(6,99) Q",
              "      STOP", "      END"]
    with tempfile.TemporaryDirectory() as tmp:
        theirs, _err, ending = _gfortran(Path(tmp), lines, "r8", [CARD])
    run, stop = _ours_uncached(lines, [CARD])
    assert ending == "normal" and stop is None, stop
    assert "".join(r + "\n" for r in run.records) == theirs
    assert len(run.records) == len(texts) + 1
