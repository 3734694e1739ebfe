"""The crash test's leaf spring in a core run: how far it was crushed when it began to unload,
and the set it keeps (the compression at which its unloading force reaches zero): the
registry's ``leaf_spring_peak_compression_ft`` and ``leaf_spring_set_ft``."""

from __future__ import annotations

import math

from deck_emulator.vocabulary.events import EventKind

__all__ = ["at_unloading"]


def at_unloading(outcome) -> dict:
    """``{"time_s", "compression_ft", "set_ft"}`` at the core's "leaf spring unloads" event
    (NaN for a run without one: the emulator's, a scene without a leaf spring)."""
    none = {"time_s": math.nan, "compression_ft": math.nan, "set_ft": math.nan}
    result = outcome.raw
    if outcome.engine != "core" or result is None:
        return none
    t = next((e.time_s for e in result.events if e.name == EventKind.LEAF_UNLOADS), None)
    leaf = result.scene.vehicle.leaf_spring if result.scene.vehicle else None
    if t is None or leaf is None:
        return none
    from deck_emulator.core.kinematics import Kinematics
    from deck_emulator.core.leaf_spring import zero_force_set
    from deck_emulator.core.model import assemble

    model = assemble(result.scene, result.options)
    x = model.components["vehicle contact"].compression(
        Kinematics(model, list(result.trajectory.state(t))), "S")
    return {"time_s": t, "compression_ft": float(x), "set_ft": float(zero_force_set(x, leaf))}
