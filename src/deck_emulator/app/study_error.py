"""``deck-emulator study error``: error against run time: the emulator at H = 0.0004/2**k, the
core at rtol."""

from __future__ import annotations

from . import Answer, command
from . import common
from .groups import StudyOut
from .options import option, options_class


@options_class
class ErrorStudyOptions(StudyOut):
    deck: str = option(positional=True, metavar="SOURCE",
                       help="a shipped deck's name (steel40) or a text deck file")


@command("study error", ErrorStudyOptions,
         help="error against run time and work: the emulator at H = 0.0004/2**k, the core at "
         "rtol 1e-3 ... 1e-11, against a 1e-12 reference",
         description="Work-precision study on DECK: the emulator in double precision at H = "
         "0.0004/2**k (k = 0..6; the listing's ED tolerance and a tightened one), in the IBM "
         "7094 arithmetic at k = 0, and the core with DOP853, RK45 and Radau at rtol 1e-3 ... "
         "1e-11, with and without its largest-step bound, and the compiled DOP853, all against "
         "the core at rtol 1e-12 (itself checked with Radau and LSODA at 1e-13); every run "
         "with one BLAS thread.")
def study_error(o: ErrorStudyOptions) -> Answer:
    from deck_emulator.studies.error import error_study

    def run(deck, sha256, jobs, typed):
        s = error_study(deck.path, o.out, quick=o.quick, jobs=jobs, command=typed,
                        quiet=o.quiet, scheduler=common.scheduler(o), resume=o.resume,
                        deck=deck, deck_sha256=sha256)
        orders = s["orders"]
        return s, [
            "observed order (listing as printed): "
            f"{orders['legacy, ED as printed (double)']['vs_h'].text()}",
            "observed order (ED tightened): "
            f"{orders['legacy, ED tightened (double)']['vs_h'].text()}"]

    return common.study_answer("error", o, run)
