"""``deck-emulator study stability``: stiff springs against H, and extreme scenes, for the
emulator and the core."""

from __future__ import annotations

from . import Answer, command
from . import common
from .groups import StudyOut
from .options import option, options_class


@options_class
class StabilityStudyOptions(StudyOut):
    deck: str | None = option(None, metavar="SOURCE",
                              help="base deck: a shipped deck's name or a text deck file "
                              "(default: the report's deck steel40)")


@command("study stability", StabilityStudyOptions,
         help="stiff springs against H, and extreme scenes, for the emulator and the core",
         description="Stability study: a grid of scenes derived from steel40 (CK = CT from "
         "3.3e4 to 1e10 lb/ft against H; speeds 5-120 mph; approach angles to 90 deg; delta = "
         "0; the start-up THA; A = B = C; light and heavy posts; base friction; THB near 90 "
         "deg), each run by the emulator and the core, with how it ended.")
def study_stability(o: StabilityStudyOptions) -> Answer:
    from deck_emulator.studies.stability import stability_study

    def run(deck, sha256, jobs, typed):
        s = stability_study(o.out, quick=o.quick, jobs=jobs, deck_path=deck and deck.path,
                            command=typed, quiet=o.quiet, scheduler=common.scheduler(o),
                            resume=o.resume, deck=deck, deck_sha256=sha256)
        return s, [f"emulator classes: {s['classes']}"]

    return common.study_answer("stability", o, run)
