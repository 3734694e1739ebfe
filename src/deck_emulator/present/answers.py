"""What the commands answer: one vocabulary, a table a person reads, the same content as JSON.

Every quantity a command prints has one name (the JSON key), one label, one unit and one
number of digits, all in the registry :data:`deck_emulator.engine.quantities.QUANTITIES`,
which also defines its value; the table and the JSON are both built from the same answer
dict, so they cannot disagree.  The JSON schema is documented in ``docs/json.md``
(a test checks that every name here is listed there).
"""

from __future__ import annotations

from deck_emulator.engine import quantities
from deck_emulator.engine.quantities import QUANTITIES
from deck_emulator.vocabulary.deck_fields import DECK_FIELDS, READ_LIST

#: Version of the JSON answers; bumped when a key changes meaning or goes away.
SCHEMA = 2

#: The keys every command's JSON answer begins with (docs/json.md): the schema's version, the
#: command, what it was given, how it ran, ``"ok"`` or ``"stopped"`` (exit status 3), and the
#: notes a reader must see; the command's own keys follow.
ENVELOPE = ("schema", "command", "source", "settings", "status", "notes")


def envelope(command: str, source, *, settings: dict | None = None, status: str = "ok",
             notes=(), **result) -> dict:
    """A JSON answer: the :data:`ENVELOPE` keys, then the command's ``result`` keys."""
    return {"schema": SCHEMA, "command": command, "source": source,
            "settings": dict(settings or {}), "status": status, "notes": list(notes),
            **result}

#: The terminal points' coordinates (ft, the printout's five decimals).
POINT_DIGITS = 5
#: What summary and core print: the outcome, then the occupant risk.
OUTCOME = ("hit_time_s", "delta_v_crush_mph", "delta_v_contact_mph", "max_decel_g")
OCCUPANT_RISK = ("oiv_m_s", "ora_g", "max_decel_10ms_g", "occupant_strike_time_s",
                 "body_clearance_ft", "roof_clearance_ft")


# ------------------------------------------------------------------------ summary and core


def criteria_answer() -> dict:
    """The limits the answers are judged by, each with its standard and citation; only those
    that can be cited (see docs/safety.md for the unconfirmed ones)."""
    from deck_emulator.engine.safety import CRITERIA, STANDARDS

    return {k: {"standard": STANDARDS[c.standard].title, "quantity": c.quantity,
                "preferred": c.preferred, "maximum": c.maximum, "unit": c.unit,
                "limit": c.label(), "source": c.source}
            for k, c in CRITERIA.items()}


def outcome_result(out) -> dict:
    """An engine's :class:`Outcome` as the answer of ``summary``, ``core`` or ``assembly``
    (the keys after the envelope's): the registry's quantities, read from the outcome, and
    the verdicts (:func:`deck_emulator.engine.ratings.ratings`)."""
    from deck_emulator.engine.ratings import ratings

    quantities_ = quantities.values(out, OUTCOME)
    risk = None
    if out.scene is not None and out.t.size and quantities.value("oiv_m_s", out) is not None:
        risk = quantities.values(out, OCCUPANT_RISK)
    # what a run that stopped did not reach: no value, and why (nothing is rated for it)
    missing = quantities.unavailable(out, OUTCOME + OCCUPANT_RISK)
    # a coordinate the printout could not hold (its field overflowed: ****) is None; the
    # outcome's flags name it
    terminal = {k: [None if v is None else round(float(v), POINT_DIGITS) for v in p]
                for k, p in (out.terminal or {}).items() if p is not None}
    return dict(
        engine=out.engine,
        errata=list(out.errata),
        events=[e.as_dict() for e in out.events],
        quantities=quantities_,
        terminal_xl_yl_zl_ft=terminal,
        occupant_risk=risk,
        ratings=ratings(out) if risk is not None else None,
        criteria=criteria_answer() if risk is not None else None,
        unavailable=missing,
    )


def _table(rows: list[tuple[str, ...]], heads: tuple[str, ...], right: set[int]) -> list[str]:
    widths = [max(len(r[i]) for r in [heads, *rows]) for i in range(len(heads))]

    def line(r):
        return "  ".join(c.rjust(w) if i in right else c.ljust(w)
                         for i, (c, w) in enumerate(zip(r, widths))).rstrip()

    return [line(heads)] + [line(r) for r in rows]


def _quantity_rows(values: dict) -> list[tuple[str, ...]]:
    return [(QUANTITIES[k].label, k, QUANTITIES[k].show(v), QUANTITIES[k].unit)
            for k, v in values.items()]


def _setting(v) -> str:
    """A setting as a person reads it: ``sincos chop, decimal round`` for a mapping, the
    items of a list joined, anything else as it stands."""
    if isinstance(v, dict):
        return ", ".join(f"{k} {x}" for k, x in v.items())
    if isinstance(v, (list, tuple)):
        return ", ".join(map(str, v)) or "none"
    return str(v)


