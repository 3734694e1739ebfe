"""The two engines behind one interface: ``engine.run(source) -> Outcome``.

* :class:`EmulatorEngine` -- the 1967 program (``deck_emulator.legacy``) on a card deck, in
  one of its arithmetics, with the errata the user named (:mod:`.errata`);
* :class:`~.core_engine.CoreEngine` -- the modern core (``deck_emulator.core``) on a deck or
  a typed scene, in :mod:`.core_engine`.

:func:`engine_for` names both.  An engine never raises for a run that
cannot end: the :class:`~deck_emulator.engine.outcome.Outcome` says why (``error``) and keeps
what was computed up to then.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from deck_emulator.legacy.arithmetic import get_arithmetic
from deck_emulator.legacy.fortran import STEP_LITERALS, listing_program
from deck_emulator.legacy.stops import EmulatorError, Limits
from deck_emulator.legacy.printer import event_message
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.choices import ENGINES
from deck_emulator.vocabulary.events import EventKind

from . import errata as errata_policy
from .sources import given, source_name

# Outcome (and with it numpy) is imported where an outcome is made, not here: the plain
# `deck-emulator run` prints the program's records (EmulatorEngine.execute) and needs neither.
# (typing.TYPE_CHECKING's value at run time, without importing typing at the start)
TYPE_CHECKING = False
if TYPE_CHECKING:
    from .outcome import Outcome



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
    ed_tolerance: str = defaults.LISTING_ED_TOLERANCE
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

    def run(self, deck, *, name: str = "", watch=None, scene=None) -> Outcome:
        """``deck`` (or its name, or a file: :func:`given`) run; ``watch``: as
        :meth:`execute`; ``scene``: as :meth:`outcome_of`."""
        deck, stem = given(deck, self.name)
        return self.outcome_of(self.execute(deck, watch=watch), deck, name=name or stem,
                               scene=scene)

    def outcome_of(self, done: "Execution", deck, *, name: str = "", scene=None) -> Outcome:
        """The :class:`Outcome` of an :meth:`execute` of ``deck``, made once; ``scene``: the
        deck's scene where the caller has built it (else it is built here)."""
        import dataclasses

        from deck_emulator.vocabulary.scene import Scene

        from .outcome import Outcome
        from .trajectory import Sampled

        run, name = done.run, name or source_name(deck)
        d = dict(deck.values)
        events = tuple(run.events)
        hit = next((e for e in events if e.kind is EventKind.HIT), None)
        fields = dict(
            engine="emulator", name=name,
            scene=scene or Scene.from_deck(deck, name=name, checked=False),
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
        states, every_step_fs = {}, None
        if self.trace and run.trace:
            arrays, states, every_step_fs = _emulator_arrays(run.trace, d)
            fields.update(arrays)
        printed_notes, printed_fsa = _printed_quantities(fields, run, deck)
        # the largest printed FSA (as the report read it) and the largest over every step:
        # the forces the registry turns into decelerations
        fields["trajectory"] = Sampled(fields.get("t", ()), fields.get("points", {}),
                                       fields.get("vv", ()), states,
                                       peak_forces_lb=(printed_fsa, every_step_fs))
        out = Outcome(**fields)
        flags = _listing_flags(out) if run.error is None else []
        flags += [n for n in printed_notes if "overflow" in n]  # a field printed as ****
        return dataclasses.replace(out, flags=tuple(flags)) if flags else out


def _post_state(row):
    from .trajectory import PostState

    return PostState((row["V1"], row["V2"], row["V3"]), (row["W1"], row["W2"], row["W3"]),
                     row["ZZCM"])


def _emulator_arrays(rows, d) -> tuple[dict, dict, float | None]:
    """The outcome's fields read from the program's trace (its accepted steps as arrays, the
    deceleration over each contact step, the end of the contact), the post's motion at the
    instants the run has, and the largest spring force FS over every contact step (lb)."""
    import numpy as np  # here, not at the top: a run without a trace (deck-emulator run) needs none

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
    out = dict(t=t, sv=sv, vv=vv, free=free, points=points)
    tc, vc = t[~free], vv[~free]
    if tc.size >= 2:  # the deceleration over each accepted contact step; |VV| falling = +
        out["pulse_t"] = tc[1:]
        with np.errstate(divide="ignore", invalid="ignore"):
            out["pulse_g"] = -np.diff(np.abs(vc)) / np.diff(tc) / d["G"]
        out["contact_end_s"] = float(tc[-1])
    fs = [r["FS"] for r in in_contact if "FS" in r]
    return out, states, (max(fs) if fs else None)


def _printed_quantities(fields: dict, run, deck) -> tuple[list[str], float | None]:
    """What the report read off the printout, into ``fields``: the end of the crush pulse and
    the terminal points (``extract`` reads the records, as the report's authors read the
    paper); its notes, and the largest FSA printed (lb)."""
    from deck_emulator.legacy.extract import ExtractError, extract

    try:
        printed = extract(run.records, deck)
    except ExtractError as exc:  # said in the outcome's notes
        fields["notes"] = (f"the printout's own numbers could not be read "
                           f"({type(exc).__name__}: {exc}): the speed lost by the end of the "
                           "crush pulse, the largest printed deceleration and the terminal "
                           "points are not given",)
        return [], None
    fields.update(crush_end_s=printed.crush_pulse_end_s,
                  terminal={k: (p.XL, p.YL, p.ZL) for k, p in printed.terminal.items()})
    return list(printed.notes), printed.max_fsa_lb


def _listing_flags(out: Outcome) -> list[str]:
    """The core's outcome checks applied to what the listing printed (its hit, the terminal
    heights ZL, the speed lost), with the listing's own ground bands as tolerances."""
    from .quantities import speed_lost_at, value  # the registry: not for a plain run's printout

    from deck_emulator.core.checks import check_summary

    hit = out.hit
    return check_summary(
        hit=(f"{hit.surface.value} hit" if hit and hit.surface else None),
        hit_time_s=out.hit_time_s,
        heights_at_hit_ft={k: (p[2] if p[2] is not None else None)
                           for k, p in out.terminal.items()} if hit else None,
        delta_v_contact_mph=speed_lost_at(out, out.contact_end_s),
        car_speed_mph=out.speed_mph,
        max_decel_g=value("max_decel_g", out),
        no_hit_reason=None if hit else "the listing stopped without a hit message",
        ground_tolerance_ft=dict(defaults.LISTING_GROUND_TOLERANCE_FT),
        who="the listing",
    )


def engine_for(name: str, **options):
    """``engine_for("emulator", errata=(...))`` or ``engine_for("core", preset=...)``."""
    if name == "emulator":
        return EmulatorEngine(**options)
    if name == "core":
        from .core_engine import CoreEngine

        return CoreEngine(**options)
    raise ValueError(f"unknown engine {name!r}: {ENGINES}")

