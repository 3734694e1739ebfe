"""The many-scene commands: ``sweep``, ``sensitivity``, ``study error``, ``study stability``.
Each writes a folder of files (whole, or not at all) and answers with what it wrote."""

from __future__ import annotations

import os
import shlex
import time
from dataclasses import dataclass
from pathlib import Path

from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.vocabulary.defaults import SCENE_STORE

from . import Answer, command
from . import common
from .options import ENGINES, Cluster, Common, Errata, Preset, option, whole_number



@dataclass(frozen=True, kw_only=True)
class _Study(Common, Cluster):
    quiet: bool = option(False, help="no progress display on stderr (shown only on a terminal)")
    json: bool = option(False, help="print what ran and what was written as one JSON object "
                        "(docs/json.md)")


# ------------------------------------------------------------------------------------ sweep


@dataclass(frozen=True, kw_only=True)
class SweepOptions(_Study, Errata, Preset):
    post: str = option("steel", choices=("steel",),
                       help="the post (the report's steel post: its deck steel40, shipped with "
                       "the package)")
    base_deck: str | None = option(None, metavar="SOURCE",
                                   help="another base deck instead of --post's: a shipped "
                                   "deck's name or a text deck file")
    speeds: str = option(metavar="MPH,...", required=True,
                         help="vehicle speeds in mph: 20,40 or 10:60:10 (stop included)")
    angles: str = option(metavar="DEG,...", required=True,
                         help="approach angles in degrees: 0,15,30 or 0:45:5")
    engine: str = option("emulator", choices=ENGINES,
                         help="which engine runs the scenes (default emulator)")
    vvb_decimals: int = option(2, parse=whole_number, metavar="N",
                               help="decimals VVB is cut to (default 2, as the report's deck: "
                               "-58.66)")
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
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.studies.distributed import output_store
    from deck_emulator.studies.sweep import (POSTS, parse_grid, render_markdown, scene_deck,
                                             sweep as run_sweep, write_csv)

    try:
        speeds = parse_grid(o.speeds)
        angles = parse_grid(o.angles)
    except ValueError as exc:
        raise UsageError(f"--speeds/--angles: {exc}") from None
    if any(s <= 0 for s in speeds):
        raise UsageError("--speeds must be positive (mph)")
    if any(not (0 <= a < 90) for a in angles):
        raise UsageError("--angles must be in [0, 90) degrees")
    if not 0 <= o.vvb_decimals <= 5:
        raise UsageError("--vvb-decimals must be 0 to 5")
    base = (Path(common.deck_file(o.base_deck, "sweep --base-deck")) if o.base_deck
            else POSTS[o.post])
    base_deck = read_deck(base)  # bad deck -> DeckError, before any work
    for s in speeds:  # every VVB/ALPHA must punch: fail before running anything
        for a in angles:
            scene_deck(base_deck, s, a, o.vvb_decimals)
    check_output_dir(o.out)
    options = (dict(errata=tuple(o.erratum)) if o.engine == "emulator" else o.core_keywords())
    store = output_store(o.out, o.resume)  # a new sweep: the scenes of the last one go
    started = time.perf_counter()
    rows = run_sweep(speeds, angles, engine=o.engine, options=options, post=o.post, base=base,
                     jobs=o.jobs, vvb_decimals=o.vvb_decimals, quiet=o.quiet, store_dir=store,
                     scheduler=common.scheduler(o), resume=o.resume)
    wall = time.perf_counter() - started
    with OutputSet(directory=o.out) as outputs:
        outputs.write("sweep.csv", write_csv(rows))
        outputs.write("sweep.md", render_markdown(rows, command=o.command_line, engine=o.engine))
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


# ------------------------------------------------------------------------------ sensitivity


@dataclass(frozen=True, kw_only=True)
class SensitivityOptions(_Study, Preset):
    deck: tuple[str, ...] = option((), many=True, metavar="SOURCE",
                                   help="a shipped deck's name or a text deck file; repeat for "
                                   "several (default steel40)")
    engine: str = option("core", choices=("core", "emulator"),
                         help="default core: the emulator's deck has no base-friction field")
    input: tuple[str, ...] = option((), many=True, metavar="NAME=LO:HI",
                                    help="add or re-range an input (a READ-list name, or "
                                    "friction_lb, friction_travel_ft on the core)")
    only: bool = option(False, help="only the --input inputs")
    n: int | None = option(None, flag="-N", parse=whole_number, metavar="N",
                           help="base sample size, a power of two (default 256; 16 with --quick)")
    quick: bool = option(False, help="N = 16 (128 scenes with the default inputs): a first look "
                         "in about a minute on two cores; wide intervals")
    seed: int = option(0, parse=whole_number, help="the sample's seed (default 0)")
    out: str = option(metavar="DIR", required=True, help="directory for the results")


@command("sensitivity", SensitivityOptions,
         help="Sobol indices of the outcome over the report's uncertain inputs",
         description="Sample the inputs the report takes as estimates (base friction and its "
         "travel, CK, CT, FCONST, WV; and any --input NAME=LO:HI), run every sample on one "
         "engine on a Dask cluster, and write DIR/sensitivity.csv and .md (Sobol S1 and ST "
         "with 95% confidence, for N and N/2), a bar chart of the indices and a map of what "
         "the post hits first over the two most influential inputs. Scenes are stored as they "
         f"finish in DIR/{SCENE_STORE}/; --resume runs only the missing ones.")
