"""The commands that answer with one run's outcome: ``summary``, ``core``, ``scene``, ``diff``,
``assembly`` and ``plot``."""

from __future__ import annotations

from dataclasses import dataclass

from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.vocabulary import defaults

from . import Answer, command
from . import common
from .options import (ENGINES, PRECISIONS, SOURCE_HELP, VIEWS, Answering, Cluster, Common, Emulator,
                      Errata, Preset, Source, angle_deg, max_k, option, positive_float,
                      speed_mph, tolerance)

_TRAJECTORY_HELP = ("also write the run's trajectory: time, every named point (road and report "
                    "axes), the shaft's tilt and heading, the car (pandas reads it)")


def _outcome_answer(name: str, out, source: str, settings: dict, o) -> Answer:
    """An outcome as the answer of ``summary``, ``core`` or ``assembly`` (its text made by
    :func:`_rendered` once the caller's notes are in): the registry's quantities, and for a
    run that stopped what it reached, status ``stopped``, and why."""
    from deck_emulator.present.answers import outcome_result

    answer = Answer(name, source, settings=settings, result=outcome_result(out),
                    notes=common.odd_deck_notes(out), json=o.json, out=o.out)
    if out.error is not None:  # what it reached is answered; the status says it stopped
        answer.status, answer.error = "stopped", common.failed(out, source)
    return answer


# ---------------------------------------------------------------------------------- summary


@dataclass(frozen=True, kw_only=True)
class SummaryOptions(Emulator, Answering):
    trajectory: str | None = option(None, metavar="FILE.csv|FILE.parquet", help=_TRAJECTORY_HELP)


def _summary_description() -> str:
    from deck_emulator.engine.quantities import definitions_help

    return ("Run the emulated program and print what the report's Tables 11 and 12 give: the "
            "events as sentences, the hit, the car's speed change in mph, the largest printed "
            "deceleration in g, P, Q, R at the hit in XL, YL, ZL; then the occupant-risk numbers "
            "and the cited limits they are judged by. The two speed changes: "
            + definitions_help() + ". --json: the same as one JSON object (docs/json.md).")


@command("summary", SummaryOptions,
         help="run a deck and print its outcomes (events, hit, delta-V, deceleration, P/Q/R)",
         description=_summary_description)
def summary(o: SummaryOptions) -> Answer:
    from deck_emulator.engine import errata

    src = common.load(o, "summary", kinds=("deck",))
    deck = src.deck("summary")
    common.check_out(o.out)
    common.check_trajectory(o.trajectory)
    engine = common.emulator(o)
    out = common.with_progress(o.quiet, engine, deck)
    written = common.write_trajectory(o.trajectory, out)
    settings = {"arithmetic": engine.arithmetic().describe(),
                "assumptions": dict(getattr(engine.arithmetic(), "assumptions", {}) or {}),
                "errata": errata.describe(out.errata)}
    if not settings["assumptions"]:
        settings.pop("assumptions")
    answer = _outcome_answer("summary", out, str(deck.path), settings, o)
    answer.notes += list(out.flags)
    answer.text = _rendered(answer)
    answer.said = list(src.notes) + ([written] if written else [])
    return answer


def _rendered(answer: Answer) -> str:
    from deck_emulator.present.answers import render_outcome

    return render_outcome(answer.document())


# ------------------------------------------------------------------------------------- core


