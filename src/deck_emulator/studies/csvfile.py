"""The one CSV layout of the studies' tables: a header, one line a row, floats to 12
significant digits, empty cells for None and NaN, ``true``/``false`` for booleans.

12 digits: more than any number here supports (the core's tolerances are 1e-10 at the
tightest the studies use; the emulator's times are sums of its 0.0004 s steps, whose last
bits are binary rounding: 0.8143999999999756 s is the printout's 0.8144), and fewer than
the float's 17, whose last ones would only carry that rounding into the tables."""

from __future__ import annotations

import csv
import io
import math
import numbers


def csv_value(v):
    """One cell as the CSV holds it."""
    kind = type(v)  # the plain kinds first: the abstract classes' checks cost 0.1 ms a row
    if kind is float:
        return "" if math.isnan(v) else repr(float(f"{v:.12g}"))
    if kind is str:
        return v
    if v is None:
        return ""
    if isinstance(v, bool) or type(v).__name__ == "bool_":
        return "true" if v else "false"
    if isinstance(v, numbers.Integral):
        return int(v)
    if isinstance(v, numbers.Real):
        return "" if math.isnan(v) else repr(float(f"{float(v):.12g}"))
    return v


def csv_text(rows: list[dict], columns) -> str:
    """The CSV of ``rows`` (one line per row, ``columns`` in order) as text."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(columns), extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for row in rows:
        w.writerow({c: csv_value(row.get(c)) for c in columns})
    return buf.getvalue()
