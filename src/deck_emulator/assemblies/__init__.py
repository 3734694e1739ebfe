"""Description files (TOML) of the report's support assemblies and of the Chapter V crash
test, shipped with the package.  Build, print or run them with
``deck-emulator assembly NAME`` or :func:`deck_emulator.core.assembly.load_assembly`."""
