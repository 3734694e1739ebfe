"""The dossier pages of ``run --html``, ``compare --html`` and ``diff --html`` (issue 49), read
back with the standard library's HTML parser.

What the pages are checked against comes from elsewhere: the printout's records from
golden/steel40.r8.txt (gfortran's printout of the listing), the statement a record's link
names from the program's own cards (luminaire.f, or the job deck's file) read here, and the
FORMAT's Hollerith texts from those cards too."""

from __future__ import annotations

import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[1]
GOLDEN = (ROOT / "golden" / "steel40.r8.txt").read_text().split("\n")[:-1]
LISTING = (ROOT / "src" / "deck_emulator" / "legacy" / "luminaire.f").read_text().splitlines()
#: the page may be this large at the most (issue 49)
MAX_BYTES = 1_000_000


class Page(HTMLParser):
    """A page's records (each with the href of the link it stands in), its ids, the texts
    of its listing's cards, its table rows, and every reference that would leave the page."""

    def __init__(self, text: str):
        super().__init__()
        self.records: list[tuple[str, str | None]] = []
        self.ids: set[str] = set()
        self.cards: dict[str, str] = {}
        self.outside: list[str] = []
        self.order: list[str] = []  # the ids of sections and of the stop alert, in order
        self.rows: list[tuple[str, list[str]]] = []
        self.csp = None
        self._link: list[str | None] = []
        self._record: list[str] | None = None
        self._depth = 0
        self._row: tuple[str, list[str]] | None = None
        self._cell: list[str] | None = None
        self.pre_texts: list[str] = []
        self._pre: list[str] | None = None
        self.feed(text)
        self.close()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            assert a["id"] not in self.ids, f"id {a['id']} twice"
            self.ids.add(a["id"])
        for name in ("src", "srcset", "action", "formaction", "poster", "data", "background"):
            if name in a:
                self.outside.append(f"{tag} {name}={a[name]}")
        if tag in ("link", "iframe", "object", "embed", "base", "img", "video", "audio"):
            self.outside.append(tag)
        href = a.get("href") or a.get("xlink:href")
        if href is not None and not href.startswith(("#", "data:")):
            self.outside.append(f"{tag} href={href}")
        if "url(" in (a.get("style") or ""):
            self.outside.append(f"{tag} style url()")
        if tag == "meta" and a.get("http-equiv") == "Content-Security-Policy":
            self.csp = a["content"]
        if tag == "a":
            self._link.append(href if "w" in (a.get("class") or "").split() else None)
        if tag in ("section", "div") and ("id" in a or a.get("role") == "alert"):
            self.order.append(a.get("id") or "alert")
        if tag == "span" and self._record is not None:
            self._depth += 1
        elif tag == "span" and "r" in (a.get("class") or "").split():
            self._record, self._depth = [], 1
        if tag == "span" and "c" in (a.get("class") or "").split():
            self.cards[a["id"]] = a.get("data-text", "")
        if tag == "tr":
            self._row = (a.get("class") or "", [])
        if tag in ("td", "th") and self._row is not None:
            self._cell = []
        if tag == "pre":
            self._pre = []

    def handle_endtag(self, tag):
        if tag == "a" and self._link:
            self._link.pop()
        if tag == "span" and self._record is not None:
            self._depth -= 1
            if self._depth == 0:
                links = [h for h in self._link if h is not None]
                self.records.append(("".join(self._record), links[-1] if links else None))
                self._record = None
        if tag in ("td", "th") and self._cell is not None and self._row is not None:
            self._row[1].append("".join(self._cell))
            self._cell = None
        if tag == "tr" and self._row is not None:
            self.rows.append(self._row)
            self._row = None
        if tag == "pre" and self._pre is not None:
            self.pre_texts.append("".join(self._pre))
            self._pre = None

    def handle_data(self, data):
        if self._record is not None:
            self._record.append(data)
        if self._cell is not None:
            self._cell.append(data)
        if self._pre is not None:
            self._pre.append(data)


def _statements(lines: list[str]) -> dict[int, str]:
    """Card number -> the statement starting on it, columns 7-72 of it and its continuation
    cards joined (as punched, blanks kept: a Hollerith text's blanks count)."""
    out: dict[int, str] = {}
    start = None
    for n, line in enumerate(lines, start=1):
        if not line[:72].strip() or line[:1] in "C*$":
            continue
        if len(line) > 5 and line[5] not in " 0" and start is not None:
            out[start] += line[6:72]
            continue
        start = n
        out[n] = line[:72]
    return out


