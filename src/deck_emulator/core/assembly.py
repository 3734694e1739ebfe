"""Post-assembly builder: from a description of a luminaire support (as the report gives
one: shaft, base, arm(s), luminaire(s)) to mass properties, named points and a typed
:class:`~deck_emulator.vocabulary.scene.Scene`.

Builder's frame: ``x`` the road's ``XX`` (normal to the arms' plane), ``y`` its ``YY``, ``z``
up; the shaft axis is ``x = y = 0``, Q at ``z = 0``, P at ``z = L``.  Lengths in ft, weights
in lb (a mass ``W/g`` slug), inertias in slug ft^2.  Every part is summed about this origin,
then moved to the mass centre ``c`` by the parallel-axis theorem in tensor form,
``I_G = I_O - M (|c|^2 1 - c c^T)``.

1. The shaft, a thin-wall tapered tube: outside diameter ``D(s)`` linear in the height ``s``,
   wall ``t``; a slice is a ring of radius ``r = (D - t)/2`` and mass ``rho pi (D - t) t ds``
   (``I = dm r^2`` about its axis, ``dm r^2/2`` about a diameter).  The integrands are
   polynomials of degree <= 3: Gauss-Legendre with 8 points is exact.  Given the total weight
   instead of the wall, ``t`` is solved for (the mass grows with ``t``).
2. An arm, a slender rod of uniform mass along a quadratic Bezier curve from its root on the
   shaft axis to the luminaire point R (``shape = "straight"``: the control point on the
   chord), cut into straight pieces, each ``m l^2/12 (1 - u u^T)`` about its centre (exact
   for a straight arm at any number of pieces).
3. Point masses (the luminaire at R, a base on the axis): ``m (|d|^2 1 - d d^T)``; the
   luminaire's own size is neglected (an assumption).
4. Principal axes by ``numpy.linalg.eigh``: axis 3 the one nearest the shaft, axis 1 nearest
   ``XX``; every part lies in (or is symmetric about) ``x = 0``, so axis 3 is
   ``(0, -sin delta, cos delta)``, ``delta = atan2(-e3_y, e3_z)`` (the scene's convention).

Named points (road axes, from the mass centre): P top, Q base, R and U the arms' ends, S and
T the car's impact points on the shaft, C the listing's extra ground point (the report's deck
puts it on Q).
"""

from __future__ import annotations

import dataclasses
import importlib.resources
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from deck_emulator.vocabulary.scene import (
    LISTING_BASE_FRICTION,
    LISTING_NORMAL_RELEASE_FT,
    toml_number,
)
from deck_emulator.vocabulary.toml_limits import TomlLimitError, loads
from deck_emulator.vocabulary.units import G_FT_S2

__all__ = [
    "G_FT_S2",
    "Shaft",
    "BaseMass",
    "Arm",
    "Assembly",
    "MassProperties",
    "AssemblyError",
    "tube_properties",
    "rod_tensor",
    "point_tensor",
    "principal_axes",
    "mass_properties",
    "assembly_from_toml",
    "load_assembly",
    "assembly_names",
    "scene_runs_on_listing",
    "inferred_geometry",
    "STEEL_DECK_TARGET",
    "steel_deck_residuals",
    "calibrate_on_steel_deck",
    "CALIBRATION_SCALES",
    "arm_properties",
    "crash_test_description",
    "MAX_DESCRIPTION_BYTES",
]

IN = 1.0 / 12.0


class AssemblyError(ValueError):
    """A description that cannot be built."""


# --------------------------------------------------------------------------------------
# description


@dataclass(frozen=True)
class Shaft:
    """Tapered tube.  Give ``wall_in`` or leave it ``None`` to solve it from the total
    weight of the assembly (:attr:`Assembly.total_weight_lb`)."""

    density_lb_ft3: float
    base_od_in: float
    top_od_in: float
    length_ft: float
    wall_in: float | None = None


