"""Imported once, after :mod:`.worker_preload`, by the forkserver of a run of core scenes: the
compiled core and the studies that run it, for every worker to share (docs/scale.md).  A core
that cannot load here is left to each worker, which says why in its scenes' rows."""

import contextlib
import gc

with contextlib.suppress(Exception):
    from deck_emulator.engine import load_core

    load_core()
    import deck_emulator.studies.sensitivity
    import deck_emulator.studies.sweep  # noqa: F401

gc.collect()
gc.freeze()
