"""Figures 22-29 of the report (Chapter VI), regenerated: which runs each figure shows, the
runs themselves (both engines where both run), and the page that sets each figure beside the
report's own words about it and its Tables 11 and 12 (``docs/report/figures.md``).

The report's pictures are lost in the OCR text; its captions (seed lines 1817-1868) and its
text (lines 1724, 1740-1744) say what each shows.  Our reading of the parts:

* Figures 22 and 23 (one caption each): the terminal position for α = 0°, 15° and 30°, one
  picture with a row per angle;
* Figures 25-28 (three captions each): parts a, b, c are α = 0°, 15°, 30°;
* Figures 24 and 29 (two captions each, "THE TRAJECTORY"): parts a and b are α = 0° and
  30° (the twin post turns only where α ≠ 0, and Figure 29 is cited for that turn).

Which α each part shows is our choice: the report does not say.

The runs: the 18 columns of Tables 11 and 12 as :mod:`.report_full` builds them
(:func:`~report.full.column_inputs`), and any other speed and angle of the three posts
(30 mph, the speed Chapter V's statements name): the steel post is the report's deck
``steel40.dat`` with VVB and ALPHA set by the sweep's rules (as ``deck-emulator sweep``
sets them), the aluminium and twin posts are built the way ``deck-emulator assembly NAME
--speed-mph S --alpha-deg A`` builds them (steel40's car with VVB and ALPHA set).  Each
scene is asked of the engines (the emulator: ``double``, erratum ``ed-direction`` for every
column, as :mod:`.report_full` runs them; the core: the ``legacy`` preset); the twin post
runs on the core only (the listing has no point U).  The runs are few and short (well under
a second each), so they run one after the other in this process: the pictures need the
whole :class:`~deck_emulator.engine.Outcome`, not a row of the scene runner.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from deck_emulator.engine import CoreEngine, EmulatorEngine, Outcome, quantities
from deck_emulator.engine.errata import ED_DIRECTION
from deck_emulator.decks import path as deck_path
from report.full import DELTA_V_CANDIDATES, column_inputs
from report.statements import quote_of
from deck_emulator.studies.report_tables import CASES_ALL, REPORT_ALL, SOURCE

__all__ = ["POSTS", "ANGLES", "Case", "FigurePart", "FIGURES", "case_name", "case_inputs",
           "run_case", "run_cases", "needed_cases", "report_points", "figures_page"]

POSTS = ("aluminium", "steel", "twin")
ANGLES = (0, 15, 30)
POST_WORDS = {"aluminium": "aluminium post", "steel": "steel post",
              "twin": "steel post with twin luminaires"}


def case_name(post: str, mph: float, alpha: float) -> str:
    """``steel40``, ``twin20_a15``, ``aluminium30_a30``: the tables' column names, extended to
    any speed and angle."""
    return f"{post}{mph:g}" + ("" if alpha == 0 else f"_a{alpha:g}")


def case_inputs(post: str, mph: float, alpha: float):
    """(deck or None, scene, how the car was made) of a post at a speed and an angle."""
    name = case_name(post, mph, alpha)
    if name in CASES_ALL:
        deck, scene = column_inputs(name)
        return deck, scene, "the column's deck (report_full)"
    from deck_emulator.core.assembly import load_assembly, mass_properties, scene_runs_on_listing
    from deck_emulator.engine.assemblies import to_deck_text, to_deck_values, to_scene
    from deck_emulator.legacy.deck import parse_deck, read_deck
    from deck_emulator.studies.sweep import car_at, scene_deck
    from deck_emulator.vocabulary.scene import Scene

    if post == "steel":  # the report's own deck, as deck-emulator sweep sets speed and angle
        deck = scene_deck(read_deck(deck_path("steel40")), mph, alpha)
        return deck, Scene.from_deck(deck, name=name), (
            "the report's deck steel40.dat with VVB and ALPHA set by the sweep's rules")
    asm, _, _ = load_assembly(post)
    mp = mass_properties(asm)
    template, car = car_at(mph, alpha)
    scene = to_scene(asm, mp, template=template, **car)
    scene = type(scene)(**{**scene.__dict__, "name": name})
    deck = None
    if scene_runs_on_listing(scene) is None:
        deck = parse_deck(to_deck_text(to_deck_values(asm, mp, template=template, **car)),
                          path=name)
    return deck, scene, (f"{template}'s car" + (", VVB and ALPHA set" if car else "")
                         + " (as deck-emulator assembly does: studies.sweep.car_at)")


@dataclass
class Case:
    """One post at one speed and angle, run on both engines where both run."""

    name: str
    post: str
    mph: float
    alpha: float
    core: Outcome
    emulator: Outcome | None = None
    refusal: str | None = None  # why the listing cannot run it
    car: str = ""
    #: the core with the shaft and the arms checked against the car (``--shaft-contact``,
    #: which the listing never did): the same scene and preset otherwise
    core_shaft: Outcome | None = None

    @property
    def outcomes(self) -> list[Outcome]:
        """The engines' outcomes, the emulator first."""
        return [o for o in (self.emulator, self.core) if o is not None]

    @property
    def in_tables(self) -> bool:
        return self.name in CASES_ALL


