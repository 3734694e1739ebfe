"""The core's wall bounds (max_wall_s) read a clock that leaves out numba compiling or loading
the core's machine code: a cold cache (a minute of compiling on a new machine) must never stop
a run on its bound (core/laws.py, working_clock)."""

from __future__ import annotations

import time

from numba import njit
from numba.core import event

from deck_emulator.core import laws


def test_the_bounds_clock_leaves_out_what_numba_spends_compiling():
    """A function compiled inside the window (a new one: nothing cached) holds numba's compiler
    lock for a while, timed by numba's own timer; the bounds' clock advances by the window less
    that time, and by no more than the window."""
    laws.compile_functions()  # the core's compiled path, which the clock watches numba for
    spent: list[float] = []

    def one_more(x):
        return x + 1.0

    with event.install_timer("numba:compiler_lock", spent.append):
        w0, p0 = laws.working_clock(), time.perf_counter()
        assert njit(one_more)(1.0) == 2.0
        w1, p1 = laws.working_clock(), time.perf_counter()
    compiling = sum(spent)
    assert compiling > 0
    left_out = (p1 - p0) - (w1 - w0)
    assert 0 <= w1 - w0 <= p1 - p0
    # both listeners see the same start and end events, microseconds apart (a wide margin: a
    # loaded machine may pause the process between the two)
    assert abs(left_out - compiling) <= 0.25 * compiling
