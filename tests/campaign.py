"""The fault campaign, kept: generators of bad, odd and mutated inputs for every
input kind, each case run through the command line in process and held to the tool's promise:

* it ends with a documented exit status: 0 computed, 2 bad input, 3 a run that could not end
  (argparse's own 2 for a malformed option included), and for ``compare`` 1 the printouts
  differ, 4 some record of them could not be read;
* no traceback, and a refusal (2) says so in exactly one ``deck-emulator: error:`` line;
* a refused command writes nothing: the output paths it was given do not exist afterwards.

The cases are drawn from seeded generators (``random.Random(seed)``), so a corpus is the same
every time.  :func:`corpus` builds it: ``fast`` a sample for the default suite
(tests/robustness/test_campaign.py), the full corpus under ``-m slow_corpus``.  Run as a script it runs a
corpus and prints the count of cases and of broken promises per category::

    python tests/campaign.py            # the full corpus
    python tests/campaign.py --fast     # the default suite's sample

The default suite also runs one slice of the full corpus chosen by the commit checked out
(:func:`commit_slice`, ``CAMPAIGN_SLICE=k`` to choose), so that successive commits cover it.

A resume of a changed study is a case of two commands in one folder: the study (``first``),
then its files changed (``change``), then ``--resume``, refused in one line naming what changed
(``names``) with nothing of the folder changed, or run (a grid made larger: the rest run).
Interruptions, kills and concurrent runs are not cases here: they need processes of their own
(tests/robustness/test_kill.py, test_interrupt_startup.py, test_store_lock.py,
test_output_sets.py, test_signals.py).
"""

from __future__ import annotations

import contextlib
import io
import os
import random
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
STEEL40 = ROOT / "decks" / "steel40.dat"
GOLDEN40 = ROOT / "golden" / "steel40.r8.txt"
CRASH_TEST = ROOT / "src" / "deck_emulator" / "assemblies" / "crash_test.toml"
STATUSES = {0, 2, 3}


@dataclass
class Case:
    """One command of the campaign: ``argv`` with ``{dir}`` standing for its own folder,
    ``files`` (name -> bytes) written there first, ``outputs`` the names it may write."""

    category: str
    name: str
    argv: list[str]
    files: dict[str, bytes] = field(default_factory=dict)
    outputs: tuple[str, ...] = ()
    statuses: frozenset[int] = frozenset(STATUSES)
    #: the standard streams it runs with: "" (text), "stdout closed", "stderr closed", or an
    #: encoding the output must degrade to ("ascii", "latin-1")
    streams: str = ""
    #: bytes a writer sends through a pipe, named ``{pipe}`` in ``argv`` (/dev/fd/N)
    pipe: bytes | None = None
    #: a hostile scheduler (:class:`Hostile`'s mode and answer), named ``{scheduler}``
    scheduler: tuple[str, bytes] | None = None
    #: environment variables set while it runs
    env: dict[str, str] = field(default_factory=dict)
    #: a command run first in the same folder (it must end with 0 or 3), and the files written
    #: over after it, before ``argv`` runs: a study and its inputs changed before a resume
    first: list[str] | None = None
    change: dict[str, bytes] = field(default_factory=dict)
    #: what a refusal's line must say (``{dir}`` as in ``argv``)
    names: str = ""


@dataclass
class Result:
    case: Case
    status: int
    seconds: float
    broken: list[str]


# ------------------------------------------------------------------------------ the inputs


def _deck_bytes() -> bytes:
    return STEEL40.read_bytes()


def _scene_bytes() -> bytes:
    from deck_emulator.vocabulary.scene import Scene
    from deck_emulator.legacy.deck import read_deck

    return Scene.from_deck(read_deck(STEEL40)).to_toml().encode()


def _mutate(data: bytes, rng: random.Random) -> tuple[str, bytes]:
    """One random mutation of a file's bytes (its name, the bytes)."""
    kind = rng.choice(["byte", "bytes", "cut", "drop-line", "twice-line", "swap-lines",
                       "letters", "bom", "nul", "high", "crlf", "blank", "repeat"])
    b = bytearray(data)
    lines = data.split(b"\n")
    i = rng.randrange(len(b))
    if kind == "byte":
        b[i] = rng.randrange(256)
    elif kind == "bytes":
        for _ in range(rng.randint(2, 12)):
            b[rng.randrange(len(b))] = rng.randrange(32, 127)
    elif kind == "cut":
        del b[i:]
    elif kind in ("drop-line", "twice-line", "swap-lines"):
        j = rng.randrange(len(lines))
        if kind == "drop-line":
            del lines[j]
        elif kind == "twice-line":
            lines.insert(j, lines[j])
        else:
            k = rng.randrange(len(lines))
            lines[j], lines[k] = lines[k], lines[j]
        b = bytearray(b"\n".join(lines))
    elif kind == "letters":
        b[i:i + 3] = b"1E+"
    elif kind == "bom":
        b[:0] = b"\xef\xbb\xbf"
    elif kind == "nul":
        b[i:i] = b"\x00" * rng.randint(1, 40)
    elif kind == "high":
        b[i:i] = "é½—".encode()[: rng.randint(1, 7)]
    elif kind == "crlf":
        b = bytearray(bytes(b).replace(b"\n", b"\r\n"))
    elif kind == "blank":
        b = bytearray(b" " * rng.randint(0, 200))
    else:
        b = bytearray(bytes(b) * rng.randint(2, 40))
    return kind, bytes(b)


