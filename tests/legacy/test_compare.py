"""Printouts compared by their records (issues 26, 33): the emulator's printout against the
compiled listing's of every golden deck agrees; each change below is made to the golden
steel40 printout here, and the findings expected are what that change is (a value changed is
one difference, a line lost is one record missing, a value damaged as a scan damages it is
read as what was printed before the damage), whatever the page layout; what is not a
printout is refused in one line."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = ROOT / "golden"
STEEL40 = GOLDEN / "steel40.r8.txt"
LINES = STEEL40.read_text().split("\n")
VALUE = re.compile(r"THE VALUE OF (\w+) IS +(\S+)")


def _goldens():
    """(deck, errata, golden) for the binary64 goldens: the compiled listing's printouts."""
    for path in sorted(GOLDEN.glob("*.r8.txt")):
        parts = path.name.split(".")
        yield pytest.param(parts[0], parts[1:-2], path, id=path.name)


def _compare(capsys, tmp_path, lines_b, *options, a=STEEL40) -> tuple[int, dict]:
    """compare A (the golden) with B (``lines_b``) --json: (exit status, the answer)."""
    b = tmp_path / "b.txt"
    b.write_text(lines_b if isinstance(lines_b, str) else "\n".join(lines_b))
    status = main(["compare", str(a), str(b), "--json", *options])
    return status, json.loads(capsys.readouterr().out)


def _counts(answer: dict) -> tuple[int, int, int]:
    return answer["differences_total"], answer["damaged_total"], answer["missing_total"]


def _line_of(name: str, nth: int = 0) -> int:
    """Index of the nth line that prints ``name`` (alone on its line)."""
    return [i for i, line in enumerate(LINES) if f"THE VALUE OF {name} IS" in line][nth]


def _replace_value(line: str, new: str) -> str:
    old = VALUE.search(line).group(2)
    return line[: line.rindex(old)] + new.rjust(len(old))


@pytest.mark.parametrize("deck, errata, golden", list(_goldens()))
def test_the_emulators_printout_agrees_with_the_compiled_listings(deck, errata, golden,
                                                                  tmp_path, capsys):
    ours = tmp_path / "ours.txt"
    argv = ["run", deck, "--out", str(ours)] + [a for e in errata for a in ("--erratum", e)]
    assert main(argv) == 0
    capsys.readouterr()
    assert main(["compare", str(ours), str(golden)]) == 0
    assert "agree (exactly as printed)" in capsys.readouterr().out


def test_the_same_printout_agrees(tmp_path, capsys):
    status, answer = _compare(capsys, tmp_path, LINES)
    assert status == 0 and answer["agree"] is True and _counts(answer) == (0, 0, 0)


def test_one_value_changed_is_one_difference_named_by_record_and_variable(tmp_path, capsys):
    k = _line_of("XPFA")
    old = VALUE.search(LINES[k]).group(2)
    changed = LINES[:]
    changed[k] = _replace_value(LINES[k], f"{float(old) + 0.25:.5f}")
    status, answer = _compare(capsys, tmp_path, changed)
    assert status == 1 and answer["agree"] is False and _counts(answer) == (1, 0, 0)
    (d,) = answer["differences"]
    assert (d["record_a"], d["record_b"], d["what"]) == (k + 1, k + 1, "XPFA")
    assert d["a"] == old and d["size"] == pytest.approx(0.25)
    # the block's TIME: the first TIME printed after the changed line
    time = next(VALUE.search(line).group(2) for line in LINES[k:] if "OF TIME IS" in line)
    assert d["time_s"] == float(time)
    status, answer = _compare(capsys, tmp_path, changed, "--tolerance", "0.3")
    assert status == 0 and _counts(answer) == (0, 0, 0)  # within a stated tolerance


