"""deck_emulator: the 1967 TTI luminaire-support impact program, emulated card for card,
beside a modern rigid-body solution of the same model."""

import os as _os
import sys as _sys

#: in the environment of the worker processes a command's embedded Dask cluster spawns (set
#: by deck_emulator.studies.distributed only while it spawns them)
SPAWNED_WORKER_ENV = "DECK_EMULATOR_SPAWNED_WORKER"

if _os.environ.get(SPAWNED_WORKER_ENV) and "multiprocessing.spawn" in _sys.modules:
    # A worker process of a command's embedded Dask cluster, spawned: it imports this package
    # (its parent's main module) before Dask, a second or so before Dask's preload
    # (deck_emulator.studies.worker_preload) makes it ignore SIGINT.  A terminal's Ctrl-C
    # goes to the whole process group; the command handles it and closes its workers, so a
    # worker ignores it from here on rather than print a KeyboardInterrupt traceback of its
    # own.
    import signal as _signal

    _signal.signal(_signal.SIGINT, _signal.SIG_IGN)


def __getattr__(name: str):
    # The version is written once, in pyproject.toml; this reads the installed metadata, and
    # only when asked (importlib.metadata costs ~50 ms of every command's start-up).
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            return version("deck_emulator")
        except PackageNotFoundError:
            return "0+unknown (not installed)"
    if name == "run":  # deck_emulator.run(source, engine=...): engine.api.run
        from deck_emulator.engine.api import run

        return run
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