@dataclass(frozen=True)
class BaseMass:
    """Base plate or transformer base: a point mass on the shaft axis ``height_ft`` above Q."""

    weight_lb: float = 0.0
    height_ft: float = 0.0


@dataclass(frozen=True)
class Arm:
    """A luminaire arm and its luminaire.

    ``reach_ft`` horizontal distance from the shaft axis to R, ``rise_ft`` height of R
    above P, ``side`` = -1 (towards ``-YY``, as the report's deck) or +1.  ``shape``:
    "straight" or "bezier" (``control`` = (fraction of reach, fraction of rise) of the
    control point, measured from the root).  ``attach_below_top_ft``: the root's depth
    below P."""

    reach_ft: float
    rise_ft: float
    weight_lb: float
    luminaire_weight_lb: float
    side: float = -1.0
    shape: str = "straight"
    control: tuple[float, float] = (0.5, 0.5)
    attach_below_top_ft: float = 0.0


@dataclass(frozen=True)
class Assembly:
    """A luminaire support assembly, and where the car's springs meet it.

    ``s_height_ft``, ``t_height_ft``: heights of the impact points S, T above Q;
    ``c_height_ft``: height of point C above Q (the report's deck: on Q).
    ``pedestal_ft``: the ground is this far below Q (the report's deck: 0.5 ft)."""

    name: str
    shaft: Shaft
    arms: tuple[Arm, ...] = ()
    base: BaseMass = BaseMass()
    total_weight_lb: float | None = None
    s_height_ft: float = 1.0
    t_height_ft: float = 2.27
    c_height_ft: float = 0.0
    pedestal_ft: float = 0.5
    gravity_ft_s2: float = G_FT_S2
    notes: str = ""


@dataclass(frozen=True)
class MassProperties:
    """What the builder gives.  Points are (XX, YY, ZZ) in ft from the mass centre."""

    weight_lb: float
    mass_slug: float
    A: float
    B: float
    C: float
    delta_rad: float
    cm_height_ft: float  # above Q
    cm_offset_ft: float  # YY of the mass centre from the shaft axis
    wall_in: float
    points: dict[str, tuple[float, float, float]] = field(default_factory=dict)

    @property
    def delta_deg(self) -> float:
        return math.degrees(self.delta_rad)


# --------------------------------------------------------------------------------------
# the pieces

_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)


def tube_properties(shaft: Shaft, wall_in: float, g: float = G_FT_S2):
    """(mass slug, mass-centre height ft, tensor about Q (3x3)) of the thin-wall tube."""
    L = shaft.length_ft
    t = wall_in * IN
    s = 0.5 * L * (_GL_X + 1.0)
    w = 0.5 * L * _GL_W
    D = (shaft.base_od_in + (shaft.top_od_in - shaft.base_od_in) * s / L) * IN
    Dm = D - t
    r = Dm / 2.0
    lam = (shaft.density_lb_ft3 / g) * math.pi * Dm * t  # slug/ft
    m = float(np.sum(w * lam))
    sc = float(np.sum(w * lam * s)) / m
    izz = float(np.sum(w * lam * r * r))
    ixx = float(np.sum(w * lam * (r * r / 2.0 + s * s)))
    return m, sc, np.diag([ixx, ixx, izz])


def point_tensor(m: float, d) -> np.ndarray:
    """Tensor of a point mass ``m`` at ``d`` about the origin: ``m (|d|^2 1 - d d^T)``."""
    d = np.asarray(d, dtype=float)
    return m * (float(d @ d) * np.eye(3) - np.outer(d, d))


