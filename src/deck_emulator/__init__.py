"""deck_emulator: the 1967 TTI luminaire-support impact program, emulated card for card,
beside a modern rigid-body solution of the same model."""

#: in the environment of a worker process of a command's embedded scene runner (set by
#: deck_emulator.studies.local_pool as the worker starts, and only there)
SPAWNED_WORKER_ENV = "DECK_EMULATOR_SPAWNED_WORKER"


def __getattr__(name: str):
    # The version is written once, in pyproject.toml; this reads the installed metadata, and
    # only when asked (a command that does not ask does not import importlib.metadata).
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
