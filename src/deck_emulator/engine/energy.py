"""The post's energy in an engine's run: what the stability study reads to tell a sound
solution from a drifting one (the quantities ``launch_ke_ftlb`` and
``free_flight_energy_drift`` of :mod:`.quantities`).

* ``launch_ke_ftlb``: translational plus rotational kinetic energy of the post when the car
  lets go (ft lb);
* ``free_drift``: ``(E_end - E_start) / E_start`` over the free flight, ``E`` kinetic plus
  ``W G (ZZ + HEIGHT)`` (the height above the ground).

The emulator's run gives them at its accepted steps (its trace carries the body velocities
``V1, V2, V3`` and rates ``W1, W2, W3`` of every step); the core's at its located events.
"""

from __future__ import annotations

import math

__all__ = ["energies"]

_NONE = {"launch_ke_ftlb": math.nan, "free_drift": math.nan}


def energies(outcome) -> dict:
    """``{"launch_ke_ftlb", "free_drift"}`` of an outcome (NaN where its run has none: no run,
    no free flight, a run that never left the car, a free flight that starts with no energy).
    A trace without a field the energy reads, or a solution that cannot be read where its
    run says it has one, is a defect, not a missing value: it raises, with the run named."""
    if outcome.raw is None:
        return dict(_NONE)
    try:
        if outcome.engine == "emulator":
            return _emulator(outcome.raw, outcome.scene)
        return _core(outcome.raw)
    except (KeyError, ValueError) as exc:
        raise ValueError(f"the post's energy in the {outcome.engine}'s run of "
                         f"{outcome.name!r} cannot be computed: {type(exc).__name__}: "
                         f"{exc}") from exc


def _emulator(run, scene) -> dict:
    mass, inertia = scene.post.mass_slug, scene.post.principal_inertia_slug_ft2
    g, depth = scene.environment.gravity_ft_s2, scene.environment.ground_depth_ft

    def energy(row, potential=True):
        ke = 0.5 * mass * (row["V1"] ** 2 + row["V2"] ** 2 + row["V3"] ** 2) + 0.5 * (
            inertia[0] * row["W1"] ** 2 + inertia[1] * row["W2"] ** 2 + inertia[2] * row["W3"] ** 2)
        return ke + (mass * g * (row["ZZCM"] + depth) if potential else 0.0)

    contact = [r for r in run.trace if r["phase"] == "contact"]
    free = [r for r in run.trace if r["phase"] != "contact"]
    out = dict(_NONE)
    if contact and free:
        out["launch_ke_ftlb"] = energy(contact[-1], potential=False)
    if len(free) >= 2:
        e0, e1 = energy(free[0]), energy(free[-1])
        out["free_drift"] = (e1 - e0) / e0 if e0 else math.nan
    return out


def _core(result) -> dict:
    from deck_emulator.core import kinetic_energy

    out = dict(_NONE)
    t0 = result.vehicle_contact_lost_s
    if t0 is None:
        return out
    post = result.scene.post
    mass, inertia = post.mass_slug, post.principal_inertia_slug_ft2
    g, depth = result.scene.environment.gravity_ft_s2, result.scene.environment.ground_depth_ft
    traj = result.trajectory
    t1 = min(result.end_time_s, traj.t_end)

    def energy(t, potential=True):
        y = traj.state(t)
        ke = float(kinetic_energy(y[:13], mass, inertia))
        return ke + (mass * g * float(y[2] + depth) if potential else 0.0)

    out["launch_ke_ftlb"] = energy(t0, potential=False)
    if t1 > t0:
        e0 = energy(t0)
        out["free_drift"] = (energy(t1) - e0) / e0 if e0 else math.nan
    return out