def rod_tensor(m: float, a, b) -> tuple[np.ndarray, np.ndarray]:
    """(tensor about the origin, centre) of a slender straight rod of mass ``m`` from a to b."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    v = b - a
    l = float(np.linalg.norm(v))
    u = v / l if l > 0 else v
    c = 0.5 * (a + b)
    own = m * l * l / 12.0 * (np.eye(3) - np.outer(u, u))
    return own + point_tensor(m, c), c


def _arm_curve(arm: Arm, top_ft: float, n: int) -> np.ndarray:
    root = np.array([0.0, 0.0, top_ft - arm.attach_below_top_ft])
    end = np.array([0.0, arm.side * arm.reach_ft, top_ft + arm.rise_ft])
    if arm.shape == "straight":
        ctrl = 0.5 * (root + end)
    elif arm.shape == "bezier":
        fy, fz = arm.control
        ctrl = root + np.array([0.0, fy * (end[1] - root[1]), fz * (end[2] - root[2])])
    else:
        raise AssemblyError(f"unknown arm shape {arm.shape!r} (straight or bezier)")
    u = np.linspace(0.0, 1.0, n + 1)[:, None]
    return (1 - u) ** 2 * root + 2 * u * (1 - u) * ctrl + u**2 * end


def arm_properties(arm: Arm, top_ft: float, g: float = G_FT_S2, n: int = 400):
    """(mass slug, first moment (3,), tensor about Q) of an arm's rod, mass uniform along
    its length."""
    pts = _arm_curve(arm, top_ft, n)
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    total = float(seg.sum())
    m = arm.weight_lb / g
    I = np.zeros((3, 3))
    first = np.zeros(3)
    for k in range(n):
        mk = m * seg[k] / total
        Ik, ck = rod_tensor(mk, pts[k], pts[k + 1])
        I += Ik
        first += mk * ck
    return m, first, I


def principal_axes(I: np.ndarray):
    """(A, B, C, axes as columns 1, 2, 3, delta) of a tensor whose axis 3 is near ZZ."""
    vals, vecs = np.linalg.eigh(I)
    k3 = int(np.argmax(np.abs(vecs[2])))
    rest = [k for k in range(3) if k != k3]
    k1 = max(rest, key=lambda k: abs(vecs[0, k]))
    k2 = next(k for k in rest if k != k1)
    e1, e2, e3 = vecs[:, k1].copy(), vecs[:, k2].copy(), vecs[:, k3].copy()
    if e3[2] < 0:
        e3 = -e3
    if e1[0] < 0:
        e1 = -e1
    e2 = np.cross(e3, e1)
    delta = math.atan2(-e3[1], e3[2])
    if abs(delta) < 1e-12:  # a symmetric assembly: no tilt (and no -0.0)
        delta = 0.0
    return float(vals[k1]), float(vals[k2]), float(vals[k3]), np.column_stack([e1, e2, e3]), delta


def _parts_weight_lb(a: Assembly) -> float:
    """What the assembly weighs besides its shaft, lb: the base, the arms, the luminaires."""
    return a.base.weight_lb + sum(arm.weight_lb + arm.luminaire_weight_lb for arm in a.arms)


def _solve_wall(a: Assembly) -> float:
    if a.shaft.wall_in is not None:
        if a.total_weight_lb is not None:  # two answers to one question: never one in silence
            raise AssemblyError(_wall_and_weight(a))
        return a.shaft.wall_in
    if a.total_weight_lb is None:
        raise AssemblyError(f"{a.name}: give the shaft's wall_in or the total weight")
    target = (a.total_weight_lb - _parts_weight_lb(a)) / a.gravity_ft_s2
    if target <= 0:
        raise AssemblyError(f"{a.name}: the parts weigh more than the total")
    lo, hi = 0.0, min(a.shaft.base_od_in, a.shaft.top_od_in) / 2.0
    if tube_properties(a.shaft, hi, a.gravity_ft_s2)[0] < target:
        raise AssemblyError(f"{a.name}: no wall of this tube reaches the total weight")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if tube_properties(a.shaft, mid, a.gravity_ft_s2)[0] < target:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def mass_properties(a: Assembly) -> MassProperties:
    """Mass, principal moments, tilt delta and named points of an assembly."""
    g = a.gravity_ft_s2
    wall = _solve_wall(a)
    L = a.shaft.length_ft
    m_s, sc, I = tube_properties(a.shaft, wall, g)
    mass = m_s
    first = np.array([0.0, 0.0, m_s * sc])
    I = I.copy()
    if a.base.weight_lb:
        mb = a.base.weight_lb / g
        d = np.array([0.0, 0.0, a.base.height_ft])
        I += point_tensor(mb, d)
        first += mb * d
        mass += mb
    ends = []
    for arm in a.arms:
        ma, fa, Ia = arm_properties(arm, L, g)
        I += Ia
        first += fa
        mass += ma
        end = np.array([0.0, arm.side * arm.reach_ft, L + arm.rise_ft])
        ends.append(end)
        ml = arm.luminaire_weight_lb / g
        I += point_tensor(ml, end)
        first += ml * end
        mass += ml
    c = first / mass
    IG = I - point_tensor(mass, c)
    A, B, C, _, delta = principal_axes(IG)

    def rel(p):
        q = np.asarray(p, float) - c
        return (float(q[0]), float(q[1]), float(q[2]))

    points = {
        "P": rel((0, 0, L)),
        "Q": rel((0, 0, 0)),
        "S": rel((0, 0, a.s_height_ft)),
        "T": rel((0, 0, a.t_height_ft)),
        "C": rel((0, 0, a.c_height_ft)),
    }
    for letter, end in zip(("R", "U"), ends):
        points[letter] = rel(end)
    return MassProperties(
        weight_lb=mass * g,
        mass_slug=mass,
        A=A,
        B=B,
        C=C,
        delta_rad=delta,
        cm_height_ft=float(c[2]),
        cm_offset_ft=float(c[1]),
        wall_in=wall,
        points=points,
    )


# --------------------------------------------------------------------------------------
# description files (TOML)


#: Largest description file read (bytes): the shipped ones are under 3 kB.
MAX_DESCRIPTION_BYTES = 1_000_000

# The domain of every key: (kind, lower, lower inclusive, optional).  kind "num" is a
# finite number (TOML integer or float, not a boolean); a lower bound of None is none.
_POSITIVE = ("num", 0.0, False, False)
_NON_NEGATIVE = ("num", 0.0, True, False)
_FINITE = ("num", None, True, False)
_FIELDS: dict[str, dict[str, tuple]] = {
    "shaft": {
        "density_lb_ft3": _POSITIVE, "base_od_in": _POSITIVE, "top_od_in": _POSITIVE,
        "length_ft": _POSITIVE, "wall_in": ("num", 0.0, False, True),
    },
    "base": {"weight_lb": _NON_NEGATIVE, "height_ft": _NON_NEGATIVE},
    "arm": {
        "reach_ft": _NON_NEGATIVE, "rise_ft": _FINITE, "weight_lb": _NON_NEGATIVE,
        "luminaire_weight_lb": _NON_NEGATIVE, "side": ("side",), "shape": ("shape",),
        "control": ("pair",), "attach_below_top_ft": _NON_NEGATIVE,
    },
    "top level": {
        "name": ("str",), "total_weight_lb": ("num", 0.0, False, True),
        "s_height_ft": _NON_NEGATIVE, "t_height_ft": _NON_NEGATIVE, "c_height_ft": _NON_NEGATIVE,
        "pedestal_ft": _NON_NEGATIVE, "gravity_ft_s2": _POSITIVE, "notes": ("str",),
    },
}
_REQUIRED = {
    "shaft": ("density_lb_ft3", "base_od_in", "top_od_in", "length_ft"),
    "arm": ("reach_ft", "rise_ft", "weight_lb", "luminaire_weight_lb"),
    "base": (), "top level": ("name",),
}


def _checked(value: Any, rule: tuple, key: str):
    kind = rule[0]
    if kind == "num":
        _, low, inclusive, _ = rule
        x = toml_number(value, key, AssemblyError)  # the scene files' check of a number
        if low is not None and (x < low or (x == low and not inclusive)):
            raise AssemblyError(f"{key} = {x:g} must be {'>=' if inclusive else '>'} {low:g}")
        return x
    if kind == "str":
        if not isinstance(value, str):
            raise AssemblyError(f"{key} must be a string, not {type(value).__name__}")
        return value
    if kind == "side":
        x = toml_number(value, key, AssemblyError)
        if x not in (-1.0, 1.0):
            raise AssemblyError(f"{key} = {x:g} must be -1 or +1")
        return x
    if kind == "shape":
        if value not in ("straight", "bezier"):
            raise AssemblyError(f"{key} = {value!r:.40} must be \"straight\" or \"bezier\"")
        return value
    if kind == "pair":
        if not isinstance(value, list) or len(value) != 2:
            raise AssemblyError(f"{key} must be a list of two numbers")
        return tuple(toml_number(x, f"{key}[{i}]", AssemblyError) for i, x in enumerate(value))
    raise AssertionError(kind)  # pragma: no cover


def _checked_table(data: Any, where: str) -> dict[str, Any]:
    """The keys of one table, each checked against its domain (:data:`_FIELDS`)."""
    if not isinstance(data, dict):
        raise AssemblyError(f"[{where}] must be a table, not {type(data).__name__}")
    rules = _FIELDS[where]
    unknown = set(data) - set(rules)
    if unknown:
        raise AssemblyError(f"unknown key(s) in [{where}]: {', '.join(sorted(unknown))}")
    missing = [k for k in _REQUIRED[where] if k not in data]
    if missing:
        raise AssemblyError(f"[{where}] lacks {', '.join(missing)}")
    prefix = "" if where == "top level" else f"{where}."
    return {k: _checked(v, rules[k], prefix + k) for k, v in data.items()}


def _wall_and_weight(a: Assembly) -> str:
    """The one line that refuses a description giving both the shaft's wall and the total
    weight (each decides the other), with the weight the wall gives."""
    m = tube_properties(a.shaft, a.shaft.wall_in, a.gravity_ft_s2)[0]
    weight = m * a.gravity_ft_s2 + _parts_weight_lb(a)
    return (f"{a.name}: total_weight_lb = {a.total_weight_lb:g} and shaft.wall_in = "
            f"{a.shaft.wall_in:g} both decide the shaft's wall (that wall makes the post "
            f"{weight:.2f} lb): give one of them")


def _check_geometry(a: Assembly) -> None:
    """Relations between keys that no single key's domain holds."""
    L = a.shaft.length_ft
    if a.shaft.wall_in is not None and a.shaft.wall_in > min(a.shaft.base_od_in, a.shaft.top_od_in) / 2:
        raise AssemblyError(f"shaft.wall_in = {a.shaft.wall_in:g} is thicker than the tube's radius")
    if a.shaft.wall_in is not None and a.total_weight_lb is not None:
        raise AssemblyError(_wall_and_weight(a))
    for k, arm in enumerate(a.arms, 1):
        if arm.attach_below_top_ft > L:
            raise AssemblyError(f"arm {k}: attach_below_top_ft = {arm.attach_below_top_ft:g} is "
                                f"below the shaft's base (length_ft = {L:g})")
        if math.hypot(arm.reach_ft, arm.rise_ft + arm.attach_below_top_ft) == 0.0:
            raise AssemblyError(f"arm {k}: reach_ft and rise_ft give an arm of no length")
    for key in ("s_height_ft", "t_height_ft", "c_height_ft"):
        if getattr(a, key) > L:
            raise AssemblyError(f"{key} = {getattr(a, key):g} is above the shaft's top "
                                f"(shaft.length_ft = {L:g})")


