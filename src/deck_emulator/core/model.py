"""The model of one scene, assembled from the components the scene has.

:func:`assemble` turns a :class:`~deck_emulator.vocabulary.scene.Scene` and
:class:`~deck_emulator.vocabulary.scene.ModelOptions` into a :class:`Model`: the post's named points
(only those the scene has), the force components of the contact phase (only those the
scene has: the base's normal force, the base friction, the car's crush springs), and the
free-flight checks (:mod:`.regions`).  A component the scene lacks is not built, so nothing
of it is ever evaluated; the tests prove it.

Contact-phase forces (eq. 3.28-3.31, computed as road-axes vectors, ``torque = r x F``):

* gravity ``-W*G`` along ``ZZ`` at the mass centre;
* base normal force ``FN`` along ``+ZZ`` at Q until the base has moved the release
  distance along ``-XX`` (a latch, as the listing's ``FNA=0.0``);
* base friction along ``+XX`` at Q while the base is inside its slip window;
* the crush spring ``FS`` (eq. 3.15) at S, later at T, along ``(-cos alpha, sin alpha, 0)``;
  the car feels ``+FS`` along ``XV`` (``VV' = FS/WV``: the listing's
  ``VVA=VVB+(H/WV)*FSB``; the printed eq. 3.18 has the opposite sign).

Eq. 3.30's ``TXO`` (the initial equilibrium torque) is not in the listing and not here.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from deck_emulator.vocabulary.events import EventKind
from deck_emulator.vocabulary.scene import (
    LISTING_BASE_FRICTION,
    LISTING_FRICTION_WINDOW_FT,
    ModelOptions,
    Scene,
)

from . import laws
from .components import BaseFriction, BaseNormalForce, VehicleContact
from .kinematics import ContactMode, EventSpec, Kinematics
from .leaf_spring import LeafSpringContact
from .regions import FreeFlightChecks, build_checks
from .rigid import quat_about_axis, quat_multiply
from .segments import SegmentChecks, build_segment_checks

__all__ = ["Model", "assemble"]


# --------------------------------------------------------------------------------------
# the model


class Model:
    """A scene's equations, assembled from the components it has.

    Attributes: ``body_points`` (letter -> principal-axes coordinates, ft; only the
    points the scene has), ``components`` (force components of the contact phase,
    by name), ``checks`` (:class:`~.regions.FreeFlightChecks`), ``segment_checks``
    (:class:`~.segments.SegmentChecks` or None).
    """

    def __init__(self, scene: Scene, options: ModelOptions):
        self.scene = scene
        self.options = options
        post = scene.post
        delta = post.principal_tilt_rad
        self.mass = post.mass_slug
        self.inertia = post.principal_inertia_slug_ft2
        self.gravity = scene.environment.gravity_ft_s2
        self.weight = self.mass * self.gravity
        self.body_points = {k: p.principal_coordinates(delta) for k, p in post.points().items()}
        # body -> road at t = 0: the tilt about XX, then the scene's initial attitude
        self.q_tilt = quat_about_axis((1.0, 0.0, 0.0), delta)
        vehicle = scene.vehicle
        self.vehicle_mass = vehicle.mass_slug if vehicle is not None else 1.0
        if vehicle is not None:
            a = vehicle.approach_angle_rad
            self.cos_a, self.sin_a = math.cos(a), math.sin(a)
        else:
            self.cos_a, self.sin_a = 1.0, 0.0

        self.y0 = self.initial_state()
        self._q0 = self.point_position(Kinematics(self, self.y0), "Q")

        comps: dict[str, object] = {}
        base = scene.base
        if vehicle is not None and base is not None:
            if base.normal_force_lb != 0.0:
                comps["base normal force"] = BaseNormalForce(
                    base.normal_force_lb, base.normal_release_ft
                )
            if options.listing_friction:
                comps["base friction"] = BaseFriction(
                    LISTING_BASE_FRICTION.force_lb, LISTING_FRICTION_WINDOW_FT
                )
            elif base.friction is not None:
                comps["base friction"] = BaseFriction(
                    base.friction.force_lb,
                    base.friction.slip_window_ft,
                    reaction=options.friction_reaction,
                )
        if vehicle is not None and getattr(vehicle, "leaf_spring", None) is not None:

            comps["vehicle contact"] = LeafSpringContact(scene, options, self)
        elif vehicle is not None:
            comps["vehicle contact"] = VehicleContact(scene, options, self)
        self.components = comps
        self.checks: FreeFlightChecks = build_checks(scene, options, self)
        #: the shaft and arms against the car (``ModelOptions.shaft_contact``), or None
        self.segment_checks: SegmentChecks | None = build_segment_checks(scene, options, self)
        #: the compiled laws' parameter vector (:mod:`.laws`)
        self.law_parameters = self._pack()
        self._modes: dict[ContactMode, np.ndarray] = {}

    def _pack(self) -> np.ndarray:
        P = np.zeros(laws.N_P)
        P[laws.P_MASS] = self.mass
        P[laws.P_I1], P[laws.P_I2], P[laws.P_I3] = self.inertia
        P[laws.P_WV] = self.vehicle_mass
        P[laws.P_COS], P[laws.P_SIN] = self.cos_a, self.sin_a
        for k, letter in enumerate(laws.LETTERS):
            if letter in self.body_points:
                j = laws.P_POINTS + 3 * k
                P[j : j + 3] = self.body_points[letter]
        P[laws.P_CAP] = math.nan
        P[laws.P_Q0X] = self._q0[0]
        P[laws.P_DEPTH] = self.scene.environment.ground_depth_ft
        P[laws.P_WEIGHT] = self.weight
        for c in self.components.values():
            c.pack(P)
        kick = self.options.startup_kick
        if kick is not None and self.scene.vehicle is not None:
            # the listing's first step: in the 'kick' window the post feels only
            # body_force_1_lb along body axis 1, the car vehicle_force_lb
            P[laws.P_HAS_KICK] = 1.0
            P[laws.P_KICK_F1] = kick.body_force_1_lb
            P[laws.P_KICK_FV] = kick.vehicle_force_lb
            P[laws.P_KICK_FS] = kick.first_step_spring_force_lb
        return P

    def mode_vector(self, mode: ContactMode) -> np.ndarray:
        """The compiled laws' mode vector of ``mode`` (:mod:`.laws`; kept per mode)."""
        M = self._modes.get(mode)
        if M is None:
            M = np.full(laws.N_M, math.nan)
            M[laws.M_POINT] = laws.AT_S if mode.contact_point == "S" else laws.AT_T
            M[laws.M_NORMAL_ON] = float(mode.normal_on)
            M[laws.M_FRICTION_ON] = float(mode.friction_on)
            M[laws.M_CAP_ENGAGED] = float(mode.cap_engaged)
            M[laws.M_WINDOW] = {None: laws.WINDOW_NONE, "kick": laws.WINDOW_KICK,
                                "first_step": laws.WINDOW_FIRST_STEP}[mode.window]
            M[laws.M_FRICTION_STICK] = float(mode.friction_stick)
            M[laws.M_FRICTION_SIGN] = mode.friction_sign
            M[laws.M_CAP_SLIDING] = float(mode.cap_sliding)
            if mode.spring_peak_ft is not None:
                M[laws.M_LEAF_PEAK] = mode.spring_peak_ft
            M.setflags(write=False)
            self._modes[mode] = M
        return M

    # -- geometry

    def point_position(self, kin: Kinematics, letter: str):
        """Road-axes position of point ``letter`` (every point look-up goes through here)."""
        bx, by, bz = self.body_points[letter]
        y = kin.y
        return laws.point_position(y[0], y[1], y[2], kin.R, bx, by, bz)

    def initial_xv(self, letter: str) -> float:
        x, y, _ = self.point_position(Kinematics(self, self.y0), letter)
        return x * self.cos_a - y * self.sin_a

    def base_travel(self, y) -> float:
        """``XQ - XQ0``: the base's travel along ``XX`` (ft; the listing tests ``XQA``,
        the same when ``XQO = 0``)."""
        return self.point_position(Kinematics(self, y), "Q")[0] - self._q0[0]

    def initial_state(self) -> list[float]:
        ini = self.scene.initial
        q = quat_multiply(self.q_tilt, ini.attitude_wxyz)
        w = list(ini.angular_velocity_body_rad_s)
        kick = self.options.startup_kick if self.scene.vehicle is not None else None
        if kick is not None:
            # the listing's THA=0.000022 at the end of the first step, W2A=0.0545 throughout
            extra = kick.tilt_at_step_rad - kick.pitch_rate_rad_s * kick.step_s
            q = quat_multiply(q, quat_about_axis((0.0, 1.0, 0.0), extra))
            w = [0.0, kick.pitch_rate_rad_s, 0.0]
        vehicle = self.scene.vehicle
        sv = vehicle.initial_position_ft if vehicle is not None else 0.0
        vv = vehicle.initial_velocity_ft_s if vehicle is not None else 0.0
        return [*ini.mass_centre_ft, *ini.velocity_body_ft_s, *q, *w, sv, vv]

    # -- contact phase

    def initial_mode(self) -> ContactMode:
        y0 = self.y0
        friction = self.components.get("base friction")
        return ContactMode(
            normal_on="base normal force" in self.components,
            friction_on=friction is not None and friction.active_at(self, y0),
            window=self.window_at(0.0),
        )

    def window_at(self, t: float) -> str | None:
        kick = self.options.startup_kick
        if kick is None or self.scene.vehicle is None:
            return None
        if t < kick.step_s:
            return "kick"
        if t < 2 * kick.step_s:
            return "first_step"
        return None

    def schedule(self) -> list[float]:
        """Times at which the contact mode changes by the clock (kick windows, cap)."""
        times = []
        kick = self.options.startup_kick
        if kick is not None and self.scene.vehicle is not None:
            times += [kick.step_s, 2 * kick.step_s]
        contact = self.components.get("vehicle contact")
        if contact is not None and contact.cap_lb is not None:
            times.append(self.options.force_cap_from_s)
        return sorted(set(times))

    def mode_at_time(self, mode: ContactMode, t: float, y) -> ContactMode:
        """The mode after a scheduled time ``t`` has been reached."""
        mode = replace(mode, window=self.window_at(t))
        contact = self.components.get("vehicle contact")
        cap_from = self.options.force_cap_from_s
        if (
            contact is not None
            and contact.cap_lb is not None
            and not mode.cap_armed
            and t >= cap_from
        ):
            engaged = contact.diff_rate(Kinematics(self, y)) >= 0.0
            mode = replace(mode, cap_armed=True, cap_engaged=engaged)
        return mode

    def contact_rhs(self, mode: ContactMode):
        P = self.law_parameters
        derivative = laws.contact_derivative
        M = self.mode_vector(mode)
        fun = lambda t, y: derivative(t, y, P, M)  # noqa: E731
        fun.law = ("contact", M)  # the batch's compiled integrator runs the same law
        return fun

    def vehicle_forces(self, ts, ys, mode: ContactMode):
        """:meth:`vehicle_force` at times ``ts`` and states ``ys`` (15, n), in one call."""
        return laws.vehicle_forces(np.asarray(ts, dtype=float), ys, self.law_parameters,
                                   self.mode_vector(mode))

    def contact_events(self, mode: ContactMode) -> list[EventSpec]:
        out = []
        for c in self.components.values():
            out.extend(c.events(self, mode))
        return out

    def transition(self, mode: ContactMode, name: str, y) -> tuple[ContactMode, bool]:
        """The mode after event ``name``; second item: the car has left the post."""
        contact = self.components.get("vehicle contact")
        own = getattr(contact, "transition", None)
        if own is not None and name in getattr(contact, "EVENT_NAMES", ()):
            return own(self, mode, name, y)
        if name == EventKind.LOST_FIRST_SPRING:
            mode = replace(mode, first_spring_lost=True)
            if contact is None or not contact.has_t:
                return mode, True
            if contact.switch_ft == 0.0:
                mode = replace(mode, contact_point="T")
            # T may already be clear of the car: then contact ends now
            if contact.separation(Kinematics(self, y), "T") >= 0.0:
                return mode, True
            return mode, False
        if name == "spring force moves to T":
            return replace(mode, contact_point="T"), False
        if name == EventKind.LOST_VEHICLE:
            return mode, True
        if name == "normal force released":
            return replace(mode, normal_on=False), False
        if name == "base friction ends":
            return replace(mode, friction_on=False), False
        if name == "base friction resumes":
            return replace(mode, friction_on=True), False
        if name == EventKind.FORCE_CAP:
            return replace(mode, cap_engaged=True), False
        if name == "force cap released":
            return replace(mode, cap_engaged=False), False
        raise ValueError(f"unknown contact event {name!r}")

    # -- free flight

    def free_rhs(self):
        P = self.law_parameters
        derivative = laws.free_derivative
        fun = lambda t, y: derivative(t, y, P)  # noqa: E731
        fun.law = ("free flight", None)
        return fun


def assemble(scene: Scene, options: ModelOptions) -> Model:
    """The model of ``scene`` under ``options`` (only the components the scene has)."""
    return Model(scene, options)
