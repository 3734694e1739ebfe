"""compare's verdict at its boundaries, as properties over generated changes (issue 45).

A is always the compiled listing's own printout of steel40 (golden/steel40.r8.txt, written by
gfortran); B is that printout changed here, in one of the layouts people hold: carriage
control in column 1, the text ``pdftotext -layout`` takes from the PDF of the pages (the
page's lines, a form feed at each new page) and the text plain ``pdftotext`` takes (each
label on a line of its own, its value on the next line that is not blank) -- the two
pdftotext shapes are made here from the golden, as pdftotext lays them out, so these tests
need no pdftotext; one test runs the real one where it is installed.  What each change must
give follows from what the change is, not from the program's output:

* any printed value changed to another number its FORMAT prints (its last digit included) is
  a difference: exit 1;
* any value made unreadable (a character no scan's confusion explains, a digit lost, nothing
  left) is unreadable, never "agree": exit 4 when nothing else changed, and the finding shows
  B's line as it stands;
* every value unreadable: no value compared, not "agree";
* a label or the words around it damaged as a scan damages them (``F5A`` for ``FSA``,
  ``VA1UE``, ``I5``) is damage shown with B's line, not a record missing.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[2]
STEEL40 = ROOT / "golden" / "steel40.r8.txt"
LINES = STEEL40.read_text().split("\n")
VALUE = re.compile(r"THE VALUE OF (\w+) IS +(\S+)")
#: every printed value of A: (line index, label, the field's span on its line)
FIELDS = [(k, m.group(1), m.span(2)) for k, line in enumerate(LINES)
          for m in VALUE.finditer(line)]
MESSAGES = sum("THE POST HAS" in line for line in LINES)
SETTINGS = settings(max_examples=25, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow,
                                           HealthCheck.function_scoped_fixture])


def _formats() -> dict[str, set[tuple[int, int]]]:
    """The printed labels and their Fw.d fields, read here from legacy/luminaire.f's FORMAT
    statements (the listing itself, not the package's table of them)."""
    cards = (ROOT / "src" / "deck_emulator" / "legacy" / "luminaire.f").read_text()
    statements: list[str] = []
    for card in cards.split("\n"):
        if card[:1] in ("C", "c", "*"):
            continue
        if len(card) > 5 and card[5] not in " 0" and not card[:5].strip() and statements:
            statements[-1] += card[6:72]  # a continuation card
        else:
            statements.append(card[:72])
    source = "\n".join(statements)
    out: dict[str, set[tuple[int, int]]] = {}
    for label, w, d in re.findall(r"THE VALUE OF (\w+) IS ,F(\d+)\.(\d+)", source):
        out.setdefault(label, set()).add((int(w), int(d)))
    return out


FORMATS = _formats()


# ---------------------------------------------------------------- the layouts of B

def carriage_control(lines: list[str]) -> str:
    return "\n".join(lines)


def pdftotext_layout(lines: list[str]) -> str:
    """As ``pdftotext -layout`` gives the pages: each printed line without its carriage
    control and left margin, a form feed before each new page's first line."""
    out, new_page = [], False
    for line in lines:
        if line == "1":
            new_page = True
            continue
        text = line[1:]
        text = text[5:] if text.startswith("     ") else text
        if new_page and text.strip():
            text, new_page = "\f" + text, False
        out.append(text)
    return "\n".join(out)


def pdftotext_plain(lines: list[str]) -> str:
    """As plain ``pdftotext`` gives the pages: each record's label on a line of its own and
    its value on the next line but one, blank lines between, a form feed before a new page."""
    out, new_page = [], False
    for line in lines:
        if line == "1":
            new_page = True
            continue
        # (a field left blank is no value: the next record's THE is not taken for one)
        for m in re.finditer(r"(THE POST HAS [A-Z ]*[A-Z])"
                             r"|(THE \S+ \S+ \S+ \S+)(?:[ ]+(?!THE )(\S+))?", line):
            first = m.group(1) or m.group(2)
            out += [("\f" if new_page else "") + first, ""]
            new_page = False
            if m.group(2) and m.group(3):
                out += [m.group(3), ""]
    return "\n".join(out)


LAYOUTS = {"carriage control": carriage_control, "pdftotext -layout": pdftotext_layout,
           "pdftotext": pdftotext_plain}


def _compare(tmp_path: Path, capsys, b_text: str, *options) -> tuple[int, dict]:
    b = tmp_path / "b.txt"
    b.write_text(b_text)
    status = main(["compare", str(STEEL40), str(b), "--json", *options])
    return status, json.loads(capsys.readouterr().out)


def _with_fields(changes: dict[int, str]) -> list[str]:
    """A's lines with the fields of FIELDS[i] replaced by changes[i]."""
    lines = LINES[:]
    for i in sorted(changes, key=lambda i: -FIELDS[i][2][0]):  # right to left on a line
        k, _, (start, end) = FIELDS[i]
        lines[k] = lines[k][:start] + changes[i] + lines[k][end:]
    return lines


def _field_shape(i: int) -> tuple[int, int]:
    """(w, d) of FIELDS[i]: TIME is F10.6 in contact and F10.5 in free flight; the printed
    field's own decimals tell which."""
    _, label, (start, end) = FIELDS[i]
    field = LINES[FIELDS[i][0]][start:end]
    decimals = len(field.split(".")[1])
    (shape,) = [s for s in FORMATS[label] if s[1] == decimals]
    return shape


@st.composite
def changed_value(draw, i=None):
    """(index into FIELDS, a field its FORMAT prints that reads as another number,
    ``"changed"``)."""
    i = draw(st.integers(0, len(FIELDS) - 1)) if i is None else i
    k, _, (start, end) = FIELDS[i]
    old = LINES[k][start:end]
    w, d = _field_shape(i)
    units = int(old.replace("-", "").replace(".", "")) * (-1 if old.startswith("-") else 1)
    delta = draw(st.one_of(st.sampled_from([-1, 1]), st.integers(-10**7, 10**7)))
    new_units = units + delta
    if delta == 0 or new_units == 0:  # a zero: the other sign is another printed value
        negative = not old.startswith("-") if new_units == 0 else False
        new = ("-" if negative else "") + "0." + "0" * d
        assume(new != old)
    else:
        digits = str(abs(new_units)).rjust(d + 1, "0")
        new = ("-" if new_units < 0 else "") + digits[:-d] + "." + digits[-d:]
    assume(len(new) <= w)
    return i, new, "changed"


#: characters no scan's confusion turns into a digit or a point
_FOREIGN = "#%?&x~=!@"


@st.composite
def unreadable_value(draw):
    """(index into FIELDS, what is left of its field: nothing F``w``.``d`` prints, even read
    through a scan's confusions, ``"unreadable"``)."""
    i = draw(st.integers(0, len(FIELDS) - 1))
    k, _, (start, end) = FIELDS[i]
    old = LINES[k][start:end]
    how = draw(st.sampled_from(["foreign character", "a decimal lost", "nothing"]))
    if how == "foreign character":
        at = draw(st.integers(0, len(old)))
        new = old[:at] + draw(st.sampled_from(_FOREIGN)) + old[at:]
    elif how == "a decimal lost":
        at = draw(st.integers(old.index(".") + 1, len(old) - 1))
        new = old[:at] + old[at + 1:]
    else:
        new = ""
    return i, new, "unreadable"


def _shown_lines(answer: dict) -> set[int]:
    return {d["record"] for d in answer["damaged"] if d["printout"] == "B"}


@pytest.mark.parametrize("layout", LAYOUTS)
def test_the_same_printout_agrees_in_every_layout(layout, tmp_path, capsys):
    status, answer = _compare(tmp_path, capsys, LAYOUTS[layout](LINES))
    counts = answer["counts"]
    assert (status, answer["verdict"]) == (0, "agree")
    assert counts["values_compared"] == len(FIELDS) and counts["messages_compared"] == MESSAGES
    assert (counts["differing"], counts["unreadable"], counts["missing"]) == (0, 0, 0)


@SETTINGS
@given(layout=st.sampled_from(sorted(LAYOUTS)),
       edits=st.lists(st.one_of(changed_value(), unreadable_value()), min_size=1, max_size=5,
                      unique_by=lambda e: e[0]))
def test_any_value_changed_or_made_unreadable_is_never_agreement(layout, edits, tmp_path,
                                                                  capsys):
    unreadable = {i for i, _, kind in edits if kind == "unreadable"}
    changed = {i for i, _, kind in edits if kind == "changed"}
    b_lines = _with_fields({i: new for i, new, _ in edits})
    status, answer = _compare(tmp_path, capsys, LAYOUTS[layout](b_lines))
    assert answer["verdict"] != "agree" and status != 0
    assert status == (1 if changed else 4)
    assert answer["counts"]["unreadable"] == len(unreadable)
    if layout == "carriage control":  # the lines are A's: each edit is found on its own line
        found = {d["record_b"] for d in answer["differences"]} | {
            m["record"] for m in answer["missing"] if m["printout"] == "B"}
        assert {FIELDS[i][0] + 1 for i in changed} <= found
        assert _shown_lines(answer) == {FIELDS[i][0] + 1 for i in unreadable}
        for d in answer["damaged"]:  # B's line as it stands
            assert d["text"] == b_lines[d["record"] - 1]


@SETTINGS
@given(layout=st.sampled_from(sorted(LAYOUTS)), i=st.integers(0, len(FIELDS) - 1),
       data=st.data())
def test_a_value_changed_in_its_last_printed_digit_is_a_difference(layout, i, data, tmp_path,
                                                                   capsys):
    k, label, (start, end) = FIELDS[i]
    old = LINES[k][start:end]
    last = int(old[-1])
    new_last = data.draw(st.sampled_from([c for c in "0123456789" if int(c) != last]))
    new = old[:-1] + new_last
    status, answer = _compare(tmp_path, capsys, LAYOUTS[layout](_with_fields({i: new})))
    assert status == 1 and answer["verdict"] == "differ"
    (d,) = answer["differences"]
    assert (d["what"], d["a"], d["b"]) == (label, old, new)
    _, decimals = _field_shape(i)
    assert d["size"] == pytest.approx(abs(int(new_last) - last) * 10.0**-decimals)
    assert answer["counts"]["equal"] == len(FIELDS) + MESSAGES - 1


@pytest.mark.parametrize("layout", LAYOUTS)
def test_every_value_unreadable_compares_no_value_and_does_not_agree(layout, tmp_path, capsys):
    status, answer = _compare(tmp_path, capsys,
                              LAYOUTS[layout](_with_fields(dict.fromkeys(range(len(FIELDS)),
                                                                         "?"))))
    counts = answer["counts"]
    assert status == 4 and answer["verdict"] == "unreadable"
    assert counts["values_compared"] == 0 and counts["unreadable"] == len(FIELDS)
    assert counts["missing"] == 0


def test_the_issues_sed_every_first_value_of_a_line_blanked(tmp_path, capsys):
    """``sed -E 's/ IS +-?[0-9.]+/ IS/'``: the first value of each line removed; the second
    of a two-record line (FORMATs 200, 202, 204) stays."""
    b = [re.sub(r" IS +-?[0-9.]+", " IS", line, count=1) for line in LINES]
    blanked = sum(bool(VALUE.search(line)) for line in LINES)
    status, answer = _compare(tmp_path, capsys, "\n".join(b))
    counts = answer["counts"]
    assert status == 4 and answer["verdict"] == "unreadable"
    assert counts["unreadable"] == blanked
    assert counts["values_compared"] == len(FIELDS) - blanked
    assert counts["missing"] == 0


def _label_line(name: str, nth: int = 0) -> int:
    return [k for k, line in enumerate(LINES) if f"THE VALUE OF {name} IS" in line][nth]


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("printed, damaged", [
    ("THE VALUE OF FSA IS", "THE VALUE OF F5A IS"),
    ("THE VALUE OF FSA IS", "THE VA1UE OF FSA IS"),
    ("THE VALUE OF FSA IS", "THE VALUE OF FSA I5"),
    ("THE VALUE OF ZZSA IS", "THE VALUE OF ZZ5A I5"),
])
def test_a_label_damaged_as_a_scan_damages_it_is_damage_shown_with_its_line(
        layout, printed, damaged, tmp_path, capsys):
    k = _label_line(printed.split()[3], 5)
    lines = LINES[:]
    lines[k] = lines[k].replace(printed, damaged)
    status, answer = _compare(tmp_path, capsys, LAYOUTS[layout](lines))
    assert (status, answer["verdict"]) == (0, "agree")  # read as what it stands for
    assert answer["counts"]["missing"] == 0
    assert answer["counts"]["values_compared"] == len(FIELDS)
    (d,) = answer["damaged"]
    assert d["printout"] == "B" and d["reading"] == "damaged" and d["what"] == printed.split()[3]
    assert damaged in d["text"]  # B's line as it stands
    if layout == "carriage control":
        assert d["record"] == k + 1 and d["text"] == lines[k]


@pytest.mark.parametrize("layout", LAYOUTS)
def test_a_label_that_reads_as_none_of_the_listings_is_unreadable_not_missing(layout, tmp_path,
                                                                             capsys):
    k = _label_line("XPFA", 3)
    lines = LINES[:]
    lines[k] = lines[k].replace("OF XPFA IS", "OF XQ#A IS")
    status, answer = _compare(tmp_path, capsys, LAYOUTS[layout](lines))
    assert (status, answer["verdict"]) == (4, "unreadable")
    assert answer["counts"]["missing"] == 0 and answer["counts"]["unreadable"] == 1
    (d,) = answer["damaged"]
    assert d["reading"] == "unreadable" and "XQ#A" in d["text"]
    assert "XPFA" in d["other"]  # what it lined up with in A


def test_findings_name_the_labels_printed_on_the_paper(tmp_path, capsys):
    """FORMAT 207 prints ZXCMA for ZZCMA, FORMAT 60 THFA for THFAD, FORMAT 133 ZYCFA."""
    changes = {}
    for label in ("ZXCMA", "THFA", "ZYCFA", "THA"):
        i = next(i for i, f in enumerate(FIELDS) if f[1] == label)
        k, _, (start, end) = FIELDS[i]
        old = LINES[k][start:end]
        changes[i] = old[:-1] + ("1" if old[-1] != "1" else "2")
    status, answer = _compare(tmp_path, capsys, "\n".join(_with_fields(changes)))
    assert status == 1
    assert {d["what"] for d in answer["differences"]} == {"ZXCMA", "THFA", "ZYCFA", "THA"}
    assert {d["what"] for d in answer["differences"]} <= set(FORMATS)


@pytest.mark.slow
def test_the_real_pdftotext_of_the_pages_both_layouts(tmp_path, capsys):
    """pdftotext (poppler) on the PDF of run --pages, plain and -layout: the same records as
    the compiled listing's printout, each compared and equal; 40 values changed in the plain
    text are 40 differences."""
    if shutil.which("pdftotext") is None:
        pytest.skip("pdftotext (poppler-utils) is not installed: the shapes of its text are "
                    "tested above with text made by the test itself")
    pytest.importorskip("matplotlib")
    pdf = tmp_path / "s40.pdf"
    assert main(["run", "steel40", "--pages", str(pdf)]) == 0
    capsys.readouterr()
    texts = {}
    for name, flags in (("plain", []), ("layout", ["-layout"])):
        out = tmp_path / f"{name}.txt"
        subprocess.run(["pdftotext", *flags, str(pdf), str(out)], check=True)
        texts[name] = out.read_text()
        status, answer = _compare(tmp_path, capsys, texts[name])
        assert (status, answer["verdict"]) == (0, "agree"), name
        assert answer["counts"]["values_compared"] == len(FIELDS)
    lines = texts["plain"].split("\n")
    numbers = [k for k, line in enumerate(lines) if re.fullmatch(r"-?[0-9]+\.[0-9]+", line)]
    assert len(numbers) > 0.9 * len(FIELDS)  # most values on lines of their own
    for k in numbers[:: len(numbers) // 40][:40]:
        lines[k] = lines[k][:-1] + str((int(lines[k][-1]) + 1) % 10)
    status, answer = _compare(tmp_path, capsys, "\n".join(lines))
    assert status == 1 and answer["counts"]["differing"] == 40


@pytest.mark.slow
def test_the_pdf_itself_is_read(tmp_path, capsys):
    pytest.importorskip("pypdf")
    pytest.importorskip("matplotlib")
    pdf = tmp_path / "s40.pdf"
    assert main(["run", "steel40", "--pages", str(pdf)]) == 0
    capsys.readouterr()
    status = main(["compare", str(STEEL40), str(pdf), "--json"])
    answer = json.loads(capsys.readouterr().out)
    assert (status, answer["verdict"]) == (0, "agree")
    assert answer["counts"]["values_compared"] == len(FIELDS)
