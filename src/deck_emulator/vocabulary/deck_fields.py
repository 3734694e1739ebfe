"""The 64 fields of the deck, one row each: the listing's READ-list name, its card and field
(FORMAT(8F10.5): eight fields of ten columns on each of eight cards), its unit, where it goes
in a scene, and one line of what it is (TTI Report 75-9's nomenclature, Appendix).

Everything about a deck field is derived from here: the READ list and the columns the card
reader reads (``legacy.deck``), the units (``parse``, axis labels), the deck <-> scene mapping
(``vocabulary.scene``), the fields the scene leaves to the listing's difference scheme.  A new
field is one new row.
"""

from __future__ import annotations

from dataclasses import dataclass

#: FORMAT(8F10.5)
FIELDS_PER_CARD = 8
FIELD_WIDTH = 10
CARD_COLUMNS = 80


@dataclass(frozen=True)
class DeckField:
    """One field: ``name`` in the READ list, on ``card`` as its ``field``-th field (both
    1-based), in ``unit`` (empty: a pure number); ``scene``: the path of the scene field it is
    (through the tables of ``Scene.to_toml``; None: the initial state, which a scene keeps as
    a quaternion and body rates, or a start value of the listing's difference scheme, which
    the first step overwrites: ``role`` says which); ``meaning``: one line."""

    name: str
    card: int
    field: int
    unit: str
    scene: tuple[str, ...] | None
    role: str  # "scene", "initial" or "scheme"
    meaning: str

    @property
    def columns(self) -> tuple[int, int]:
        """First and last column (1-based) of the field on its card."""
        return field_columns(self.field)


def _point(letter: str, attr: str, what: str) -> list[tuple]:
    return [(f"{axis}{letter}O", "ft", ("post", attr, coord), "scene",
             f"{axis} of {what} at t = 0 (road axes XX, YY, ZZ)")
            for axis, coord in (("X", "xx_ft"), ("YY", "yy_ft"), ("ZZ", "zz_ft"))]


