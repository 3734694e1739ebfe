"""The two engines behind one interface: ``engine.run(source) -> Outcome``.

* :class:`EmulatorEngine` -- the 1967 program (``deck_emulator.legacy``) on a card deck, in
  one of its arithmetics, with the errata the user named (:mod:`.errata`);
* :class:`CoreEngine` -- the modern core (``deck_emulator.core``) on a deck or a typed scene.

This is the only module that knows both paths.  An engine never raises for a run that
cannot end: the :class:`~deck_emulator.engine.outcome.Outcome` says why (``error``) and keeps
what was computed up to then.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass, field

from deck_emulator import decks
from deck_emulator.legacy.arithmetic import get_arithmetic
from deck_emulator.legacy.fortran import STEP_LITERALS, listing_program
from deck_emulator.legacy.stops import EmulatorError, Limits
from deck_emulator.legacy.printer import event_message
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.events import Event, EventKind, Surface
from deck_emulator.vocabulary.units import force_in_g

from . import errata as errata_policy
from .sources import file_stem, kinds_for, load_source

# Outcome (and with it numpy) is imported where an outcome is made, not here: the plain
# `deck-emulator run` prints the program's records (EmulatorEngine.execute) and needs neither.
# (typing.TYPE_CHECKING's value at run time, without importing typing at the start)
TYPE_CHECKING = False
if TYPE_CHECKING:
    from .outcome import Outcome

ENGINES = ("emulator", "core")


def given(source, engine: str) -> tuple[object, str]:
    """``source`` as ``engine`` runs it, and its name: a deck or a scene object as it is (no
    name); a shipped deck's name or a file read as :func:`deck_emulator.run` reads it."""
    if not isinstance(source, (str, os.PathLike)):
        return source, ""
    src = load_source(source, kinds=kinds_for(engine), command=f"the {engine}")
    return src.for_engine(engine), src.stem


def source_name(source) -> str:
    """'steel40' for decks/steel40.dat; a scene's own name; else 'scene'."""
    path = getattr(source, "path", None)
    if path:
        return file_stem(str(path))
    return getattr(source, "name", "") or "scene"


# ============================================================================ the emulator


def _initial_points(d) -> dict:
    return {
        "P": (d["XPO"], d["YYPO"], d["ZZPO"]),
        "Q": (d["XQO"], d["YYQO"], d["ZZQO"]),
        "R": (d["XRO"], d["YYRO"], d["ZZRO"]),
        "C": (d["XCO"], d["YYCO"], d["ZZCO"]),
        "CM": (0.0, 0.0, 0.0),
    }


def step_literals() -> tuple[str, ...]:
    """The listing's literals that mean "one step" (0.0004 s): what the emulator's
    ``step_scale_k`` divides by 2**k, in words."""
    return tuple(words for _, _, words in STEP_LITERALS)


@dataclass(frozen=True)
class Execution:
    """One run of the program, before it is an :class:`Outcome`: its ``run`` (the records,
    the printout's text, the events), the guard that stopped it (``error``, an
    ``EmulatorError``) or a defect of ours (``defect``, with ``record_defects``), and how long
    the program's loop took (``run_s``)."""

    run: object
    error: Exception | None = None
    defect: str | None = None
    run_s: float = 0.0

    @property
    def stopped(self) -> bool:
        return self.error is not None or self.defect is not None


