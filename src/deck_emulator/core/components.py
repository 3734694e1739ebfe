"""Force components of the contact phase (eq. 3.28-3.31, 3.15).

Each component has ``pack(P)``, writing its numbers into the parameter vector of the
compiled force laws (:func:`~.laws.contact_loads` evaluates them, each only where the
scene's model packed it), and ``events(model, mode)``, the located events it needs.  The
model builds only the components its scene has.
"""

from __future__ import annotations

import math

from deck_emulator.vocabulary.events import EventKind
from deck_emulator.vocabulary.scene import ModelOptions, Scene

from . import laws
from .kinematics import IDX_SV, IDX_VV, EventSpec

__all__ = ["BaseNormalForce", "BaseFriction", "VehicleContact"]


class BaseNormalForce:
    """``FN`` along ``+ZZ`` at Q; released for good at ``XQ - XQ0 <= -release``."""

    def __init__(self, force_lb: float, release_ft: float):
        self.force_lb = force_lb
        self.release_ft = release_ft

    def pack(self, P) -> None:
        P[laws.P_HAS_NORMAL] = 1.0
        P[laws.P_FN] = self.force_lb
        P[laws.P_FN_RELEASE] = self.release_ft

    def events(self, model, mode) -> list[EventSpec]:
        if not mode.normal_on:
            return []
        return [EventSpec("normal force released", -1.0, (laws.EV_BASE_TRAVEL, self.release_ft))]


class BaseFriction:
    """Friction at Q along ``XX`` while ``XQ - XQ0 > -window`` (section 3.3).

    ``reaction=False`` (the listing): a constant ``force_lb`` along ``+XX``.
    ``reaction=True``: Coulomb friction with ``force_lb`` as its limit -- while the base
    slips (``mode.friction_sign`` = the sign of its velocity along ``XX``) the force is
    ``-force_lb * sign``; while it sticks (``mode.friction_stick``) it is the reaction that
    holds it (:mod:`.sliding`).
    """

    def __init__(self, force_lb: float, window_ft: float, reaction: bool = False):
        self.force_lb = force_lb
        self.window_ft = window_ft
        self.reaction = reaction

    def force(self, mode, model) -> float:
        """The friction force along ``+XX`` (lb) in ``mode`` (:func:`~.laws.friction_force`)."""
        return laws.friction_force(model.law_parameters, model.mode_vector(mode))

    def pack(self, P) -> None:
        P[laws.P_HAS_FRICTION] = 1.0
        P[laws.P_FR] = self.force_lb
        P[laws.P_FR_WINDOW] = self.window_ft
        P[laws.P_FR_REACTION] = 1.0 if self.reaction else 0.0

    def events(self, model, mode) -> list[EventSpec]:
        code = (laws.EV_BASE_TRAVEL, self.window_ft)
        if mode.friction_on:
            return [EventSpec("base friction ends", -1.0, code)]
        return [EventSpec("base friction resumes", +1.0, code)]

    def active_at(self, model, y) -> bool:
        return model.base_travel(y) + self.window_ft > 0.0


class VehicleContact:
    """The car's crush springs acting on the post at S, then T (eq. 3.15)."""

    def __init__(self, scene: Scene, options: ModelOptions, model):
        v = scene.vehicle
        self.cos_a, self.sin_a = math.cos(v.approach_angle_rad), math.sin(v.approach_angle_rad)
        self.stiffness = {"S": v.first_spring.stiffness_lb_per_ft}
        if v.second_spring is not None:
            self.stiffness["T"] = v.second_spring.stiffness_lb_per_ft
        self.has_t = "T" in self.stiffness
        self.sv_contact = v.contact_position_ft
        self.factor = options.spring_factor
        self.absolute = options.spring_absolute
        self.switch_ft = options.spring_switch_ft
        self.cap_lb = v.force_cap_lb if options.force_cap_from_s is not None else None
        self.listing_diff = options.listing_diff
        # XVSO, XVTO: the points' initial XV coordinates
        self.xv0 = {k: model.initial_xv(k) for k in self.stiffness}

    # -- geometry of the contact (eq. 3.13-3.15)

    def _xv(self, kin, letter):
        x, y_, _ = kin.point(letter)
        return x * self.cos_a - y_ * self.sin_a

    def compression(self, kin, letter) -> float:
        """``(SVO - SV) - (XVO - XV)`` of point S or T (ft); positive: crushed."""
        return laws.compression(self.sv_contact, kin.y[IDX_SV], self.xv0[letter],
                                self._xv(kin, letter))

    def diff(self, kin, letter) -> float:
        """The listing's ``DIFF`` (S) or ``DIFFT`` (T): ``|XV - XVO| - |SV - SVO|``."""
        return laws.listing_diff(self.sv_contact, kin.y[IDX_SV], self.xv0[letter],
                                 self._xv(kin, letter))

    def separation(self, kin, letter) -> float:
        """Crosses zero upwards when the point leaves the car: ``DIFF`` under the listing's
        quirks, ``-compression`` otherwise (the same while both move towards ``-XV``)."""
        return self.diff(kin, letter) if self.listing_diff else -self.compression(kin, letter)

    def diff_rate(self, kin) -> float:
        """``d DIFF/dt`` of point S (ft/s): the cap's ``DIFF >= DIFFB`` test."""
        vx, vy, _ = kin.point_velocity("S")
        dxv = self._xv(kin, "S") - self.xv0["S"]
        dsv = kin.y[IDX_SV] - self.sv_contact
        return laws.diff_rate(dxv, dsv, vx * self.cos_a - vy * self.sin_a, kin.y[IDX_VV])

    def pack(self, P) -> None:
        P[laws.P_HAS_CONTACT] = 1.0
        P[laws.P_K_S] = self.stiffness["S"]
        P[laws.P_K_T] = self.stiffness.get("T", 0.0)
        P[laws.P_HAS_T] = 1.0 if self.has_t else 0.0
        P[laws.P_SV_CONTACT] = self.sv_contact
        P[laws.P_XV0_S] = self.xv0["S"]
        P[laws.P_XV0_T] = self.xv0.get("T", 0.0)
        P[laws.P_FACTOR] = self.factor
        P[laws.P_ABSOLUTE] = 1.0 if self.absolute else 0.0
        P[laws.P_CAP] = math.nan if self.cap_lb is None else self.cap_lb
        P[laws.P_LISTING_DIFF] = 1.0 if self.listing_diff else 0.0
        P[laws.P_SWITCH] = self.switch_ft

    # -- events

    def events(self, model, mode) -> list[EventSpec]:
        out = []
        if not mode.first_spring_lost:
            out.append(EventSpec(EventKind.LOST_FIRST_SPRING, +1.0,
                                 (laws.EV_SEPARATION, float(laws.LETTERS.index("S")))))
        if self.has_t and mode.contact_point == "S" and self.switch_ft > 0.0:
            out.append(EventSpec("spring force moves to T", +1.0,
                                 (laws.EV_DIFF_S, self.switch_ft)))
        if self.has_t and mode.first_spring_lost:
            out.append(EventSpec(EventKind.LOST_VEHICLE, +1.0,
                                 (laws.EV_SEPARATION, float(laws.LETTERS.index("T")))))
        if mode.cap_armed and self.cap_lb is not None:
            code = (laws.EV_DIFF_RATE, 0.0)
            if mode.cap_engaged:
                out.append(EventSpec("force cap released", -1.0, code))
            else:
                out.append(EventSpec(EventKind.FORCE_CAP, +1.0, code))
        return out
