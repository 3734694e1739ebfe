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

def _value(text: str):
    return None if text == "" else text if not _is_number(text) else float(text)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


#: deck -> (vehicle speed in mph, approach angle in degrees, table number).
CASES = MappingProxyType({
    "steel40": (40, 0, 12), "steel40_a15": (40, 15, 12), "steel40_a30": (40, 30, 12),
    "steel20": (20, 0, 11), "steel20_a15": (20, 15, 11), "steel20_a30": (20, 30, 11),
})


def report_comment(hit) -> str:
    """A hit :class:`~deck_emulator.vocabulary.events.Event` in the words of the tables' COMMENTS row:
    'POST HITS GROUND WITH POINT R', 'POST HITS TOP OF CAR'."""
    surface = hit.surface.value.upper() if hit.surface else "?"
    if surface == "GROUND":
        return f"POST HITS GROUND WITH POINT {hit.point}"
    return f"POST HITS {surface} OF CAR"


# ------------------------------------------------------------------------------------------
# All 18 columns of Tables 11 and 12: aluminium, steel, twin-luminaire steel post.
#
# Same seed lines as the steel post's (the module docstring), plus the twin post's point U rows
# (XUL, YUL, ZUL: Table 11 lines 1763-1765, Table 12 lines 1787-1789). Column headings at
# lines 1748 and 1772, assembly weights at lines 1750 and 1774. Columns are named
# ``<post><mph>[_a15|_a30]`` like the steel decks ("aluminium40_a15", "twin20").
# Cells as printed; the OCR's "00.39" (Table 11, aluminium 0 deg, YQL) is kept as text and
# reads 0.39; "10.5" / "-10.5" / "0.0" as printed (one decimal where the scan has one).

NUMERIC_FIELDS_ALL = NUMERIC_FIELDS[:11] + ("XUL", "YUL", "ZUL") + NUMERIC_FIELDS[11:]