@dataclass(frozen=True)
class EmulatorEngine:
    """The 1967 program. ``precision``: ``double``, ``single`` or ``ibm7094`` (with the
    7094's ``arithmetic_options``); ``errata`` as requested (default: as printed); the
    options of :func:`deck_emulator.legacy.fortran.listing_program` (``step_scale_k``,
    ``ed_tolerance``, ``tha_start``) and ``limits``; ``trace``: build the trajectory arrays;
    ``record_defects``: an exception that is not one of the emulator's guards (a defect of
    ours) ends the run as guard ``"crash"`` instead of propagating (the studies record it)."""

    precision: str = "double"
    errata: tuple[str, ...] = ()
    step_scale_k: int = 0
    ed_tolerance: str = ".0001"
    tha_start: str | None = None
    limits: object = None
    arithmetic_options: dict = field(default_factory=dict)
    trace: bool = True
    record_defects: bool = False
    #: a job deck's own program (legacy.fortran.Program) run instead of the listing's
    fortran: object = None
    name = "emulator"

    def arithmetic(self):
        return get_arithmetic(self.precision, **self.arithmetic_options)

    def program(self, deck):
        """The run of the program on ``deck``: a job deck's own program, or the listing with
        the errata and options asked, both through the FORTRAN front end."""
        program = self.fortran or listing_program(
            errata_policy.resolve(self.errata), step_scale_k=self.step_scale_k,
            tha_start=self.tha_start, ed_tolerance=self.ed_tolerance)
        return program.runner(deck, self.arithmetic(), limits=self.limits or Limits(),
                              trace=self.trace)

    def execute(self, deck, *, watch=None) -> "Execution":
        """The program's run alone, without the :class:`Outcome` (which :meth:`outcome_of`
        makes from it): what the plain ``deck-emulator run`` prints.  ``watch``: called with
        the program before it runs (a progress display may read its ``step`` from another
        thread; nothing is added to the program's loop).  ``deck``: a deck, a shipped deck's
        name or a file (:func:`given`)."""
        program = self.program(given(deck, self.name)[0])
        if watch is not None:
            watch(program)
        error = defect = None
        started = time.perf_counter()  # the program's run alone: what a study times
        try:
            run = program.run()
        except EmulatorError as exc:
            run, error = exc.run, exc
        except Exception as exc:  # noqa: BLE001 - recorded only when asked (record_defects)
            if not self.record_defects:
                raise
            run = program.run_
            defect = f"{type(exc).__name__}: {exc} (label {program.label}, step {program.step})"
        return Execution(run, error, defect, time.perf_counter() - started)

    def run(self, deck, *, name: str = "", watch=None) -> Outcome:
        """``deck`` (or its name, or a file: :func:`given`) run; ``watch``: as
        :meth:`execute`."""
        deck, stem = given(deck, self.name)
        return self.outcome_of(self.execute(deck, watch=watch), deck, name=name or stem)

    def outcome_of(self, done: "Execution", deck, *, name: str = "") -> Outcome:
        """The :class:`Outcome` of an :meth:`execute` of ``deck``, made once."""
        import dataclasses

        from deck_emulator.vocabulary.scene import Scene

        from .outcome import Outcome

        run, name = done.run, name or source_name(deck)
        d = dict(deck.values)
        events = tuple(run.events)
        hit = next((e for e in events if e.kind is EventKind.HIT), None)
        fields = dict(
            engine="emulator", name=name,
            scene=Scene.from_deck(deck, name=name, checked=False),
            errata=tuple(run.errata), arithmetic=self.precision,
            settings=f"arithmetic {run.arithmetic}; errata: "
            f"{errata_policy.describe(run.errata)}",
            records=tuple(run.records), events=events, run_s=done.run_s,
            hit_message=event_message(hit) if hit is not None else None)
        if done.error is not None:
            fields.update(error=str(done.error), guard=done.error.guard,
                          hint=errata_policy.hint(done.error.guard, run.errata))
        elif done.defect is not None:
            fields.update(error=done.defect, guard="crash")
        if self.trace and run.trace:
            fields.update(_emulator_arrays(run.trace, d))
        printed_notes = _printed_quantities(fields, run, deck)
        out = Outcome(**fields)
        flags = _listing_flags(out) if run.error is None else []
        flags += [n for n in printed_notes if "overflow" in n]  # a field printed as ****
        return dataclasses.replace(out, flags=tuple(flags)) if flags else out


def _post_state(row):
    from .trajectory import PostState

    return PostState((row["V1"], row["V2"], row["V3"]), (row["W1"], row["W2"], row["W3"]),
                     row["ZZCM"])


