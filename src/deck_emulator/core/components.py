"""Force components of the contact phase (eq. 3.28-3.31, 3.15).

Each component has ``apply(t, kin, mode, acc)``, adding its force and torque about the
mass centre (road axes) and its force on the car into ``acc`` = (Fx, Fy, Fz, Tx, Ty, Tz,
F_vehicle), and ``events(model, mode)``, the located events it needs.  The model builds
only the components its scene has.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .scene import LISTING_BASE_FRICTION, LISTING_FRICTION_WINDOW_FT, ModelOptions, Scene
from .kinematics import IDX_SV, IDX_VV, EventSpec, Kinematics
from .rigid import rotate

if TYPE_CHECKING:
    from .model import Model

__all__ = [
    "Gravity",
    "BaseNormalForce",
    "BaseFriction",
    "StartupKickLoad",
    "VehicleContact",
    "LISTING_FRICTION_LB",
    "LISTING_FRICTION_WINDOW_FT",
]

#: ``FFXA=3.1*T`` with ``T=300.0``
#: the listing's friction force and the window it acts in (one home: the scene module)
LISTING_FRICTION_LB = LISTING_BASE_FRICTION.force_lb


def _add_force(acc, force, arm) -> None:
    fx, fy, fz = force
    ax, ay, az = arm
    acc[0] += fx
    acc[1] += fy
    acc[2] += fz
    acc[3] += ay * fz - az * fy
    acc[4] += az * fx - ax * fz
    acc[5] += ax * fy - ay * fx


class Gravity:
    name = "gravity"

    def __init__(self, weight_lb: float):
        self.weight_lb = weight_lb

    def apply(self, t, kin, mode, acc) -> None:
        acc[2] -= self.weight_lb

    def events(self, model, mode) -> list[EventSpec]:
        return []


class BaseNormalForce:
    """``FN`` along ``+ZZ`` at Q; released for good at ``XQ - XQ0 <= -release``."""

    name = "base normal force"

    def __init__(self, force_lb: float, release_ft: float):
        self.force_lb = force_lb
        self.release_ft = release_ft

    def apply(self, t, kin, mode, acc) -> None:
        if mode.normal_on:
            _add_force(acc, (0.0, 0.0, self.force_lb), kin.arm("Q"))

    def events(self, model, mode) -> list[EventSpec]:
        if not mode.normal_on:
            return []
        return [
            EventSpec(
                "normal force released", lambda t, y: model.base_travel(y) + self.release_ft, -1.0
            )
        ]


class BaseFriction:
    """Friction at Q along ``XX`` while ``XQ - XQ0 > -window`` (section 3.3).

    ``reaction=False`` (the listing): a constant ``force_lb`` along ``+XX``.
    ``reaction=True``: Coulomb friction with ``force_lb`` as its limit -- while the base
    slips (``mode.friction_sign`` = the sign of its velocity along ``XX``) the force is
    ``-force_lb * sign``; while it sticks (``mode.friction_stick``) it is the reaction that
    holds it, set by :mod:`.sliding` through ``override``.
    """

    name = "base friction"

    def __init__(self, force_lb: float, window_ft: float, reaction: bool = False):
        self.force_lb = force_lb
        self.window_ft = window_ft
        self.reaction = reaction
        self.override: float | None = None

    def force(self, mode) -> float:
        """The friction force along ``+XX`` (lb) in ``mode``."""
        if not mode.friction_on:
            return 0.0
        if self.override is not None:
            return self.override
        if not self.reaction:
            return self.force_lb
        if mode.friction_stick:  # pragma: no cover - the stick force always comes as override
            return 0.0
        return -self.force_lb * mode.friction_sign

    def apply(self, t, kin, mode, acc) -> None:
        if mode.friction_on:
            f = self.force(mode)
            if f != 0.0:
                _add_force(acc, (f, 0.0, 0.0), kin.arm("Q"))

    def events(self, model, mode) -> list[EventSpec]:
        f = lambda t, y: model.base_travel(y) + self.window_ft  # noqa: E731
        if mode.friction_on:
            return [EventSpec("base friction ends", f, -1.0)]
        return [EventSpec("base friction resumes", f, +1.0)]

    def active_at(self, model, y) -> bool:
        return model.base_travel(y) + self.window_ft > 0.0


class StartupKickLoad:
    """The listing's first step (:class:`~deck_emulator.core.scene.StartupKick`): during the
    'kick' window the post feels only ``body_force_1_lb`` along body axis 1, the car
    ``vehicle_force_lb``."""

    name = "start-up kick"

    def __init__(self, kick):
        self.kick = kick

    def apply(self, t, kin, mode, acc) -> None:
        f = rotate(kin.R, (self.kick.body_force_1_lb, 0.0, 0.0))
        acc[0] += f[0]
        acc[1] += f[1]
        acc[2] += f[2]
        acc[6] += self.kick.vehicle_force_lb

    def events(self, model, mode) -> list[EventSpec]:
        return []


class VehicleContact:
    """The car's crush springs acting on the post at S, then T (eq. 3.15)."""

    name = "vehicle contact"

    def __init__(self, scene: Scene, options: ModelOptions, model: "Model"):
        v = scene.vehicle
        self.alpha = v.approach_angle_rad
        self.cos_a, self.sin_a = math.cos(self.alpha), math.sin(self.alpha)
        self.direction = (-self.cos_a, self.sin_a, 0.0)
        self.stiffness = {"S": v.first_spring.stiffness_lb_per_ft}
        if v.second_spring is not None:
            self.stiffness["T"] = v.second_spring.stiffness_lb_per_ft
        self.has_t = "T" in self.stiffness
        self.sv_contact = v.contact_position_ft
        self.factor = options.spring_factor
        self.absolute = options.spring_absolute
        self.switch_ft = options.spring_switch_ft
        self.cap_lb = v.force_cap_lb if options.force_cap_from_s is not None else None
        self.kick = options.startup_kick
        self.listing_diff = options.listing_diff
        # XVSO, XVTO: the points' initial XV coordinates
        self.xv0 = {k: model.initial_xv(k) for k in self.stiffness}
        # the spring force set by :mod:`.sliding` while the cap's switching surface is held
        self.override: float | None = None

    # -- geometry of the contact (eq. 3.13-3.15)

    def _xv(self, kin, letter):
        x, y_, _ = kin.point(letter)
        return x * self.cos_a - y_ * self.sin_a

    def compression(self, kin, letter) -> float:
        """``(SVO - SV) - (XVO - XV)`` of point S or T (ft); positive: crushed."""
        return (self.sv_contact - kin.y[IDX_SV]) - (self.xv0[letter] - self._xv(kin, letter))

    def diff(self, kin, letter) -> float:
        """The listing's ``DIFF`` (S) or ``DIFFT`` (T): ``|XV - XVO| - |SV - SVO|``."""
        return abs(self._xv(kin, letter) - self.xv0[letter]) - abs(kin.y[IDX_SV] - self.sv_contact)

    def separation(self, kin, letter) -> float:
        """Crosses zero upwards when the point leaves the car: ``DIFF`` under the listing's
        quirks, ``-compression`` otherwise (the same while both move towards ``-XV``)."""
        return self.diff(kin, letter) if self.listing_diff else -self.compression(kin, letter)

    def diff_rate(self, kin) -> float:
        """``d DIFF/dt`` of point S (ft/s): the cap's ``DIFF >= DIFFB`` test."""
        vx, vy, _ = kin.point_velocity("S")
        dxv = self._xv(kin, "S") - self.xv0["S"]
        dsv = kin.y[IDX_SV] - self.sv_contact
        return (
            math.copysign(1.0, dxv) * (vx * self.cos_a - vy * self.sin_a)
            - math.copysign(1.0, dsv) * kin.y[IDX_VV]
        )

    def spring_force(self, kin, mode) -> float:
        """``FS`` (lb) in this mode."""
        if mode.window == "first_step":
            return self.kick.first_step_spring_force_lb
        if self.override is not None:
            return self.override
        letter = mode.contact_point
        kx = self.stiffness[letter] * self.compression(kin, letter)
        fs = abs(kx) if self.absolute else max(0.0, kx)
        fs *= self.factor
        if mode.cap_engaged and self.cap_lb is not None and fs > self.cap_lb:
            fs = self.cap_lb
        return fs

    def apply(self, t, kin, mode, acc) -> None:
        fs = self.spring_force(kin, mode)
        if fs != 0.0:
            d = self.direction
            _add_force(acc, (fs * d[0], fs * d[1], 0.0), kin.arm(mode.contact_point))
        acc[6] += fs

    # -- events

    def events(self, model, mode) -> list[EventSpec]:
        out = []
        if not mode.first_spring_lost:
            out.append(
                EventSpec(
                    "first spring lost",
                    lambda t, y: self.separation(Kinematics(model, y), "S"),
                    +1.0,
                )
            )
        if self.has_t and mode.contact_point == "S" and self.switch_ft > 0.0:
            out.append(
                EventSpec(
                    "spring force moves to T",
                    lambda t, y: self.diff(Kinematics(model, y), "S") - self.switch_ft,
                    +1.0,
                )
            )
        if self.has_t and mode.first_spring_lost:
            out.append(
                EventSpec(
                    "vehicle contact lost",
                    lambda t, y: self.separation(Kinematics(model, y), "T"),
                    +1.0,
                )
            )
        if mode.cap_armed and self.cap_lb is not None:
            f = lambda t, y: self.diff_rate(Kinematics(model, y))  # noqa: E731
            if mode.cap_engaged:
                out.append(EventSpec("force cap released", f, -1.0))
            else:
                out.append(EventSpec("force cap engaged", f, +1.0))
        return out
