"""What an engine returns: one :class:`Outcome`, whichever engine ran."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from deck_emulator.vocabulary.scene import Scene
from deck_emulator.vocabulary.events import Event, EventKind
from deck_emulator.vocabulary.units import ft_s_to_mph

from .trajectory import Sampled, Trajectory, readonly

_EMPTY = readonly(np.zeros(0))
_EMPTY_BOOL = readonly(np.zeros(0, dtype=bool))
_NO_MAP = MappingProxyType({})


@dataclass(frozen=True)
class Outcome:
    """One run of either engine, as arrays over time (road axes XX, YY, ZZ; ft, s): a value,
    made once by its engine; no field can be assigned, no array written, no sequence or
    mapping changed.

    * ``engine``: ``"emulator"`` or ``"core"``; ``settings``: what was run, in words (the
      arithmetic and its assumptions, the errata; or the preset, method and tolerances);
      ``arithmetic``: the arithmetic it ran in (the emulator's ``double``, ``single`` or
      ``ibm7094``; the core's ``IEEE double``); ``errata``: the errata the emulator applied.
    * ``scene``: what was run, typed (:class:`~deck_emulator.vocabulary.scene.Scene`: the post
      and its named points, U included, the car, the base, the ground); an emulator's deck
      is a :class:`~deck_emulator.vocabulary.scene.DeckScene` (built through the one deck <->
      scene mapping, not checked: the listing runs decks the core refuses). ``None`` only
      for a row that stands for no run.
    * ``t``; ``points``: name -> (n, 3) for the post's points ``P``, ``Q``, ``R``, ``C``, a
      second luminaire ``U`` where the post has one, and the mass centre ``CM`` (NaN where an engine does not give a point); ``sv``, ``vv``: the
      car's position and velocity along XV; ``free``: the free-flight samples.
    * ``pulse_t``, ``pulse_g``: the car's deceleration (g) over the contact phase.
    * ``events``: :class:`~deck_emulator.vocabulary.events.Event` in time order; ``hit``: the last one
      if it is a hit; ``hit_message``: the hit as the listing words it ("THE POST HAS HIT
      THE GROUND WITH POINT R"; the core's own for what the listing cannot say).
    * ``crush_end_s``: the instant the crush pulse ends (the spring force first capped at
      FCONST: the core's located event; the emulator's first printed step so capped, as the
      report read the paper); ``contact_end_s``: the instant the contact with the car ends
      (the car let go, or the post hit the car while in contact).  The registry reads the
      speed the car lost at each (:func:`car_velocity`): the engines compute no ΔV.
    * The largest decelerations are the registry's (:mod:`deck_emulator.engine.quantities`),
      from the forces on the car the trajectory gives (``peak_car_force``: the emulator's
      largest *printed* FSA, as the report read it, and every step's FS; the core's
      continuous maximum).
    * ``terminal``: P, Q, R, C (and U) at the hit in the report's XL, YL, ZL axes (ft).
    * ``flags``: sentences naming what is physically absurd in an answer the engine gave
      (a hit with a point under the ground, a delta-V above the car's speed ...); the
      emulator's printout is left as the listing prints it, the flags say what is odd.
    * ``error``: why the run stopped early (one line), ``None`` if it ended; ``guard``: the
      emulator's guard that stopped it; ``hint``: what would let it run.
    * ``contact_test``: what of the post the run tested against the car in free flight:
      ``"points"`` (the listing's P, R and C: the emulator, the core without
      ``shaft_contact``) or ``"segments"`` (the shaft Q-P and the arms too: the core's
      ``ModelOptions.shaft_contact``); what a verdict on the occupant compartment can rest on.
    * ``method``: the core's integration method as it ran (``auto`` resolved); ``notes``: what
      the engine says of the run (the core's sentences about its scene and solution).
    * ``records``: the emulator's printout, record by record (carriage control in column 1).
    * ``evaluations``: the core's right-hand-side evaluations; ``engine_events``: every event
      the engine located, in its own words, ``(name, time_s)`` (the core's normal force
      released, its sliding modes ...); ``end_s``: where its solution ends.  :meth:`position`
      reads the solution itself (the core's dense one) at any instant.
    * ``run_s``: seconds the engine's solver ran (the program's loop; the core's solution),
      without building this outcome.
    * ``trajectory``: the run as every reader reads it, whichever engine made it
      (:mod:`.trajectory`: the emulator's accepted steps, the core's dense solution).
    """

    engine: str
    name: str
    scene: Scene | None = None
    settings: str = ""
    arithmetic: str = ""
    errata: tuple[str, ...] = ()
    t: np.ndarray = field(default_factory=lambda: _EMPTY)
    points: Mapping[str, np.ndarray] = field(default_factory=lambda: _NO_MAP)
    sv: np.ndarray = field(default_factory=lambda: _EMPTY)
    vv: np.ndarray = field(default_factory=lambda: _EMPTY)
    free: np.ndarray = field(default_factory=lambda: _EMPTY_BOOL)
    pulse_t: np.ndarray = field(default_factory=lambda: _EMPTY)
    pulse_g: np.ndarray = field(default_factory=lambda: _EMPTY)
    events: tuple[Event, ...] = ()
    hit_message: str | None = None
    crush_end_s: float | None = None
    contact_end_s: float | None = None
    terminal: Mapping[str, tuple[float, float, float]] = field(default_factory=lambda: _NO_MAP)
    error: str | None = None
    flags: tuple[str, ...] = ()
    guard: str | None = None
    hint: str = ""
    run_s: float = 0.0
    method: str = ""
    contact_test: str = "points"
    notes: tuple[str, ...] = ()
    records: tuple[str, ...] = ()
    evaluations: int | None = None
    engine_events: tuple[tuple[str, float], ...] = ()
    end_s: float | None = None
    trajectory: Trajectory | None = field(default=None, repr=False, compare=False)
    #: what :mod:`.quantities` has computed from this outcome once (the pulse, the clearance):
    #: a memo of a value, which cannot go stale (:meth:`memo`)
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        put = object.__setattr__
        for name in ("t", "sv", "vv", "pulse_t", "pulse_g"):
            put(self, name, readonly(getattr(self, name), float))
        put(self, "free", readonly(self.free, bool))
        put(self, "points", MappingProxyType(
            {k: readonly(v, float) for k, v in self.points.items()}))
        put(self, "terminal", MappingProxyType(
            {k: tuple(p) for k, p in self.terminal.items()}))
        for name in ("errata", "events", "flags", "notes", "records", "engine_events"):
            put(self, name, tuple(getattr(self, name)))
        if self.trajectory is None:  # an outcome made of its samples is read through them
            put(self, "trajectory", Sampled(self.t, self.points, self.vv))

    def memo(self, key: str, compute):
        """``compute(self)``, once per outcome."""
        if key not in self._memo:
            self._memo[key] = compute(self)
        return self._memo[key]

    # -- events ---------------------------------------------------------------------------

    def _first(self, kind: EventKind) -> Event | None:
        return next((e for e in self.events if e.kind is kind), None)

    @property
    def hit(self) -> Event | None:
        return self._first(EventKind.HIT)

    @property
    def hit_time_s(self) -> float | None:
        return self.hit.time_s if self.hit else None

    @property
    def printout(self) -> str:
        """The emulator's printout as text, a record a line."""
        return "".join(r + "\n" for r in self.records)

    @property
    def ended(self) -> bool:
        """The run came to its end: a hit, with no guard or error stopping it first (a run
        that did not end has no quantity that depends on its end: engine.quantities)."""
        return self.error is None and self.hit is not None

    @property
    def first_spring_lost_s(self) -> float | None:
        e = self._first(EventKind.LOST_FIRST_SPRING)
        return e.time_s if e else None

    @property
    def vehicle_contact_lost_s(self) -> float | None:
        e = self._first(EventKind.LOST_VEHICLE)
        return e.time_s if e else None

    # -- the scene ------------------------------------------------------------------------

    @property
    def speed_mph(self) -> float:
        """The car's speed at t = 0 (mph; NaN without a car)."""
        car = self.scene.vehicle if self.scene is not None else None
        return ft_s_to_mph(abs(car.initial_velocity_ft_s)) if car is not None else math.nan

    @property
    def angle_deg(self) -> float:
        """The car's approach angle (deg; NaN without a car)."""
        car = self.scene.vehicle if self.scene is not None else None
        return math.degrees(car.approach_angle_rad) if car is not None else math.nan

    @property
    def gravity_ft_s2(self) -> float:
        return self.scene.environment.gravity_ft_s2

    @property
    def end_time_s(self) -> float:
        return float(self.t[-1]) if self.t.size else 0.0

    def at(self, t: float) -> int:
        """Index of the sample nearest to ``t``."""
        return int(np.argmin(np.abs(self.t - t)))

    def to_l(self, p):
        """XX, YY, ZZ -> the report's XL, YL, ZL (origin on the ground under the base Q at
        t = 0)."""
        base, ground = self.scene.post.base, self.scene.environment.ground_depth_ft
        p = np.asarray(p, dtype=float)
        return p - np.array([base.xx_ft, base.yy_ft, -ground])

    @property
    def point_names(self) -> tuple[str, ...]:
        """The post's named points the run follows."""
        return self.trajectory.point_names

    @property
    def span(self) -> tuple[float, float]:
        """Where the run's solution starts and ends (s)."""
        return self.trajectory.span

    def position(self, name: str, t) -> np.ndarray:
        """The post's point ``name`` (``CM``: the mass centre) at ``t`` (a time, or an array of
        them) in the road axes XX, YY, ZZ: (3,) or (3, n) (:attr:`trajectory`)."""
        return self.trajectory.position(name, t)

    def car_velocity(self, t: float) -> float | None:
        """The car's velocity VV along XV at ``t``; None outside the run."""
        return self.trajectory.car_velocity(t)

    def motion(self, t: float) -> dict:
        """The post's and the car's motion at ``t`` from a dense solution:
        ``mass_centre_ft`` (XX, YY, ZZ), ``velocity_body_ft_s``, ``attitude_wxyz`` (body to
        road), ``angular_velocity_body_rad_s``, ``car_position_ft`` and ``car_velocity_ft_s``
        (SV, VV along XV); a run known only at its steps raises ValueError."""
        return self.trajectory.motion(t)

    def solver_steps(self) -> int:
        """The integrator's steps over its segments (a dense solution's; else ValueError)."""
        return self.trajectory.solver_steps()

    def accepted_steps(self) -> tuple[np.ndarray, np.ndarray]:
        """The emulator's accepted steps: their times (n,) and the mass centre at each (3, n)
        (the arrays' first sample, t = 0, is the deck's start, not a step)."""
        if "CM" not in self.points:
            return np.zeros(0), np.zeros((3, 0))
        return self.t[1:], np.asarray(self.points["CM"], dtype=float)[1:].T.reshape(3, -1)

    def point_l(self, name: str, t: float) -> tuple[float, float, float] | None:
        """The post's point ``name`` at ``t`` in the report's XL, YL, ZL axes: the core's
        dense solution, the emulator's nearest accepted step (None outside the run or for a
        point the post lacks)."""
        p = self.trajectory.point_near(name, t)
        return None if p is None else tuple(float(x) for x in self.to_l(p))

    def trajectory_frame(self):
        """The run as a :class:`pandas.DataFrame`, one row per sample (the emulator's accepted
        steps; the core's dense solution on its sampling grid): ``t_s``, ``phase``
        (``contact`` or ``free``), every named point in the road axes (``P_xx_ft`` ...) and in
        the report's axes (``P_xl_ft`` ...), the mass centre ``CM``, the shaft's tilt from the
        vertical and its heading in plan (``shaft_tilt_deg``, ``shaft_heading_deg``: the line
        Q->P, the same definition for both engines), and the car (``car_position_ft`` SV,
        ``car_velocity_ft_s`` VV along XV)."""
        import pandas as pd

        cols: dict[str, np.ndarray] = {"t_s": self.t,
                                       "phase": np.where(self.free, "free", "contact")}
        for name, xyz in self.points.items():
            xyz = np.asarray(xyz, dtype=float)
            xl = self.to_l(xyz) if xyz.size else xyz
            for i, (road, report) in enumerate((("xx", "xl"), ("yy", "yl"), ("zz", "zl"))):
                cols[f"{name}_{road}_ft"] = xyz[:, i]
                if name != "CM":
                    cols[f"{name}_{report}_ft"] = xl[:, i]
        if "P" in self.points and "Q" in self.points:
            axis = np.asarray(self.points["P"], float) - np.asarray(self.points["Q"], float)
            horizontal = np.hypot(axis[:, 0], axis[:, 1])
            cols["shaft_tilt_deg"] = np.degrees(np.arctan2(horizontal, axis[:, 2]))
            cols["shaft_heading_deg"] = np.degrees(np.arctan2(axis[:, 1], axis[:, 0]))
        cols["car_position_ft"] = self.sv
        cols["car_velocity_ft_s"] = self.vv
        return pd.DataFrame(cols)

    def contact_history(self):
        """(t, vv) up to the end of the contact with the car (the whole run if it never ends)."""
        lost = self.vehicle_contact_lost_s
        if lost is None or not self.t.size:
            return self.t, self.vv
        k = int(np.searchsorted(self.t, lost + 1e-9, side="right"))
        k = max(k, 2)
        return self.t[:k], self.vv[:k]

    def verdict(self) -> str:
        """'hit ground (R)' or 'no hit (why)'."""
        if self.hit:
            return self.hit.short()
        return f"no hit ({self.error})" if self.error else "no hit"
