"""The FORTRAN front end (legacy/fortran) against independent sources: the goldens (gfortran's
build of legacy/luminaire.f), gfortran's build of each mutated program, and, for the 7094's
arithmetic, the hand port of the listing (another program over the same arithmetic)."""

from __future__ import annotations

import json
import re
import tempfile
from pathlib import Path

import pytest

from deck_emulator.cli import main
from deck_emulator.legacy import oracle
from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.emulator import EmulatorError, Limits, run_deck
from deck_emulator.legacy.fortran import DialectError, Program, listing_program
from deck_emulator.legacy.jobdeck import job_deck_texts, listing_lines

from test_emulator import GOLDEN, ROOT, golden_runs
from test_goldens import need_gfortran


def _deck(name: str):
    return read_deck(ROOT / "decks" / f"{name}.dat")


def _ended(runner):
    try:
        return runner.run(), None
    except EmulatorError as exc:
        return exc.run, exc


@pytest.mark.parametrize("deck_name, errata, golden", golden_runs("r8"))
def test_the_listing_through_the_front_end_prints_the_r8_golden(deck_name, errata, golden):
    run = listing_program(errata).runner(_deck(deck_name), "double").run()
    assert run.text() == golden.read_text()  # byte for byte


@pytest.mark.parametrize("deck_name, errata, golden", golden_runs("r4"))
def test_binary32_stops_where_gfortran_traps(deck_name, errata, golden):
    trap = golden.with_suffix("").with_suffix(".r4.trap").read_text()
    run, err = _ended(listing_program(errata).runner(_deck(deck_name), "single"))
    assert err is not None and err.guard == "arithmetic"
    assert run.records == golden.read_text().splitlines()
    assert err.variable == re.search(r"statement:\n\s+(\w+)=", trap).group(1)  # PHIA
    assert err.label == 44 and err.step == 2


def test_the_7094s_arithmetic_prints_what_the_port_prints():
    deck = _deck("steel40")
    ours = listing_program().runner(deck, "ibm7094").run()
    assert ours.text() == run_deck(deck, "ibm7094", trace=False).text()
    assert len(ours.records) > 4000


@pytest.mark.parametrize("change, label, variable, guard", [
    (dict(W=0.0), 124, "V1A", "arithmetic"),  # a massless post: F1B/W
    (dict(XCMB=1.0), "ED 21", "DF", "arithmetic"),  # DF divides by SIN(THB + ...) = 0
    (dict(XCMB=1.0, THB=0.000022, THDB=0.0545, W2B=0.0545), 108, None, "halvings"),
    (dict(HEIGHT=5000.0), 59, None, "time_s"),  # a post that never lands
])
def test_a_run_stops_where_and_as_the_port_stops(change, label, variable, guard):
    deck = _deck("steel40").with_values(**change)
    limits = Limits(halvings=12, time_s=1.5)
    run, err = _ended(listing_program().runner(deck, "double", limits=limits))
    with pytest.raises(EmulatorError) as port:
        run_deck(deck, limits=limits, trace=False)
    assert err is not None and err.guard == guard == port.value.guard
    assert (err.label, err.variable, err.step) == (label, variable, port.value.step)
    assert err.time == port.value.time and str(err) == str(port.value)
    assert run.records == port.value.run.records


def test_ed_walking_away_stops_as_the_ports_root_search_guard():
    deck = _deck("steel40_a15")
    limits = Limits(ed_iterations=5000)
    run, err = _ended(listing_program().runner(deck, "double", limits=limits))
    with pytest.raises(EmulatorError) as port:
        run_deck(deck, limits=limits, trace=False)
    assert err.guard == "ed_iterations" == port.value.guard
    assert "ED's root search did not converge in 5000 iterations (D = " in str(err)
    assert str(err) == str(port.value)
    assert (err.label, err.step, err.time) == (port.value.label, port.value.step,
                                               port.value.time)
    assert run.records == port.value.run.records


