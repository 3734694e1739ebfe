"""Sliding modes of the contact phase (Filippov) and the solid ground.

Two forces of the contact phase switch on a surface of the state and can hold the state on
it -- a sliding mode, where an event-per-switch integration chatters:

* the ``FCONST`` cap (``ModelOptions.cap_sliding``), on while ``DIFF`` does not decrease:
  under the cap the post falls behind, under the uncapped spring it runs ahead, so on the
  surface ``dDIFF/dt = 0`` the spring force is the one that keeps it there, between the cap
  and the uncapped force; the mode ends (a located event) when that force reaches a bound,
  the cap staying engaged at the lower one and released at the upper.
* Coulomb friction at the base (``ModelOptions.friction_reaction``): on ``v_Q = 0`` along
  ``XX`` the friction is the reaction that keeps the base still, up to the friction limit;
  the base slips once the reaction needed reaches the limit and sticks again when its
  velocity returns to zero with a reaction within the limit.

Both forces act linearly on the derivative, so the force that holds a surface follows from
the derivatives at its two bounds (Filippov's convex combination; a 2 x 2 system with both
modes); a mode is entered only where it attracts.  The solid ground
(``ModelOptions.solid_ground``): events that end the run with a ground hit when a post point
reaches the ground while the car still pushes.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from deck_emulator.vocabulary.events import EventKind
from . import laws
from .kinematics import IDX_VV, ContactMode, EventSpec, Kinematics

__all__ = [
    "Filippov",
    "contact_events",
    "after_event",
    "initial_mode",
    "friction_force",
    "mode_labels",
]

#: a mode is entered only if its force is this far (as a fraction of the bound interval)
#: inside its bounds: at the bound itself its exit event would fire at once
_INSIDE = 1e-9


def _sliders(mode: ContactMode) -> list[str]:
    """The sliding surfaces ``mode`` holds, the cap's first: "cap" (``dDIFF/dt = 0`` of point
    S) and "stick" (the base's ``v_Q = 0`` along ``XX``)."""
    out = []
    if mode.cap_sliding:
        out.append("cap")
    if mode.friction_on and mode.friction_stick:
        out.append("stick")
    return out


class Filippov:
    """The sliding forces of ``mode`` at a state: ``solve(t, y)`` -> dict with ``d`` (the
    state derivative), ``lam`` (unclamped position of each force between its bounds, 0 at
    the lower, 1 at the upper), ``force``, ``bounds``, ``diag`` (d sigma_dot / d lam: > 0
    where the mode attracts)."""

    def __init__(self, model, mode: ContactMode):
        self.model = model
        self.mode = mode
        self.sliders = _sliders(mode)

    def solve(self, t, y):
        m, n = self.model, len(self.sliders)
        d = np.empty(15)
        lam, force, lo, hi, diag = (np.empty(2) for _ in range(5))
        laws.filippov(t, np.asarray(y, dtype=float), m.law_parameters,
                      m.mode_vector(self.mode), d, lam, force, lo, hi, diag)
        return {
            "d": d.tolist(),
            "lam": lam[:n].tolist(),
            "force": force[:n].tolist(),
            "bounds": list(zip(lo[:n].tolist(), hi[:n].tolist())),
            "diag": diag[:n].tolist(),
            "sliders": self.sliders,
        }

    def admissible(self, t, y) -> bool:
        """The mode attracts and its forces lie strictly inside their bounds."""
        if not self.sliders:
            return False
        r = self.solve(t, y)
        for (a, b), lam, diag in zip(r["bounds"], r["lam"], r["diag"]):
            if not (b > a and diag > 0.0 and _INSIDE < lam < 1.0 - _INSIDE):
                return False
        return True


def vehicle_force(model, t, y, mode) -> float:
    """Force on the car along ``+XV`` (lb) in ``mode``, the cap's sliding force while it
    holds (:func:`~.laws.sliding_vehicle_force`)."""
    return laws.sliding_vehicle_force(t, np.ascontiguousarray(y, dtype=float),
                                      model.law_parameters, model.mode_vector(mode))


def friction_force(model, t, y, mode) -> float:
    """The base friction along ``+XX`` (lb) in ``mode`` (0 without friction)."""
    comp = model.components.get("base friction")
    if comp is None or not mode.friction_on or mode.window == "kick":
        return 0.0
    if mode.friction_stick:
        r = Filippov(model, mode).solve(t, y)
        return r["force"][r["sliders"].index("stick")]
    return comp.force(mode, model)


def contact_events(model, mode: ContactMode) -> list[EventSpec]:
    """The model's contact events for ``mode``, with the sliding modes' and the ground's,
    each evaluated by the compiled laws' :func:`~.laws.contact_event` (both roads)."""
    out = model.contact_events(mode)
    if mode.cap_sliding:
        out = [e for e in out if e.name not in (EventKind.FORCE_CAP, "force cap released")]
    for i, s in enumerate(_sliders(mode)):
        out.append(EventSpec(f"{s} sliding ends at lower bound", -1.0, (laws.EV_LAM, float(i))))
        out.append(EventSpec(f"{s} sliding ends at upper bound", +1.0,
                             (laws.EV_LAM_UPPER, float(i))))
        if s == "cap":
            out.append(EventSpec("cap sliding ends: cap not binding", -1.0,
                                 (laws.EV_SPAN, float(i))))
    comp = model.components.get("base friction")
    if comp is not None and comp.reaction and mode.friction_on and not mode.friction_stick:
        out.append(EventSpec("base stops sliding", -1.0,
                             (laws.EV_BASE_VELOCITY, mode.friction_sign)))
    if model.options.solid_ground:  # the points the free flight checks against the ground
        out.extend(EventSpec(f"ground reached by {p}", +1.0,
                             (laws.EV_GROUND, float(laws.LETTERS.index(p))))
                   for p in model.checks.points)
    P, M = model.law_parameters, model.mode_vector(mode)
    for e in out:
        e.function = lambda t, y, c=e.code: laws.contact_event(c[0], c[1], t, y, P, M)
    return out


def _friction_state(model, mode: ContactMode, t, y) -> ContactMode:
    """Stick or slip (and which way) for a base with friction at state ``y``."""
    comp = model.components.get("base friction")
    if comp is None or not comp.reaction or not mode.friction_on or mode.window == "kick":
        return replace(mode, friction_stick=False, friction_sign=0.0)
    kin = Kinematics(model, y)
    v = kin.point_velocity("Q")[0]
    scale = 1e-9 * max(1.0, abs(kin.y[IDX_VV]))
    if abs(v) > scale:
        return replace(mode, friction_stick=False, friction_sign=math.copysign(1.0, v))
    trial = replace(mode, friction_stick=True, friction_sign=0.0)
    if comp.force_lb > 0.0 and Filippov(model, trial).admissible(t, y):
        return trial
    # it slips: which way?  the base's acceleration with the friction at its limit against
    plus = replace(mode, friction_stick=False, friction_sign=+1.0)
    d, ya = np.empty(15), np.asarray(kin.y, dtype=float)
    laws.plain_derivative(t, ya, model.law_parameters, model.mode_vector(plus), np.empty(7), d)
    if laws.point_acceleration(ya, kin.R, d, *model.body_points["Q"])[0] > 0.0:
        return plus
    return replace(mode, friction_stick=False, friction_sign=-1.0)


def _cap_state(model, mode: ContactMode, t, y) -> ContactMode:
    """Enter the cap's sliding mode if it attracts at ``y``; else ``mode`` as it is."""
    contact = model.components.get("vehicle contact")
    if (
        contact is None
        or contact.cap_lb is None
        or not mode.cap_armed
        or not model.options.cap_sliding
    ):
        return mode
    trial = replace(mode, cap_sliding=True, cap_engaged=True)
    if mode.contact_point == "S" and Filippov(model, trial).admissible(t, y):
        return trial
    return mode


def initial_mode(model) -> ContactMode:
    mode = model.initial_mode()
    return _friction_state(model, mode, 0.0, list(model.y0))


def after_event(model, mode: ContactMode, name: str, t, y) -> tuple[ContactMode, bool, str]:
    """The mode after event ``name`` at ``(t, y)``: (mode, car has left, hit point or "")."""
    if name.startswith("ground reached by "):
        return mode, True, name.rsplit(" ", 1)[-1]
    if name == "cap sliding ends at lower bound":
        return replace(mode, cap_sliding=False, cap_engaged=True), False, ""
    if name in ("cap sliding ends at upper bound", "cap sliding ends: cap not binding"):
        return replace(mode, cap_sliding=False, cap_engaged=False), False, ""
    if name == "stick sliding ends at lower bound":  # friction at -limit: the base slips +XX
        return replace(mode, friction_stick=False, friction_sign=+1.0), False, ""
    if name == "stick sliding ends at upper bound":
        return replace(mode, friction_stick=False, friction_sign=-1.0), False, ""
    if name == "base stops sliding":
        return _friction_state(model, replace(mode, friction_sign=0.0), t, y), False, ""
    old = mode
    mode, ended = model.transition(mode, name, y)
    if name in (EventKind.FORCE_CAP, "force cap released"):
        mode = _cap_state(model, mode, t, y)
    elif old.cap_sliding and mode.contact_point != old.contact_point or (
        old.cap_sliding and name == EventKind.LOST_FIRST_SPRING
    ):
        contact = model.components["vehicle contact"]
        mode = replace(
            mode, cap_sliding=False, cap_engaged=contact.diff_rate(Kinematics(model, y)) >= 0.0
        )
    if name in ("base friction ends", "base friction resumes"):
        mode = _friction_state(model, mode, t, y)
    return _still_sliding(model, mode, t, y), ended, ""


def _still_sliding(model, mode: ContactMode, t, y) -> ContactMode:
    """Leave a sliding mode whose force an event has put outside its bounds (another
    force changed at the event: its exit event could not see the jump)."""
    if not (mode.cap_sliding or (mode.friction_on and mode.friction_stick)):
        return mode
    r = Filippov(model, mode).solve(t, y)
    for name, lam, (lo, hi) in zip(r["sliders"], r["lam"], r["bounds"]):
        if name == "cap" and (lam <= 0.0 or not hi > lo):
            mode = replace(mode, cap_sliding=False, cap_engaged=lam <= 0.0)
        elif name == "cap" and lam >= 1.0:
            mode = replace(mode, cap_sliding=False, cap_engaged=False)
        elif name == "stick" and lam <= 0.0:
            mode = replace(mode, friction_stick=False, friction_sign=+1.0)
        elif name == "stick" and lam >= 1.0:
            mode = replace(mode, friction_stick=False, friction_sign=-1.0)
    return mode


def mode_at_time(model, mode: ContactMode, t, y) -> ContactMode:
    """:meth:`Model.mode_at_time` with the friction's stick/slip state refreshed."""
    new = model.mode_at_time(mode, t, y)
    if new.window != mode.window:
        new = _friction_state(model, new, t, y)
    return _still_sliding(model, new, t, y)


def mode_labels(mode: ContactMode) -> set[str]:
    """The named sliding modes ``mode`` is in ("cap holding", "base sticking")."""
    out = set()
    if mode.cap_sliding:
        out.add("cap holding")
    if mode.friction_on and mode.friction_stick:
        out.add("base sticking")
    return out
