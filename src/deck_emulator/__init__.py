"""deck_emulator: the 1967 TTI luminaire-support impact program, emulated card for card,
beside a modern rigid-body solution of the same model."""


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
