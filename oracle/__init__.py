"""The compiled listing as an oracle: legacy/luminaire.f built with gfortran and run on a deck.

A tool of the checkout, beside the package (it needs gfortran and the checkout's ``legacy/``):
the goldens, the differential corpus and the front end's mutants are made with it; no command
of the installed package uses it.

* :func:`make_goldens` -- every shipped deck through the compiled listing in both precisions:
  the only way golden/ is made (``python scripts/make_goldens.py``);
* :class:`Oracle` -- a deck through the compiled listing (REAL*8) and through the emulator
  in binary64, compared record for record (tests/legacy/test_differential.py,
  benchmarks/differential.py); :func:`corpus` -- seeded random decks for it.

Golden files, for each deck in decks/ and each precision:

* ``<deck>.r8.txt`` -- REAL*8 build (``-fdefault-real-8``), the printout (unit 6);
* ``<deck>.r4.txt`` -- default REAL (IEEE binary32) build that traps on the first invalid
  operation, division by zero or overflow; the printout up to the trap, and ``<deck>.r4.trap``
  -- the trapping source line and statement.

A deck whose run as printed does not end within the time limit (ED's search walking away from
its root, see legacy/CORRECTIONS.md) is run again with the named erratum applied, and its golden
says so in its name: ``<deck>.ed-direction.r8.txt``.  ``MANIFEST.txt`` lists, for every run,
the build, the flags and how it ended.  Every run is bounded by a timeout, so nothing hangs.

The oracle needs gfortran and a checkout: the listing and its errata are read from the
checkout's ``legacy/`` folder (:data:`LEGACY`).

How a run ends is compared too (:func:`compare`):

* the compiled program ends normally  <-> the emulator ends normally: identical bytes;
* it traps (SIGFPE)                   <-> the emulator stops on an arithmetic error: the
  records printed up to the stop identical;
* it does not end within the time limit <-> one of the emulator's guards fires (ED without a
  root, endless halving, a post that never lands): the shorter record list is a prefix of the
  longer (the compiled program is cut off by the clock, the emulator by its guard).
"""

from __future__ import annotations

import os
import random
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

from deck_emulator.files import OutputSet
from deck_emulator.legacy.deck import read_deck
from deck_emulator.legacy.stops import EmulatorError
from deck_emulator.vocabulary.units import FT_S_PER_MPH

__all__ = ["COMMON_FLAGS", "PRECISIONS", "TIMEOUT_S", "LEGACY", "compile_program",
           "compile_source", "run_program", "trap_record", "make_goldens", "random_deck",
           "corpus", "compare", "Comparison", "Oracle", "mutant", "mutants", "reordered"]

#: The checkout's legacy/ folder: the listing and its errata.
LEGACY = Path(__file__).resolve().parents[1] / "legacy"
#: The shipped decks.
DECKS = LEGACY.parent / "src" / "deck_emulator" / "decks"
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
    """The listing (with ``erratum`` applied, or as printed) compiled for ``precision`` into
    ``build``: the executable's path."""
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
    return _compile(src_dir / "legacy" / SOURCE, exe, precision, build)


def compile_source(build: Path, lines: list[str], precision: str, name: str) -> Path:
    """Any FORTRAN (``lines``, the listing's dialect: a mutant, a job deck's program) compiled
    for ``precision`` with the goldens' flags into ``build``: the executable's path."""
    src = build / f"{name}.f"
    src.write_text("".join(line + "\n" for line in lines))
    return _compile(src, build / name, precision, build)


def _compile(src: Path, exe: Path, precision: str, build: Path) -> Path:
    cmd = ["gfortran", *COMMON_FLAGS, *PRECISIONS[precision], "-o", str(exe), str(src)]
    subprocess.run(cmd, check=True, cwd=build, capture_output=True)
    return exe


def run_program(exe: Path, deck: Path, timeout_s: float | None = None) -> tuple[str, str, str]:
    """Run on one deck. Returns (stdout, stderr, ending) with ending 'normal', 'trap' or 'hang'."""
    env = dict(os.environ, GFORTRAN_UNBUFFERED_ALL="1")
    # IBSYS consumed the $DATA control card; the program's READs see only the data cards
    cards = b"".join(line for line in deck.read_bytes().splitlines(keepends=True)
                     if not line.startswith(b"$"))
    try:
        proc = subprocess.run([str(exe)], input=cards, capture_output=True, env=env,
                              timeout=timeout_s or TIMEOUT_S)
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


