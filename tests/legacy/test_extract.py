"""deck_emulator.legacy.extract on the gfortran golden, checked against the golden's own text parsed
here independently; and deck_emulator.studies.report_tables checked against the report's scanned text."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.extract import (
    INSTANTS,
    ExtractError,
    Outcome,
    extract,
    parse_printout,
)
from deck_emulator.studies.report_tables import CASES, REPORT, ROW_LABELS

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = ROOT / "golden" / "steel40.r8.txt"
SEED = ROOT.parent / "shared" / "seed" / "000_527dfe033c64384d.txt"


@pytest.fixture(scope="module")
def deck():
    return read_deck(ROOT / "decks" / "steel40.dat")


@pytest.fixture(scope="module")
def text():
    return GOLDEN.read_text()


@pytest.fixture(scope="module")
def outcome(text, deck) -> Outcome:
    return extract(text, deck)


# ---- the golden, read here with nothing but regular expressions -------------------------------

def _lines(text):
    return text.splitlines()


def _value(line_text, name):
    m = re.search(rf"THE VALUE OF {name} IS +(\S+)", line_text)
    return None if m is None else float(m.group(1))


def _last_before(lines, index, name):
    """The last printed value of `name` on a line before `index`."""
    for i in range(index - 1, -1, -1):
        v = _value(lines[i], name)
        if v is not None:
            return v
    raise AssertionError(f"no {name} before line {index}")


def _first_after(lines, index, name):
    for line in lines[index + 1:]:
        v = _value(line, name)
        if v is not None:
            return v
    raise AssertionError(f"no {name} after line {index}")


def test_hit_message_and_final_time_as_in_the_golden(text, outcome):
    lines = _lines(text)
    hits = [i for i, s in enumerate(lines) if "THE POST HAS HIT" in s]
    assert len(hits) == 1
    assert outcome.hit == lines[hits[0]].strip() == "THE POST HAS HIT THE GROUND WITH POINT R"
    times = [float(m.group(1)) for m in re.finditer(r"THE VALUE OF TIME IS +(\S+)", text)]
    assert outcome.final_time_s == times[-1] == 0.8216
    # the hit's block is printed after the message (GO TO 98): its TIME is the last one
    assert outcome.hit_time_s == _first_after(lines, hits[0], "TIME") == times[-1]


def test_events_count_and_times(text, outcome):
    lines = _lines(text)
    lost = [i for i, s in enumerate(lines) if "LOST CONTACT" in s]
    assert len(outcome.events) == len(lost) == 2
    for event, i in zip(outcome.events, lost, strict=True):
        assert event.message == lines[i].strip()
        # the step that lost contact is printed just before the message (GO TO 88)
        assert event.time_s == _last_before(lines, i, "TIME")
    assert [e.time_s for e in outcome.events] == [0.1, 0.1184]
    assert "FIRST SPRING" in outcome.events[0].message
    assert "THE VEHICLE" in outcome.events[1].message


def test_terminal_coordinates_are_the_last_block_moved_to_the_base(text, deck, outcome):
    lines = _lines(text)
    hit = next(i for i, s in enumerate(lines) if "THE POST HAS HIT" in s)
    d = deck.values
    raw = {name: _first_after(lines, hit, name)
           for name in ("XPFA", "YYPFA", "ZZPFA", "XQFA", "YYQFA", "ZZQFA", "XRFA", "YYRFA",
                        "ZZRFA", "XCFA", "YYCFA", "ZYCFA")}
    q = outcome.terminal["Q"]
    assert q.XL == pytest.approx(raw["XQFA"] - d["XQO"], abs=1e-12)
    assert q.YL == pytest.approx(raw["YYQFA"] - d["YYQO"], abs=1e-12)
    assert q.ZL == pytest.approx(raw["ZZQFA"] + d["HEIGHT"], abs=1e-12)
    for p in ("P", "R"):
        pt = outcome.terminal[p]
        assert pt.XL == pytest.approx(raw[f"X{p}FA"] - d["XQO"], abs=1e-12)
        assert pt.YL == pytest.approx(raw[f"YY{p}FA"] - d["YYQO"], abs=1e-12)
        assert pt.ZL == pytest.approx(raw[f"ZZ{p}FA"] + d["HEIGHT"], abs=1e-12)
    # ZYCFA is FORMAT 133's typo for ZZCFA; C coincides with Q in this deck
    assert outcome.terminal["C"].ZL == pytest.approx(raw["ZYCFA"] + d["HEIGHT"], abs=1e-12)
    assert outcome.terminal["C"] == outcome.terminal["Q"]
    # R hit the ground: the listing's test is |ZZRFA + HEIGHT| <= 0.1
    assert abs(outcome.terminal["R"].ZL) <= 0.1
    assert outcome.terminal_time_s == outcome.final_time_s


def test_max_force_and_the_speeds_at_the_instants_are_the_printed_values(text, deck, outcome):
    d = deck.values
    fsa = [float(x) for x in re.findall(r"THE VALUE OF FSA IS +(\S+)", text)]
    times = [float(x) for x in re.findall(r"THE VALUE OF TIME IS +(\S+)", text)]
    assert outcome.max_fsa_lb == max(fsa)
    lines = _lines(text)
    for instant, message in (("first_spring_lost", "LOST CONTACT WITH FIRST SPRING"),
                             ("vehicle_contact_lost", "LOST CONTACT WITH THE VEHICLE")):
        i = next(i for i, s in enumerate(lines) if message in s)
        assert outcome.vehicle_speed_fps[instant] == _last_before(lines, i, "VVA")
    # crush-pulse end: the first FSA printed equal to FCONST after one above it
    vvas = [float(x) for x in re.findall(r"THE VALUE OF VVA IS +(\S+)", text)]
    k = next(k for k in range(1, len(fsa)) if fsa[k - 1] > d["FCONST"] and fsa[k] == d["FCONST"])
    assert outcome.vehicle_speed_fps["crush_pulse_end"] == vvas[k]
    assert outcome.crush_pulse_end_s == times[k]  # contact blocks come first, TIME in each
    assert tuple(outcome.vehicle_speed_fps) == INSTANTS
    # VVFA is constant in free flight: the speed recovered from SVFA equals VVA at separation
    assert outcome.vehicle_speed_fps["end_of_run"] == pytest.approx(
        outcome.vehicle_speed_fps["vehicle_contact_lost"], abs=0.005)


def test_text_and_records_give_the_same_outcome(text, deck, outcome):
    assert extract(text.splitlines(), deck) == outcome
    assert extract(text.splitlines(), deck.values) == outcome
    # YYPFA 1.51891 - YYQO 1.53, to the printout's 5 decimals
    assert round(outcome.terminal["P"].YL, 5) == -0.01109


def test_parse_keeps_the_variable_names_behind_the_typos(text):
    blocks = [b for b in parse_printout(text) if hasattr(b, "kind")]
    assert {b.kind for b in blocks} == {"contact", "free"}
    assert "ZZCMA" in blocks[0].values and "ZXCMA" not in blocks[0].values
    assert "ZZCFA" in blocks[-1].values and "ZYCFA" not in blocks[-1].values


def test_cut_printout_and_empty_printout(text, deck):
    lines = text.splitlines()
    hit = next(i for i, s in enumerate(lines) if "THE POST HAS HIT" in s)
    cut = extract(lines[:hit], deck)
    assert cut.hit is None and cut.terminal and cut.notes
    with pytest.raises(ExtractError):
        extract("", deck)


def test_emulator_double_gives_the_golden_outcome(deck, outcome):
    from deck_emulator.legacy.fortran import run_deck

    run = run_deck(deck, "double")
    assert extract(run, deck) == outcome
    from deck_emulator.legacy.printer import event_message

    assert [event_message(e) for e in run.events][:2] == [e.message for e in outcome.events]


# ---- the report's tables against the scanned text -----------------------------------------------

def _seed_row(lines, mph, label):
    """The nine cells of a row of Table 11 (20 mph) or 12 (40 mph)."""
    caption = "TABLE II A COMPARISON" if mph == 20 else "TABLE 12 A COMPARISON"
    end = next(i for i, s in enumerate(lines) if s.startswith(caption))
    start = max(i for i, s in enumerate(lines[:end]) if s.startswith("VEHICLE VELOCITY (MPH)"))
    row = next(s for s in lines[start:end] if s.startswith(label))
    cells = row.split("\t")[1:]
    return cells + [""] * (9 - len(cells))


@pytest.mark.skipif(not SEED.exists(), reason="the report's text (../shared/seed) is not here")
@pytest.mark.parametrize("deck_name", ["steel40", "steel20_a30"])
def test_report_table_column_matches_the_seed(deck_name):
    lines = SEED.read_text().splitlines()
    mph, alpha, _ = CASES[deck_name]
    column = 3 + (0, 15, 30).index(alpha)  # STEEL POST: the 4th to 6th of nine columns
    for field, label in ROW_LABELS.items():
        cell = _seed_row(lines, mph, label)[column].strip()
        want = REPORT[deck_name][field]
        if cell in ("", "—"):
            assert want is None, field
        elif field == "comment":
            assert want == cell
        else:
            assert want == float(cell), field


# ---- a printed value that overflows its field ------------------------------


def test_an_overflowed_terminal_value_reads_as_none_and_is_named(text, deck):
    # F15.5 prints a value of 10**9 ft or more as a field of asterisks; the last block's
    # XRFA (record 4743 of the golden) made so must not break the extraction.
    lines = text.split("\n")
    k = max(i for i, line in enumerate(lines) if "THE VALUE OF XRFA IS" in line)
    lines[k] = lines[k].split(" IS ")[0] + " IS " + "*" * 15
    out = extract("\n".join(lines), deck)
    assert out.terminal["R"].XL is None
    assert out.terminal["R"].YL is not None and out.terminal["P"].XL is not None
    assert any("XRFA overflowed" in n for n in out.notes)


def test_a_damaged_value_is_a_named_extract_error(text, deck):
    damaged = text.replace("THE VALUE OF XRFA IS    0.34894", "THE VALUE OF XRFA IS    0.3#894", 1)
    assert damaged != text
    with pytest.raises(ExtractError, match="XRFA"):
        extract(damaged, deck)
