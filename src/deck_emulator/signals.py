"""SIGTERM (and SIGHUP) as exceptions, so that ``finally`` blocks and ``with`` exits run and
remove temporary files, as they already do for Ctrl-C (KeyboardInterrupt); the exit statuses a
shell expects of a program ended by a signal: 128 + the signal's number.

Usage from a command's ``main()``::

    from deck_emulator import signals

    def main(argv=None) -> int:
        signals.install_signal_handlers()
        try:
            return _main(argv)
        except BaseException as exc:
            code = signals.exit_status(exc)
            if code is None:
                raise
            return code

or simply ``return signals.run(_main, argv)``.
"""

from __future__ import annotations

import signal
import sys

__all__ = ["Terminated", "install_signal_handlers", "exit_status", "run",
           "EXIT_SIGINT", "EXIT_SIGTERM"]

EXIT_SIGINT = 128 + signal.SIGINT  # 130
EXIT_SIGTERM = 128 + signal.SIGTERM  # 143


class Terminated(BaseException):
    """Raised in the main thread when SIGTERM (or SIGHUP) arrives; like KeyboardInterrupt it is
    not an ``Exception``, so ``except Exception`` does not swallow it."""

    def __init__(self, signum: int):
        self.signum = signum
        super().__init__(f"terminated by {signal.Signals(signum).name}")


def _raise(signum, frame):
    raise Terminated(signum)


def install_signal_handlers() -> None:
    """SIGTERM and SIGHUP raise :class:`Terminated`; SIGINT raises KeyboardInterrupt (Python's
    default, restored if it was changed, but left ignored if our parent ignores it, as a shell
    does for a background job).  Only possible from the main thread; elsewhere a no-op."""
    try:
        signal.signal(signal.SIGTERM, _raise)
        if hasattr(signal, "SIGHUP") and signal.getsignal(signal.SIGHUP) is not signal.SIG_IGN:
            signal.signal(signal.SIGHUP, _raise)
        if signal.getsignal(signal.SIGINT) not in (signal.SIG_IGN, signal.default_int_handler):
            signal.signal(signal.SIGINT, signal.default_int_handler)
    except ValueError:  # not the main thread
        pass


def exit_status(exc: BaseException) -> int | None:
    """130 for KeyboardInterrupt (SIGINT), 128 + n for :class:`Terminated` (143 for SIGTERM),
    None for any other exception."""
    if isinstance(exc, KeyboardInterrupt):
        return EXIT_SIGINT
    if isinstance(exc, Terminated):
        return 128 + exc.signum
    return None


def run(fn, *args, **kwargs) -> int:
    """``fn(*args, **kwargs)`` with the handlers installed; a SIGINT/SIGTERM becomes its exit
    status (one line on stderr), after every ``finally`` has run."""
    install_signal_handlers()
    try:
        return fn(*args, **kwargs)
    except (KeyboardInterrupt, Terminated) as exc:
        name = "interrupted" if isinstance(exc, KeyboardInterrupt) else str(exc)
        try:
            print(f"deck-emulator: {name}", file=sys.stderr, flush=True)
        except (OSError, ValueError):
            pass
        return exit_status(exc)
