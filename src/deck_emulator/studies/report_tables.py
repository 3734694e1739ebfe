"""The report's own results for the steel post: Tables 11 and 12 of TTI Research Report 75-9.

This is the one place in the project that holds the report's numbers. They are the "STEEL POST"
columns (the middle three of nine: aluminium post, steel post, twin-luminaire steel post) of

* Table 11, "A COMPARISON OF MODEL RESULTS FOR A VEHICULAR VELOCITY OF 20 MPH"
  (rows at lines 1752-1768 of the OCR text, see :data:`SOURCE`), and
* Table 12, the same for 40 MPH (lines 1776-1792),

each for approach angles alpha = 0, 15, 30 degrees, keyed here by the name of the deck in
``decks/`` that reproduces that case. Values are copied as printed (text, then ``float``); a
dash or an empty cell is ``None``. The weight of the assembly is 485.07 lb in every column.

Row meanings (the report's Chapter VI): ``delta_v_crush_mph`` "DECREASE IN VEHICLE VELOCITY (MPH)";
``max_decel_g`` "MAXIMUM VEHICLE DECELERATION (g's)"; ``XPL`` ... ``ZQL`` the coordinates (ft)
of points P (top of the post), R (luminaire end of the arm) and Q (base of the post) in the
XL, YL, ZL axes, "origin at the base of the support ... determined by translating the XX, YY,
ZZ coordinate system", taken "at a time when the post, on its return path, has struck either
the vehicle or the ground"; ``time_to_hit_car_ms`` / ``time_to_hit_ground_ms``; ``comment``.
"""

from __future__ import annotations

from types import MappingProxyType

#: Where the numbers come from: the report, and the text the line numbers below refer to.
SOURCE = ("J. E. Martinez, An Analytical Solution of the Impact Behavior of Luminaire Support "
          "Assemblies, Texas Transportation Institute Research Report 75-9 (1967), Chapter VI, "
          "Tables 11 and 12; line numbers of the project's OCR text of the report")

#: Seed line (1-based) of each row label, for Table 11 (20 mph) and Table 12 (40 mph).
SEED_LINES = MappingProxyType({
    20: MappingProxyType({"DECREASE IN VEHICLE VELOCITY (MPH)": 1752,
                          "MAXIMUM VEHICLE DECELERATION": 1753, "XPL (FT)": 1754,
                          "YPL (FT)": 1755, "ZPL (FT)": 1756, "XRL (FT)": 1757,
                          "YRL (FT)": 1758, "ZRL (FT)": 1759, "XQL (FT)": 1760,
                          "YQL (FT)": 1761, "ZQL (FT)": 1762,
                          "TIME TO HIT CAR (MILLISEC)": 1766,
                          "TIME TO HIT GROUND (MILLISEC)": 1767, "COMMENTS": 1768}),
    40: MappingProxyType({"DECREASE IN VEHICLE VELOCITY (MPH)": 1776,
                          "MAXIMUM VEHICLE DECELERATION": 1777, "XPL (FT)": 1778,
                          "YPL (FT)": 1779, "ZPL (FT)": 1780, "XRL (FT)": 1781,
                          "YRL (FT)": 1782, "ZRL (FT)": 1783, "XQL (FT)": 1784,
                          "YQL (FT)": 1785, "ZQL (FT)": 1786,
                          "TIME TO HIT CAR (MILLISEC)": 1790,
                          "TIME TO HIT GROUND (MILLISEC)": 1791, "COMMENTS": 1792}),
})

#: Field name here -> row label in the seed (the label text up to its first tab).
ROW_LABELS = MappingProxyType({
    "delta_v_crush_mph": "DECREASE IN VEHICLE VELOCITY (MPH)",
    "max_decel_g": "MAXIMUM VEHICLE DECELERATION",
    "XPL": "XPL (FT)", "YPL": "YPL (FT)", "ZPL": "ZPL (FT)",
    "XRL": "XRL (FT)", "YRL": "YRL (FT)", "ZRL": "ZRL (FT)",
    "XQL": "XQL (FT)", "YQL": "YQL (FT)", "ZQL": "ZQL (FT)",
    "time_to_hit_car_ms": "TIME TO HIT CAR (MILLISEC)",
    "time_to_hit_ground_ms": "TIME TO HIT GROUND (MILLISEC)",
    "comment": "COMMENTS",
})

