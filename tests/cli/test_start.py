"""The emulator's start: what a plain ``deck-emulator run`` does not load.

Speed itself is measured by benchmarks/bench_emulator_start.py, never asserted here."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[2]

#: Modules a plain run of a text deck must not import: the heavy libraries no run uses, and
#: what this work took out of the run's path (fortranformat and the importlib.metadata its
#: __init__ reads; importlib.resources, read only for the listing's text or a shipped deck's
#: name; ctypes, for binary32's sinf/cosf only; traceback, for a stopped run only).
#: Then what the command line's start took out: the other subcommands'
#: parsers and what they import (the answers and the quantity registry: dataclasses,
#: inspect), json (for --json only), typing; shutil (argparse's way to the terminal's width,
#: and the writer's, which a run whose program's made code is already kept never needs), the
#: IBM 7094's arithmetic and fractions.  Then the FORTRAN front end's parser and code maker:
#: the listing's made code is kept in the user's cache folder, named by the SHA-256 of what
#: made it (hashlib, which a plain run now loads for it) and checked against the cards whole,
#: and a later run only loads it.  pathlib (with the urllib.parse and ipaddress it imports,
#: about 3 ms): the run's path names files by os.path.
NOT_IMPORTED = ("scipy", "matplotlib", "pandas", "dask", "distributed", "fortranformat",
                "importlib.metadata", "importlib.resources", "traceback",
                "deck_emulator.present", "deck_emulator.engine.quantities",
                "deck_emulator.studies", "json", "typing", "shutil",
                "deck_emulator.legacy.arithmetic.ibm7094", "fractions",
                "deck_emulator.legacy.fortran.parse", "deck_emulator.legacy.fortran.make",
                "pathlib")

# (what the interpreter's own start loaded, before the run, does not count)
PROBE = """
import runpy, sys
before = set(sys.modules)
sys.argv = ["deck-emulator", "run", sys.argv[1]]
try:
    runpy.run_module("deck_emulator", run_name="__main__")
except SystemExit as exc:
    assert not exc.code, exc.code
