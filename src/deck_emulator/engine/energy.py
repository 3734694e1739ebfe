"""The post's energy in a run: what the stability study reads to tell a sound solution from a
drifting one (the quantities ``launch_ke_ftlb`` and ``free_flight_energy_drift`` of
:mod:`.quantities`).

* ``launch_ke_ftlb``: translational plus rotational kinetic energy of the post when the car
  lets go (ft lb);
* ``free_drift``: ``(E_end - E_start) / E_start`` over the free flight, ``E`` kinetic plus
  ``W G (ZZ + HEIGHT)`` (the height above the ground).

Both read the post's motion at the run's own instants (``Outcome.trajectory.post_state``:
the emulator's accepted steps, the core's located events), the same formula for both engines.
"""

from __future__ import annotations

import math


def energies(outcome) -> dict:
    """``{"launch_ke_ftlb", "free_drift"}`` of an outcome (NaN where its run has none: no run,
    no free flight, a run that never left the car, a free flight that starts with no energy)."""
    traj, scene = outcome.trajectory, outcome.scene
    out = {"launch_ke_ftlb": math.nan, "free_drift": math.nan}
    if scene is None:
        return out
    mass, inertia = scene.post.mass_slug, scene.post.principal_inertia_slug_ft2
    g, depth = scene.environment.gravity_ft_s2, scene.environment.ground_depth_ft

    def energy(s, potential=True):
        v, w = s.velocity_body_ft_s, s.rates_body_rad_s
        ke = 0.5 * mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + 0.5 * (
            inertia[0] * w[0] * w[0] + inertia[1] * w[1] * w[1] + inertia[2] * w[2] * w[2])
        return ke + (mass * g * (s.mass_centre_zz_ft + depth) if potential else 0.0)

    launch = traj.post_state("launch")
    start, end = traj.post_state("free_start"), traj.post_state("free_end")
    if launch is not None:
        out["launch_ke_ftlb"] = energy(launch, potential=False)
    if start is not None and end is not None:
        e0 = energy(start)
        out["free_drift"] = (energy(end) - e0) / e0 if e0 else math.nan
    return out
