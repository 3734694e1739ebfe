"""The package's progress display: :func:`progress_bar` (a tqdm bar on stderr, only on a
terminal) and :class:`busy` (the same for one long call that reports nothing itself).

Runs of many scenes go to the one scene runner,
:func:`deck_emulator.studies.distributed.run_scenes`.
"""

from __future__ import annotations

import sys
import time

__all__ = ["progress_bar", "busy"]


def _on_terminal() -> bool:
    """Whether stderr is a terminal (False for a closed or replaced stderr)."""
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


#: the share of a bar's work done before it shows the time left (and at least two items):
#: the first items' time holds the workers' start, so the time left they give is far off
SETTLED = 0.1

_NO_TIME_LEFT = "{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}, {rate_fmt}{postfix}]"


def progress_bar(total: int | None = None, *, desc: str = "", unit: str = "it",
                 quiet: bool = False, **options):
    """The package's one progress display: a tqdm bar on stderr, shown only when stderr is a
    terminal and not ``quiet`` (``total=None``: a counter).  The time left is shown once
    :data:`SETTLED` of the work is done."""
    from tqdm import tqdm

    class Bar(tqdm):
        @property
        def format_dict(self):  # tqdm's documented place to change what a bar shows
            shown = super().format_dict
            todo = (shown["total"] or 0) - self.initial
            if shown["bar_format"] is None and shown["n"] - self.initial < max(2, SETTLED * todo):
                shown["bar_format"] = _NO_TIME_LEFT
            return shown

    return Bar(total=total, desc=desc, unit=unit, file=sys.stderr, leave=False,
               disable=quiet or not _on_terminal(), **options)


class busy:
    """``with busy("emulator"): work()`` -- for one long call that reports nothing itself:
    the same bar, counting seconds of wall time from a background thread (nothing is added
    to the work's own loop)."""

    def __init__(self, desc: str, *, quiet: bool = False, every_s: float = 0.5, status=None):
        """``status``: a callable giving a short text to show (e.g. the emulator's step)."""
        self.desc, self.quiet, self.every_s, self.status = desc, quiet, every_s, status

    def __enter__(self):
        self._bar = None
        if self.quiet or not _on_terminal():
            return self
        import threading  # (here: a run without a terminal, a plain run's, has no bar)

        self._stop = threading.Event()
        self._bar = progress_bar(desc=self.desc, unit="s", quiet=self.quiet,
                                 bar_format="{desc}: {elapsed}{postfix}")
        started = time.monotonic()

        def tick():
            while not self._stop.wait(self.every_s):
                self._bar.n = int(time.monotonic() - started)
                if self.status is not None:
                    try:
                        self._bar.set_postfix_str(self.status(), refresh=False)
                    except Exception as exc:  # noqa: BLE001 - a courtesy: said in its place
                        self._bar.set_postfix_str(f"no status ({type(exc).__name__}: {exc})"[:80],
                                                  refresh=False)
                self._bar.refresh()

        self._thread = threading.Thread(target=tick, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc):
        if self._bar is not None:
            self._stop.set()
            self._thread.join()
            self._bar.close()
        return False