def test_a_changed_time_is_one_difference_not_a_block_missing(tmp_path, capsys):
    k = _line_of("TIME", 7)
    changed = LINES[:]
    changed[k] = _replace_value(LINES[k], "0.999999")
    status, answer = _compare(capsys, tmp_path, changed)
    assert status == 1 and _counts(answer) == (1, 0, 0)
    assert answer["differences"][0]["what"] == "TIME"


@pytest.mark.parametrize("nth", [0, 40, 118])
def test_a_page_mark_removed_costs_nothing(nth, tmp_path, capsys):
    marks = [i for i, line in enumerate(LINES) if line == "1"]
    cut = LINES[: marks[nth]] + LINES[marks[nth] + 1:]
    status, answer = _compare(capsys, tmp_path, cut)
    assert status == 0 and _counts(answer) == (0, 0, 0)


def test_the_page_as_printed_agrees(tmp_path, capsys):
    """The asa-rendered form: form feeds and blank lines, no carriage-control column."""
    status = main(["run", "steel40", "--render", "--out", str(tmp_path / "asa.txt")])
    assert status == 0
    rendered = (tmp_path / "asa.txt").read_text()
    assert "\f" in rendered and not any(line[:1] == "1" for line in rendered.split("\n"))
    capsys.readouterr()
    status, answer = _compare(capsys, tmp_path, rendered)
    assert status == 0 and _counts(answer) == (0, 0, 0)


def test_a_printout_typed_with_other_spacing_agrees(tmp_path, capsys):
    """Another source's printout: its blank lines and page marks dropped, fields re-spaced."""
    typed = [" ".join(line.split()) for line in LINES if line.strip() and line != "1"]
    status, answer = _compare(capsys, tmp_path, typed)
    assert status == 0 and _counts(answer) == (0, 0, 0)


def _damage(field: str) -> str:
    """A scan's damage: the first 0 read as O, else the first 1 as l."""
    return field.replace("0", "O", 1) if "0" in field else field.replace("1", "l", 1)


def test_twelve_values_damaged_and_one_changed(tmp_path, capsys):
    values = [i for i, line in enumerate(LINES) if len(VALUE.findall(line)) == 1
              and re.search("[01]", VALUE.search(line).group(2))]
    damaged_at = values[3::150][:12]
    assert len(damaged_at) == 12
    changed_at = _line_of("SVFA", 5)
    assert changed_at not in damaged_at
    lines = LINES[:]
    printed = {}
    for k in damaged_at:
        field = VALUE.search(LINES[k]).group(2)
        printed[k] = _damage(field)
        assert printed[k] != field
        lines[k] = _replace_value(LINES[k], printed[k])
    lines[changed_at] = _replace_value(LINES[changed_at], "12.34567")
    status, answer = _compare(capsys, tmp_path, lines)
    assert status == 1 and _counts(answer) == (1, 12, 0)
    assert answer["differences"][0]["record_b"] == changed_at + 1
    assert answer["differences"][0]["b"] == "12.34567"
    found = {d["record"]: d for d in answer["damaged"]}
    assert set(found) == {k + 1 for k in damaged_at}
    for k in damaged_at:
        d = found[k + 1]
        assert d["printout"] == "B" and d["reading"] == "damaged"
        assert d["printed"] == printed[k]
        assert d["read_as"] == VALUE.search(LINES[k]).group(2)  # what was printed before


def test_damage_alone_does_not_make_printouts_differ(tmp_path, capsys):
    k = _line_of("XPA", 3)
    lines = LINES[:]
    field = VALUE.search(LINES[k]).group(2)
    lines[k] = _replace_value(LINES[k], _damage(field))
    status, answer = _compare(capsys, tmp_path, lines)
    assert status == 0 and answer["agree"] is True and _counts(answer) == (0, 1, 0)