@dataclass(frozen=True, kw_only=True)
class CoreOptions(Source, Preset, Answering):
    method: str = option(defaults.CORE_METHOD,
                         choices=("auto", "DOP853", "RK45", "Radau", "BDF", "LSODA"),
                         help="solve_ivp's method; auto (the default): DOP853, or Radau for the "
                         "contact when the scene's springs make it stiff (the outcome says which)")
    rtol: float = option(defaults.CORE_RTOL, parse=tolerance,
                         help="relative tolerance, 0 < RTOL < 1 (default %(default)g)")
    atol: float = option(defaults.CORE_ATOL, parse=tolerance,
                         help="absolute tolerance, 0 < ATOL < 1 (default %(default)g)")
    max_time: float = option(defaults.T_MAX_S, parse=positive_float, metavar="S",
                             help="stop when simulated time passes S seconds (default "
                             "%(default)s)")
    max_wall: float = option(defaults.MAX_WALL_S, parse=positive_float, metavar="S",
                             help="stop when the run has taken S seconds of wall time "
                             "(default %(default)s)")
    trajectory: str | None = option(None, metavar="FILE.csv|FILE.parquet", help=_TRAJECTORY_HELP)


@command("core", CoreOptions, help="solve a deck or a scene (.toml) with the modern core",
         description="The same model solved with quaternions, solve_ivp and located events. "
         "Presets: legacy (the listing's quirks) or physical (none).")
def core(o: CoreOptions) -> Answer:
    from deck_emulator.engine import CoreEngine
    from deck_emulator.vocabulary.scene import overridden_fields

    common.require("core")
    src = common.load(o, "core")
    source = src.scene_or_deck("core")
    common.engine_scene(source)  # a deck the core cannot solve: exit 2 before any work
    common.check_out(o.out)
    common.check_trajectory(o.trajectory)
    engine = CoreEngine(**o.core_keywords(), method=o.method, rtol=o.rtol, atol=o.atol,
                        t_max_s=o.max_time, max_wall_s=o.max_wall)
    set_aside = (overridden_fields(source, engine.model_options()) if src.kind == "scene"
                 else [])  # a scene file's field the preset overrides: said, never silent
    out = common.with_progress(o.quiet, engine, source)
    written = common.write_trajectory(o.trajectory, out)
    used = out.method or o.method
    settings = {**o.core_keywords(),
                "method": f"{used} (auto)" if o.method == "auto" and out.method else used,
                "rtol": o.rtol, "atol": o.atol}
    answer = _outcome_answer("core", out, src.name, settings, o)
    answer.notes += set_aside + list(out.notes)
    if out.error is None and out.hit_message is None:  # a run that could not end: exit 3
        answer.status = "stopped"
        answer.error = (f"{src.name}: simulated time passed the limit of {o.max_time:g} s "
                        "(--max-time) with no hit: the post has not landed")
        answer.notes.append(answer.error)
    answer.text = _rendered(answer)
    answer.said = list(src.notes) + set_aside + ([written] if written else [])
    return answer


# ------------------------------------------------------------------------------------ scene


@dataclass(frozen=True, kw_only=True)
class SceneOptions(Source):
    out: str | None = option(None, metavar="FILE", help="write to FILE instead of stdout")
    json: bool = option(False, help="print the scene (the TOML's tables) as one JSON object "
                        "(docs/json.md)")


@command("scene", SceneOptions,
         help="write a deck's scene as TOML (to edit by hand, then `core`)")
def scene(o: SceneOptions) -> Answer:
    import tomllib

    src = common.load(o, "scene")
    made = common.engine_scene(src.scene_or_deck("scene"), name=src.stem)
    common.check_out(o.out)
    text = made.to_toml()
    return Answer("scene", src.name, notes=list(src.notes), said=list(src.notes),
                  result={"scene": tomllib.loads(text)} if o.json else {}, text=text,
                  json=o.json, out=o.out)


# ------------------------------------------------------------------------------------- diff


