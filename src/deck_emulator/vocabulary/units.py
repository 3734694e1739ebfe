"""Units and the conversions between them: the one place for each factor.

The report works in ft, lb, slug, s and rad; speeds in the tables are mph; the crash-safety
criteria are in m/s and g.
"""

from __future__ import annotations

#: ft in a mile, s in an hour
FT_PER_MILE, S_PER_HOUR = 5280, 3600
#: ft/s in one mph (88/60)
FT_S_PER_MPH = FT_PER_MILE / S_PER_HOUR
#: m in one ft (exact, by the 1959 international yard)
M_PER_FT = 0.3048
#: the report's acceleration of gravity, ft/s^2 (the deck's G; standard gravity is 32.1740)
G_FT_S2 = 32.174


def ft_s_to_mph(ft_s: float) -> float:
    return ft_s / FT_S_PER_MPH


def force_in_g(force_lb, mass_slug: float, g_ft_s2: float):
    """A force on a mass as its acceleration in g, ``F / (m g)`` (lb, slug, ft/s^2; a number or
    an array of forces): the one formula of every deceleration in g read from a force."""
    return force_lb / (mass_slug * g_ft_s2)


def speed_lost_mph(v0_ft_s: float, v_ft_s: float) -> float:
    """The speed the car lost between two velocities along its path, ``|v0| - |v|`` (ft/s
    in, mph out): the one formula of every delta-V here. The registry's two delta-Vs
    (:mod:`deck_emulator.engine.quantities`) differ only in the instant ``v`` is read."""
    return ft_s_to_mph(abs(v0_ft_s) - abs(v_ft_s))
