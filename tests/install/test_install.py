"""Installed = checked out: the wheel, installed into a fresh virtual environment, runs the
README's commands from a directory outside the checkout."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import venv
from pathlib import Path

import pytest

#: process-level or document tests: the README's test command runs them, a bare pytest not
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
#: what a source distribution of the checkout holds (the rest is history and local state)
_NOT_SHIPPED = shutil.ignore_patterns(".git", "build", "*.egg-info", "__pycache__",
                                      ".pytest_cache", ".hypothesis", ".venv*", "dist")


def _run(argv, cwd, timeout=300):
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "PYTHONUSERBASE", "VIRTUAL_ENV")}
    return subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env)


def _running_site_dirs() -> list[str]:
    """The folders this interpreter imports installed packages from: a virtualenv's own
    site-packages, or the system interpreter's (and the user's, where it is used)."""
    dirs = [sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]]
    dirs += [p for p in sys.path if p.rstrip("/").endswith(("site-packages", "dist-packages"))]
    return list(dict.fromkeys(d for d in dirs if Path(d).is_dir()))


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """A fresh venv with this checkout installed as ``pip install .`` does: a wheel built from
    a copy of the source tree, not an editable install.  The wheel is built offline with the
    running environment's setuptools (no build isolation, no index).  The venv is made without
    system site-packages; a ``.pth`` file in it names the running environment's site folders,
    where the README's test command installed numpy, fortranformat and the rest, so the
    dependencies are those the suite runs with (in a virtualenv or the system interpreter
    alike) and nothing is fetched.  The venv's own site-packages comes first on its path: the
    package itself is the wheel's."""
    base = tmp_path_factory.mktemp("install")
    source = base / "source"
    shutil.copytree(ROOT, source, symlinks=True, ignore=_NOT_SHIPPED)
    wheels = base / "wheels"
    build = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
                  "--no-index", "--wheel-dir", str(wheels), str(source)], cwd=base)
    assert build.returncode == 0, build.stdout + build.stderr
    (wheel,) = wheels.glob("deck_emulator-*.whl")

    env_dir = base / "venv"
    venv.EnvBuilder(system_site_packages=False, with_pip=True).create(env_dir)
    python = env_dir / "bin" / "python"
    purelib = _run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                   cwd=base).stdout.strip()
    (Path(purelib) / "_running_environment.pth").write_text("\n".join(_running_site_dirs()) + "\n")
    inst = _run([str(python), "-m", "pip", "install", "--no-deps", "--no-index", str(wheel)],
                cwd=base)
    assert inst.returncode == 0, inst.stdout + inst.stderr
    where = _run([str(python), "-c", "import deck_emulator, numpy; print(deck_emulator.__file__)"],
                 cwd=base)
    assert where.returncode == 0, where.stderr
    assert where.stdout.startswith(purelib), where.stdout  # the wheel, not the checkout
    work = base / "elsewhere"
    work.mkdir()
    return env_dir / "bin" / "deck-emulator", work



#: the base install: what the 1967 path needs (pyproject.toml's dependencies), its modules
LIGHT = ("numpy", "fortranformat", "tqdm", "tomli_w", "fontTools")
#: what only an extra brings (deck_emulator.extras)
HEAVY = ("numba", "scipy", "dask", "distributed", "matplotlib", "pandas", "pyarrow", "SALib")


def test_the_wheel_requires_only_the_light_packages(installed):
    """``pip install .`` brings numpy, fortranformat, tqdm, tomli-w and fonttools, nothing
    else: the wheel's own metadata, every heavier package behind an extra."""
    import email

    (wheel,) = (installed[0].parents[2] / "wheels").glob("deck_emulator-*.whl")
    import zipfile

    with zipfile.ZipFile(wheel) as z:
        (meta,) = [n for n in z.namelist() if n.endswith(".dist-info/METADATA")]
        requires = email.message_from_bytes(z.read(meta)).get_all("Requires-Dist")
    plain = sorted(r.split(">")[0].split("=")[0].strip().lower().replace("-", "_")
                   for r in requires if "extra ==" not in r)
    assert plain == sorted(name.lower() for name in LIGHT)


def test_the_extras_table_is_pyprojects():
    """deck_emulator.extras names, for each heavy module, the extra pyproject.toml installs it
    with."""
    import re
    import tomllib

    from deck_emulator.extras import EXTRA_OF_MODULE

    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    def names(requirement: str) -> set[str]:  # dask[distributed] brings distributed too
        m = re.match(r"([A-Za-z0-9_.-]+)(?:\[([^\]]*)\])?", requirement)
        return {m.group(1).lower(), *(x.strip().lower() for x in (m.group(2) or "").split(",") if x)}

    direct = {extra: set().union(*(names(r) for r in reqs if not r.startswith("deck_emulator")))
              for extra, reqs in extras.items()}
    for module, extra in EXTRA_OF_MODULE.items():
        if module == "llvmlite":  # numba's own dependency
            continue
        assert module.lower() in direct[extra], (module, extra)
    assert {m.lower() for m in HEAVY} <= {m.lower() for m in EXTRA_OF_MODULE}


