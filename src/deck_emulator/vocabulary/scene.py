"""One crash scene, described in the report's terms, and the named model options.

A :class:`Scene` is what the 1967 program simulates -- a rigid break-away post struck
by a car -- written as frozen, typed dataclasses with descriptive names and the report's
units (ft, lb, slug, s, rad).  It is built from a card deck with :meth:`Scene.from_deck`
or from a TOML file with :meth:`Scene.from_toml`, and written with :meth:`Scene.to_toml`.

Axes (TTI Research Report 75-9, section 3.1; origin at the post's mass centre at t = 0):

* ``XX, YY, ZZ`` -- the road axes: ``XX`` along the highway, ``ZZ`` up.  Every position in
  a scene is given in these axes (the deck's ``XSO, YYSO, ZZSO`` ...).
* ``X, Y, Z`` -- the principal axes 1, 2, 3 of the post at t = 0, obtained by turning
  ``XX, YY, ZZ`` by the tilt delta about ``XX`` (``3`` is the post axis).
* ``XV, YV, ZV`` -- the vehicle axes: ``XX, YY, ZZ`` turned by the approach angle alpha
  about ``-ZZ``; the car travels along ``XV`` (towards ``-XV``: its speed is negative).

A component a scene does not have is ``None`` (no luminaire arm R, no point C, no second
crush spring T, no base friction, no car body outline, no vehicle at all); the core then
builds no force, no point and no check for it.

Deck names (the READ list) map to fields through :data:`SCENE_PATHS`, read and written both
ways; the initial state is kept as a quaternion and body rates.  The base friction and the
normal force's release are the listing's constants, not deck fields: :meth:`Scene.from_deck`
fills in :data:`LISTING_BASE_FRICTION` and :data:`LISTING_NORMAL_RELEASE_FT`.

:class:`ModelOptions` (with the presets :data:`LEGACY` and :data:`PHYSICAL`) says how the
core treats the listing's quirks -- each one a named flag, so every difference between the
emulator and the core can be traced to one option.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
import tomllib
import types
import typing
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, is_dataclass, replace
from typing import Any

from deck_emulator.vocabulary import choices
from deck_emulator.vocabulary.deck_fields import SCENE_PATHS
from deck_emulator.vocabulary.defaults import (
    LISTING_CAP_STEPS,
    LISTING_STEP_S,
    LISTING_THA_START,
    MAX_SCENE_BYTES,
)
from deck_emulator.vocabulary.units import G_FT_S2

__all__ = [
    "OVERRIDDEN",
    "overridden_fields",
    "Vec3",
    "PostPoint",
    "Post",
    "PostInitialState",
    "CrushSpring",
    "LeafSpring",
    "VehicleBody",
    "Vehicle",
    "BaseFriction",
    "BreakawayBase",
    "Environment",
    "Scene",
    "DeckScene",
    "StartupKick",
    "ModelOptions",
    "LEGACY",
    "PHYSICAL",
    "PRESETS",
    "LISTING_BASE_FRICTION",
    "LISTING_NORMAL_RELEASE_FT",
    "SceneError",
    "read_scene",
    "scene_from_bytes",
    "MAX_SCENE_BYTES",
]

Vec3 = tuple[float, float, float]


class SceneError(ValueError):
    """A scene that cannot be built (missing value, inconsistent components)."""


# --------------------------------------------------------------------------------------
# the post


@dataclass(frozen=True)
class PostPoint:
    """A point fixed on the post, relative to its mass centre, in the road axes at t = 0.

    ``xx_ft, yy_ft, zz_ft``: coordinates in ft along ``XX, YY, ZZ`` (the deck gives
    ``XPO, YYPO, ZZPO`` for P; the ``X`` coordinate is the same in both frames).
    """

    xx_ft: float
    yy_ft: float
    zz_ft: float

    def principal_coordinates(self, principal_tilt_rad: float) -> Vec3:
        """The point in the principal axes X, Y, Z (ft) -- the listing's ``XPO, YPO, ZPO``.

        ``YPO = YYPO*COS(DELTA) + ZZPO*SIN(DELTA)``, ``ZPO = -YYPO*SIN(DELTA) + ZZPO*COS(DELTA)``.
        """
        c, s = math.cos(principal_tilt_rad), math.sin(principal_tilt_rad)
        return (self.xx_ft, self.yy_ft * c + self.zz_ft * s, -self.yy_ft * s + self.zz_ft * c)


@dataclass(frozen=True)
class Post:
    """The rigid post assembly (post, base plate, luminaire arm); each field's deck name and
    meaning is its row of :mod:`~deck_emulator.vocabulary.deck_fields`.

    The principal axes X, Y, Z are the road axes turned by ``principal_tilt_rad`` about
    ``XX`` (3 is the post axis).  Of the named points (:data:`POINT_FIELDS`) P and Q are
    always there; the others are ``None`` when the scene has no such point.
    """

    mass_slug: float
    inertia_1_slug_ft2: float
    inertia_2_slug_ft2: float
    inertia_3_slug_ft2: float
    top: PostPoint
    base: PostPoint
    principal_tilt_rad: float = 0.0
    first_impact: PostPoint | None = None
    second_impact: PostPoint | None = None
    luminaire_end: PostPoint | None = None
    point_c: PostPoint | None = None
    #: U, the end of a second luminaire arm (the twin-luminaire post of Chapter VI); the
    #: listing has no such point (the core checks it against ground and car like R)
    second_luminaire_end: PostPoint | None = None

    #: listing letter -> field name, in the listing's checking order P, Q, R, C, then S, T
    POINT_FIELDS = {
        "P": "top",
        "Q": "base",
        "R": "luminaire_end",
        "C": "point_c",
        "S": "first_impact",
        "T": "second_impact",
        "U": "second_luminaire_end",
    }

    @property
    def principal_inertia_slug_ft2(self) -> Vec3:
        return (self.inertia_1_slug_ft2, self.inertia_2_slug_ft2, self.inertia_3_slug_ft2)

    def points(self) -> dict[str, PostPoint]:
        """The points this post has, by listing letter (absent points are left out)."""
        out = {}
        for letter, name in self.POINT_FIELDS.items():
            point = getattr(self, name)
            if point is not None:
                out[letter] = point
        return out


@dataclass(frozen=True)
class PostInitialState:
    """The post's motion at t = 0 (the deck's B values): the mass centre in ``XX, YY, ZZ``
    (the deck gives ``XCMB, YCMB, ZCMB`` in ``X, Y, Z``), its velocity (``V1B`` ...) and the
    angular velocity (``W1B`` ...) along the body axes, and the attitude as a unit quaternion
    ``(w, x, y, z)``, the report's rotation parameters ``(chi, xi, eta, zeta)`` (eq. 2.51;
    :meth:`from_euler` converts the listing's ``PSIB, THB, PHIB``)."""

    mass_centre_ft: Vec3 = (0.0, 0.0, 0.0)
    velocity_body_ft_s: Vec3 = (0.0, 0.0, 0.0)
    angular_velocity_body_rad_s: Vec3 = (0.0, 0.0, 0.0)
    attitude_wxyz: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)

    @staticmethod
    def quaternion_from_euler(psi_rad: float, theta_rad: float, phi_rad: float):
        """Eq. 2.51: ``(chi, xi, eta, zeta)`` of the Euler angles psi, theta, phi.

        The report's rotation is ``Rz(phi) Ry(theta) Rz(psi)`` (its direction cosines,
        eq. 3.22-3.24, are the columns of that matrix).
        """
        st, ct = math.sin(theta_rad / 2), math.cos(theta_rad / 2)
        dm, dp = (psi_rad - phi_rad) / 2, (psi_rad + phi_rad) / 2
        return (ct * math.cos(dp), st * math.sin(dm), st * math.cos(dm), ct * math.sin(dp))

    @classmethod
    def from_euler(
        cls,
        psi_rad: float = 0.0,
        theta_rad: float = 0.0,
        phi_rad: float = 0.0,
        **kwargs: Any,
    ) -> "PostInitialState":
        return cls(attitude_wxyz=cls.quaternion_from_euler(psi_rad, theta_rad, phi_rad), **kwargs)