_TABLE11_ALUMINIUM = {  # 20 mph, line 1752 on
    "delta_v_crush_mph": ("1.07", "1.07", "1.09"),
    "max_decel_g": ("2.85", "2.86", "2.88"),
    "XPL": ("-0.48", "-0.96", "0.04"),
    "YPL": ("-6.39", "-4.35", "-1.02"),
    "ZPL": ("6.90", "5.07", "4.28"),
    "XRL": ("2.24", "2.07", "0.34"),
    "YRL": ("-1.51", "-1.30", "-6.59"),
    "ZRL": ("16.14", "15.40", "13.53"),
    "XQL": ("-29.09", "-27.87", "-25.13"),
    "YQL": ("00.39", "7.73", "14.23"),
    "ZQL": ("3.76", "5.04", "6.32"),
    "time_to_hit_car_ms": ("820.0", "829.0", "836.4"),
    "time_to_hit_ground_ms": ("", "", ""),
    "comment": ("POST HITS TOP OF CAR",) * 3,
}
_TABLE11_TWIN = {
    "delta_v_crush_mph": ("1.43", "1.43", "1.43"),
    "max_decel_g": ("3.31", "3.33", "3.35"),
    "XPL": ("-4.33", "-3.75", "-2.74"),
    "YPL": ("0.0", "1.68", "2.67"),
    "ZPL": ("3.93", "5.36", "7.78"),
    "XRL": ("0.42", "-0.76", "-0.13"),
    "YRL": ("-10.5", "-8.12", "-5.52"),
    "ZRL": ("3.76", "0.08", "0.0"),
    "XQL": ("-31.56", "-30.43", "-27.07"),
    "YQL": ("0.0", "7.15", "14.32"),
    "ZQL": ("4.91", "4.58", "3.98"),
    "XUL": ("0.42", "2.56", "3.15"),
    "YUL": ("10.5", "9.57", "6.79"),
    "ZUL": ("3.76", "10.90", "16.80"),
    "time_to_hit_car_ms": ("975.0", "971.2", ""),
    "time_to_hit_ground_ms": ("", "", "992.0"),
    "comment": ("POST HITS TOP OF CAR", "POST HITS TOP OF CAR", "POST HITS GROUND WITH POINT R"),
}
_TABLE12_ALUMINIUM = {  # 40 mph, line 1776 on
    "delta_v_crush_mph": ("1.90", "1.91", "1.94"),
    "max_decel_g": ("5.52", "5.54", "5.59"),
    "XPL": ("-8.91", "-11.28", "-13.49"),
    "YPL": ("-6.76", "-4.10", "1.04"),
    "ZPL": ("5.81", "3.37", "0.00"),
    "XRL": ("-6.81", "-5.62", "-3.55"),
    "YRL": ("2.15", "4.49", "5.17"),
    "ZRL": ("0.00", "0.00", "0.99"),
    "XQL": ("-35.40", "-33.28", "-28.77"),
    "YQL": ("-1.23", "7.80", "15.52"),
    "ZQL": ("17.56", "19.00", "20.75"),
    "time_to_hit_car_ms": ("", "", ""),
    "time_to_hit_ground_ms": ("730.0", "739.0", "746.8"),
    "comment": ("POST HITS GROUND WITH POINT R", "POST HITS GROUND WITH POINT R",
                "POST HITS GROUND WITH POINT P"),
}
_TABLE12_TWIN = {
    "delta_v_crush_mph": ("2.56", "2.58", "2.62"),
    "max_decel_g": ("6.60", "6.62", "6.71"),
    "XPL": ("-12.99", "-8.10", "-5.96"),
    "YPL": ("0.00", "3.05", "4.7"),
    "ZPL": ("3.49", "8.72", "10.81"),
    "XRL": ("-9.68", "-7.97", "-5.50"),
    "YRL": ("-10.50", "-4.58", "0.52"),
    "ZRL": ("0.00", "0.00", "0.00"),
    "XQL": ("-32.01", "-32.67", "-30.16"),
    "YQL": ("0.00", "7.02", "15.12"),
    "ZQL": ("23.01", "19.84", "17.76"),
    "XUL": ("-9.68", "0.33", "2.01"),
    "YUL": ("10.50", "9.30", "5.25"),
    "ZUL": ("0.00", "13.48", "19.12"),
    "time_to_hit_car_ms": ("", "", ""),
    "time_to_hit_ground_ms": ("808.0", "695.2", "657.2"),
    "comment": ("POST HITS GROUND WITH POINTS R&U", "POST HITS GROUND WITH POINT R",
                "POST HITS GROUND WITH POINT R"),
}

_ALL_TABLES = (
    ("aluminium", 20, _TABLE11_ALUMINIUM), ("steel", 20, _TABLE11_STEEL),
    ("twin", 20, _TABLE11_TWIN), ("aluminium", 40, _TABLE12_ALUMINIUM),
    ("steel", 40, _TABLE12_STEEL), ("twin", 40, _TABLE12_TWIN),
)

#: The printed text of all 18 columns: column -> field -> text.
REPORT_TEXT_ALL = MappingProxyType({
    f"{post}{mph}{suffix}": MappingProxyType({k: v[i] for k, v in table.items()})
    for post, mph, table in _ALL_TABLES
    for i, suffix in enumerate(("", "_a15", "_a30"))
})

#: All 18 columns as values (float, str for the comment, None for an empty cell).
REPORT_ALL = MappingProxyType({
    col: MappingProxyType({k: _value(v) for k, v in cells.items()})
    for col, cells in REPORT_TEXT_ALL.items()
})

#: column -> (post, mph, alpha in degrees, table number), in the report's column order.
CASES_ALL = MappingProxyType({
    f"{post}{mph}{suffix}": (post, mph, alpha, 11 if mph == 20 else 12)
    for mph in (20, 40)
    for post in ("aluminium", "steel", "twin")
    for alpha, suffix in ((0, ""), (15, "_a15"), (30, "_a30"))
})