def _emulator_arrays(rows, d) -> dict:
    """The outcome's fields read from the program's trace: its accepted steps as arrays (and
    the :class:`~.trajectory.Sampled` trajectory over them), the deceleration over each contact
    step, the end of the contact."""
    import numpy as np  # here, not at the top: a run without a trace (deck-emulator run) needs none

    from .trajectory import Sampled

    init = _initial_points(d)
    n = len(rows) + 1
    t = np.empty(n)
    t[0] = 0.0
    pts = {k: np.full((n, 3), np.nan) for k in init}
    for k, p in init.items():
        pts[k][0] = p
    sv, vv = np.empty(n), np.empty(n)
    sv[0], vv[0] = d["SVB"], d["VVB"]
    free = np.zeros(n, dtype=bool)
    c_is_q = init["C"] == init["Q"]
    for i, r in enumerate(rows, start=1):
        t[i] = r["t"]
        sv[i], vv[i] = r["SV"], r["VV"]
        free[i] = r["phase"] == "free"
        pts["CM"][i] = (r["XCM"], r["YYCM"], r["ZZCM"])
        for k in ("P", "Q", "R"):
            pts[k][i] = (r[f"X{k}"], r[f"YY{k}"], r[f"ZZ{k}"])
        if "XC" in r:
            pts["C"][i] = (r["XC"], r["YYC"], r["ZZC"])
        elif c_is_q:
            pts["C"][i] = pts["Q"][i]
    # the contact-to-free handover is recorded twice (label 42 and the first free step):
    # keep times strictly increasing
    keep = np.concatenate([[True], np.diff(t) > 0])
    t, sv, vv, free = t[keep], sv[keep], vv[keep], free[keep]
    points = {k: v[keep] for k, v in pts.items()}
    in_contact = [r for r in rows if r["phase"] == "contact"]
    in_free = [r for r in rows if r["phase"] != "contact"]
    states = {}
    if in_contact and in_free:
        states["launch"] = _post_state(in_contact[-1])
    if len(in_free) >= 2:
        states["free_start"], states["free_end"] = _post_state(in_free[0]), _post_state(in_free[-1])
    out = dict(t=t, sv=sv, vv=vv, free=free, points=points,
               trajectory=Sampled(t, points, vv, states))
    tc, vc = t[~free], vv[~free]
    if tc.size >= 2:  # the deceleration over each accepted contact step; |VV| falling = +
        out["pulse_t"] = tc[1:]
        with np.errstate(divide="ignore", invalid="ignore"):
            out["pulse_g"] = -np.diff(np.abs(vc)) / np.diff(tc) / d["G"]
        out["contact_end_s"] = float(tc[-1])
    fs = [r["FS"] for r in in_contact if "FS" in r]
    if fs and d["WV"] * d["G"] != 0:
        out["max_decel_every_step_g"] = force_in_g(max(fs), d["WV"], d["G"])
    return out


def _printed_quantities(fields: dict, run, deck) -> list[str]:
    """What the report read off the printout, into ``fields``: the end of the crush pulse,
    the largest printed deceleration, the terminal points (``extract`` reads the records, as
    the report's authors read the paper); its notes."""
    from deck_emulator.legacy.extract import ExtractError, extract

    try:
        printed = extract(run.records, deck)
    except (ExtractError, ZeroDivisionError) as exc:  # said in the outcome's notes
        fields["notes"] = (f"the printout's own numbers could not be read "
                           f"({type(exc).__name__}: {exc}): the speed lost by the end of the "
                           "crush pulse, the largest printed deceleration and the terminal "
                           "points are not given",)
        return []
    fields.update(crush_end_s=printed.crush_pulse_end_s, max_decel_g=printed.max_decel_g,
                  terminal={k: (p.XL, p.YL, p.ZL) for k, p in printed.terminal.items()})
    return list(printed.notes)