@dataclass(frozen=True, kw_only=True)
class DiffOptions(Source, Errata, Cluster, Answering):
    precision: str = option("double", choices=PRECISIONS,
                            help="the emulator's arithmetic at k = 0 (must run the deck to its "
                            "end)")
    max_k: int = option(4, parse=max_k, metavar="K",
                        help="halve the step up to K times, 0 <= K <= 8 (default 4; K = 8 runs "
                        "the listing's 2,054 steps 256 times over)")
    rtol: float = option(defaults.CORE_RTOL, parse=tolerance,
                         help="the core's tolerance, rtol = atol, 0 < RTOL < 1 (default "
                         "%(default)g)")
    as_printed_ed: bool = option(False, help="keep ED's tolerance .0001 at every k (the scheme "
                                 "then does not converge)")
    store: str | None = option(None, metavar="DIR",
                               help="keep the runs in DIR as they finish (default: a temporary "
                               "folder)")


@command("diff", DiffOptions,
         help="run the emulator and the modern core on a deck and compare them",
         description="Side by side: the emulator (the listing as printed, or with errata) and "
         "the core's legacy preset; then both again as the step is halved k = 0..K times, with "
         "the observed order of convergence.")
def diff(o: DiffOptions) -> Answer:
    common.require("studies")
    from deck_emulator.studies.diff import DiffStopped, diff_deck, format_diff

    src = common.load(o, "diff", kinds=("deck",))
    deck = src.deck("diff")
    common.engine_scene(deck, name=src.name)  # the core must be able to solve it: exit 2
    common.check_out(o.out)
    if o.resume and not o.store:
        raise UsageError("--resume needs --store DIR (the folder the runs were stored in)")
    try:
        data = diff_deck(deck, precision=o.precision, errata=tuple(o.erratum),
                         ks=range(o.max_k + 1), rtol=o.rtol, atol=o.rtol,
                         tighten_ed=not o.as_printed_ed, jobs=o.jobs,
                         scheduler=common.scheduler(o), store_dir=o.store, resume=o.resume,
                         quiet=o.quiet, desc="deck-emulator: diff")
    except DiffStopped as exc:
        raise RunFailed(str(exc)) from None
    text = format_diff(data)
    settings = {k: data.pop(k) for k in ("precision", "errata", "core_method", "core_rtol",
                                         "ed_tolerance_scaled")}
    data.pop("deck")
    return Answer("diff", src.name, settings=settings, notes=list(src.notes),
                  said=list(src.notes), result=data, text=text, json=o.json, out=o.out)


# --------------------------------------------------------------------------------- assembly


@dataclass(frozen=True, kw_only=True)
class AssemblyOptions(Common, Errata, Preset):
    description: str = option(positional=True, metavar="NAME_OR_TOML",
                              help="steel, aluminium, twin, crash_test, or a description file "
                              "(.toml)")
    what: str = option("props", positional=True,
                       choices=("props", "deck", "scene", "core", "emulator"),
                       help="what to print or run (default props)")
    speed_mph: float = option(40.0, parse=speed_mph, metavar="MPH",
                              help="the car's speed in mph, any from 1 to 200 (default 40; the "
                              "report's 20 and 40 take its own decks' car)")
    alpha_deg: float = option(0.0, parse=angle_deg, metavar="DEG",
                              help="the approach angle in degrees, 0 to 89 (default 0; the "
                              "report ran 0, 15 and 30)")
    json: bool = option(False, help="print what it prints as one JSON object (with core: the "
                        "outcome, as deck-emulator core --json)")
    out: str | None = option(None, metavar="FILE", help="write to FILE instead of stdout")


def _ms(t_s) -> str:
    return "no time" if t_s is None else f"{1000.0 * t_s:.1f} ms"


@command("assembly", AssemblyOptions,
         help="build, print or run a support assembly from a description file",
         description="NAME is a shipped description (steel, aluminium, twin, crash_test) or a "
         ".toml file. WHAT: props (mass properties and points), deck (the 8-card deck; one "
         "arm only), scene (TOML), core (run the core), emulator (run the listing).")
