"""The one interface a run is read through, whichever engine made it: an
:class:`~deck_emulator.engine.outcome.Outcome`'s ``trajectory``.

* :class:`Sampled` -- a run known at its samples (the emulator's accepted steps, an outcome
  built by hand from arrays), linear between two of them;
* :class:`Dense` -- the core's dense solution, at any instant.

Both answer the same questions (:class:`Trajectory`), so that the outcome and the registry of
quantities (:mod:`.quantities`, :mod:`.energy`, :mod:`.leaf_spring`) never ask which engine
ran, and never reach the engine's own result.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Protocol

import numpy as np

from deck_emulator.vocabulary.events import TRACED_POINTS

__all__ = ["Trajectory", "PostState", "Sampled", "Dense", "readonly", "INSTANTS",
           "SAMPLED_POINTS"]

#: the post's named points an outcome samples (beside its mass centre ``CM``), in this order:
#: the vocabulary's one row of them
SAMPLED_POINTS = TRACED_POINTS

#: the instants a run gives the post's motion at, for the energy (:mod:`.energy`):
#: ``launch`` -- the car lets go (the last contact step); ``free_start``, ``free_end`` --
#: the first and last instants of the free flight.
INSTANTS = ("launch", "free_start", "free_end")


def readonly(a, dtype=None) -> np.ndarray:
    """``a`` as an array no one can write through: an array that owns its memory is locked in
    place (no copy), any other (a view, a list) is copied first."""
    a = np.asarray(a, dtype=dtype)
    if a.flags.writeable:
        if a.base is not None:
            a = a.copy()
        a.flags.writeable = False
    return a


@dataclass(frozen=True)
class PostState:
    """The post's motion at one instant: what its energy is made of."""

    velocity_body_ft_s: tuple[float, float, float]
    rates_body_rad_s: tuple[float, float, float]
    mass_centre_zz_ft: float


class Trajectory(Protocol):
    """What every engine's run answers (road axes XX, YY, ZZ; ft, s): its points' names and
    span; ``position`` of a point (``CM``: the mass centre) at ``t``, (3,) or (3, n);
    ``point_near``, the point as the run gives it at ``t`` (None outside it, or no such
    point); ``car_velocity``, VV along XV (None outside the run); ``peak_car_force``, the
    largest force on the car (lb) over the contact (after the start-up steps), None where the
    run gives no force; ``motion`` and
    ``solver_steps``, a dense solution's only (else ValueError); ``post_state``, the post's
    motion at one of :data:`INSTANTS` (None: none); ``leaf_spring_unloading``, (time,
    compression ft) where the car's leaf spring begins to unload (None: none)."""

    point_names: tuple[str, ...]
    span: tuple[float, float]
    integrator: str | None

    def position(self, name: str, t) -> np.ndarray: ...
    def point_near(self, name: str, t: float) -> np.ndarray | None: ...
    def car_velocity(self, t: float) -> float | None: ...
    def peak_car_force(self, after_startup: bool) -> float | None: ...
    def motion(self, t: float) -> dict: ...
    def solver_steps(self) -> int: ...
    def post_state(self, instant: str) -> PostState | None: ...
    def leaf_spring_unloading(self) -> tuple[float, float] | None: ...


