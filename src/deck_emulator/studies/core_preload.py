"""Imported once, after :mod:`.worker_preload`, in the process the embedded runner forks the
workers of a run of core scenes from: the compiled core's machine code (numba's, from its
cache) and the studies that run core scenes, loaded here once so that every worker shares
their pages instead of loading its own copy (docs/scale.md).  A core that cannot load here (no numba, a limit of the machine) is left to each
worker, which then says why in its scenes' rows."""

from __future__ import annotations

import contextlib
import gc

with contextlib.suppress(Exception):
    from deck_emulator.engine import load_core

    load_core()
    # the batch functions the workers run
    import deck_emulator.studies.sensitivity
    import deck_emulator.studies.sweep  # noqa: F401

gc.collect()
gc.freeze()