def _format_of(lines: list[str], write_card: int) -> list[str]:
    """The Hollerith texts of the FORMAT a WRITE statement names (the FORMAT labelled so
    nearest the WRITE: each FORMAT of a unit has its own label)."""
    statements = _statements(lines)
    label = re.match(r"\s*WRITE\s*\(\s*6\s*,\s*(\d+)\s*\)", statements[write_card][6:]).group(1)
    found = sorted((abs(n - write_card), text) for n, text in statements.items()
                   if text[:5].strip() == label and text[6:].lstrip().startswith("FORMAT"))
    assert found, f"no FORMAT {label} for the WRITE of card {write_card}"
    body, texts, i = found[0][1][6:], [], 0
    while i < len(body):
        m = re.compile(r"(\d+)H").match(body, i)
        if m and (i == 0 or not body[i - 1].isalnum() or body[i - 1] in ",(/"):
            n = int(m.group(1))
            texts.append(body[m.end():m.end() + n])
            i = m.end() + n
        else:
            i += 1
    return texts


def _check_links(page: Page, lines: list[str]):
    """Every record stands in a link to a card of the listing that holds a WRITE statement,
    the card on the page as in ``lines``; a record with text holds a Hollerith text of that
    WRITE's FORMAT."""
    linked = 0
    for text, href in page.records:
        assert href is not None and href.startswith("#c"), text
        card = int(href[2:])
        assert href[1:] in page.ids and href[1:] in page.cards
        assert page.cards[href[1:]] == lines[card - 1].rstrip().strip()
        assert re.match(r"\s*WRITE\s*\(\s*6\s*,", lines[card - 1][6:72]), lines[card - 1]
        if text[1:].strip():
            texts = [t.strip() for t in _format_of(lines, card) if t.strip()]
            assert any(t in text for t in texts), (text, texts)
        linked += 1
    return linked


def _self_contained(page: Page, path: Path):
    assert page.outside == []
    assert page.csp is not None and "default-src 'none'" in page.csp
    assert path.stat().st_size <= MAX_BYTES


def test_run_html_holds_every_record_of_the_golden_printout_each_linked_to_its_write(tmp_path,
                                                                                    capsys):
    """run steel40 --html: the page holds every record of gfortran's printout, in order,
    character for character; every record links to the listing's card of the WRITE that
    printed it (the card a WRITE of the FORMAT whose text the record prints); nothing is
    fetched; at most 1 MB."""
    html = tmp_path / "s.html"
    assert main(["run", "steel40", "--html", str(html), "--quiet", "--out",
                 str(tmp_path / "s.txt")]) == 0
    page = Page(html.read_text())
    assert [text for text, _ in page.records] == GOLDEN
    assert _check_links(page, LISTING) == len(GOLDEN)
    _self_contained(page, html)
    assert (tmp_path / "s.txt").read_text().split("\n")[:-1] == GOLDEN  # --out as before
    # what the run said, and its provenance on the page: the deck's SHA-256 among it
    import hashlib

    from deck_emulator import decks
    sha = hashlib.sha256(Path(decks.path("steel40")).read_bytes()).hexdigest()
    assert sha in html.read_text()
    assert "wrote the dossier" in capsys.readouterr().err


def test_a_job_decks_own_program_links_to_its_own_cards(tmp_path, capsys):
    """A job deck whose FORTRAN is not the listing's (a statement punched differently, to the
    same effect) runs its own program: its records, gfortran's, each link to the deck's own
    card of the WRITE that printed them."""
    job = tmp_path / "steel40.job"
    assert main(["punch", "steel40", "--job", "--to", "text", "--out", str(job)]) == 0
    cards = job.read_text().split("\n")
    at = cards.index("      E=0.0")
    cards[at] = "      E=0.0*1.0"
    mod = tmp_path / "own.job"
    mod.write_text("\n".join(cards))
    html = tmp_path / "own.html"
    assert main(["run", str(mod), "--html", str(html), "--quiet", "--out",
                 str(tmp_path / "o.txt")]) == 0
    assert "own FORTRAN runs" in capsys.readouterr().err
    page = Page(html.read_text())
    assert [text for text, _ in page.records] == GOLDEN
    program = cards[:cards.index("$DATA")]
    assert _check_links(page, program) == len(GOLDEN)
    # the links name the deck's cards, not the listing's lines (the two are numbered apart)
    assert {href for _, href in page.records} != {f"#c{n}" for n, line in
                                                  enumerate(LISTING, 1) if "WRITE(6," in line}
    _self_contained(page, html)


