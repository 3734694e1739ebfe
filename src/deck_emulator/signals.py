"""SIGTERM (and SIGHUP) as exceptions, so that ``finally`` blocks and ``with`` exits run and
remove temporary files, as they already do for Ctrl-C (KeyboardInterrupt); the exit statuses a
shell expects of a program ended by a signal: 128 + the signal's number.  A command's
``main()`` returns ``signals.run(_main, argv)``.

A signal is never swallowed.  Python cannot raise an exception out of a garbage-collector
callback, a ``__del__`` or a weakref callback: one raised there is printed ("Exception ignored
in ...") and dropped, and the program would go on as if no signal had come.  So each signal
is noted as *pending* until its exception reaches :func:`run`; while one is pending, SIGALRM
is armed every :data:`REDELIVER_S` seconds and raises it again -- unless it is on its way out
already (being handled: a ``finally`` or ``with`` exit running on its account, which must not
be cut).  A command that returns while a signal is pending ends with its status all the same.
"""

from __future__ import annotations

import contextlib
import signal
import sys

__all__ = ["Terminated", "held", "install_signal_handlers", "exit_status", "run",
           "EXIT_SIGINT", "REDELIVER_S"]

EXIT_SIGINT = 128 + signal.SIGINT  # 130


class Terminated(BaseException):
    """Raised in the main thread when SIGTERM (or SIGHUP) arrives; like KeyboardInterrupt it is
    not an ``Exception``, so ``except Exception`` does not swallow it."""

    def __init__(self, signum: int):
        self.signum = signum
        super().__init__(f"terminated by {signal.Signals(signum).name}")


#: Seconds after which a signal whose exception has not reached :func:`run` is raised again.
REDELIVER_S = 0.5

#: Signals raised as exceptions that have not reached :func:`run` yet (first first).
_pending: list[int] = []


def _exception(signum: int) -> BaseException:
    return KeyboardInterrupt() if signum == signal.SIGINT else Terminated(signum)


def _arm() -> None:
    try:
        signal.signal(signal.SIGALRM, _redeliver)
        signal.setitimer(signal.ITIMER_REAL, REDELIVER_S)
    except (ValueError, OSError, AttributeError):  # not the main thread; no SIGALRM here
        pass


def _disarm() -> None:
    _pending.clear()
    try:
        signal.setitimer(signal.ITIMER_REAL, 0)
    except (ValueError, OSError, AttributeError):
        pass


def _on_its_way(exc: BaseException | None) -> bool:
    """True when a signal's exception is being handled now (in the chain of the exception
    being handled): it is propagating, its cleanups are running."""
    seen = 0
    while exc is not None and seen < 100:
        if isinstance(exc, (KeyboardInterrupt, Terminated)):
            return True
        exc, seen = exc.__context__, seen + 1
    return False


def _raise(signum, frame):
    if signum not in _pending:
        _pending.append(signum)
    _arm()
    raise _exception(signum)


def _redeliver(signum, frame):
    if not _pending:
        return
    _arm()
    if _on_its_way(sys.exc_info()[1]):
        return  # propagating: its finally blocks run; look again later
    raise _exception(_pending[0])


def _unraisable(hook):
    """``sys.unraisablehook`` that drops a signal's exception raised where Python cannot raise
    it (a garbage-collector callback, a ``__del__``, an exit hook): it is pending and raised
    again (the module docstring), so "Exception ignored in ..." with its traceback would only
    be noise.  Every other unraisable exception goes to ``hook`` as before."""

    def unraisable(info):
        if isinstance(info.exc_value, (KeyboardInterrupt, Terminated)):
            return
        hook(info)

    unraisable.deck_emulator = True
    return unraisable


@contextlib.contextmanager
def held():
    """``with signals.held():`` a SIGINT, SIGTERM or SIGHUP that comes meanwhile is noted and
    raised only as the block ends, not inside it: over the commit of output files (a few
    renames, :mod:`deck_emulator.files`), and for a library's compiled code (Cython's) that
    catches an exception raised in it and prints its traceback itself, past
    ``sys.unraisablehook`` (scipy while SALib builds a Sobol' sample).

    The Python handlers are swapped for one that notes the signal, and what was noted is
    raised again once they are back (blocking the signals with ``pthread_sigmask`` would not
    hold them: the kernel gives them to another thread, numpy's OpenBLAS starts some, and
    Python runs the handler in the main thread all the same).  Python runs handlers only in
    the main thread: from another thread nothing is changed."""
    noted: list[int] = []

    def note(signum, frame):
        if signum not in noted:
            noted.append(signum)

    swapped = {}
    try:
        for sig in (signal.SIGINT, signal.SIGTERM, getattr(signal, "SIGHUP", None),
                    signal.SIGALRM):
            handler = None if sig is None else signal.getsignal(sig)
            if handler in (signal.SIG_IGN, None) or (sig == signal.SIGALRM
                                                     and handler is not _redeliver):
                continue  # ignored, not Python's to restore, or no redelivery of ours
            swapped[sig] = signal.signal(sig, note)
    except ValueError:  # not the main thread
        pass
    try:
        yield
    finally:
        for sig, handler in swapped.items():
            signal.signal(sig, handler)
        for sig in noted:  # its own handler now: KeyboardInterrupt, Terminated
            signal.raise_signal(sig)


def install_signal_handlers() -> None:
    """SIGTERM and SIGHUP raise :class:`Terminated`; SIGINT raises KeyboardInterrupt (as
    Python's default does, but left ignored if our parent ignores it, as a shell does for a
    background job); each noted until :func:`run` sees it (the module docstring).  Only
    possible from the main thread; elsewhere a no-op."""
    if not getattr(sys.unraisablehook, "deck_emulator", False):
        sys.unraisablehook = _unraisable(sys.unraisablehook)
    try:
        signal.signal(signal.SIGTERM, _raise)
        if hasattr(signal, "SIGHUP") and signal.getsignal(signal.SIGHUP) is not signal.SIG_IGN:
            signal.signal(signal.SIGHUP, _raise)
        if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:
            signal.signal(signal.SIGINT, _raise)  # KeyboardInterrupt, noted until it is seen
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
    _disarm()
    try:
        status = fn(*args, **kwargs)
        if not _pending:
            return status
        exc = _exception(_pending[0])  # swallowed on the way and never raised again in time
    except (KeyboardInterrupt, Terminated) as caught:
        exc = caught
    finally:
        _disarm()
    name = "interrupted" if isinstance(exc, KeyboardInterrupt) else str(exc)
    try:
        print(f"deck-emulator: {name}", file=sys.stderr, flush=True)
    except (OSError, ValueError):
        pass
    return exit_status(exc)
