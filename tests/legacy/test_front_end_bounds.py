"""The FORTRAN front end on what an attacker (or a slip of the keypunch) feeds it: every program
ends, either refused before anything runs (DialectError: one line naming the card, its columns
and the statement kind) or stopped by a bound (EmulatorError, exit 3) or run to its end; never
a traceback, never a loop of hours.  Where gfortran compiles and runs the program, its build
with the goldens' flags is the oracle."""

from __future__ import annotations

import dataclasses

import pytest

from deck_emulator.cli import main
from deck_emulator.legacy.fortran import DialectError, Program
from deck_emulator.legacy.stops import EmulatorError, Limits
from deck_emulator.vocabulary import defaults

from test_dialect_kinds import CARD, HEAD, _Cards, _gfortran, _ours
from test_goldens import need_gfortran


@pytest.fixture(autouse=True)
def _made_code_kept_in_a_temporary_folder(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))


def _cards(statement: str, lead: str = "      ") -> list[str]:
    """A statement punched on as many cards as it takes (continuations in column 6)."""
    text = lead + statement
    cards, text = [text[:72]], text[72:]
    while text:
        cards.append("     1" + text[:66])
        text = text[66:]
    return cards


def _refused(lines, *where) -> str:
    with pytest.raises(DialectError) as info:
        Program(lines, cache=False)
    message = str(info.value)
    assert "\n" not in message and "Traceback" not in message
    for part in where:
        assert part in message, message
    return message


def _same_as_gfortran(tmp_path, lines, precision="double", build="r8"):
    need_gfortran()
    theirs, _err, ending = _gfortran(tmp_path, lines, build, [CARD])
    run, stop = _ours(lines, precision, [CARD])
    assert ending == "normal" and stop is None, stop
    assert "".join(r + "\n" for r in run.records) == theirs
    return run


# ---------------------------------------------------------------------- the statement budget


LOOPS = HEAD + """\
      DO 10 I = 1, 999999
      CALL S(X)
   10 CONTINUE
      STOP
      END
      SUBROUTINE S(X)
      DO 5 J = 1, 99999
    5 X = X + 1.0
      END
"""


def test_one_statement_budget_holds_across_units_loops_and_calls():
    """Each subroutine call stays far under the bound of one call; the run's budget stops it,
    naming the statement, its card and its unit's label."""
    lines = LOOPS.splitlines()
    limits = dataclasses.replace(Limits(), statements=20_000)
    with pytest.raises(EmulatorError) as info:
        Program(lines, cache=False).runner(_Cards([CARD]), "double", limits=limits).run()
    stop = info.value
    assert stop.guard == "statements" and "\n" not in str(stop)
    assert "budget of 20000 statements" in str(stop) and "card 11: X=X+1.0" in str(stop)
    assert stop.label == "S 5"


def test_the_default_budget_is_the_defaults_row():
    assert Limits().statements == defaults.PROGRAM_STATEMENTS > 1_911_496  # (the 5 s flight)


def test_a_run_within_the_budget_counts_what_it_ran():
    """The budget spends a block's statements when it starts (an upper bound of what runs):
    counted by hand here."""
    lines = (HEAD + "      X = 0.0\n      DO 10 I = 1, 4\n      X = X + P\n   10 CONTINUE\n"
             "      STOP\n      END\n").splitlines()
    runner = Program(lines, cache=False).runner(_Cards([CARD]), "double")
    runner.run()
    # blocks: [READ, X = 0.0, DO], then 4 times the range's first [X = X + P] and the block
    # of label 10 [10 CONTINUE, STOP, END] (its DO's test returns from it but the last time):
    # 3 + 4 * (1 + 3)
    assert runner.statements_run == 19


# -------------------------------------------------------------------------- powers, INTEGERs


POWERS = HEAD + """\
      X = 1.0 + Q*0.0123
      K = 3
      WRITE(6,3) X**0, X**1, X**3, X**4
      WRITE(6,3) X**5, X**6, X**7, X**13
      WRITE(6,3) X**29, X**100, (X - 1.0)**0, X**2
      L = K**0 + K**1 + K**5 + K**13
      Y = L
      WRITE(6,2) Y, P, Q
    3 FORMAT(1X,4F26.20)
      STOP
      END
"""


@pytest.mark.parametrize("precision, build", [("double", "r8"), ("single", "r4")])
def test_integer_powers_multiply_as_gfortrans_build(tmp_path, precision, build):
    """X**0 is 1, X**n squares from the low bit up as libgcc's __powidf2 (gfortran's build at
    -O0): the last bits, printed to 20 decimals, are gfortran's (multiplied left to right,
    X**5 to X**100 differ in them)."""
    lines = POWERS.splitlines()
    _same_as_gfortran(tmp_path, lines, precision, build)


