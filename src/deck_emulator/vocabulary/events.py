"""What happens to the post, as objects: the vocabulary both paths share.

An :class:`Event` is one thing the run reports: the post losing contact with the first
spring, with the car, or hitting something (the ground or one of the car's surfaces) with one
of its named points.  The 1967 path makes events from the FORMAT labels it writes
(:data:`EVENT_FORMATS`, read off the listing's messages); the modern core makes them from
located events and words them with the listing's messages (:data:`LOST_MESSAGES`,
:data:`HIT_MESSAGES`).  Nobody parses printed text back into events except
:mod:`deck_emulator.legacy.extract`, whose job is reading printouts that came from elsewhere.

This module imports only the vocabulary (the listing's words, :mod:`.listing_writes`): both
paths may use it.
"""

from __future__ import annotations

import enum
import re
from dataclasses import dataclass

from deck_emulator.vocabulary.listing_writes import MESSAGES


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


#: The listing's messages that report an event: FORMAT label -> (kind, surface, point).  The
#: words are the listing's (:data:`~deck_emulator.vocabulary.listing_writes.MESSAGES`, read from
#: ``legacy/luminaire.f``): a hit message names the surface (a :class:`Surface` by name) and, on
#: the ground, the point; the two messages of lost contact are these labels' (the one row of
#: meaning here).  The listing's car messages do not name the point: the program knows it from
#: the check it was in (P at labels 500-246, R at 112-262, C at 300-462) and passes it on.
_LOST_LABELS = {355: EventKind.LOST_FIRST_SPRING, 100: EventKind.LOST_VEHICLE}
_HIT = re.compile(r"(?P<head>.* HIT THE )(?P<surface>[A-Z]+)"
                  r"(?P<tail> OF THE VEHICLE| WITH POINT (?P<point>[A-Z]))")


def _event_formats() -> dict[int, tuple[EventKind, Surface | None, str | None]]:
    rows = {}
    for label, text in MESSAGES.items():
        if label in _LOST_LABELS:
            rows[label] = (_LOST_LABELS[label], None, None)
        elif (m := _HIT.fullmatch(text)) is not None:
            rows[label] = (EventKind.HIT, Surface[m["surface"]], m["point"])
    return rows


EVENT_FORMATS = _event_formats()


def _hit_messages() -> dict[str, str]:
    """Each surface's hit message: the listing's, the ground's point left open (``{point}``);
    FRONT and SIDE, which the listing cannot say, in the words of its car messages."""
    out, car = {}, ""
    for label, (kind, surface, point) in EVENT_FORMATS.items():
        if kind is EventKind.HIT:
            m = _HIT.fullmatch(MESSAGES[label])
            out[surface.name] = m.string[:m.start("point")] + "{point}" if point else m.string
            car = car or ("" if point else m.expand(r"\g<head>{surface}\g<tail>"))
    return out | {s.name: car.format(surface=s.name) for s in Surface
                  if s.on_car and s.name not in out}


#: The listing's messages of lost contact, by the event's kind.
LOST_MESSAGES = {kind: MESSAGES[label] for label, kind in _LOST_LABELS.items()}
#: The hit messages by the surface hit (its :class:`Surface` name): the listing's FORMATs 97-248,
#: and FRONT and SIDE, the core's exact outline, worded as the listing words the car's surfaces.
HIT_MESSAGES = _hit_messages()
#: Two luminaires landing together (the core's twin): the ground message, for two points.
JOINT_GROUND_MESSAGE = HIT_MESSAGES["GROUND"].replace("POINT {point}", "POINTS {points}")


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

#: The post's points an outcome traces (its ``points``, beside the mass centre CM): the
#: listing's P, Q, R and C, and the twin's U; the one row the engines and the pictures pick
#: their points from.
TRACED_POINTS = ("P", "Q", "R", "C", "U")


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
