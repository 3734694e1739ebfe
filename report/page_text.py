"""The prose of docs/report_full.md, one row a sentence or paragraph that states something
about numbers: its template (the figures it names are fields, filled by :mod:`report.page`
from the computation beside it) and, where the words draw a conclusion from those figures, the
check that the figures back it (:func:`say` refuses to write a claim its figures do not
back). Quoted words of the report live in :mod:`report.statements`; this is the page's own
voice.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

__all__ = ["Text", "TEXT", "say", "INCONSISTENCIES", "UNFINISHED"]


@dataclass(frozen=True)
class Text:
    template: str
    #: the claim's check over the same figures; None where the words only report them
    holds: Callable[..., bool] | None = None


def say(key: str, /, **figures) -> str:
    """The row ``key`` filled with ``figures``; a claim whose check fails is refused (the page
    would say what its numbers do not show)."""
    row = TEXT[key]
    if row.holds is not None and not row.holds(**figures):
        raise ValueError(f"report_full's '{key}' is not backed by its figures: {figures}")
    return row.template.format(**figures)


TEXT: dict[str, Text] = {
    # ------------------------------------------------------------------ the page's head
    "head": Text(
        "Made by `python scripts/make_report_full.py`; report numbers from "
        "`deck_emulator.studies.report_tables` ({source}; Tables 11-12 lines 1748-1792, "
        "Tables 8-10 lines 1622-1674). No column is a prediction from the written descriptions "
        "alone: the provenance table says, column by column, which inputs come from the "
        "report's deck, from its text, and which were read off these tables themselves.\n",
        lambda source, n_pred: n_pred == 0),
    "contents": Text(
        "Contents: the summary of the misses; provenance; the builder against the steel deck; "
        "geometry the tables imply and how much it moves the answer; every reading of ΔV and "
        "the deceleration; Tables 11 and 12 (18 columns); the two doubtful cells of the "
        "source; Chapter V's crash test (Tables 9, 10, Figure 18) with every assumption's "
        "effect; the report's statements checked; inconsistencies in the source; what is "
        "unfinished.\n"),

    # ------------------------------------------------------------- causes of a cell's miss
    "not_a_test.input": Text("not a test: the input reach, kept by the symmetry"),
    "not_a_test.symmetry": Text("not a test: fixed by the symmetry of α = 0"),
    "not_a_test.end condition": Text(
        "not a test: the height of the hitting point (the end condition; the listing stops in "
        "a 0.1 ft band)"),
    "cause.no_variants": Text("unexplained (the base-weight variants were not run)"),
    "cause.not_among": Text(
        "unexplained (the base weight, 0-120 lb, moves XQL and ZQL by up to {width:.2f} ft at "
        "{mph} mph 0°; this cell is not among the variants' runs)"),
    "cause.none_reaches": Text(
        "unexplained (tried: no base weight in 0-120 lb gives the {needed} {unit} the miss "
        "needs at {mph} mph 0°; nearest {nearest} at {w_near:.0f} lb)",
        lambda weights, **_: not weights),
    "cause.base_fits_reading": Text(
        "the base weight (fitted inputs): {weights} lb gives the value at {mph} mph 0° (the "
        "shipped base is 61 lb, carried over)"),
    "cause.base_fits": Text(
        "the base weight (fitted inputs): {w:.0f} lb gives it at {mph} mph 0°, where the max "
        "decel. {decel:.2f} g still fits the report's {rep_decel:.2f}",
        lambda decel, rep_decel, fit, **_: abs(decel - rep_decel) <= fit),
    "cause.base_misfits": Text(
        "unexplained (tried: the base weight reaches it only at {tried}, against the report's "
        "{rep_decel:.2f}{at_dec})"),
    "cause.base_misfits.at_dec": Text(
        "; at the {w:.0f} lb that fits the deceleration the α = 0 miss is {miss} {unit}"),
    "cause.reading": Text("which reading is the report's: 'ΔV and the maximum deceleration'"),
    "cause.points_only": Text(
        "points only: with the shaft test (docs/shaft_contact.md) the core misses by {with_} "
        "against {without} without it",
        lambda m_with, m_without, share, **_: abs(m_with) <= share * abs(m_without)),
    "cause.points_only_part": Text(
        "points only, in part: with the shaft test (docs/shaft_contact.md) the core misses by "
        "{with_} against {without} without it; the rest: {other}",
        lambda m_with, m_without, share, **_:
            share * abs(m_without) < abs(m_with) < abs(m_without)),
    "cause.not_points": Text(
        "not the point tests: with the shaft test (docs/shaft_contact.md) the core misses by "
        "{with_} against {without} without it; {other}",
        lambda m_with, m_without, **_: abs(m_with) >= abs(m_without)),
    "cause.no_shaft_run": Text("the shaft test's run has no value here{why}; {other}"),
    "cause.steel": Text("unexplained (the report's own deck)"),
    "cause.arithmetic": Text(
        "arithmetic (the listing's difference scheme, step 0.0004 s: the emulator matches, "
        "the core's accurate solution does not)",
        lambda em_miss, core_miss, half: em_miss <= half < core_miss),
    "cause.step": Text(
        "the listing's step, 0.0004 s (the core, the same model solved continuously, "
        "matches: 'ΔV and the maximum deceleration')",
        lambda em_miss, core_miss, half: core_miss <= half < em_miss),

    # ------------------------------------------------- the summary's cause of a column
    "shaft.none": Text("the shaft test's run did not end{why}: the point tests are not "
                       "judged{at_time}"),
    "shaft.at_time": Text("; at the report's time ours is within {d} ft"),
    "shaft.ends": Text(
        "with the shaft test (docs/shaft_contact.md) the core ends on the {surface} ({point}) "
        "at {dt} ms"),
    "shaft.dist": Text(", its end coordinates {a:.2f} ft from the report's against {b:.2f} "
                       "without{farther}"),
    "shaft.tried": Text("tried: {ends}{dist}, where the report ends on the ground"),
    "shaft.cause": Text(
        "points only: {ends}{dist}{at_time}",
        lambda a, b, t_with, t_without, share, **_:
            a <= share * b and abs(t_with) <= share * abs(t_without)),
    "shaft.cause_part": Text(
        "points only, in part: {ends}{dist}{at_time}",
        lambda a, b, t_with, t_without, share, **_:
            a < b and abs(t_with) < abs(t_without)
            and not (a <= share * b and abs(t_with) <= share * abs(t_without))),
    "shaft.not_cause": Text(
        "not the point tests: {ends}{dist}{at_time}",
        lambda a, b, t_with, t_without, **_: a >= b or abs(t_with) >= abs(t_without)),
    "main.end_steel": Text("end: unexplained (the report's own deck)"),
    "main.dv_fits": Text(
        "ΔV: the {reading} reading fits ({miss:+.2f}){carried}",
        lambda miss, fit, **_: abs(miss) <= fit),
    "main.dv_carried": Text(
        ", at the carried-over base weight (fitted inputs), which moves ΔV by more"),
    "main.dv_none": Text("ΔV: no reading within {fit} mph (nearest: {reading}, {miss}){steel}"),
    "main.decel": Text("max decel. {miss:+.2f} g: {why}", lambda miss, fit, **_: abs(miss) > fit),

    # ------------------------------------------------------------------------ summary
    "summary.intro": Text(
        "Largest coordinate Δ: over the cells that test the model (not those equal to an "
        "input, a symmetry or the end condition). ΔV Δ: the three readings (crush pulse / "
        "first spring / whole contact). Each cause names the computation that backs it; "
        "'unexplained' where none does. † marks the aluminium and twin columns: fitted "
        "inputs (|PQ| and the arm's rise read off these tables; 'Provenance'), beside every "
        "number of theirs.\n"),
    "summary.predictions": Text(
        "Genuine predictions among the 18 columns: **{n_pred}** (the provenance table below "
        "says why each is not one); the crash test of Chapter V is {crash}.\n"),

    # ----------------------------------------------------------------------- provenance
    "provenance.intro": Text(
        "**deck**: the report's own $DATA deck (`decks/steel40.dat`) or its variants; "
        "**description**: the report's written description (Chapter VI's text, the tables' "
        "header rows; Chapter V for the crash test); **fitted**: read off the very tables the "
        "column is compared with; **assumed**: the project's choice, or the steel deck's "
        "calibration carried over.\n"),
    "provenance.predictions": Text(
        "\nGenuine predictions: **{n_pred} of 18** columns, and the crash test. Cells that "
        "equal an input, a symmetry or the end condition are not tests of the model; the "
        "column tables mark them 'not a test' and the summary leaves them out:\n"),

    # ------------------------------------------------------------------------- builder
    "builder.intro": Text(
        "`deck_emulator.core.assembly` (formulas and their reasoning in its docstring): "
        "thin-wall tapered tube (wall solved from the total weight), the arm a thin rod along "
        "a quadratic Bezier curve, the luminaire and the base point masses, the parallel-axis "
        "theorem, principal axes by `numpy.linalg.eigh`.\n"),
    "builder.calibrated": Text(
        "\nCalibrated on the steel deck only (`calibrate_on_steel_deck`, weighted least "
        "squares, the control point kept inside the chord's box): base **{base_lb:.1f} lb** "
        "at Q, arm control point at **{reach:.3f} of the reach, {rise:.3f} of the rise** (an "
        "up-swept arm); wall {wall_in:.4f} in. With the mass centre in place, no shape of the "
        "arm brings A, B and C together: the tube model stays {a_pct:+.0f} % in A, "
        "{b_pct:+.0f} % in B and {c_pct:+.0f} % in C. The report's inertias cannot come from "
        "this model. The steel columns of this page (and of docs/report/, "
        "docs/shaft_contact.md) run the report's deck itself; `deck-emulator assembly steel` "
        "runs this builder's post, with these inertias, so its ends differ from the deck's "
        "(at 20 mph with the shaft test: docs/shaft_contact.md). The aluminium and twin posts "
        "carry this misfit. The same base and arm shape are carried over to aluminium and "
        "twin (an assumption: Figure 21 is lost).\n"),

    # ---------------------------------------------------- geometry from the tables
    "geometry.intro": Text(
        "Terminal coordinates are positions of one rigid body, so the distance between two of "
        "its points is the same in every column of a post. Distances (ft) over the six "
        "columns (Table 11: 0°, 15°, 30°; Table 12: 0°, 15°, 30°):\n"),
    "geometry.post": Text(
        "* **{post}**: |PQ| = {pq:.2f} ± {sd:.2f} ft; the arm's R is {reach:.2f} ft from the "
        "axis and {rise:.2f} ft above P (law of cosines on the means)."),
    "geometry.consistency": Text(
        "\nConsistency: steel |PQ| = {steel_pq} in all six columns (deck 36.708). Steel |PR| "
        "is {steel_pr20} at 20 mph (deck √125 = 11.180) but {steel_pr40} at 40 mph, where ZRL "
        "is printed 0.00: the report evidently set the hitting point to the ground (the "
        "listing prints it anywhere in the 0.1 ft band), which moves R by up to 0.1 ft. "
        "Aluminium |PQ| = {al_pq} ({al_pq_mode} in {al_pq_n} columns), not the nominal 30 ft "
        "0 in; the 20 mph 15° column's R is {al_pr_off:.1f} ft (|PR| {al_pr:.2f}) and "
        "{al_qr_off:.1f} ft (|QR| {al_qr:.2f}) off the mean of the other five — one of XRL, "
        "YRL, ZRL of that column is misprinted (which one, and what each reading does: 'Two "
        "doubtful cells'). Twin |PQ| = {twin_pq}, not the nominal 27 ft 9 in (27.75): "
        "{twin_short:.2f} ft short, as aluminium; |RU| = {twin_ru} (twice a 10.5 ft reach), "
        "|PR| {twin_pr} and |PU| {twin_pu} agree to {twin_pr_pu:.2f} ft. The two posts' "
        "nominal heights evidently include 0.5 ft below Q (a base); the builder uses the "
        "tables' |PQ|.\n"),

    # ------------------------------------------- how much the inferred geometry moves it
    "variants.moves": Text(
        "\nThe base's weight (the shaft's wall follows from the total weight) moves the end by "
        "{end_lo:.0f}-{end_hi:.0f} ms and the base point by {base_lo:.1f}-{base_hi:.1f} ft, "
        "and the car's ΔV (each reading) by {dv_lo:.2f}-{dv_hi:.2f} mph and its largest "
        "deceleration by {decel_lo:.2f}-{decel_hi:.2f} g, more than any of their misses "
        "(at most {dv_miss:.2f} mph by the nearest reading, {decel_miss:.2f} g): the base sits "
        "at Q, 1.0 ft below the impact point S, so it adds to the mass the car has to push. "
        "Whether it explains a miss is decided cell by cell (Tables 11 and 12 below, the "
        "cause column, by the rule given there): of the {n_miss} cells of the aluminium and "
        "twin columns (fitted inputs) that miss the report's last digit, {n_base} are put "
        "down to a base weight in 0-120 lb, {n_unexplained} remain unexplained, and the others "
        "go to the other causes named there.\n",
        lambda dv_lo, decel_lo, dv_miss, decel_miss, **_:
            dv_lo > dv_miss and decel_lo > decel_miss),
    "variants.fit_intro": Text(
        "Base weight (lb) at which each reading equals the report's (linear between the "
        "base-weight variants above; '—' outside 0-120 lb), and the deceleration the core "
        "gives at that base: a ΔV reading is consistent with a post's tables only where both "
        "fit at one base weight.\n"),
    "variants.joint": Text(
        "* **{post}, {mph} mph**, read jointly: the {reading} reading (ΔV fits at a base of "
        "{w:.0f} lb, where the deceleration misses by {miss:+.2f} g){others}."),
    "variants.closing": Text(
        "\nThe shipped base (61 lb) was calibrated on the steel deck's mass centre, not on "
        "these tables. Where a ΔV reading fits at a base weight at which the deceleration "
        "misses by more than the misses above, that reading is not consistent with the post's "
        "tables under this builder.\n"),

    # --------------------------------------------------------- the readings of ΔV, decel.
    "readings.intro": Text(
        "The report defines neither row. Its text gives the car's law, M_v V̇ + FS = 0 "
        "(section 3.2), so its deceleration is FS/M_v; the listing prints two instants of the "
        "contact, the post's loss of the first spring (FORMAT 355) and of the car; the crush "
        "pulse ends where the spring force is first capped at FCONST; after the contact the "
        "car keeps its speed (section 3.8), so the end of the run reads as the contact's end. "
        "The readings, each a quantity of the registry (`engine/quantities.py`, "
        "docs/json.md):\n"),
    "readings.mean": Text(
        "Mean |ours − report| over a post's six columns (least and largest signed miss in "
        "brackets); the emulator runs aluminium and steel only.\n"),
    "readings.best": Text(
        "* **{post}** (core): ΔV fits best as the {dv} reading (mean miss {dv_mean:.3f} mph; "
        "the others {others}); the deceleration as {dc} ({dc_mean:.3f} g)."),
    "readings.steel_decel": Text(
        "* Deceleration on the report's own steel deck: the listing's printed value (the "
        "emulator) is {em_lo:+.2f} to {em_hi:+.2f} g off the report, the core's continuous "
        "maximum {co_lo:+.2f} to {co_hi:+.2f} g; emulator − core on the same decks (aluminium "
        "and steel) {d_lo:+.2f} to {d_hi:+.2f} g, the listing's 0.0004 s step against a "
        "continuous solution of the same model. Why the listing prints more than the report "
        "did for the report's own deck: unexplained. For twin no reading comes within "
        "{fit} g at 40 mph; the base weight moves it by more ('How much the inferred geometry "
        "moves the answer').",
        lambda em_lo, twin40_best, fit, **_: em_lo > 0 and twin40_best > fit),
    "readings.no_one": Text(
        "* No one reading fits all three posts (core): the crush-pulse reading misses steel "
        "at 40 mph by {crush_steel40} mph, aluminium by {crush_aluminium} and twin by "
        "{crush_twin}; the first-spring reading misses aluminium by {first_aluminium}, twin "
        "by {first_twin} and steel by {first_steel}; the whole-contact reading misses "
        "aluminium by {contact_aluminium}, twin by {contact_twin} and steel by "
        "{contact_steel}. Aluminium's and twin's ΔV and deceleration move with the base "
        "weight carried over from the steel calibration by more than these misses, so their "
        "own fit does not decide the definition; read jointly with the deceleration, see the "
        "'read jointly' lines under 'How much the inferred geometry moves the answer'. The "
        "steel 20 mph columns fit no reading (crush pulse {crush_steel20}, first spring "
        "{first_steel20} mph off): unexplained."),

    # ------------------------------------------------------------------- 18 columns
    "columns.intro": Text(
        "Each column: the report's value, the emulator (the 1967 listing, `double`, erratum "
        "`ed-direction` for α ≠ 0) where the listing can run the post, the core (`LEGACY` "
        "options), and the difference ours − report. The report's one ΔV is set beside the "
        "three readings ('ΔV and the maximum deceleration' compares them). The steel columns "
        "run the shipped decks (the report's deck and its variants); aluminium runs a deck "
        "from the builder; twin runs the builder's scene on the core only (the listing has no "
        "point U: `scene_runs_on_listing` refuses it). For the twin post, \"R&U\" means: when "
        "the first of R and U enters the listing's 0.1 ft ground band (a located event), the "
        "other is inside the band too, i.e. both would be seen on the ground at one step of "
        "the listing (`core/pair_hits.py`). The causes named, each backed by a computation "
        "on this page: **the base weight** (aluminium, twin, fitted inputs: only where a base "
        "weight in 0-120 lb gives the value the miss needs in the post's α = 0 column of the "
        "same speed and, for every cell but the deceleration itself, the car's largest "
        "deceleration there still fits the report's; section 'How much the inferred geometry "
        "moves the answer'; else the miss is **unexplained**, with the base weight that was "
        "tried), **points only** (20 mph 'hits car' columns: the listing and the core's "
        "legacy preset test the points P, R, C, U against the car, not the shaft; named only "
        "where the same column run with the shaft test (docs/shaft_contact.md) takes away at "
        "least {share} of the core's miss of that cell, 'in part' where it takes away less, "
        "and 'not the point tests' where it takes away nothing, each with both misses; the "
        "core's post at the report's time is below each such column), **arithmetic** (the "
        "listing's own step and scheme: "
        "the emulator matches, the core does not); a miss none of these explains is "
        "**unexplained**. Cells that equal an input, a symmetry or the end condition are "
        "marked **not a test** and are left out of the summary's largest coordinate miss.\n"),
    "columns.at_report_time": Text("\nAt the report's time ({ms} ms) the core's post is at: "
                                   "{cells}."),

    # ------------------------------------------------------------------ doubtful cells
    "doubtful.sign": Text(
        "**Table 11, `{col}` {key}, printed '00.39'.** Read as +0.39 (the page's reading) or "
        "as −0.39 (a lost minus sign). A rigid body keeps |PQ| and |QR| in every column; the "
        "means over the four aluminium columns without a doubtful cell are |PQ| {pq:.2f}, "
        "|QR| {qr:.2f} ft. The value of {key} that fits them best (least squares, the other "
        "cells as printed) is {value:+.2f} (misfit {misfit:.2f} ft).\n"),
    "doubtful.sign_effect": Text(
        "\nNeither printed reading is the rigid body's: +0.39 is {plus:+.2f} ft off in |PQ|, "
        "−0.39 {minus:+.2f} ft. Between the readings the {key} cell's miss moves by "
        "{shift:.2f} ft; the column's largest miss (core) is {other} ft in other cells, so no "
        "conclusion of the page turns on the reading.\n",
        lambda plus, minus, shift, other_ft, **_:
            round(plus, 2) != 0 and round(minus, 2) != 0 and shift < other_ft),
    "doubtful.r": Text(
        "**Table 11, `{col}` R.** As printed, |PR| = {pr:.2f} and |QR| = {qr:.2f} ft against "
        "{pr_mean:.2f} and {qr_mean:.2f} ft in the four aluminium columns without a doubtful "
        "cell. Changing one of R's three cells to fit both distances (least squares):\n"),
    "doubtful.r_best": Text(
        "\nOnly {best} can be the misprint: read as {value:+.2f} (printed {printed:+.2f}) it "
        "leaves {misfit:.2f} ft, the others {others} ft. The column tables keep the printed "
        "value.\n"),

    # ----------------------------------------------------------------------- crash test
    "crash.scene": Text(
        "The scene: `assemblies/crash_test.toml` through `deck_emulator.studies.crash_test` — "
        "a planar post (215 lb, 62 slug ft², mass centre 4.63 ft above the base end, 9 ft "
        "long), no base friction, the base's normal force until the base has slid 5 in, a "
        "2,800 lb car at 40 ft/s with the hysteretic leaf spring (`core/leaf_spring.py`: "
        "12,000 lb/ft to 3.0 in, 26,400 lb/ft to 4.5 in, constant 6,300 lb beyond until it "
        "unloads; unloading 38,400 lb/ft, then 12,000 lb/ft below 3.0 in), solved by the core "
        "with the `PHYSICAL` options. Assumptions (Figure 17 and the impact height are lost): "
        "impact point S 1.5 ft above the base (the report's deck has its spring 1.5 ft above "
        "the ground); the unloading knee at 3.0 in; the 5 in normal-force release of the "
        "listing; the base on the ground; axial inertia 0.5 slug ft² (planar motion: no "
        "effect).\n"),
    "crash.events": Text(
        "\nEvents of our run: {events}. The car's speed at separation: {vv:.2f} ft/s. Peak "
        "compression {peak_in:.2f} in (past the 4.5 in stop), so the unloading line at "
        "38,400 lb/ft reaches zero force at {set_in:.2f} in, before the 3.0 in knee: where "
        "the knee is does not matter in this test (table below).\n",
        lambda peak_in, set_in, **_: peak_in > 4.5 and set_in > 3.0),
    "crash.early": Text(
        "Our post leaves the spring at {ours_ms:.1f} ms, the report's model at 71.8 ms and the "
        "test at 70 ms (Table 8: 'when the post and the vehicle lose contact'): {early:.1f} ms "
        "earlier than the report's model. Our spring unloads at 38,400 lb/ft as soon as the "
        "compression stops growing; the report's model 'kept [the constant force] present "
        "until displacements reached values such that the spring started to unload'. How "
        "much of the early loss the stiff unloading accounts for, by the variants below: "
        "unloading at 12,000 lb/ft alone (the softest stiffness section 5.2 gives) keeps the "
        "contact to {soft_ms:.1f} ms, {gained:.1f} of the {early:.1f} ms. The longest contact "
        "of all the runs below ({n_runs}: the assumptions' variants and the impact heights of "
        "'Table 10's model column') is {longest_ms:.1f} ms ({longest}), at θ̇ = "
        "{longest_spin:.2f} rad/s; {reach} Our θ̇, {thetadot:.2f} rad/s, is between the "
        "model's 12.50 and the test's 8.75.\n",
        lambda both, thetadot, **_: both == 0 and 8.75 < thetadot < 12.50),
    "crash.reach_long": Text(
        "the runs that keep the contact to the model's 71.8 ms or longer ({cases}) turn at "
        "{spins} rad/s, not the model's 12.50: with section 5.2's spring no run gives both, "
        "so the rest is unexplained (what fits that column is a spring other than section "
        "5.2's, below)."),
    "crash.reach_short": Text(
        "no run keeps the contact to the model's 71.8 ms, so the rest is unexplained."),
    "crash.variants": Text(
        "\nThe impact height moves θ̇ over {lo:.2f}-{hi:.2f} rad/s for S at 1.0-2.5 ft; the "
        "normal force and the base's height hardly matter before 70 ms. The spring's "
        "unloading moves it most: unloading at 12,000 lb/ft alone keeps the post on the car "
        "to {soft_ms:.1f} ms and gives θ̇ = {soft_spin:.2f} rad/s, towards the report's model "
        "(12.50, contact to 71.8 ms) but short of it. We keep our reading (the stiff "
        "unloading the report gives) and do not tune it.\n",
        lambda soft_ms, soft_spin, **_: soft_ms < 71.8 and soft_spin < 12.50),
    "t10.intro": Text(
        "The report's model lost contact at 71.8 ms with θ̇ = 12.50 rad/s; ours, reading "
        "section 5.2, at {ours_ms:.1f} ms with {ours_spin:.2f}. Section 5.2's spring first "
        "(Figure 17's stiffnesses; the unloading as read, or at 12,000 lb/ft only, the "
        "softest branch it gives), over the impact height S, which the report does not "
        "give:\n"),
    "t10.grid": Text(
        "\nWith Figure 17's stiffnesses no impact height gives both: {near}; the largest θ̇ "
        "on the grid is {top:.2f} rad/s, with the contact lost at {top_ms:.1f} ms.\n",
        lambda top, **_: top < 12.50),
    "t10.grid_near": Text("where the contact lasts 67-77 ms ({cases}) θ̇ is {spins} rad/s"),
    "t10.grid_none": Text("no run keeps the contact for 67-77 ms"),
    "t10.fits": Text(
        "**Two numbers, two unknowns** (fitted to Table 10's model column): one unloading "
        "stiffness for both branches and S, solved for the contact lost at 71.8 ms and θ̇ "
        "12.50: {two_k:,.0f} lb/ft (section 5.2: 38,400 and 12,000) with S {two_s:.2f} ft. "
        "**The whole column** (fitted to it: 8 numbers, 3 unknowns, the same minimum from all "
        "{starts} starts: {agree}): unloading {col_k:,.0f} lb/ft, S {col_s:.2f} ft, the "
        "constant force beyond the stop {plateau:,.0f} lb (section 5.2's curve: 6,300 lb).\n"),
    "t10.closing": Text(
        "\nThe two-number solution reproduces the contact and θ̇ but not the rest (its worst "
        "miss: {worst}): its post leaves faster than the report's. The whole-column fit "
        "misses by {misses}: the report's model column is close to what a spring unloading at "
        "{col_k:,.0f} lb/ft, with a constant force of {plateau:,.0f} lb, struck {col_s:.2f} ft "
        "above the base, gives. These are fits to the report's own numbers, not readings of "
        "its text: section 5.2 gives 38,400 and 12,000 lb/ft for the unloading and the "
        "loading curve's 6,300 lb, and with those no impact height reproduces the column (the "
        "grid above). Friction at the base (the test's base was greased) and the contact law "
        "(the contact ends when the spring's force returns to zero) were not varied.\n"),
    "t9.intro": Text(
        "Start: Table 8's 70 ms column (θ = 25°, θ̇ = 8.75 rad/s, XCM = −1.50, ZCM = +0.01 ft, "
        "V1 = −28.5, V3 = −12.5 ft/s, SV = 3.2 ft) — what the report says it fed its program. "
        "Table 8 has no car speed: ours is taken from our run at 70 ms ({vv:.2f} ft/s) and, "
        "as a check, 40 ft/s. No car outline is checked (the crash car's is not given). HIT, "
        "'the distance from the front end of the vehicle to the point on the vehicle where "
        "the post strikes' (section 5.3), is read as the distance along the car's path from "
        "its front (at the post's axis at the impact, SV behind since) to the post's top P: "
        "XCM + 4.37 sin θ + SV (`hit_ft`; XCM signed as Table 8).\n"),
    "t9.closed_form": Text(
        "\nThe free flight is a closed form in the plane (constant θ̇, parabolic mass centre), "
        "so these numbers follow from Table 8's state alone: from it no program can reach the "
        "report's model XCM 7.61 ft with the sign Table 8 gives (−7.10); the report's (7.61, "
        "0.27) are magnitudes, and even so ours, |XCM| = {x:.2f}, |ZCM| = {z:.2f}, differ from "
        "them by {dx:+.2f} and {dz:+.2f} ft. The start values themselves (θ = 25°, V1 = −28.5, "
        "V3 = −12.5) carry the test's reading error.\n"),
    "t9.hit": Text(
        "HIT by the same reading from the report's own states: its model (θ 121.0°, XCM −7.61, "
        "SV 11.5) gives {model:.2f} ft against its printed 7.55; the test's Table 9 state "
        "(122.0°, −7.10, 11.04) {test9:.2f} against 7.83, and with Table 8's SV 12.60 "
        "{test8:.2f}. The reading reproduces the model's HIT to {model_miss:.2f} ft; the "
        "test's 7.83 it misses by {miss9:+.2f} ft (Table 9's SV) or {miss8:+.2f} ft (Table "
        "8's): unexplained.\n"),
    "fig18.caption": Text(
        "Figure 18 (regenerated): the post (Q to P) in the XX-ZZ plane, our full run every "
        "20 ms (grey; black at 70 and 270 ms), the crash test's two measured instants (Table "
        "8, red), the report's model at 71.8 ms (Table 10, blue dashed) and Table 9's 'model' "
        "column at 273 ms (blue dotted), which is not the same run: the report's program "
        "restarted from the test's 70 ms state (section 5.3), drawn beside our own free "
        "flight from that state at 270 ms (green). The report's Figure 18 shows its model's "
        "whole run, whose 12.50 rad/s makes it overtake the test; the report prints no state "
        "of that run after 71.8 ms, so this figure cannot draw it, and it does not show the "
        "overtaking the report's figure shows.\n"),
    "statements.intro": Text(
        "The statements of Sections 5.4 and 6.2-6.4 (the arm's turn, the car passing under "
        "the post, the effect of the speed and of α, the twin post) are judged in "
        "[report/verdicts.md](report/verdicts.md), each by one computation "
        "(`report.verdicts`, made by `python scripts/make_report_figures.py` with Figures "
        "22-29). Chapter V's statements about the crash test:\n"),
}


#: The source's inconsistencies and what the page took, one a row (the page numbers them).
INCONSISTENCIES = (
    "Table 8 vs Table 9 at the same instant (270 ms): XCM −7.10 vs 7.10, ZCM −0.19 vs 0.19 — "
    "Table 9 prints magnitudes; we take Table 8's signs (the post moves with the car, to −XX).",
    "Table 8 vs Table 9: SV 12.60 vs 11.04 ft at 270 ms. From SV = 3.2 ft at 70 ms, 12.60 "
    "needs 47 ft/s over 200 ms, faster than the car's 40 ft/s at impact; 11.04 needs 39.2 ft/s. "
    "We take 11.04 (Table 9).",
    "Table 8 SV = 3.2 ft at 70 ms is more than 40 ft/s × 70 ms = 2.8 ft, the most a car "
    "slowing from 40 ft/s can travel from the impact: the test's time or distance origin "
    "differs from the model's (the model's 2.80 ft at 71.8 ms is consistent with its own).",
    "Table 9's model SV 11.5 ft at 273 ms needs 41.4 ft/s from Table 8's 3.2 ft at 70 ms, "
    "again faster than the car ever was.",
    "Table 9's model (121.0°, 7.61, 0.27 ft at 273 ms) is not what free flight from Table 8's "
    "70 ms state gives (closed form: θ 126.8°, XCM −7.82, ZCM −0.51 ft at 273 ms); the "
    "report does not print the car speed or any other start value it used.",
    "Table 8 gives θ̇ = 8.75 rad/s at both instants, while θ grows 97° in 200 ms (8.5 rad/s): "
    "consistent with free flight to the reading accuracy.",
    "Section 5.3 calls θ and θ̇ 'the angular displacement and velocity ... of the post mass "
    "center'; they are the post's attitude and rate.",
    "Notation (seed ~line 172) puts XCM, YCM, ZCM along X, Y, Z; section 5.3 along XX, ZZ "
    "(the same for the planar crash test, δ = 0).",
    "Table 10 is headed '70 milliseconds' but the model column is at 71.8 ms; Table 9 "
    "'270 milliseconds' with the model at 273.0 ms.",
    "HIT (Table 9) is defined in section 5.3 with Table 8, but Table 8 has no HIT row.",
    "Section 5.2 gives the leaf spring's two unloading stiffnesses but not where one "
    "takes over from the other (Figure 17 lost); we take 3.0 in.",
    "Chapter VI's 'arm length 10.5 ft' against the report's deck: R is 10.0 ft out and "
    "5.0 ft up (|PR| = 11.18 ft); the aluminium and twin tables imply 10.5 ft out.",
    "Chapter VI's post lengths (30 ft 0 in, 27 ft 9 in) against the tables: |PQ| = 29.50 "
    "and 27.25 ft (both 0.50 ft short); the steel post's 36 ft 8.5 in matches (36.71).",
    "Table 11, aluminium 20 mph 15°: R is inconsistent with the five other columns "
    "(|PR| 11.19 vs 10.80-10.84 ft): a misprint in one of XRL, YRL, ZRL; the section 'Two "
    "doubtful cells' finds which and what each reading does to the comparison.",
    "Table 11, aluminium 0°: YQL printed '00.39' (read 0.39); both readings and the rigid "
    "body's value, and their effect: 'Two doubtful cells'.",
    "Tables 11-12 print the hitting point's height as 0.00 (ZRL, ZPL), while the listing "
    "stops anywhere in a 0.1 ft band; Table 12 aluminium 30° prints ZRL 0.99 with 'HITS "
    "GROUND WITH POINT P' (ZPL 0.00), consistent.",
    "Chapter VI's car: '3200 lb_m' (99.5 slug) against the deck's WV = 100.0 slug.",
    "Table 11, twin 20 mph 15° (line 1759): ZRL 0.08 ft, inside the listing's 0.1 ft ground "
    "band for R, beside 'POST HITS TOP OF CAR': by the listing's own ground test R was on "
    "the ground at the step printed, yet the report names only the car (the twin 20 mph "
    "30° column, with R at 0.0, says 'HITS GROUND WITH POINT R').",
)

#: What the page leaves open.
UNFINISHED = (
    "The shaft's wall is uniform: a wall that thins towards the top, or a transformer base "
    "with its own inertia, might close the +7 %/+17 % inertia misfit; the report does not "
    "give either.",
    "Table 9's HIT is computed by one reading of its definition (the car's front to the "
    "post's top); whether the post strikes the crash car at 270 ms needs the car's outline "
    "(not given).",
    "The aluminium and twin posts use the steel deck's base weight and arm shape, and the "
    "steel deck's car (heights kept above the ground, fenders about the shaft).",
)