def _listing_flags(out: Outcome) -> list[str]:
    """The core's outcome checks applied to what the listing printed (its hit, the terminal
    heights ZL, the speed lost), with the listing's own ground bands as tolerances."""
    from .quantities import speed_lost_at  # the registry: not for a plain run's printout

    from deck_emulator.core.checks import check_summary

    hit = out.hit
    return check_summary(
        hit=(f"{hit.surface.value} hit" if hit and hit.surface else None),
        hit_time_s=out.hit_time_s,
        heights_at_hit_ft={k: (p[2] if p[2] is not None else None)
                           for k, p in out.terminal.items()} if hit else None,
        delta_v_contact_mph=speed_lost_at(out, out.contact_end_s),
        car_speed_mph=out.speed_mph,
        max_decel_g=out.max_decel_g,
        no_hit_reason=None if hit else "the listing stopped without a hit message",
        ground_tolerance_ft=dict(defaults.LISTING_GROUND_TOLERANCE_FT),
        who="the listing",
    )


# ================================================================================= the core


#: the core's located events that are reported as events (its first of each); the hit is
#: reported from the result's own hit
_REPORTED = (EventKind.LOST_FIRST_SPRING, EventKind.LOST_VEHICLE, EventKind.FORCE_CAP)


def core_events(result) -> list[Event]:
    """The core's located events as :class:`Event`: those it names by an :class:`EventKind`
    that is reported (its other events -- normal force released, a leaf spring unloading, its
    sliding modes -- are its own business and stay in ``result.events``)."""
    events = []
    for e in result.events:
        kind = e.name if e.name in _REPORTED else None
        if kind is not None and not any(x.kind is kind for x in events):
            events.append(Event(EventKind(kind), e.time_s))
    if result.hit:
        hit = result.hit
        events.append(Event(EventKind.HIT, hit.time_s, Surface[hit.surface], hit.point,
                            fraction=hit.fraction, edge=tuple(Surface[s] for s in hit.edge)))
    return sorted(events, key=lambda e: e.time_s)


def _run_errors() -> tuple[type[Exception], ...]:
    """What ends one core run as an outcome with an ``error`` instead of raising: the core's
    ``CoreError`` (imported here: the plain emulator run needs no core), ``ValueError`` (a
    scene the core refuses: ``SceneError``), ``ArithmeticError``."""
    from deck_emulator.core import CoreError

    return (CoreError, ValueError, ArithmeticError)


