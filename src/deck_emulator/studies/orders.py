"""Observed orders of convergence, derived and not read off one pair.

An error that behaves as ``C h**p`` gives ``p`` as the slope of ``log e`` against ``log h``.
:func:`order_fit` fits that slope by least squares over every step size that ran, with its
95 % confidence interval (Student's t on ``n - 2`` degrees of freedom: the scatter of the
points about the line, not an assumed error), and gives the step-by-step orders
``log2(e(h) / e(h/2))`` beside it.  Two step sizes make no fit (a line through two points has
no scatter to judge it by): :func:`order_fit` then gives no order, and its text says why
(the one step-by-step value is kept in ``pairwise``, not printed).

A quantity whose error is quantised by the step has no order at all: the emulator's hit time is
the time of the step at which its test first holds, a point of its step grid ``k H``, so its
error is the reference's hit time rounded to that grid -- anywhere from 0 to about H, jumping
as H changes, not ``C H**p`` (:data:`QUANTISED`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: why a grid-quantised error has no order, in one line (diff and the error study print it)
QUANTISED = ("the emulator's hit time lies on its step grid (the step at which the hit test "
             "first holds), so its error is the true time rounded to a multiple of H, quantised "
             "by the step, not C*H**p")

#: the confidence of the interval
CONFIDENCE = 0.95


@dataclass(frozen=True)
class OrderFit:
    """The least-squares order ``p`` with its interval ``p - half ... p + half`` over ``n``
    step sizes (``p`` NaN below three), and the step-by-step orders."""

    p: float
    half: float
    n: int
    pairwise: tuple[float, ...]

    def text(self) -> str:
        steps = ", ".join(f"{x:.2f}" for x in self.pairwise) or "none"
        if self.n < 3:  # not even the one pair's: an order read off one pair is no order
            return (f"none from {self.n} step size{'s' if self.n != 1 else ''} (a fit needs "
                    "three or more)")
        return (f"{self.p:.2f} ± {self.half:.2f} (least squares over {self.n} step sizes, "
                f"{CONFIDENCE:.0%} interval); step by step {steps}")


def _t_quantile(dof: int) -> float:
    from scipy.stats import t

    return float(t.ppf(0.5 + CONFIDENCE / 2, dof))


def order_fit(h, err) -> OrderFit:
    """The order of ``err`` in ``h`` (paired sequences, any order; points that are not finite
    and positive are left out).  Step-by-step orders only between neighbours whose steps
    differ by a factor of two, in the order of decreasing h."""
    pts = sorted(((float(a), float(b)) for a, b in zip(h, err)
                  if math.isfinite(a) and math.isfinite(b) and a > 0 and b > 0), reverse=True)
    pairwise = tuple(math.log2(e0 / e1) for (h0, e0), (h1, e1) in zip(pts, pts[1:])
                     if math.isclose(h0 / h1, 2.0, rel_tol=1e-9))
    n = len(pts)
    if n < 3:
        return OrderFit(math.nan, math.nan, n, pairwise)
    x = [math.log(a) for a, _ in pts]
    y = [math.log(b) for _, b in pts]
    mx, my = sum(x) / n, sum(y) / n
    sxx = sum((a - mx) ** 2 for a in x)
    p = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sxx
    resid = sum((b - my - p * (a - mx)) ** 2 for a, b in zip(x, y))
    se = math.sqrt(resid / (n - 2) / sxx)
    return OrderFit(p, _t_quantile(n - 2) * se, n, pairwise)
