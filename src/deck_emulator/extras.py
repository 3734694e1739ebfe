"""What each optional part of the install brings, one row a package: the module a command
imports -> the extra of ``pyproject.toml`` that installs it (a test holds the two equal).

The base install is the 1967 path (numpy, fortranformat, tqdm, tomli-w, and fonttools for
the printed pages' face).  A command that needs more and finds it missing says, in one
line, which extra to install (:func:`missing_extra`; the command line exits with status
2)."""

from __future__ import annotations

import importlib.util

#: module (its top-level name) -> the extra that installs it
EXTRA_OF_MODULE = {
    "scipy": "core",
    "numba": "core",
    "llvmlite": "core",
    "matplotlib": "plot",
    "pandas": "frames",
    "pyarrow": "frames",
    "dask": "studies",
    "distributed": "studies",
    "SALib": "studies",
    "pypdf": "pdf",
    "threadpoolctl": "studies",
}

#: what each extra is for, in the words of the message
PURPOSE = {
    "core": "the modern core",
    "plot": "pictures",
    "frames": "trajectories as tables",
    "studies": "the many-scene studies",
    "pdf": "reading a PDF's text",
}


def missing_extra(exc: ImportError) -> str | None:
    """The one-line message for an import that failed because an extra is not installed
    (None: not one of the extras' modules, or one that is installed and failed to import --
    a defect to be reported as it stands, not a missing extra)."""
    name = (getattr(exc, "name", None) or "").split(".")[0]
    extra = EXTRA_OF_MODULE.get(name)
    if extra is None or importlib.util.find_spec(name) is not None:
        return None
    return (f"{PURPOSE[extra]} needs {name}, which this install has not got: "
            f"pip install 'deck_emulator[{extra}]' (or [all])")


def require(extra: str) -> None:
    """Before any work: ``ModuleNotFoundError`` naming the first of ``extra``'s modules that
    is not installed (looked up, not imported)."""

    for module, of in EXTRA_OF_MODULE.items():
        if of == extra and importlib.util.find_spec(module) is None:
            raise ModuleNotFoundError(f"No module named {module!r}", name=module)