# --------------------------------------------------------------------------------------
# the vehicle


@dataclass(frozen=True)
class CrushSpring:
    """A massless crush spring of the car (eq. 3.15), incapable of restitution.

    ``stiffness_lb_per_ft``: ``CK`` (acting at the post's first impact point S) or ``CT``
    (acting at the second impact point T once S has separated).
    """

    stiffness_lb_per_ft: float


@dataclass(frozen=True)
class LeafSpring:
    """A hysteretic leaf spring on the car's front (the crash test of Chapter V).

    Loading (compression ``x`` ft, force lb): ``loading_stiffness_lb_per_ft[0]`` up to
    ``knee_ft``, then ``[1]`` up to ``stop_ft``, then the force at ``stop_ft`` for any
    larger ``x`` (the U-bolts on the I-beam).  Unloading from the largest compression
    reached, ``x_m``: ``unloading_stiffness_lb_per_ft[0]`` down to ``unloading_knee_ft``,
    then ``[1]``, until the force is zero; re-loading retraces the unloading line up to
    ``x_m`` and continues on the loading curve.  The force law is
    :func:`deck_emulator.core.leaf_spring.leaf_force`."""

    loading_stiffness_lb_per_ft: tuple[float, float] = (12000.0, 26400.0)
    knee_ft: float = 0.25
    stop_ft: float = 0.375
    unloading_stiffness_lb_per_ft: tuple[float, float] = (38400.0, 12000.0)
    unloading_knee_ft: float = 0.25


