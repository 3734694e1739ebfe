#!/usr/bin/env python3
"""Compile legacy/ with gfortran and run it on every deck: the only way golden/ is made.

    python scripts/make_goldens.py            # rewrite golden/
    python scripts/make_goldens.py --out DIR  # write elsewhere (the reproducibility test does)

For each deck in decks/ and each precision it writes

* ``golden/<deck>.r8.txt`` -- REAL*8 build (``-fdefault-real-8``), the printout (unit 6);
* ``golden/<deck>.r4.txt`` -- default REAL (IEEE binary32) build that traps on the first
  invalid operation, division by zero or overflow; the printout up to the trap, and
  ``golden/<deck>.r4.trap`` -- the trapping source line and statement.

A deck whose run as printed does not end within the time limit (ED's search walking away from
its root, see legacy/CORRECTIONS.md) is run again with the named erratum applied, and its golden
says so in its name: ``golden/<deck>.ed-direction.r8.txt``.  ``golden/MANIFEST.txt`` lists, for
every run, the build, the flags and how it ended.  Every run is bounded by a timeout, so the
command itself cannot hang.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))

from deck_emulator.files import OutputError, OutputSet, check_output_dir  # noqa: E402
from deck_emulator.signals import run as run_guarded  # noqa: E402
LEGACY = ROOT / "legacy"
SOURCE = "luminaire.f"
ERRATA = {"ed-direction": LEGACY / "errata" / "ed-direction.patch"}

# Flags common to both precisions, and why:
COMMON_FLAGS = [
    "-std=legacy",  # arithmetic IF, Hollerith FORMATs, statement functions without warnings
    "-ffixed-form",  # columns 1-72, continuation in column 6
    "-O0",  # no reordering or folding of the program's arithmetic
    "-ffloat-store",  # no excess precision kept in registers (a no-op with SSE, kept explicit)
    "-ffp-contract=off",  # no fused multiply-add: every * and + rounds, as written
    "-fno-automatic",  # locals static, as on IBSYS: ED's L and DH keep their values between calls
    "-finit-local-zero",  # ... and start at zero, as the 7094's cleared core gave them
    "-ffpe-trap=invalid,zero,overflow",  # stop at the first NaN, 1/0 or overflow, where it happens
    "-g",  # so the trap's backtrace names the source line
]
PRECISIONS = {
    "r8": ["-fdefault-real-8"],  # REAL and real literals become IEEE binary64
    "r4": [],  # default REAL: IEEE binary32
}
TIMEOUT_S = 5.0  # an honest run takes about 0.03 s; a hang is cut off here


def compile_program(build: Path, precision: str, erratum: str | None) -> Path:
    src_dir = build / f"src-{erratum or 'printed'}"
    if not src_dir.exists():
        (src_dir / "legacy").mkdir(parents=True)
        shutil.copy(LEGACY / SOURCE, src_dir / "legacy" / SOURCE)
        if erratum:
            subprocess.run(
                ["git", "apply", "--unsafe-paths", "--directory=.", str(ERRATA[erratum])],
                cwd=src_dir,
                check=True,
            )
    exe = build / f"luminaire-{erratum or 'printed'}-{precision}"
    cmd = ["gfortran", *COMMON_FLAGS, *PRECISIONS[precision], "-o", str(exe),
           str(src_dir / "legacy" / SOURCE)]
    subprocess.run(cmd, check=True, cwd=build)
    return exe


def run_program(exe: Path, deck: Path) -> tuple[str, str, str]:
    """Run on one deck. Returns (stdout, stderr, ending) with ending 'normal', 'trap' or 'hang'."""
    env = dict(os.environ, GFORTRAN_UNBUFFERED_ALL="1")
    # IBSYS consumed the $DATA control card; the program's READs see only the data cards
    cards = b"".join(line for line in deck.read_bytes().splitlines(keepends=True)
                     if not line.startswith(b"$"))
    try:
        proc = subprocess.run([str(exe)], input=cards, capture_output=True, env=env,
                              timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired as exc:
        return (exc.stdout or b"").decode("ascii"), "", "hang"
    out, err = proc.stdout.decode("ascii"), proc.stderr.decode("ascii", "replace")
    if proc.returncode == 0:
        return out, err, "normal"
    if "SIGFPE" in err:
        return out, err, "trap"
    raise RuntimeError(f"{exe.name} on {deck.name} failed (status {proc.returncode}):\n{err}")


def trap_record(stderr: str, source_lines: list[str]) -> str:
    """The trap's source line from gfortran's backtrace, with the statement it is part of."""
    kind = re.search(r"Floating-point exception - (.*)", stderr)
    m = re.search(rf"{re.escape(SOURCE)}:(\d+)", stderr)
    if not m:
        return f"trap: {kind.group(1) if kind else 'SIGFPE'}\nline: unknown\n"
    n = int(m.group(1))
    first = n
    while first > 1 and len(source_lines[first - 1]) > 5 and source_lines[first - 1][5] not in " 0":
        first -= 1  # back to the statement's initial line
    last = n
    while last < len(source_lines) and len(source_lines[last]) > 5 and source_lines[last][5] not in " 0":
        last += 1
    stmt = "\n".join(source_lines[first - 1:last])
    return f"trap: {kind.group(1) if kind else 'SIGFPE'}\nline: {n}\nstatement:\n{stmt}\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "golden", help="where to write (default golden/)")
    args = ap.parse_args(argv)
    if shutil.which("gfortran") is None:
        print("make_goldens: gfortran is not installed (apt-get install -y gfortran)", file=sys.stderr)
        return 2
    check_output_dir(args.out)  # a missing or read-only folder fails before any compilation
    source_lines = (LEGACY / SOURCE).read_text().splitlines()
    version = subprocess.run(["gfortran", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    manifest = [
        "Golden printouts of legacy/luminaire.f, made by: python scripts/make_goldens.py",
        f"compiler: {version}",
        f"common flags: {' '.join(COMMON_FLAGS)}",
        *(f"{p} flags: {' '.join(f) or '(none: default REAL is binary32)'}" for p, f in PRECISIONS.items()),
        f"run: GFORTRAN_UNBUFFERED_ALL=1, the deck's data cards ($ cards removed, as IBSYS did) on unit 5, timeout {TIMEOUT_S:g} s",
        "",
    ]
    decks = sorted((ROOT / "decks").glob("*.dat"))
    written: set[str] = set()
    with tempfile.TemporaryDirectory() as tmp, OutputSet(directory=args.out) as files:
        build = Path(tmp)
        for precision in PRECISIONS:
            for deck in decks:
                erratum = None
                out, err, ending = run_program(compile_program(build, precision, None), deck)
                note = ""
                if ending == "hang":
                    note = f"as printed: no end within {TIMEOUT_S:g} s; "
                    erratum = "ed-direction"
                    out, err, ending = run_program(compile_program(build, precision, erratum), deck)
                    if ending == "hang":
                        raise RuntimeError(f"{deck.name} {precision} hangs even with the erratum")
                stem = deck.stem + (f".{erratum}" if erratum else "")
                files.write(f"{stem}.{precision}.txt", out)
                written.add(f"{stem}.{precision}.txt")
                if ending == "trap":
                    files.write(f"{stem}.{precision}.trap", trap_record(err, source_lines))
                    written.add(f"{stem}.{precision}.trap")
                line = re.search(r"line: (\d+)", trap_record(err, source_lines)) if ending == "trap" else None
                manifest.append(
                    f"{stem}.{precision}: {note}{'erratum ' + erratum + ': ' if erratum else ''}"
                    f"{ending}{' at line ' + line.group(1) if line else ''}, {len(out.splitlines())} records"
                )
        files.write("MANIFEST.txt", "\n".join(manifest) + "\n")
    # the new set is in place: goldens of decks or precisions that no longer exist go
    for old in args.out.glob("*"):
        if old.suffix in (".txt", ".trap") and old.name not in written | {"MANIFEST.txt"} \
                and old.is_file() and not old.is_symlink():
            old.unlink()
    print("\n".join(manifest))
    return 0


if __name__ == "__main__":
    try:
        code = run_guarded(main)
    except OutputError as exc:  # one line, no traceback: the path and why
        print(f"make_goldens: error: {exc}", file=sys.stderr)
        code = 2
    sys.exit(code)