@dataclass(frozen=True)
class CoreEngine:
    """The modern core. ``preset``: ``legacy`` (the listing's quirks) or ``physical``;
    ``options``: a :class:`~deck_emulator.vocabulary.scene.ModelOptions` instead of a preset;
    ``method`` (``auto``: DOP853, Radau for a stiff contact), ``rtol``, ``atol``: solve_ivp's;
    ``t_max_s``: simulated time at most, ``max_step_s``: the solver's largest step (the core's
    bound, so that no event function changes sign twice in one step; ``math.inf``: none),
    ``max_wall_s``: wall time at most, of one run or of a
    whole :meth:`run_batch` (None: the row ``MAX_WALL_S``, read as the run starts:
    :attr:`wall_bound_s`; every default: :mod:`deck_emulator.vocabulary.defaults`, the same
    for every door);
    ``sample_contact_s``, ``sample_free_s``: the grid the outcome's arrays are sampled on;
    ``trace``: sample them at all; ``arrays``: which of them
    (:data:`~deck_emulator.engine.quantities.ARRAYS`, default all; a study asks for what its
    quantities read: ``quantities.arrays_for``); ``shaft_contact``: True or False sets the option of that
    name (the shaft and arms checked against the car) over the preset's, None keeps it;
    ``batched``: how :meth:`run_batch` solves its scenes -- True: the compiled batched core
    (``deck_emulator.core.simulate_batch``), False: one :meth:`simulate` after another (the
    scipy path, the reference), None: the batched core when the package has it and ``method``
    is ``auto`` (it is its own method), else the scipy path; :meth:`run` takes the same path
    for its one scene (the batch's functions uncompiled where this process has not compiled
    them: the same numbers, no numba to load)."""

    preset: str = defaults.CORE_PRESET
    options: object = None
    shaft_contact: bool | None = None
    method: str = "auto"
    rtol: float = defaults.CORE_RTOL
    atol: float = defaults.CORE_ATOL
    t_max_s: float = defaults.T_MAX_S
    max_wall_s: float | None = None
    max_step_s: float = defaults.MAX_STEP_S
    sample_contact_s: float = defaults.SAMPLE_CONTACT_S
    sample_free_s: float = defaults.SAMPLE_FREE_S
    trace: bool = True
    arrays: tuple[str, ...] = defaults.OUTCOME_ARRAYS
    batched: bool | None = None
    name = "core"

    def model_options(self):
        from deck_emulator.vocabulary.scene import PRESETS

        opts = self.options if self.options is not None else PRESETS[self.preset]
        if self.shaft_contact is None or self.shaft_contact == opts.shaft_contact:
            return opts
        return opts.replace(shaft_contact=self.shaft_contact, name=opts.name + (
            "+shaft_contact" if self.shaft_contact else "-shaft_contact"))

    def scene(self, source):
        """The scene the core solves: ``source`` itself, or the deck's (a deck or a
        :class:`~deck_emulator.vocabulary.scene.DeckScene` the core cannot solve raises
        :class:`~deck_emulator.vocabulary.scene.SceneError` naming why)."""
        from deck_emulator.vocabulary.scene import Scene

        if isinstance(source, Scene):
            return source.checked()
        return Scene.from_deck(source, name=source_name(source))

    def simulate(self, source):
        """The core's own :class:`~deck_emulator.core.CoreResult` (raises CoreError); a post
        with two luminaires ends "R&U" when both reach the ground band together
        (:func:`~deck_emulator.core.pair_hits.joint_ground_hit`)."""
        from deck_emulator.core import simulate_batch
        from deck_emulator.core.pair_hits import joint_ground_hit

        if self.batched is False or self.method != "auto":
            return self.simulate_scipy(source)
        # the batch's path, the same numbers as in a batch; its functions as this process
        # has them (plain Python where nothing compiled them: no numba to load or compile)
        [result] = simulate_batch([self.scene(source)], self.model_options(), compile=False,
                                  **self._keywords())
        if isinstance(result, Exception):
            raise result
        return joint_ground_hit(result)

    def simulate_scipy(self, source):
        """:meth:`simulate` on the scipy path (``deck_emulator.core.simulate``)."""
        from deck_emulator.core import simulate
        from deck_emulator.core.pair_hits import joint_ground_hit

        return joint_ground_hit(simulate(self.scene(source), self.model_options(),
                                         **self._keywords()))

    def _keywords(self) -> dict:
        return dict(method=self.method, rtol=self.rtol, atol=self.atol, t_max_s=self.t_max_s,
                    max_step_s=self.max_step_s, max_wall_s=self.wall_bound_s)

    @property
    def wall_bound_s(self) -> float:
        """The wall-time bound a run started now gets (``max_wall_s``, else the defaults')."""
        return defaults.MAX_WALL_S if self.max_wall_s is None else self.max_wall_s

    def settings(self) -> str:
        opts = self.model_options()
        return f"preset {opts.name}; {self.method}, rtol {self.rtol:g}"

    def run(self, source, *, name: str = "", scene=None) -> Outcome:
        """Run ``source`` (a deck or a scene, or its name or file: :func:`given`); ``scene``:
        run this scene instead, keeping the deck ``source``'s name for the outcome (a deck
        with changes the deck cannot hold, such as the base's friction); the outcome carries
        the scene that ran."""
        source, stem = given(source, self.name)
        name = name or stem
        target = scene if scene is not None else source
        return self._run(target, name or source_name(source), lambda: self.simulate(target))

    def run_free_flight(self, scene, post, t0_s: float, *, car_position_ft: float = 0.0,
                        car_velocity_ft_s: float = 0.0, name: str = "") -> Outcome:
        """Free flight of ``scene``'s post from its motion ``post`` at ``t0_s`` (a
        :class:`~deck_emulator.vocabulary.scene.PostInitialState`, attitude from body to road axes)
        with the car at ``car_position_ft``, ``car_velocity_ft_s`` along XV, until the first
        hit or ``t_max_s``: the crash test's Table 9 starts from Table 8's state at 70 ms."""
        from deck_emulator.core import free_flight
        from deck_emulator.core.kinematics import state_vector

        state = state_vector(post, car_position_ft, car_velocity_ft_s)
        return self._run(scene, name, lambda: free_flight(
            scene, state, t0_s, self.model_options(), method=self.method,
            rtol=self.rtol, atol=self.atol, t_max_s=self.t_max_s, max_step_s=self.max_step_s,
            max_wall_s=self.wall_bound_s))

    def run_batch(self, sources, *, names=None) -> list[Outcome]:
        """``[self.run(s, name=n) for s, n in zip(sources, names)]``, the scenes solved
        together (:meth:`_simulate_many`: the compiled batched core where :attr:`batched`
        asks for it, else one after another).  Each outcome is made as :meth:`run` makes it
        (:meth:`_outcome`); a scene that cannot run is an outcome with its ``error``, as in
        :meth:`run`, and spoils none of the others.  ``names``: one per source (default: each
        source's own, :func:`source_name`).  An outcome's ``run_s`` is the scene's own time
        on the scipy path, the batch's time shared evenly on the batched one."""
        sources = list(sources)
        names = [""] * len(sources) if names is None else list(names)
        if len(names) != len(sources):
            raise ValueError(f"{len(names)} names for {len(sources)} scenes")
        errors = _run_errors()
        scenes: list = []  # the checked scene, or why there is none (as simulate raises it)
        for source in sources:
            try:
                scenes.append(self.scene(source))
            except errors as exc:
                scenes.append(exc)
        solved = self._simulate_many([s for s in scenes if not isinstance(s, Exception)])
        done = iter(solved)
        return [self._outcome(source, name or source_name(source),
                              *((scene, 0.0, "") if isinstance(scene, Exception) else next(done)))
                for source, name, scene in zip(sources, names, scenes)]

    def _batch_solver(self):
        """The compiled batched core's ``simulate_batch`` when :attr:`batched` asks for it and
        the package has it, else None (the scipy path).  ``batched=True`` without it is an
        error, not a silent fall-back."""
        if self.batched is False or (self.batched is None and self.method != "auto"):
            return None
        import deck_emulator.core as core

        solver = getattr(core, "simulate_batch", None)
        if solver is None and self.batched:
            raise ValueError("batched=True: this deck_emulator.core has no simulate_batch")
        return solver

    def _simulate_many(self, scenes: list) -> list[tuple[object, float, str]]:
        """THE plug-in point of :meth:`run_batch`: checked scenes -> one ``(CoreResult or
        the exception that ended it, seconds, note)`` per scene, in order.  The compiled core
        (:meth:`_batch_solver`) takes the whole list at once; a batch it cannot take as a
        whole (it raised, or answered for another number of scenes) runs again one scene at
        a time on the scipy path, so one bad scene costs the others nothing, and each of
        its outcomes says so in its notes (``note``: that fall-back and why; '' otherwise)."""
        from deck_emulator.core.pair_hits import joint_ground_hit

        if not scenes:
            return []
        errors = _run_errors()
        solver = self._batch_solver()
        note = ""
        if solver is not None:
            started = time.perf_counter()
            try:
                got = list(solver(scenes, self.model_options(), rtol=self.rtol,
                                  atol=self.atol, t_max_s=self.t_max_s,
                                  max_step_s=self.max_step_s, max_wall_s=self.wall_bound_s))
            except errors as exc:  # said in every outcome of the batch (note)
                got, why = None, f"{type(exc).__name__}: {exc}"
            else:
                why = f"it answered for {len(got)} of {len(scenes)} scenes"
            if got is not None and len(got) == len(scenes):
                each = (time.perf_counter() - started) / len(scenes)
                return [(r if isinstance(r, Exception) else joint_ground_hit(r), each, "")
                        for r in got]
            note = (f"the compiled batch could not take this batch of {len(scenes)} scenes "
                    f"({why}): this scene ran on the scipy path (solve_ivp), one scene at a "
                    "time")
        out = []
        for scene in scenes:
            started = time.perf_counter()
            try:
                r = self.simulate_scipy(scene)
            except errors as exc:
                r = exc
            out.append((r, time.perf_counter() - started, note))
        return out

    def _run(self, source, name: str, solve) -> Outcome:
        errors = _run_errors()
        started = time.perf_counter()
        try:
            r = solve()
        except errors as exc:
            r = exc
        return self._outcome(source, name, r, time.perf_counter() - started)

    def _outcome(self, source, name: str, r, run_s: float, note: str = "") -> Outcome:
        """THE one place a core result (or the exception that ended its run) becomes an
        :class:`Outcome` of ``source`` (a deck or a scene), for :meth:`run`,
        :meth:`run_free_flight` and :meth:`run_batch` alike; ``note``: how it was run, when
        not as asked (the compiled batch's fall-back), first among its notes."""
        from deck_emulator.vocabulary.scene import Scene

        from .outcome import Outcome
        from .trajectory import Dense

        if isinstance(source, Scene):
            scene = source
        elif not isinstance(r, Exception):  # the deck's scene as the core checked and ran it
            scene = r.scene
        else:  # the deck as it is (the core refused it, or its run stopped)
            scene = Scene.from_deck(source, name=source_name(source), checked=False)
        fields = dict(engine="core", name=name or source_name(source), scene=scene,
                      settings=self.settings(), arithmetic="IEEE double", run_s=run_s,
                      contact_test="segments" if self.model_options().shaft_contact
                      else "points", notes=(note,) if note else ())
        if isinstance(r, Exception):
            return Outcome(error=f"{type(r).__name__}: {r}", **fields)
        events = core_events(r)
        fields.update(
            hit_message=r.hit_message, trajectory=Dense(r), method=r.method,
            notes=fields["notes"] + tuple(getattr(r, "notes", ()) or ()),
            evaluations=r.nfev, end_s=r.end_time_s,
            engine_events=tuple((e.name, e.time_s) for e in r.events), events=events,
            contact_end_s=r.contact_end_s,
            max_decel_g=(r.max_decel_after_startup_g if r.max_decel_after_startup_g is not None
                         else r.max_decel_g),
            max_decel_every_step_g=r.max_decel_g,
            terminal={k: v for k, v in r.terminal_points_ft.items() if v is not None},
            crush_end_s=next((e.time_s for e in events if e.kind is EventKind.FORCE_CAP), None))
        if self.trace:
            fields.update(self._arrays(r, fields))
        return Outcome(**fields)

    def _arrays(self, r, fields: dict) -> dict:
        """The outcome's sampled arrays that :attr:`arrays` asks for, and no others (with the
        post's points, C at the hit among the ``terminal`` points)."""
        import numpy as np

        asked = set(self.arrays)
        if not asked <= set(defaults.OUTCOME_ARRAYS):
            raise ValueError(f"arrays {sorted(asked)}: not among {defaults.OUTCOME_ARRAYS}")
        out = {}
        if asked & {"car", "points"}:
            out.update(self._sampled(r, fields, points="points" in asked))
        if "pulse" in asked:
            t_f, force = r.trajectory.contact_force(self.sample_contact_s / 2)
            car, g = r.scene.vehicle, r.scene.environment.gravity_ft_s2
            out["pulse_t"] = t_f
            if car is None:
                out["pulse_g"] = np.zeros(0)
            else:  # force on the car along +XV; the car moves towards -XV when VVB < 0
                sign = 1.0 if car.initial_velocity_ft_s < 0 else -1.0
                out["pulse_g"] = force_in_g(force, car.mass_slug, g) * sign
        return out

    def _sampled(self, r, fields: dict, *, points: bool) -> dict:
        """``t``, ``sv``, ``vv``, ``free`` on the sampling grid; with ``points`` the post's
        points on it and C at the hit."""
        import numpy as np

        from .trajectory import SAMPLED_POINTS

        traj = r.trajectory
        t_end = float(traj.t_end)
        lost = next((e.time_s for e in fields["events"] if e.kind is EventKind.LOST_VEHICLE),
                    None)
        t_c = lost if lost is not None else t_end
        edges = [s.t0 for s in traj.segments] + [s.t1 for s in traj.segments]
        t0 = float(traj.t_start)  # 0, or where a free flight was started
        grid = np.concatenate([np.arange(t0, t_c, self.sample_contact_s),
                               np.arange(t_c, t_end, self.sample_free_s), edges, [t_c, t_end]])
        t = np.unique(np.clip(grid, t0, t_end))
        state = traj.state(t)  # evaluated once for the points, the mass centre and the car
        out = dict(t=t, sv=state[13].copy(), vv=state[14].copy(), free=t > t_c + 1e-12)
        if not points:
            return out
        kept = [k for k in SAMPLED_POINTS if k in traj.point_names]
        pts = {k: np.ascontiguousarray(np.asarray(p).T)
               for k, p in traj.points_of(state, kept).items()}
        pts["CM"] = np.ascontiguousarray(state[0:3].T)
        out["points"] = pts
        hit_s = r.hit_time_s
        if "C" in pts and hit_s is not None:
            scene = fields["scene"]
            base, ground = scene.post.base, scene.environment.ground_depth_ft
            c = traj.point("C", min(hit_s, t_end)) - np.array([base.xx_ft, base.yy_ft, -ground])
            out["terminal"] = {**fields["terminal"], "C": tuple(float(x) for x in c)}
        return out