class Sampled:
    """A run known at its samples ``t`` (the emulator's accepted steps): the points
    ``points`` (name -> (n, 3)) and the car's velocity ``vv``, linear between two samples (the
    emulator's step VVA = VVB + (H/WV)*FSB is linear in time; its events fall on steps);
    ``states``: the post's motion at the :data:`INSTANTS` the run has; ``peak_forces_lb``:
    the largest force on the car after the start-up steps and over every step (None: not
    given)."""

    integrator = None

    def __init__(self, t, points: Mapping, vv, states: Mapping[str, PostState] | None = None,
                 *, peak_forces_lb: tuple[float | None, float | None] = (None, None)):
        self._t, self._vv = readonly(t, float), readonly(vv, float)
        self._peak_forces_lb = peak_forces_lb
        self._points = MappingProxyType({k: readonly(v, float) for k, v in points.items()})
        self._states = MappingProxyType(dict(states or {}))
        self.point_names = tuple(k for k in self._points if k != "CM")
        self.span = (float(self._t[0]), float(self._t[-1])) if self._t.size else (0.0, 0.0)

    def position(self, name: str, t) -> np.ndarray:
        xyz = self._points[name]
        return np.array([np.interp(t, self._t, xyz[:, i]) for i in range(3)])

    def point_near(self, name: str, t: float):
        if name not in self._points or not self._t.size or t > self._t[-1]:
            return None
        return self._points[name][int(np.argmin(np.abs(self._t - t)))]

    def car_velocity(self, t: float) -> float | None:
        if not self._t.size or not self._t[0] <= t <= self._t[-1]:
            return None
        return float(np.interp(t, self._t, self._vv))

    def peak_car_force(self, after_startup: bool) -> float | None:
        return self._peak_forces_lb[0 if after_startup else 1]

    def motion(self, t: float) -> dict:
        raise ValueError("the motion between steps is the core's dense solution")

    def solver_steps(self) -> int:
        raise ValueError("the integration steps are the core's solution's")

    def post_state(self, instant: str) -> PostState | None:
        return self._states.get(instant)

    def leaf_spring_unloading(self):
        return None


class Dense:
    """The core's dense solution (a :class:`~deck_emulator.core.CoreResult`'s trajectory)."""

    def __init__(self, result):
        self._result, self._traj = result, result.trajectory
        self.point_names = tuple(self._traj.point_names)
        self.span = (float(self._traj.t_start), float(self._traj.t_end))
        #: who integrated it ("scipy", "compiled", "compiled+scipy")
        self.integrator = result.integrator

    def position(self, name: str, t) -> np.ndarray:
        return self._traj.mass_centre(t) if name == "CM" else self._traj.point(name, t)

    def point_near(self, name: str, t: float):
        if name not in self.point_names or not self.span[0] <= t <= self.span[1]:
            return None
        return self._traj.point(name, t)

    def car_velocity(self, t: float) -> float | None:
        return float(self._traj.vehicle(t)[1])

    def peak_car_force(self, after_startup: bool) -> float | None:
        """None until the contact has ended (the car let go, or the post hit it while in
        contact): a run stopped in contact has no largest force."""
        if self._result.contact_end_s is None:
            return None
        force = self._traj.peak_force(after_startup)
        if force is None and after_startup:  # no contact after the start-up steps
            force = self._traj.peak_force(False)
        return force

    def motion(self, t: float) -> dict:
        traj = self._traj
        y = traj.state(t)
        return {"mass_centre_ft": y[0:3], "velocity_body_ft_s": y[3:6],
                "attitude_wxyz": y[6:10], "angular_velocity_body_rad_s": y[10:13],
                "car_position_ft": y[13], "car_velocity_ft_s": y[14]}

    def solver_steps(self) -> int:
        return sum(len(s.solution.ts) - 1 for s in self._traj.segments
                   if getattr(s.solution, "ts", None) is not None)

    def post_state(self, instant: str) -> PostState | None:
        t0 = self._result.vehicle_contact_lost_s
        if t0 is None:
            return None
        t = t0
        if instant == "free_end":
            t = min(self._result.end_time_s, self._traj.t_end)
            if not t > t0:
                return None
        y = self._traj.state(t)
        return PostState(tuple(float(v) for v in y[3:6]), tuple(float(w) for w in y[10:13]),
                         float(y[2]))

    def leaf_spring_unloading(self):
        from deck_emulator.vocabulary.events import EventKind

        r = self._result
        t = next((e.time_s for e in r.events if e.name == EventKind.LEAF_UNLOADS), None)
        if t is None or r.scene.vehicle is None or r.scene.vehicle.leaf_spring is None:
            return None
        from deck_emulator.core.kinematics import Kinematics
        from deck_emulator.core.model import assemble

        model = assemble(r.scene, r.options)
        x = model.components["vehicle contact"].compression(
            Kinematics(model, list(self._traj.state(t))), "S")
        return t, float(x)