#: The steel post's columns (the sweep's report values), deck -> field -> value.
REPORT = MappingProxyType({deck: REPORT_ALL[deck] for deck in REPORT_ALL if deck in CASES})


def report_time_ms_all(column: str) -> float | None:
    """The report's time of the terminal event (hit car, or else hit ground) of any of the 18
    columns, ms."""
    row = REPORT_ALL[column]
    return row["time_to_hit_car_ms"] if row["time_to_hit_car_ms"] is not None \
        else row["time_to_hit_ground_ms"]


#: the same of a steel post's column (its deck's name)
report_time_ms = report_time_ms_all


# ------------------------------------------------------------------------------------------
# Chapter V: the crash test (Tables 8, 9, 10), seed lines 1622-1674.

#: Table 8, "CRASH TEST DATA AT TWO CRITICAL TIMES" (lines 1622-1632): quantity -> (70 ms,
#: 270 ms); None where the table has a dash.  Units: deg, ft, ft, ft, ft/s, ft/s, rad/s.
TABLE8 = MappingProxyType({
    "theta_deg": (25.0, 122.0),     # line 1626
    "SV_ft": (3.2, 12.60),          # line 1627
    "XCM_ft": (-1.50, -7.10),       # line 1628
    "ZCM_ft": (+0.01, -0.19),       # line 1629
    "V1_ft_s": (-28.5, None),       # line 1630
    "V3_ft_s": (-12.5, None),       # line 1631
    "thetadot_rad_s": (8.75, 8.75), # line 1632
})
#: Table 8's two critical times, s (its columns: 70 and 270 ms)
TABLE8_TIMES_S = (0.070, 0.270)

#: Table 9, "COMPARISON OF MODEL DATA WITH CRASH TEST DATA AT 270 MILLISECONDS"
#: (lines 1652-1661): quantity -> (model, crash test).
TABLE9 = MappingProxyType({
    "HIT_ft": (7.55, 7.83),         # line 1656
    "theta_deg": (121.0, 122.0),    # line 1657
    "XCM_ft": (7.61, 7.10),         # line 1658
    "ZCM_ft": (0.27, 0.19),         # line 1659
    "SV_ft": (11.5, 11.04),         # line 1660
    "time_ms": (273.0, 270.0),      # line 1661
})

#: Table 10, "COMPARISON OF MODEL DATA WITH CRASH TEST DATA AT 70 MILLISECONDS"
#: (lines 1663-1674): quantity -> (model, crash test).
TABLE10 = MappingProxyType({
    "time_ms": (71.8, 70.0),            # line 1667
    "theta_deg": (26.0, 25.0),          # line 1668
    "thetadot_rad_s": (12.50, 8.75),    # line 1669
    "XCM_ft": (-1.20, -1.50),           # line 1670
    "ZCM_ft": (-0.04, +0.01),           # line 1671
    "V1_ft_s": (-28.75, -28.50),        # line 1672
    "V3_ft_s": (-15.47, -12.50),        # line 1673
    "SV_ft": (2.80, 3.20),              # line 1674
})

#: Chapter V's description of the test (lines 1578-1650), as numbers.
CRASH_TEST = MappingProxyType({
    "post_weight_lb": 215.0,            # line 1612 ("215 lbs._m")
    "post_inertia_slug_ft2": 62.0,      # line 1612 (about the mass centre, transverse)
    "post_cm_from_base_ft": 4.63,       # line 1612 (from the triangular-plate end)
    "post_length_ft": 9.0,              # line 1608
    "impact_point": "middle of the spring",  # line 1600 (its height is not given)
    "vehicle_weight_lb": 2800.0,        # line 1604
    "vehicle_speed_ft_s": 40.0,         # line 1606
    "loading_lb_per_ft": (12000.0, 26400.0),    # lines 1638-1642
    "unloading_lb_per_ft": (38400.0, 12000.0),  # lines 1644-1648
    "knee_in": 3.0,                     # line 1602 (second set of leaves engaged)
    "stop_in": 4.5,                     # lines 1602, 1650 (U-bolts meet the I-beam)
})