def assembly(o: AssemblyOptions) -> Answer:
    """Build a support assembly (or the crash test) from a description file and print its
    mass properties, its deck, its scene, or run it."""
    import math
    import tomllib

    from deck_emulator.core import assembly as asm
    from deck_emulator.engine import assemblies as bridge

    def answer(text, **result):
        return Answer("assembly", o.description, settings={
            "what": o.what, "speed_mph": o.speed_mph, "alpha_deg": o.alpha_deg},
            result=result, text=text, json=o.json, out=o.out)

    try:
        a, extra, _ = asm.load_assembly(o.description)
    except (asm.AssemblyError, OSError) as exc:
        raise UsageError(str(exc)) from None
    if a is None:  # the crash test
        from deck_emulator.studies import crash_test as ct

        scene_ = ct.crash_scene(extra["crash_test"])  # the description's own crash test
        if o.what == "scene":
            return answer(scene_.to_toml(), scene=tomllib.loads(scene_.to_toml()))
        if o.what in ("deck", "emulator"):
            raise UsageError(f"cannot run on the listing: {asm.scene_runs_on_listing(scene_)}")
        res, loss, r70 = ct.table10(scene_)  # res: the run's Outcome
        rows = [f"{k}: at loss of contact {loss[k]:.4f}, at 70 ms {r70[k]:.4f}" for k in loss]
        return answer(f"hit: {res.hit_message} at {_ms(res.hit_time_s)}\n" + "\n".join(rows)
                      + "\n", hit={"message": res.hit_message, "time_s": res.hit_time_s},
                      at_loss_of_contact=loss, at_70_ms=r70)
    # the car: the report's deck of that speed and angle where there is one, else steel40's
    # car with VVB and ALPHA set by the sweep's rules (the report's deck's decimals)
    from deck_emulator.studies.sweep import car_at

    template, car = car_at(o.speed_mph, o.alpha_deg)
    mp = asm.mass_properties(a)
    if o.what == "props":
        lines = [f"{a.name}: weight {mp.weight_lb:.2f} lb, W {mp.mass_slug:.5f} slug, wall "
                 f"{mp.wall_in:.4f} in, A {mp.A:.2f}, B {mp.B:.2f}, C {mp.C:.3f} slug ft^2, "
                 f"delta {mp.delta_rad:.5f} rad ({math.degrees(mp.delta_rad):.3f} deg), mass "
                 f"centre {mp.cm_height_ft:.3f} ft above Q, {mp.cm_offset_ft:.3f} ft in YY "
                 "from the axis"]
        lines += [f"  {k}: ({p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f}) ft" for k, p in mp.points.items()]
        return answer("\n".join(lines) + "\n", name=a.name, weight_lb=mp.weight_lb,
                      mass_slug=mp.mass_slug, wall_in=mp.wall_in,
                      inertia_slug_ft2=[mp.A, mp.B, mp.C], delta_rad=mp.delta_rad,
                      cm_height_ft=mp.cm_height_ft, cm_offset_ft=mp.cm_offset_ft,
                      points_ft={k: list(p) for k, p in mp.points.items()})
    scene_ = bridge.to_scene(a, mp, template=template, **car)
    if o.what == "scene":
        return answer(scene_.to_toml(), scene=tomllib.loads(scene_.to_toml()))
    reason = asm.scene_runs_on_listing(scene_)
    if o.what in ("deck", "emulator") and reason is not None:
        raise UsageError(f"cannot run on the listing: {reason}")
    if o.what == "deck":
        values = bridge.to_deck_values(a, mp, template=template, **car)
        return answer(bridge.to_deck_text(values), values=values,
                      cards=bridge.to_deck_text(values).splitlines())
    if o.what == "emulator":
        from deck_emulator.engine import EmulatorEngine
        from deck_emulator.legacy.deck import parse_deck

        deck = parse_deck(bridge.to_deck_text(bridge.to_deck_values(a, mp, template=template,
                                                                    **car)))
        out = EmulatorEngine(errata=tuple(o.erratum), trace=False).run(deck)
        done = answer(out.printout, records=list(out.records))
        if out.error:
            done.status, done.error = "stopped", common.stopped(out)
            done.notes = [common.stopped(out)]
        return done
    from deck_emulator.engine import CoreEngine

    out = CoreEngine(**o.core_keywords()).run(scene_, name=a.name)
    settings = {**o.core_keywords(), "method": out.method,
                "car": f"{o.speed_mph:g} mph at {o.alpha_deg:g} deg ({template}'s car"
                       + (", VVB and ALPHA set)" if car else ")")}
    done = _outcome_answer("assembly", out, a.name, settings, o)
    done.notes += list(out.notes)
    if out.error is not None:
        done.error = common.failed(out, o.description)
    done.text = _rendered(done)
    return done