def test_a_stopped_run_says_so_first_and_holds_the_records_printed_until_then(tmp_path):
    """run steel40 --max-time 0.05 --html: exit 3; the stop is the first thing on the page,
    before the provenance; the records printed until then are gfortran's first ones, linked."""
    html = tmp_path / "stop.html"
    assert main(["run", "steel40", "--max-time", "0.05", "--html", str(html), "--quiet",
                 "--out", str(tmp_path / "stop.txt")]) == 3
    text = html.read_text()
    page = Page(text)
    assert page.order.index("alert") < page.order.index("provenance")
    assert "The run stopped" in text and "0.05" in text
    # the stop links to the last WRITE's records, which are the printout's last
    alert = text[text.index('role="alert"'):]
    last = re.search(r'href="#(p1-\d+)"', alert[:alert.index("</div>")]).group(1)
    assert last in page.ids and int(last.split("-")[1]) <= len(page.records)
    records = [t for t, _ in page.records]
    assert 0 < len(records) < len(GOLDEN) and records == GOLDEN[:len(records)]
    assert _check_links(page, LISTING) == len(records)
    _self_contained(page, html)


def _damaged(tmp_path) -> tuple[Path, dict[int, str]]:
    """golden steel40 with a scan's damage (line 20: O for 0; every FSA read as F5A), a value
    no FORMAT prints (line 30), a value changed (line 40) and a record lost (line 50), and
    what each of those lines should be found as."""
    lines = list(GOLDEN)
    assert "0.00000" in lines[19] and "ZZPA" in lines[29] and "." in lines[29]
    lines[19] = lines[19].replace("0.00000", "O.00000")
    lines[29] = lines[29].replace(".", ",")
    old = lines[39].split()[-1]
    places = len(old.split(".")[1])
    lines[39] = lines[39][:-len(old)] + f"{float(old) + 1:{len(old)}.{places}f}"
    lost = lines.pop(49)
    assert lost.strip()
    lines = [line.replace("OF FSA IS", "OF F5A IS") for line in lines]
    path = tmp_path / "damaged.txt"
    path.write_text("\n".join(lines) + "\n")
    return path, {20: "damaged", 30: "unreadable", 40: "differ"}


def test_compare_html_aligns_the_two_printouts_and_marks_what_it_found(tmp_path):
    """compare golden damaged --html: the counts first; every record of each printout in a
    row of the aligned table, in order; the damaged, unreadable, differing and lost records
    marked as such."""
    damaged, expect = _damaged(tmp_path)
    html = tmp_path / "cmp.html"
    golden = str(ROOT / "golden" / "steel40.r8.txt")
    assert main(["compare", golden, str(damaged), "--html", str(html), "--max", "1"]) == 1
    page = Page(html.read_text())
    assert page.order.index("counts") < page.order.index("findings") < \
        page.order.index("aligned")
    _self_contained(page, html)
    aligned = [cells for cls, cells in page.rows if len(cells) == 5 and cls]

    def lines_shown(line: int, text: int) -> list[str]:  # a line of two records shows twice
        shown = {int(c[line]): c[text] for c in aligned if c[line]}
        return [shown[n] for n in sorted(shown)]

    assert lines_shown(0, 1) == [x for x in GOLDEN if x.strip() not in ("", "1")]
    b_lines = damaged.read_text().split("\n")
    assert lines_shown(2, 3) == [x for x in b_lines if x.strip() not in ("", "1")]
    # in the order of each printout
    for line in (0, 2):
        numbers = [int(c[line]) for c in aligned if c[line]]
        assert numbers == sorted(numbers)
    found = {int(c[2]): c[4] for c in aligned if c[2]}
    for line, what in expect.items():
        assert found[line] == what, (line, found[line])
    # the lost record: a row of A with no B, marked missing; every F5A line read as damaged
    assert [c[1] for c in aligned if not c[3]] == [GOLDEN[49]]
    assert all(found[n] in ("damaged", "differ", "unreadable")
               for n, x in enumerate(b_lines, 1) if "F5A" in x)
    assert {cls for cls, c in page.rows if len(c) == 5 and not c[3]} == {"missing"}


