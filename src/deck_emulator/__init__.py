"""deck_emulator: the 1967 TTI luminaire-support impact program, emulated card for card,
beside a modern rigid-body solution of the same model."""

__version__ = "0.1.0"
