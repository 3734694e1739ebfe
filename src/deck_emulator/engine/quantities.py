"""The one registry of quantities: each has one name, one unit, one definition and one line
saying what it is.

A :class:`Quantity`'s ``value`` is a function of an engine's
:class:`~deck_emulator.engine.outcome.Outcome`; every table, JSON answer, CSV column, picture
label and generated page takes a quantity's name, unit, digits and value from here, and
nothing else computes it.  The name carries the unit the value is in (``hit_time_s`` is in
seconds; a table may show it in ms: ``scale`` and ``unit`` say how it is shown).

Quantities that differ get different names (three speed changes read at three instants of the
contact, three decelerations): each row's definition says which.

A quantity knows what it needs of its run (``needs``): ``"end"``, the run ended with its hit
(the terminal points, the clearances over the car, the free flight's energy); ``"contact"``,
the car let go of the post (the speed lost over the contact, the decelerations, the occupant's
flail-space readings: the car keeps its speed afterwards, section 3.8); ``None``, only its own
event (a time, a speed lost by an event: none without the event).  A run that stopped has no
value for what it did not reach: ``None``, and :func:`unavailable` says why.

Where an engine measures a quantity its own way (the emulator reads what its printout says,
as the report's authors read the paper; the core locates the instant exactly), the line says
so; the studies never compute one themselves.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

from deck_emulator.vocabulary.defaults import OUTCOME_ARRAYS
from deck_emulator.vocabulary.units import force_in_g, speed_lost_mph

__all__ = ["Quantity", "QUANTITIES", "ARRAYS", "value", "values", "names", "definitions_help",
           "pulse", "clearance", "unavailable", "why_none", "speed_lost_at", "arrays_for"]

#: what a quantity may need of its run (see the module's docstring)
NEEDS = ("end", "contact", None)

#: The sampled arrays an outcome may carry, each made only when asked (the core's
#: ``CoreEngine.arrays``; the emulator's accepted steps are its arrays, made whole or not at
#: all): ``car`` -- ``t``, ``sv``, ``vv``, ``free`` on the sampling grid (the occupant-risk
#: pulse reads them); ``points`` -- the post's points on that grid and C at the hit (the
#: clearances, the attitude, the pictures; they come with ``car``); ``pulse`` -- ``pulse_t``,
#: ``pulse_g``, the force on the car over the contact (the pictures only).
ARRAYS = OUTCOME_ARRAYS


@dataclass(frozen=True)
class Quantity:
    """``name`` (the JSON key and CSV column), ``unit`` and ``label`` as a table shows them,
    ``digits`` shown, ``what`` it is in one line (with its source where it is a criterion's
    reading), ``value(outcome)`` in the unit of the name, ``scale``: shown = value * scale,
    ``needs``: what of the run it needs (:data:`NEEDS`); ``reads``: the sampled arrays
    (:data:`ARRAYS`) its definition reads -- none where it reads the events, the engine's
    own numbers or the core's dense solution (a ΔV: ``Outcome.car_velocity``)."""

    name: str
    label: str
    unit: str
    digits: int
    what: str
    value: Callable[[object], float | None]
    scale: float = 1.0
    needs: str | None = "end"
    reads: tuple[str, ...] = ()

    def of(self, outcome) -> float | None:
        """The value for ``outcome`` (``None`` where it has none, where its run stopped before
        what it :attr:`needs`, or it is not finite). A definition that raises is a defect and
        is not hidden: each returns None itself where an outcome has no such value."""
        if why_none(self.needs, outcome) is not None:
            return None
        v = self.value(outcome)
        if v is None:
            return None
        v = float(v)
        return v if math.isfinite(v) else None

    def show(self, v) -> str:
        """``v`` as a table shows it (``-`` for none)."""
        if v is None or (isinstance(v, float) and math.isnan(v)):
            return "-"
        return f"{v * self.scale:.{self.digits}f}"


# ------------------------------------------------------------------ what a run reached


def why_none(needs: str | None, o) -> str | None:
    """Why a quantity that ``needs`` this of its run has no value for ``o`` (None: it may
    have one).  Only a run that did not end lacks what a quantity needs."""
    if needs is None or o.ended:
        return None
    if needs == "contact" and o.vehicle_contact_lost_s is not None:
        return None
    how = "stopped" if o.error else "ended with no hit"
    at = f" at {1000.0 * o.end_time_s:.1f} ms" if o.t.size else ""
    before = "the car let go of the post" if needs == "contact" else "its end"
    return f"the run {how}{at}, before {before}"


