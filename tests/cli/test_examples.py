"""Every example command of the README and docs/*.md runs as written and exits as the text says.

An example is a ``deck-emulator ...`` command in a code block (fenced or indented; a ``$ `` prompt
and a leading ``... && `` are dropped) or in backquotes in the prose, that is complete: a
mention of a command by its name alone (``deck-emulator sweep``) and a synopsis with
placeholders (``SOURCE``, ``DIR``, ``FILE.png``, ``[--json]``, ``a|b``, ``...``) are not
examples. Each document's examples run in order in one temporary folder that holds the
checkout's ``decks/`` (the documents run from the checkout), so that an example may use a file
an earlier one wrote. Each must exit 0, or the status its line's comment gives (``exit 1``),
or for a command in the prose the words right after it (`` `...` (exit 2: refused)``).
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
DOCUMENTS = ["README.md", *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))]

#: examples the documents themselves present as long runs (minutes to hours): they run with
#: -m slow_corpus (test_the_long_examples_run), in their document's order
LONG = {
    "docs/sensitivity.md": (
        # "The full run": 4096 core scenes, then 2048 more on --resume
        "deck-emulator sensitivity --deck steel20 --deck steel40 -N 128 --jobs 2 --out full",
        "deck-emulator sensitivity --deck steel20 --deck steel40 -N 256 --jobs 2 --resume "
        "--out full",
    ),
}

_PROGRAM = "deck-emulator"


def _placeholder(token: str) -> bool:
    """SOURCE, DIR, FILE.png, NAME=LO:HI, tcp://HOST:8786, A, B: words the reader fills in."""
    if token.startswith("-"):
        return False
    return bool(re.search(r"(?<![a-z])[A-Z]{2,}(?![a-z])", token)) or bool(
        re.fullmatch(r"[A-Z]", token))


def _complete(command: str) -> bool:
    if any(mark in command for mark in ("[", "]", "|", "...", "…")):
        return False
    words = shlex.split(command)[1:]
    if any(_placeholder(w) for w in words):
        return False
    named_only = (len(words) == 1 and not words[0].startswith("-")) or (
        len(words) == 2 and words[0] == "study")
    return bool(words) and not named_only


def _command_of(line: str) -> str | None:
    """The deck-emulator command of a code line, without its prompt, a leading ``x && `` and
    its comment (kept apart: it may give the exit status)."""
    line = line.strip()
    if line.startswith("$ "):
        line = line[2:]
    if f"&& {_PROGRAM} " in line:
        line = line[line.index(f"&& {_PROGRAM} ") + 3:]
    return line if line.startswith(f"{_PROGRAM} ") else None


def examples(document: str) -> list[tuple[str, int]]:
    """(command, expected exit status) of every complete example of a document, in order."""
    text = (ROOT / document).read_text()
    found: list[tuple[int, str]] = []
    fenced = list(re.finditer(r"^```[^\n]*\n(.*?)^```", text, re.S | re.M))
    for block in fenced:
        for i, line in enumerate(block.group(1).splitlines()):
            command = _command_of(line)
            if command:
                found.append((block.start(1) + i, command))
    # the prose: the fenced blocks blanked out, every offset kept (the examples' order)
    prose = re.sub(r"^```[^\n]*\n.*?^```", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text,
                   flags=re.S | re.M)
    offset = 0
    for line in prose.splitlines(keepends=True):
        if line.startswith("    "):  # an indented code block
            command = _command_of(line)
            if command:
                found.append((offset, command))
        offset += len(line)
    for m in re.finditer(rf"`({_PROGRAM}[^`]*)`( \(exit \d)?", prose):
        # an inline command's exit status, when not 0, follows it: `...` (exit 2: refused)
        found.append((m.start(), " ".join(m.group(1).split()) + (
            f" #{m.group(2).strip(' (')}" if m.group(2) else "")))
    out = []
    for _, command in sorted(found, key=lambda f: f[0]):
        command, _, comment = command.partition(" #")
        command = command.strip()
        if not _complete(command):
            continue
        status = re.search(r"exit (?:status )?(\d)", comment)
        out.append((command, int(status.group(1)) if status else 0))
    return out


def _run_in_order(commands: list[tuple[str, int]], folder: Path) -> list[str]:
    """Run the commands in order in folder; the ones that did not exit as expected, with why."""
    shutil.copytree(ROOT / "decks", folder / "decks")
    program = shutil.which(_PROGRAM) or str(Path(sys.executable).parent / _PROGRAM)
    env = {**os.environ, "PYTHONHASHSEED": "0"}
    failed = []
    for command, expected in commands:
        argv = [program, *shlex.split(command)[1:]]
        done = subprocess.run(argv, cwd=folder, capture_output=True, text=True, env=env,
                              stdin=subprocess.DEVNULL)
        if done.returncode != expected:
            last = (done.stderr.strip().splitlines() or [""])[-1]
            failed.append(f"{command}: exit {done.returncode}, not {expected}: {last}")
    return failed


def test_the_examples_are_found():
    """The finder sees the README's examples and leaves out its synopsis."""
    readme = [c for c, _ in examples("README.md")]
    assert "deck-emulator summary decks/steel40.dat" in readme
    assert "deck-emulator run decks/steel40.dat" in readme  # after `pip install ... &&`
    assert "deck-emulator parse steel40.bcd --card-format bcd --keypunch 029" in readme
    assert not any("SOURCE" in c or "[" in c for c in readme)
    assert "deck-emulator sensitivity --quick --out quick" in [
        c for c, _ in examples("docs/sensitivity.md")]


def _long(document: str) -> tuple[str, ...]:
    """The examples of a document that run with -m slow_corpus: those of :data:`LONG`, and all
    but the first of docs/diff.md, whose sections are one command (a diff at five step sizes,
    tens of runs of both engines) on each of the shipped decks in turn."""
    if document == "docs/diff.md":
        return tuple(c for c, _ in examples(document)[1:])
    return LONG.get(document, ())


@pytest.mark.parametrize("document", DOCUMENTS)
def test_every_example_runs_as_written(document, tmp_path):
    long = _long(document)
    commands = [(c, s) for c, s in examples(document) if c not in long]
    assert _run_in_order(commands, tmp_path) == []


@pytest.mark.slow_corpus
@pytest.mark.parametrize("document", sorted({*LONG, "docs/diff.md"}))
def test_the_long_examples_run(document, tmp_path):
    long = _long(document)
    commands = [(c, s) for c, s in examples(document) if c in long]
    assert long and [c for c, _ in commands] == list(long)  # still in the document
    assert _run_in_order(commands, tmp_path) == []