def _printouts() -> dict[str, bytes]:
    """The golden steel40 printout in every layout compare reads: carriage control in column
    1, the page as printed (asa), the text of the PDF's forms (each printed line, stripped, no
    blank lines), and typed (blank lines and page marks dropped, fields re-spaced)."""
    from deck_emulator.legacy.pages import layout
    from deck_emulator.legacy.printer import render_asa

    text = GOLDEN40.read_text()
    records = text.split("\n")[:-1]
    forms = layout(records)
    pdf_text = "\n".join("\n".join(line.strip() for _, line in form if line.strip())
                         for form in forms)
    typed = "\n".join(" ".join(r.split()) for r in records if r.strip() and r != "1")
    return {"carriage control": text.encode(), "asa": render_asa(records).encode(),
            "pdf text": pdf_text.encode(), "typed": typed.encode()}


def _scanned(data: bytes, rng: random.Random) -> tuple[str, bytes]:
    """A scan's damage: some digits of some values read as the letters a scan confuses them
    with, a point lost or doubled, or a field made unreadable."""
    from deck_emulator.legacy.records import OCR_CONFUSIONS

    confusions = sorted(OCR_CONFUSIONS.items())
    lines = data.decode().split("\n")
    values = [i for i, line in enumerate(lines) if "VALUE OF" in line]
    for i in rng.sample(values, min(len(values), rng.randint(1, 40))):
        head, _, field = lines[i].rpartition(" ")
        kind = rng.choice(["letter", "letter", "point lost", "point doubled", "unreadable"])
        if kind == "letter":  # each digit a scan confuses, read as one of its letters
            for letter, digit in rng.sample(confusions, rng.randint(1, len(confusions))):
                field = field.replace(digit, letter, 1)
        elif kind == "point lost":
            field = field.replace(".", "")
        elif kind == "point doubled":
            field = field.replace(".", "..")
        else:
            field = rng.choice(["#", "", "?.?", "1e5", "nan", "-", ".", "--1.0"])
        lines[i] = f"{head} {field}"
    return "scanned", "\n".join(lines).encode()


ODD_VALUES = [0.0, -0.0, 1e-5, -1e-5, 99999.0, -99999.0, 9999999.0, -999999.0, 123456.7]


def _odd_deck(rng: random.Random) -> tuple[str, bytes]:
    """A deck well formed in every column whose values are physically odd."""
    from deck_emulator.engine.assemblies import to_deck_text
    from deck_emulator.legacy.deck import NAMES, DeckError, read_deck

    from deck_emulator.core.assembly import AssemblyError

    deck = read_deck(STEEL40)
    while True:  # values a 10-column field cannot hold are drawn again
        names = rng.sample(list(NAMES), rng.randint(1, 3))
        changes = {}
        for n in names:
            base = float(deck.values[n])
            changes[n] = rng.choice(ODD_VALUES + [base * rng.choice([-1, 10, 100, 0.01, 1e4])])
        try:
            text = to_deck_text(dict(deck.with_values(**changes).values))
        except (AssemblyError, DeckError):
            continue
        return ",".join(f"{n}={v:g}" for n, v in changes.items()), text.encode()


def _toml_mutation(text: str, rng: random.Random) -> tuple[str, str]:
    """A scene or assembly description with one key's value changed, or one key or table
    dropped or added."""
    lines = text.splitlines()
    keyed = [i for i, line in enumerate(lines) if "=" in line and not line.startswith("#")]
    i = rng.choice(keyed)
    key = lines[i].split("=")[0].strip()
    kind = rng.choice(["value", "value", "value", "drop", "unknown-key", "unknown-table",
                       "not-toml", "empty"])
    if kind == "value":
        new = rng.choice(['"x"', "-5", "0", "nan", "inf", "-inf", "1e400", "[]", "[1, 2]",
                          "true", "1" + "0" * 400, "{}", "-1e-300", '""', "0.0"])
        lines[i] = f"{key} = {new}"
        return f"{key}={new[:12]}", "\n".join(lines) + "\n"
    if kind == "drop":
        del lines[i]
        return f"no {key}", "\n".join(lines) + "\n"
    if kind == "unknown-key":
        lines.insert(i, "colour = 3.0")
        return "unknown key", "\n".join(lines) + "\n"
    if kind == "unknown-table":
        return "unknown table", text + "\n[weather]\nrain = true\n"
    if kind == "not-toml":
        return "not TOML", text.replace("=", ":", 1)
    return "empty", ""