@pytest.mark.parametrize("name, nth, damaged", [
    ("VVA", 0, lambda f: f.replace(".", "")),  # the point lost: F15.5 puts it back
    ("XCMFA", 3, lambda f: f.replace(".", "..")),  # the point doubled
    ("TIME", 2, lambda f: f.replace(".", "")),  # F10.6 in a contact block
    ("TIME", -1, lambda f: f.replace(".", "")),  # F10.5 in free flight
])
def test_a_lost_or_doubled_point_is_put_back_where_the_format_has_it(name, nth, damaged,
                                                                    tmp_path, capsys):
    k = _line_of(name, nth)
    field = VALUE.search(LINES[k]).group(2)
    lines = LINES[:]
    lines[k] = _replace_value(LINES[k], damaged(field))
    status, answer = _compare(capsys, tmp_path, lines)
    assert status == 0 and _counts(answer) == (0, 1, 0)
    assert answer["damaged"][0]["read_as"] == field


def test_an_unreadable_value_is_named_and_the_comparison_goes_on(tmp_path, capsys):
    k, later = _line_of("XRFA", 2), _line_of("YYQFA", 30)
    lines = LINES[:]
    lines[k] = _replace_value(LINES[k], "0.3#8%4")
    lines[later] = _replace_value(LINES[later], "77.00000")
    status, answer = _compare(capsys, tmp_path, lines)
    assert status == 1 and _counts(answer) == (1, 1, 0)
    (d,) = answer["damaged"]
    assert (d["record"], d["reading"], d["read_as"], d["printed"]) == (
        k + 1, "unreadable", None, "0.3#8%4")
    assert answer["differences"][0]["record_a"] == later + 1


def test_one_value_line_removed_is_one_record_missing(tmp_path, capsys):
    k = _line_of("XPFA", 4)
    status, answer = _compare(capsys, tmp_path, LINES[:k] + LINES[k + 1:])
    assert status == 1 and _counts(answer) == (0, 0, 1)
    (m,) = answer["missing"]
    assert (m["printout"], m["record"], m["what"]) == ("A", k + 1, "XPFA")


def test_two_lines_lost_in_one_block_its_time_among_them(tmp_path, capsys):
    time = _line_of("TIME", 10)
    fsa = max(i for i in range(time) if "OF FSA IS" in LINES[i])
    lost = {time, fsa}
    status, answer = _compare(capsys, tmp_path,
                              [line for i, line in enumerate(LINES) if i not in lost])
    assert status == 1 and _counts(answer) == (0, 0, 2)
    assert {(m["printout"], m["record"]) for m in answer["missing"]} == {
        ("A", time + 1), ("A", fsa + 1)}


def test_a_record_added_is_one_record_missing_from_the_other(tmp_path, capsys):
    k = _line_of("XSA", 9)
    status, answer = _compare(capsys, tmp_path, LINES[:k] + [LINES[k]] + LINES[k:])
    assert status == 1 and _counts(answer) == (0, 0, 1)
    assert answer["missing"][0]["printout"] == "B"


def test_lines_joined_read_as_the_records_they_hold(tmp_path, capsys):
    """Every value line of every block joined to the next one (the blank line between
    lost, and with it the line end), twice with no space at all."""
    joined, k = [], 0
    glue = [" ", "", "   "]
    while k < len(LINES):
        line = LINES[k]
        if VALUE.search(line) and k + 2 < len(LINES) and VALUE.search(LINES[k + 2]):
            joined.append(line + glue[len(joined) % 3] + LINES[k + 2].strip())
            k += 3
            continue
        joined.append(line)
        k += 1
    assert len(joined) < len(LINES) * 0.7
    status, answer = _compare(capsys, tmp_path, joined)
    assert status == 0 and _counts(answer) == (0, 0, 0)


def test_a_message_missing_is_a_record_missing(tmp_path, capsys):
    message = "THE POST HAS LOST CONTACT WITH FIRST SPRING"
    k = next(i for i, line in enumerate(LINES) if message in line)
    status, answer = _compare(capsys, tmp_path, LINES[:k] + LINES[k + 1:])
    assert status == 1 and _counts(answer) == (0, 0, 1)
    assert (answer["missing"][0]["what"], answer["missing"][0]["printed"]) == (
        "message", message)


