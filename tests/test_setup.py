"""The README's set-up commands and CI agree."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def readme_commands():
    return re.findall(r"```\n(.+?)\n```", (ROOT / "README.md").read_text())


def test_ci_runs_exactly_the_readme_test_command():
    test_command = next(c for c in readme_commands() if "pytest" in c)
    ci_lines = [l for l in (ROOT / ".ci" / "run").read_text().splitlines()
                if l and not l.startswith(("#", "set ", "cd "))]
    assert ci_lines == [test_command]


def test_readme_main_job_runs_the_original_deck():
    assert any("deck-emulator run decks/steel40.dat" in c for c in readme_commands())
