"""``deck-emulator sensitivity``: Sobol indices of the outcome over the report's uncertain
inputs."""

from __future__ import annotations

from deck_emulator.errors import RunFailed
from deck_emulator.vocabulary.defaults import SCENE_STORE

from . import Answer, command
from . import common
from .groups import Preset, Many
from .options import option, options_class, whole_number


@options_class
class SensitivityOptions(Many, Preset):
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
         "engine on worker processes (or a Dask cluster), and write DIR/sensitivity.csv and "
         ".md (Sobol S1 and ST with 95% confidence, for N and N/2), a bar chart of the indices "
         "and a map of what the post hits first over the two most influential inputs. The "
         "core tests the shaft and the arms against the car unless --no-shaft-contact is "
         "given (the outcomes include what the post hits); a model that tests only P, R and C "
         "is named blind to them, and they get no indices. Scenes "
         "are stored as they "
         f"finish in DIR/{SCENE_STORE}/; --resume runs only the missing ones.")
def sensitivity(o: SensitivityOptions) -> Answer:
    common.require("studies")
    from deck_emulator.studies.sensitivity import run_command

    read = {deck: common.deck_file(deck, "sensitivity --deck", with_sha256=True)
            for deck in o.deck}  # shipped names stay names (the outputs are named by them)
    answer = Answer("sensitivity", list(o.deck) or ["steel40"], json=o.json)
    keywords = o.core_keywords()
    if o.engine == "core" and o.shaft_contact is None:
        # its outcomes include what the post hits: the study's default model tests the shaft
        keywords["shaft_contact"] = True
    if o.engine == "core":
        common.compile_core(o.quiet)
    try:
        run_command(out=o.out, decks=o.deck, engine=o.engine, engine_keywords=keywords,
                    inputs_text=o.input, only=o.only, n=o.n, quick=o.quick, seed=o.seed,
                    jobs=o.jobs, scheduler=common.scheduler(o), resume=o.resume,
                    quiet=o.quiet, command_line=o.command_line,
                    say=lambda line: answer.said.append(f"sensitivity: {line}"), read=read)
    except RunFailed as exc:  # said as every command says it; the JSON still answers
        answer.status, answer.error = "stopped", str(exc)
    answer.result = common.outputs_result(o.out)
    return answer