@dataclass(frozen=True)
class VehicleBody:
    """The car's outline for the free-flight checks (Figures 11-12, eq. 3.36-3.38).

    Lengths along ``XV`` (ft): ``hood_length_ft`` HLEN (the hood runs from the bumper
    ``XBUMP = SV - HLEN`` to the windshield at ``SV``), ``top_length_ft`` TLEN (top from ``SV``
    to ``XENTOP = SV + TLEN``), ``trunk_length_ft`` TRLEN (trunk to ``XTAIL = XENTOP + TRLEN``).
    Heights are ``ZZ`` coordinates measured from the post's initial mass centre (ft):
    ``hood_height_ft`` HHV, ``top_height_ft`` HTV, ``trunk_height_ft`` HTRV.  Fenders are
    ``YV`` coordinates (ft): ``left_fender_ft`` YLFEN <= YV <= ``right_fender_ft`` YRFEN.
    """

    hood_length_ft: float
    top_length_ft: float
    trunk_length_ft: float
    hood_height_ft: float
    top_height_ft: float
    trunk_height_ft: float
    left_fender_ft: float
    right_fender_ft: float

    def outline_xv(self, sv_ft: float) -> dict[str, float]:
        """The car's profile along ``XV`` with its reference point at ``sv_ft`` (eq.
        3.36-3.38): ``XBUMP`` the bumper, ``SV`` the windshield's foot (the hood's end),
        ``XENTOP`` the end of the top, ``XTAIL`` the tail.  The one outline: the core's
        checks, the clearances and the pictures all use it."""
        xentop = sv_ft + self.top_length_ft
        return {"XBUMP": sv_ft - self.hood_length_ft, "SV": sv_ft, "XENTOP": xentop,
                "XTAIL": xentop + self.trunk_length_ft}


@dataclass(frozen=True)
class CarBox:
    """One of the car's three solid boxes (the exact checks' car; the clearances' parts).

    In the vehicle axes, relative to the car's reference point SV:
    ``x0_ft <= XV - SV <= x1_ft``, ``left_ft <= YV <= right_ft``, ``ZZ <= top_ft`` (down to
    the ground: no bottom face).  ``part`` is the clearances' name (hood, roof, trunk);
    ``surfaces`` names the faces (front ``XV - SV = x0``, rear ``= x1``, top), each as the
    surface the post hits when it enters the box through it; the flanks are SIDE.
    ``occupant_compartment``: the box is the car's occupant compartment (the roof box: its
    front face the windshield, its top and rear faces the roof, its flanks the side glass),
    the part of the car whose intrusion or deformation the crash-test criteria judge; the
    hood and the trunk are not (:data:`COMPARTMENT_FACES`)."""

    part: str
    x0_ft: float
    x1_ft: float
    left_ft: float
    right_ft: float
    top_ft: float
    front_surface: str
    rear_surface: str
    top_surface: str
    occupant_compartment: bool = False


#: The occupant compartment's faces by the face of its box a post enters through, in the
#: words the verdicts use (the listing calls the roof box's front face the windshield and its
#: top, and its rear face, the top; its flanks are the side glass of a real car).
COMPARTMENT_FACES = {"front": "windshield", "top": "roof", "rear": "roof",
                     "left": "side glass", "right": "side glass"}


def car_boxes(body) -> tuple[CarBox, CarBox, CarBox]:
    """The car of a :class:`~deck_emulator.vocabulary.scene.VehicleBody` as three boxes, from its
    one outline (:meth:`~deck_emulator.vocabulary.scene.VehicleBody.outline_xv`): the hood
    (bumper to the windshield's foot SV, up to HHV), the passenger compartment (SV to
    XENTOP, up to HTV: the one box that is the occupant compartment) and the trunk (XENTOP to
    the tail, up to HTRV)."""
    o = body.outline_xv(0.0)
    yl, yr = body.left_fender_ft, body.right_fender_ft
    return (
        CarBox("hood", o["XBUMP"], o["SV"], yl, yr, body.hood_height_ft,
               "FRONT", "WINDSHIELD", "HOOD"),
        CarBox("roof", o["SV"], o["XENTOP"], yl, yr, body.top_height_ft,
               "WINDSHIELD", "TOP", "TOP", occupant_compartment=True),
        CarBox("trunk", o["XENTOP"], o["XTAIL"], yl, yr, body.trunk_height_ft,
               "TOP", "TRUNK", "TRUNK"),
    )


