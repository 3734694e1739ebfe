"""The crash test's leaf spring in a run: how far it was crushed when it began to unload, and
the set it keeps (the compression at which its unloading force reaches zero): the registry's
``leaf_spring_peak_compression_ft`` and ``leaf_spring_set_ft``."""

from __future__ import annotations

import math


def at_unloading(outcome) -> dict:
    """``{"time_s", "compression_ft", "set_ft"}`` where the run's leaf spring begins to unload
    (``Outcome.trajectory.leaf_spring_unloading``; NaN for a run without one: the emulator's,
    a scene without a leaf spring)."""
    got = outcome.trajectory.leaf_spring_unloading()
    car = outcome.scene.vehicle if outcome.scene is not None else None
    leaf = car.leaf_spring if car is not None else None
    if got is None or leaf is None:
        return {"time_s": math.nan, "compression_ft": math.nan, "set_ft": math.nan}
    from deck_emulator.core.leaf_spring import zero_force_set

    t, x = got
    return {"time_s": t, "compression_ft": x, "set_ft": float(zero_force_set(x, leaf))}
