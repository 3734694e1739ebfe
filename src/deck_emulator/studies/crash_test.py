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

from deck_emulator.engine import CoreEngine, quantities
from deck_emulator.engine.assemblies import AssemblyError, load_assembly
from deck_emulator.studies.report_tables import TABLE8, TABLE8_TIMES_S, TABLE9
from deck_emulator.vocabulary.scene import (
    BreakawayBase,
    CrushSpring,
    Environment,
    LeafSpring,
    Post,
    PostInitialState,
    PostPoint,
    Scene,
    Vehicle,
)



def crash_description(name_or_path: str = "crash_test") -> dict:
    """The checked ``[crash_test]`` table of a crash-test description: the shipped one by
    default, or a user's file (``.toml``); :class:`~deck_emulator.core.assembly.AssemblyError`
    when the file is not a crash-test description or a value is out of its domain."""

    asm, extra, _ = load_assembly(name_or_path)
    if asm is not None:
        raise AssemblyError(f"{name_or_path}: a support assembly, not a crash-test description")
    return extra["crash_test"]


def crash_scene(description: dict | None = None, **changes) -> Scene:
    """The crash-test scene of ``description`` (a checked ``[crash_test]`` table, as
    :func:`crash_description` or ``load_assembly(...)[1]["crash_test"]`` gives; the shipped
    one when ``None``); keyword arguments override its values (``impact_height_ft=2.0``,
    ``unloading_knee_ft=...``, ``normal_force_release_ft=0`` for no normal force,
    ``base_on_ground=False`` ...)."""
    d = crash_description() if description is None else description
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


def state_row(out, t: float) -> dict:
    """theta (deg), theta-dot (rad/s), XCM, ZCM (ft), V1, V3 (ft/s), SV (ft), VV (ft/s) at
    ``t`` of a core outcome's motion."""
    m = out.motion(t)
    w, _, qy, _ = m["attitude_wxyz"]
    x, _, z = m["mass_centre_ft"]
    v1, _, v3 = m["velocity_body_ft_s"]
    sv, vv = m["car_position_ft"], m["car_velocity_ft_s"]
    return {
        "time_ms": 1000.0 * t,
        "theta_deg": math.degrees(2.0 * math.atan2(qy, w)),
        "thetadot_rad_s": float(m["angular_velocity_body_rad_s"][1]),
        "XCM_ft": float(x),
        "ZCM_ft": float(z),
        "V1_ft_s": float(v1),
        "V3_ft_s": float(v3),
        "SV_ft": float(-sv),
        "VV_ft_s": float(vv),
    }


#: The crash test's runs: the physical preset at the core's tolerances.
def _engine(t_max_s: float) -> CoreEngine:
    return CoreEngine(preset="physical", t_max_s=t_max_s, trace=False)


def _result(out):
    """An outcome that ran; a run that could not end is an error here."""
    if out.error is not None:
        raise RuntimeError(f"the crash test's run did not end: {out.error}")
    return out


def table10(scene: Scene | None = None, *, t_max_s: float = 0.6):
    """(the run's :class:`~deck_emulator.engine.Outcome`, row at the loss of contact, row at
    70 ms) of a full run of the scene."""
    out = _result(_engine(t_max_s).run(scene or crash_scene()))
    t_loss = out.vehicle_contact_lost_s
    return out, (state_row(out, t_loss) if t_loss is not None else None), state_row(out, TABLE8_TIMES_S[0])


def table9_start(t8: dict) -> PostInitialState:
    """The post's motion in Table 8's 70 ms column (planar: theta about YY)."""
    th = math.radians(t8["theta_deg"][0])
    return PostInitialState(
        mass_centre_ft=(t8["XCM_ft"][0], 0.0, t8["ZCM_ft"][0]),
        velocity_body_ft_s=(t8["V1_ft_s"][0], 0.0, t8["V3_ft_s"][0]),
        attitude_wxyz=(math.cos(th / 2), 0.0, math.sin(th / 2), 0.0),
        angular_velocity_body_rad_s=(0.0, t8["thetadot_rad_s"][0], 0.0),
    )


def table9(scene: Scene | None = None, *, vv_ft_s: float,
           t_end_s: float = TABLE9["time_ms"][0] / 1000):
    """Free flight from Table 8's 70 ms state to ``t_end_s``: the result (rows at 270 and
    273 ms with :func:`state_row`)."""

    scene = scene or crash_scene()
    free_scene = dataclasses.replace(scene, vehicle=dataclasses.replace(
        scene.vehicle, body=None))
    return _result(_engine(t_end_s).run_free_flight(
        free_scene, table9_start(TABLE8), TABLE8_TIMES_S[0], car_position_ft=-TABLE8["SV_ft"][0],
        car_velocity_ft_s=-abs(vv_ft_s)))


#: Figure 18 draws the post every this many seconds, up to :data:`FIGURE_END_S`.
FIGURE_STEP_S, FIGURE_END_S = 0.02, 0.29


def crash_run(task: dict) -> dict:
    """Worker of the scene runner: one crash-test scene (``task["changes"]``: the keywords of
    :func:`crash_scene`) as plain values: the rows of Table 10 at the loss of contact, 70 ms
    and 270 ms, the hit time, the events, the leaf spring's peak compression and set (the
    registry's), the ground's depth and Figure 18's post Q-P (``figure``: rows t, XX and ZZ of
    Q, XX and ZZ of P); with ``task["free_flight"]`` also Table 9's free flights from Table 8's
    state (``table9``: rows at 270 and 273 ms with the car at our 70 ms speed; ``table9_40``:
    at 270 ms with the car at 40 ft/s)."""

    scene = crash_scene(**task["changes"])
    out, loss, r70 = table10(scene)
    t270 = TABLE8_TIMES_S[1]
    t_stop = out.span[1]
    t_end = min(t_stop, FIGURE_END_S)
    figure = []
    for t in sorted(set(np.arange(0.0, t_end + 1e-9, FIGURE_STEP_S).round(6)) | set(TABLE8_TIMES_S)):
        if t <= t_stop:
            q, p = out.position("Q", t), out.position("P", t)
            figure.append([float(t), float(q[0]), float(q[2]), float(p[0]), float(p[2])])
    row = {"loss": loss, "at_70": r70,
           "at_270": state_row(out, t270) if t_stop >= t270 else None,
           "hit_time_s": out.hit_time_s,
           "vehicle_contact_lost_s": out.vehicle_contact_lost_s,
           "events": [list(e) for e in out.engine_events],
           "leaf_spring_peak_compression_ft": quantities.value("leaf_spring_peak_compression_ft",
                                                               out),
           "leaf_spring_set_ft": quantities.value("leaf_spring_set_ft", out),
           "ground_depth_ft": scene.environment.ground_depth_ft,
           "figure": figure}
    if task.get("free_flight"):
        f9 = table9(scene, vv_ft_s=abs(r70["VV_ft_s"]))
        f40 = table9(scene, vv_ft_s=40.0)
        row["table9"] = {"at_270": state_row(f9, t270),
                         "at_273": state_row(f9, TABLE9["time_ms"][0] / 1000)}
        row["table9_40"] = {"at_270": state_row(f40, t270)}
    return row