def make_goldens(out_dir: Path) -> list[str]:
    """Compile the listing in both precisions, run every shipped deck, write the goldens and
    MANIFEST.txt into ``out_dir`` (as one set: all or nothing) and remove goldens of decks or
    precisions that no longer exist. Returns the manifest's lines."""
    if not (LEGACY / SOURCE).is_file():
        raise RuntimeError(f"the oracle needs a checkout: {LEGACY / SOURCE} is not there")
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
    decks = sorted(DECKS.glob("*.dat"))
    written: set[str] = set()
    with tempfile.TemporaryDirectory() as tmp, OutputSet(directory=out_dir) as files:
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
    for old in out_dir.glob("*"):
        if old.suffix in (".txt", ".trap") and old.name not in written | {"MANIFEST.txt"} \
                and old.is_file() and not old.is_symlink():
            old.unlink()
    return manifest


# ------------------------------------------------------------------------ the standing oracle


def _r(x: float, places: int) -> float:
    return round(x, places)


def random_deck(rng: random.Random):
    """One deck: the 40 mph steel deck with speed, angle, post mass and inertias, springs,
    FCONST, car outline, height and DELTA drawn at random; about one deck in eight physically
    odd (car moving away, a very light or very flat post, stiff or no springs ...)."""

    base = read_deck(DECKS / "steel40.dat")
    d = base.values  # each drawn value is the deck's own, scaled or shifted
    u = rng.uniform
    ch = {
        "VVB": _r(-u(10, 60) * FT_S_PER_MPH, 2),  # 10 to 60 mph towards the post
        "ALPHA": 0.0 if rng.random() < 0.6 else _r(u(0.03, 0.6), 4),
        "W": _r(d["W"] * u(0.5, 2.0), 2),  # the post's mass (before 2026-11: the car's, 100)
        "A": _r(d["A"] * u(0.5, 2.0), 2),
        "B": _r(d["B"] * u(0.5, 2.0), 2),
        "C": _r(d["C"] * u(0.5, 2.0), 2),
        "CK": _r(d["CK"] * u(0.3, 3.0), 1),
        "CT": _r(d["CT"] * u(0.3, 3.0), 1),
        "FCONST": _r(d["FCONST"] * u(0.3, 3.0), 1),
        "HLEN": _r(d["HLEN"] * u(0.6, 1.6), 3),
        "TLEN": _r(d["TLEN"] * u(0.6, 1.4), 3),
        "TRLEN": _r(d["TRLEN"] * u(0.6, 1.4), 3),
        "HHV": _r(d["HHV"] + u(-1.5, 1.5), 3),
        "HTV": _r(d["HTV"] + u(-1.5, 1.5), 3),
        "HTRV": _r(d["HTRV"] + u(-1.5, 1.5), 3),
        "YLFEN": _r(d["YLFEN"] + u(-2.0, 1.0), 3),
        "YRFEN": _r(d["YRFEN"] + u(-1.0, 2.0), 3),
        "HEIGHT": _r(d["HEIGHT"] * u(0.8, 1.2), 3),
        "DELTA": _r(d["DELTA"] + u(-0.1, 0.1), 4),
    }
    if rng.random() < 0.125:  # the physically odd
        odd = rng.choice(["away", "slow", "light", "flat", "stiff", "soft", "nocap", "low", "fast"])
        ch.update({
            "away": {"VVB": _r(u(1, 30), 2)},
            "slow": {"VVB": _r(-u(0.5, 5), 2)},
            "light": {"W": _r(u(1, 10), 2)},
            "flat": {"C": _r(u(1, 10), 2), "A": _r(u(100, 500), 2)},
            "stiff": {"CK": _r(u(3e5, 9e5), 1), "CT": _r(u(3e5, 9e5), 1)},
            "soft": {"CK": _r(u(100, 1000), 1), "CT": _r(u(100, 1000), 1)},
            "nocap": {"FCONST": _r(u(1e5, 9e5), 1)},
            "low": {"HEIGHT": _r(u(1, 5), 3)},
            "fast": {"VVB": _r(-u(120, 250), 2)},
        }[odd])
    return base.with_values(**ch)


def corpus(n: int, seed: int):
    rng = random.Random(seed)
    return [random_deck(rng) for _ in range(n)]