#: The keys of a crash-test description (``[crash_test]`` and ``[crash_test.leaf_spring]``).
_CRASH_FIELDS = {
    "post_weight_lb": _POSITIVE, "post_length_ft": _POSITIVE, "cm_from_base_ft": _POSITIVE,
    "transverse_inertia_slug_ft2": _POSITIVE, "axial_inertia_slug_ft2": _POSITIVE,
    "vehicle_weight_lb": _POSITIVE, "vehicle_speed_ft_s": _POSITIVE,
    "impact_height_ft": _NON_NEGATIVE, "base_on_ground": ("bool",),
    "normal_force_release_ft": _NON_NEGATIVE, "gravity_ft_s2": _POSITIVE,
}
_LEAF_FIELDS = {
    "loading_stiffness_lb_per_ft": ("pair",), "knee_ft": _POSITIVE, "stop_ft": _POSITIVE,
    "unloading_stiffness_lb_per_ft": ("pair",), "unloading_knee_ft": _NON_NEGATIVE,
}


def crash_test_description(table: Any) -> dict[str, Any]:
    """The ``[crash_test]`` table of a description, every key present and checked against
    its domain (:class:`AssemblyError` naming the first that is not)."""
    if not isinstance(table, dict):
        raise AssemblyError("[crash_test] must be a table")
    out: dict[str, Any] = {}
    for where, rules, data in (("crash_test", _CRASH_FIELDS, table),
                               ("crash_test.leaf_spring", _LEAF_FIELDS, table.get("leaf_spring"))):
        if not isinstance(data, dict):
            raise AssemblyError(f"[{where}] must be a table")
        extra = set(data) - set(rules) - ({"leaf_spring"} if where == "crash_test" else set())
        if extra:
            raise AssemblyError(f"unknown key(s) in [{where}]: {', '.join(sorted(extra))}")
        missing = [k for k in rules if k not in data]
        if missing:
            raise AssemblyError(f"[{where}] lacks {', '.join(missing)}")
        got = {}
        for k, rule in rules.items():
            if rule[0] == "bool":
                if not isinstance(data[k], bool):
                    raise AssemblyError(f"{where}.{k} must be true or false")
                got[k] = data[k]
            else:
                got[k] = _checked(data[k], rule, f"{where}.{k}")
                if rule[0] == "pair" and min(got[k]) <= 0:
                    raise AssemblyError(f"{where}.{k} must be two stiffnesses > 0")
        if where == "crash_test":
            out.update(got)
        else:
            out["leaf_spring"] = got
    if out["cm_from_base_ft"] >= out["post_length_ft"]:
        raise AssemblyError("crash_test.cm_from_base_ft must lie inside the post (< post_length_ft)")
    if out["impact_height_ft"] > out["post_length_ft"]:
        raise AssemblyError("crash_test.impact_height_ft is above the post's top (post_length_ft)")
    if out["leaf_spring"]["stop_ft"] < out["leaf_spring"]["knee_ft"]:
        raise AssemblyError("crash_test.leaf_spring.stop_ft must be >= knee_ft")
    return out


