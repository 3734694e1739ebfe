"""Imported once in the process the embedded runner forks its workers from
(:mod:`deck_emulator.studies.local_pool`, multiprocessing's forkserver *preload*), before it
serves its first worker.

* SIGINT is ignored from here on, in it and in every worker forked from it: a Ctrl-C at a
  terminal goes to the whole foreground process group, and the command handles it (it
  stores what has completed and closes its workers); a worker that took it too would only
  print a ``KeyboardInterrupt`` traceback of its own.  SIGTERM and SIGKILL still end them.
* The runner's own module is loaded here, once, for every worker.
* What is loaded by then is put out of the garbage collector's way (``gc.freeze``): a
  collection in a worker that went through those objects would write to (and so copy) the
  pages the worker shares with this process.
"""

from __future__ import annotations

import gc
import signal

signal.signal(signal.SIGINT, signal.SIG_IGN)

import deck_emulator.studies.distributed  # noqa: F401 - what every worker runs

gc.collect()
gc.freeze()