@dataclass
class Comparison:
    ending_compiled: str  # normal, trap, hang
    ending_emulator: str  # normal, arithmetic, or the guard's name
    agree: bool
    why: str = ""
    records: int = 0
    compiled_text: str = ""  # what the compiled program printed


GUARDS = ("ed_iterations", "halvings", "time_s", "runaway")


def _listing_run(deck, errata):
    """The listing through the FORTRAN front end, binary64: the engine's road."""
    from deck_emulator.legacy.fortran import listing_program

    return listing_program(tuple(errata)).runner(deck, "double", trace=False).run()


def compare(deck, exe_for, workdir: Path, timeout_s: float | None = None, *,
            ours=None, errata=None) -> Comparison:
    """Run one deck both ways and compare. ``exe_for(erratum)`` gives the compiled program;
    ``ours(deck, errata)`` runs our side (default: the emulator in binary64) and returns its
    ``Run`` or raises its ``EmulatorError``; ``errata``: default ed-direction on an angled
    deck."""

    if errata is None:
        errata = ("ed-direction",) if deck["ALPHA"] != 0 else ()
    path = workdir / "deck.dat"
    path.write_text(deck.to_text())
    out, _err, ending = run_program(exe_for(errata[0] if errata else None), path, timeout_s)
    theirs = out.splitlines()
    ours = ours or (lambda deck, errata: _listing_run(deck, errata))
    try:
        run = ours(deck, errata)
        ours, ours_ending = run.records, "normal"
    except EmulatorError as exc:
        ours, ours_ending = exc.run.records, exc.guard or "error"
    o = Comparison(ending, ours_ending, False, records=len(theirs), compiled_text=out)
    if ending == "normal":
        if ours_ending != "normal":
            o.why = f"the compiled program ended normally, the emulator stopped ({ours_ending})"
        elif "".join(r + "\n" for r in ours) != out:
            o.why = _first_difference(ours, theirs)
        else:
            o.agree = True
    elif ending == "trap":
        if ours_ending != "arithmetic":
            o.why = f"the compiled program trapped, the emulator ended {ours_ending}"
        elif ours != theirs:
            o.why = _first_difference(ours, theirs)
        else:
            o.agree = True
    else:  # hang: cut off by the clock; its last line may be cut too
        if not out.endswith("\n") and theirs:
            theirs = theirs[:-1]
        n = min(len(ours), len(theirs))
        if ours_ending not in GUARDS:
            o.why = f"the compiled program did not end, the emulator ended {ours_ending}"
        elif ours[:n] != theirs[:n]:
            o.why = _first_difference(ours[:n], theirs[:n])
        else:
            o.agree = True
    return o


def _first_difference(ours, theirs) -> str:
    for i, (a, b) in enumerate(zip(ours, theirs), start=1):
        if a != b:
            return f"record {i}: emulator {a!r}, compiled {b!r}"
    return f"{len(ours)} records from the emulator, {len(theirs)} from the compiled program"


class Oracle:
    """The compiled listing, built once per erratum into a temporary directory."""

    def __init__(self, timeout_s: float | None = None):
        if shutil.which("gfortran") is None:
            raise RuntimeError("gfortran is not installed")
        self.timeout_s = timeout_s  # None: TIMEOUT_S; an honest run takes about 0.03 s
        self._tmp = tempfile.TemporaryDirectory(prefix="oracle-")
        self.dir = Path(self._tmp.name)
        self._exes = {}

    def exe(self, erratum):
        if erratum not in self._exes:
            self._exes[erratum] = compile_program(self.dir, "r8", erratum)
        return self._exes[erratum]

    def compare(self, deck) -> Comparison:
        return compare(deck, self.exe, self.dir, self.timeout_s)

    def close(self):
        self._tmp.cleanup()




# ------------------------------------------------------------------ mutated programs


#: What a mutant changes: one digit of a REAL constant of an executable statement, one letter
#: of a FORMAT's Hollerith text, or one digit of a FORMAT's Fw.d or nX.
MUTATIONS = ("constant", "format text", "format field")
_REAL_CONSTANT = re.compile(r"(?<![A-Z0-9.])(\d+\.\d*|\.\d+)")