def run_case(post: str, mph: float, alpha: float) -> Case:
    """Ask the engines for the post at ``mph`` and ``alpha`` degrees."""
    from deck_emulator.core.assembly import scene_runs_on_listing

    name = case_name(post, mph, alpha)
    deck, scene, car = case_inputs(post, mph, alpha)
    core = CoreEngine(preset="legacy").run(scene, name=name)
    core_shaft = CoreEngine(preset="legacy", shaft_contact=True).run(scene, name=name)
    em = None
    if deck is not None:
        # ed-direction for every column, as report_full runs them: the angled decks need it,
        # and it leaves the 0° printouts byte-identical (legacy/CORRECTIONS.md)
        em = EmulatorEngine(errata=(ED_DIRECTION,)).run(deck, name=name)
    return Case(name, post, mph, alpha, core, em, scene_runs_on_listing(scene), car,
                core_shaft)


@dataclass(frozen=True)
class FigurePart:
    """One picture: a figure of the report (or one part of it)."""

    figure: int
    part: str  # "" or "a", "b", "c"
    kind: str  # "terminal" or "trajectory"
    post: str
    mph: int
    alphas: tuple[int, ...]
    caption: str
    caption_line: int

    @property
    def file(self) -> str:
        return f"figure_{self.figure}{self.part}.png"

    @property
    def cases(self) -> list[str]:
        return [case_name(self.post, self.mph, a) for a in self.alphas]


def _parts(figure, kind, post, mph, caption, lines, alphas_by_part):
    return [FigurePart(figure, part, kind, post, mph, alphas, caption, line)
            for part, alphas, line in zip(("a", "b", "c") if len(alphas_by_part) > 1 else ("",),
                                          alphas_by_part, lines)]


_T = "THE TERMINAL POSITION OF THE "
_J = "THE TRAJECTORY OF THE "
#: Every picture, in the report's order; captions as printed (seed lines 1817-1868).
FIGURES: tuple[FigurePart, ...] = tuple(
    _parts(22, "terminal", "steel", 40, _T + "STEEL SUPPORT POST ASSEMBLY FOR A VEHICLE "
           "VELOCITY OF 40 MPH", (1817,), (ANGLES,))
    + _parts(23, "terminal", "aluminium", 40, _T + "ALUMINUM SUPPORT POST ASSEMBLY FOR A "
             "VEHICLE VELOCITY OF 40 MPH", (1820,), (ANGLES,))
    + _parts(24, "trajectory", "aluminium", 40, _J + "ALUMINUM SUPPORT POST ASSEMBLY FOR A "
             "VEHICLE VELOCITY OF 40 MPH", (1823, 1826), ((0,), (30,)))
    + _parts(25, "terminal", "aluminium", 20, _T + "ALUMINUM SUPPORT POST ASSEMBLY FOR A "
             "VEHICLE VELOCITY OF 20 MPH", (1829, 1832, 1835), ((0,), (15,), (30,)))
    + _parts(26, "terminal", "steel", 20, _T + "STEEL SUPPORT POST ASSEMBLY FOR A VEHICLE "
             "VELOCITY OF 20 MPH", (1838, 1841, 1844), ((0,), (15,), (30,)))
    + _parts(27, "terminal", "twin", 40, _T + "STEEL SUPPORT POST ASSEMBLY WITH TWIN "
             "LUMINAIRES FOR A VEHICLE VELOCITY OF 40 MPH", (1847, 1850, 1853),
             ((0,), (15,), (30,)))
    + _parts(28, "terminal", "twin", 20, _T + "STEEL SUPPORT POST ASSEMBLY WITH TWIN "
             "LUMINAIRES FOR A VEHICLE VELOCITY OF 20 MPH", (1856, 1859, 1862),
             ((0,), (15,), (30,)))
    + _parts(29, "trajectory", "twin", 40, _J + "STEEL SUPPORT POST ASSEMBLY WITH TWIN "
             "LUMINAIRES FOR A VEHICLE VELOCITY OF 40 MPH", (1865, 1868), ((0,), (30,)))
)