def unavailable(outcome, which: Iterable[str]) -> dict[str, str]:
    """``{name: why}`` of the quantities ``which`` that ``outcome``'s run did not reach."""
    out = {}
    for name in which:
        why = why_none(QUANTITIES[name].needs, outcome)
        if why is not None:
            out[name] = why
    return out


# ------------------------------------------------------------------ what the definitions read


def pulse(o):
    """The occupant-risk reading of the outcome's contact history
    (:class:`~deck_emulator.engine.safety.PulseMetrics`, computed once; None without one)."""
    from .safety import assess_outcome

    return o.memo("pulse", lambda o: assess_outcome(o) if o.t.size
                   and why_none("contact", o) is None else None)


def clearance(o):
    """The post's clearance over the car in free flight
    (:class:`~deck_emulator.engine.safety.Clearance`, computed once; None without one)."""
    from .safety import clearance_of

    return o.memo("clearance", lambda o: clearance_of(o) if o.t.size
                   and why_none("end", o) is None else None)


def _energies(o):
    from .energy import energies

    return o.memo("energies", energies)


def _leaf(o):
    from .leaf_spring import at_unloading

    return o.memo("leaf", at_unloading)


def _attitude():
    from . import attitude

    return attitude


def _terminal(point: str, axis: int):
    def value(o):
        p = _attitude().point_at_end_l(o, point)
        return None if p is None else p[axis]

    return value


def _yl_shift(point: str):
    def value(o):
        end, start = _attitude().point_at_end_l(o, point), _attitude().start_l(o, point)
        return None if end is None or start is None else end[1] - start[1]

    return value


def _attr(name):
    return lambda o: getattr(o, name)


def _of_pulse(field):
    return lambda o: None if pulse(o) is None else getattr(pulse(o), field)


def _of_clearance(field):
    return lambda o: None if clearance(o) is None else getattr(clearance(o), field)


def speed_lost_at(o, t: float | None) -> float | None:
    """THE reading of every ΔV: the speed (mph) the car of ``o`` has lost by the instant
    ``t``: its velocity at the start (the scene's car's, else the first sample) against
    :meth:`~deck_emulator.engine.outcome.Outcome.car_velocity` at ``t``; None without the
    instant or outside the run."""
    car = o.scene.vehicle if o.scene is not None else None
    v0 = car.initial_velocity_ft_s if car is not None else (
        float(o.vv[0]) if o.vv.size else None)
    v = None if t is None or v0 is None else o.car_velocity(t)
    return None if v is None else speed_lost_mph(v0, v)


def arrays_for(which: Iterable[str]) -> tuple[str, ...]:
    """The sampled arrays (:data:`ARRAYS`, in that order) the quantities ``which`` read: what
    an engine must make for them, and no more."""
    wanted = {a for name in which for a in QUANTITIES[name].reads}
    return tuple(a for a in ARRAYS if a in wanted)


def _speed_lost_by(instant: str):
    return lambda o: speed_lost_at(o, getattr(o, instant))


def _peak_decel(after_startup: bool):
    """THE reading of the largest deceleration (g): the largest force on the car over the
    contact that the run's trajectory gives (:meth:`~.trajectory.Trajectory.peak_car_force`:
    the core's dense solution, the emulator's printed FSA or every step's FS) over WV*G
    (``units.force_in_g``); none for a car without mass or a scene without gravity."""
    def value(o):
        force = o.trajectory.peak_car_force(after_startup)
        mass, g = o.scene.vehicle.mass_slug, o.scene.environment.gravity_ft_s2
        if force is None or not (mass > 0.0 and g > 0.0):
            return None
        return force_in_g(force, mass, g)

    return value


_CAR, _POINTS = ("car",), ("car", "points")  # the points come on the car's grid