def _sites(lines: list[str]) -> dict[str, list[tuple[int, int]]]:
    """(line index, column index) of every character a mutation may change, by kind."""
    from deck_emulator.legacy.jobdeck import is_comment, statements

    sites: dict[str, list[tuple[int, int]]] = {kind: [] for kind in MUTATIONS}
    starts = {s.line - 1: s for s in statements(lines)}
    for index, s in starts.items():
        cards = [n - 1 for n, _ in s.cards]
        if s.text.upper().startswith("FORMAT("):
            if s.text.upper() == "FORMAT(8F10.5)":
                continue  # the READs' (the cards' layout stays)
            for n in cards:
                line = lines[n]
                inside = _hollerith_columns(line, n == index)
                for col in range(6, min(len(line), 72)):
                    ch = line[col]
                    if col in inside and ch.isalpha():
                        sites["format text"].append((n, col))
                    elif col not in inside and ch.isdigit() and col > 5 and (
                            line[col - 1] in "F." or line[col + 1:col + 2] == "X"):
                        if not (line[col - 1] == "." and ch == "0"):
                            sites["format field"].append((n, col))
            continue
        for n in cards:
            line = lines[n][:72]
            if is_comment(line):
                continue
            for m in _REAL_CONSTANT.finditer(line, 6):
                sites["constant"] += [(n, c) for c in range(m.start(), m.end())
                                      if line[c].isdigit()]
    return sites


def _hollerith_columns(line: str, first: bool) -> set[int]:
    """The columns of ``line`` inside nH texts (a text that runs on to the next card is
    counted on this card only)."""
    inside: set[int] = set()
    col = 6
    while col < min(len(line), 72):
        m = re.match(r"(\d+)H", line[col:])
        if m and line[col - 1] in "(,/":
            start = col + m.end()
            inside |= set(range(start, min(start + int(m.group(1)), 72)))
            col = start + int(m.group(1))
            continue
        col += 1
    return inside


def mutant(rng: random.Random, lines: list[str] | None = None, kind: str | None = None):
    """One mutated program: (what changed, its lines), from the listing (``lines``) by one
    seeded change of ``kind`` (default: drawn from :data:`MUTATIONS`)."""
    from deck_emulator.legacy import listing_lines

    lines = list(lines or listing_lines())
    sites = _sites(lines)
    kind = kind or rng.choice(MUTATIONS)
    n, col = rng.choice(sites[kind])
    old = lines[n][col]
    pool = ("ABCDEFGHIJKLMNOPQRSTUVWXYZ" if old.isalpha() else
            "123456789" if kind == "format field" else "0123456789")
    new = rng.choice([c for c in pool if c != old])
    lines[n] = lines[n][:col] + new + lines[n][col + 1:]
    return f"{kind}: line {n + 1}, column {col + 1}: {old!r} -> {new!r}", lines


_NAME = re.compile(r"[A-Z][A-Z0-9]*")


def reordered(rng: random.Random, lines: list[str] | None = None) -> tuple[str, list[str]]:
    """A mutant of the listing whose meaning is the listing's: two adjacent assignments swapped
    where neither reads or assigns what the other assigns (one card each, the second
    unlabelled; a label of the first stays in columns 1-5, so a GO TO to it still reaches
    both)."""
    from deck_emulator.legacy import listing_lines
    from deck_emulator.legacy.jobdeck import statements

    lines = list(lines or listing_lines())
    pairs = []
    for a, b in zip(statements(lines), statements(lines)[1:]):
        if b.label or len(a.cards) != 1 or len(b.cards) != 1 or b.line != a.line + 1:
            continue
        sides = [s.text.split("=", 1) for s in (a, b)]
        if any(len(x) != 2 or not _NAME.fullmatch(x[0]) for x in sides):
            continue
        (left1, right1), (left2, right2) = sides
        if left1 != left2 and left1 not in _NAME.findall(right2) and (
                left2 not in _NAME.findall(right1)):
            pairs.append(a.line - 1)
    n = rng.choice(pairs)
    lines[n], lines[n + 1] = lines[n][:6] + lines[n + 1][6:], lines[n + 1][:6] + lines[n][6:]
    return f"reordered: lines {n + 1} and {n + 2}", lines


def mutants(count: int, seed: int, swaps: int = 0):
    """``count`` seeded mutants of the listing (see :func:`mutant`) and ``swaps`` reordered
    ones (:func:`reordered`)."""
    rng = random.Random(seed)
    return [mutant(rng) for _ in range(count)] + [reordered(rng) for _ in range(swaps)]