@dataclass(frozen=True)
class Vehicle:
    """The single-degree-of-freedom car (section 3.2, eq. 3.18); each field's deck name and
    meaning is its row of :mod:`~deck_emulator.vocabulary.deck_fields`.

    It moves along ``XV``, towards ``-XV`` (a negative ``initial_velocity_ft_s``); its spring
    starts to crush at ``contact_position_ft`` (eq. 3.15: ``FS = K*((SVO - SV) - (XVSO -
    XVS))``).  ``None``: no second spring, no force cap (used only by the ``force_cap_from_s``
    option), no ``body`` (no vehicle checks in free flight).
    """

    mass_slug: float
    initial_velocity_ft_s: float
    first_spring: CrushSpring
    approach_angle_rad: float = 0.0
    initial_position_ft: float = 0.0
    contact_position_ft: float = 0.0
    second_spring: CrushSpring | None = None
    force_cap_lb: float | None = None
    body: VehicleBody | None = None
    #: a hysteretic spring at S in place of ``first_spring`` (only scenes that have one)
    leaf_spring: LeafSpring | None = None


# --------------------------------------------------------------------------------------
# the base, the environment


@dataclass(frozen=True)
class BaseFriction:
    """Friction of the slip base at Q (section 3.3), acting in ``+XX``.

    ``force_lb`` acts while the base has moved less than ``slip_window_ft`` along ``-XX``
    (the bolts are still in their slots).
    """

    force_lb: float
    slip_window_ft: float


@dataclass(frozen=True)
class BreakawayBase:
    """The break-away base at Q.

    ``normal_force_lb`` -- ``FNA``: upward force on the post at Q, released for good once
    the base has moved ``normal_release_ft`` along ``-XX`` (the listing's ``XQA <= -0.4166``).
    ``friction`` -- :class:`BaseFriction` or ``None``.
    """

    normal_force_lb: float
    normal_release_ft: float
    friction: BaseFriction | None = None


@dataclass(frozen=True)
class Environment:
    """``gravity_ft_s2`` -- ``G``; the ground is the plane ``ZZ = -ground_depth_ft`` (``HEIGHT``:
    the depth of the ground below the post's initial mass centre, ft)."""

    ground_depth_ft: float
    gravity_ft_s2: float = G_FT_S2


#: The listing's base friction: ``FFXA=3.1*T`` with ``T=300.0`` lb, over the 1 in. slot
#: (``XQA+0.083333``).  The listing's extra ``-0.004`` ft is a tolerance, not a slot: it
#: belongs to the ``listing_friction`` option.
LISTING_BASE_FRICTION = BaseFriction(force_lb=3.1 * 300.0, slip_window_ft=0.083333)
#: The window the listing's friction acts in, as coded: while ``XQA+0.083333-0.004 > 0``.
LISTING_FRICTION_WINDOW_FT = LISTING_BASE_FRICTION.slip_window_ft - 0.004
#: The listing's release of the normal force: ``IF(XQA+0.4166)107,107,106`` (5 in.).
LISTING_NORMAL_RELEASE_FT = 0.4166

# --------------------------------------------------------------------------------------
# the scene


