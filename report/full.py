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

import math
from functools import lru_cache

from deck_emulator.core.assembly import load_assembly, mass_properties, scene_runs_on_listing
from deck_emulator.vocabulary.scene import Scene
from deck_emulator.decks import path as deck_path
from deck_emulator.engine import CoreEngine, EmulatorEngine, Outcome
from deck_emulator.engine.assemblies import to_deck_text, to_deck_values, to_scene
from deck_emulator.engine.errata import ED_DIRECTION
from deck_emulator.engine.quantities import values
from deck_emulator.legacy.deck import parse_deck, read_deck
from deck_emulator.studies.report_tables import CASES_ALL, REPORT_ALL

__all__ = ["column_inputs", "run_column", "column_task", "column_tasks", "template_deck",
           "columns_row", "DELTA_V_CANDIDATES", "DECEL_CANDIDATES", "PROVENANCE",
           "PROVENANCE_CRASH", "provenance", "cell_kind", "rigid_distances", "rigid_means",
           "as_rigid_body_requires", "DOUBTFUL"]

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


# ------------------------------------------------------------------------------ provenance

#: Where each input of a post's columns comes from (issue 24, item 5): ``deck``: the report's
#: own $DATA deck (``decks/steel40.dat``) or its variants; ``description``: the report's
#: written description (Chapter VI's text, the tables' header rows); ``fitted``: read off the
#: very tables the columns are compared with; ``assumed``: the project's own choice, or the
#: steel deck's calibration carried over. ``prediction``: whether the column predicts the
#: tables from inputs none of which was read off them.
PROVENANCE = {
    "steel": {
        "deck": "every input: the report's deck (mass, A, B, C, δ, P, Q, R, S, T, the car WV, "
                "CK, CT, FCONST, friction, normal force, ground)",
        "description": "the column's speed (VVB) and approach angle (ALPHA), Chapter VI",
        "fitted": "none",
        "assumed": "none",
        "prediction": False,
        "why": "a re-run of the report's own input deck: a reproduction, not a prediction",
    },
    "aluminium": {
        "deck": "the car and its springs (WV, CK, CT, FCONST, outline), base friction and "
                "normal force, S and T 1.0 and 2.27 ft above Q, ground 0.5 ft below Q (the "
                "steel deck of the same speed and angle)",
        "description": "weight 316.63 lb (the tables' header row); shaft 8 in × 6 in tapered; "
                       "arm reach 10.5 ft, arm 83.5 lb, luminaire 35 lb; speed and angle",
        "fitted": "|PQ| 29.5 ft (text: 30 ft 0 in) and the arm's rise 2.5 ft above P, from "
                  "these tables' terminal coordinates",
        "assumed": "base 61 lb and the arm's shape (the steel deck's calibration carried "
                   "over); density 169 lb/ft³; a uniform wall",
        "prediction": False,
        "why": "|PQ| and the arm's rise were read off the tables it is compared with",
    },
    "twin": {
        "deck": "the car and its springs (WV, CK, CT, FCONST, outline), base friction and "
                "normal force, S and T 1.0 and 2.27 ft above Q, ground 0.5 ft below Q (the "
                "steel deck of the same speed and angle)",
        "description": "weight 502.45 lb (the tables' header row); shaft 8 in × 4.1 in "
                       "tapered steel; two arms, reach 10.5 ft, 83.5 lb, luminaires 35 lb; "
                       "speed and angle",
        "fitted": "|PQ| 27.25 ft (text: 27 ft 9 in) and the arms' rise 4.75 ft above P, from "
                  "these tables' terminal coordinates",
        "assumed": "base 61 lb and the arms' shape (the steel deck's calibration carried "
                   "over); density 490 lb/ft³; a uniform wall",
        "prediction": False,
        "why": "|PQ| and the arms' rise were read off the tables it is compared with",
    },
}

#: The crash test of Chapter V (Tables 9, 10), the same way.
PROVENANCE_CRASH = {
    "deck": "none (the listing's 5 in normal-force release is kept)",
    "description": "post 215 lb, 62 slug ft², mass centre 4.63 ft from the base, 9 ft; car "
                   "2,800 lb at 40 ft/s; the leaf spring's four stiffnesses and its 3.0 and "
                   "4.5 in limits (section 5.2)",
    "fitted": "none (the spring's unloading is not tuned to Table 10)",
    "assumed": "impact point S 1.5 ft above the base; the unloading knee at 3.0 in; the base "
               "on the ground; axial inertia 0.5 slug ft² (each one's effect: the variants' "
               "table)",
    "prediction": True,
    "why": "every input is the text's or a stated assumption; none was read off Tables 9, 10",
}


