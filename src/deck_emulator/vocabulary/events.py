"""What happens to the post, as objects: the vocabulary both paths share.

An :class:`Event` is one thing the run reports: the post losing contact with the first
spring, with the car, or hitting something (the ground or one of the car's surfaces) with one
of its named points.  The 1967 path makes events from the FORMAT labels it writes (the table
sits next to the FORMATs, in :mod:`deck_emulator.legacy.printer`); the modern core makes them
from located events.  Nobody parses printed text back into events except
:mod:`deck_emulator.legacy.extract`, whose job is reading printouts that came from elsewhere.

This module imports nothing from the package: both paths may use it.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass


class EventKind(enum.StrEnum):
    """What kind of thing happened: the events both engines report (the core names its located
    events by these members; its other located events, of its sliding modes and springs, are
    its own business)."""

    LOST_FIRST_SPRING = "lost contact with the first spring"
    LOST_VEHICLE = "lost contact with the vehicle"
    HIT = "hit"
    FORCE_CAP = "force cap engaged"  # the core's; the listing prints nothing for it
    LEAF_UNLOADS = "leaf spring unloads"  # the core's crash-test spring (Chapter V)


class Surface(str, enum.Enum):
    """What the post hit. The listing knows the first five; FRONT and SIDE are the core's
    exact outline (the bumper face and the flanks of its boxes)."""

    GROUND = "ground"
    HOOD = "hood"
    WINDSHIELD = "windshield"
    TOP = "top"
    TRUNK = "trunk"
    FRONT = "front"
    SIDE = "side"

    @property
    def on_car(self) -> bool:
        return self is not Surface.GROUND


#: The listing's messages, one row each: what its FORMATs 355 and 100 print when the post leaves
#: the first spring and the car (legacy/printer.py holds the FORMATs themselves, as the
#: listing writes them; a test holds the two equal), and its hit messages (FORMATs 97-248) by
#: the surface hit; FRONT and SIDE, and two luminaires landing together, are the core's own
#: words for what the listing cannot say.
LOST_MESSAGES = {
    EventKind.LOST_FIRST_SPRING: "THE POST HAS LOST CONTACT WITH FIRST SPRING",
    EventKind.LOST_VEHICLE: "THE POST HAS LOST CONTACT WITH THE VEHICLE",
}
HIT_MESSAGES = {
    "GROUND": "THE POST HAS HIT THE GROUND WITH POINT {point}",
    "HOOD": "THE POST HAS HIT THE HOOD OF THE VEHICLE",
    "WINDSHIELD": "THE POST HAS HIT THE WINDSHIELD OF THE VEHICLE",
    "TOP": "THE POST HAS HIT THE TOP OF THE VEHICLE",
    "TRUNK": "THE POST HAS HIT THE TRUNK OF THE VEHICLE",
    "FRONT": "THE POST HAS HIT THE FRONT OF THE VEHICLE",
    "SIDE": "THE POST HAS HIT THE SIDE OF THE VEHICLE",
}
JOINT_GROUND_MESSAGE = "THE POST HAS HIT THE GROUND WITH POINTS {points}"


def hit_message(surface: str, point: str) -> str:
    """The hit's message: ``surface`` a :data:`HIT_MESSAGES` key (GROUND, HOOD ...)."""
    return HIT_MESSAGES[surface].format(point=point)


#: The post's named points (the report's letters): P top, Q base, R luminaire end of the arm,
#: U a second luminaire, S and T the impact points of the two crush springs, C the listing's
#: extra point; CM the mass centre; Q-P, P-R, P-U the shaft and the arms as segments.
POINT_NAMES = {
    "P": "top P",
    "Q": "base Q",
    "R": "luminaire end R",
    "U": "second luminaire U",
    "R&U": "luminaire ends R and U together",
    "S": "impact point S",
    "T": "impact point T",
    "C": "point C",
    "CM": "mass centre",
    # segments (the core's shaft_contact option: the post checked as segments against the car)
    "Q-P": "shaft Q-P",
    "P-R": "arm P-R",
    "P-U": "second arm P-U",
}


@dataclass(frozen=True)
class Event:
    """One event: ``kind``, ``time_s``; for a hit the ``surface`` and the post ``point`` that
    touched it (``None`` where the source does not say); ``label`` the listing's FORMAT label
    when the 1967 program printed it.  A hit of a segment of the post (``point`` Q-P, P-R,
    P-U: the core's shaft test) says where along it (``fraction``, 0 at its first letter) and
    the other faces of the car it met at once (``edge``: the hit is on that edge of
    ``surface``)."""

    kind: EventKind
    time_s: float
    surface: Surface | None = None
    point: str | None = None
    label: int | None = None
    fraction: float | None = None
    edge: tuple[Surface, ...] = ()

    def sentence(self) -> str:
        """'post hit the ground with the luminaire end R at 819.2 ms'."""
        when = f"at {1000.0 * self.time_s:.1f} ms"
        if self.kind is EventKind.HIT:
            what = "the ground" if self.surface is Surface.GROUND else (
                f"the {self.surface.value} of the car" if self.surface else "something")
            who = f" with the {POINT_NAMES.get(self.point, self.point)}" if self.point else ""
            return f"post hit {what}{who} {when}"
        if self.kind is EventKind.FORCE_CAP:
            return f"crush force capped at FCONST {when}"
        return f"post {self.kind.value} {when}"

    def short(self) -> str:
        """'hit ground (R)', 'hit top (P)': for table cells."""
        if self.kind is EventKind.HIT:
            s = self.surface.value if self.surface else "?"
            return f"hit {s}" + (f" ({self.point})" if self.point else "")
        return self.kind.value

    def as_dict(self) -> dict:
        return {
            "kind": self.kind.name.lower(),
            "time_s": self.time_s,
            "surface": self.surface.value if self.surface else None,
            "point": self.point,
            "label": self.label,
            "fraction": self.fraction,
            "edge": [s.value for s in self.edge],
            "sentence": self.sentence(),
        }
