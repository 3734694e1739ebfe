"""``deck-emulator assembly``: build, print or run a support assembly from a description file."""

from __future__ import annotations

import math

from deck_emulator.errors import UsageError
from deck_emulator.vocabulary import defaults

from . import Answer, command, common
from .groups import Preset
from .options import Common, Errata, angle_deg, option, options_class, speed_mph


@options_class
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
                              help="the approach angle in degrees, 0 to "
                              f"{defaults.MAX_APPROACH_ANGLE_DEG:g} (default 0; the report ran "
                              "0, 15 and 30)")
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
    import tomllib

    from deck_emulator.core import assembly as asm
    from deck_emulator.engine import assemblies as bridge

    def answer(text, **result):
        return Answer("assembly", o.description, settings={
            "what": o.what, "speed_mph": o.speed_mph, "alpha_deg": o.alpha_deg},
            result=result, text=text, json=o.json, out=o.out)

    def scene_answer(scene_):
        text = scene_.to_toml()
        return answer(text, scene=tomllib.loads(text))

    try:
        a, extra, _ = asm.load_assembly(o.description)
    except (asm.AssemblyError, OSError) as exc:
        raise UsageError(str(exc)) from None
    if a is None:  # the crash test
        from deck_emulator.studies import crash_test as ct

        scene_ = ct.crash_scene(extra["crash_test"])  # the description's own crash test
        if o.what == "scene":
            return scene_answer(scene_)
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
    # the scene and its deck's values made together: the template deck read once
    scene_, values = bridge.scene_and_deck_values(a, mp, template=template, **car)
    if o.what == "scene":
        return scene_answer(scene_)
    reason = asm.scene_runs_on_listing(scene_)
    if o.what in ("deck", "emulator") and reason is not None:
        raise UsageError(f"cannot run on the listing: {reason}")
    if o.what in ("deck", "emulator"):  # it runs on the listing: one arm, so its values
        text = bridge.to_deck_text(values)
    if o.what == "deck":
        return answer(text, values=values, cards=text.splitlines())
    if o.what == "emulator":
        from deck_emulator.engine import EmulatorEngine
        from deck_emulator.legacy.deck import parse_deck

        deck = parse_deck(text)
        out = EmulatorEngine(errata=tuple(o.erratum), trace=False).run(deck, scene=scene_)
        done = answer(out.printout, records=list(out.records), deck=dict(deck.values))
        if out.error:
            done.status, done.error = "stopped", common.stopped(out)
            done.notes = [common.stopped(out)]
        return done
    from deck_emulator.engine import CoreEngine

    out = CoreEngine(**o.core_keywords()).run(scene_, name=a.name)
    settings = {**o.core_keywords(), "method": out.method,
                "car": f"{o.speed_mph:g} mph at {o.alpha_deg:g} deg ({template}'s car"
                       + (", VVB and ALPHA set)" if car else ")")}
    done = common.outcome_answer("assembly", out, a.name, settings, o)
    done.result["deck"] = scene_.deck_values()  # the post run: the deck's values (one post)
    done.notes += list(out.notes)
    if out.error is not None:
        done.error = common.failed(out, o.description)
    done.text = common.rendered(done)
    return done
