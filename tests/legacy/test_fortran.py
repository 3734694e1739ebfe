"""The FORTRAN front end (legacy/fortran) against independent sources: gfortran's build of the
listing with the options' literals respelled in its text, and of each mutated program; for the
7094's arithmetic, the goldens' story (test_emulator.py holds the listing against the goldens)."""

from __future__ import annotations

import json
import random
import re
import tempfile
from pathlib import Path

import pytest

from deck_emulator.cli import main
import oracle
from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.stops import EmulatorError
from deck_emulator.legacy.fortran import DialectError, Program, listing_program, run_deck
from deck_emulator.legacy import listing_lines
from deck_emulator.legacy.jobdeck import job_deck_texts

from test_emulator import GOLDEN, ROOT
from test_goldens import need_gfortran


@pytest.fixture(autouse=True)
def _made_code_kept_in_a_temporary_folder(tmp_path, monkeypatch):
    """(a program's made code is kept in the user's cache folder: here, a temporary one)"""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))


def _deck(name: str):
    return read_deck(ROOT / "decks" / f"{name}.dat")


def test_the_7094s_arithmetic_tells_the_goldens_story():
    """The 7094's 27-bit words take other steps than binary64 (4129 records, the golden 4769),
    so its printout is not the golden's; the story is: the same three events, in order, at
    times within 2 % of those gfortran's binary64 build printed (measured: 0.4, 0.7, 1.8 %)."""
    from deck_emulator.legacy.printer import event_message

    run = run_deck(_deck("steel40"), "ibm7094", trace=False)
    golden = (GOLDEN / "steel40.r8.txt").read_text()
    printed = re.findall(r"TIME IS\s+(\S+)\s*\n(?:.*\n){2}\s*(THE POST HAS .*)", golden)
    assert [event_message(e) for e in run.events] == [m for _, m in printed]
    for event, (t, _) in zip(run.events, printed):
        assert event.time_s == pytest.approx(float(t), rel=0.02)
    assert len(run.records) > 4000


#: The listing's options as its text respelled (gfortran compiles that): each statement of
#: STEP_LITERALS with its step halved (k=1) or quartered (k=2): binary64 divides by 2 exactly.
_RESPELLED = {
    1: {"HI=0.0004": "HI=0.0002", "H=0.0004": "H=0.0002", "IF(Q-0.0004)123,44,44":
        "IF(Q-0.0002)123,44,44", "IF(Q-.0004)83,84,84": "IF(Q-.0002)83,84,84",
        "THA=0.000022": "THA=0.000011", "IF(LL-20)600,501,501": "IF(LL-40)600,501,501",
        "E=E+.0004": "E=E+.0002", "E=E+0.0002": "E=E+0.0001"},
    2: {"HI=0.0004": "HI=0.0001", "H=0.0004": "H=0.0001", "IF(Q-0.0004)123,44,44":
        "IF(Q-0.0001)123,44,44", "IF(Q-.0004)83,84,84": "IF(Q-.0001)83,84,84",
        "THA=0.000022": "THA=0.0000055", "IF(LL-20)600,501,501": "IF(LL-80)600,501,501",
        "E=E+.0004": "E=E+.0001", "E=E+0.0002": "E=E+0.00005"},
}


def _gfortran_listing(tmp: Path, precision: str, errata=(), step_scale_k=0, tha_start=None,
                      ed_tolerance=None) -> Path:
    """The listing (errata applied by the oracle's build) with the options spelled in its text,
    compiled by gfortran with the goldens' flags."""
    erratum = errata[0] if errata else None
    oracle.compile_program(tmp, precision, erratum)
    lines = (tmp / f"src-{erratum or 'printed'}" / "legacy" / "luminaire.f").read_text().splitlines()
    respelled = dict(_RESPELLED.get(step_scale_k, {}))
    if tha_start:
        respelled["THA=0.000022"] = f"THA={tha_start}"
    if ed_tolerance:
        for end in ("4", "13"):
            respelled[f"IF(ABS(DF(DH))-.0001)20,20,{end}"] = (
                f"IF(ABS(DF(DH))-{ed_tolerance})20,20,{end}")
    lines = [line[:6] + respelled.get(line[6:].strip(), line[6:]) for line in lines]
    return oracle.compile_source(tmp, lines, precision, f"options-{precision}")