@dataclass(frozen=True)
class Scene:
    """One crash scene.  ``vehicle`` and ``base`` may be ``None`` (a post dropped or thrown
    with nothing else: the core starts it in free flight)."""

    post: Post
    environment: Environment
    initial: PostInitialState = field(default_factory=PostInitialState)
    vehicle: Vehicle | None = None
    base: BreakawayBase | None = None
    name: str = ""

    def __post_init__(self) -> None:
        problems = self.problems()
        if problems:
            raise SceneError(problems[0])

    def problems(self) -> list[str]:
        """What keeps the core from solving this scene (empty: nothing); a :class:`Scene`
        refuses to be built with any, a :class:`DeckScene` keeps them."""
        out = []
        if self.vehicle is not None and self.post.first_impact is None:
            out.append("a scene with a vehicle needs the post's first impact point S")
        if (
            self.vehicle is not None
            and self.vehicle.second_spring is not None
            and self.post.second_impact is None
        ):
            out.append("a second crush spring needs the post's second impact point T")
        for value, what in (
            (self.post.mass_slug, "post mass"),
            (self.post.inertia_1_slug_ft2, "inertia A"),
            (self.post.inertia_2_slug_ft2, "inertia B"),
            (self.post.inertia_3_slug_ft2, "inertia C"),
        ):
            if not value > 0.0:
                out.append(f"{what} must be positive, got {value!r}")
        if self.vehicle is not None and not self.vehicle.mass_slug > 0.0:
            out.append(f"vehicle mass must be positive, got {self.vehicle.mass_slug!r}")
        q = self.initial.attitude_wxyz
        if not math.isfinite(sum(c * c for c in q)) or not sum(c * c for c in q) > 0.0:
            out.append(f"initial.attitude_wxyz = {list(q)} is not a rotation (a quaternion "
                       "of non-zero, finite length)")
        return out

    def checked(self) -> "Scene":
        """This scene as a :class:`Scene` the core can solve (raises :class:`SceneError`
        naming the first problem)."""
        if type(self) is Scene:
            return self
        return Scene(**{f.name: getattr(self, f.name) for f in fields(self)})

    # ---- from a deck -----------------------------------------------------------------

    @classmethod
    def from_deck(cls, deck: Any, *, name: str = "", checked: bool = True) -> "Scene":
        """Build the scene of a card deck (a :class:`deck_emulator.legacy.deck.Deck` or a mapping
        READ-list name -> value).

        A point at the mass centre (all three coordinates 0), a zero spring constant
        ``CT``, a zero ``FCONST`` and an all-zero car outline mean "absent".  Missing
        names read as 0.0.  Base friction and the normal-force release distance are the
        listing's constants (:data:`LISTING_BASE_FRICTION`, :data:`LISTING_NORMAL_RELEASE_FT`).

        ``checked=False``: the deck as it is, even one the core cannot solve (a zero mass, P
        or Q at the mass centre, a car without S): a :class:`DeckScene`, which is what an
        emulator's outcome carries -- the 1967 program runs such decks.
        """
        values = deck if isinstance(deck, Mapping) else deck.values
        if not name and not isinstance(deck, Mapping):
            path = getattr(deck, "path", None)
            if path:
                name = str(path).replace("\\", "/").rsplit("/", 1)[-1]

        def v(key: str) -> float:
            return float(values.get(key, 0.0))

        tree: dict[str, Any] = {}
        for key, path in SCENE_PATHS.items():
            node = tree
            for step in path[:-1]:
                node = node.setdefault(step, {})
            node[path[-1]] = v(key)
        post, vehicle = tree["post"], tree["vehicle"]
        # what a zero means in the deck: a point at the mass centre, CT = 0, FCONST = 0 and an
        # all-zero car outline are absent components
        for attr in Post.POINT_FIELDS.values():
            if attr in post and not any(post[attr].values()) and (
                    checked or attr not in ("top", "base")):
                del post[attr]
        if "top" not in post or "base" not in post:
            raise SceneError("the deck must give the top P and the base Q of the post")
        if vehicle["second_spring"]["stiffness_lb_per_ft"] == 0.0:
            del vehicle["second_spring"]
            post.pop("second_impact", None)
        if vehicle["force_cap_lb"] == 0.0:
            del vehicle["force_cap_lb"]
        outline = vehicle["body"]
        if not any(v for k, v in outline.items() if not k.endswith("fender_ft")):
            del vehicle["body"]
        # what the deck has no field for: the listing's constants
        tree["base"].update(normal_release_ft=LISTING_NORMAL_RELEASE_FT,
                            friction=_plain(LISTING_BASE_FRICTION))
        scene = _build_dataclass(cls if checked else DeckScene, tree, "")
        # XCMB, YCMB, ZCMB are in X, Y, Z: turn them into XX, YY, ZZ (Table 6)
        delta = v("DELTA")
        c, s = math.cos(delta), math.sin(delta)
        xcm, ycm, zcm = v("XCMB"), v("YCMB"), v("ZCMB")
        initial = PostInitialState.from_euler(
            v("PSIB"),
            v("THB"),
            v("PHIB"),
            mass_centre_ft=(xcm, ycm * c - zcm * s, ycm * s + zcm * c),
            velocity_body_ft_s=(v("V1B"), v("V2B"), v("V3B")),
            angular_velocity_body_rad_s=(v("W1B"), v("W2B"), v("W3B")),
        )
        return replace(scene, initial=initial, name=name)

    def deck_values(self) -> dict[str, float]:
        """The READ-list values the scene carries, through :data:`SCENE_PATHS` (an absent
        component reads 0.0, as a deck writes it); the initial state is not among them."""
        tree = _plain(self)
        out = {}
        for key, path in SCENE_PATHS.items():
            node: Any = tree
            for step in path:
                node = node.get(step) if isinstance(node, dict) else None
            out[key] = float(node) if node is not None else 0.0
        return out

    # ---- TOML ------------------------------------------------------------------------

    def to_toml(self) -> str:
        """The scene as TOML text (tables ``[post]``, ``[post.top]`` ...; absent components
        are absent tables).  :meth:`from_toml` reads it back to an equal scene."""
        import tomli_w

        header = ("# deck_emulator scene: ft, lb, slug, s, rad; positions relative to the post's\n"
                  "# mass centre at t = 0 in the road axes XX, YY, ZZ (see deck_emulator.vocabulary.scene).\n")
        return header + tomli_w.dumps(_plain(self))

    @classmethod
    def from_toml(cls, text: str) -> "Scene":
        """Read a scene from TOML text (the layout :meth:`to_toml` writes); a file's path is
        refused with what to call instead (:func:`read_scene`)."""
        if not isinstance(text, str) or ("\n" not in text and "=" not in text
                                         and str(text).endswith(".toml")):
            raise SceneError(f"{text!r}: from_toml takes the TOML text; read_scene(path) "
                             "reads a file")
        from deck_emulator.vocabulary.toml_limits import TomlLimitError, loads

        try:
            data = loads(text)  # within the bounds on size, nesting, keys and digits
        except TomlLimitError as exc:
            raise SceneError(str(exc)) from None
        except tomllib.TOMLDecodeError as exc:
            raise SceneError(f"not valid TOML: {exc}") from exc
        return _build_dataclass(cls, data, "")