print(sorted(m for m in %r if m in set(sys.modules) - before), file=sys.stderr)
""" % (NOT_IMPORTED,)


def test_a_plain_run_imports_none_of_what_it_does_not_need():
    # a first run makes the listing's code and keeps it; the run looked at is a later one
    subprocess.run([sys.executable, "-m", "deck_emulator.cli", "run", str(ROOT / "decks" /
                    "steel40.dat")], capture_output=True, check=True)
    proc = subprocess.run([sys.executable, "-c", PROBE, str(ROOT / "decks" / "steel40.dat")],
                          capture_output=True, text=True, check=True)
    assert proc.stdout == (ROOT / "golden" / "steel40.r8.txt").read_text()  # and it did run
    assert proc.stderr.strip().splitlines()[-1] == "[]"


def test_double_does_not_load_ctypes_for_binary32():
    probe = ("import sys; from deck_emulator.legacy.arithmetic import get_arithmetic; "
             "get_arithmetic('double'); print('ctypes' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "False"


_DIGITS = st.text("0123456789", min_size=1, max_size=6)
_FIELDS = st.builds(
    lambda sign, mant, exp: (sign + mant + exp)[:10],
    st.sampled_from(["", "+", "-"]),
    st.one_of(_DIGITS, st.builds(lambda a, b: a + "." + b, st.text("0123456789", max_size=4),
                                 st.text("0123456789", max_size=4)).filter(lambda t: t != ".")),
    st.one_of(st.just(""), st.builds(lambda e, s, d: e + s + d, st.sampled_from(["E", "D", ""]),
                                     st.sampled_from(["", "+", "-"]),
                                     st.text("0123456789", min_size=1, max_size=3))
              .filter(lambda t: t[0] in "ED" or t[0] in "+-")),
)


@settings(max_examples=2000, deadline=None)
@given(_FIELDS)
def test_fortranformat_reads_every_field_the_deck_reader_accepts(text):
    """The deck reader decides which texts are numbers by its own pattern and no longer asks
    fortranformat (an independent F10.5 reader) for each field: every field the pattern
    accepts, fortranformat reads too, to the same number (to its double rounding)."""
    from fortranformat import FortranRecordReader

    from deck_emulator.legacy.deck import DeckError, _NUMBER_RE, read_field

    if not _NUMBER_RE.fullmatch(text):
        return
    theirs = FortranRecordReader("(F10.5)").read(text)[0]
    assert theirs is not None
    try:
        ours, _ = read_field(text.rjust(10), name="X", card=1, columns=(1, 10), path=None)
    except DeckError:  # out of binary64's range: fortranformat gives inf or 0 there
        assert not math.isfinite(theirs) or abs(theirs) < 1e-290
        return
    if not math.isfinite(theirs) or (theirs == 0) != (ours == 0):
        # fortranformat converts before applying the implied decimal point ('2E308' is 2E303,
        # in range, to gfortran and to the deck reader; fortranformat overflows): deck.py says so
        assert "." not in text and abs(ours) > 1e290 or abs(ours) < 1e-290
        return
    assert math.isclose(ours, theirs, rel_tol=1e-15)


# --- the IBM 7094 arithmetic's faster paths, against the exact ones they replace -------------


def test_float_word_is_the_exact_ratio_chopped_or_rounded():
    """_sincos_libm reads a binary64's word off math.frexp; _from_ratio, the exact rational
    conversion, must give the same word for every such float."""
    import random

    from deck_emulator.legacy.arithmetic.ibm7094 import _float_word, _from_ratio

    rng = random.Random(7094)
    values = [rng.uniform(0.5, 1.0) * 2.0 ** rng.randint(-119, 119) for _ in range(20000)]
    values += [1.0, 0.5, 1 - 2**-53, 1 - 2**-28, 1 - 2**-27, 2**-119 * 1.5, 0.75 + 2**-28,
               0.75 + 2**-29]  # ties and carries at the 27th bit
    for y in values:
        n, d = y.as_integer_ratio()
        for nearest in (False, True):
            w = _from_ratio(n, d, False, nearest)
            assert _float_word(y, nearest) == (w.characteristic, w.fraction), (y, nearest)


def test_like_signed_fad_is_the_54_bit_sum_chopped():
    """FAD of like signs, now added in 27-bit integers, against the exact sum chopped to 27
    bits (exact arithmetic in Fractions: an independent computation); carries included."""
    import random
    from fractions import Fraction

    from deck_emulator.legacy.arithmetic.ibm7094 import Word

    rng = random.Random(1967)
    for _ in range(20000):
        c1 = rng.randint(1, 254)
        c2 = min(254, max(1, c1 + rng.choice([0, 0, 1, -1, rng.randint(-70, 70)])))
        s = rng.getrandbits(1)
        a = Word(s, c1, rng.choice([2**27 - 1, 2**26, rng.randint(2**26, 2**27 - 1)]))
        b = Word(s, c2, rng.choice([2**27 - 1, 2**26, rng.randint(2**26, 2**27 - 1)]))
        exact = abs(a.exact() + b.exact())
        got = a + b
        assert got.sign == s
        assert got.exact() == (-1) ** s * Word.from_fraction(exact, "chop").exact()


def _subparsers(parser):
    import argparse

    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return action.choices


def test_one_subcommands_parser_is_the_whole_parsers():
    """A command line that names a subcommand is parsed by a parser holding that one alone
    (cli.build_parser(name)): its help, and what it makes of a command line, are the whole
    parser's."""
    from deck_emulator import cli
    from deck_emulator.app import NAMES

    whole = _subparsers(cli.build_parser())
    assert list(whole) == list(dict.fromkeys(name.split()[0] for name in NAMES))
    argv = ["run", "steel40", "--precision", "ibm7094", "--sincos", "round", "--erratum",
            "ed-direction", "--tha-start", "-1e-5", "--quiet"]
    assert (vars(cli.build_parser("run").parse_args(argv))
            == vars(cli.build_parser().parse_args(argv)))
    for name, parser in whole.items():
        alone = _subparsers(cli.build_parser(name))
        assert list(alone) == [name]
        assert alone[name].format_help() == parser.format_help(), name
        assert alone[name].format_usage() == parser.format_usage(), name


def test_each_command_is_the_module_of_its_name():
    """A command line loads only its command's module: each name of app.NAMES is the module
    that registers it (``study error``: ``study_error``), and no module registers another."""
    import importlib

    from deck_emulator import app

    for name in app.NAMES:
        module = importlib.import_module(f"deck_emulator.app.{name.replace(' ', '_')}")
        registered = [n for n, c in app.COMMANDS.items() if c.run.__module__ == module.__name__]
        assert registered == [name]
    assert list(app.all_commands()) == list(app.NAMES)
