"""Free-flight checks: where the falling post first touches the ground or the car.

Each check is a *region* of one post point's position -- an intersection of half-spaces
``g = a_xv*XV + a_yv*YV + a_zz*ZZ + a_sv*SV + c >= 0`` (XV, YV, ZZ of the point; SV the
car's position) -- and a hit is the first time a point enters its region.  Entry happens
when one of the region's functions becomes non-negative while the others already are, so
every function is an event (direction +1) for ``solve_ivp``; the events on ground
functions end the integration, the others are recorded and sorted out afterwards.

Two sets of regions, chosen by ``ModelOptions.listing_hit_tolerances``:

* **listing** (labels 81-462): the ground band ``|ZZ + HEIGHT| <= 0.1`` ft for P, R and C,
  ``0.01`` ft for Q; for P, R and C inside the fenders ``YLFEN <= YV <= YRFEN``: the hood
  band ``|ZZ - HHV| <= 0.1`` over ``XBUMP <= XV < SV``; over ``SV <= XV <= XENTOP`` the
  windshield anywhere below ``HTV`` and the top in ``HTV <= ZZ <= HTV + 0.1``; the trunk
  band ``|ZZ - HTRV| <= 0.1`` over ``XENTOP < XV <= XTAIL``.
* **exact**: the ground plane ``ZZ = -HEIGHT``; the car as three solid boxes (hood,
  passenger compartment, trunk) reaching down to the ground, the surface named by the
  face crossed: the hood's top, the compartment's front (WINDSHIELD) or top (TOP), the
  trunk's top or rear (TRUNK); a box's front bumper face is FRONT, its flanks SIDE
  (two words the listing has not got).

Points checked, as in the listing: P, Q, R, C against the ground, P, R, C against the
car -- only those the scene has; a scene's second luminaire U is checked like R.
"""

from __future__ import annotations

import copy
import functools
from dataclasses import dataclass

import numpy as np

from deck_emulator.vocabulary.defaults import LISTING_GROUND_TOLERANCE_FT
from deck_emulator.vocabulary.scene import car_boxes

from . import laws
from .kinematics import EventSpec

__all__ = ["Region", "FreeFlightChecks", "build_checks"]

GROUND_POINTS = ("P", "Q", "R", "C", "U")
VEHICLE_POINTS = ("P", "R", "C", "U")
#: the listing's car-surface tolerance, ft (labels 235, 241, 246 ...)
LISTING_SURFACE_TOLERANCE_FT = 0.1
#: how far outside its other half-spaces a point may be and still count as inside (ft)
SLACK_FT = 1e-9


@dataclass(frozen=True)
class Region:
    """One check: ``point`` enters the intersection of ``rows`` (indices of functions);
    entering through ``rows[i]`` means hitting ``surfaces[i]``."""

    point: str
    kind: str  # "ground" or "vehicle"
    rows: tuple[int, ...]
    surfaces: tuple[str, ...]


class FreeFlightChecks:
    """All regions of a model, their functions as one matrix, and their events."""

    def __init__(self, model, points: tuple[str, ...]):
        self.model = model
        self.points = points
        self._row_key: dict[tuple, int] = {}
        self.row_point: list[int] = []
        self.row_coef: list[tuple[float, float, float, float]] = []
        self.row_const: list[float] = []
        self.regions: list[Region] = []
        self._cache_key = None
        self._cache_val = None

    # -- building

    def _row(self, point: str, coef, const: float) -> int:
        key = (point, tuple(float(c) for c in coef), float(const))
        if key not in self._row_key:
            self._row_key[key] = len(self.row_coef)
            self.row_point.append(self.points.index(point))
            self.row_coef.append(key[1])
            self.row_const.append(key[2])
        return self._row_key[key]

    def add_region(self, point: str, kind: str, half_spaces) -> None:
        """``half_spaces``: (coef (XV, YV, ZZ, SV), const, surface) triples."""
        rows = tuple(self._row(point, c, k) for c, k, _ in half_spaces)
        self.regions.append(Region(point, kind, rows, tuple(s for _, _, s in half_spaces)))

    def finish(self) -> "FreeFlightChecks":
        n, npnt = len(self.row_coef), len(self.points)
        A = np.zeros((n, 3 * npnt + 1))
        for i, (p, c) in enumerate(zip(self.row_point, self.row_coef)):
            A[i, 3 * p : 3 * p + 3] = c[:3]
            A[i, -1] = c[3]
        self.A = A
        self.const = np.array(self.row_const)
        #: the points' indices among the compiled laws' letters (:func:`~.laws.check_coordinates`)
        self.letters = np.array([laws.LETTERS.index(p) for p in self.points], dtype=np.int64)
        ground_rows = {r for reg in self.regions if reg.kind == "ground" for r in reg.rows}
        self.terminal = [i in ground_rows for i in range(n)]
        return self

    def bound(self, model) -> "FreeFlightChecks":
        """These checks for ``model`` (the rows, the matrix and the regions shared, read only;
        the last state's values its own)."""
        out = copy.copy(self)
        out.model, out._cache_key, out._cache_val = model, None, None
        return out

    # -- evaluation

    def values(self, y) -> np.ndarray:
        """All region functions at state ``y`` (cached for the last state)."""
        yl = y.tolist() if isinstance(y, np.ndarray) else list(y)
        key = tuple(yl)
        if key == self._cache_key:
            return self._cache_val
        z = np.empty(3 * len(self.points) + 1)
        laws.check_coordinates(np.asarray(yl, dtype=float), self.model.law_parameters,
                               self.letters, z)
        val = self.A @ z + self.const
        self._cache_key, self._cache_val = key, val
        return val

    def events(self):
        out = []
        for i, terminal in enumerate(self.terminal):
            out.append(EventSpec(f"row {i}", +1.0, (laws.EV_ROW, float(i)), terminal=terminal,
                                 function=lambda t, y, i=i: self.values(y)[i]))
        return out

    def inside(self, y) -> list[tuple[Region, str]]:
        """Regions that already hold their point at state ``y`` (surface: the first row's)."""
        g = self.values(y)
        return [(r, r.surfaces[0]) for r in self.regions if all(g[k] >= 0.0 for k in r.rows)]

    def entered(self, row: int, y) -> list[tuple[Region, str]]:
        """Regions entered when function ``row`` has just become zero at state ``y``."""
        g = self.values(y)
        out = []
        for r in self.regions:
            if row not in r.rows:
                continue
            if all(g[k] >= -SLACK_FT for k in r.rows if k != row):
                out.append((r, r.surfaces[r.rows.index(row)]))
        return out

    def priority(self, region: Region) -> int:
        return self.regions.index(region)