def test_a_huge_integer_power_is_computed_in_32_bits_at_once():
    """K = 3**99999999: 32-bit two's complement as gfortran's build wraps it (computed here by
    Python's modular pow, independently of the made code)."""
    lines = (HEAD + "      K = 3**99999999\n      X = K\n      WRITE(6,4) X\n"
             "    4 FORMAT(1X,F20.1)\n      STOP\n      END\n").splitlines()
    run, stop = _ours(lines, "double", [CARD])
    want = pow(3, 99999999, 2**32)
    want -= 2**32 if want >= 2**31 else 0
    assert stop is None and float(run.records[0].split()[0]) == float(want)


def test_a_huge_real_power_ends_at_once():
    lines = (HEAD + "      Y = 1.0\n      X = Y**999999999\n      WRITE(6,2) X, P, Q\n"
             "      STOP\n      END\n").splitlines()
    run, stop = _ours(lines, "double", [CARD])
    assert stop is None and run.records[0].split()[0] == "1.0000"


def test_integer_overflow_wraps_in_32_bits_as_gfortrans_build(tmp_path):
    lines = (HEAD + """\
      K = 2147483647
      K = K + 1
      L = -K - 1
      M = 65536
      M = M*M + 7
      N = (K + 5)/3
      X = K
      Y = L
      Z = M
      W = N
      WRITE(6,4) X, Y, Z
      WRITE(6,4) W, P, Q
    4 FORMAT(1X,3F20.4)
      STOP
      END
""").splitlines()
    run = _same_as_gfortran(tmp_path, lines)
    assert run.records[0].split()[0] == "-2147483648.0000"


def test_a_real_too_large_for_an_integer_stops_where_gfortran_traps(tmp_path):
    lines = (HEAD + "      WRITE(6,2) P, Q, P\n      X = 1.0E20\n      K = X\n"
             "      WRITE(6,2) P, Q, P\n      STOP\n      END\n").splitlines()
    run, stop = _ours(lines, "double", [CARD])
    assert stop is not None and stop.guard == "arithmetic" and stop.variable == "K"
    assert "\n" not in str(stop)
    need_gfortran()
    theirs, _err, ending = _gfortran(tmp_path, lines, "r8", [CARD])
    assert ending == "trap" and "".join(r + "\n" for r in run.records) == theirs


# ----------------------------------------------------------------- long, deep and many things


def test_a_sum_of_500_terms_on_20_cards_runs(tmp_path):
    """Legal FORTRAN (8 cards), made without recursion: P added 500 times is 625 exactly."""
    lines = HEAD.splitlines() + _cards("X = " + "+".join(["P"] * 500)) + [
        "      WRITE(6,2) X, P, Q", "      STOP", "      END"]
    run = _same_as_gfortran(tmp_path, lines)
    assert run.records[0].split()[0] == "625.0000"


def test_a_statement_of_more_than_19_continuation_cards_is_refused():
    lines = HEAD.splitlines() + _cards("X = " + "+".join(["P"] * 3000)) + ["      END"]
    _refused(lines, "card 24, column 6: assignment statement: more than 19 continuation cards")


def test_parentheses_nested_150_deep_are_refused_and_40_run():
    deep = HEAD.splitlines() + _cards("X = " + "(" * 150 + "P" + ")" * 150) + ["      END"]
    _refused(deep, "card 4, column 51: assignment statement: parentheses",
             f"more than {defaults.PROGRAM_NESTING} deep")
    ok = HEAD.splitlines() + _cards("X = " + "(" * 40 + "P" + ")" * 40) + [
        "      WRITE(6,2) X, P, Q", "      STOP", "      END"]
    run, stop = _ours(ok, "double", [CARD])
    assert stop is None and run.records[0].split()[0] == "1.2500"


def test_chained_statement_functions_and_subroutines_beyond_the_depth_are_refused():
    functions = ["      F0(X) = X + 1.0"] + [f"      F{i}(X) = F{i - 1}(X)" for i in
                                              range(1, 1200)] + ["      Y = F1199(1.0)",
                                                                 "      END"]
    _refused(functions, "card 201, columns 7-72: statement function statement: "
             "statement functions referring to each other 201 deep")
    subroutines = ["      CALL S1", "      END"] + [
        line for i in range(1, 600) for line in (f"      SUBROUTINE S{i}", f"      CALL S{i + 1}",
                                                  "      END")] + ["      SUBROUTINE S600",
                                                                   "      END"]
    _refused(subroutines, "columns 7-72: SUBROUTINE statement: subprograms calling each other")


def test_fifty_chained_subroutines_run():
    lines = HEAD.splitlines() + ["      CALL S1(X)", "      WRITE(6,2) X, P, Q", "      STOP",
                                 "      END"] + [
        line for i in range(1, 50) for line in (f"      SUBROUTINE S{i}(X)",
                                                f"      CALL S{i + 1}(X)", "      X = X + 1.0",
                                                "      END")] + [
        "      SUBROUTINE S50(X)", "      X = 0.5", "      END"]
    run, stop = _ours(lines, "double", [CARD])
    assert stop is None and run.records[0].split()[0] == "49.5000"