def provenance(column: str) -> dict:
    """The provenance of ``column`` (a name of ``CASES_ALL``, or ``"crash_test"``)."""
    if column == "crash_test":
        return PROVENANCE_CRASH
    return PROVENANCE[CASES_ALL[column][0]]


def cell_kind(column: str, key: str) -> str | None:
    """Why a column's cell is not a test of the model, or None where it is one:

    * ``"input"``: the cell is an input of the run (twin at α = 0: YRL = -10.50 and
      YUL = +10.50 are the arms' reach, which the symmetry keeps);
    * ``"symmetry"``: the cell is fixed by the symmetry of the scene (twin at α = 0: the
      car's path and the post are symmetric about the XL-ZL plane, so YPL = YQL = 0, and U
      mirrors R: XUL = XRL, ZUL = ZRL);
    * ``"end condition"``: the height of the point whose ground hit ends the run (the
      listing stops with it in a 0.1 ft band; the report prints 0.00 or near it).
    """
    post, mph, alpha, _ = CASES_ALL[column]
    if post == "twin" and alpha == 0:
        if key in ("YRL", "YUL"):
            return "input"
        if key in ("YPL", "YQL", "XUL", "ZUL"):
            return "symmetry"
    comment = REPORT_ALL[column]["comment"]
    if "GROUND" in comment and len(key) == 3 and key[0] == "Z" and key[2] == "L":
        hitting = comment.rsplit(" ", 1)[1].split("&")
        if key[1] in hitting:
            return "end condition"
    return None


# ------------------------------------------------------------------ doubtful source cells


def _dist(a, b) -> float:
    return math.dist(a, b)


def _point(row, p):
    return tuple(row[f"{a}{p}L"] for a in "XYZ")


def rigid_distances(column: str, overrides: dict | None = None) -> dict:
    """|PQ|, |PR|, |QR| of ``column``'s printed terminal points (``overrides``: field ->
    another reading of a cell)."""
    row = {**REPORT_ALL[column], **(overrides or {})}
    P, Q, R = (_point(row, k) for k in "PQR")
    return {"PQ": _dist(P, Q), "PR": _dist(P, R), "QR": _dist(Q, R)}


#: The two doubtful cells of the source (issue 24, item 7): Table 11's aluminium 20 mph 0°
#: YQL, printed "00.39" (read 0.39; a lost minus sign would make it -0.39), and the aluminium
#: 20 mph 15° column's R, 0.4 and 0.7 ft off the rigid body the five other columns keep.
DOUBTFUL = (("aluminium20", "YQL"), ("aluminium20_a15", "R"))


def rigid_means(post: str, leave_out=()) -> dict:
    """Mean |PQ|, |PR|, |QR| of ``post``'s columns but those in ``leave_out`` (a rigid body's
    distances: the same in every column)."""
    cols = [c for c in CASES_ALL if CASES_ALL[c][0] == post and c not in leave_out]
    ds = [rigid_distances(c) for c in cols]
    return {k: sum(d[k] for d in ds) / len(ds) for k in ("PQ", "PR", "QR")}


def as_rigid_body_requires(column: str, key: str) -> dict:
    """The value of the one cell ``key`` of ``column`` (the others as printed) that brings
    the two distances it enters (|PQ| and |QR| for Q's cells, |PR| and |QR| for R's)
    closest, by least squares (scipy), to the means of the post's columns whose cells are not
    doubtful; and the remaining misfit (ft, the root of the summed squares)."""
    from scipy.optimize import least_squares

    post = CASES_ALL[column][0]
    want = rigid_means(post, leave_out=tuple(c for c, _ in DOUBTFUL))
    pairs = {"Q": ("PQ", "QR"), "R": ("PR", "QR"), "P": ("PQ", "PR")}[key[1]]

    def resid(x):
        d = rigid_distances(column, {key: float(x[0])})
        return [d[p] - want[p] for p in pairs]

    fit = least_squares(resid, [REPORT_ALL[column][key]])
    return {"value": float(fit.x[0]), "misfit_ft": float(math.hypot(*fit.fun)),
            "pairs": pairs, "means": want}
