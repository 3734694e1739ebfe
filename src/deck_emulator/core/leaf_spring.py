"""The crash test's hysteretic leaf spring (Chapter V) as a contact component.

Force law (compression ``x`` in ft, force in lb; :class:`~.scene.LeafSpring` holds the
numbers).  Loading curve ``F_L(x)``: ``k1 x`` up to the knee (3.0 in), then
``F_L(knee) + k2 (x - knee)`` up to the stop (4.5 in), then constant ``F_L(stop)`` -- the
report's "constant spring force ... after the displacement of the spring exceeded 4.5 in.
... kept present until ... the spring started to unload".  Unloading from the largest
compression reached, ``x_m`` with ``F_m = F_L(x_m)``: ``F_m - u1 (x_m - x)`` down to the
unloading knee, then ``F_k - u2 (knee - x)``, never below zero; the force is zero once
``x`` is below the set ``x0``.  (The report gives the two unloading stiffnesses, 38,400
and 12,000 lb/ft, not where one gives way to the other: Figure 17 did not survive.  The
knee at 3.0 in, where the second set of leaves disengages, is this project's assumption.)
Re-loading below ``x_m`` retraces the unloading line, then continues on ``F_L``.  With
``u2 = k1`` a spring loaded no further than the knee is elastic.

The history ``x_m`` is a discrete state of the contact mode (``ContactMode.spring_peak_ft``,
``None`` while loading), changed only at located events: "leaf spring unloads" (the
compression rate crosses zero downwards), "leaf spring reloads" (the compression comes back
to ``x_m``), "first spring lost" (the compression falls to ``x0``: contact ends).  So the
force is a function of the state within each segment and the integration stays smooth.
"""

from __future__ import annotations

import math
from dataclasses import replace

from deck_emulator.vocabulary.events import EventKind
from . import laws

from .components import VehicleContact
from .kinematics import EventSpec, Kinematics
from deck_emulator.vocabulary.scene import LeafSpring

__all__ = ["loading_force", "unloading_force", "leaf_force", "zero_force_set", "loop_area",
           "LeafSpringContact"]


def _numbers(s: LeafSpring):
    k1, k2 = s.loading_stiffness_lb_per_ft
    u1, u2 = s.unloading_stiffness_lb_per_ft
    return k1, k2, s.knee_ft, s.stop_ft, u1, u2, s.unloading_knee_ft


def loading_force(x: float, s: LeafSpring) -> float:
    k1, k2, knee, stop, _, _, _ = _numbers(s)
    return laws.leaf_loading_force(x, k1, k2, knee, stop)


def _knee_force(x_m: float, s: LeafSpring) -> tuple[float, float]:
    """(knee compression, force there) on the unloading line from ``x_m``."""
    k1, k2, knee, stop, u1, _, uknee = _numbers(s)
    return laws.leaf_knee_force(x_m, k1, k2, knee, stop, u1, uknee)


def unloading_force(x: float, x_m: float, s: LeafSpring) -> float:
    return laws.leaf_unloading_force(x, x_m, *_numbers(s))


def leaf_force(x: float, x_peak: float | None, s: LeafSpring) -> float:
    """Spring force at compression ``x`` given the peak so far (``None``: loading)."""
    return laws.leaf_force(x, math.nan if x_peak is None else x_peak, *_numbers(s))


def zero_force_set(x_m: float, s: LeafSpring) -> float:
    """``x0``: the compression at which the unloading force from ``x_m`` reaches zero."""
    u1, u2 = s.unloading_stiffness_lb_per_ft
    xk, fk = _knee_force(x_m, s)
    if fk <= 0.0:
        return x_m - loading_force(x_m, s) / u1
    return xk - fk / u2


def loop_area(x_m: float, s: LeafSpring) -> float:
    """Energy (ft lb) a load to ``x_m`` and unload to zero force dissipates, in closed form:
    area under the loading curve (triangle, trapezoid, rectangle) minus the area under the
    unloading curve (trapezoid and triangle)."""
    k1, k2 = s.loading_stiffness_lb_per_ft
    u1, u2 = s.unloading_stiffness_lb_per_ft
    a = min(x_m, s.knee_ft)
    load = 0.5 * k1 * a * a
    if x_m > s.knee_ft:
        b = min(x_m, s.stop_ft) - s.knee_ft
        load += k1 * s.knee_ft * b + 0.5 * k2 * b * b
    if x_m > s.stop_ft:
        load += loading_force(s.stop_ft, s) * (x_m - s.stop_ft)
    fm = loading_force(x_m, s)
    xk, fk = _knee_force(x_m, s)
    if fk <= 0.0:
        unload = 0.5 * fm * fm / u1
    else:
        unload = 0.5 * (fm + fk) * (x_m - xk) + 0.5 * fk * fk / u2
    return load - unload


class LeafSpringContact(VehicleContact):
    """The car's leaf spring at S (in place of the linear crush spring)."""

    EVENT_NAMES = (EventKind.LEAF_UNLOADS, "leaf spring reloads", EventKind.LOST_FIRST_SPRING)

    def __init__(self, scene, options, model):
        super().__init__(scene, options, model)
        self.leaf = scene.vehicle.leaf_spring
        self.has_t = False
        self.cap_lb = None

    def pack(self, P) -> None:
        super().pack(P)
        P[laws.P_HAS_LEAF] = 1.0
        (P[laws.P_LEAF_K1], P[laws.P_LEAF_K2], P[laws.P_LEAF_KNEE], P[laws.P_LEAF_STOP],
         P[laws.P_LEAF_U1], P[laws.P_LEAF_U2], P[laws.P_LEAF_UKNEE]) = _numbers(self.leaf)

    def events(self, model, mode) -> list[EventSpec]:
        if mode.spring_peak_ft is None:
            return [EventSpec(EventKind.LEAF_UNLOADS, -1.0, (laws.EV_COMPRESSION_RATE, 0.0))]
        x_m = mode.spring_peak_ft
        x0 = zero_force_set(x_m, self.leaf)
        return [EventSpec("leaf spring reloads", +1.0, (laws.EV_COMPRESSION, x_m)),
                EventSpec(EventKind.LOST_FIRST_SPRING, -1.0, (laws.EV_COMPRESSION, x0))]

    def transition(self, model, mode, name, y):
        if name == EventKind.LEAF_UNLOADS:
            x = self.compression(Kinematics(model, y), "S")
            return replace(mode, spring_peak_ft=x), False
        if name == "leaf spring reloads":
            return replace(mode, spring_peak_ft=None), False
        return replace(mode, first_spring_lost=True), True