@pytest.fixture(scope="module")
def light(installed, tmp_path_factory):
    """The installed wheel in a second fresh venv that sees only the light packages (links to
    the running environment's copies: nothing is fetched), as ``pip install .`` leaves it."""
    exe, work = installed
    base = tmp_path_factory.mktemp("light")
    site = base / "site"
    site.mkdir()
    import importlib.util

    for name in LIGHT:
        spec = importlib.util.find_spec(name)
        top = Path(spec.origin).parent if spec.submodule_search_locations else Path(spec.origin)
        (site / top.name).symlink_to(top)
        libs = top.parent / f"{name}.libs"  # numpy's bundled OpenBLAS
        if libs.is_dir():
            (site / libs.name).symlink_to(libs)
    env_dir = base / "venv"
    venv.EnvBuilder(system_site_packages=False, with_pip=True).create(env_dir)
    python = env_dir / "bin" / "python"
    purelib = _run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                   cwd=base).stdout.strip()
    (Path(purelib) / "_light.pth").write_text(f"{site}\n")
    (wheel,) = (exe.parents[2] / "wheels").glob("deck_emulator-*.whl")
    inst = _run([str(python), "-m", "pip", "install", "--no-deps", "--no-index", str(wheel)],
                cwd=base)
    assert inst.returncode == 0, inst.stdout + inst.stderr
    for name in HEAVY:
        found = _run([str(python), "-c", f"import {name}"], cwd=base)
        assert found.returncode != 0, f"{name} is importable in the light venv"
    return env_dir / "bin" / "deck-emulator", work


@pytest.mark.parametrize("argv", [["run", "steel40"], ["parse", "steel40", "--json"],
                                  ["summary", "steel40", "--json"],
                                  ["punch", "steel40", "--to", "cbn", "--out", "j.cbn"], ["corrections"],
                                  ["scene", "steel40"],
                                  ["run", "steel40", "--pages", "p.pdf", "--paper", "striped"]])
def test_the_1967_path_runs_on_the_light_install(light, argv):
    exe, work = light
    proc = _run([str(exe), *argv], cwd=work)
    assert proc.returncode == 0, proc.stderr
    if argv == ["run", "steel40"]:
        assert proc.stdout == (ROOT / "golden" / "steel40.r8.txt").read_text()
    if "--pages" in argv:  # the printed pages need no matplotlib: the face is the package's
        assert (work / "p.pdf").read_bytes().startswith(b"%PDF-")


@pytest.mark.parametrize("argv, extra", [(["core", "steel40"], "core"),
                                         (["plot", "steel40", "--out", "x.png"], "plot"),
                                         (["run", "steel40", "--trajectory", "t.csv"], "frames")])
def test_a_command_whose_extra_is_missing_names_it(light, argv, extra):
    exe, work = light
    proc = _run([str(exe), *argv], cwd=work)
    assert proc.returncode == 2, (proc.stdout, proc.stderr)
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert f"deck_emulator[{extra}]" in proc.stderr
    assert not list(work.glob("x.*")) and not (work / "t.csv").exists()

def test_the_installed_version_is_the_one_in_pyproject(installed):
    import tomllib

    exe, work = installed
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    proc = _run([str(exe), "--version"], cwd=work)
    assert (proc.returncode, proc.stdout) == (0, f"deck-emulator {version}\n"), proc.stderr


def test_run_and_summary_on_an_absolute_deck_path(installed):
    exe, work = installed
    deck = str(ROOT / "decks" / "steel40.dat")
    run = _run([str(exe), "run", deck], cwd=work)
    assert run.returncode == 0, run.stderr
    assert run.stdout == (ROOT / "golden" / "steel40.r8.txt").read_text()
    summary = _run([str(exe), "summary", deck, "--json"], cwd=work)
    assert summary.returncode == 0, summary.stderr
    hit = json.loads(summary.stdout)["events"][-1]
    assert (hit["kind"], hit["surface"], hit["point"]) == ("hit", "ground", "R")