@dataclass(frozen=True)
class DeckScene(Scene):
    """A scene as a card deck gives it, not checked: the emulator runs decks the core refuses
    (:meth:`Scene.problems` says what they lack); :meth:`Scene.checked` is the core's way in."""

    def __post_init__(self) -> None:
        pass


def _plain(obj: Any) -> dict:
    """A dataclass as nested plain dicts for tomli-w: ``None`` (an absent component) left
    out, tuples as lists, the name first."""
    out: dict[str, Any] = {}
    for f in fields(obj):
        value = getattr(obj, f.name)
        if value is None or (f.name == "name" and value == ""):
            continue
        if is_dataclass(value):
            value = _plain(value)
        elif isinstance(value, tuple):
            value = list(value)
        out[f.name] = value
    return out


@functools.cache
def _field_types(cls: type) -> dict[str, Any]:
    """A scene class's field types, resolved once a class (get_type_hints evaluates every
    annotation's text each time it is called)."""
    return typing.get_type_hints(cls)


def _build_dataclass(cls: type, data: Mapping[str, Any], where: str) -> Any:
    hints = _field_types(cls)
    known = {f.name for f in fields(cls)}
    unknown = set(data) - known
    if unknown:
        raise SceneError(
            f"unknown key(s) in [{where or 'top level'}]: {', '.join(sorted(unknown))}"
        )
    kwargs = {}
    for f in fields(cls):
        if f.name not in data:
            continue  # its default
        value = data[f.name]
        tp = hints[f.name]
        args = typing.get_args(tp)
        if typing.get_origin(tp) in (typing.Union, types.UnionType):
            tp = next(a for a in args if a is not type(None))
            args = typing.get_args(tp)
        path = f"{where}.{f.name}" if where else f.name
        if is_dataclass(tp):
            if not isinstance(value, Mapping):
                raise SceneError(f"{path} must be a table")
            kwargs[f.name] = _build_dataclass(tp, value, path)
        elif typing.get_origin(tp) is tuple:
            if not isinstance(value, list) or len(value) != len(args):
                raise SceneError(f"{path} must be a list of {len(args)} numbers")
            kwargs[f.name] = tuple(toml_number(x, path) for x in value)
        elif tp is float:
            kwargs[f.name] = toml_number(value, path)
        elif tp is str:
            if not isinstance(value, str):
                raise SceneError(f"{path} must be a string")
            kwargs[f.name] = value
        else:  # pragma: no cover - no other field types
            raise SceneError(f"{path}: unsupported type {tp!r}")

    missing = [f.name for f in fields(cls) if f.name not in data
               and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    if missing:
        lacks = ", ".join(f"{where}.{m}" if where else m for m in missing)
        raise SceneError(f"[{where or 'top level'}] lacks {lacks}")
    try:
        return cls(**kwargs)
    except TypeError as exc:
        raise SceneError(f"[{where or 'top level'}]: {exc}") from exc


def toml_number(value: Any, path: str, error: type[Exception] = SceneError) -> float:
    """A TOML number as a finite float (TOML allows inf, nan and integers beyond a double's
    range): ``error`` (a scene's :class:`SceneError`, an assembly's ``AssemblyError``)
    naming ``path`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise error(f"{path} must be a number, got {value!r:.40}")
    try:
        x = float(value)
    except OverflowError:
        raise error(f"{path} = {value!s:.40}...: beyond the range of a double") from None
    if not math.isfinite(x):
        raise error(f"{path} = {x}: not a finite number")
    return x


def read_scene(path: str | os.PathLike[str]) -> "Scene":
    """The scene of a TOML file: at most :data:`MAX_SCENE_BYTES` read, UTF-8 without a
    byte-order mark, every key checked (:meth:`Scene.from_toml`).  :class:`SceneError` (one
    line) for what the file holds; ``OSError`` when it cannot be read."""
    with open(path, "rb") as handle:
        data = handle.read(MAX_SCENE_BYTES + 1)
    return scene_from_bytes(data)


def scene_from_bytes(data: bytes) -> "Scene":
    """The scene of a TOML file's bytes, read as :func:`read_scene` reads a file."""
    if len(data) > MAX_SCENE_BYTES:
        raise SceneError(f"file is larger than {MAX_SCENE_BYTES} bytes; a scene TOML is a few kB")
    if data.startswith(b"\xef\xbb\xbf"):
        raise SceneError("starts with a UTF-8 byte-order mark; save it as plain UTF-8")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(f"not UTF-8 text (byte {exc.start})") from None
    return Scene.from_toml(text)


# --------------------------------------------------------------------------------------
# model options


@dataclass(frozen=True)
class StartupKick:
    """The listing's first step (labels 123, 124 and 83), as forces over two windows.

    At t = 0 the listing sets ``W2A=0.0545`` (``pitch_rate_rad_s``) and, for its first
    step of ``step_s`` = 0.0004 s, drives the post with ``F1B=-10000.0`` lb along body
    axis 1 alone (no gravity, no base forces, no torque; ``body_force_1_lb``) and the car
    with ``FSB=10000.0`` lb (``vehicle_force_lb``); at the end of that step the attitude
    is ``THA=0.000022`` rad about axis 2 (``tilt_at_step_rad``: the core adds the missing
    ``0.000022 - 0.0545*0.0004`` rad to the attitude at t = 0).  Over the second step
    the spring force is ``FSA=1320.0`` lb (``first_step_spring_force_lb``), the other forces
    as usual.
    """

    pitch_rate_rad_s: float = 0.0545
    tilt_at_step_rad: float = float(LISTING_THA_START)
    step_s: float = LISTING_STEP_S
    body_force_1_lb: float = -10000.0
    vehicle_force_lb: float = 10000.0
    first_step_spring_force_lb: float = 1320.0


@dataclass(frozen=True)
class ModelOptions:
    """How the core treats each quirk of the listing; one flag per quirk.

    * ``startup_kick`` -- :class:`StartupKick` or ``None``.
    * ``spring_factor`` -- the listing's ``FSA=0.8*FSA`` (1.0: eq. 3.15 as printed).
    * ``spring_absolute`` -- the listing's ``FSA=ABS(CK*(...))``: a stretched spring
      pushes as hard as a crushed one.  False: the spring only pushes (``max(0, K x)``).
    * ``spring_switch_ft`` -- the force moves from S (``CK``) to T (``CT``) when ``DIFF``
      exceeds this (the listing's ``IF(DIFF-0.01)356,356,357``); 0.0: when S separates.
    * ``force_cap_from_s`` -- the ``FCONST`` cap: from this time on (the listing's
      ``IF(LL-20)``: 20 steps of 0.0004 s), while ``DIFF`` does not decrease, the spring
      force is at most ``FCONST``.  ``None``: no cap.
    * ``listing_diff`` -- contact ends when the listing's ``DIFF = |XVS-XVSO| - |SV-SVO|``
      (``DIFFT`` for T) turns positive; False: when the spring's compression (eq. 3.15)
      falls to zero.  The two agree while post and car both move towards ``-XV``.
    * ``listing_friction`` -- base friction ``3.1*300`` lb while ``XQ > -0.083333+0.004``
      whatever the scene says; False: the scene's :class:`BaseFriction` (none if absent).
    * ``listing_hit_tolerances`` -- the listing's hit tests as event definitions: a point
      hits the ground when within 0.1 ft of it (0.01 ft for Q), a car surface when within
      0.1 ft of it inside the outline; the windshield when inside the top's outline below
      ``HTV``.  False: the exact surfaces (ground plane; the car as three solid boxes).
    * ``cap_sliding`` -- when the ``FCONST`` cap's on/off decision would chatter (the
      capped spring holds ``DIFF`` stationary), the core enters the sliding mode
      (Filippov): the spring force is the one that keeps ``DIFF`` stationary, between the
      cap and the uncapped force, until that force reaches either bound (a located
      event).  False: plain switching (a chattering cap ends in ``CoreError``).
    * ``solid_ground`` -- the ground is solid during the contact too: a post point reaching
      it while the car still pushes is a hit.  False (the listing): the ground is checked
      only in free flight, and the outcome says when and how deep the post went through it.
    * ``friction_reaction`` -- base friction is Coulomb friction at Q along ``XX``: it
      opposes the base's sliding velocity with the scene's force as its limit, and holds
      the base still (stick) while a smaller force would do; only inside the slip-base
      travel.  False (the listing): a constant force along ``+XX`` inside the travel.
    * ``shaft_contact`` -- in free flight the shaft Q-P and the arms P-R, P-U (and C off
      them) are checked as segments against the car's three solid boxes
      (:mod:`.segments`), not only the points P, R, C: a shaft falling across the hood with
      its ends clear of the outline hits it.  False (the listing): only the points.

    The scene fields an option sets aside (the base friction under ``listing_friction``, the
    force cap without ``force_cap_from_s``) are :data:`OVERRIDDEN`; ``core`` names them.
    """

    startup_kick: StartupKick | None = None
    spring_factor: float = 1.0
    spring_absolute: bool = False
    spring_switch_ft: float = 0.0
    force_cap_from_s: float | None = None
    listing_diff: bool = False
    listing_friction: bool = False
    listing_hit_tolerances: bool = False
    cap_sliding: bool = True
    solid_ground: bool = True
    friction_reaction: bool = True
    shaft_contact: bool = True
    name: str = "custom"

    def replace(self, **changes: Any) -> "ModelOptions":
        if "name" not in changes:
            changes["name"] = "custom"
        return dataclasses.replace(self, **changes)


#: The listing's behaviour, quirk for quirk.
LEGACY = ModelOptions(
    startup_kick=StartupKick(),
    spring_factor=0.8,
    spring_absolute=True,
    spring_switch_ft=0.01,
    force_cap_from_s=LISTING_CAP_STEPS * LISTING_STEP_S,
    listing_diff=True,
    listing_friction=True,
    listing_hit_tolerances=True,
    solid_ground=False,
    friction_reaction=False,
    shaft_contact=False,
    name="legacy",
)

#: The model of chapter III without the listing's quirks.
PHYSICAL = ModelOptions(name="physical")

PRESETS: dict[str, ModelOptions] = {"legacy": LEGACY, "physical": PHYSICAL}
assert tuple(PRESETS) == choices.PRESETS, "a preset without its model options, or the other way"


@dataclass(frozen=True)
class Overridden:
    """A scene field a model option sets aside: while ``ModelOptions.<flag>`` is ``when``,
    the core uses ``instead`` whatever the scene's ``field`` (its TOML path) says; ``value``
    reads the field from a scene (None: not given); a scene value equal to ``same`` is what
    the option uses anyway (nothing is set aside)."""

    flag: str
    when: Any
    field: str
    value: Any
    same: float | None
    instead: str


def _friction(scene, name):
    base = scene.base
    return None if base is None or base.friction is None else getattr(base.friction, name)


#: Which option overrides which scene field (read from the core: core/model.py builds the
#: base friction from the listing's numbers under ``listing_friction``; core/components.py
#: caps the spring force at ``force_cap_lb`` only when ``force_cap_from_s`` is set).
OVERRIDDEN: tuple[Overridden, ...] = (
    Overridden("listing_friction", True, "base.friction.force_lb",
               lambda s: _friction(s, "force_lb"), LISTING_BASE_FRICTION.force_lb,
               f"the listing's base friction, 3.1*300 = {LISTING_BASE_FRICTION.force_lb:g} lb"),
    Overridden("listing_friction", True, "base.friction.slip_window_ft",
               lambda s: _friction(s, "slip_window_ft"), LISTING_BASE_FRICTION.slip_window_ft,
               f"the listing's slot, {LISTING_BASE_FRICTION.slip_window_ft:g} ft (less its "
               "0.004 ft tolerance)"),
    Overridden("force_cap_from_s", None, "vehicle.force_cap_lb",
               lambda s: None if s.vehicle is None else s.vehicle.force_cap_lb, None,
               "no cap on the crush spring's force"),
)


def overridden_fields(scene: "Scene", options: ModelOptions) -> list[str]:
    """A sentence for each field of ``scene`` that ``options`` set aside (:data:`OVERRIDDEN`),
    naming the field, what is used instead, and the preset that would honour it."""
    said = []
    for o in OVERRIDDEN:
        value = o.value(scene)
        if getattr(options, o.flag) != o.when or value is None or value == o.same:
            continue
        honour = [name for name, p in PRESETS.items() if getattr(p, o.flag) != o.when]
        said.append(f"scene field {o.field} = {value:g} is not used: the {options.name} "
                    f"preset's {o.flag} applies {o.instead}"
                    + (f"; --preset {' or '.join(honour)} honours it" if honour else ""))
    return said