# ------------------------------------------- one engine: what the port gives, the front end gives


def _both(deck, precision, *, errata=(), limits=Limits(), trace=True, **options):
    """(port's run, its error), (front end's run, its error) of the listing on ``deck``."""
    from deck_emulator.legacy.emulator import Program as Port

    port = _ended(Port(deck, precision, errata=errata, limits=limits, trace=trace,
                       **options))
    program = listing_program(errata, **options)
    return port, _ended(program.runner(deck, precision, limits=limits, trace=trace))


def _same(port, ours):
    (a, ea), (b, eb) = port, ours
    assert b.records == a.records
    assert b.trace == a.trace  # the rows the Outcome's arrays are built from
    assert b.events == a.events
    assert (b.errata, b.step_scale_k, b.arithmetic) == (a.errata, a.step_scale_k, a.arithmetic)
    assert str(eb) == str(ea) and getattr(eb, "guard", None) == getattr(ea, "guard", None)


@pytest.mark.parametrize("precision", ["double", "single", "ibm7094"])
@pytest.mark.parametrize("errata", [(), ("ed-direction",)])
def test_the_front_end_gives_the_ports_records_trace_events_and_stop(precision, errata):
    """steel40 (lands; three events) in each precision and errata setting; binary32 stops."""
    port, ours = _both(_deck("steel40"), precision, errata=errata)
    _same(port, ours)
    assert len(ours[0].events) == (3 if precision != "single" else 0)


@pytest.mark.parametrize("options", [
    dict(step_scale_k=1), dict(step_scale_k=2, errata=("ed-direction",)),
    dict(tha_start="0.00003"), dict(ed_tolerance=".00001"),
    dict(step_scale_k=2, tha_start="0.000011", ed_tolerance=".00005"),
], ids=str)
def test_the_listings_options_through_the_front_end_give_the_ports_run(options):
    deck = _deck("steel40")
    errata = options.pop("errata", ())
    port, ours = _both(deck, "double", errata=errata, **options)
    _same(port, ours)


def test_step_scale_divides_the_listings_step_literals_in_its_generated_source():
    source = listing_program(step_scale_k=2).python()
    assert "s_k_0p0004 = k_0p0004/_K('2.')/_K('2.')" in source
    assert "HI = s_k_0p0004  # HI=0.0004" in source
    assert "LL-80" in source and "# IF(LL-20)600,501,501" in source
    assert "THA = k_0p00003  # THA=0.000022" in listing_program(tha_start="0.00003").python()
    with pytest.raises(ValueError, match="unknown erratum"):
        listing_program(("no-such",))


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
    assert "    def L125():" in source and "    def L41():" in source


# ------------------------------------------------------------------------------ refusals