@pytest.mark.parametrize("argv, made", [
    (["parse", "{deck}", "--json"], None),
    (["run", "{deck}", "--precision", "ibm7094", "--out", "r.txt"], "r.txt"),
    (["plot", "{deck}", "--out", "side.png"], "side.png"),
    (["diff", "{deck}", "--erratum", "ed-direction", "--max-k", "0"], None),
    (["core", "{deck}"], None),
    (["scene", "{deck}", "--out", "s.toml"], "s.toml"),
    (["core", "s.toml"], None),
    (["punch", "{deck}", "--to", "cbn", "--job", "--out", "j.cbn"], "j.cbn"),
    (["run", "j.cbn", "--pages", "j.pdf"], "j.pdf"),
    (["assembly", "aluminium", "deck"], None),
    (["study", "error", "{deck}", "--quick", "--jobs", "2", "--out", "err"], "err/README.md"),
])
def test_every_readme_command_runs_installed(installed, argv, made):
    """Each command of the README, as a user types it, from outside the checkout (in order:
    the scene and the punched job deck of earlier rows are inputs of later ones)."""
    exe, work = installed
    deck = str(ROOT / "decks" / "steel40.dat")
    proc = _run([str(exe)] + [a.format(deck=deck) for a in argv], cwd=work, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    if made:
        assert (work / made).stat().st_size > 0
    else:
        assert proc.stdout.strip()


def test_shipped_decks_by_name_from_another_folder(installed):
    """After pip install, a shipped deck is named, not found in a checkout: run, summary,
    core and the Python API take ``steel40`` from any folder."""
    exe, work = installed
    run = _run([str(exe), "run", "steel40"], cwd=work)
    assert run.returncode == 0, run.stderr
    assert run.stdout == (ROOT / "golden" / "steel40.r8.txt").read_text()
    for command in ("summary", "core"):
        proc = _run([str(exe), command, "steel40", "--json", "--quiet"], cwd=work)
        assert proc.returncode == 0, proc.stderr
        assert json.loads(proc.stdout)["source"] == "steel40"
    python = exe.parent / "python"
    api = _run([str(python), "-c", "import deck_emulator; print(deck_emulator.run('steel40')"
                ".hit_message)"], cwd=work)
    assert api.stdout.strip() == "THE POST HAS HIT THE GROUND WITH POINT R", api.stderr


def test_sweep_and_study_need_no_base_deck_path(installed):
    exe, work = installed
    sweep = _run([str(exe), "sweep", "--speeds", "40", "--angles", "0", "--jobs", "1",
                  "--out", "sweep"], cwd=work)
    assert sweep.returncode == 0, sweep.stderr
    assert "POST HITS GROUND WITH POINT R" in (work / "sweep" / "sweep.md").read_text()
    study = _run([str(exe), "study", "stability", "--quick", "--jobs", "2", "--out", "stab"],
                 cwd=work, timeout=600)
    assert study.returncode == 0, study.stderr
    assert (work / "stab" / "README.md").is_file()


def test_the_listing_ships_with_the_package(installed):
    """Job decks carrying the program's source are compared with the listing: the installed
    package holds it (the checkout's file, through a link in the package's folder)."""
    exe, work = installed
    python = exe.parent / "python"
    code = ("import importlib.resources as r; "
            "print(r.files('deck_emulator.legacy').joinpath('luminaire.f').read_text(), end='')")
    proc = _run([str(python), "-c", code], cwd=work)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == (ROOT / "legacy" / "luminaire.f").read_text()


def test_the_corrections_and_errata_ship_with_the_package(installed):
    """The record and the patches a stopped run's message points to, from outside the
    checkout: the command lists them and shows one in full."""
    exe, work = installed
    listed = _run([str(exe), "corrections"], cwd=work)
    assert listed.returncode == 0, listed.stderr
    assert "ed-direction" in listed.stdout and "DIRC1X" in listed.stdout
    shown = _run([str(exe), "corrections", "ed-direction"], cwd=work)
    assert shown.returncode == 0, shown.stderr
    assert "+    1 DH=D-H" in shown.stdout
    whole = _run([str(exe), "corrections", "--all"], cwd=work)
    assert whole.stdout.startswith((ROOT / "legacy" / "CORRECTIONS.md").read_text())


def test_the_listing_and_the_banner_on_the_pages_installed(installed):
    """run --pages --listing from outside the checkout: the listing is the package's."""
    exe, work = installed
    proc = _run([str(exe), "run", "steel40", "--pages", "l.pdf", "--listing", "--json"],
                cwd=work)
    assert proc.returncode == 0, proc.stderr
    facts = json.loads(proc.stdout)["provenance"]
    assert facts["deck file"] == "steel40, shipped with the tool"
    data = (work / "l.pdf").read_bytes()
    assert data.startswith(b"%PDF") and b"/FontFile2" in data
