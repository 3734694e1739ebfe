"""``deck-emulator plot``: draw the post's fall (side, plan, 3-d), the vehicle pulse, or an
animation."""

from __future__ import annotations

from deck_emulator.errors import UsageError
from deck_emulator.vocabulary.choices import ENGINES, VIEWS

from . import Answer, command
from . import common
from .groups import Preset
from .options import DECK_WORDS, Errata, option, options_class, positive_float, quiet_option, Source


@options_class
class PlotOptions(Source, Errata, Preset):
    source: str = option(positional=True, metavar="SOURCE",
                         help=DECK_WORDS + "; with --engine core also a scene "
                         "file (.toml)")
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
    quiet: bool = quiet_option()
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
    source = src.scene_or_deck(name)
    # the core's scene, built once; a deck the core cannot solve: exit 2 before any run
    scene = None if emulator else common.engine_scene(source, scene_name=src.stem)
    options = {"emulator": {"errata": tuple(o.erratum)}, "core": o.core_keywords()}
    with busy("deck-emulator: plot", quiet=o.quiet):
        stopped, said = draw(source, src.name, engine=o.engine, options=options, out=o.out,
                     view=o.view, pulse=o.pulse, animate=o.animate, every_ms=o.every,
                     scene=scene)
    return Answer("plot", src.name, status="stopped" if stopped else "ok",
                  settings={"engine": o.engine, "view": o.view, "pulse": o.pulse,
                            "errata": list(o.erratum), "preset": o.preset},
                  notes=list(src.notes), said=list(src.notes) + said,
                  result={"outputs": [o.out] + ([o.animate] if o.animate else [])},
                  json=o.json)
