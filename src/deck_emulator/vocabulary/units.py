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


def speed_lost_mph(v0_ft_s: float, v_ft_s: float) -> float:
    """The speed the car lost between two velocities along its path, ``|v0| - |v|`` (ft/s
    in, mph out): the one formula of every delta-V here. The registry's two delta-Vs
    (:mod:`deck_emulator.engine.quantities`) differ only in the instant ``v`` is read."""
    return ft_s_to_mph(abs(v0_ft_s) - abs(v_ft_s))


#: The deck's quantities and their units (TTI Report 75-9's nomenclature; ft, lb, slug, s,
#: rad). Names not listed are pure numbers.
DECK_UNITS = {
    **dict.fromkeys(('V1B', 'V2B', 'V3B', 'VVB'), 'ft/s'),
    **dict.fromkeys(('F1B', 'F2B', 'F3B', 'FNA', 'FSB', 'FCONST'), 'lb'),
    **dict.fromkeys(('PSIDB', 'THDB', 'PHIDB', 'W1B', 'W2B', 'W3B'), 'rad/s'),
    **dict.fromkeys(('W', 'WV'), 'slug'),
    **dict.fromkeys(('A', 'B', 'C'), 'slug·ft²'),
    **dict.fromkeys(('G',), 'ft/s²'),
    **dict.fromkeys(('XCMB', 'YCMB', 'ZCMB', 'HEIGHT', 'SVB', 'XSO', 'YYSO', 'ZZSO', 'XPO',
                     'YYPO', 'ZZPO', 'XQO', 'YYQO', 'ZZQO', 'SVO', 'HLEN', 'TLEN', 'YLFEN',
                     'YRFEN', 'TRLEN', 'HTRV', 'HTV', 'HHV', 'XRO', 'YYRO', 'ZZRO', 'XCO', 'YYCO',
                     'ZZCO', 'XTO', 'YYTO', 'ZZTO'), 'ft'),
    **dict.fromkeys(('CK', 'CT'), 'lb/ft'),
    **dict.fromkeys(('PSIB', 'THB', 'PHIB', 'ALPHA', 'DELTA'), 'rad'),
    **dict.fromkeys(('T1B', 'T2B', 'T3B'), 'lb·ft'),
}


def deck_label(name: str) -> str:
    """A READ-list name with its listing unit, as an axis or a column shows it: ``ALPHA (rad)``."""
    unit = DECK_UNITS.get(name)
    return f"{name} ({unit})" if unit else name