def test_the_text_names_each_finding(tmp_path, capsys):
    k, j = _line_of("PHIFA", 1), _line_of("ZZQA", 2)
    lines = LINES[:]
    lines[k] = _replace_value(LINES[k], "5.55555")
    del lines[j]
    (tmp_path / "b.txt").write_text("\n".join(lines))
    assert main(["compare", str(STEEL40), str(tmp_path / "b.txt")]) == 1
    out = capsys.readouterr().out.splitlines()
    # first the verdict and its counts: one record fewer in B, so one fewer aligned
    values = sum(len(VALUE.findall(line)) for line in LINES)
    messages = sum("THE POST HAS" in line for line in LINES)
    records = values + messages
    assert out[0] == (f"differ: {records:,} records in A, {records - 1:,} in B; "
                      f"{records - 1:,} aligned; {records - 1:,} compared ({values - 1:,} "
                      f"values, {messages} messages): {records - 2:,} equal, 1 differing; "
                      "0 unreadable; 1 missing")
    # the value named by the label printed on the paper (FORMAT 61: PHIFA), not its
    # variable (PHIFAD)
    assert out[1].startswith(f"record {k + 1} ") and "PHIFA:" in out[1] and "5.55555" in out[1]
    assert "PHIFAD" not in "\n".join(out)
    assert out[2].startswith(f"missing: record {j + 1} of A") and "ZZQA" in out[2]
    assert "1 difference(s), 1 record(s) in one printout only" in out[-1]


@pytest.mark.slow
def test_the_text_of_the_pdf_pages_agrees(tmp_path, capsys):
    """The text taken from run --pages --listing's PDF: the banner page, the compile listing
    (whose FORMAT statements hold the same words as Hollerith text), then the output."""
    pypdf = pytest.importorskip("pypdf")
    pdf = tmp_path / "p.pdf"
    assert main(["run", "steel40", "--pages", str(pdf), "--listing"]) == 0
    text = "\n".join(page.extract_text() for page in pypdf.PdfReader(str(pdf)).pages)
    assert "HTHE VALUE OF VVA IS" in text  # the listing is there
    capsys.readouterr()
    status, answer = _compare(capsys, tmp_path, text)
    assert status == 0 and _counts(answer) == (0, 0, 0)


def test_an_empty_file_is_refused_in_one_line(tmp_path, capsys):
    (tmp_path / "empty.txt").write_text("")
    assert main(["compare", str(STEEL40), str(tmp_path / "empty.txt")]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert captured.out == "" and len(err) == 1
    assert "empty.txt" in err[0] and "empty" in err[0] and "THE VALUE OF" in err[0]


def test_what_is_not_a_printout_is_refused(capsys):
    assert main(["compare", str(ROOT / "decks" / "steel40.dat"), str(STEEL40)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "steel40.dat" in err[0] and "not a printout" in err[0]


def test_a_pdf_without_the_pdf_extra_is_refused_in_one_line_naming_it(tmp_path, capsys,
                                                                    monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pypdf", None)  # as an install without the [pdf] extra
    pdf = tmp_path / "pages.pdf"
    pdf.write_bytes(b"%PDF-1.4\n%\xe2\xe3\xcf\xd3\n")
    assert main(["compare", str(STEEL40), str(pdf)]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert captured.out == "" and len(err) == 1 and "deck_emulator[pdf]" in err[0]


def test_a_pdf_whose_text_cannot_be_read_is_refused_in_one_line(tmp_path, capsys):
    pytest.importorskip("pypdf")
    pdf = tmp_path / "cut.pdf"
    pdf.write_bytes(b"%PDF-1.4\n1 0 obj << /Type /Catalog >>\n")  # cut short: no xref, no EOF
    assert main(["compare", str(STEEL40), str(pdf)]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert captured.out == "" and len(err) == 1 and "cut.pdf" in err[0] and "PDF" in err[0]