#: What the report's text says of the figures (seed line, words as printed).
SAID_OF_ALL = (1724, "Figures 22 through 29 show the posts at various positions for different "
                     "values of the angle α and the vehicular velocity.")
SAID_OF = {24: [quote_of("6.4-1", "6.4-2")], 29: [quote_of("6.4-3", "6.4-4")]}

#: What the text says each figure shows, as the registry reads it in our parts: figure ->
#: (quantity, the sign the text gives it, its words).
SHOWN = {24: ("arm_spin_deg", -1, "a negative rotation about ZL"),
         29: ("arm_spin_deg", +1, "a positive rotation about ZL")}


#: The cases every picture and every verdict needs: the 18 columns, and the three posts at
#: 30 mph (Chapter V names 30 and 40 mph) at every angle.
EXTRA_SPEEDS = (30,)


def needed_cases() -> list[tuple[str, int, int]]:
    """(post, mph, alpha) of every case, the tables' columns first, in their order."""
    cases = [CASES_ALL[c][:3] for c in CASES_ALL]
    cases += [(p, s, a) for s in EXTRA_SPEEDS for p in POSTS for a in ANGLES]
    return cases


def run_cases(cases=None, progress=None) -> dict[str, Case]:
    """name -> :class:`Case` for ``cases`` ((post, mph, alpha) triples; default
    :func:`needed_cases`), one after the other; ``progress(name)`` is called before each."""
    out = {}
    for post, mph, alpha in cases if cases is not None else needed_cases():
        name = case_name(post, mph, alpha)
        if progress is not None:
            progress(name)
        out[name] = run_case(post, mph, alpha)
    return out


def report_points(name: str) -> dict[str, tuple[float, float, float]]:
    """The report's terminal points of a column (Tables 11, 12): P, R, Q and U where printed,
    in XL, YL, ZL (ft); empty for a case the report did not run."""
    if name not in REPORT_ALL:
        return {}
    row = REPORT_ALL[name]
    out = {}
    for p in ("P", "Q", "R", "U"):
        xyz = [row.get(f"{ax}{p}L") for ax in "XYZ"]
        if all(v is not None for v in xyz):
            out[p] = tuple(float(v) for v in xyz)
    return out


def report_end(name: str) -> tuple[str | None, float | None]:
    """The report's COMMENTS and the time of the end (ms) of a column."""
    from deck_emulator.studies.report_tables import report_time_ms_all

    if name not in REPORT_ALL:
        return None, None
    return REPORT_ALL[name]["comment"], report_time_ms_all(name)


# ----------------------------------------------------------------------------- the page

_ROWS = [(f"terminal_{p.lower()}_{ax.lower()}_ft", f"{ax[0]}{p}L") for p in "PRQU"
         for ax in ("XL", "YL", "ZL")]


def _num(v, nd=2) -> str:
    if v is None:
        return "—"
    if round(v, nd) == 0:
        v = 0.0
    return f"{v:.{nd}f}"


def _engine_label(o: Outcome) -> str:
    if o.engine == "emulator":
        return "emulator (listing, " + ("+".join(o.errata) or "as printed") + ")"
    return "core (legacy preset)"


