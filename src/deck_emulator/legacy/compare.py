"""Two printouts of the 1967 program, lined up record by record and value by value (issue 26).

A printout is read as :func:`~deck_emulator.legacy.extract.parse_printout` reads it: pages of
``THE VALUE OF name IS value`` lines (blocks) and ``THE POST HAS ...`` lines (messages), in
printed order.  The two are compared item by item: a message's words, a block's values name by
name.  Only what is printed is compared, so a printout typed or scanned from another source,
with other spacing or blank lines, compares equal to this tool's when every value and message
agrees.  A value agrees when both fields overflowed (``**********``) or when the two numbers
differ by at most ``tolerance`` (0: exactly as printed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from deck_emulator.legacy.extract import Block, Message, parse_printout

__all__ = ["Difference", "compare"]


@dataclass(frozen=True)
class Difference:
    """One disagreement: where (each printout's record, 1-based: the value's line, or the
    message's, or the page's first), what (a variable's name, ``message``, ``printed item``),
    the two values and the size (``None`` where no number measures it)."""

    item: int  # 1-based position among the printed blocks and messages
    record_a: int | None
    record_b: int | None
    time_s: float | None  # the block's TIME, where there is one
    what: str
    a: str
    b: str
    size: float | None

    def line(self) -> str:
        where = (f"record {self.record_a}" if self.record_a == self.record_b
                 else f"record {self.record_a} of A, {self.record_b} of B")
        when = "" if self.time_s is None else f" (TIME {self.time_s:g})"
        size = "" if self.size is None else f"  |difference| {self.size:.6g}"
        return f"{where}{when}: {self.what}: A {self.a}  B {self.b}{size}"


def _shown(value: float | None) -> str:
    return "**********" if value is None else f"{value:.5f}"


def _item(item: Block | Message | None) -> str:
    if item is None:
        return "nothing"
    if isinstance(item, Message):
        return repr(item.text)
    return f"a page of {len(item.values)} values"


def compare(a, b, tolerance: float = 0.0) -> list[Difference]:
    """The differences between printouts ``a`` and ``b`` (text, records, or an object with
    ``.records``); empty when they agree within ``tolerance``."""
    if not (tolerance >= 0.0 and math.isfinite(tolerance)):
        raise ValueError(f"tolerance must be finite and >= 0, got {tolerance}")
    items_a, items_b = parse_printout(a), parse_printout(b)
    out: list[Difference] = []
    for k in range(max(len(items_a), len(items_b))):
        x = items_a[k] if k < len(items_a) else None
        y = items_b[k] if k < len(items_b) else None
        rec_a = None if x is None else x.record + 1
        rec_b = None if y is None else y.record + 1
        if isinstance(x, Block) and isinstance(y, Block):
            time = x.time if x.time is not None else y.time
            for name in list(dict.fromkeys([*x.values, *y.values])):
                rec_a = x.value_records.get(name, x.record) + 1
                rec_b = y.value_records.get(name, y.record) + 1
                if name not in x.values or name not in y.values:
                    out.append(Difference(k + 1, rec_a, rec_b, time, name,
                                          _shown(x.values[name]) if name in x.values else "absent",
                                          _shown(y.values[name]) if name in y.values else "absent",
                                          None))
                    continue
                u, v = x.values[name], y.values[name]
                if u is None or v is None:
                    if u is not v:
                        out.append(Difference(k + 1, rec_a, rec_b, time, name, _shown(u),
                                              _shown(v), None))
                elif abs(u - v) > tolerance:
                    out.append(Difference(k + 1, rec_a, rec_b, time, name, _shown(u), _shown(v),
                                          abs(u - v)))
        elif isinstance(x, Message) and isinstance(y, Message):
            if x.text != y.text:
                out.append(Difference(k + 1, rec_a, rec_b, None, "message", repr(x.text),
                                      repr(y.text), None))
        else:
            out.append(Difference(k + 1, rec_a, rec_b, None, "printed item", _item(x),
                                  _item(y), None))
    return out