@pytest.mark.parametrize("card, kind, columns", [
    ("      DOUBLE PRECISION X", "DOUBLE PRECISION", "columns 7-72"),
    ("      READ(3,1)X", "READ", "column 12"),
    ("      IF(Q.GT.0.)GO TO 125", "IF", "column 11"),
    ("      DO 10 I=1,5", "DO", "columns 7-72"),
    ("      X=SQRT(Q)", "assignment", "column 9"),
    ("      DIMENSION X(10)", "DIMENSION", "columns 7-72"),
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


def test_errata_and_a_trajectory_are_refused_for_a_decks_own_fortran(tmp_path, capsys):
    job = _job(tmp_path, "      HI=0.0004", "      HI=0.0002")
    assert main(["run", str(job), "--erratum", "ed-direction"]) == 2
    assert "--erratum change the listing's program" in capsys.readouterr().err
    csv = tmp_path / "t.csv"
    assert main(["run", str(job), "--trajectory", str(csv)]) == 2
    assert "keeps no trajectory" in capsys.readouterr().err and not csv.exists()


# ------------------------------------------------------------------- mutants and gfortran


def _mutants_agree(count: int, seed: int):
    need_gfortran()
    decks = [_deck("steel40"), _deck("steel20")]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for k, (what, lines) in enumerate(oracle.mutants(count, seed)):
            exe = oracle.compile_source(tmp, lines, "r8", f"m{k}")
            program = Program(lines)
            o = oracle.compare(decks[k % 2], lambda erratum: exe, tmp, timeout_s=3.0,
                               ours=lambda deck, errata: program.runner(deck, "double").run(),
                               errata=())
            assert o.agree, f"{what}: {o.why}"


def test_seeded_mutants_print_what_gfortran_prints():
    _mutants_agree(6, seed=34)


@pytest.mark.slow
def test_the_larger_corpus_of_mutants_prints_what_gfortran_prints():
    _mutants_agree(80, seed=3400)


@pytest.mark.slow
def test_the_differential_corpus_through_the_front_end_prints_as_the_compiled_listing():
    """tests/legacy/test_differential.py's 20 seeded decks, the listing run by the front end."""
    need_gfortran()
    from test_differential import SMALL, SMALL_SEED

    programs = {errata: listing_program(errata) for errata in ((), ("ed-direction",))}
    o = oracle.Oracle(timeout_s=2.0)
    try:
        for deck in oracle.corpus(SMALL, SMALL_SEED):
            outcome = oracle.compare(deck, o.exe, o.dir, o.timeout_s, ours=lambda deck, errata:
                                     programs[tuple(errata)].runner(deck, "double").run())
            assert outcome.agree, outcome.why
    finally:
        o.close()


# ------------------------------------------------------------ the listing's made source


def test_the_made_listing_source_is_what_the_front_end_makes_now():
    """legacy/fortran/listing_made.py is what ``python scripts/make_listing_source.py`` writes
    now (after a change to the listing or the front end, run it: meanwhile its first line no
    longer matches and the source is made at each start, never a stale one run)."""
    from deck_emulator.legacy.fortran.run import LISTING_FILE, MADE_LISTING

    assert MADE_LISTING.read_text() == listing_program().python(), \
        "run: python scripts/make_listing_source.py"
    program = Program(listing_lines, name="legacy/luminaire.f", made=MADE_LISTING,
                      cards_file=LISTING_FILE)
    code, _ = program._make(True, False)
    assert code.co_filename == str(MADE_LISTING)  # the made file's code is what runs
    assert program._units is None  # and nothing was parsed for it


def test_a_made_source_whose_first_line_differs_is_not_used(tmp_path):
    from deck_emulator.legacy.fortran.run import MADE_LISTING, LISTING_FILE

    stale = tmp_path / "listing_made.py"
    text = MADE_LISTING.read_text().replace("k_2p = _K('2.')", "k_2p = _K('3.')")
    stale.write_text(text)  # the same first line: it would be used
    lines = listing_lines()
    name = "legacy/luminaire.f"
    fresh = Program(lambda: lines, name=name, made=stale, cards_file=LISTING_FILE)
    assert fresh._make(True, False)[0].co_filename == str(stale)
    stale.write_text("# another program" + text[text.index("\n"):])
    other = Program(lambda: lines, name=name, made=stale, cards_file=LISTING_FILE)
    assert other._make(True, False)[0].co_filename == "<fortran>"
    assert other.runner(_deck("steel40"), "double").run().text() == (
        GOLDEN / "steel40.r8.txt").read_text()


def test_the_engine_runs_the_listing_through_the_front_end():
    from deck_emulator.engine import EmulatorEngine
    from deck_emulator.legacy.fortran import Runner

    engine = EmulatorEngine(errata=("ed-direction",), step_scale_k=1)
    program = engine.program(_deck("steel40"))
    assert isinstance(program, Runner) and program.errata == ("ed-direction",)
    out = engine.run(_deck("steel40"))
    port, _ = _both(_deck("steel40"), "double", errata=("ed-direction",), step_scale_k=1)
    assert out.records == tuple(port[0].records) and out.events == port[0].events
    assert len(out.t) > 2000  # the trajectory, from the front end's trace