def compartment_words(comp: dict) -> str:
    """The occupant compartment's verdict (:func:`~deck_emulator.engine.ratings.compartment`)
    in a line: the verdict, and the first place the post meets the car, as what it is (the
    hood and the trunk are not the compartment)."""
    if comp["part"] is None:
        return comp["verdict"]
    where = ("on the occupant compartment" if comp["in_compartment"] else
             "outside the occupant compartment" if comp["in_compartment"] is False else
             "where on the car is not known")
    return (f"{comp['verdict']}: {comp['part']} strikes the {comp['surface']} at "
            f"{1000 * comp['time_s']:.1f} ms ({where})")


def _rating_lines(ratings: dict) -> list[str]:
    """The verdicts as lines: the occupant compartment, then each rated reading against
    each standard's limit."""
    from deck_emulator.engine.safety import CRITERIA, STANDARDS

    comp = ratings["occupant_compartment"]
    lines = [f"  occupant compartment: {compartment_words(comp)}", f"    {comp['reason']}"]
    for name, r in ratings.items():
        if name == "occupant_compartment" or not r["verdicts"]:
            continue
        q = QUANTITIES[name]
        words = "; ".join(f"{STANDARDS[CRITERIA[k].standard].name}: {w}"
                          for k, w in r["verdicts"].items())
        why = f" ({r['reason']})" if r["reason"] else ""
        lines.append(f"  {name} {q.show(r['value'])} {q.unit}: {words}{why}")
    return lines


def _limit_lines(criteria: dict) -> list[str]:
    """The cited limits, one a line with its source (those not confirmed in a source are
    left out: docs/safety.md lists them)."""
    from deck_emulator.engine.safety import CRITERIA, STANDARDS

    lines = [f"  {c['quantity']}, {STANDARDS[CRITERIA[k].standard].name}: {c['limit']} "
             f"({c['source']})" for k, c in criteria.items()]
    return lines + ["  (a limit not confirmed in a source is left out: docs/safety.md lists them)"]


def render_outcome(a: dict) -> str:
    """The table of ``summary`` / ``core``."""
    lines = [f"{a['source']}: the {a['engine']}"]
    lines += [f"  {k}: {_setting(v)}" for k, v in a["settings"].items()]
    lines += [f"note: {n}" for n in a["notes"]]
    lines += ["", "events"]
    lines += [f"  {e['sentence']}" for e in a["events"]] or ["  none"]
    lines += [""] + _table(_quantity_rows(a["quantities"]), ("outcome", "name", "value", "unit"),
                           {2})
    if a.get("unavailable"):  # the run stopped before these were reached: why, once each
        by_reason: dict[str, list[str]] = {}
        for name, why in a["unavailable"].items():
            by_reason.setdefault(why, []).append(name)
        lines += ["", "no value (-) and no rating:"]
        lines += [f"  {', '.join(names)}: {why}" for why, names in by_reason.items()]
    if a["terminal_xl_yl_zl_ft"]:
        rows = [(k, *("*" * 10 if x is None else f"{x:.{POINT_DIGITS}f}" for x in p))
                for k, p in a["terminal_xl_yl_zl_ft"].items()]
        lines += ["", "at the hit (ft, the report's XL, YL, ZL axes)"]
        lines += ["  " + s for s in _table(rows, ("point", "XL", "YL", "ZL"), {1, 2, 3})]
    if a["occupant_risk"]:
        lines += [""] + _table(_quantity_rows(a["occupant_risk"]),
                               ("occupant risk (docs/safety.md)", "name", "value", "unit"), {2})
        if a.get("ratings"):
            lines += ["", "ratings (docs/safety.md)"] + _rating_lines(a["ratings"])
        lines += ["", "limits, with their sources"] + _limit_lines(a["criteria"])
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------- parse


def parse_result(deck) -> dict:
    """A deck's 64 values under their READ-list names, with their units (the keys after the
    envelope's)."""
    cards = []
    for card_no in range(1, len(READ_LIST) + 1):  # each card's rows of the deck-field table
        cards.append({"card": card_no, "fields": [
            {"name": f.name, "columns": list(f.columns), "value": deck[f.name], "unit": f.unit}
            for f in DECK_FIELDS if f.card == card_no]})
    return {"values": dict(deck.values), "cards": cards}


def _field(value: float) -> str:
    """FORMAT F10.5's five decimals, unless the card gave more (then every digit it gave)."""
    shown = f"{value:.5f}"
    return shown if float(shown) == value else repr(value)


def render_parse(a: dict) -> str:
    lines = [f"{a['source']}: 8 cards, FORMAT(8F10.5)"]
    for card in a["cards"]:
        rows = [(f"{f['columns'][0]}-{f['columns'][1]}", f["name"], _field(f["value"]),
                 f["unit"]) for f in card["fields"]]
        lines += ["", f"card {card['card']}"]
        lines += ["  " + s for s in _table(rows, ("columns", "name", "value", "unit"), {2})]
    return "\n".join(lines) + "\n"