_REGISTRY = (
    Quantity("hit_time_s", "post hits", "ms", 1, "time of the hit that ends the run",
             _attr("hit_time_s"), 1000.0, needs=None),
    Quantity("first_spring_lost_s", "post leaves the first spring", "ms", 1,
             "time the post loses contact with the car's first crush spring",
             _attr("first_spring_lost_s"), 1000.0, needs=None),
    Quantity("vehicle_contact_lost_s", "post leaves the car", "ms", 1,
             "time the post loses contact with the car", _attr("vehicle_contact_lost_s"),
             1000.0, needs=None),
    Quantity("delta_v_crush_mph", "speed lost, crush pulse", "mph", 2,
             "the speed the car has lost by the end of the crush pulse (the spring force first "
             "capped at FCONST): one of three readings of the report's DECREASE IN VEHICLE "
             "VELOCITY (Tables 11 and 12), which the report defines nowhere: it fits the "
             "report's steel 40 mph columns, the first-spring reading its aluminium and twin "
             "ones, whose base weight moves ΔV by more, so the tables cannot decide "
             "(docs/report_full.md, 'ΔV and the maximum deceleration') (emulator: read at the "
             "first printed step where FSA is cut to "
             "FCONST; core: at its located 'force cap engaged' event)",
             _speed_lost_by("crush_end_s"), needs=None),
    Quantity("delta_v_first_spring_mph", "speed lost, to the first spring's loss", "mph", 2,
             "the speed the car has lost by the instant the post loses contact with the first "
             "spring (the listing's THE POST HAS LOST CONTACT WITH FIRST SPRING; emulator: "
             "the car's speed at that accepted step; core: at its located event)",
             _speed_lost_by("first_spring_lost_s"), needs=None),
    Quantity("delta_v_contact_mph", "speed lost, whole contact", "mph", 2,
             "the speed the car has lost by the end of its contact with the post",
             _speed_lost_by("contact_end_s"), needs="contact"),
    Quantity("max_decel_g", "largest deceleration of the car", "g", 2,
             "the report's MAXIMUM VEHICLE DECELERATION: the largest spring force over WV*G "
             "after the start-up steps (emulator: the largest printed FSA, as the report read "
             "it; core: the largest over its continuous solution after the start-up kick, "
             "whose 10,000 lb is a device of the listing's scheme, not an impact force)",
             _peak_decel(True), needs="contact"),
    Quantity("max_decel_every_step_g", "largest deceleration, every step", "g", 4,
             "the largest spring force over WV*G at every accepted step of the emulator (not "
             "only the printed ones), start-up steps included; the core's continuous maximum "
             "likewise: what the two engines compute alike, for diff",
             _peak_decel(False), needs="contact"),
    Quantity("max_decel_10ms_g", "largest 10 ms average deceleration", "g", 2,
             "the largest average deceleration of the car over any 10 ms window of the contact",
             _of_pulse("max_decel_10ms_g"), needs="contact", reads=_CAR),
    Quantity("oiv_m_s", "occupant impact velocity (OIV)", "m/s", 2,
             "flail-space model (0.6 m): the occupant's speed relative to the car when it "
             "strikes the interior; judged by the cited limits of NCHRP Report 350 and MASH "
             "(engine.safety.CRITERIA)",
             _of_pulse("oiv_m_s"), needs="contact", reads=_CAR),
    Quantity("ora_g", "occupant ridedown acceleration (ORA)", "g", 2,
             "the largest 10 ms average deceleration of the car after the occupant strikes; "
             "judged by the cited limits (engine.safety.CRITERIA)",
             _of_pulse("ora_g"), needs="contact", reads=_CAR),
    Quantity("occupant_strike_time_s", "occupant strikes the interior", "ms", 1,
             "flail-space model: when the occupant has moved 0.6 m relative to the car "
             "(none: never)", _of_pulse("occupant_strike_time_s"), 1000.0, needs="contact",
             reads=_CAR),
    Quantity("body_clearance_ft", "least clearance above the car body", "ft", 3,
             "the post's least height above the car's outline (hood, roof, trunk) while over "
             "it in free flight, every arm included", _of_clearance("body_ft"), reads=_POINTS),
    Quantity("roof_clearance_ft", "least clearance above the roof", "ft", 3,
             "the same over the passenger compartment only (windshield base to the end of the "
             "top)", _of_clearance("roof_ft"), reads=_POINTS),
    Quantity("launch_ke_ftlb", "post's kinetic energy as the car lets go", "ft·lb", 1,
             "translational plus rotational kinetic energy of the post when its contact with "
             "the car ends", lambda o: _energies(o)["launch_ke_ftlb"], needs="contact"),
    Quantity("free_flight_energy_drift", "energy drift in free flight", "1", 3,
             "(E_end - E_start) / E_start over the free flight, E kinetic plus potential "
             "above the ground: zero for an exact solution", lambda o: _energies(o)["free_drift"]),
    Quantity("leaf_spring_peak_compression_ft", "leaf spring's largest compression", "ft", 4,
             "the crash test's leaf spring (Chapter V): its compression when it begins to "
             "unload", lambda o: _leaf(o)["compression_ft"], needs=None),
    Quantity("leaf_spring_set_ft", "leaf spring's set", "ft", 4,
             "the compression at which the leaf spring's unloading force reaches zero (the "
             "crush it keeps)", lambda o: _leaf(o)["set_ft"], needs=None),
    Quantity("arm_spin_deg", "arm's spin about the post's axis, at the end", "deg", 1,
             "the post's rotation about its own axis Q->P from t = 0 to the hit (right hand; "
             "for the upright post the rotation about ZL, negative = clockwise seen from "
             "above), tracked continuously over the run's samples, so a turn past a half turn "
             "keeps its sense (-200, not +160): at each sample the attitude as a spin about "
             "the initial axis followed by the smallest swing of the axis, read from P, Q, R "
             "(engine.attitude.arm_spin_track)",
             lambda o: _attitude().arm_spin_deg(o, "end"), reads=_POINTS),
    Quantity("arm_spin_release_deg", "arm's spin about the post's axis, car lets go", "deg", 1,
             "the same rotation, tracked the same way, from t = 0 to the loss of contact with "
             "the car",
             lambda o: _attitude().arm_spin_deg(o, "release"), needs="contact",
             reads=_POINTS),
    *(Quantity(f"terminal_{p.lower()}_{ax.lower()}_ft", f"{ax} of {what} at the end", "ft", 2,
               f"{ax} of {what} at the hit (the report's XL, YL, ZL axes: origin on the ground "
               f"under the base, +YL away from the highway; Tables 11 and 12's {ax[0]}{p}L)",
               _terminal(p, i), reads=_POINTS)
      for p, what in (("P", "the top P"), ("Q", "the base Q"), ("R", "the luminaire end R"),
                      ("U", "the second luminaire end U"))
      for i, ax in enumerate(("XL", "YL", "ZL"))),
    *(Quantity(f"terminal_cm_{ax.lower()}_ft", f"{ax} of the mass centre at the end", "ft", 2,
               f"{ax} of the post's mass centre at the hit (the report's axes)",
               _terminal("CM", i), reads=_POINTS)
      for i, ax in enumerate(("XL", "YL"))),
    *(Quantity(f"{name}_yl_shift_ft", f"{what} moved across the road", "ft", 2,
               f"YL of {what} at the hit less its YL at t = 0 (positive: away from the "
               "highway, the arm reaching over it along -YL)", _yl_shift(p), reads=_POINTS)
      for p, name, what in (("R", "luminaire", "the luminaire end R"),
                            ("U", "second_luminaire", "the second luminaire end U"))),
)