def assembly_from_toml(text: str) -> tuple[Assembly | None, dict[str, Any]]:
    """(assembly, the file's other table: ``[source]``, where the numbers come from) of a
    description, or
    (``None``, ``{"name": ..., "crash_test": checked table}``) of a crash-test description.
    A text with neither ``[shaft]`` nor ``[crash_test]`` is refused."""

    try:
        data = loads(text)  # within the bounds on size, nesting, keys and digits
    except TomlLimitError as exc:
        raise AssemblyError(f"not a description: {exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise AssemblyError(f"not valid TOML: {exc}") from None
    if "shaft" not in data:
        if "crash_test" not in data:
            raise AssemblyError("not a description: it has neither a [shaft] nor a "
                                "[crash_test] table")
        unknown = set(data) - {"name", "crash_test", "notes", "source"}
        if unknown:
            raise AssemblyError(f"unknown key(s) beside [crash_test]: {', '.join(sorted(unknown))}")
        if not isinstance(data.get("name", ""), str):
            raise AssemblyError("name must be a string")
        return None, {**data, "crash_test": crash_test_description(data["crash_test"])}
    if "run" in data:  # a table nothing reads: refused, not ignored
        raise AssemblyError("[run] is not read from a description: give the run's settings "
                            "(speed, angle, preset) on the command line")
    arm_list = data.get("arm", [])
    if not isinstance(arm_list, list):
        raise AssemblyError("arm must be an array of tables ([[arm]])")
    for k, x in enumerate(arm_list, 1):  # a key its shape does not read: refused, not ignored
        if isinstance(x, dict) and "control" in x and x.get("shape", "straight") == "straight":
            raise AssemblyError(f"arm {k}: control is not read by shape = \"straight\" (its "
                                "control point is on the chord): drop it, or give shape = "
                                "\"bezier\"")
    arms = tuple(Arm(**_checked_table(x, "arm")) for x in arm_list)
    top = {k: v for k, v in data.items() if k not in ("shaft", "arm", "base", "run", "source")}
    asm = Assembly(**_checked_table(top, "top level"), arms=arms,
                   shaft=Shaft(**_checked_table(data["shaft"], "shaft")),
                   base=BaseMass(**_checked_table(data.get("base", {}), "base")))
    _check_geometry(asm)
    extra = {k: data[k] for k in ("source",) if k in data}
    return asm, extra


def assembly_names() -> list[str]:
    """Names of the shipped description files."""

    files = importlib.resources.files("deck_emulator.assemblies")
    return sorted(p.name[:-5] for p in files.iterdir() if p.name.endswith(".toml"))


def _read_description(path: str) -> str:
    """A description file's text: at most :data:`MAX_DESCRIPTION_BYTES`, UTF-8."""

    with Path(path).open("rb") as f:
        raw = f.read(MAX_DESCRIPTION_BYTES + 1)
    if len(raw) > MAX_DESCRIPTION_BYTES:
        raise AssemblyError(f"{path}: larger than {MAX_DESCRIPTION_BYTES} bytes; not a description")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise AssemblyError(f"{path}: not UTF-8 text (byte {exc.start})") from None


def load_assembly(name_or_path: str):
    """(assembly or None, extra tables, text) of a shipped description (by name) or a file;
    for a crash-test description the assembly is ``None`` and ``extra["crash_test"]`` is its
    checked table (:func:`crash_test_description`)."""

    if name_or_path.endswith(".toml"):
        text = _read_description(name_or_path)
    else:
        f = importlib.resources.files("deck_emulator.assemblies") / f"{name_or_path}.toml"
        if not f.is_file():
            raise AssemblyError(f"no shipped description {name_or_path!r}")
        text = f.read_text()
    asm, extra = assembly_from_toml(text)
    return asm, extra, text


# --------------------------------------------------------------------------------------
# deck and scene

#: The report's steel deck's mass properties (decks/steel40.dat), for the calibration.
STEEL_DECK_TARGET = {
    "W": 15.1, "A": 3351.41, "B": 3282.6, "C": 69.68, "DELTA": 0.1463,
    "cm_height_ft": 19.77, "cm_offset_ft": -1.53, "FNA": 485.07,
}

def scene_runs_on_listing(scene) -> str | None:
    """``None`` when the 1967 listing can run the scene, else the reason (one line)."""
    post = scene.post
    if getattr(post, "second_luminaire_end", None) is not None:
        return "the listing carries one luminaire arm (point R); this scene has a second (U)"
    if getattr(scene.vehicle, "leaf_spring", None) is not None if scene.vehicle else False:
        return "the listing's car has linear crush springs; this scene has a hysteretic leaf spring"
    if scene.vehicle is None:
        return "the listing always has a car; this scene has none"
    if scene.base is None:
        return "the listing always has the break-away base; this scene has none"

    if scene.base.friction != LISTING_BASE_FRICTION:
        return "the listing's base friction is fixed (930 lb over 1 in); this scene's differs"
    if scene.base.normal_release_ft != LISTING_NORMAL_RELEASE_FT:
        return "the listing releases the normal force at 5 in; this scene elsewhere"
    return None


# --------------------------------------------------------------------------------------
# geometry the report's tables imply


def inferred_geometry(cells: dict[str, list[tuple[float, float, float]]]) -> dict[str, Any]:
    """Distances between points that a rigid body keeps, from terminal coordinates.

    ``cells``: letter -> list of (XL, YL, ZL) over the columns of one post.  Returns, per
    pair, the list of distances and their mean and sample standard deviation, and (when P,
    Q, R are given) the arm's rise above P and reach from the axis that the means imply
    (law of cosines: ``|QR|^2 = |PQ|^2 + |PR|^2 + 2 |PQ| rise``)."""
    letters = [k for k in "PQRU" if k in cells]
    out: dict[str, Any] = {}
    for i, a in enumerate(letters):
        for b in letters[i + 1:]:
            d = [math.dist(p, q) for p, q in zip(cells[a], cells[b])]
            out[a + b] = {
                "values": d,
                "mean": float(np.mean(d)),
                "sd": float(np.std(d, ddof=1)) if len(d) > 1 else 0.0,
            }
    if all(k in out for k in ("PQ", "PR", "QR")):
        pq, pr, qr = out["PQ"]["mean"], out["PR"]["mean"], out["QR"]["mean"]
        rise = (qr * qr - pq * pq - pr * pr) / (2 * pq)
        out["rise_ft"] = rise
        out["reach_ft"] = math.sqrt(max(pr * pr - rise * rise, 0.0))
    return out


# --------------------------------------------------------------------------------------
# calibration of the unknowns on the report's steel deck

#: scale of each residual of :func:`calibrate_on_steel_deck` (what counts as "one unit")
CALIBRATION_SCALES = {
    "cm_height_ft": 0.01, "cm_offset_ft": 0.01, "A": 0.01, "B": 0.01, "C": 0.01, "DELTA": 0.0017,
}


def steel_deck_residuals(mp: MassProperties) -> dict[str, float]:
    """Builder minus the report's steel deck: ft for the mass centre, relative for A, B, C,
    rad for delta."""
    T = STEEL_DECK_TARGET
    return {
        "cm_height_ft": mp.cm_height_ft - T["cm_height_ft"],
        "cm_offset_ft": mp.cm_offset_ft - T["cm_offset_ft"],
        "A": mp.A / T["A"] - 1.0,
        "B": mp.B / T["B"] - 1.0,
        "C": mp.C / T["C"] - 1.0,
        "DELTA": mp.delta_rad - T["DELTA"],
    }


def calibrate_on_steel_deck(a: Assembly) -> tuple[Assembly, dict[str, float]]:
    """Fit the two unknowns Figure 21 would have given -- the base's weight (a point on
    the axis at Q) and the arm's shape (the Bezier control point, kept inside the
    chord's box: fractions in [0, 1], an up-swept arm) -- to the steel deck's mass centre,
    A, B, C and delta by weighted least squares (:data:`CALIBRATION_SCALES`).  Returns the
    calibrated assembly and its residuals (:func:`steel_deck_residuals`)."""

    from scipy.optimize import least_squares

    def build(p):
        arm = dataclasses.replace(a.arms[0], shape="bezier", control=(float(p[1]), float(p[2])))
        return dataclasses.replace(a, arms=(arm,), base=BaseMass(float(p[0]), a.base.height_ft))

    def res(p):
        r = steel_deck_residuals(mass_properties(build(p)))
        return [r[k] / CALIBRATION_SCALES[k] for k in CALIBRATION_SCALES]

    fit = least_squares(res, [50.0, 0.5, 0.5], bounds=([0.0, 0.0, 0.0], [300.0, 1.0, 1.0]),
                        xtol=1e-12, ftol=1e-12)
    out = build(fit.x)
    return out, steel_deck_residuals(mass_properties(out))
