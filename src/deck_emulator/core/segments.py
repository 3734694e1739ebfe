"""The shaft and the arms against the car: segments of the post checked in free flight.

The listing (and :mod:`.regions`) checks only the points P, R and C against the car, so a
shaft falling across the hood with its ends clear goes through the car unseen.  Under
``ModelOptions.shaft_contact`` the core checks the segments Q-P, P-R, P-U (those the scene
has) and C where it lies off them against each of the car's three solid boxes
(:func:`deck_emulator.vocabulary.scene.car_boxes`), under either preset: the listing has no
segment test whose tolerances could be copied.

The event function of a segment ``X(s) = A + s (B - A)`` and a box is
``h = max over s in [0, 1] of min over k of g_k(X(s))``, ``g_k`` the signed distance to the
plane of face ``k`` (front, rear, two flanks, top; positive inside): the depth of the
segment's deepest point in the box.  Each ``g_k`` is affine in ``s``, so the maximum lies at
an end or where two lines cross: ``h`` is exact, with no iteration.  ``h`` is 1-Lipschitz in
the ends and the car's position, hence continuous along a run, and crosses zero upwards at
the first contact -- what scipy's event location needs (the Euclidean distance would not do:
it stays zero through a penetration).

The surface named is the face crossed: of the faces at the deepest point, the one whose
``g_k`` grew fastest.  A segment already inside a box when free flight starts (the crush the
car took) is checked against it only once it has left it (an upward crossing), as
:func:`deck_emulator.engine.safety.body_clearance` counts it; the notes say so.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .kinematics import IDX_SV, IDX_VV, EventSpec, Kinematics
from deck_emulator.vocabulary.scene import CarBox, car_boxes
from . import laws

__all__ = ["Pair", "SegmentChecks", "build_segment_checks", "post_segments"]

#: faces whose depth is within this of the deepest (ft) are "at" the contact
ACTIVE_FT = 1e-9
#: how close to a segment C must be to count as on it (ft)
ON_SEGMENT_FT = 1e-9


@dataclass(frozen=True)
class Pair:
    """One check: ``segment`` (its label; ends ``a``, ``b``, the same letter for a point)
    against ``box``."""

    segment: str
    a: str
    b: str
    box: CarBox


def post_segments(body_points: dict) -> list[tuple[str, str, str]]:
    """(label, end A, end B) of the post's segments: Q-P, P-R, P-U (those it has), and C as
    a point where it lies off them (principal-axes coordinates ``body_points``)."""
    out = [("Q-P", "Q", "P")]
    for arm in ("R", "U"):
        if arm in body_points:
            out.append((f"P-{arm}", "P", arm))
    if "C" in body_points:
        c = np.asarray(body_points["C"], float)
        on = False
        for _, a, b in out:
            pa, pb = np.asarray(body_points[a], float), np.asarray(body_points[b], float)
            d = pb - pa
            s = float(np.clip(np.dot(c - pa, d) / max(np.dot(d, d), 1e-300), 0.0, 1.0))
            on = on or float(np.linalg.norm(pa + s * d - c)) <= ON_SEGMENT_FT
        if not on:
            out.append(("C", "C", "C"))
    return out


FACE_SURFACES = ("front", "rear", "SIDE", "SIDE", "top")


class SegmentChecks:
    """The (segment, box) pairs of a model, their event functions and the surface hit."""

    def __init__(self, model, pairs: list[Pair]):
        self.model = model
        self.pairs = pairs
        self._cache_key = None
        self._cache_val = None
        # each pair as the compiled laws take it: its ends' positions among the free-flight
        # checks' points (their coordinates, :func:`~.laws.check_coordinates`), its box
        points = model.checks.points
        self.table = np.array([[points.index(p.a), points.index(p.b), p.box.x0_ft, p.box.x1_ft,
                                p.box.left_ft, p.box.right_ft, p.box.top_ft] for p in pairs],
                              dtype=float).reshape(-1, 7)

    def _coordinates(self, yl):
        checks = self.model.checks
        z = np.empty(3 * len(checks.points) + 1)
        laws.check_coordinates(np.asarray(yl, dtype=float), self.model.law_parameters,
                               checks.letters, z)
        return z

    def depths(self, y) -> list[tuple[float, float]]:
        """(h, s at the deepest point) of every pair at state ``y`` (cached for the last)."""
        yl = y.tolist() if isinstance(y, np.ndarray) else list(y)
        key = tuple(yl)
        if key == self._cache_key:
            return self._cache_val
        z = self._coordinates(yl)
        out = [laws.pair_depth(z, row) for row in self.table]
        self._cache_key, self._cache_val = key, out
        return out

    def events(self) -> list[EventSpec]:
        """One event per pair: ``h`` crossing zero upwards; recorded, not terminal (the
        earliest of all the free flight's candidates is the hit)."""
        return [EventSpec(f"segment {p.segment} / {p.box.part}", +1.0,
                          (laws.EV_SEGMENT, float(i)), terminal=False,
                          function=lambda t, y, i=i: self.depths(y)[i][0])
                for i, p in enumerate(self.pairs)]

    def inside(self, y) -> list[Pair]:
        """The pairs whose segment is inside its box at state ``y`` (``h > 0``)."""
        return [p for p, (h, _) in zip(self.pairs, self.depths(y)) if h > 0.0]

    def surface(self, i: int, y) -> tuple[str, float, tuple[str, ...]]:
        """(surface, s, others) of pair ``i`` at the state ``y`` of its located event: the
        face crossed, where along the segment, and the other faces through the contact (an
        edge: a straight segment meets a flat face first at an edge of it, or with an end,
        unless it lies parallel to it)."""
        p = self.pairs[i]
        m = self.model
        yl = y.tolist() if isinstance(y, np.ndarray) else list(y)
        z = self._coordinates(yl)
        ia, ib = int(self.table[i][0]), int(self.table[i][1])
        a, b = z[3 * ia: 3 * ia + 3], z[3 * ib: 3 * ib + 3]  # XV, YV, ZZ of the ends
        box = p.box
        ga, db = laws.segment_faces(a[0], a[1], a[2], b[0], b[1], b[2], yl[IDX_SV], box.x0_ft,
                                    box.x1_ft, box.left_ft, box.right_ft, box.top_ft)
        h, s = laws.segment_depth(ga, db)
        s = float(s)
        g = [float(x + d * s) for x, d in zip(ga, db)]
        active = [k for k in range(5) if g[k] <= h + ACTIVE_FT]
        kin = Kinematics(m, yl)
        va, vb = np.array(kin.point_velocity(p.a)), np.array(kin.point_velocity(p.b))
        v = (1.0 - s) * va + s * vb  # a rigid body's velocity is affine along a segment
        vxv, vyv = v[0] * m.cos_a - v[1] * m.sin_a, v[0] * m.sin_a + v[1] * m.cos_a
        vv = yl[IDX_VV]
        rates = (vxv - vv, vv - vxv, vyv, -vyv, -v[2])
        k = max(active, key=lambda j: rates[j])
        words = {"front": box.front_surface, "rear": box.rear_surface, "top": box.top_surface}
        name = [words.get(FACE_SURFACES[j], FACE_SURFACES[j]) for j in range(5)]
        others = tuple(dict.fromkeys(name[j] for j in active if name[j] != name[k]))
        return name[k], s, others


def build_segment_checks(scene, options, model) -> SegmentChecks | None:
    """The segment checks of ``scene`` under ``options`` (``None`` when the option is off
    or the scene has no car outline)."""
    if not options.shaft_contact:
        return None
    car = scene.vehicle
    if car is None or car.body is None:
        return None
    pairs = [Pair(label, a, b, box) for label, a, b in post_segments(model.body_points)
             for box in car_boxes(car.body)]
    return SegmentChecks(model, pairs)
