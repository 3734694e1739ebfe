"""The dossier pages opened in a real browser (issue 49): Debian's chromium, headless, loads
each page from disk, runs its script, and gives back the DOM (``--dump-dom``) and a
screenshot.  The DOM must hold what the page was written with (every record, every link
resolving), the browser's log no console message (a request the page's policy blocks is
logged as one: no request) and the screenshot be a rendered page, not a blank one.

The screenshot is not compared with a reference picture: the fonts a machine has change the
rendering by whole pixels, so such a comparison would pass or fail with the machine; it is
checked to be a page of many colours and edges (non-blank) instead."""

from __future__ import annotations

import os
import re
import shutil
import subprocess

import pytest

from deck_emulator.cli import main
from test_html import GOLDEN, LISTING, Page, _check_links, _damaged

pytestmark = pytest.mark.slow


def _chromium() -> str:
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    if found is None:
        if os.environ.get("CI"):
            pytest.fail("chromium is missing on CI: .ci/run must install it")
        pytest.skip("chromium is not installed (Debian: apt-get install chromium)")
    return found


def _open(page, tmp_path, *, screenshot=None, fragment="") -> tuple[str, list[str]]:
    """(the DOM after the page's script ran, the browser's console lines) of ``page``."""
    profile = tmp_path / f"profile-{page.stem}"
    args = [_chromium(), "--headless", "--disable-gpu", "--no-sandbox", "--hide-scrollbars",
            "--no-first-run", "--enable-logging=stderr", "--v=0",
            f"--user-data-dir={profile}", "--host-resolver-rules=MAP * ~NOTFOUND",
            "--virtual-time-budget=3000", "--window-size=1600,1200"]
    args += [f"--screenshot={screenshot}"] if screenshot else ["--dump-dom"]
    done = subprocess.run(args + [page.resolve().as_uri() + fragment], capture_output=True,
                          text=True, timeout=180, check=True)
    console = [line for line in done.stderr.splitlines() if ":CONSOLE" in line]
    return done.stdout, console


def _rendered(png) -> None:
    """A screenshot of a page: many colours, and not one flat field."""
    image = pytest.importorskip("PIL.Image")
    stat = pytest.importorskip("PIL.ImageStat")
    with image.open(png) as im:
        grey = im.convert("L")
        assert stat.Stat(grey).stddev[0] > 20
        assert len(im.convert("RGB").getcolors(1 << 24)) > 50


def test_the_browser_logs_what_the_page_would_fetch(tmp_path):
    """The check below can fail: a page that asks for an image from the network, under the
    dossier's policy, is logged by the browser (so is a console error of its script)."""
    from deck_emulator.present.dossier import CSP

    bad = tmp_path / "bad.html"
    bad.write_text(f'<!DOCTYPE html><html><head><meta http-equiv="Content-Security-Policy" '
                   f'content="{CSP}"></head><body><img src="http://example.invalid/x.png">'
                   "<script>console.error('boom')</script></body></html>")
    _, console = _open(bad, tmp_path)
    assert any("Content Security Policy" in line for line in console)
    assert any("boom" in line for line in console)


def _pages(tmp_path) -> dict:
    pages = {}
    run = tmp_path / "run.html"
    assert main(["run", "steel40", "--quiet", "--html", str(run), "--out",
                 str(tmp_path / "r.txt")]) == 0
    pages["run"] = run
    job = tmp_path / "steel40.job"
    assert main(["punch", "steel40", "--job", "--to", "text", "--out", str(job)]) == 0
    cards = job.read_text().split("\n")
    cards[cards.index("      E=0.0")] = "      E=0.0*1.0"
    own = tmp_path / "own.job"
    own.write_text("\n".join(cards))
    pages["job"] = tmp_path / "job.html"
    assert main(["run", str(own), "--quiet", "--html", str(pages["job"]), "--out",
                 str(tmp_path / "j.txt")]) == 0
    pages["stopped"] = tmp_path / "stopped.html"
    assert main(["run", "steel40", "--quiet", "--max-time", "0.05", "--html",
                 str(pages["stopped"]), "--out", str(tmp_path / "s.txt")]) == 3
    damaged, _ = _damaged(tmp_path)
    pages["compare"] = tmp_path / "compare.html"
    golden = str(tmp_path / "golden.txt")
    (tmp_path / "golden.txt").write_text("\n".join(GOLDEN) + "\n")
    assert main(["compare", golden, str(damaged), "--html", str(pages["compare"]),
                 "--out", str(tmp_path / "c.txt")]) == 1
    pages["diff"] = tmp_path / "diff.html"
    assert main(["diff", "steel40", "--max-k", "0", "--quiet", "--html", str(pages["diff"]),
                 "--out", str(tmp_path / "d.txt")]) == 0
    return pages, cards[:cards.index("$DATA")]


def test_each_page_opens_in_chromium_with_no_console_message_and_no_request(tmp_path):
    """run, a job deck's own program, a stopped run, compare with damaged input, diff: each
    page opened in headless chromium logs nothing; its DOM, after its script ran, holds
    every record linked to its WRITE (run pages) and its tables (compare, diff); a
    screenshot of each is a rendered page."""
    _chromium()
    pages, job_program = _pages(tmp_path)
    for name, path in pages.items():
        dom, console = _open(path, tmp_path)
        assert console == [], (name, console)
        page = Page(dom)
        assert page.outside == [], name
        if name in ("run", "job", "stopped"):
            records = [text for text, _ in page.records]
            n = len(records)
            assert records == GOLDEN[:n] and (n == len(GOLDEN)) == (name != "stopped")
            assert _check_links(page, job_program if name == "job" else LISTING) == n
            # the script ran: it shows the search, hidden from a reader without it
            assert '<div class="search">' in dom and 'class="search" hidden' not in dom
        else:
            assert len(page.rows) > 10
        png = tmp_path / f"{name}.png"
        _open(path, tmp_path, screenshot=png)
        _rendered(png)


def test_a_records_link_opened_shows_its_write_format_and_values(tmp_path):
    """run.html#p1-21 (the records of the 11th WRITE, the first of two values on a line):
    the page's script fills the detail box with the WRITE of luminaire.f's card that printed
    them, its FORMAT over its two cards, and the two values of its list (which round to
    what gfortran printed)."""
    _chromium()
    page = tmp_path / "run.html"
    assert main(["run", "steel40", "--quiet", "--html", str(page), "--out",
                 str(tmp_path / "r.txt")]) == 0
    dom, console = _open(page, tmp_path, fragment="#p1-21")
    assert console == []
    box = dom[dom.index('id="detail"'):]
    box = box[:box.index("</div>")]
    write = next(n for n, line in enumerate(LISTING, 1) if line.strip() == "WRITE(6,200)YYPA,XRA")
    assert f'href="#c{write}"' in box and "WRITE(6,200)YYPA,XRA" in box
    assert "THE VALUE OF YYPA IS ,F15.5,30X,20HTHE VALUE OF XRA IS ,F15.5)" in box
    # the values, rounded as F15.5 rounds them, are what gfortran printed on that line
    values = re.search(r"YYPA = (\S+), XRA = (\S+)<", box).groups()
    printed = next(line for line in GOLDEN if "OF YYPA IS" in line).split()
    assert [f"{float(v):.5f}" for v in values] == [printed[5], printed[-1]]
