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

from deck_emulator.core.assembly import load_assembly, mass_properties, scene_runs_on_listing
from deck_emulator.core.scene import Scene
from deck_emulator.decks import path as deck_path
from deck_emulator.engine import CoreEngine, EmulatorEngine, Outcome
from deck_emulator.engine.assemblies import to_deck_text, to_deck_values, to_scene
from deck_emulator.engine.errata import ED_DIRECTION
from deck_emulator.engine.quantities import values
from deck_emulator.legacy.deck import parse_deck, read_deck
from deck_emulator.studies.report_tables import CASES_ALL

__all__ = ["column_inputs", "run_column", "column_task", "column_tasks", "template_deck",
           "columns_row", "DELTA_V_CANDIDATES", "DECEL_CANDIDATES"]

#: The readings of the report's "DECREASE IN VEHICLE VELOCITY" computed for every column
#: (registry names): the report defines it nowhere; its text gives the car's law (M_v V' + FS
#: = 0, section 3.2) and the listing prints two instants of the contact (FORMAT 355, the first
#: spring lost; the contact lost), and the crush pulse's end is where the spring force is
#: first capped. After the contact the car keeps its speed (section 3.8): the end of the run
#: reads as the contact's end.
DELTA_V_CANDIDATES = ("delta_v_crush_mph", "delta_v_first_spring_mph", "delta_v_contact_mph")

#: The readings of its "MAXIMUM VEHICLE DECELERATION" (registry names): the largest FS/(WV G)
#: as printed after the start-up steps, at every step, and the largest 10 ms average.
DECEL_CANDIDATES = ("max_decel_g", "max_decel_every_step_g", "max_decel_10ms_g")


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


def columns_row(out: Outcome) -> dict:
    """An engine's outcome of a column, keyed like ``REPORT_ALL``'s fields: every candidate
    reading of the report's ΔV and deceleration (:data:`DELTA_V_CANDIDATES`,
    :data:`DECEL_CANDIDATES`, from the registry), the end
    (the hit as the listing words it) and its time, the terminal points XL, YL, ZL."""
    row = {**values(out, DELTA_V_CANDIDATES + DECEL_CANDIDATES),
           "hit": out.hit_message,
           "time_ms": None if out.hit_time_s is None else 1000 * out.hit_time_s,
           "error": out.error, "errata": list(out.errata)}
    for p in ("P", "R", "Q", "U"):
        xyz = out.terminal.get(p)
        for i, ax in enumerate("XYZ"):
            row[f"{ax}{p}L"] = None if xyz is None or xyz[i] is None else float(xyz[i])
    return row


#: The post's points whose places the page reads off the core's run.
POINTS_L = ("P", "R", "Q", "U")


def run_column(column: str) -> dict:
    """Both engines' outcomes of one column, as plain values (a row of the scene runner):
    ``emulator`` and ``core`` (:func:`columns_row`; ``emulator`` is ``None`` where the listing
    cannot carry the post), ``listing_refusal`` (why not, or None), and the core's post in
    the report's XL, YL, ZL axes (``core_points_l``: at t = 0 under ``initial``, at the
    report's time of the column's end under ``report_time``, None where the run did not
    reach it)."""
    from deck_emulator.studies.report_tables import report_time_ms_all

    deck, scene = column_inputs(column)
    out: dict = {"column": column, "emulator": None, "core": None,
                 "listing_refusal": scene_runs_on_listing(scene)}
    if deck is not None:
        # requested for every column: the angled ones need it, and it leaves the 0° printouts
        # byte-identical (legacy/CORRECTIONS.md)
        # traced: the first spring's ΔV and the 10 ms deceleration read the car's history
        em = EmulatorEngine(errata=(ED_DIRECTION,)).run(deck)
        out["emulator"] = columns_row(em)
    co = CoreEngine(preset="legacy").run(scene, name=column)
    out["core"] = columns_row(co)
    report_ms = report_time_ms_all(column)

    def points_at(t):
        got = {k: co.point_l(k, t) for k in POINTS_L} if t is not None else {}
        return {k: list(p) for k, p in got.items() if p is not None}

    out["core_points_l"] = {"initial": points_at(0.0),
                            "report_time": points_at(None if report_ms is None
                                                     else report_ms / 1000.0)}
    return out


def column_task(task: dict) -> dict:
    """Worker of the scene runner: :func:`run_column` of ``task["column"]``."""
    return run_column(task["column"])


def column_tasks(columns) -> list[dict]:
    """The scene runner's tasks for ``columns``."""
    return [{"kind": "column", "column": c, "cost": 1.0} for c in columns]