def test_diff_html_sets_the_emulator_beside_the_core(tmp_path, capsys):
    """diff steel40 --max-k 0 --html: the table as the command prints it, and the emulator
    and the core side by side; the emulator's hit at the last TIME gfortran's printout
    prints."""
    html = tmp_path / "diff.html"
    out = tmp_path / "diff.txt"
    assert main(["diff", "steel40", "--max-k", "0", "--quiet", "--html", str(html),
                 "--out", str(out)]) == 0
    page = Page(html.read_text())
    _self_contained(page, html)
    assert out.read_text() in page.pre_texts
    side = {cells[0]: cells[1:] for _, cells in page.rows if len(cells) == 4}
    last_time = next(float(x.split()[-1]) for x in reversed(GOLDEN) if "OF TIME IS" in x)
    assert float(side["hit_time_s"][0]) == pytest.approx(last_time, abs=1e-9)
    assert float(side["hit_time_s"][1]) > 0  # the core's, beside it


# ------------------------------------------------------------- the forms, for any records


def test_any_records_stand_on_the_forms_as_written_each_in_its_writes_link():
    """For any records (any carriage control, any printable text, HTML's own characters
    among it) and any WRITEs printing them, the forms read back give the records, in order,
    character for character, each in the link of the WRITE that printed it."""
    from hypothesis import given, settings
    from hypothesis import strategies as st

    from deck_emulator.present.dossier import PrintedSection, Program, printout

    text = st.text(st.characters(min_codepoint=32, max_codepoint=126), max_size=20)
    record = st.tuples(st.sampled_from(["", "1", "0", "+", " ", "-", "<", "&"]), text).map(
        lambda t: (t[0] + t[1]) if t[0] else "")

    @settings(max_examples=100, deadline=None)
    @given(st.lists(st.tuples(st.integers(1, 999), st.lists(record, min_size=1, max_size=4)),
                    min_size=1, max_size=12))
    def check(writes):
        records, rows = [], []
        for card, printed in writes:
            rows.append((len(records), "MAIN", card, 6, ()))
            records += printed
        section = PrintedSection("d", "s", tuple(records), tuple(rows))
        page = Page(printout(section, Program("p", ()), 1))
        assert [t for t, _ in page.records] == records
        owners = [f"#c{card}" for card, printed in writes for _ in printed]
        assert [href for _, href in page.records] == owners

    check()


def test_html_refuses_a_name_that_is_no_page_or_another_output_before_any_work(tmp_path,
                                                                                capsys):
    """--html names an .html file, not the printout's own file: refused in one line, exit
    2, nothing written."""
    out = tmp_path / "s.html"
    assert main(["run", "steel40", "--html", str(tmp_path / "s.txt")]) == 2
    assert "name a .html file" in capsys.readouterr().err
    assert main(["run", "steel40", "--quiet", "--out", str(out), "--html", str(out)]) == 2
    err = capsys.readouterr().err
    assert len([line for line in err.splitlines() if "error" in line]) == 1
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_a_job_deck_of_two_sections_gives_two_printouts_beside_one_listing(tmp_path):
    """A job deck holding steel40's $DATA section twice: two printouts, each gfortran's
    whole, each record linked to the one listing's WRITE; the page says whose outcome it
    shows."""
    job = tmp_path / "steel40.job"
    assert main(["punch", "steel40", "--job", "--to", "text", "--out", str(job)]) == 0
    cards = job.read_text().split("\n")
    data = cards.index("$DATA")
    cards[data + 9:data + 9] = cards[data:data + 9]
    two = tmp_path / "two.job"
    two.write_text("\n".join(cards))
    html = tmp_path / "two.html"
    assert main(["run", str(two), "--quiet", "--html", str(html), "--out",
                 str(tmp_path / "two.txt")]) == 0
    text = html.read_text()
    page = Page(text)
    assert [t for t, _ in page.records] == GOLDEN + GOLDEN
    assert _check_links(page, LISTING) == 2 * len(GOLDEN)
    assert {"printout-1", "printout-2"} <= page.ids and "printout-3" not in page.ids
    assert "last $DATA section run" in text


def test_a_run_with_an_erratum_links_to_the_listing_as_run(tmp_path):
    """run steel40_a15 --erratum ed-direction --html: gfortran's printout of the patched
    listing, record for record, each linked to its WRITE; the listing on the page is the
    program as run (the patched statements DH=D-H in it)."""
    html = tmp_path / "e.html"
    assert main(["run", "steel40_a15", "--erratum", "ed-direction", "--quiet", "--html",
                 str(html), "--out", str(tmp_path / "e.txt")]) == 0
    golden = (ROOT / "golden" / "steel40_a15.ed-direction.r8.txt").read_text()
    page = Page(html.read_text())
    assert [t for t, _ in page.records] == golden.split("\n")[:-1]
    assert _check_links(page, LISTING) == len(page.records)
    assert "DH=D-H" in "".join(page.cards.values())