_V = ("vehicle",)
_BODY = ("vehicle", "body")
#: (name, unit, scene path, role, meaning), in READ order: card by card, eight a card
_ROWS: list[tuple] = [
    # card 1
    ("V1B", "ft/s", None, "initial", "the post's mass-centre velocity at t = 0, body axis 1"),
    ("V2B", "ft/s", None, "initial", "the same, body axis 2"),
    ("V3B", "ft/s", None, "initial", "the same, body axis 3"),
    ("VVB", "ft/s", (*_V, "initial_velocity_ft_s"), "scene",
     "the car's velocity along its path XV at t = 0 (negative: towards the post)"),
    ("F1B", "lb", None, "scheme", "the force on the post at the step before, body axis 1"),
    ("F2B", "lb", None, "scheme", "the same, body axis 2"),
    ("F3B", "lb", None, "scheme", "the same, body axis 3"),
    ("PSIDB", "rad/s", None, "scheme", "the Euler angle PSI's rate at the step before"),
    # card 2
    ("THDB", "rad/s", None, "scheme", "the Euler angle THETA's rate at the step before"),
    ("PHIDB", "rad/s", None, "scheme", "the Euler angle PHI's rate at the step before"),
    ("W", "slug", ("post", "mass_slug"), "scene", "the post's mass"),
    ("WV", "slug", (*_V, "mass_slug"), "scene", "the car's mass"),
    ("A", "slug·ft²", ("post", "inertia_1_slug_ft2"), "scene",
     "the post's principal moment of inertia about body axis 1"),
    ("B", "slug·ft²", ("post", "inertia_2_slug_ft2"), "scene", "the same, body axis 2"),
    ("C", "slug·ft²", ("post", "inertia_3_slug_ft2"), "scene", "the same, body axis 3"),
    ("G", "ft/s²", ("environment", "gravity_ft_s2"), "scene", "the acceleration of gravity"),
    # card 3
    ("XCMB", "ft", None, "initial", "the post's mass centre at t = 0, XX"),
    ("YCMB", "ft", None, "initial", "the same, YY"),
    ("ZCMB", "ft", None, "initial", "the same, ZZ"),
    ("CK", "lb/ft", (*_V, "first_spring", "stiffness_lb_per_ft"), "scene",
     "the stiffness of the car's first crush spring (at the impact point S)"),
    ("W1B", "rad/s", None, "initial", "the post's angular velocity at t = 0, body axis 1"),
    ("W2B", "rad/s", None, "initial", "the same, body axis 2"),
    ("W3B", "rad/s", None, "initial", "the same, body axis 3"),
    ("HEIGHT", "ft", ("environment", "ground_depth_ft"), "scene",
     "the depth of the ground below the road axes' origin"),
    # card 4
    ("PSIB", "rad", None, "initial", "the Euler angle PSI at t = 0"),
    ("THB", "rad", None, "initial", "the Euler angle THETA at t = 0"),
    ("PHIB", "rad", None, "initial", "the Euler angle PHI at t = 0"),
    ("SVB", "ft", (*_V, "initial_position_ft"), "scene",
     "the car's reference point along XV at t = 0"),
    *_point("S", "first_impact", "the first impact point S"),
    ("FNA", "lb", ("base", "normal_force_lb"), "scene",
     "the normal force holding the breakaway base"),
    # card 5
    *_point("P", "top", "the top of the post P"),
    *_point("Q", "base", "the base of the post Q"),
    ("SVO", "ft", (*_V, "contact_position_ft"), "scene",
     "the car's reference point along XV when it first touches the post"),
    ("ALPHA", "rad", (*_V, "approach_angle_rad"), "scene", "the car's approach angle"),
    # card 6
    ("T1B", "lb·ft", None, "scheme", "the torque on the post at the step before, body axis 1"),
    ("T2B", "lb·ft", None, "scheme", "the same, body axis 2"),
    ("T3B", "lb·ft", None, "scheme", "the same, body axis 3"),
    ("HLEN", "ft", (*_BODY, "hood_length_ft"), "scene", "the car's hood length"),
    ("TLEN", "ft", (*_BODY, "top_length_ft"), "scene", "the car's top (roof) length"),
    ("DELTA", "rad", ("post", "principal_tilt_rad"), "scene",
     "the tilt of the post's principal axes from its geometric ones"),
    ("YLFEN", "ft", (*_BODY, "left_fender_ft"), "scene", "the car's left fender, YV"),
    ("YRFEN", "ft", (*_BODY, "right_fender_ft"), "scene", "the car's right fender, YV"),
    # card 7
    ("TRLEN", "ft", (*_BODY, "trunk_length_ft"), "scene", "the car's trunk length"),
    ("HTRV", "ft", (*_BODY, "trunk_height_ft"), "scene", "the car's trunk height"),
    ("FSB", "lb", None, "scheme", "the first spring's force at the step before"),
    ("HTV", "ft", (*_BODY, "top_height_ft"), "scene", "the car's top (roof) height"),
    ("HHV", "ft", (*_BODY, "hood_height_ft"), "scene", "the car's hood height"),
    *_point("R", "luminaire_end", "the luminaire end R"),
    # card 8
    *_point("C", "point_c", "the post's point C"),
    *_point("T", "second_impact", "the second impact point T"),
    ("CT", "lb/ft", (*_V, "second_spring", "stiffness_lb_per_ft"), "scene",
     "the stiffness of the car's second crush spring (at T)"),
    ("FCONST", "lb", (*_V, "force_cap_lb"), "scene",
     "the largest force the crush springs give (the force cap)"),
]

#: the 64 fields, in READ order
DECK_FIELDS: tuple[DeckField, ...] = tuple(
    DeckField(name, i // FIELDS_PER_CARD + 1, i % FIELDS_PER_CARD + 1, unit, scene, role, meaning)
    for i, (name, unit, scene, role, meaning) in enumerate(_ROWS))
#: the READ list: the names card by card
READ_LIST: tuple[tuple[str, ...], ...] = tuple(
    tuple(f.name for f in DECK_FIELDS if f.card == card)
    for card in range(1, len(DECK_FIELDS) // FIELDS_PER_CARD + 1))
#: the 64 names, flat, in READ order
NAMES: tuple[str, ...] = tuple(f.name for f in DECK_FIELDS)
#: name -> its unit (names of pure numbers left out)
DECK_UNITS: dict[str, str] = {f.name: f.unit for f in DECK_FIELDS if f.unit}
#: the one deck <-> scene mapping: name -> the scene field's path
SCENE_PATHS: dict[str, tuple[str, ...]] = {f.name: f.scene for f in DECK_FIELDS if f.scene}


def field_columns(index: int) -> tuple[int, int]:
    """First and last column (1-based) of field ``index`` (1-based) on a card."""
    first = (index - 1) * FIELD_WIDTH + 1
    return first, first + FIELD_WIDTH - 1


def deck_label(name: str) -> str:
    """A READ-list name with its listing unit, as an axis or a column shows it: ``ALPHA (rad)``."""
    unit = DECK_UNITS.get(name)
    return f"{name} ({unit})" if unit else name