#: name -> :class:`Quantity`, in the order tables show them.
QUANTITIES: Mapping[str, Quantity] = MappingProxyType({q.name: q for q in _REGISTRY})


def value(name: str, outcome) -> float | None:
    """The value of quantity ``name`` for ``outcome``."""
    return QUANTITIES[name].of(outcome)


def values(outcome, which: Iterable[str]) -> dict[str, float | None]:
    """``{name: value}`` of the quantities ``which`` for ``outcome``."""
    return {n: QUANTITIES[n].of(outcome) for n in which}


def names() -> list[str]:
    return list(QUANTITIES)


def definitions_help() -> str:
    """The two ΔVs, for ``--help``."""
    return "; ".join(f"{k}: {QUANTITIES[k].what}" for k in ("delta_v_crush_mph",
                                                            "delta_v_contact_mph"))


def markdown_table() -> str:
    """The registry as the table of docs/json.md (a test keeps the page equal to it)."""
    rows = ["| name | label in the tables | unit | digits | definition |", "|---|---|---|---|---|"]
    for q in QUANTITIES.values():
        unit = q.unit if q.scale == 1.0 else f"s (shown in {q.unit})"
        rows.append(f"| `{q.name}` | {q.label} | {unit} | {q.digits} | {q.what} |")
    return "\n".join(rows)