def _toml_bomb(text: str, rng: random.Random) -> tuple[str, str]:
    """A scene or assembly description with a bomb put in at a random line: arrays or inline
    tables nested deep, a dotted key or a header of many parts, a number of many digits."""
    lines = text.splitlines()
    i = rng.randrange(len(lines) + 1)
    kind = rng.choice(["arrays", "tables", "dotted key", "header", "digits", "mixed"])
    depth = rng.choice([17, 50, 1000, 20000, 100_000])
    if kind == "arrays":
        bomb = "bomb = " + "[" * depth + "1" + "]" * depth
    elif kind == "tables":
        bomb = "bomb = " + "{a = " * depth + "1" + "}" * depth
    elif kind == "dotted key":
        bomb = "a" + ".a" * depth + " = 1"
    elif kind == "header":
        bomb = "[" + ".".join(["t"] * (depth + 1)) + "]\nx = 1"
    elif kind == "digits":
        key = lines[i - 1].split("=")[0].strip() if i and "=" in lines[i - 1] else "n"
        bomb = f"{key}_x = " + rng.choice(["", "-", "0."]) + "7" * rng.choice([101, 4301, 100_000])
    else:
        bomb = "bomb = [" + "{a = [" * (depth // 2) + "1" + "]}" * (depth // 2) + "]"
    lines.insert(i, bomb)
    return f"{kind} {depth}", "\n".join(lines) + "\n"


BAD_NUMBERS = ["nan", "inf", "-inf", "-1", "0", "1e309", "1e-300", "", "abc", "1,5", "0x10"]

#: (command line, the option that takes a bad value): the options a command checks
OPTIONS = [
    (["run", "steel40", "--max-ed-iterations"], ""),
    (["run", "steel40", "--tha-start"], ""),
    (["core", "steel40", "--rtol"], ""),
    (["core", "steel40", "--atol"], ""),
    (["core", "steel40", "--max-step"], ""),
    (["plot", "steel40", "--out", "{dir}/p.png", "--every"], ""),
    (["diff", "steel40", "--max-k"], ""),
    (["sweep", "--angles", "0", "--out", "{dir}/sw", "--speeds"], ""),
    (["sweep", "--speeds", "20", "--out", "{dir}/sw", "--angles"], ""),
    (["sweep", "--speeds", "20", "--angles", "0", "--out", "{dir}/sw", "--jobs"], ""),
    (["sensitivity", "--quick", "--out", "{dir}/se", "-N"], ""),
    (["sensitivity", "--quick", "--out", "{dir}/se", "--seed"], ""),
    (["sensitivity", "--quick", "--out", "{dir}/se", "--input"], "W="),
    (["assembly", "steel", "core", "--speed-mph"], ""),
    (["assembly", "steel", "core", "--alpha-deg"], ""),
]

#: commands whose output holds characters outside ASCII, or that write to stdout at all
STREAM_COMMANDS = [["parse", "steel40"], ["parse", "steel40", "--json"], ["run", "steel40"],
                   ["summary", "steel40"], ["corrections", "--all"], ["scene", "steel40"],
                   ["corrections"], ["core", "steel40"], ["diff", "steel40"]]

#: SOURCEs that are neither files nor pipes
NOT_FILES = ["/dev/null", "/dev/zero", "/dev/urandom", "/dev/full", "{dir}", "/proc/self"]

#: commands and the output options they take, for the output-path cases
WRITERS = [
    (["run", "steel40", "--out"], ()),
    (["run", "steel40", "--pages"], ()),
    (["core", "steel40", "--trajectory"], ()),
    (["punch", "steel40", "--to", "cbn", "--out"], ()),
    (["plot", "steel40", "--out"], ()),
    (["sweep", "--speeds", "20", "--angles", "0", "--erratum", "ed-direction", "--quiet",
      "--jobs", "1", "--out"], ()),
]

BAD_PATHS = ["{dir}/missing/x", "{dir}/file/x", "{dir}", "/dev/full", "/proc/version",
             "{dir}/ro/x", "/dev/null/x", "{dir}/x\x00y"]


#: Statements a mutated program may gain: outside the front end's dialect, or in it.
_STATEMENTS = ["      DOUBLE PRECISION HI", "      READ(3,1)Q", "      COMMON/B/HI",
               "      DIMENSION X(10)", "      IF(Q.GT.0.0)GO TO 125", "      DO 10 I=1,5",
               "      X=SQRT(Q)", "      GO TO (1,2),I", "      ASSIGN 10 TO I",
               "      WRITE(6,999)Q", "      CALL NONE(Q)", "      Q=Q+", "      Q=Q**0.5",
               "      H=H/0.0", "      GO TO 77777", "   41 CONTINUE", "      RETURN",
               "      FUNCTION F(X)", "      END", "      STOP", "  999 FORMAT(E15.5)",
               "  998 FORMAT(5HABC)", "      READ(5,1)Q", "      CALL ED(Q)"]


def _program_mutation(job: list[str], rng: random.Random) -> tuple[str, list[str]]:
    """A job deck whose FORTRAN changed: a card's character, a card dropped or repeated, or a
    statement added (:data:`_STATEMENTS`)."""
    texts = list(job)
    first = texts.index("$IBFTC MAIN") + 1
    last = texts.index("$ENTRY         MAIN")
    at = rng.randrange(first, last)
    kind = rng.choice(["character", "character", "drop", "repeat", "statement"])
    if kind == "character":
        line = texts[at].ljust(72)
        col = rng.randrange(72)
        new = rng.choice("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 =+-*/(),.$'")
        texts[at] = (line[:col] + new + line[col + 1:]).rstrip()
        return f"card {at + 1} column {col + 1} -> {new!r}", texts
    if kind == "drop":
        del texts[at]
    elif kind == "repeat":
        texts.insert(at, texts[at])
    else:
        texts.insert(at, rng.choice(_STATEMENTS))
    return f"{kind} at card {at + 1}", texts


class Hostile:
    """A TCP server on a free local port that is not a Dask scheduler: to every connection it
    says nothing (``silent``), sends ``answer`` once after reading (``answer``), or sends it a
    byte every 0.3 s (``drip``); ``refused``: nothing listens at the port."""

    def __init__(self, mode: str, answer: bytes = b""):
        import socket
        import threading

        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.address = f"tcp://127.0.0.1:{self.sock.getsockname()[1]}"
        self.mode, self.answer = mode, answer
        if mode == "refused":
            self.sock.close()
            return
        self.sock.listen(8)
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        import threading

        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            threading.Thread(target=self._answer, args=(conn,), daemon=True).start()

    def _answer(self, conn):
        try:
            if self.mode == "answer":
                conn.recv(1024)
                conn.sendall(self.answer)
            for k in range(100 if self.mode == "drip" else 0):
                conn.sendall(self.answer[k % len(self.answer):][:1] or b"x")
                time.sleep(0.3)
            time.sleep(30)
        except OSError:
            pass
        finally:
            conn.close()

    def close(self):
        self.sock.close()


def _hostile_answer(rng: random.Random) -> tuple[str, bytes]:
    """What a server that is not Dask's says: an HTTP status, random bytes, a frame header
    promising more than it sends, a line of text."""
    kind = rng.choice(["http", "random", "frames", "text"])
    if kind == "http":
        code = rng.choice([200, 400, 404, 500, 503])
        return f"HTTP {code}", f"HTTP/1.1 {code} X\r\nContent-Length: 0\r\n\r\n".encode()
    if kind == "random":
        return "random bytes", bytes(rng.randrange(256) for _ in range(rng.randint(1, 64)))
    if kind == "frames":
        return "a short frame", rng.randint(1, 2**40).to_bytes(8, "little") * 2 + b"\x00" * 7
    return "text", b"220 mail.example ESMTP ready\r\n"


# ------------------------------------------------------------------------------ the corpus


#: The full corpus in the default suite, a slice a commit: slice k of SLICES holds the cases
#: whose place within their category is k modulo SLICES (a category of SLICES cases or more
#: in every slice), k
#: chosen by the commit checked out (:func:`commit_slice`), so that successive commits run
#: the whole corpus; about a quarter of the fixed sample's cases a commit.
SLICES = 64


def commit_slice() -> int:
    """The slice of the commit checked out: the number of commits to HEAD modulo SLICES
    (successive commits: successive slices), from a shallow clone (which counts one) HEAD's
    hash modulo SLICES; ``CAMPAIGN_SLICE=k`` picks one (a failure in CI, run again here);
    0 outside a git checkout."""
    import subprocess

    if os.environ.get("CAMPAIGN_SLICE"):
        return int(os.environ["CAMPAIGN_SLICE"]) % SLICES

    def git(*args: str) -> str:
        return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True,
                              check=True, timeout=60).stdout.strip()
    try:
        if git("rev-parse", "--is-shallow-repository") == "false":
            return int(git("rev-list", "--count", "HEAD")) % SLICES
        return int(git("rev-parse", "HEAD"), 16) % SLICES
    except (OSError, ValueError, subprocess.SubprocessError):
        return 0


