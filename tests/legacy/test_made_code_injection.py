"""Nothing a user feeds runs as code: every text from outside (the program's name and path, its
cards, labels, names and Hollerith texts, its FORMATs, an option's constant) enters the made
Python only as a literal, so the made code's syntax tree is the same, constants and names
masked, whatever the text.  A job deck whose file name carries Python runs its cards and
nothing else."""

from __future__ import annotations

import ast
import copy
import dataclasses
import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from deck_emulator.cli import main
from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.fortran import DialectError, Program
from deck_emulator.legacy.fortran.make import made_lines
from deck_emulator.legacy.jobdeck import job_deck_texts

from test_emulator import ROOT

#: A small program of the dialect, other than the listing: a READ, a REAL constant, a label,
#: a FORMAT with a Hollerith text, a subroutine.
PROGRAM = [
    "      READ(5,1) A",
    "    1 FORMAT(F10.5)",
    "      B = A + 1.5",
    "   10 CALL TWICE(B)",
    "      WRITE(6,2) B",
    "    2 FORMAT(6H  B IS,F12.4)",
    "      STOP",
    "      END",
    "      SUBROUTINE TWICE(X)",
    "      X = X*2.0",
    "      RETURN",
    "      END",
]

#: Texts an attacker would try: line ends of every kind Python or str.splitlines knows,
#: quotes, backslashes, NUL, a comment's and a string's ends, non-ASCII, digits of other
#: scripts, and long runs of them.
_HOSTILE_CHARS = st.sampled_from(
    ["\n", "\r", "\r\n", "\x00", "'", '"', "\\", "#", "'''", '"""', "\x0c", "\x0b", "\x1c",
     "\x85", "\u2028", "\u2029", "é", "\u0663", "\U0001f600", "\udcff", " ", ";", ":", "(",
     ")", "import os", "os.system('x')", "A", "1", ".", "E", "+", "-", "H", ","])
HOSTILE = st.one_of(
    st.lists(_HOSTILE_CHARS, max_size=20).map("".join),
    st.text(max_size=40),
    st.tuples(_HOSTILE_CHARS, st.integers(1, 20_000)).map(lambda t: t[0] * t[1]),
)


class _Mask(ast.NodeTransformer):
    """Every constant and every identifier made alike: what remains is the statements and
    expressions the front end wrote."""

    def generic_visit(self, node):
        super().generic_visit(node)
        if isinstance(node, ast.Constant):
            node.value = None
        for name in ("id", "name", "attr", "arg"):
            if isinstance(getattr(node, name, None), str):
                setattr(node, name, "_")
        if isinstance(node, (ast.Nonlocal, ast.Global)):
            node.names = ["_"] * len(node.names)
        return node


def shape(source: str) -> str:
    """The made source's syntax tree, its constants and names masked."""
    return ast.dump(_Mask().visit(ast.parse(source)))


def _source(lines) -> str:
    return "\n".join(text for text, _ in lines) + "\n"


def _made(program: Program) -> str:
    source = program.python()
    compile(source, "<fortran>", "exec")  # (it compiles: no NUL, no broken literal)
    return source


BENIGN = shape(_made(Program(PROGRAM, cache=False)))
_SETTINGS = settings(max_examples=60, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow])


@_SETTINGS
@given(HOSTILE)
def test_a_programs_name_or_path_enters_its_made_code_only_as_a_literal(text):
    for program in (Program(PROGRAM, name=text, cache=False),
                    Program(PROGRAM, path=text, cache=False)):
        source = _made(program)
        assert shape(source) == BENIGN
        assert ast.literal_eval(source.splitlines()[1].split(" = ", 1)[1])[0] == (
            text or "the program")


def _or_refused(lines) -> str | None:
    """The made source of ``lines``' program, or None if the front end refuses it."""
    try:
        return _made(Program(lines, cache=False))
    except DialectError:
        return None


def _punched(where: str, text: str) -> list[str]:
    """PROGRAM with ``text`` punched in a Hollerith text, a label's columns, a variable's name,
    the sequence columns 73-80 or a comment card."""
    lines = list(PROGRAM)
    if where == "hollerith":
        lines[5] = f"    2 FORMAT({len(text)}H{text},F12.4)"
    elif where == "label":
        lines[3] = f"{text[:5]:<5} CALL TWICE(B)"
    elif where == "name":
        lines[2:5] = [f"      {text} = A + 1.5", f"   10 CALL TWICE({text})",
                      f"      WRITE(6,2) {text}"]
    elif where == "sequence":
        lines[2] = lines[2].ljust(72) + text
    else:
        lines.insert(2, "C" + text)
    return lines


