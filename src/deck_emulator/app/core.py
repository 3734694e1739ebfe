"""``deck-emulator core``: solve a deck or a scene (.toml) with the modern core."""

from __future__ import annotations

from deck_emulator.vocabulary import defaults

from . import Answer, command
from . import common
from .groups import Preset, SceneSource
from .options import (Answering, option, options_class, positive_float, tolerance,
                      trajectory_option)


@options_class
class CoreOptions(SceneSource, Preset, Answering):
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
    trajectory: str | None = trajectory_option()


@command("core", CoreOptions, one_scene=True,
         help="solve a deck or a scene (.toml) with the modern core",
         description="The same model solved with quaternions, solve_ivp and located events. "
         "Presets: legacy (the listing's quirks) or physical (none).")
def core(o: CoreOptions) -> Answer:
    from deck_emulator.engine import CoreEngine
    from deck_emulator.vocabulary.scene import overridden_fields

    common.require("core")
    src = common.load(o, "core")
    source = src.scene_or_deck("core")
    # the scene the core solves, built once; a deck the core cannot solve: exit 2 before any work
    scene = common.engine_scene(source, scene_name=src.stem)
    common.check_out(o.out)
    common.check_trajectory(o.trajectory)
    engine = CoreEngine(**o.core_keywords(), method=o.method, rtol=o.rtol, atol=o.atol,
                        t_max_s=o.max_time, max_wall_s=o.max_wall)
    set_aside = (overridden_fields(source, engine.model_options()) if src.kind == "scene"
                 else [])  # a scene file's field the preset overrides: said, never silent
    out = common.with_progress(o.quiet, engine, source, scene=scene)
    written = common.write_trajectory(o.trajectory, out)
    used = out.method or o.method
    settings = {**o.core_keywords(),
                "method": f"{used} (auto)" if o.method == "auto" and out.method else used,
                "rtol": o.rtol, "atol": o.atol}
    answer = common.outcome_answer("core", out, src.name, settings, o)
    answer.notes += set_aside + list(out.notes)
    if out.error is None and out.hit_message is None:  # a run that could not end: exit 3
        answer.status = "stopped"
        answer.error = (f"{src.name}: simulated time passed the limit of {o.max_time:g} s "
                        "(--max-time) with no hit: the post has not landed")
        answer.notes.append(answer.error)
    answer.text = common.rendered(answer)
    answer.said = list(src.notes) + set_aside + ([written] if written else [])
    return answer
