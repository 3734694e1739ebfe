"""All 18 columns of the report's Tables 11 and 12, run on both engines where they can run.

* steel: the shipped decks (``decks/steel*.dat``; the report's own deck and its variants);
* aluminium: a deck from the post-assembly builder (``assemblies/aluminium.toml``) with the
  car, springs and speeds of the steel deck of the same column (heights kept above the
  ground, fenders about the shaft axis);
* twin: a scene from the builder (two arms, R and U); the listing cannot carry U, so the
  core alone runs it (:func:`~deck_emulator.core.assembly.scene_runs_on_listing`).

The emulator runs in ``double`` with the ``ed-direction`` erratum for alpha != 0 (the
shipped steel angle decks need it, see ``decks/README.md``); the core runs the scene under
the ``LEGACY`` options (the listing's quirks).
"""

from __future__ import annotations

from functools import lru_cache

from deck_emulator.core import LEGACY, simulate
from deck_emulator.core.assembly import (
    load_assembly,
    mass_properties,
    scene_runs_on_listing,
)
from deck_emulator.engine.assemblies import to_deck_text, to_deck_values, to_scene
from deck_emulator.core.pair_hits import joint_ground_hit, terminal_points_xl
from deck_emulator.core.scene import Scene
from deck_emulator.decks import path as deck_path
from deck_emulator.legacy.deck import parse_deck, read_deck
from deck_emulator.engine import EmulatorEngine
from deck_emulator.engine.errata import ED_DIRECTION
from deck_emulator.legacy.extract import extract
from deck_emulator.studies.report_tables import CASES_ALL

__all__ = ["column_inputs", "run_column", "template_deck"]


def template_deck(column: str) -> str:
    """The shipped steel deck with the column's speed and angle (``aluminium40_a15`` ->
    ``steel40_a15``)."""
    post, mph, alpha, _ = CASES_ALL[column]
    return f"steel{mph}" + ("" if alpha == 0 else f"_a{alpha}")


@lru_cache(maxsize=None)
def column_inputs(column: str):
    """(deck or None, scene) of a column."""
    post = CASES_ALL[column][0]
    template = template_deck(column)
    if post == "steel":
        deck = read_deck(deck_path(template))
        return deck, Scene.from_deck(deck, name=column)
    asm, _, _ = load_assembly(post)
    mp = mass_properties(asm)
    scene = to_scene(asm, mp, template=template)
    scene = type(scene)(**{**scene.__dict__, "name": column})
    if scene_runs_on_listing(scene) is not None:
        return None, scene
    deck = parse_deck(to_deck_text(to_deck_values(asm, mp, template=template)), path=column)
    return deck, scene


@lru_cache(maxsize=None)
def run_column(column: str) -> dict:
    """Both engines' numbers of one column, keyed like ``REPORT_ALL``'s fields."""
    post, mph, alpha, table = CASES_ALL[column]
    deck, scene = column_inputs(column)
    out: dict = {"column": column, "emulator": None, "core": None,
                 "listing_refusal": scene_runs_on_listing(scene)}
    if deck is not None:
        # requested for every column: the angled ones need it, and it leaves the 0° printouts
        # byte-identical (legacy/CORRECTIONS.md)
        errata = (ED_DIRECTION,)
        result = EmulatorEngine(errata=errata, trace=False).run(deck)
        run, err = result.raw, result.error
        o = extract(run.text(), deck)
        em = {"delta_v_crush_mph": o.delta_v_crush_mph, "max_decel_g": o.max_decel_g,
              "hit": o.hit, "time_ms": None if o.hit_time_s is None else 1000 * o.hit_time_s,
              "error": err, "errata": errata}
        for p in ("P", "R", "Q"):
            pt = o.terminal.get(p)
            for ax in "XYZ":
                em[f"{ax}{p}L"] = None if pt is None else getattr(pt, f"{ax}L")
        out["emulator"] = em
    res = joint_ground_hit(simulate(scene, LEGACY))
    pts = terminal_points_xl(res)
    co = {"delta_v_crush_mph": res.delta_v_contact_mph, "max_decel_g": res.max_decel_g,
          "hit": res.hit_message, "time_ms": None if res.hit is None else 1000 * res.hit.time_s}
    for p in ("P", "R", "Q", "U"):
        for i, ax in enumerate("XYZ"):
            co[f"{ax}{p}L"] = pts[p][i] if p in pts else None
    out["core"] = co
    out["result"] = res
    return out
