"""The README's set-up commands, the lock and CI agree."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def readme_commands():
    setup = (ROOT / "README.md").read_text().split("## Set-up on a fresh machine", 1)[1]
    setup = setup.split("\n## ", 1)[0]
    return re.findall(r"```\n(.+?)\n```", setup)


def test_the_readme_holds_exactly_two_setup_commands():
    main_job, tests = readme_commands()
    assert "deck-emulator run decks/steel40.dat" in main_job
    assert "pytest" in tests


def test_ci_runs_exactly_the_readme_test_command_in_a_fresh_virtualenv():
    test_command = readme_commands()[1]
    lines = [l for l in (ROOT / ".ci" / "run").read_text().splitlines()
             if l and not l.startswith(("#", "set ", "cd "))]
    assert lines[-1] == test_command
    made = next(i for i, l in enumerate(lines) if re.fullmatch(r'python3 -m venv "\$(\w+)"', l))
    name = re.fullmatch(r'python3 -m venv "\$(\w+)"', lines[made]).group(1)
    assert f'. "${name}/bin/activate"' in lines[made + 1:-1]


def test_both_setup_commands_install_the_locked_versions():
    """Every package the suite runs with is pinned to one version in constraints.txt, and
    both commands give that file to pip."""
    for command in readme_commands():
        assert "pip install -c constraints.txt " in command
    pins = {}
    for line in (ROOT / "constraints.txt").read_text().splitlines():
        if line and not line.startswith("#"):
            name, version = line.split("==")
            pins[name.lower().replace("_", "-")] = version
    for needed in ("numpy", "scipy", "fortranformat", "matplotlib", "pytest", "pytest-xdist", "hypothesis",
                   "import-linter", "setuptools", "dask", "salib", "pyarrow"):
        assert needed in pins, needed
