"""Imported once by the embedded runner's forkserver (:mod:`.local_pool`) before its first
worker: SIGINT ignored there and in every worker (the command handles a terminal's Ctrl-C),
the runner's module loaded, and what is loaded then frozen out of the garbage collector's way
(a collection in a worker would otherwise copy the pages it shares with the server)."""

import gc
import signal

signal.signal(signal.SIGINT, signal.SIG_IGN)

import deck_emulator.studies.distributed  # noqa: E402,F401 - what every worker runs

gc.collect()
gc.freeze()