def sliced(cases: list[Case], k: int, n: int = SLICES) -> list[Case]:
    """Slice ``k`` of ``n`` of ``cases``: those whose place within their category is k mod n."""
    places: dict[str, int] = {}
    out = []
    for case in cases:
        place = places.get(case.category, 0)
        places[case.category] = place + 1
        if place % n == k:
            out.append(case)
    return out


def corpus(fast: bool = True, seed: int = 23) -> list[Case]:
    """The campaign's cases: a sample of each category (``fast``) or the full corpus."""
    rng = random.Random(seed)
    n = {"deck": 40, "odd": 12, "cards": 16, "toml": 30, "printouts": 16, "path": 0,
         "cut": 12, "bomb": 12, "streams": 16, "sources": 12, "programs": 12,
         "schedulers": 6, "stopped": 3, "promises": 6, "resumed": 2} if fast \
        else {"deck": 1200, "odd": 300, "cards": 600, "toml": 600, "printouts": 400, "path": 0,
              "cut": 300, "bomb": 300, "streams": 120, "sources": 120, "programs": 300,
              "schedulers": 60, "stopped": 40, "promises": 60, "resumed": 24}
    deck = _deck_bytes()
    cases: list[Case] = []

    commands = [["parse"], ["run"], ["summary", "--quiet"], ["core"]]
    for k in range(n["deck"]):
        kind, data = _mutate(deck, rng)
        cmd = commands[k % len(commands)]
        cases.append(Case("mutated decks", f"{kind} #{k}", [cmd[0], "{dir}/d.dat", *cmd[1:]],
                          {"d.dat": data}))

    for k in range(n["odd"]):
        what, data = _odd_deck(rng)
        cmd = ["run", "core", "summary"][k % 3]
        cases.append(Case("physically odd decks", what, [cmd, "{dir}/d.dat"], {"d.dat": data}))

    from deck_emulator.legacy.cardimage import write_images
    from deck_emulator.legacy.jobdeck import data_deck_texts, job_deck_texts
    from deck_emulator.legacy.deck import read_deck

    d40 = read_deck(STEEL40)
    images = {(fmt, job): write_images((job_deck_texts if job else data_deck_texts)([d40]),
                                       fmt, "026")
              for fmt in ("binary", "cbn", "bcd") for job in (False, True)}
    for k in range(n["cards"]):
        (fmt, job), data = list(images.items())[k % len(images)]
        kind, bad = _mutate(data, rng)
        cmd = ["parse", "run"][k % 2]
        cases.append(Case("mutated card images", f"{fmt}{' job' if job else ''} {kind} #{k}",
                          [cmd, "{dir}/d.img", "--card-format", fmt], {"d.img": bad}))

    cut_rng = random.Random(seed + 1)  # its own, so that the other categories stay the same
    for k in range(n["cut"]):  # a card image cut short: refused, unless cut between cards
        (fmt, job), data = list(images.items())[k % len(images)]
        size = cut_rng.randrange(1, len(data))
        between = size % 160 == 0 if fmt == "binary" else bool(data[size] & 0x80)
        cmd = [["parse"], ["run"], ["summary", "--quiet"]][k % 3]
        card_format = ["--card-format", fmt] if k % 2 else []
        cases.append(Case("card images cut short", f"{fmt}{' job' if job else ''} to {size} #{k}",
                          [cmd[0], "{dir}/d.img", *cmd[1:], *card_format],
                          {"d.img": data[:size]},
                          statuses=frozenset(STATUSES) if between else frozenset({2})))

    printouts = _printouts()
    golden = printouts["carriage control"]
    empty = [("empty", b""), ("blanks", b" \n\n\f\n"), ("a deck", deck), ("a PDF", b"%PDF-1.4\n")]
    for k in range(n["printouts"]):
        layout_name = list(printouts)[k % len(printouts)]
        data = printouts[layout_name]
        if k % 8 == 7:
            kind, bad = empty[(k // 8) % len(empty)]
        elif k % 2:
            kind, bad = _scanned(data, rng)
        else:
            kind, bad = _mutate(data, rng)
        files = {"a.txt": golden, "b.txt": bad}
        argv = ["compare", "{dir}/a.txt", "{dir}/b.txt"] + (["--json"] if k % 3 == 0 else [])
        if k % 5 == 4:  # the damaged one as A
            argv[1:3] = argv[2:0:-1]
        cases.append(Case("printouts", f"{layout_name} {kind} #{k}", argv, files,
                          statuses=frozenset({0, 1, 2, 4})))

    scene, assembly = _scene_bytes().decode(), CRASH_TEST.read_text()
    for k in range(n["toml"]):
        if k % 2:
            what, text = _toml_mutation(scene, rng)
            cases.append(Case("scene and assembly files", f"scene {what}",
                              ["core", "{dir}/s.toml"], {"s.toml": text.encode()}))
        else:
            what, text = _toml_mutation(assembly, rng)
            cases.append(Case("scene and assembly files", f"assembly {what}",
                              ["assembly", "{dir}/a.toml", "scene"], {"a.toml": text.encode()}))

    bomb_rng = random.Random(seed + 2)  # its own, so that the other categories stay the same
    bomb_commands = [["core"], ["scene"], ["run"]]
    for k in range(n["bomb"]):
        if k % 2:
            what, text = _toml_bomb(scene, bomb_rng)
            cmd = bomb_commands[(k // 2) % len(bomb_commands)]
            cases.append(Case("scene and assembly bombs", f"scene {what} #{k}",
                              [cmd[0], "{dir}/s.toml"], {"s.toml": text.encode()},
                              statuses=frozenset({2})))
        else:
            what, text = _toml_bomb(assembly, bomb_rng)
            cases.append(Case("scene and assembly bombs", f"assembly {what} #{k}",
                              ["assembly", "{dir}/a.toml", "scene"], {"a.toml": text.encode()},
                              statuses=frozenset({2})))

    stream_rng = random.Random(seed + 3)  # its own, so that the other categories stay the same
    for k in range(n["streams"]):
        argv = stream_rng.choice(STREAM_COMMANDS)
        streams = ["stdout closed", "stderr closed", "ascii", "latin-1"][k % 4]
        if stream_rng.random() < 0.3:  # a refusal, said (or not) on the stream as it is
            argv = [argv[0], "{dir}/missing.dat"]
        cases.append(Case("closed streams and bare encodings", f"{streams}: {' '.join(argv)}",
                          argv, streams=streams,
                          statuses=frozenset({2}) if streams == "stdout closed" else
                          frozenset({0, 2, 3})))

    source_rng = random.Random(seed + 4)  # its own, so that the other categories stay the same
    for k in range(n["sources"]):
        cmd = [["parse"], ["run"], ["summary", "--quiet"], ["core"]][k % 4]
        if k % 3 == 0:
            what = NOT_FILES[(k // 3) % len(NOT_FILES)]
            cases.append(Case("sources that are not files", f"{cmd[0]} {what}",
                              [cmd[0], what, *cmd[1:]], statuses=frozenset({2})))
            continue
        if k % 3 == 1:
            kind, data = "whole", deck
        else:
            kind, data = _mutate(deck, source_rng)
        cases.append(Case("sources that are not files", f"{cmd[0]} a pipe of a {kind} deck #{k}",
                          [cmd[0], "{pipe}", *cmd[1:]], pipe=data,
                          statuses=frozenset({0, 3}) if kind == "whole" else
                          frozenset(STATUSES)))

    program_rng = random.Random(seed + 5)  # its own, so that the other categories stay the same
    job = job_deck_texts([d40])
    for k in range(n["programs"]):
        what, texts = _program_mutation(job, program_rng)
        cases.append(Case("mutated programs", f"{what} #{k}",
                          ["run", "{dir}/p.job", "--out", "{dir}/out.txt", "--quiet"],
                          {"p.job": ("\n".join(texts) + "\n").encode()}, outputs=("out.txt",)))
    scheduler_rng = random.Random(seed + 6)  # its own, so that the other categories stay the same
    for k in range(n["schedulers"]):
        cmd = [["sweep", "--speeds", "20", "--angles", "0"], ["study", "error", "steel40"],
               ["sensitivity", "--quick"]][k % 3]
        mode = scheduler_rng.choice(["silent", "answer", "answer", "drip", "refused"])
        what, answer = _hostile_answer(scheduler_rng)
        cases.append(Case("hostile schedulers", f"{' '.join(cmd[:2])}: {mode} {what} #{k}",
                          [*cmd, "--quiet", "--out", "{dir}/o", "--scheduler", "{scheduler}"],
                          outputs=("o",), statuses=frozenset({2}), scheduler=(mode, answer)))

    stopped_rng = random.Random(seed + 7)  # its own, so that the other categories stay the same
    for k in range(n["stopped"]):
        # a core run past its wall bound: a stopped scene, exit 3, said in one line
        wall = stopped_rng.choice([1e-9, 1e-6, 1e-4])
        source = stopped_rng.choice(["steel40", "steel20_a15", "{dir}/s.toml"])
        extra = stopped_rng.choice([[], ["--json"], ["--preset", "physical"]])
        cases.append(Case("stopped core runs", f"core {source} --max-wall {wall:g} #{k}",
                          ["core", source, "--max-wall", repr(wall), *extra],
                          {"s.toml": _scene_bytes()}, statuses=frozenset({3})))
    promise_rng = random.Random(seed + 8)
    for k in range(n["promises"]):
        # the smaller promises: long legal names, undecodable bytes in a name, a bad
        # SOURCE_DATE_EPOCH; each a documented status and no traceback
        kind = ["long name", "undecodable", "epoch"][k % 3]
        if kind == "long name":
            name = "n" * promise_rng.randint(236, 251) + ".csv"
            cases.append(Case("smaller promises", f"core --trajectory, {len(name)}-byte name",
                              ["core", "steel40", "--trajectory", "{dir}/" + name],
                              outputs=(name,), statuses=frozenset({0})))
        elif kind == "undecodable":
            name = os.fsdecode(bytes(promise_rng.randrange(0x80, 0x100) for _ in range(3))
                               + b".txt")
            cases.append(Case("smaller promises", f"run --out, undecodable name #{k}",
                              ["run", "steel40", "--out", "{dir}/" + name],
                              outputs=(name,), statuses=frozenset({0})))
        else:
            epoch = promise_rng.choice(["abc", "1e9", "-1", "", " 12", "0x10", "1.5",
                                        "253402300800", "9" * 30])
            cases.append(Case("smaller promises", f"run --pages, SOURCE_DATE_EPOCH={epoch!r}",
                              ["run", "steel40", "--pages", "{dir}/o.pdf", "--quiet"],
                              outputs=("o.pdf",), env={"SOURCE_DATE_EPOCH": epoch}))

    resume_rng = random.Random(seed + 9)  # its own, so that the other categories stay the same
    for k in range(n["resumed"]):
        cases.append(_changed_study(k, resume_rng, d40))

    for argv, prefix in OPTIONS:
        values = BAD_NUMBERS if not fast else BAD_NUMBERS[:4]
        for v in values:
            cases.append(Case("invalid options", f"{argv[-1]} {prefix}{v!r}",
                              [*argv, prefix + v], outputs=("sw", "se", "p.png")))

    for argv, _ in WRITERS:
        for path in (BAD_PATHS if not fast else BAD_PATHS[:3] + BAD_PATHS[-1:]):
            cases.append(Case("output paths", f"{argv[0]} {argv[-1]} {path!r}",
                              [*argv, path], {"file": b"x"}))
    return cases


_STUDY_CHANGED = "the engine or its settings changed"


def _changed_study(k: int, rng: random.Random, deck) -> Case:
    """A study made, then resumed with something changed: its deck's contents, its engine,
    its preset, its grid or its seed (refused, naming it), or its grid made larger (the rest
    run)."""
    kind = ["deck", "engine", "grid", "study deck", "preset", "larger grid", "seed"][k % 7]
    changed = deck.with_values(WV=round(rng.uniform(80.0, 120.0), 3)).to_text().encode()
    speed, angles = rng.choice([20, 30, 40, 50]), rng.choice(["0", "0,15", "15"])
    engine = rng.choice(["emulator", "core"])
    sweep = ["sweep", "--base-deck", "{dir}/b.dat", "--speeds", str(speed), "--angles", angles,
             "--jobs", "1", "--quiet", "--out", "{dir}/o"]
    first, argv = [*sweep, "--engine", engine], [*sweep, "--engine", engine, "--resume"]
    names, statuses = _STUDY_CHANGED, frozenset({2})
    if kind in ("deck", "study deck"):
        if kind == "study deck":
            first = ["sensitivity", "--deck", "{dir}/b.dat", "-N", "2", "--only", "--input",
                     "WV=90:110", "--jobs", "1", "--quiet", "--out", "{dir}/o"]
            argv = [*first, "--resume"]
        names = "{dir}/b.dat changed since"
    elif kind == "engine":
        argv[-2] = {"emulator": "core", "core": "emulator"}[engine]
    elif kind == "preset":
        first, argv = [*sweep, "--engine", "core"], [*sweep, "--engine", "core", "--preset",
                                                      "physical", "--resume"]
    elif kind == "grid":
        argv[argv.index("--speeds") + 1] = str(speed + 5)
    elif kind == "larger grid":  # the scenes both grids hold are the same: the rest run
        argv[argv.index("--angles") + 1] = angles + ",30"
        names, statuses = "", frozenset({0, 3})
    else:
        first = ["sensitivity", "--deck", "{dir}/b.dat", "-N", "2", "--only", "--input",
                 "WV=90:110", "--jobs", "1", "--quiet", "--out", "{dir}/o"]
        argv = [*first, "--seed", str(rng.randint(1, 99)), "--resume"]
    return Case("resumes of a changed study", f"{kind} #{k}", argv, {"b.dat": _deck_bytes()},
                statuses=statuses, first=first,
                change={"b.dat": changed} if kind in ("deck", "study deck") else {},
                names=names)


def _snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` and its bytes, but a store's lock (its holder's pid)."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and p.name != ".lock"}


# ------------------------------------------------------------------------------ running


def _prepare(case: Case, folder: Path) -> list[str]:
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in case.files.items():
        (folder / name).write_bytes(data)
    ro = folder / "ro"
    ro.mkdir(exist_ok=True)
    os.chmod(ro, 0o555)
    return [a.replace("{dir}", str(folder)) for a in case.argv]


def run_case(case: Case, folder: Path) -> Result:
    """Run one case in process and list the promises it broke."""
    from deck_emulator.cli import main

    import threading

    argv = _prepare(case, folder)
    before = {p.name for p in folder.iterdir()}
    out, err = io.StringIO(), io.StringIO()
    raw_out = raw_err = None
    if case.streams == "stdout closed":
        out = None  # as Python starts with the descriptor closed
    elif case.streams == "stderr closed":
        err = None
    elif case.streams:
        raw_out, raw_err = io.BytesIO(), io.BytesIO()
        out = io.TextIOWrapper(raw_out, encoding=case.streams, errors="strict")
        err = io.TextIOWrapper(raw_err, encoding=case.streams, errors="strict")
    pipe = writer = None
    if case.pipe is not None:
        pipe = os.pipe()
        argv = [a.replace("{pipe}", f"/dev/fd/{pipe[0]}") for a in argv]

        def write(fd=pipe[1], data=case.pipe):
            with contextlib.suppress(OSError), os.fdopen(fd, "wb") as fh:
                fh.write(data)

        writer = threading.Thread(target=write, daemon=True)
        writer.start()
    server = None
    if case.scheduler is not None:
        from deck_emulator.vocabulary import defaults

        server = Hostile(*case.scheduler)
        argv = [a.replace("{scheduler}", server.address) for a in argv]
        bound, defaults.SCHEDULER_CONNECT_S = defaults.SCHEDULER_CONNECT_S, 0.5
    saved_env = {k: os.environ.get(k) for k in case.env}
    os.environ.update(case.env)
    started = time.perf_counter()
    broken = []
    made = None
    if case.first is not None:  # the study to resume, then its inputs changed
        with contextlib.redirect_stdout(io.StringIO()), \
                contextlib.redirect_stderr(io.StringIO()) as said:
            code = main([a.replace("{dir}", str(folder)) for a in case.first])
        if code not in (0, 3):  # it ran (3: a scene of it stopped, as an angled deck may)
            broken.append(f"the first run exited {code}: {said.getvalue().strip()[-200:]}")
        for name, data in case.change.items():
            (folder / name).write_bytes(data)
        made = _snapshot(folder)
        before = {p.name for p in folder.iterdir()}
    cwd = os.getcwd()
    saved = sys.stdout, sys.stderr
    try:
        os.chdir(folder)  # anything written to the current folder is seen
        sys.stdout, sys.stderr = out, err
        try:
            status = main(argv)
        except SystemExit as exc:  # not expected: main returns its status
            status = exc.code if isinstance(exc.code, int) else 2
            broken.append("SystemExit raised")
    except Exception as exc:  # noqa: BLE001 - the broken promise being looked for
        status = 1
        broken.append(f"traceback: {type(exc).__name__}: {exc}"[:200])
    finally:
        sys.stdout, sys.stderr = saved
        os.chdir(cwd)
        if pipe is not None:
            os.close(pipe[0])
            writer.join(30)
        if server is not None:
            server.close()
            defaults.SCHEDULER_CONNECT_S = bound
        for k, v in saved_env.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    if raw_err is not None:
        out.flush()
        err.flush()
        text_out = raw_out.getvalue().decode(case.streams)
        err = io.StringIO(raw_err.getvalue().decode(case.streams))
        if case.streams == "ascii" and not text_out.isascii():
            broken.append("non-ASCII output")
    unsaid = err is None  # stderr closed: nothing said can be read, the status is checked
    if unsaid:
        err = io.StringIO()
    seconds = time.perf_counter() - started
    text = err.getvalue()
    if status not in case.statuses:
        broken.append(f"exit status {status}")
    if "Traceback" in text:
        broken.append("a traceback on stderr")
    if status == 2:
        lines = [x for x in text.splitlines() if x.startswith("deck-emulator")
                 and "error:" in x]
        if len(lines) != 1 and not unsaid:
            broken.append(f"{len(lines)} error lines for a refusal")
        written = {p.name for p in folder.iterdir()} - before
        if written:
            broken.append(f"a refusal wrote {sorted(written)}")
        if made is not None and _snapshot(folder) != made:
            broken.append("a refused resume changed the study's folder")
        said = case.names.replace("{dir}", str(folder))
        if said and not any(said in x for x in lines):
            broken.append(f"the refusal does not say {case.names!r}")
    with contextlib.suppress(OSError):
        os.chmod(folder / "ro", 0o755)
    return Result(case, status, seconds, broken)


def run_corpus(cases: list[Case], base: Path, progress: bool = False) -> list[Result]:
    results = []
    for k, case in enumerate(cases):
        results.append(run_case(case, base / f"case{k}"))
        if progress and k % 50 == 0:
            print(f"{k}/{len(cases)}", file=sys.stderr, flush=True)
    return results


def counts(results: list[Result]) -> Iterator[tuple[str, int, int, dict[int, int], float]]:
    """Per category: cases, broken cases, cases per exit status, the longest case (s)."""
    by: dict[str, list[Result]] = {}
    for r in results:
        by.setdefault(r.case.category, []).append(r)
    for category, rs in by.items():
        statuses: dict[int, int] = {}
        for r in rs:
            statuses[r.status] = statuses.get(r.status, 0) + 1
        yield (category, len(rs), sum(bool(r.broken) for r in rs), dict(sorted(statuses.items())),
               max(r.seconds for r in rs))


if __name__ == "__main__":
    import tempfile

    fast = "--fast" in sys.argv
    with tempfile.TemporaryDirectory() as tmp:
        results = run_corpus(corpus(fast=fast), Path(tmp), progress=True)
    print("| category | cases | broken | exit statuses | longest (s) |")
    print("|---|---|---|---|---|")
    for category, n, broken, statuses, longest in counts(results):
        shown = ", ".join(f"{s}: {c}" for s, c in statuses.items())
        print(f"| {category} | {n} | {broken} | {shown} | {longest:.1f} |")
    for r in results:
        if r.broken:
            print(f"BROKEN {r.case.category} / {r.case.name}: {r.case.argv}: {r.broken}")
