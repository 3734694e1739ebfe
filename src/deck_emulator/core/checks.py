"""Plausibility checks of an outcome before it is reported.

:func:`check_outcome` checks a core run (:class:`~.result.CoreResult`; ``simulate(...,
check=True)`` raises :class:`~.solve.CoreError` naming the first failure);
:func:`check_summary` makes the same checks on plain numbers, for any program's outcome (the
emulator's flags).  The checks: every number is finite; no post point is below the ground at
a hit by more than the hit test's tolerance; the car's speed change lies between 0 and its
speed; a run without a hit names its reason.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from deck_emulator.vocabulary.defaults import LISTING_GROUND_TOLERANCE_FT
from deck_emulator.vocabulary.units import ft_s_to_mph, speed_lost_mph

__all__ = [
    "check_outcome",
    "check_summary",
    "ground_tolerance_ft",
    "EXACT_GROUND_TOLERANCE_FT",
    "DELTA_V_TOLERANCE_MPH",
]

#: below-ground depth allowed at a hit located on the exact ground plane (ft): the event
#: is located to a few units in the last place of t, far inside this
EXACT_GROUND_TOLERANCE_FT = 1e-6
#: slack on the delta-V bounds (mph)
DELTA_V_TOLERANCE_MPH = 1e-9


def _fmt(x: float) -> str:
    return f"{x:.3g}"


def check_summary(
    *,
    hit: str | None,
    hit_time_s: float | None,
    heights_at_hit_ft: Mapping[str, float | None] | None = None,
    delta_v_contact_mph: float | None = None,
    car_speed_mph: float | None = None,
    max_decel_g: float | None = None,
    no_hit_reason: str | None = None,
    ground_tolerance_ft: float | Mapping[str, float] = EXACT_GROUND_TOLERANCE_FT,
    who: str = "the run",
    extra_numbers: Mapping[str, float | None] | None = None,
) -> list[str]:
    """Flag sentences for an outcome given as plain numbers (empty list: nothing absurd).

    ``hit``: the hit's wording ("ground hit", "WINDSHIELD" ...) or ``None``;
    ``heights_at_hit_ft``: each post point's height above the ground at the hit (ZL, ft);
    ``delta_v_contact_mph``: the speed the car lost; ``car_speed_mph``: its speed at impact
    (magnitude); ``ground_tolerance_ft``: how far below the ground the hit test lets a
    point be (one number, or one per point); ``who`` starts each sentence ("the listing").
    """
    flags: list[str] = []
    numbers = {
        "hit time": hit_time_s,
        "delta-V": delta_v_contact_mph,
        "largest deceleration": max_decel_g,
        "car speed": car_speed_mph,
    }
    for k, v in (heights_at_hit_ft or {}).items():
        numbers[f"height of point {k} at the hit"] = v
    numbers.update(extra_numbers or {})
    for what, v in numbers.items():
        if v is not None and not math.isfinite(v):
            flags.append(f"{who} reports a non-finite {what} ({v})")
    if hit is not None:
        for k, h in (heights_at_hit_ft or {}).items():
            if h is None or not math.isfinite(h):
                continue
            tol = (
                ground_tolerance_ft.get(k, EXACT_GROUND_TOLERANCE_FT)
                if isinstance(ground_tolerance_ft, Mapping)
                else ground_tolerance_ft
            )
            if h < -tol:
                flags.append(
                    f"{who} reports a {hit} at {_fmt(hit_time_s or 0.0)} s with {k} "
                    f"{-h:.3g} ft below the ground (tolerance {tol:g} ft)"
                )
    elif not no_hit_reason:
        flags.append(f"{who} reports no hit and names no reason")
    if delta_v_contact_mph is not None and math.isfinite(delta_v_contact_mph):
        if delta_v_contact_mph < -DELTA_V_TOLERANCE_MPH:
            flags.append(f"{who} reports a negative delta-V ({_fmt(delta_v_contact_mph)} mph): the car sped up")
        if (
            car_speed_mph is not None
            and math.isfinite(car_speed_mph)
            and delta_v_contact_mph > abs(car_speed_mph) + DELTA_V_TOLERANCE_MPH
        ):
            flags.append(
                f"{who} reports a delta-V of {_fmt(delta_v_contact_mph)} mph, more than the car's "
                f"speed ({_fmt(abs(car_speed_mph))} mph): the car reversed"
            )
    return flags


def ground_tolerance_ft(options) -> dict[str, float] | float:
    """The hit test's ground tolerance under ``options`` (ft; per point for the listing's)."""
    if options.listing_hit_tolerances:

        return {**LISTING_GROUND_TOLERANCE_FT, "S": 0.1, "T": 0.1}
    return EXACT_GROUND_TOLERANCE_FT


def check_outcome(result) -> list[str]:
    """The failed checks of core run ``result`` as sentences (empty: may be reported)."""

    scene = result.scene
    depth = scene.environment.ground_depth_ft
    heights = None
    traj = result.trajectory
    if result.hit is not None and traj.segments:
        t = min(result.hit.time_s, traj.t_end)
        heights = {p: float(x[2]) + depth for p, x in traj.points(t).items()}  # one state
    car_speed = delta_v = None
    if scene.vehicle is not None:
        v0 = scene.vehicle.initial_velocity_ft_s
        car_speed = ft_s_to_mph(abs(v0))
        if result.contact_end_s is not None:
            delta_v = speed_lost_mph(v0, float(traj.vehicle(result.contact_end_s)[1]))
    extra = {"end time": result.end_time_s}
    for k, v in result.terminal_points_ft.items():
        if v is not None:
            for axis, x in zip(("XL", "YL", "ZL"), v):
                extra[f"{axis} of point {k}"] = x
    flags = check_summary(
        hit=(result.hit.surface.lower() + " hit") if result.hit else None,
        hit_time_s=result.hit_time_s,
        heights_at_hit_ft=heights,
        delta_v_contact_mph=delta_v,
        car_speed_mph=car_speed,
        no_hit_reason=result.no_hit_reason,
        ground_tolerance_ft=ground_tolerance_ft(result.options),
        who="the core",
        extra_numbers=extra,
    )
    if result.hit is None and traj.segments and not result.ground_passage:
        t = traj.t_end
        low = min((float(x[2]) + depth, p) for p, x in traj.points(t).items())
        if low[0] < -EXACT_GROUND_TOLERANCE_FT:
            flags.append(
                f"the core reports no hit with point {low[1]} {-low[0]:.3g} ft below the "
                f"ground at the end ({t:.3g} s) and no ground passage named"
            )
    return flags
