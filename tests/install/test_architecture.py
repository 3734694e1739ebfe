"""The layering, as import-linter contracts (pyproject.toml), and what it buys: quick start-up."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LINT = shutil.which("lint-imports")
pytestmark = pytest.mark.skipif(LINT is None, reason="import-linter is not installed")


def _lint(config: Path | None = None) -> subprocess.CompletedProcess:
    argv = [LINT] + (["--config", str(config)] if config else [])
    return subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_the_import_contracts_hold():
    proc = _lint()
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "0 broken" in proc.stdout
    for name in ("CLI > commands > pictures > studies > engine", "Nothing imports the CLI",
                 "Only the CLI imports the commands' table",
                 "does not import its implementations", "No import cycles"):
        assert name in proc.stdout


def test_a_broken_contract_fails_the_linter(tmp_path):
    """The contracts are live: one the code breaks (the engine layer does import the 1967
    path) is reported as broken, with the import that breaks it."""
    config = tmp_path / "broken.toml"
    config.write_text(textwrap.dedent("""
        [tool.importlinter]
        root_package = "deck_emulator"

        [[tool.importlinter.contracts]]
        name = "The engine layer never imports the 1967 path (false on purpose)"
        type = "forbidden"
        source_modules = ["deck_emulator.engine"]
        forbidden_modules = ["deck_emulator.legacy"]
    """))
    proc = _lint(config)
    assert proc.returncode != 0
    assert "BROKEN" in proc.stdout and "deck_emulator.engine" in proc.stdout


@pytest.mark.parametrize("command", [
    ["parse", "decks/steel40.dat"],
    ["run", "decks/steel40.dat", "--out", "{tmp}/steel40.txt"],
])
def test_parse_and_run_start_without_scipy_or_matplotlib(command, tmp_path):
    argv = [a.format(tmp=tmp_path) for a in command]
    code = textwrap.dedent(f"""
        import sys
        from deck_emulator.cli import main
        status = main({argv!r})
        heavy = sorted(m for m in ("scipy", "matplotlib") if m in sys.modules)
        print("HEAVY", heavy, "STATUS", status)
    """)
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert "HEAVY [] STATUS 0" in proc.stdout, proc.stdout + proc.stderr


def test_every_named_choice_is_implemented_by_its_layer():
    """The choices' names are one table (vocabulary/choices.py) that the command line offers
    without importing the layers below; each layer must implement exactly those names."""
    from importlib.resources import files

    from deck_emulator.engine import engine_for
    from deck_emulator.legacy import cardimage
    from deck_emulator.legacy.arithmetic import get_arithmetic
    from deck_emulator.legacy.keypunch import CODES
    from deck_emulator.vocabulary import choices
    from deck_emulator.vocabulary.scene import PRESETS

    for name in choices.ARITHMETICS:
        assert get_arithmetic(name) is not None
    errata = files("deck_emulator.legacy") / "errata"
    assert {p.name for p in errata.iterdir() if p.name.endswith(".patch")} == {
        f"{name}.patch" for name in choices.ERRATA}
    assert tuple(PRESETS) == choices.PRESETS
    assert [engine_for(name).name for name in choices.ENGINES] == list(choices.ENGINES)
    assert set(cardimage._READERS) == set(choices.CARD_FORMATS)
    assert tuple(CODES) == choices.KEYPUNCH_CODES


def test_only_the_cli_parses_arguments():
    """No module of the package but cli.py mentions argparse, a Namespace or sys.argv: the
    commands take typed options, and only the command line parses."""
    found = [str(p.relative_to(ROOT)) for p in (ROOT / "src" / "deck_emulator").rglob("*.py")
             if p.name != "cli.py" or p.parent.name != "deck_emulator"
             if re.search(r"argparse|Namespace|sys\.argv", p.read_text())]
    assert found == []


#: A unit factor written out: ft in a mile, s in an hour, mph <-> ft/s (and its rounded
#: 1.46667), m in a ft, the report's gravity. units.py is the one place for each.
_UNIT_FACTOR = re.compile(r"\b5280\b|\b3600\b|1\.4666|0\.6818|0\.3048|88\.0? */ *60\b|32\.174")


def test_unit_factors_are_written_in_units_py_only():
    files = [*(ROOT / "src").rglob("*.py"), *(ROOT / "scripts").glob("*.py"),
             *(ROOT / "benchmarks").glob("*.py")]
    found = []
    for path in files:
        if path.name == "units.py":
            continue
        for i, line in enumerate(path.read_text().splitlines(), 1):
            if _UNIT_FACTOR.search(line.split("#", 1)[0]):
                found.append(f"{path.relative_to(ROOT)}:{i}: {line.strip()}")
    assert found == []



#: A tolerance, step or sampling default written as a number: ``rtol=1e-9``, ``RTOL = 1e-12``,
#: ``default=1e-10``, ``step_s: float = 0.0004``.  vocabulary/defaults.py is the one place.
_DEFAULT_LITERAL = re.compile(r"(rtol|atol|RTOL|ATOL)[A-Za-z_]*\s*[:=]\s*(float\s*=\s*)?[0-9.]+e-[0-9]+"
                              r"|default=1e-[0-9]+|(step|sample)[A-Za-z_]*_s\s*(:\s*float)?\s*=\s*[0-9.]+\b")


def test_defaults_are_written_in_the_defaults_module_only():
    found = []
    for path in (ROOT / "src").rglob("*.py"):
        if path.name == "defaults.py":
            continue
        for i, line in enumerate(path.read_text().splitlines(), 1):
            if _DEFAULT_LITERAL.search(line.split("#", 1)[0]):
                found.append(f"{path.relative_to(ROOT)}:{i}: {line.strip()}")
    assert found == []


def test_every_door_to_the_core_is_the_same_run():
    """``CoreEngine()``, ``deck_emulator.run(..., engine="core")`` and ``deck-emulator core``
    take their settings from one defaults module, so they are one run: the same hit time to
    the last bit (not a tolerance: the same computation)."""
    import json

    import deck_emulator
    from deck_emulator.engine import CoreEngine
    from deck_emulator.engine.sources import load_source

    cli = subprocess.run([sys.executable, "-m", "deck_emulator", "core", "steel40", "--json"],
                         capture_output=True, text=True, timeout=300, check=True)
    answer = json.loads(cli.stdout)
    api = deck_emulator.run("steel40", engine="core")
    engine = CoreEngine().run(load_source("steel40").deck())
    assert answer["quantities"]["hit_time_s"] == api.hit_time_s == engine.hit_time_s
    assert api.hit_time_s is not None

def _one_road() -> dict:
    import tomllib

    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    (road,) = [c for c in config["contracts"] if c["id"] == "one-road"]
    return road


def _imported_names(path: Path):
    """(module, name) of every import in ``path`` (name None for ``import module``)."""
    import ast

    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, None
        elif isinstance(node, ast.ImportFrom) and node.module:
            for a in node.names:
                yield node.module, a.name


#: the engines' machinery: what a script asks the engine layer for instead of importing it
MACHINERY = ("deck_emulator.legacy.fortran", "deck_emulator.legacy.arithmetic",
             "deck_emulator.legacy.printer", "deck_emulator.core.solve", "deck_emulator.core.model",
             "deck_emulator.core.components", "deck_emulator.core.sliding",
             "deck_emulator.core.leaf_spring", "deck_emulator.core.regions",
             "deck_emulator.core.pair_hits", "deck_emulator.core.rigid",
             "deck_emulator.core.kinematics", "deck_emulator.core.result",
             "deck_emulator.core.checks", "deck_emulator.core.batch")


def test_studies_and_pictures_import_neither_path():
    """The contract forbids the studies and the pictures both paths whole (import-linter reads
    every import, type-checking ones included): the 1967 path's and the core's packages."""
    assert set(_one_road()["forbidden_modules"]) == {"deck_emulator.legacy", "deck_emulator.core"}
    assert "ignore_imports" not in _one_road()


def test_scripts_reach_the_machinery_through_no_back_door():
    """Scripts are outside import-linter's reach: none imports a machinery module, directly or
    as a lazily loaded name of the packages ``deck_emulator.core`` or ``deck_emulator.legacy``."""
    lazy = {"deck_emulator.core", "deck_emulator.legacy"}
    found = []
    for path in (ROOT / "scripts").glob("*.py"):
        for module, name in _imported_names(path):
            if any(module == m or module.startswith(m + ".") for m in MACHINERY):
                found.append(f"{path.name}: {module}")
            elif module in lazy and name is not None:
                found.append(f"{path.name}: from {module} import {name}")
    assert found == []


def test_no_script_runs_an_engine_itself():
    """Scripts ask the engine layer for a run: none calls the emulator's program or the core's
    solver."""
    runs = re.compile(r"(?<![.\w])(simulate|free_flight|run_deck|Program)\(")
    found = [f"{p.name}:{i}" for p in (ROOT / "scripts").glob("*.py")
             for i, line in enumerate(p.read_text().splitlines(), 1)
             if runs.search(line.split("#", 1)[0])]
    assert found == []
