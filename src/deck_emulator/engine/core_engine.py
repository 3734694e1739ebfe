"""The modern core (``deck_emulator.core``) behind the engine interface: :class:`CoreEngine`
runs a deck or a typed scene and makes its :class:`~deck_emulator.engine.outcome.Outcome`.

Apart from :mod:`.engines` (the emulator's), so that a plain ``deck-emulator run`` does not
define a class it never uses at every start.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass

from deck_emulator import decks
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.events import Event, EventKind, Surface
from deck_emulator.vocabulary.units import force_in_g

from .sources import given, load_source, source_name

# (typing.TYPE_CHECKING's value at run time, without importing typing at the start)
TYPE_CHECKING = False
if TYPE_CHECKING:
    from .outcome import Outcome


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
    method: str = defaults.CORE_METHOD
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
