"""golden/ is reproducible: the documented command, run now, writes the same bytes."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from deck_emulator.legacy.printer import Printer

ROOT = Path(__file__).resolve().parents[2]


def need_gfortran():
    if shutil.which("gfortran") is None:
        if os.environ.get("CI"):
            pytest.fail("gfortran is missing on CI: .ci/run must install it")
        pytest.skip("gfortran is not installed")


def test_goldens_reproduce_byte_for_byte(tmp_path):
    need_gfortran()
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_goldens.py"), "--out", str(tmp_path)],
                   check=True, capture_output=True, timeout=300)
    ours = sorted(p.name for p in tmp_path.iterdir())
    theirs = sorted(p.name for p in (ROOT / "golden").iterdir())
    assert ours == theirs
    for name in ours:
        assert (tmp_path / name).read_bytes() == (ROOT / "golden" / name).read_bytes(), name


def test_printer_rounds_ties_as_gfortran(tmp_path):
    """Exact binary ties, printed by a gfortran program and by the printer."""
    need_gfortran()
    values = ["539.640625", "-539.640625", "0.000005", "0.0000025", "-0.000001", "1.234565",
              "20530.591259765625", "0.0000015"]
    src = tmp_path / "ties.f"
    lines = [f"      X={v}D0\n      WRITE(6,1)X\n" for v in values]
    src.write_text("".join(lines) + "    1 FORMAT(/,5X,20HTHE VALUE OF FSA IS ,F15.5)\n      END\n")
    exe = tmp_path / "ties"
    subprocess.run(["gfortran", "-std=legacy", "-fdefault-real-8", "-o", str(exe), str(src)], check=True)
    expected = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    printer = Printer()
    for v in values:
        printer.write(39, float(v))  # FORMAT 39: F15.5, the same binary64 values
    assert "".join(r + "\n" for r in printer.records) == expected
