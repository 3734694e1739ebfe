"""A differential fuzzer of the FORTRAN front end (``deck_emulator.legacy.fortran``): seeded
random programs over the dialect's whole table, each judged against gfortran.

A tool of the checkout beside the oracle (it needs gfortran); no command of the package uses
it.  ``python -m oracle.fuzz --seed S --count N [--jobs 2] [--shrink] [--out DIR]`` runs a
campaign and prints its counts per outcome and per class (docs/fuzzing.md).

* :mod:`.generate` -- the programs (valid, terminating, well defined by construction);
* :mod:`.judge` -- gfortran's checked build, then the oracle build against the front end;
* :mod:`.tolerance` -- the IBM 7094's printout against binary64 within single precision;
* :mod:`.classes` -- what a disagreement is an instance of;
* :mod:`.shrink` -- delta debugging of a disagreement to a minimal program;
* :mod:`.campaign` -- many programs, counted.
"""

from .generate import FEATURES, FuzzProgram, generate, job_deck

__all__ = ["FEATURES", "FuzzProgram", "generate", "job_deck"]
