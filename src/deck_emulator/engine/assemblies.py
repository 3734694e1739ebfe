"""Assemblies as the two paths take them: the typed scene of a described support and, where
the listing can carry it (one arm), its 8-card deck.

An assembly is one post: its values are the deck's as punched (each field as its 10 columns
carry it, F10.5 where it fits), and the core's scene is built from those same values, so that
``assembly NAME emulator`` and ``assembly NAME core`` run the same post (docs/models.md, 'One
post, one deck').

The builder (:mod:`deck_emulator.core.assembly`) knows masses and points; a deck also needs
the report's car, springs and start values, which come from a template deck read by the 1967
path's reader.  This bridge between the two paths is why these functions live in the engine
layer.
"""

from __future__ import annotations

import dataclasses

from deck_emulator.core.assembly import (
    Assembly,
    AssemblyError,
    MassProperties,
    load_assembly,
    mass_properties,
)
from deck_emulator.decks import path as deck_path
from deck_emulator.legacy.deck import READ_LIST, read_deck
from deck_emulator.vocabulary.deck_fields import SCENE_PATHS
from deck_emulator.vocabulary.scene import Post, PostPoint, Scene

#: the builder's description reader and its error are the studies' too (crash_test): through here
__all__ = ["AssemblyError", "load_assembly", "punched", "to_deck_values", "to_deck_text",
           "to_scene"]


#: vehicle values of the report's deck that are heights above the ground (ft) or YV
#: offsets from the shaft axis, so that one car meets every post the same way.
_HEIGHTS = ("HTRV", "HTV", "HHV")


def to_deck_values(
    a: Assembly,
    mp: MassProperties | None = None,
    *,
    template: str = "steel40",
    speed_ft_s: float | None = None,
    alpha_rad: float | None = None,
) -> dict[str, float]:
    """READ-list values of the assembly's deck, as punched (:func:`punched`): the post from
    the builder, the car, the springs and everything else from the ``template`` deck, with
    the car's heights kept above the ground and its fenders kept about the shaft axis.  One
    arm at most."""

    if len(a.arms) > 1:
        raise AssemblyError(f"{a.name}: the listing carries one arm (point R); this has {len(a.arms)}")
    mp = mp or mass_properties(a)
    t = read_deck(deck_path(template))
    v = dict(t.values)
    old_depth = v["HEIGHT"]  # ground below the template's mass centre
    old_axis = v["YYPO"]  # template shaft axis YY
    depth = mp.cm_height_ft + a.pedestal_ft
    axis = -mp.cm_offset_ft
    for k in _HEIGHTS:
        v[k] = v[k] + old_depth - depth
    for k in ("YLFEN", "YRFEN"):
        v[k] = v[k] - old_axis + axis
    v.update(W=round(mp.mass_slug, 5), A=mp.A, B=mp.B, C=mp.C, DELTA=mp.delta_rad,
             HEIGHT=depth, FNA=mp.weight_lb)
    # the post's points, through the one deck <-> scene mapping (an absent point reads 0.0)
    letter_of = {attr: letter for letter, attr in Post.POINT_FIELDS.items()}
    coord_index = {"xx_ft": 0, "yy_ft": 1, "zz_ft": 2}
    for name, path in SCENE_PATHS.items():
        if path[0] == "post" and len(path) == 3:
            p = mp.points.get(letter_of[path[1]])
            v[name] = 0.0 if p is None else p[coord_index[path[2]]]
    if speed_ft_s is not None:
        v["VVB"] = -abs(speed_ft_s)
    if alpha_rad is not None:
        v["ALPHA"] = alpha_rad
    return {name: punched(x) for name, x in v.items()}


def _field(x: float) -> str:
    """A value in 10 columns, readable by F10.5: explicit point, left-justified, at most
    nine characters (a blank column between fields, as the report's deck), with as many
    of F10.5's five decimals as fit."""
    for nd in (5, 4, 3, 2, 1):
        s = f"{x:.{nd}f}"
        if len(s) <= 9:
            if float(s) == 0.0:
                s = "0.0"
            return s.ljust(10)
    raise AssemblyError(f"{x!r} does not fit a 10-column field")


def punched(x: float) -> float:
    """``x`` as its deck field carries it (:func:`_field`): what the 1967 program reads."""
    return float(_field(x))


def to_deck_text(values: dict[str, float]) -> str:
    """The deck (``$DATA`` and 8 cards of 8 fields in 8F10.5 columns) of READ-list values."""

    lines = ["$DATA".ljust(80)]
    for card in READ_LIST:
        lines.append("".join(_field(values.get(n, 0.0)) for n in card))
    return "\n".join(lines) + "\n"


def to_scene(
    a: Assembly,
    mp: MassProperties | None = None,
    *,
    template: str = "steel40",
    speed_ft_s: float | None = None,
    alpha_rad: float | None = None,
):
    """The typed scene of the assembly (any number of arms up to two: R, and U)."""

    return scene_and_deck_values(a, mp, template=template, speed_ft_s=speed_ft_s,
                                 alpha_rad=alpha_rad)[0]


def scene_and_deck_values(
    a: Assembly,
    mp: MassProperties | None = None,
    *,
    template: str = "steel40",
    speed_ft_s: float | None = None,
    alpha_rad: float | None = None,
):
    """``(scene, values)``: :func:`to_scene` and the deck values (:func:`to_deck_values`) of
    the assembly's first arm it is made from, the template deck read once; where the scene
    runs on the listing (one arm, no U) the values are the deck the listing runs."""

    if len(a.arms) > 2:
        raise AssemblyError(f"{a.name}: at most two arms (R and U)")
    mp = mp or mass_properties(a)
    one = dataclasses.replace(a, arms=a.arms[:1])
    mp1 = dataclasses.replace(mp, points={k: p for k, p in mp.points.items() if k != "U"})
    values = to_deck_values(one, mp1, template=template, speed_ft_s=speed_ft_s, alpha_rad=alpha_rad)
    scene = Scene.from_deck(values, name=a.name)
    if "U" in mp.points:  # no card carries U: taken to a deck field's precision all the same
        u = PostPoint(*(punched(x) for x in mp.points["U"]))
        post = dataclasses.replace(scene.post, second_luminaire_end=u)
        scene = dataclasses.replace(scene, post=post)
    return scene, values
