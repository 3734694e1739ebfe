"""The crash test of Chapter V as a core scene, and Tables 9 and 10 regenerated.

The scene (:func:`crash_scene`) is built from ``assemblies/crash_test.toml``: a planar
post (delta = 0, every point at ``YY = 0``), no luminaire arm, a car of 2,800 lb at
40 ft/s with the hysteretic leaf spring at S (:mod:`deck_emulator.core.leaf_spring`), the
break-away base's normal force at Q and no base friction ("friction negligible").  It runs
under the ``PHYSICAL`` options: none of the listing's quirks (no start-up kick, no
``0.8*FSA``, no ``FCONST``), since the report's crash-test model replaced the listing's
spring by the leaf spring's curves.

Angles: theta is the rotation of the post about ``+YY`` (the report's Euler angle theta
of a planar motion; the top moves towards ``+XX`` when the car, moving towards ``-XX``,
pushes below the mass centre).  ``V1, V3``: mass-centre velocity along the post's
principal axes 1 and 3 (3 along the post).  ``SV``: distance the car has travelled since
contact (ft, positive).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from deck_emulator.units import G_FT_S2

from deck_emulator.engine import CoreEngine
from deck_emulator.core.assembly import load_assembly
from deck_emulator.core.scene import (
    BreakawayBase,
    CrushSpring,
    Environment,
    LeafSpring,
    Post,
    PostPoint,
    Scene,
    Vehicle,
)

__all__ = ["crash_description", "crash_scene", "state_row", "table10", "table9_state",
           "table9", "G"]

G = G_FT_S2  # the report's gravity (units.py)


def crash_description() -> dict:
    """The ``[crash_test]`` table of the shipped description."""
    _, extra, text = load_assembly("crash_test")
    import tomllib

    return tomllib.loads(text)["crash_test"]


def crash_scene(**changes) -> Scene:
    """The crash-test scene; keyword arguments override the description's values
    (``impact_height_ft=2.0``, ``unloading_knee_ft=...``, ``normal_force_release_ft=0`` for
    no normal force, ``base_on_ground=False`` ...)."""
    d = crash_description()
    spring = dict(d["leaf_spring"])
    for k in list(changes):
        if k in spring:
            spring[k] = changes.pop(k)
    d = {**d, **changes}
    g = d["gravity_ft_s2"]
    m = d["post_weight_lb"] / g
    zc = d["cm_from_base_ft"]
    L = d["post_length_ft"]
    post = Post(
        mass_slug=m,
        inertia_1_slug_ft2=d["transverse_inertia_slug_ft2"],
        inertia_2_slug_ft2=d["transverse_inertia_slug_ft2"],
        inertia_3_slug_ft2=d["axial_inertia_slug_ft2"],
        top=PostPoint(0.0, 0.0, L - zc),
        base=PostPoint(0.0, 0.0, -zc),
        first_impact=PostPoint(0.0, 0.0, d["impact_height_ft"] - zc),
    )
    leaf = LeafSpring(
        loading_stiffness_lb_per_ft=tuple(spring["loading_stiffness_lb_per_ft"]),
        knee_ft=spring["knee_ft"],
        stop_ft=spring["stop_ft"],
        unloading_stiffness_lb_per_ft=tuple(spring["unloading_stiffness_lb_per_ft"]),
        unloading_knee_ft=spring["unloading_knee_ft"],
    )
    vehicle = Vehicle(
        mass_slug=d["vehicle_weight_lb"] / g,
        initial_velocity_ft_s=-abs(d["vehicle_speed_ft_s"]),
        first_spring=CrushSpring(spring["loading_stiffness_lb_per_ft"][0]),
        leaf_spring=leaf,
    )
    release = d["normal_force_release_ft"]
    base = BreakawayBase(normal_force_lb=d["post_weight_lb"] if release > 0 else 0.0,
                         normal_release_ft=release)
    depth = zc if d["base_on_ground"] else zc + 0.5
    return Scene(post=post, environment=Environment(ground_depth_ft=depth, gravity_ft_s2=g),
                 vehicle=vehicle, base=base, name="crash_test")


def state_row(result, t: float) -> dict:
    """theta (deg), theta-dot (rad/s), XCM, ZCM (ft), V1, V3 (ft/s), SV (ft) at ``t``."""
    y = result.trajectory.state(t)
    w, qx, qy, qz = y[6:10]
    theta = 2.0 * math.atan2(qy, w)
    return {
        "time_ms": 1000.0 * t,
        "theta_deg": math.degrees(theta),
        "thetadot_rad_s": float(y[11]),
        "XCM_ft": float(y[0]),
        "ZCM_ft": float(y[2]),
        "V1_ft_s": float(y[3]),
        "V3_ft_s": float(y[5]),
        "SV_ft": float(-y[13]),
        "VV_ft_s": float(y[14]),
    }


#: The crash test's runs: the physical preset at tight tolerances.
def _engine(t_max_s: float) -> CoreEngine:
    return CoreEngine(preset="physical", rtol=1e-10, atol=1e-10, t_max_s=t_max_s, trace=False)


def _result(out):
    """The core's result of an outcome; a run that could not end is an error here."""
    if out.error is not None:
        raise RuntimeError(f"the crash test's run did not end: {out.error}")
    return out.raw


def table10(scene: Scene | None = None, *, t_max_s: float = 0.6):
    """(the run's :class:`~deck_emulator.engine.Outcome`, row at the loss of contact, row at
    70 ms) of a full run of the scene."""
    scene = scene or crash_scene()
    out = _engine(t_max_s).run(scene)
    res = _result(out)
    t_loss = res.vehicle_contact_lost_s
    return out, (state_row(res, t_loss) if t_loss is not None else None), state_row(res, 0.070)


def table9_state(t8: dict, vv_ft_s: float) -> np.ndarray:
    """The core's 15-number state of Table 8's 70 ms column (planar; car at ``vv_ft_s``)."""
    th = math.radians(t8["theta_deg"][0])
    return np.array([
        t8["XCM_ft"][0], 0.0, t8["ZCM_ft"][0],
        t8["V1_ft_s"][0], 0.0, t8["V3_ft_s"][0],
        math.cos(th / 2), 0.0, math.sin(th / 2), 0.0,
        0.0, t8["thetadot_rad_s"][0], 0.0,
        -t8["SV_ft"][0], -abs(vv_ft_s),
    ])


def table9(scene: Scene | None = None, *, vv_ft_s: float, t_end_s: float = 0.273):
    """Free flight from Table 8's 70 ms state to ``t_end_s``: the result (rows at 270 and
    273 ms with :func:`state_row`)."""
    from deck_emulator.studies.report_tables import TABLE8

    scene = scene or crash_scene()
    free_scene = dataclasses.replace(scene, vehicle=dataclasses.replace(
        scene.vehicle, body=None))
    return _result(_engine(t_end_s).run_free_flight(free_scene, table9_state(TABLE8, vv_ft_s),
                                                     0.070))