@pytest.mark.parametrize("options", [
    dict(errata=("ed-direction",)), dict(step_scale_k=1),
    dict(step_scale_k=2, errata=("ed-direction",)), dict(tha_start="0.00003"),
    dict(ed_tolerance=".00001"), dict(step_scale_k=2, tha_start="0.000011", ed_tolerance=".00005"),
], ids=str)
@pytest.mark.parametrize("precision, build", [("double", "r8"), ("single", "r4")])
def test_the_listings_options_print_what_gfortran_prints_for_them_spelled(tmp_path, options,
                                                                          precision, build):
    """Errata and the options of listing_program against gfortran's build of the listing with
    the same changes made in its text (binary32: both trap at the same statement)."""
    need_gfortran()
    exe = _gfortran_listing(tmp_path, build, **options)
    errata = options.get("errata", ())
    o = oracle.compare(_deck("steel40"), lambda erratum: exe, tmp_path, timeout_s=5.0,
                       ours=lambda deck, errata: run_deck(deck, precision, errata=errata,
                                                          trace=False, **{
                           k: v for k, v in options.items() if k != "errata"}),
                       errata=errata)
    assert o.agree, o.why  # (the same records; both end, both trap, or a guard where it hangs)
    if precision == "double":
        assert o.records > 20
    else:  # binary32 traps at step 2, before any record (as in the r4 goldens)
        assert o.ending_compiled == "trap"


def test_step_scale_divides_the_listings_step_literals_in_its_generated_source():
    source = listing_program(step_scale_k=2).python()
    assert "s_k_0p0004 = k_0p0004/_K('2.')/_K('2.')" in source
    assert "HI = s_k_0p0004  # HI=0.0004" in source
    assert "LL-80" in source and "# IF(LL-20)600,501,501" in source
    assert "THA = k_0p00003  # THA=0.000022" in listing_program(tha_start="0.00003").python()
    with pytest.raises(ValueError, match="unknown erratum"):
        listing_program(("no-such",))


def test_the_rows_of_the_literals_the_options_replace_are_the_listings_own():
    """The defaults' rows of THA's start-up and ED's tolerance, read against luminaire.f's
    statements (labels 123, 15 and 16), and an option's value reaching both ED statements."""
    from deck_emulator.legacy.jobdeck import statements as cards
    from deck_emulator.vocabulary import defaults

    punched = {s.text.replace(" ", "") for s in cards(listing_lines())}
    assert f"THA={defaults.LISTING_THA_START}" in punched
    assert {f"IF(ABS(DF(DH))-{defaults.LISTING_ED_TOLERANCE})20,20,{label}"
            for label in (4, 13)} <= punched
    source = listing_program(ed_tolerance="0.003").python()
    assert source.count("# IF(ABS(DF(DH))-.0001)20,20,") == 2 and "0p003" in source


def test_the_generated_source_keeps_the_statements_one_a_line_with_their_labels():
    program = listing_program()
    source = program.python()
    statements = [line.split("  # ", 1)[1] for line in source.splitlines() if "  # " in line
                  and not line.lstrip().startswith(("def ", "#"))]
    # every executable statement of the listing, in order, one a line
    from deck_emulator.legacy.jobdeck import statements as cards

    executable = [f"{s.label + ' ' if s.label else ''}{s.text}" for s in cards(listing_lines())
                  if not s.text.startswith(("FORMAT", "SUBROUTINE")) and "DF(D)=" not in s.text]
    assert statements == executable
    assert "    def _block():  # label 125" in source and "    def _block():  # label 41" in source


# ------------------------------------------------------------------------------ refusals


@pytest.mark.parametrize("card, kind, columns", [
    ("      DOUBLE PRECISION X", "DOUBLE PRECISION", "columns 7-72"),
    ("      READ(3,1)X", "READ", "column 12"),
    ("      IF(Q.GT.0.)DO 10 I=1,5", "IF", "column 18"),  # a DO in a logical IF
    ("      DO 10 I=1,5", "DO", "columns 7-72"),  # MAIN has no statement 10
    ("      X=SQRT(Q)", "assignment", "column 9"),
    ("      DIMENSION X(10)", "DIMENSION", "columns 7-72"),  # after executable statements
    ("      IF(Q.GT.0.)Q=Q.GT.1.", "IF", "column 20"),  # a relation assigned
    ("      GO TO (125, 12), Q", "GO TO", "column 24"),  # a REAL index
])
def test_a_statement_outside_the_dialect_is_refused_naming_card_columns_and_kind(card, kind,
                                                                                  columns):
    lines = listing_lines()
    at = lines.index("      HI=0.0004")
    with pytest.raises(DialectError) as info:
        Program(lines[:at] + [card] + lines[at:])
    message = str(info.value)
    assert "\n" not in message and f"card {at + 1}, {columns}: {kind} statement:" in message


