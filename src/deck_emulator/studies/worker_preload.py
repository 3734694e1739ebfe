"""Run in each worker process of the embedded Dask cluster as it starts (Dask's *preload*):
the worker ignores SIGINT.

A Ctrl-C at a terminal goes to the whole foreground process group: the command *and* the
workers it spawned.  The command handles it (its ``finally`` blocks store what has completed
and close the cluster, which ends the workers); a worker that took it too would only print a
``KeyboardInterrupt`` traceback of its own.  SIGTERM and SIGKILL still end a worker, and the
cluster's nanny still stops it when the cluster closes.
"""

from __future__ import annotations

import signal


def dask_setup(worker) -> None:  # the name Dask's preload looks for
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the process's main thread: nothing to do there
        pass