#: The numeric fields, in the order of the report's rows.
NUMERIC_FIELDS = ("delta_v_crush_mph", "max_decel_g", "XPL", "YPL", "ZPL", "XRL", "YRL", "ZRL",
                  "XQL", "YQL", "ZQL", "time_to_hit_car_ms", "time_to_hit_ground_ms")

#: Steel-post columns as printed (text), row -> (alpha 0, 15, 30); "" is an empty or dashed cell.
_TABLE11_STEEL = {  # 20 mph
    "delta_v_crush_mph": ("1.15", "1.17", "1.24"),
    "max_decel_g": ("3.31", "3.33", "3.37"),
    "XPL": ("3.39", "2.43", "1.65"),
    "YPL": ("-6.96", "-7.15", "-6.34"),
    "ZPL": ("19.77", "16.66", "12.07"),
    "XRL": ("6.64", "7.14", "6.35"),
    "YRL": ("0.30", "-1.84", "-4.53"),
    "ZRL": ("27.62", "25.30", "22.05"),
    "XQL": ("-26.51", "-26.59", "-25.29"),
    "YQL": ("2.00", "9.15", "16.56"),
    "ZQL": ("0.46", "1.19", "2.23"),
    "time_to_hit_car_ms": ("760.4", "807.6", "873.0"),
    "time_to_hit_ground_ms": ("", "", ""),
    "comment": ("POST HITS FRONT OF CAR",) * 3,
}
_TABLE12_STEEL = {  # 40 mph
    "delta_v_crush_mph": ("2.05", "2.05", "2.06"),
    "max_decel_g": ("6.58", "6.61", "6.70"),
    "XPL": ("-4.31", "-3.52", "-5.13"),
    "YPL": ("0.06", "-0.97", "-2.05"),
    "ZPL": ("8.82", "10.48", "8.88"),
    "XRL": ("-0.30", "-0.03", "1.26"),
    "YRL": ("-5.66", "-3.14", "0.56"),
    "ZRL": ("0.00", "0.00", "0.00"),
    "XQL": ("-40.60", "-38.43", "-33.63"),
    "YQL": ("-1.45", "9.74", "20.09"),
    "ZQL": ("14.16", "14.18", "15.59"),
    "time_to_hit_car_ms": ("", "", ""),
    "time_to_hit_ground_ms": ("819.2", "795.2", "792.0"),
    "comment": ("POST HITS GROUND WITH POINT R",) * 3,
}

#: The printed text of each cell, deck -> field -> text ("" for an empty or dashed cell).
REPORT_TEXT = MappingProxyType({
    f"steel{mph}{suffix}": MappingProxyType({k: v[i] for k, v in table.items()})
    for mph, table in ((20, _TABLE11_STEEL), (40, _TABLE12_STEEL))
    for i, suffix in enumerate(("", "_a15", "_a30"))
})


def _value(text: str):
    return None if text == "" else text if not _is_number(text) else float(text)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


#: deck -> field -> value: float for numbers, str for the comment, None for an empty cell.
REPORT = MappingProxyType({
    deck: MappingProxyType({k: _value(v) for k, v in cells.items()})
    for deck, cells in REPORT_TEXT.items()
})

#: deck -> (vehicle speed in mph, approach angle in degrees, table number).
CASES = MappingProxyType({
    "steel40": (40, 0, 12), "steel40_a15": (40, 15, 12), "steel40_a30": (40, 30, 12),
    "steel20": (20, 0, 11), "steel20_a15": (20, 15, 11), "steel20_a30": (20, 30, 11),
})


def report_time_ms(deck: str) -> float | None:
    """The report's time of the terminal event (hit car, or else hit ground), in ms."""
    row = REPORT[deck]
    return row["time_to_hit_car_ms"] if row["time_to_hit_car_ms"] is not None \
        else row["time_to_hit_ground_ms"]


def report_comment(hit) -> str:
    """A hit :class:`~deck_emulator.events.Event` in the words of the tables' COMMENTS row:
    'POST HITS GROUND WITH POINT R', 'POST HITS TOP OF CAR'."""
    surface = hit.surface.value.upper() if hit.surface else "?"
    if surface == "GROUND":
        return f"POST HITS GROUND WITH POINT {hit.point}"
    return f"POST HITS {surface} OF CAR"