def column_table(case: Case) -> list[str]:
    """The report's numbers of the column beside both engines' (registry quantities)."""
    rep = REPORT_ALL.get(case.name, {})
    outs = case.outcomes
    head = "| | report | " + " | ".join(_engine_label(o) for o in outs) + " |"
    lines = [head, "|---" * (2 + len(outs)) + "|"]
    comment, t_ms = report_end(case.name)
    ends = [o.hit.short() if o.hit else f"no hit ({o.error})" for o in outs]
    lines.append(f"| the end | {comment or '—'} | " + " | ".join(ends) + " |")
    times = [quantities.QUANTITIES["hit_time_s"].show(quantities.value("hit_time_s", o))
             for o in outs]
    lines.append(f"| its time, ms | {_num(t_ms, 1)} | " + " | ".join(times) + " |")
    for qname, label in _ROWS:
        ours = [quantities.value(qname, o) for o in outs]
        theirs = rep.get(label)
        if theirs is None and all(v is None for v in ours):
            continue
        lines.append(f"| {label} (ft) | {_num(theirs)} | "
                     + " | ".join(_num(v) for v in ours) + " |")
    if t_ms is not None and case.core.hit_time_s is not None \
            and t_ms / 1000.0 < case.core.hit_time_s - 1e-3:
        rep_pts = report_points(case.name)
        gaps = []
        for k, xyz in rep_pts.items():
            ours = case.core.point_l(k, t_ms / 1000.0)
            gaps.append(f"{k} {math.dist(ours, xyz):.2f}" if ours is not None else f"{k} —")
        lines.append(f"| the core's post at the report's {_num(t_ms, 1)} ms: distance to the "
                     f"report's points (ft) | — | " + " | ".join(
                         ", ".join(gaps) if o is case.core else "—" for o in outs) + " |")
    for qname in DELTA_V_CANDIDATES + ("max_decel_g",):
        q = quantities.QUANTITIES[qname]
        ours = [q.show(quantities.value(qname, o)) for o in outs]
        theirs = rep.get("delta_v_crush_mph" if qname in DELTA_V_CANDIDATES else qname)
        lines.append(f"| {q.label} ({q.unit}) | {_num(theirs)} | " + " | ".join(ours) + " |")
    return lines


def shown_note(number: int, cases: dict) -> str:
    """What our parts of figure ``number`` show of what the text says it shows
    (:data:`SHOWN`), read from the registry on the core: '' for a figure the text says
    nothing particular of."""
    if number not in SHOWN:
        return ""
    name = SHOWN[number][0]
    got = [(f"{number}{p.part}", c, quantities.value(name, cases[c].core))
           for p in FIGURES if p.figure == number for c in p.cases]
    return shown_words(number, got)


def shown_words(number: int, got: list) -> str:
    """:func:`shown_note`'s words for ``got`` ((part, case, value) of each part): each part
    judged on the value the page displays (the quantity's digits), so a part shown as 0.0°
    is said to show no rotation, whatever the sign of the unrounded value. The spin is the
    registry's, tracked over the run: its sign is the sense the arm turned, however far."""
    name, sign, words = SHOWN[number]
    q = quantities.QUANTITIES[name]

    def show(v):  # no '-0.0'
        return q.show(0.0 if v is not None and float(q.show(v)) == 0.0 else v)

    shown = [(fig, c, v, None if v is None else float(show(v))) for fig, c, v in got]
    cells = ", ".join(f"{fig} (`{c}`) {show(v)}°" for fig, c, v, _ in shown)
    zero = [fig for fig, _, _, d in shown if d == 0.0]
    other = [fig for fig, _, _, d in shown if d is None or d * sign < 0]

    def parts(figs):
        return f"Part{'s' if len(figs) > 1 else ''} {', '.join(figs)}"

    verdict = []
    if zero:
        verdict.append(f"{parts(zero)} show{'' if len(zero) > 1 else 's'} no rotation (zero at "
                       f"the page's {q.digits} decimal{'s' if q.digits != 1 else ''})")
    if other:
        verdict.append(f"{parts(other)} do{'' if len(other) > 1 else 'es'} not show {words}")
    return (f"What our parts show of it (`{name}`, the {q.label}, tracked over the run's "
            f"samples from t = 0; core): {cells}. "
            + ("; ".join(verdict) + ": the regenerated figure does not show there what the "
               "report says its figure shows"
               + (" (at α = 0° the twin post is symmetric about the car's path and has no "
                  "reason to turn)" if number == 29 and zero else "") + "."
               if verdict else f"Each shows {words}."))