def _job(tmp_path: Path, old: str, new: str, name: str = "changed.job") -> Path:
    texts = job_deck_texts([_deck("steel40")])
    at = texts.index(old)
    texts[at] = new
    path = tmp_path / name
    path.write_text("\n".join(texts) + "\n")
    return path


def test_run_refuses_a_deck_whose_fortran_is_outside_the_dialect_and_runs_nothing(tmp_path,
                                                                                   capsys):
    job = _job(tmp_path, "      HI=0.0004", "      DOUBLE PRECISION HI")
    out = tmp_path / "out.txt"
    assert main(["run", str(job), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    lines = [x for x in err.splitlines() if x.startswith("deck-emulator: error:")]
    assert len(lines) == 1 and "Traceback" not in err and not out.exists()
    assert "DOUBLE PRECISION statement" in lines[0] and "card 23" in lines[0]
    assert "nothing was run" in lines[0]


# ------------------------------------------------------------- the deck's own program runs


def _gfortran_prints(lines, deck, tmp: Path) -> tuple[str, str]:
    exe = oracle.compile_source(tmp, lines, "r8", "program")
    path = tmp / "deck.dat"
    path.write_text(deck.to_text())
    out, _err, ending = oracle.run_program(exe, path)
    return out, ending


def test_run_runs_the_job_decks_own_fortran_as_gfortran_does(tmp_path, capsys):
    need_gfortran()
    job = _job(tmp_path, "  504 FSA=FCONST", "  504 FSA=FCONST*0.5")
    out = tmp_path / "out.txt"
    assert main(["run", str(job), "--out", str(out), "--quiet"]) == 0
    first = capsys.readouterr().err.splitlines()[0]
    assert "the job deck's own FORTRAN runs" in first
    assert "statement 153 differs" in first and "'504 FSA=FCONST*0.5' against" in first
    lines = listing_lines()
    lines[lines.index("  504 FSA=FCONST")] = "  504 FSA=FCONST*0.5"
    theirs, ending = _gfortran_prints(lines, _deck("steel40"), tmp_path)
    assert ending == "normal" and out.read_text() == theirs
    assert theirs != (GOLDEN / "steel40.r8.txt").read_text()  # the change shows
    # --listing-program: the transcription on the deck's data, the golden
    assert main(["run", str(job), "--listing-program", "--out", str(out)]) == 0
    assert out.read_text() == (GOLDEN / "steel40.r8.txt").read_text()
    # --json and the banner's facts name the program that ran, with its SHA-256
    capsys.readouterr()
    assert main(["run", str(job), "--json", "--quiet"]) == 0
    facts = json.loads(capsys.readouterr().out)["provenance"]
    texts = job.read_text().splitlines()
    program = Program(texts[:texts.index("$DATA")])
    assert facts["program sha256"] == program.sha256 != Program(listing_lines()).sha256
    assert "own FORTRAN" in facts["program"]


def test_errata_are_refused_for_a_decks_own_fortran(tmp_path, capsys):
    job = _job(tmp_path, "      HI=0.0004", "      HI=0.0002")
    assert main(["run", str(job), "--erratum", "ed-direction"]) == 2
    assert "--erratum change the listing's program" in capsys.readouterr().err


def test_a_trajectory_of_a_decks_own_fortran_where_it_keeps_the_listings_labels(tmp_path,
                                                                                capsys):
    """The trace is recorded at the listing's labels 41, 42, 400 and 82: a program that keeps
    them writes its own trajectory (ending at the hit its printout shows); one whose label 82
    is renumbered 890 is refused, nothing written."""
    job = _job(tmp_path, "      HI=0.0004", "      HI=0.0002")
    csv, listing_csv = tmp_path / "t.csv", tmp_path / "listing.csv"
    assert main(["run", str(job), "--trajectory", str(csv), "--quiet", "--out",
                 str(tmp_path / "own.txt")]) == 0
    assert main(["run", str(job), "--listing-program", "--trajectory", str(listing_csv),
                 "--quiet", "--out", str(tmp_path / "listing.txt")]) == 0
    own, listing = csv.read_text().splitlines(), listing_csv.read_text().splitlines()
    assert own[0] == listing[0] and len(own) > 1000 and own[1:] != listing[1:]
    printed = re.findall(r"TIME IS\s+(\S+)", (tmp_path / "own.txt").read_text())
    assert float(own[-1].split(",")[0]) == pytest.approx(float(printed[-1]), abs=5e-6)  # the hit
    capsys.readouterr()
    job = _job(tmp_path, "      IF(I-1)81,82,81", "      IF(I-1)81,890,81", name="82.job")
    job.write_text(job.read_text().replace("   82 CONTINUE\n", "  890 CONTINUE\n", 1))
    csv.unlink()
    assert main(["run", str(job), "--trajectory", str(csv)]) == 2
    err = capsys.readouterr().err
    assert "keeps no trajectory" in err and "82" in err and not csv.exists()


# ------------------------------------------------------------------- mutants and gfortran


def _mutants_agree(count: int, seed: int, swaps: int):
    """``count`` of oracle.mutants (a constant, a FORMAT's letter or field changed) and
    ``swaps`` reordered ones, each on steel40 or steel20, against gfortran's build of it."""
    need_gfortran()
    decks = [_deck("steel40"), _deck("steel20")]
    corpus = oracle.mutants(count, seed, swaps=swaps)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for k, (what, lines) in enumerate(corpus):
            exe = oracle.compile_source(tmp, lines, "r8", f"m{k}")
            program = Program(lines)
            o = oracle.compare(decks[k % 2], lambda erratum: exe, tmp, timeout_s=3.0,
                               ours=lambda deck, errata: program.runner(deck, "double").run(),
                               errata=())
            assert o.agree, f"{what}: {o.why}"


def test_seeded_mutants_print_what_gfortran_prints():
    _mutants_agree(6, seed=34, swaps=3)


@pytest.mark.slow_corpus  # a larger corpus: on request (-m slow_corpus)
def test_the_larger_corpus_of_mutants_prints_what_gfortran_prints():
    _mutants_agree(80, seed=3400, swaps=40)


def test_a_reordered_mutant_swaps_two_independent_assignments_and_keeps_the_labels():
    lines = listing_lines()
    rng = random.Random(7)
    for _ in range(20):
        what, mutant = oracle.reordered(rng, lines)
        n = int(re.search(r"lines (\d+)", what).group(1)) - 1
        changed = [i for i, (a, b) in enumerate(zip(lines, mutant)) if a != b]
        assert changed == [n, n + 1] and [m[:6] for m in mutant] == [x[:6] for x in lines]
        assert mutant[n][6:] == lines[n + 1][6:] and mutant[n + 1][6:] == lines[n][6:]


# ------------------------------------------------------------ the listing's made code


def test_the_listings_made_code_is_kept_and_a_later_start_parses_nothing():
    """The listing, as any program, is parsed and made once; a later start (a new Program of
    the same cards) runs the kept code and prints the golden without parsing."""
    first = Program(listing_lines, name="legacy/luminaire.f")
    assert first.runner(_deck("steel40"), "double").run().text() == (
        GOLDEN / "steel40.r8.txt").read_text()
    again = Program(listing_lines, name="legacy/luminaire.f")
    assert again._units is None  # nothing parsed: its code was kept
    code, _ = again._make(True, False)
    assert code.co_filename == "<fortran>" and again._units is None
    assert again.runner(_deck("steel40"), "double").run().text() == (
        GOLDEN / "steel40.r8.txt").read_text()


def test_the_engine_runs_the_listing_through_the_front_end(tmp_path):
    from deck_emulator.engine import EmulatorEngine
    from deck_emulator.legacy.fortran import Runner

    engine = EmulatorEngine(errata=("ed-direction",), step_scale_k=1)
    program = engine.program(_deck("steel40"))
    assert isinstance(program, Runner) and program.errata == ("ed-direction",)
    out = engine.run(_deck("steel40"))
    assert len(out.t) > 2000  # the trajectory, from the front end's trace
    need_gfortran()
    exe = _gfortran_listing(tmp_path, "r8", errata=("ed-direction",), step_scale_k=1)
    path = tmp_path / "steel40.dat"
    path.write_text(_deck("steel40").to_text())
    theirs, _, ending = oracle.run_program(exe, path)
    assert ending == "normal" and "".join(r + "\n" for r in out.records) == theirs


def test_a_defect_of_ours_names_the_label_it_stopped_in(monkeypatch):
    """record_defects: an exception that is not the program's (here: the event of FORMAT 355,
    written in the block of label 354, made to fail) is named with the label it ran in."""
    from deck_emulator.engine import EmulatorEngine
    from deck_emulator.legacy.fortran import Runner

    def fails(self, fmt, t):
        raise RuntimeError(f"no event for FORMAT {fmt}")

    monkeypatch.setattr(Runner, "event", fails)
    out = EmulatorEngine(record_defects=True, trace=False).run(_deck("steel40"))
    assert out.guard == "crash"
    assert re.fullmatch(r"RuntimeError: no event for FORMAT 355 \(label 354, step \d+\)",
                        out.error), out.error