def build_checks(scene, options, model) -> FreeFlightChecks:
    """The regions of ``scene`` (only for points and a car body it has), for ``model``: made
    once for each layout (the post's points, the ground's depth, the tolerances, the car's
    outline) and shared by the models of a batch, whose scenes mostly differ in other
    numbers."""
    body = scene.vehicle.body if scene.vehicle is not None else None
    return _layout(frozenset(model.body_points), scene.environment.ground_depth_ft,
                   options.listing_hit_tolerances, body).bound(model)


@functools.lru_cache(maxsize=256)
def _layout(have: frozenset, depth: float, listing: bool, body) -> FreeFlightChecks:
    """The checks of one layout, bound to no model (:meth:`FreeFlightChecks.bound`)."""
    vpoints = tuple(p for p in VEHICLE_POINTS if p in have) if body is not None else ()
    gpoints = tuple(p for p in GROUND_POINTS if p in have)
    points = tuple(p for p in GROUND_POINTS if p in gpoints or p in vpoints)
    checks = FreeFlightChecks(None, points)

    # ground: h = ZZ + HEIGHT
    for p in gpoints:
        if listing:
            tol = LISTING_GROUND_TOLERANCE_FT[p]
            checks.add_region(
                p,
                "ground",
                [((0, 0, -1, 0), tol - depth, "GROUND"), ((0, 0, 1, 0), depth + tol, "GROUND")],
            )
        else:
            checks.add_region(p, "ground", [((0, 0, -1, 0), -depth, "GROUND")])

    if body is not None:
        # the outline relative to the car's reference point SV (the one outline, scene.py)
        o = body.outline_xv(0.0)
        hl, tl, trl = -o["XBUMP"], o["XENTOP"], o["XTAIL"] - o["XENTOP"]
        hh, ht, htr = body.hood_height_ft, body.top_height_ft, body.trunk_height_ft
        yl, yr = body.left_fender_ft, body.right_fender_ft
        for p in vpoints:
            if listing:
                tol = LISTING_SURFACE_TOLERANCE_FT

                def fenders(s):
                    return [((0, 1, 0, 0), -yl, s), ((0, -1, 0, 0), yr, s)]

                def band(h, s, tol=tol):
                    return [((0, 0, 1, 0), tol - h, s), ((0, 0, -1, 0), h + tol, s)]

                over_top = [((1, 0, 0, -1), 0.0), ((-1, 0, 0, 1), tl)]  # SV <= XV <= XENTOP
                checks.add_region(
                    p,
                    "vehicle",
                    fenders("HOOD")
                    + [((1, 0, 0, -1), hl, "HOOD"), ((-1, 0, 0, 1), 0.0, "HOOD")]
                    + band(hh, "HOOD"),
                )
                checks.add_region(
                    p,
                    "vehicle",
                    fenders("WINDSHIELD")
                    + [(c, k, "WINDSHIELD") for c, k in over_top]
                    + [((0, 0, -1, 0), ht, "WINDSHIELD")],
                )
                checks.add_region(
                    p,
                    "vehicle",
                    fenders("TOP")
                    + [(c, k, "TOP") for c, k in over_top]
                    + [((0, 0, 1, 0), -ht, "TOP"), ((0, 0, -1, 0), ht + tol, "TOP")],
                )
                checks.add_region(
                    p,
                    "vehicle",
                    fenders("TRUNK")
                    + [((1, 0, 0, -1), -tl, "TRUNK"), ((-1, 0, 0, 1), tl + trl, "TRUNK")]
                    + band(htr, "TRUNK"),
                )
            else:
                # the three boxes: XV - SV >= x0 (front face), XV - SV <= x1 (rear face),
                # the flanks (SIDE), ZZ <= top
                for box in car_boxes(body):
                    checks.add_region(
                        p,
                        "vehicle",
                        [((1, 0, 0, -1), 0.0 - box.x0_ft, box.front_surface),
                         ((-1, 0, 0, 1), box.x1_ft, box.rear_surface),
                         ((0, 1, 0, 0), -box.left_ft, "SIDE"),
                         ((0, -1, 0, 0), box.right_ft, "SIDE"),
                         ((0, 0, -1, 0), box.top_ft, box.top_surface)],
                    )
    return checks.finish()