def sensitivity(o: SensitivityOptions) -> Answer:
    common.require("studies")
    from deck_emulator.studies.sensitivity import run_command

    for deck in o.deck:  # shipped names stay names (the outputs are named by them)
        common.deck_file(deck, "sensitivity --deck")
    answer = Answer("sensitivity", list(o.deck) or ["steel40"], json=o.json)
    try:
        run_command(out=o.out, decks=o.deck, engine=o.engine, engine_keywords=o.core_keywords(),
                    inputs_text=o.input, only=o.only, n=o.n, quick=o.quick, seed=o.seed,
                    jobs=o.jobs, scheduler=common.scheduler(o), resume=o.resume,
                    quiet=o.quiet, command_line=o.command_line,
                    say=lambda line: answer.said.append(f"sensitivity: {line}"))
    except RunFailed as exc:  # said as every command says it; the JSON still answers
        answer.status, answer.error = "stopped", str(exc)
    answer.result = common.outputs_result(o.out)
    return answer


# ------------------------------------------------------------------------------------ study


@dataclass(frozen=True, kw_only=True)
class _StudyOut(_Study):
    out: str = option(metavar="DIR", required=True, help="directory for the outputs")
    quick: bool = option(False, help="a small grid (seconds, for tests) instead of the full "
                         "study")


@dataclass(frozen=True, kw_only=True)
class ErrorStudyOptions(_StudyOut):
    deck: str = option(positional=True, metavar="SOURCE",
                       help="a shipped deck's name (steel40) or a text deck file")


@dataclass(frozen=True, kw_only=True)
class StabilityStudyOptions(_StudyOut):
    deck: str | None = option(None, metavar="SOURCE",
                              help="base deck: a shipped deck's name or a text deck file "
                              "(default: the report's deck steel40)")


def _study(name: str, o, run) -> Answer:
    """A study's command: the deck checked, the folder checked, the study run, its lines."""
    from deck_emulator.files import check_output_dir
    from deck_emulator.legacy.deck import read_deck

    common.require("studies")
    deck = None
    if o.deck:
        deck = common.deck_file(o.deck, f"study {name}")
        common.engine_scene(read_deck(deck), name=deck)  # both engines run it: exit 2
    check_output_dir(o.out)  # before any work, and before the study makes the folder
    jobs = o.jobs or os.cpu_count() or 1
    typed = o.command_line or shlex.join(  # called from Python: the command it stands for
        ["deck-emulator", "study", name, *([o.deck] if o.deck else []), "--out", o.out,
         *(["--quick"] if o.quick else []), "--jobs", str(jobs)])
    summary, lines = run(deck, jobs, typed)
    answer = Answer(f"study {name}", o.deck or "steel40", json=o.json)
    answer.said = [f"study {name}: {line}" for line in
                   lines + [f"wrote {o.out} in {summary['wall_s']:.0f} s"]]
    answer.result = common.outputs_result(o.out)
    return answer


@command("study error", ErrorStudyOptions,
         help="error against run time: the emulator at H = 0.0004/2**k, the core at rtol "
         "1e-3 ... 1e-11, against a 1e-12 reference",
         description="Work-precision study on DECK: the emulator in double precision at H = "
         "0.0004/2**k (k = 0..6; the listing's ED tolerance and a tightened one), in the IBM "
         "7094 arithmetic at k = 0, and the core with DOP853, RK45 and Radau at rtol 1e-3 ... "
         "1e-11, all against the core at rtol 1e-12 (itself checked with Radau and LSODA at "
         "1e-13).")
def study_error(o: ErrorStudyOptions) -> Answer:
    from deck_emulator.studies.error import error_study

    def run(deck, jobs, typed):
        s = error_study(deck, o.out, quick=o.quick, jobs=jobs, command=typed, quiet=o.quiet,
                        scheduler=common.scheduler(o), resume=o.resume)
        orders = s["orders"]
        return s, [
            "observed order (listing as printed): "
            f"{orders['legacy, ED as printed (double)']['vs_h']:.2f}",
            f"observed order (ED tightened): {orders['legacy, ED tightened (double)']['vs_h']:.2f}"]

    return _study("error", o, run)


@command("study stability", StabilityStudyOptions,
         help="stiff springs against H, and extreme scenes, for the emulator and the core",
         description="Stability study: a grid of scenes derived from steel40 (CK = CT from "
         "3.3e4 to 1e10 lb/ft against H; speeds 5-120 mph; approach angles to 90 deg; delta = "
         "0; the start-up THA; A = B = C; light and heavy posts; base friction; THB near 90 "
         "deg), each run by the emulator and the core, with how it ended.")
def study_stability(o: StabilityStudyOptions) -> Answer:
    from deck_emulator.studies.stability import stability_study

    def run(deck, jobs, typed):
        s = stability_study(o.out, quick=o.quick, jobs=jobs, deck_path=deck, command=typed,
                            quiet=o.quiet, scheduler=common.scheduler(o), resume=o.resume)
        return s, [f"emulator classes: {s['classes']}"]

    return _study("stability", o, run)