def compile_core(wait) -> None:
    """Numba compiles the core at its first use after an install (or an upgrade), a wait no
    progress can count: compile it here, once, by solving the report's steel post on the
    compiled batch inside ``wait()`` (a context manager that says the wait), so that a
    study's workers load the cache instead of each compiling it at the same time.  A marker
    in numba's cache of the core (:func:`deck_emulator.core.compiled_cache_folder`) says it
    was done; where none can be written numba compiles in each process, as it must.  Once
    done, this process imports no numba: a study's workers run the core, not the command
    (what numba costs a command: docs/scale.md)."""
    from importlib.metadata import version

    from deck_emulator.core import compiled_cache_folder

    marker = os.path.join(compiled_cache_folder(), f"compiled-numba{version('numba')}-py"
                          f"{sys.version_info[0]}{sys.version_info[1]}")
    if os.path.exists(marker):
        return
    with wait():
        load_core()
    try:
        open(marker, "a").close()
    except OSError:
        pass


def load_core() -> None:
    """The compiled core in this process: the report's steel post solved once on the
    compiled batch (numba loads its machine code from the cache, or compiles it there)."""
    CoreEngine(batched=True, trace=False).run_batch([load_source(decks.path("steel40")).deck()])


def core_keywords(preset: str, shaft_contact: bool | None = None) -> dict:
    """:class:`CoreEngine`'s keywords for a preset and the command line's ``--shaft-contact``
    (``shaft_contact`` left out when None: the preset's, and a stored task keeps its key)."""
    return {"preset": preset, **({} if shaft_contact is None else
                                 {"shaft_contact": bool(shaft_contact)})}


def engine_for(name: str, **options):
    """``engine_for("emulator", errata=(...))`` or ``engine_for("core", preset=...)``."""
    if name == "emulator":
        return EmulatorEngine(**options)
    if name == "core":
        return CoreEngine(**options)
    raise ValueError(f"unknown engine {name!r}: {ENGINES}")