def figures_page(cases: dict[str, Case], command: str) -> str:
    """``docs/report/figures.md``: each figure (its pictures) beside the report's caption, what
    its text says of it, and the column's numbers (report, emulator, core)."""
    out = ["# Figures 22-29 of the report, regenerated\n",
           f"Made by `{command}` (every picture and this page, with "
           "[verdicts.md](verdicts.md)). The report's numbers: "
           f"`deck_emulator.studies.report_tables` ({SOURCE}). The report's pictures are lost "
           "in the OCR text; each caption below is quoted with its line in the OCR text, then "
           "what the text says of the figure, our picture, and the column's numbers: the "
           "report's, the emulator's (the 1967 listing, where it can carry the post) and the "
           "core's, each read from the registry of quantities (`engine/quantities.py`).\n",
           "How to read the pictures: plan view XL-YL (left) and side view XL-ZL (right), in "
           "the report's axes (ft; origin on the ground under the base of the support; the car "
           "drives towards -XL; the arm reaches out over the highway along -YL, so +YL is away "
           "from the highway). Each engine's post at the hit is drawn through its points "
           "(base Q, top P, luminaire end R, second luminaire U), in the engine's colour; the "
           "report's terminal points (Tables 11, 12) are black crosses joined by a dashed line; "
           "the post at t = 0 is grey; the car's outline is the core's at its hit. Where the "
           "report's run ended before ours, the core's post at the report's time of its end "
           "is drawn dash-dotted in the core's colour, and the column's table says how far it "
           "then is from the report's points (for the steel post at 20 mph, where the report "
           "ended on the shaft meeting the car's front, a test the listing as printed does not "
           "make, this is where the report's post was).\n",
           "What the pictures rest on (fitted inputs said beside every number they touch): "
           "the steel columns are the report's own decks (`decks/steel*.dat`), nothing fitted; "
           "the aluminium and twin posts are the assembly builder's "
           "(`assemblies/aluminium.toml`, `twin.toml`), whose |PQ| and arm rise were fitted "
           "to these tables' own terminal coordinates, with the base weight and arm shape of "
           "the builder's calibration on the steel deck and the steel deck's car carried over "
           "(docs/report_full.md, 'Provenance'). The split of the figures into parts (which α "
           "each part shows) is ours: the report does not say.\n",
           "The report's one ΔV ('DECREASE IN VEHICLE VELOCITY') is defined nowhere in it; "
           "each column's table sets it beside the registry's three readings of it (crush "
           "pulse, first spring, whole contact: docs/report_full.md, 'ΔV and the maximum "
           "deceleration', says which fits which post; none fits all).\n",
           "Where the report's 20 mph run ends on the car, the post at the end of the runs "
           "without the shaft test (the listing's point tests) lies through the car's outline; "
           "the core's run with the shaft test (`--shaft-contact`, docs/shaft_contact.md) is "
           "drawn beside them, dotted, ending where its shaft meets the car.\n",
           f"Line {SAID_OF_ALL[0]}: \"{SAID_OF_ALL[1]}\"\n"]
    by_figure: dict[int, list[FigurePart]] = {}
    for part in FIGURES:
        by_figure.setdefault(part.figure, []).append(part)
    for number, parts in by_figure.items():
        first = parts[0]
        out.append(f"## Figure {number}: {first.caption.lower()}\n")
        out.append("Caption (line" + ("s " if len(parts) > 1 else " ")
                   + ", ".join(str(p.caption_line) for p in parts) + f"): \"FIGURE {number} "
                   f"{first.caption}\"" + (f", printed on {len(parts)} pages (parts "
                                           + ", ".join(p.part for p in parts) + ")"
                                           if len(parts) > 1 else "") + ".\n")
        for line, words in SAID_OF.get(number, []):
            out.append(f"What the text says of it (line{'s' if '-' in line else ''} {line}): "
                       f"\"{words}\" These words are checked in [verdicts.md](verdicts.md) "
                       "(Section 6.4).\n")
        if shown_note(number, cases):
            out.append(shown_note(number, cases) + "\n")
        if number not in SAID_OF:
            out.append("The text says nothing of this figure beyond line "
                       f"{SAID_OF_ALL[0]}.\n")
        for part in parts:
            names = part.cases
            what = ("the post at the hit" if part.kind == "terminal"
                    else "the post every 100 ms and the paths of its points")
            alphas = ", ".join(f"{a}°" for a in part.alphas)
            out.append(f"### Figure {number}{part.part}: {POST_WORDS[part.post]}, "
                       f"{part.mph} mph, α = {alphas}: {what}\n")
            out.append(f"![Figure {number}{part.part}]({part.file})\n")
            for name in names:
                case = cases[name]
                how = (" the report's own deck." if case.post == "steel"
                       else f" fitted: |PQ| and the arm rise were read off Tables 11 and 12's "
                            f"terminal coordinates (`assemblies/{case.post}.toml`); every "
                            "number of ours below rests on that fit.")
                out.append(f"`{name}` (Table {CASES_ALL[name][3]}):" + how
                           + (f" The emulator cannot run it: {case.refusal}." if case.refusal
                              else "") + "\n")
                out += column_table(case)
                out.append("")
    return "\n".join(out) + "\n"
