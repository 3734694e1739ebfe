"""``deck-emulator sweep``: run a grid of speeds and approach angles and tabulate it like
Tables 11 and 12."""

from __future__ import annotations

import os
import time
from pathlib import Path

from deck_emulator.errors import UsageError
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.choices import ENGINES
from deck_emulator.vocabulary.defaults import SCENE_STORE

from . import Answer, command
from . import common
from .groups import Many, Preset
from .options import Errata, option, options_class, whole_number


@options_class
class SweepOptions(Many, Errata, Preset):
    post: str = option("steel", choices=("steel",),
                       help="the post (the report's steel post: its deck steel40, shipped with "
                       "the package)")
    base_deck: str | None = option(None, metavar="SOURCE",
                                   help="another base deck instead of --post's: a shipped "
                                   "deck's name or a text deck file (the scenes and sweep.md "
                                   "are named after it: car820.dat gives car820_v40_a15)")
    speeds: str = option(metavar="MPH,...", required=True,
                         help="vehicle speeds in mph: 20,40 or 10:60:10 (stop included)")
    angles: str = option(metavar="DEG,...", required=True,
                         help="approach angles in degrees, from 0 to "
                         f"{defaults.MAX_APPROACH_ANGLE_DEG:g}: 0,15,30 or 0:45:5")
    engine: str = option("emulator", choices=ENGINES,
                         help="which engine runs the scenes (default emulator)")
    vvb_decimals: int = option(defaults.VVB_DECIMALS, parse=whole_number, metavar="N",
                               help="decimals VVB is cut to (default %(default)s, as the "
                               "report's deck: -58.66)")
    out: str = option(metavar="DIR", required=True,
                      help="directory for sweep.csv and sweep.md (and the scene store, "
                      f"DIR/{SCENE_STORE}, kept for --resume)")


@command("sweep", SweepOptions,
         help="run a grid of speeds and approach angles and tabulate it like Tables 11 and 12",
         description="Regenerate the report's parameter study: every speed x angle of the grid "
         "is the base deck with VVB and ALPHA changed, run in parallel. Writes DIR/sweep.csv "
         "(one row per scene, every output, the report's value and the difference) and "
         "DIR/sweep.md (one table per speed, laid out like Tables 11 and 12). The emulator runs "
         "the listing as printed unless --erratum names an erratum (the angled scenes need "
         "ed-direction).")
def sweep(o: SweepOptions) -> Answer:
    common.require("studies")
    from deck_emulator.files import OutputSet, check_output_dir
    from deck_emulator.studies.store import output_store
    from deck_emulator.studies.sweep import (POSTS, parse_grid, read_base, render_markdown,
                                             scene_deck, sweep as run_sweep, write_csv)

    try:
        speeds = parse_grid(o.speeds)
        angles = parse_grid(o.angles)
    except ValueError as exc:
        raise UsageError(f"--speeds/--angles: {exc}") from None
    if any(s <= 0 for s in speeds):
        raise UsageError("--speeds must be positive (mph)")
    if any(not (0 <= a <= defaults.MAX_APPROACH_ANGLE_DEG) for a in angles):
        raise UsageError(f"--angles must be from 0 to {defaults.MAX_APPROACH_ANGLE_DEG:g} "
                         "degrees")
    if not 0 <= o.vvb_decimals <= 5:
        raise UsageError("--vvb-decimals must be 0 to 5")
    if o.base_deck:  # bad deck -> DeckError, before any work
        base_deck, base_sha256 = common.deck_file(o.base_deck, "sweep --base-deck",
                                                  with_sha256=True)
    else:
        base_deck, base_sha256 = read_base(POSTS[o.post])
    base = Path(base_deck.path)
    # the scenes are named after the deck given (car820.dat: car820_v40_a15), the post's after it
    label = o.post if not o.base_deck else Path(o.base_deck).stem
    label = f"{label}_deck" if o.base_deck and label in POSTS else label
    # every VVB and ALPHA must punch: fail before running anything.  A speed gives VVB and an
    # angle ALPHA, each punched in its own field: each speed and each angle once is every one
    for s in speeds:
        scene_deck(base_deck, s, angles[0], o.vvb_decimals)
    for a in angles:
        scene_deck(base_deck, speeds[0], a, o.vvb_decimals)
    check_output_dir(o.out)
    options = (dict(errata=tuple(o.erratum)) if o.engine == "emulator" else o.core_keywords())
    store = output_store(o.out, o.resume)  # a new sweep: the scenes of the last one go
    if o.engine == "core":
        common.compile_core(o.quiet)
    started = time.perf_counter()
    rows = run_sweep(speeds, angles, engine=o.engine, options=options, post=label, base=base,
                     base_deck=base_deck, base_sha256=base_sha256, jobs=o.jobs,
                     vvb_decimals=o.vvb_decimals, quiet=o.quiet, store_dir=store,
                     scheduler=common.scheduler(o), resume=o.resume)
    wall = time.perf_counter() - started
    with OutputSet(directory=o.out) as outputs:
        outputs.write("sweep.csv", write_csv(rows))
        outputs.write("sweep.md", render_markdown(rows, command=o.command_line, engine=o.engine,
                                                      base=o.base_deck))
    failed = [r for r in rows if r["error"]]
    where = f"on {o.scheduler}" if o.scheduler else f"on {o.jobs or os.cpu_count()} job(s)"
    written = [str(Path(o.out) / "sweep.csv"), str(Path(o.out) / "sweep.md")]
    answer = Answer(
        "sweep", str(o.base_deck or o.post),
        settings={"engine": o.engine, **{k: list(v) if isinstance(v, tuple) else v
                                         for k, v in options.items()},
                  "speeds_mph": list(speeds), "angles_deg": list(angles)},
        notes=[r["stopped_hint"] for r in failed if r["stopped_hint"]][:1],
        result={"outputs": written, "scenes": len(rows), "stopped": [r["scene"] for r in failed]},
        json=o.json,
        said=[f"{len(rows)} scenes ({o.engine}) in {wall:.1f} s {where}; {len(failed)} stopped "
              f"early; wrote {written[0]} and {written[1]}"])
    if failed:  # the tables are written, the stopped rows marked and not rated: exit 3
        answer.said += [f"stopped scenes: {hint}" for hint in
                        dict.fromkeys(r["stopped_hint"] for r in failed if r["stopped_hint"])]
        answer.status = "stopped"
        answer.error = (", ".join(r["scene"] for r in failed) + " stopped early (their rows "
                        "say why; no ratings for them)")
    return answer