#: The benign programs whose shapes a hostile card's program may have besides PROGRAM's: the
#: label left out (a blank label's columns), or the card a comment (C, c, * or $ in column
#: 1: jobdeck.is_comment); the name A, one variable with the one read.  (A name the parser
#: takes is a REAL's: an INTEGER's is refused, TWICE's dummy being REAL.)
_TWINS = {"label": ("     ", "C"), "name": ("A",)}


@_SETTINGS
@given(HOSTILE, st.sampled_from(["hollerith", "label", "name", "sequence", "comment"]))
def test_a_cards_text_enters_the_made_code_only_as_a_literal(text, where):
    """Hostile text punched on a card: the program is refused, or its made code has the
    statements of a benign program's, no more."""
    source = _or_refused(_punched(where, text))
    if source is not None:
        twins = {BENIGN} | {shape(_made(Program(_punched(where, t), cache=False)))
                            for t in _TWINS.get(where, ())}
        assert shape(source) in twins
    if where == "name" and source is not None:  # (the name taken is ASCII letters and digits)
        names = {n.id for n in ast.walk(ast.parse(source)) if isinstance(n, ast.Name)}
        assert all(n.isascii() and n.replace("_", "").isalnum() for n in names)


@_SETTINGS
@given(HOSTILE, st.sampled_from(["const", "step"]))
def test_an_options_constant_enters_the_made_code_only_as_a_literal(text, how):
    """A constant given for a literal of the program (the listing's --tha-start and
    --ed-tolerance; Program.literals): a literal and a name of ASCII letters and digits."""
    key = ("MAIN", "B=A+1.5", "1.5")
    benign = shape(_made(Program(PROGRAM, literals={key: (how, "2.5")}, cache=False)))
    assert shape(_made(Program(PROGRAM, literals={key: (how, text)}, cache=False))) == benign


def _hostile_units(units: dict, text: str) -> dict:
    """The parsed units with every text the maker is given replaced by ``text`` (what the
    card reader would never let through: line ends, NUL)."""
    out = {}
    for name, unit in units.items():
        unit = copy.deepcopy(unit)
        unit.statements = [dataclasses.replace(s, text=text) for s in unit.statements]
        unit.formats = {label: text for label in unit.formats}
        out[name] = unit
    return out


@_SETTINGS
@given(HOSTILE)
def test_the_maker_writes_any_text_it_is_given_as_a_literal(text):
    """By construction, not by the card reader's filtering: the code maker given hostile
    statement texts, FORMATs and header texts still writes only its own statements."""
    units = Program(PROGRAM, cache=False).units
    made_from = (text, text, text, text)
    for native, checking in ((True, False), (False, True)):
        benign = shape(_source(made_lines(units, ("p", "s", "f", "h"), native=native,
                                          checking=checking, watch=None, literals={},
                                          step_scale_k=0)))
        lines = made_lines(_hostile_units(units, text), made_from, native=native,
                           checking=checking, watch=None, literals={}, step_scale_k=0)
        source = _source(lines)
        compile(source, "<fortran>", "exec")
        assert shape(source) == benign
        # one made line, one line of source: a traceback's line number finds its statement
        assert all("\n" not in t and "\r" not in t for t, _ in lines)


# ----------------------------------------------------------------- the reproducer


def _small_job(folder) -> bytes:
    """A job deck of steel40's data whose own program is PROGRAM (not the listing)."""
    texts = job_deck_texts([read_deck(ROOT / "decks" / "steel40.dat")])
    first, last = texts.index("$IBFTC MAIN") + 1, texts.index("$ENTRY         MAIN")
    return ("\n".join(texts[:first] + PROGRAM + texts[last:]) + "\n").encode()


@pytest.mark.parametrize("end", ["\n", "\r", "\r\n"])
def test_a_job_decks_file_name_runs_no_python(tmp_path, monkeypatch, capsys, end):
    """f=$'x\\nopen("PWNED","w").write("x")\\n#.job'; deck-emulator run "$f": the cards run,
    and no file is written but the outputs, then or when the same cards run again (their
    made code kept)."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    name = f'x{end}open("PWNED","w").write("x"){end}#.job'
    (work / name).write_bytes(_small_job(work))
    (work / "small.job").write_bytes(_small_job(work))
    before = set(os.listdir(work))
    for deck in (name, "small.job"):
        assert main(["run", deck, "--out", "out.txt", "--quiet"]) == 0
        # steel40's first card's first field is 0.0: B = (0.0 + 1.5)*2 = 3.0, in F12.4
        assert (work / "out.txt").read_text().splitlines()[0] == "  B IS      3.0000"
        assert set(os.listdir(work)) == before | {"out.txt"}
    capsys.readouterr()