# ------------------------------------------------------------------------------------- plot


@dataclass(frozen=True, kw_only=True)
class PlotOptions(Source, Errata, Preset):
    source: str = option(positional=True, metavar="SOURCE",
                         help=SOURCE_HELP + "; a scene with --engine core")
    out: str = option(metavar="FILE.png", required=True,
                      help="the picture to write: .png, .svg, .pdf (any format matplotlib "
                      "writes)")
    engine: str = option("emulator", choices=ENGINES,
                         help="which engine's run to draw (default emulator)")
    view: str = option("side", choices=VIEWS, help="which view (default side)")
    pulse: bool = option(False, help="draw the vehicle pulse (both engines) instead of the "
                         "trajectory")
    animate: str | None = option(None, metavar="FILE.gif",
                                 help="also write the fall as an animated GIF (.mp4 if ffmpeg "
                                 "is installed)")
    every: float | None = option(None, parse=positive_float, metavar="MS",
                                 help="draw the post every MS milliseconds (default: about 20 "
                                 "instants)")
    quiet: bool = option(False, help="no progress display on stderr (shown only on a terminal)")
    json: bool = option(False, help="print what was drawn and written as one JSON object "
                        "(docs/json.md)")


@command("plot", PlotOptions,
         help="draw the post's fall (side, plan, 3-d), the vehicle pulse, or an animation",
         description="Draw the post as a line through its named points at regular instants in "
         "the report's XL, YL, ZL axes, with the ground, the car at the hit and the hit point "
         "(--view side|plan|3d|all); or, with --pulse, the car's deceleration and speed over "
         "the contact for both engines. The emulator runs the listing as printed unless "
         "--erratum names an erratum. Exit status 3 if a run stopped early (the picture shows "
         "what it computed).")
def plot(o: PlotOptions) -> Answer:
    from deck_emulator.parallel import busy
    from deck_emulator.present.plot import check_plot_outputs, draw

    common.require("plot")
    check_plot_outputs(o.out, o.animate)
    if o.animate and (o.view in ("3d", "all") or o.pulse):
        raise UsageError(f"--animate draws the side or the plan view, not "
                         f"{'the pulse' if o.pulse else '--view ' + o.view}: give "
                         "--view side or --view plan")
    name = "plot" + (" --pulse" if o.pulse else "")
    emulator = o.engine != "core" or o.pulse
    src = common.load(o, name, kinds=("deck",) if emulator else ("deck", "scene"))
    options = {"emulator": {"errata": tuple(o.erratum)}, "core": o.core_keywords()}
    with busy("deck-emulator: plot", quiet=o.quiet):
        drawn = draw(src.scene_or_deck(name), src.name, engine=o.engine, options=options,
                     out=o.out, view=o.view, pulse=o.pulse, animate=o.animate, every_ms=o.every)
    return Answer("plot", src.name, status="stopped" if drawn.stopped else "ok",
                  settings={"engine": o.engine, "view": o.view, "pulse": o.pulse,
                            "errata": list(o.erratum), "preset": o.preset},
                  notes=list(src.notes), said=list(src.notes) + drawn.said,
                  result={"outputs": [o.out] + ([o.animate] if o.animate else [])},
                  json=o.json)