def test_arrays_beyond_the_storage_are_refused_before_any_element_is_walked():
    _refused(["      COMMON B(99999,99999,999)", "      END"],
             "card 1, column 14: COMMON statement: the unit's arrays hold 9989800200999 elements")
    _refused(["      DIMENSION A(20000), B(20000)", "      END"], "DIMENSION statement")


def test_many_labels_parse_and_run():
    lines = HEAD.splitlines() + [f"{k:5d} X = X + P" for k in range(10, 2010)] + [
        "      WRITE(6,2) X, P, Q", "      STOP", "      END"]
    run, stop = _ours(lines, "double", [CARD])
    assert stop is None and run.records[0].split()[0] == "2500.0000"


def test_a_variable_named_like_a_blocks_label_is_the_variable(tmp_path):
    lines = (HEAD + "      L10 = 3\n   10 X = L10\n      WRITE(6,2) X, P, Q\n      STOP\n"
             "      END\n").splitlines()
    _same_as_gfortran(tmp_path, lines)


# --------------------------------------------------------------------------------- the data


def test_a_reads_slash_past_the_last_data_card_stops_in_one_line():
    lines = (HEAD + "      READ(5,7) A, B\n    7 FORMAT(F10.3/F10.3)\n      STOP\n"
             "      END\n").splitlines()
    run, stop = _ours(lines, "double", [CARD])
    assert stop is not None and stop.guard == "read" and "\n" not in str(stop)
    assert "past the last of the deck's 1 data cards" in str(stop)


# ------------------------------------------------------------------- outside the card code


@pytest.mark.parametrize("card, where", [
    ("      K = \u0661\u0662", "card 4, column 11: assignment statement: the character '\u0661'"),
    ("    \u0667 X = 1.0", "card 4, column 5: assignment statement: the character '\u0667'"),
    ("      X = 1.0\r+P", "card 4, column 14: assignment statement: the character '\\r'"),
    ("      X = 1.0\t+P", "card 4, column 14: assignment statement: the character '\\t'"),
    ("    3 FORMAT(5H AB\udcffC)", "card 4, column 19: FORMAT statement: the character "
                                  "'\\udcff'"),
    ("    3 FORMAT(1X, F0.2)", "card 4, column 18: FORMAT statement: F0.2: a field of width 0"),
    ("    3 FORMAT(0X, F8.2)", "card 4, column 14: FORMAT statement: 0X: a count or width"),
    ("    3 FORMAT(0H, F8.2)", "card 4, column 14: FORMAT statement: 0H: a count or width"),
    ("      X = 1." + "1" * 45, "card 4, columns 7-72: assignment statement: a constant or "
                                "label of more than 40 digits"),
    ("      K = 2147483648", "card 4, column 11: assignment statement: the INTEGER constant "
                             "2147483648 is beyond 32 bits"),
    ("      X = 1.0E999", "card 4, column 11: assignment statement: the REAL constant 1.0E999 "
                          "overflows"),
])
def test_what_gfortran_refuses_is_refused_in_one_line(card, where):
    _refused(HEAD.splitlines() + [card, "      END"], where)


def test_a_job_deck_of_a_runaway_ends_with_exit_3_in_one_line(tmp_path, capsys):
    """The command, on a loop of two statements: exit 3, one line of error."""
    from test_dialect_kinds import ROOT, job_deck_texts, read_deck

    texts = job_deck_texts([read_deck(ROOT / "decks" / "steel40.dat")])
    first, last = texts.index("$IBFTC MAIN") + 1, texts.index("$ENTRY         MAIN")
    job = tmp_path / "loop.job"
    job.write_text("\n".join(texts[:first] + ["    5 X = X + 1.0", "      GO TO 5",
                                              "      END"] + texts[last:]) + "\n")
    code = main(["run", str(job), "--out", str(tmp_path / "out.txt"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 3, err
    errors = [line for line in err.splitlines() if "error" in line]
    assert len(errors) == 1 and "statements (Limits.budget) without STOP" in errors[0]


# ------------------------------------------------------------------ any card at all


from hypothesis import given, settings, strategies as st  # noqa: E402

_CARD_TEXT = st.lists(st.sampled_from(list("XYPQKIN0123456789.+-*/(),= EF\r\t\u0661\udcff")
                                      + ["**", ".LT.", ".AND.", ".NOT.", "SIN(", "1H"]),
                      max_size=80).map("".join)


@settings(max_examples=150, deadline=None)
@given(statement=_CARD_TEXT, fmt=_CARD_TEXT)
def test_any_statement_is_taken_or_refused_in_one_line(statement, fmt):
    """Whatever a card holds, the front end parses and makes it (Python that compiles), or
    refuses it with a DialectError of one line: never another exception, never Python's
    recursion."""
    lines = HEAD.splitlines() + _cards("X = " + statement) + _cards(
        "FORMAT(" + fmt, lead="    9 ") + ["      END"]
    try:
        compile(Program(lines, cache=False).python(), "<made>", "exec")
    except DialectError as exc:
        assert "\n" not in str(exc) and str(exc).startswith("card ")
