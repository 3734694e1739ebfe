"""A command's outputs are one set and every file goes through the one writer: the
printout's PDF is whole or absent after a kill, a PDF that cannot be made is a named error
that leaves nothing behind and no printout of the set replaced, two outputs on one path are
refused, and a device or FIFO in a set fails before any regular file is replaced."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
import types
import zlib
from pathlib import Path

import pytest

from deck_emulator.files import OutputError, OutputSet, check_distinct
from deck_emulator.legacy.pages import write_pdf

#: process-level or document tests: the README's test command runs them, a bare pytest not
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src"
# The golden printout of the steel deck: records with carriage control in column 1.
RECORDS = (ROOT / "golden" / "steel40.r8.txt").read_text().splitlines()


def ours(folder: Path) -> list[str]:
    """Temporary names of the writer's left in ``folder``."""
    return sorted(p.name for p in folder.iterdir() if ".~" in p.name)


@pytest.fixture
def full_disk_in_the_pdf_backend(monkeypatch):
    """The PDF writer's compressor fails as it does on a full disk (zlib.error)."""
    import deck_emulator.legacy.pdf as backend

    def broken(*a, **k):
        raise zlib.error("Error -3 while compressing data")

    monkeypatch.setattr(backend, "zlib", types.SimpleNamespace(compress=broken,
                                                               error=zlib.error))


def test_a_pdf_that_cannot_be_made_is_named_and_leaves_no_file(tmp_path,
                                                               full_disk_in_the_pdf_backend):
    target = tmp_path / "pages.pdf"
    with pytest.raises(OutputError, match="could not be written") as info:
        write_pdf(RECORDS[:200], target)
    assert str(target) in str(info.value) and "\n" not in str(info.value)
    assert not target.exists() and ours(tmp_path) == []  # no 0-byte PDF


def test_a_failing_pdf_replaces_neither_itself_nor_the_printout(tmp_path,
                                                                full_disk_in_the_pdf_backend):
    printout, pdf = tmp_path / "run.txt", tmp_path / "run.pdf"
    printout.write_text("the old printout\n")
    pdf.write_bytes(b"%PDF-old")
    with pytest.raises(OutputError):
        with OutputSet() as out:
            out.write(printout, "the new printout\n")
            write_pdf(RECORDS[:200], pdf, outputs=out)
    assert printout.read_text() == "the old printout\n" and pdf.read_bytes() == b"%PDF-old"
    assert ours(tmp_path) == []


def test_the_printout_and_its_pdf_are_committed_together(tmp_path):
    from pypdf import PdfReader

    from deck_emulator.legacy.pages import layout

    printout, pdf = tmp_path / "run.txt", tmp_path / "run.pdf"
    with OutputSet() as out:
        out.write(printout, "new\n")
        pages = write_pdf(RECORDS[:200], pdf, outputs=out)
        assert not printout.exists() and not pdf.exists()  # staged, not yet in place
    assert printout.read_text() == "new\n"
    assert len(PdfReader(pdf).pages) == pages == len(layout(RECORDS[:200]))


def test_a_killed_pdf_write_leaves_the_old_file_or_the_new_one_whole(tmp_path):
    from pypdf import PdfReader

    target = tmp_path / "pages.pdf"
    old = b"%PDF-1.4 the old pages\n"
    script = tmp_path / "write.py"
    script.write_text(textwrap.dedent(f"""
        import sys
        from pathlib import Path
        from deck_emulator.legacy.pages import write_pdf
        records = Path({str(ROOT / "golden" / "steel40.r8.txt")!r}).read_text().splitlines()
        print("start", flush=True)
        write_pdf(records, {str(target)!r})
        print("done", flush=True)
        """))
    env = dict(os.environ, PYTHONPATH=str(SRC))
    outcomes = set()
    for delay in (0.5, 1.5, 3.0):
        target.write_bytes(old)
        proc = subprocess.Popen([sys.executable, str(script)], env=env, text=True,
                                stdout=subprocess.PIPE)
        assert proc.stdout.readline().strip() == "start"
        time.sleep(delay)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
        data = target.read_bytes()
        if data == old:
            outcomes.add("old")
        else:  # the new file, whole: a reader finds every page
            assert len(PdfReader(target).pages) > 0
            outcomes.add("new")
    assert outcomes  # every trial checked above; which one a trial gives depends on timing


def test_two_outputs_on_one_path_are_refused(tmp_path):
    a = tmp_path / "x.txt"
    with pytest.raises(OutputError, match="same file"):
        check_distinct(a, a)
    with pytest.raises(OutputError, match="same file"):
        check_distinct(str(a), str(tmp_path / "." / "x.txt"))
    link = tmp_path / "link.txt"
    a.write_text("x")
    link.symlink_to(a)
    with pytest.raises(OutputError, match="same file"):
        check_distinct(a, link)
    check_distinct(a, tmp_path / "y.pdf", None)  # distinct, and an output not asked for
    check_distinct("/dev/null", "/dev/null")  # a stream is no file replaced


def test_a_fifo_without_a_reader_is_an_error_within_its_bound(tmp_path, monkeypatch):
    import deck_emulator.files as files

    monkeypatch.setattr(files, "FIFO_WAIT_S", 0.3)
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    started = time.monotonic()
    with pytest.raises(OutputError, match="no reader"):
        files.write_file(fifo, b"nobody reads this")
    assert time.monotonic() - started < 10


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this system")
def test_a_full_device_in_a_set_replaces_no_file_of_the_set(tmp_path):
    picture = tmp_path / "ok.png"
    picture.write_bytes(b"old picture")
    with pytest.raises(OutputError, match="/dev/full"):
        with OutputSet() as out:
            out.write(picture, b"new picture")
            out.write("/dev/full", b"x" * 100_000)
    assert picture.read_bytes() == b"old picture" and ours(tmp_path) == []
