"""The report's statements of Sections 5.4 and 6.2-6.4, each checked by a computation, with a
verdict: holds, does not hold, or cannot be checked (and why) -- ``docs/report/verdicts.md``.

Every statement is quoted with its line in the OCR text of the report.  Every number comes
from the runs of :mod:`.report_figures` (the 18 columns of Tables 11 and 12 and the three
posts at 30 mph, both engines where both run) through the registry of quantities
(:mod:`deck_emulator.engine.quantities`), or from the report's own Tables 11 and 12
(:mod:`.report_tables`) read by the same definitions (:mod:`deck_emulator.engine.attitude`).
A verdict is given on each source that can carry it: the report's own numbers, the emulator,
the core.  The rules that turn the numbers into a verdict are functions of this module
(:func:`tally`, :func:`increasing`, :func:`significant`), tested on hand-made cases.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from deck_emulator.engine import attitude, quantities
from deck_emulator.engine.safety import CRITERIA
from report.figures import ANGLES, POSTS, Case, _num, case_name
from deck_emulator.studies.report_tables import REPORT_ALL, SOURCE

__all__ = ["Verdict", "HOLDS", "FAILS", "CANNOT", "tally", "increasing", "significant",
           "verdicts", "verdicts_page", "SIGNIFICANT_FRACTION"]

HOLDS = "holds"
FAILS = "does not hold"
CANNOT = "cannot be checked"

#: "Not significantly": our reading, since the report gives none: a change smaller than this
#: fraction of the post's length |PQ|.
SIGNIFICANT_FRACTION = 0.10

SOURCES = ("report", "emulator", "core")


@dataclass
class Verdict:
    """One statement: ``section``, ``lines`` (of the OCR text), ``quote``; ``how`` (the runs
    and the quantities); ``table`` (markdown lines of the numbers); ``on``: source
    (report, emulator, core) -> verdict; ``verdict`` overall and ``why``."""

    key: str
    section: str
    lines: str
    quote: str
    how: str
    table: list[str] = field(default_factory=list)
    on: dict[str, str] = field(default_factory=dict)
    verdict: str = CANNOT
    why: str = ""


# --------------------------------------------------------------------------- the rules


def tally(flags) -> str:
    """:data:`HOLDS` when every flag is True, :data:`FAILS` when any is False;
    :data:`CANNOT` when there is none (None entries are left out: a value the source lacks)."""
    flags = [f for f in flags if f is not None]
    if not flags:
        return CANNOT
    return HOLDS if all(flags) else FAILS


def increasing(values) -> bool | None:
    """True when ``values`` rise strictly from each to the next, False when not; None when any
    is missing."""
    if any(v is None for v in values):
        return None
    return all(b > a for a, b in zip(values, values[1:]))


def significant(change_ft: float | None, length_ft: float) -> bool | None:
    """Whether a change (ft) is significant: at least :data:`SIGNIFICANT_FRACTION` of the
    post's length."""
    if change_ft is None:
        return None
    return change_ft >= SIGNIFICANT_FRACTION * length_ft


def overall(on: dict[str, str]) -> str:
    """One verdict from the sources': the same word where they agree, else each named."""
    known = {k: v for k, v in on.items() if v != CANNOT}
    if not known:
        return CANNOT
    words = set(known.values())
    if len(words) == 1:
        return words.pop()
    return "; ".join(f"{v} on the {k}'s numbers" if k == "report" else f"{v} on the {k}"
                     for k, v in known.items())


# --------------------------------------------------------------------------- reading runs


def _q(case: Case | None, engine: str, name: str):
    if case is None:
        return None
    o = case.emulator if engine == "emulator" else case.core
    return None if o is None else quantities.value(name, o)


def _out(case: Case | None, engine: str):
    if case is None:
        return None
    return case.emulator if engine == "emulator" else case.core


def _end(case, engine) -> str:
    o = _out(case, engine)
    if o is None:
        return "—"
    return o.hit.short() if o.hit else "no hit"


def _hits_car(case, engine) -> bool | None:
    o = _out(case, engine)
    if o is None or o.hit is None:
        return None
    return o.hit.surface.value != "ground"


#: The mark of a run whose post was fitted to the report's tables (the aluminium and twin
#: posts' geometries were read off Tables 11 and 12's terminal coordinates).
FITTED_MARK = "†"


def _tag(label: str, post: str) -> str:
    return label if post == "steel" else f"{label} {FITTED_MARK}"


def _show(name: str, v) -> str:
    return quantities.QUANTITIES[name].show(v)


_f = _num  # a number as the figures' page shows it (one rule: report_figures._num)


def _rep(name: str, fld: str):
    return REPORT_ALL.get(name, {}).get(fld)


def _report_point(name: str, p: str):
    xyz = [_rep(name, f"{ax}{p}L") for ax in "XYZ"]
    return None if any(v is None for v in xyz) else tuple(xyz)


def _report_spin(case: Case) -> float | None:
    """The arm's spin read off the report's own P, Q, R (Tables 11, 12), from our t = 0."""
    now = [_report_point(case.name, p) for p in "PQR"]
    start = [attitude.start_l(case.core, p) for p in "PQR"]
    if any(v is None for v in now + start):
        return None
    return attitude.spin_deg(*now, *start)


def _length_ft(case: Case) -> float:
    p, q = attitude.start_l(case.core, "P"), attitude.start_l(case.core, "Q")
    return math.dist(p, q)


def _engines(case: Case | None) -> list[str]:
    if case is None:
        return []
    return [e for e in ("emulator", "core") if _out(case, e) is not None]


def _cases(cases, posts=POSTS, speeds=(20, 40), angles=ANGLES) -> list[Case]:
    out = []
    for mph in speeds:
        for post in posts:
            for a in angles:
                c = cases.get(case_name(post, mph, a))
                if c is not None:
                    out.append(c)
    return out


# ----------------------------------------------------------------------- the statements


def _s54_1(cases) -> Verdict:
    v = Verdict("5.4-1", "5.4 (1)", "1692",
                "The luminaire support arm rotates clockwise when the post is struck by the "
                "vehicle in the manner described in Chapter III.",
                "every run of the single-arm posts (steel, aluminium) at 20, 30 and 40 mph and "
                "α = 0°, 15°, 30°: `arm_spin_release_deg` (the post's spin about its own axis "
                "from t = 0 to the moment the car lets go; for the upright post the rotation "
                "about ZL, clockwise seen from above is negative). Clockwise is read as seen "
                "from above (the report's ZL points up; Section 6.4 says the same arm turns "
                "negatively about ZL). The twin post is shown, not judged (two arms).")
    v.table = ["| run | emulator, deg | core, deg |", "|---|---|---|"]
    flags = {"emulator": [], "core": []}
    for c in _cases(cases, speeds=(20, 30, 40)):
        vals = {e: _q(c, e, "arm_spin_release_deg") for e in ("emulator", "core")}
        v.table.append(f"| {_tag(c.name, c.post)} | {_f(vals['emulator'], 1)} | "
                       f"{_f(vals['core'], 1)} |")
        if c.post != "twin":
            for e in flags:
                flags[e].append(None if vals[e] is None else vals[e] < 0)
    v.on = {"report": CANNOT, **{e: tally(f) for e, f in flags.items()}}
    v.verdict = overall(v.on)
    neg = {e: (sum(x is True for x in f), sum(x is not None for x in f)) for e, f in flags.items()}
    v.why = (f"single-arm runs turning clockwise by the time the car lets go: emulator "
             f"{neg['emulator'][0]} of {neg['emulator'][1]}, core {neg['core'][0]} of "
             f"{neg['core'][1]}. The report prints no attitude at the end of the contact, so its "
             "own numbers cannot carry this check.")
    return v


def _clears(c, e) -> bool | None:
    """The car passes under the post: the run ends on the ground, and no segment of the post
    (shaft and arms) is ever inside the car's outline in free flight."""
    o = _out(c, e)
    if o is None or o.hit is None:
        return None
    body = quantities.value("body_clearance_ft", o)
    return o.hit.surface.value == "ground" and (body is None or body >= 0.0)


def _s54_2(cases) -> Verdict:
    v = Verdict("5.4-2", "5.4 (2)", "1693",
                "For vehicular speeds of 30 miles/hr and 40 miles/hr, the vehicle is seen to "
                "pass under the post and not be struck by the post on its return path to the "
                "ground.",
                "every post at 30 and 40 mph, α = 0°, 15°, 30°: the run's end (the engine's hit "
                "event: ground or a part of the car) and `body_clearance_ft` (the least height "
                "of the post's segments Q-P, P-R, P-U above the car's outline in free flight; "
                "negative: the shaft or an arm passes through the car, which the listing's "
                "tests of points P, R, C, U do not see). A run holds when it ends on the "
                "ground and the clearance is not negative.")
    v.table = ["| run | report's end | emulator: end, clearance ft | core: end, clearance ft |",
               "|---|---|---|---|"]
    flags = {"report": [], "emulator": [], "core": []}
    for c in _cases(cases, speeds=(30, 40)):
        cells = []
        for e in ("emulator", "core"):
            o = _out(c, e)
            if o is None:
                cells.append("—")
                continue
            cells.append(f"{_end(c, e)}, {_show('body_clearance_ft', _q(c, e, 'body_clearance_ft'))}")
            flags[e].append(_clears(c, e))
        rep = _rep(c.name, "comment")
        if rep is not None:
            flags["report"].append("GROUND" in rep)
        v.table.append(f"| {_tag(c.name, c.post)} | {rep or 'not run'} | {cells[0]} | {cells[1]} |")
    v.on = {k: tally(f) for k, f in flags.items()}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"runs in which the car passes under: report {n['report'][0]} of {n['report'][1]} "
             f"(40 mph only: it printed no 30 mph run), emulator {n['emulator'][0]} of "
             f"{n['emulator'][1]}, core {n['core'][0]} of {n['core'][1]}.")
    return v


def _s54_3(cases) -> Verdict:
    v = Verdict("5.4-3", "5.4 (3)", "1694-1696",
                "The rotation of the support arm for the vehicular speeds mentioned previously "
                "is large enough so that the luminaire comes to rest at the edge of the highway "
                "and therefore does not cause an unsafe condition for other motorists.",
                "every post at 30 and 40 mph: `terminal_r_yl_ft` (YL of the luminaire end R at "
                "the hit; +YL away from the highway), `luminaire_yl_shift_ft` (how far R has "
                "moved across the road since t = 0, where it reached 10 to 10.5 ft out over the "
                "highway) and, for the twin post, `terminal_u_yl_ft`.")
    v.table = ["| run | report YRL | emulator YRL, moved | core YRL, moved | core YUL |",
               "|---|---|---|---|---|"]
    ys, twin = [], []
    for c in _cases(cases, speeds=(30, 40)):
        cells = []
        for e in ("emulator", "core"):
            y, m = _q(c, e, "terminal_r_yl_ft"), _q(c, e, "luminaire_yl_shift_ft")
            cells.append("—" if y is None else f"{_f(y)}, {_f(m, 2)}")
            if y is not None:
                (twin if c.post == "twin" else ys).append(y)
        u = _q(c, "core", "terminal_u_yl_ft")
        v.table.append(f"| {_tag(c.name, c.post)} | {_f(_rep(c.name, 'YRL'))} | {cells[0]} | {cells[1]} | "
                       f"{_f(u)} |")
    v.on = {s: CANNOT for s in SOURCES}
    v.verdict = CANNOT
    v.why = ("the report places no edge of the highway (no lateral position of the post from "
             "the pavement is given), and every run ends at the post's first hit: where the "
             "luminaire comes to rest after it is not computed by the listing or the core. What "
             f"is computed: the single arm's R lands between YL = {min(ys):.2f} and {max(ys):.2f} ft, "
             f"so the statement would hold if the pavement ended at YL ≤ {min(ys):.2f} ft (the "
             f"base at least {-min(ys):.1f} ft from it), and fail otherwise; the twin post's R "
             f"lands as far out as YL = {min(twin):.2f} ft.")
    return v


def _s54_4(cases) -> Verdict:
    v = Verdict("5.4-4", "5.4 (4)", "1698",
                "Variations of up to 15 degrees in the angle Alpha do not significantly affect "
                "the trajectory of the luminaire support assembly for the speeds considered.",
                "each post at 30 and 40 mph, α = 0° against α = 15°: the largest distance "
                "between the two runs' paths of the luminaire end R and of the mass centre at "
                "the same instants (`engine.attitude.largest_distance_ft`, over the time both "
                "ran), and the distance between their terminal points P, Q, R (`terminal_*_ft`). "
                f"'Significant' is our reading (the report gives none): at least "
                f"{100 * SIGNIFICANT_FRACTION:.0f} % of the post's length |PQ|. The report's "
                "own Table 12 (40 mph) is read the same way.")
    v.table = ["| post, speed | |PQ| ft | source | path of R, ft | path of CM, ft | "
               "end of P, Q, R moved, ft |", "|---|---|---|---|---|---|"]
    flags = {"report": [], "emulator": [], "core": []}
    largest = {k: (0.0, "") for k in flags}

    def note(src, ends, where):
        for p, d in zip("PQR", ends):
            if d is not None and d > largest[src][0]:
                largest[src] = (d, f"{p} of {where}")

    for mph in (30, 40):
        for post in POSTS:
            a = cases.get(case_name(post, mph, 0))
            b = cases.get(case_name(post, mph, 15))
            if a is None or b is None:
                continue
            length = _length_ft(a)
            for e in _engines(a):
                oa, ob = _out(a, e), _out(b, e)
                if ob is None:
                    continue
                dr = attitude.largest_distance_ft(oa, ob, "R")
                dcm = attitude.largest_distance_ft(oa, ob, "CM")
                ends = [_dist(_end_point(oa, p), _end_point(ob, p)) for p in "PQR"]
                note(e, ends, f"{post} {mph} mph")
                flags[e].append(not any(significant(d, length) for d in ends + [dr]
                                        if d is not None))
                v.table.append(f"| {_tag(f'{post} {mph} mph', post)} | {length:.2f} | {e} | {_f(dr)} | "
                               f"{_f(dcm)} | " + ", ".join(_f(d) for d in ends) + " |")
            if a.name in REPORT_ALL and b.name in REPORT_ALL:
                ends = [_dist(_report_point(a.name, p), _report_point(b.name, p)) for p in "PQR"]
                note("report", ends, f"{post} {mph} mph")
                flags["report"].append(not any(significant(d, length) for d in ends
                                               if d is not None))
                v.table.append(f"| {_tag(f'{post} {mph} mph', post)} | {length:.2f} | report | — | — | "
                               + ", ".join(_f(d) for d in ends) + " |")
    v.on = {k: tally(f) for k, f in flags.items()}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"cases where α = 15° changes nothing significantly: report {n['report'][0]} of "
             f"{n['report'][1]}, emulator {n['emulator'][0]} of {n['emulator'][1]}, core "
             f"{n['core'][0]} of {n['core'][1]}. The largest move of a terminal point: "
             + "; ".join(f"{k} {d:.1f} ft ({w})" for k, (d, w) in largest.items() if w) + ".")
    return v


def _end_point(o, p):
    return attitude.point_at_end_l(o, p)


def _dist(a, b):
    return None if a is None or b is None else math.dist(a, b)


def _s62_1(cases) -> Verdict:
    v = Verdict("6.2-1", "6.2", "1728",
                "The reader may observe from Table 11 that for a vehicular velocity of 20 miles "
                "per hour the support post, with one exception, strikes the vehicle before "
                "striking the ground.",
                "the nine 20 mph columns: the run's end (hit event: the car or the ground) on "
                "the emulator and the core, which test the points P, R, C, U against the car as "
                "the listing does, with `body_clearance_ft` (< 0: the post's shaft or arm "
                "passes through the car's outline, which those tests do not see); and the core "
                "with the shaft test (`--shaft-contact`: the shaft Q-P and the arms checked as "
                "segments against the car, docs/shaft_contact.md). The statement holds for a "
                "source when exactly 8 of 9 runs strike the car first.")
    shaft = "core with the shaft test"
    v.table = ["| column | report | emulator: end, clearance ft | core: end, clearance ft | "
               "core with the shaft test: end |", "|---|---|---|---|---|"]
    count = {"report": 0, "emulator": 0, "core": 0, shaft: 0}
    through = {"emulator": 0, "core": 0}
    ran = {"report": 0, "emulator": 0, "core": 0, shaft: 0}
    for c in _cases(cases, speeds=(20,)):
        rep = _rep(c.name, "comment")
        ran["report"] += 1
        count["report"] += "CAR" in rep
        cells = []
        for e in ("emulator", "core"):
            o = _out(c, e)
            if o is None:
                cells.append("—")
                continue
            ran[e] += 1
            count[e] += bool(_hits_car(c, e))
            body = _q(c, e, "body_clearance_ft")
            through[e] += body is not None and body < 0
            cells.append(f"{_end(c, e)}, {_show('body_clearance_ft', body)}")
        o = c.core_shaft
        if o is not None and o.hit is not None:
            ran[shaft] += 1
            count[shaft] += o.hit.surface.value != "ground"
        cells.append("—" if o is None else o.hit.short() if o.hit else "no hit")
        v.table.append(f"| {_tag(c.name, c.post)} | {rep} | {' | '.join(cells)} |")
    v.on = {k: (HOLDS if count[k] == ran[k] - 1 else FAILS) if ran[k] else CANNOT
            for k in count}
    v.verdict = overall(v.on)
    v.why = (f"runs that strike the car: report {count['report']} of {ran['report']}; "
             f"emulator {count['emulator']} of {ran['emulator']}, core {count['core']} of "
             f"{ran['core']} (points only); core with the shaft test {count[shaft]} of "
             f"{ran[shaft]}. Counting a shaft or arm that passes through the car's outline as a "
             f"strike: emulator {through['emulator']}, core {through['core']} runs do. The "
             "report ends its 20 mph runs on the shaft meeting the car (its words: 'front of "
             "car', 'top of car'), a test the listing as printed does not have; with that test "
             "the core strikes the car in every column, the report's one exception (twin 30°, "
             "R on the ground) included.")
    return v


def _s62_2(cases) -> Verdict:
    v = Verdict("6.2-2", "6.2", "1728",
                "Table 12 shows that for a vehicular velocity of 40 miles per hour the support "
                "assembly clears the vehicle in all cases.",
                "the nine 40 mph columns: the run's end and `body_clearance_ft` (as for 5.4 (2)).")
    v.table = ["| column | report | emulator: end, clearance ft | core: end, clearance ft |",
               "|---|---|---|---|"]
    flags = {"report": [], "emulator": [], "core": []}
    for c in _cases(cases, speeds=(40,)):
        rep = _rep(c.name, "comment")
        flags["report"].append("GROUND" in rep)
        cells = []
        for e in ("emulator", "core"):
            o = _out(c, e)
            if o is None:
                cells.append("—")
                continue
            flags[e].append(_clears(c, e))
            cells.append(f"{_end(c, e)}, {_show('body_clearance_ft', _q(c, e, 'body_clearance_ft'))}")
        v.table.append(f"| {_tag(c.name, c.post)} | {rep} | {cells[0]} | {cells[1]} |")
    v.on = {k: tally(f) for k, f in flags.items()}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"runs that clear the car: report {n['report'][0]} of {n['report'][1]}, emulator "
             f"{n['emulator'][0]} of {n['emulator'][1]}, core {n['core'][0]} of {n['core'][1]}.")
    return v


def _s62_3(cases) -> Verdict:
    v = Verdict("6.2-3", "6.2", "1730",
                "The overall behavior of the support post assembly for the two vehicular "
                "velocities considered is very similar.",
                "none: the report names no measure of similarity.")
    v.on = {s: CANNOT for s in SOURCES}
    v.verdict = CANNOT
    v.why = ("'very similar' names no quantity and no tolerance; the other statements of this "
             "page compare the two speeds on named quantities (the end, the arm's spin, the "
             "terminal points).")
    return v


def _s62_4(cases) -> Verdict:
    v = Verdict("6.2-4", "6.2", "1730",
                "In the case of a vehicular velocity of 20 miles per hour the slower moving "
                "vehicle imparts less energy to the support assembly and causes it to encounter "
                "the vehicle before striking the ground.",
                "each post and α at 20, 30 and 40 mph: `launch_ke_ftlb` (the post's kinetic "
                "energy, translation and rotation, when the car lets go). The energy part holds "
                "when it rises with the speed in every series; the causal part ('causes it to "
                "encounter the vehicle') is not a computation: see 6.2 (line 1728) for what the "
                "20 mph runs hit.")
    v.table = ["| post, α | engine | 20 mph | 30 mph | 40 mph |", "|---|---|---|---|---|"]
    flags = {"emulator": [], "core": []}
    for post in POSTS:
        for a in ANGLES:
            series = [cases.get(case_name(post, s, a)) for s in (20, 30, 40)]
            for e in ("emulator", "core"):
                vals = [_q(c, e, "launch_ke_ftlb") for c in series]
                if all(x is None for x in vals):
                    continue
                flags[e].append(increasing(vals))
                v.table.append(f"| {_tag(post, post)}, {a}° | {e} | "
                               + " | ".join(_show("launch_ke_ftlb", x) for x in vals) + " |")
    v.on = {"report": CANNOT, **{e: tally(f) for e, f in flags.items()}}
    v.verdict = overall(v.on)
    v.why = ("the energy the car imparts (ft·lb) rises with the speed in every series of "
             "both engines" if v.verdict == HOLDS else
             "the energy the car imparts does not rise with the speed in every series") + \
        ("; the report prints no energy, and the causal part cannot be checked by a run.")
    return v


def _trend(cases, post, mph, qname, engine):
    return [_q(cases.get(case_name(post, mph, a)), engine, qname) for a in ANGLES]


def _s63_1(cases) -> Verdict:
    v = Verdict("6.3-1", "6.3", "1734",
                "The study showed that an increase in the vehicular approach angle α caused the "
                "support post assembly to have a smaller absolute terminal coordinate in the XL "
                "direction and a larger one in the YL direction. [...] This conclusion is "
                "obtained by assuming that the post does not first encounter the vehicle and the "
                "terminal coordinates are taken as the coordinates describing the position of "
                "the assembly when it strikes the ground.",
                "each post at 40 mph (every column ends on the ground in Table 12) and 30 mph, "
                "for each of its points P, Q, R (U): `terminal_{p}_xl_ft`, `terminal_{p}_yl_ft` "
                "at α = 0°, 15°, 30°. A series holds when |XL| falls and YL rises from each "
                "angle to the next; the report's own Table 12 is read the same way.")
    v.table = ["| post, speed, point | source | XL at 0°, 15°, 30° | YL at 0°, 15°, 30° | "
               "holds |", "|---|---|---|---|---|"]
    flags = {"report": [], "emulator": [], "core": []}
    for mph in (40, 30):
        for post in POSTS:
            for p in ("P", "Q", "R", "U"):
                if p == "U" and post != "twin":
                    continue
                rows = []
                if mph == 40:
                    xs = [_rep(case_name(post, mph, a), f"X{p}L") for a in ANGLES]
                    ys = [_rep(case_name(post, mph, a), f"Y{p}L") for a in ANGLES]
                    rows.append(("report", xs, ys))
                for e in ("emulator", "core"):
                    xs = _trend(cases, post, mph, f"terminal_{p.lower()}_xl_ft", e)
                    ys = _trend(cases, post, mph, f"terminal_{p.lower()}_yl_ft", e)
                    if all(x is None for x in xs):
                        continue
                    rows.append((e, xs, ys))
                for src, xs, ys in rows:
                    ok_x = increasing([-abs(x) if x is not None else None for x in xs])
                    ok_y = increasing(ys)
                    ok = None if ok_x is None or ok_y is None else ok_x and ok_y
                    flags[src].append(ok)
                    v.table.append(f"| {_tag(f'{post} {mph} mph', post)}, {p} | {src} | "
                                   + ", ".join(_f(x) for x in xs) + " | "
                                   + ", ".join(_f(y) for y in ys) + " | "
                                   + ("yes" if ok else "no") + " |")
    v.on = {k: tally(f) for k, f in flags.items()}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"series (post, speed, point) that follow the statement: report {n['report'][0]} "
             f"of {n['report'][1]}, emulator {n['emulator'][0]} of {n['emulator'][1]}, core "
             f"{n['core'][0]} of {n['core'][1]}. The statement does not say which point; read "
             "for every point, the report's own Table 12 does not bear it out.")
    return v


def _s63_2(cases) -> Verdict:
    v = Verdict("6.3-2", "6.3", "1734",
                "This fact gives the assembly a tendency to fall more in the direction away from "
                "the highway as the angle α is increased.",
                "each post at 30 and 40 mph: `terminal_cm_yl_ft` (YL of the post's mass centre "
                "at the hit) at α = 0°, 15°, 30°: holds when it rises with α. The report prints "
                "no mass centre; its YQL and YPL are in 6.3 (line 1734) above.")
    v.table = ["| post, speed | engine | mass centre YL at 0°, 15°, 30° (ft) |", "|---|---|---|"]
    flags = {"emulator": [], "core": []}
    for mph in (30, 40):
        for post in POSTS:
            for e in ("emulator", "core"):
                ys = _trend(cases, post, mph, "terminal_cm_yl_ft", e)
                if all(y is None for y in ys):
                    continue
                flags[e].append(increasing(ys))
                v.table.append(f"| {_tag(f'{post} {mph} mph', post)} | {e} | " + ", ".join(_f(y) for y in ys)
                               + " |")
    v.on = {"report": CANNOT, **{e: tally(f) for e, f in flags.items()}}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"series in which the mass centre lands further from the highway as α grows: "
             f"emulator {n['emulator'][0]} of {n['emulator'][1]}, core {n['core'][0]} of "
             f"{n['core'][1]}.")
    return v


def _s64_1(cases) -> Verdict:
    v = Verdict("6.4-1", "6.4", "1740",
                "From the values presented for point R in Tables 11 and 12 and from Figure 24, "
                "it is clear that regardless of the vehicular speed, type of post used, or "
                "vehicular approach angle, the tendency is for the single luminaire support arm "
                "to have a negative rotation (according to the right hand rule) about the ZL "
                "axis.",
                "the 12 single-arm columns (and the single-arm posts at 30 mph): `arm_spin_deg` "
                "(the post's spin about its own axis from t = 0 to the hit, read from P, Q, R), "
                "and the same definition (`engine.attitude.spin_deg`) applied to the report's own "
                "terminal P, Q, R with our t = 0 points. For a post lying on the ground 'about "
                "ZL' needs a reading: the spin about the post's own axis is the rotation about "
                "ZL while the post stands; the report gives none.")
    v.table = ["| run | report's points, deg | emulator, deg | core, deg |", "|---|---|---|---|"]
    flags = {"report": [], "emulator": [], "core": []}
    for c in _cases(cases, posts=("aluminium", "steel"), speeds=(20, 30, 40)):
        rep = _report_spin(c) if c.in_tables else None
        if c.in_tables:
            flags["report"].append(None if rep is None else rep < 0)
        vals = {e: _q(c, e, "arm_spin_deg") for e in ("emulator", "core")}
        for e in vals:
            flags[e].append(None if vals[e] is None else vals[e] < 0)
        v.table.append(f"| {_tag(c.name, c.post)} | {_f(rep, 1)} | {_f(vals['emulator'], 1)} "
                       f"| {_f(vals['core'], 1)} |")
    v.on = {k: tally(f) for k, f in flags.items()}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"negative spins at the end: report's own points {n['report'][0]} of "
             f"{n['report'][1]}, emulator {n['emulator'][0]} of {n['emulator'][1]}, core "
             f"{n['core'][0]} of {n['core'][1]}. While the car holds the post the arm turns "
             "clockwise (5.4 (1), line 1692, above); read at the hit, from the terminal points, "
             "the spin has either sign, in the report's own numbers too.")
    return v


def _s64_2(cases) -> Verdict:
    v = Verdict("6.4-2", "6.4", "1740",
                "This rotation causes the support arm to rotate in a direction away from the "
                "highway after the post is impacted and not strike the highway causing an unsafe "
                "condition for other motorists.",
                "the 12 single-arm columns and the single-arm posts at 30 mph: "
                "`luminaire_yl_shift_ft` (YL of R at the hit less its YL at t = 0: positive is "
                "away from the highway); the report's YRL less our t = 0 YL of R.")
    v.table = ["| run | report, ft | emulator, ft | core, ft |", "|---|---|---|---|"]
    flags = {"report": [], "emulator": [], "core": []}
    for c in _cases(cases, posts=("aluminium", "steel"), speeds=(20, 30, 40)):
        r0 = attitude.start_l(c.core, "R")
        rep = _rep(c.name, "YRL")
        rep_shift = None if rep is None or r0 is None else rep - r0[1]
        if c.in_tables:
            flags["report"].append(None if rep_shift is None else rep_shift > 0)
        vals = {e: _q(c, e, "luminaire_yl_shift_ft") for e in ("emulator", "core")}
        for e in vals:
            flags[e].append(None if vals[e] is None else vals[e] > 0)
        v.table.append(f"| {_tag(c.name, c.post)} | {_f(rep_shift)} | {_f(vals['emulator'])} | "
                       f"{_f(vals['core'])} |")
    v.on = {k: tally(f) for k, f in flags.items()}
    v.verdict = overall(v.on)
    v.why = ("the luminaire end moves away from the highway in every run" if v.verdict == HOLDS
             else "the luminaire end does not move away from the highway in every run") + \
        ("; whether it then strikes the highway cannot be checked: the report places no edge "
         "of the pavement (see 5.4 (3)).")
    return v


def _s64_3(cases) -> Verdict:
    v = Verdict("6.4-3", "6.4", "1742",
                "The case involving the support post with twin luminaires shows that here the "
                "tendency is for the rotation to be positive about the ZL axis. This is shown "
                "in Figure 29.",
                "the twin post at α = 15° and 30° (at α = 0° the twin post is symmetric about "
                "the car's path and has no reason to turn), 20, 30 and 40 mph: `arm_spin_deg`, "
                "and the same definition on the report's own terminal P, Q, R. The twin post "
                "runs on the core only (the listing has no point U).")
    v.table = ["| run | report's points, deg | core, deg |", "|---|---|---|"]
    flags = {"report": [], "core": []}
    for c in _cases(cases, posts=("twin",), speeds=(20, 30, 40), angles=(15, 30)):
        rep = _report_spin(c) if c.in_tables else None
        if c.in_tables:
            flags["report"].append(None if rep is None else rep > 0)
        val = _q(c, "core", "arm_spin_deg")
        flags["core"].append(None if val is None else val > 0)
        v.table.append(f"| {_tag(c.name, c.post)} | {_f(rep, 1)} | {_f(val, 1)} |")
    v.on = {"report": tally(flags["report"]), "emulator": CANNOT, "core": tally(flags["core"])}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"positive spins: report's own points {n['report'][0]} of {n['report'][1]}, core "
             f"{n['core'][0]} of {n['core'][1]}.")
    return v


def _s64_4(cases) -> Verdict:
    v = Verdict("6.4-4", "6.4", "1742-1744",
                "A positive rotation causes point U to displace towards the highway but for the "
                "cases investigated this effect always causes the striking point to increase in "
                "the direction away from the assumed edge of the pavement.",
                "the twin post at α = 15° and 30°, 20, 30 and 40 mph: "
                "`second_luminaire_yl_shift_ft` (YL of U at the hit less its YL at t = 0; "
                "negative is towards the highway); the report's YUL less our t = 0 YL of U. The "
                "second half ('the striking point ... away from the assumed edge') cannot be "
                "checked: the report never gives the edge it assumed.")
    v.table = ["| run | report, ft | core, ft |", "|---|---|---|"]
    flags = {"report": [], "core": []}
    for c in _cases(cases, posts=("twin",), speeds=(20, 30, 40), angles=(15, 30)):
        u0 = attitude.start_l(c.core, "U")
        rep = _rep(c.name, "YUL")
        rep_shift = None if rep is None or u0 is None else rep - u0[1]
        if c.in_tables:
            flags["report"].append(None if rep_shift is None else rep_shift < 0)
        val = _q(c, "core", "second_luminaire_yl_shift_ft")
        flags["core"].append(None if val is None else val < 0)
        v.table.append(f"| {_tag(c.name, c.post)} | {_f(rep_shift)} | {_f(val)} |")
    v.on = {"report": tally(flags["report"]), "emulator": CANNOT, "core": tally(flags["core"])}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"U moves towards the highway: report's own numbers {n['report'][0]} of "
             f"{n['report'][1]}, core {n['core'][0]} of {n['core'][1]} (the first half); the "
             "second half cannot be checked (no edge of the pavement is given).")
    return v


def _s64_5(cases) -> Verdict:
    v = Verdict("6.4-5", "6.4", "1744",
                "Tables 11 and 12 reveal that for these cases, the point R is the first to "
                "contact the ground.",
                "the twin post's runs that end on the ground (20, 30, 40 mph, every α): the hit "
                "event's point. 'R&U' (both in the listing's 0.1 ft ground band at one step) "
                "counts as R first, as the report's own 'POINTS R&U' does.")
    v.table = ["| run | report | core |", "|---|---|---|"]
    flags = {"report": [], "core": []}
    for c in _cases(cases, posts=("twin",), speeds=(20, 30, 40)):
        rep = _rep(c.name, "comment")
        if rep is not None and "GROUND" in rep:
            flags["report"].append("POINT R" in rep or "POINTS R" in rep)
        o = c.core
        if o.hit is not None and o.hit.surface.value == "ground":
            flags["core"].append(o.hit.point in ("R", "R&U"))
        v.table.append(f"| {_tag(c.name, c.post)} | {rep or 'not run'} | {_end(c, 'core')} |")
    v.on = {"report": tally(flags["report"]), "emulator": CANNOT, "core": tally(flags["core"])}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"ground hits led by R: report {n['report'][0]} of {n['report'][1]}, core "
             f"{n['core'][0]} of {n['core'][1]}.")
    return v


def _s64_6(cases) -> Verdict:
    v = Verdict("6.4-6", "6.4", "1744",
                "As the vehicle approach angle is increased, the terminal position of the point "
                "R increases in the direction away from the highway. The same effect had been "
                "noticed in the case of the single luminaire support assembly.",
                "each post at 20, 30 and 40 mph: `terminal_r_yl_ft` at α = 0°, 15°, 30°: holds "
                "when it rises with α; the report's YRL likewise.")
    v.table = ["| post, speed | source | YRL at 0°, 15°, 30° (ft) | holds |", "|---|---|---|---|"]
    flags = {"report": [], "emulator": [], "core": []}
    for mph in (20, 30, 40):
        for post in POSTS:
            rows = []
            if mph != 30:
                rows.append(("report", [_rep(case_name(post, mph, a), "YRL") for a in ANGLES]))
            for e in ("emulator", "core"):
                ys = _trend(cases, post, mph, "terminal_r_yl_ft", e)
                if not all(y is None for y in ys):
                    rows.append((e, ys))
            for src, ys in rows:
                ok = increasing(ys)
                flags[src].append(ok)
                v.table.append(f"| {_tag(f'{post} {mph} mph', post)} | {src} | " + ", ".join(_f(y) for y in ys)
                               + f" | {'yes' if ok else 'no'} |")
    v.on = {k: tally(f) for k, f in flags.items()}
    v.verdict = overall(v.on)
    n = {k: (sum(x is True for x in f), sum(x is not None for x in f)) for k, f in flags.items()}
    v.why = (f"series in which R lands further from the highway as α grows: report "
             f"{n['report'][0]} of {n['report'][1]}, emulator {n['emulator'][0]} of "
             f"{n['emulator'][1]}, core {n['core'][0]} of {n['core'][1]}.")
    return v


def _s64_7(cases) -> Verdict:
    oiv, ora = CRITERIA["nchrp350_oiv"], CRITERIA["nchrp350_ora"]
    v = Verdict("6.4-7", "6.4", "1746",
                "The values of the maximum vehicle deceleration presented in Tables 11 and 12 "
                "show that in all the cases considered the impact forces are kept within "
                "tolerable limits.",
                "every run (20, 30, 40 mph): `max_decel_g` (the report's maximum vehicle "
                "deceleration), judged by the only limits this project can cite (the report "
                f"names none): `oiv_m_s` against {oiv.source} ({oiv.label()}) and `ora_g` "
                f"against {ora.source} ({ora.label()}), a standard of 1993 the report could "
                "not know. The report's own decelerations are set beside them.")
    flags = {"report": [], "emulator": [], "core": []}
    worst = {k: {"max_decel_g": None, "oiv_m_s": None, "ora_g": None} for k in flags}
    for c in _cases(cases, speeds=(20, 30, 40)):
        rep = _rep(c.name, "max_decel_g")
        if rep is not None:
            w = worst["report"]["max_decel_g"]
            worst["report"]["max_decel_g"] = rep if w is None else max(w, rep)
        for e in ("emulator", "core"):
            o = _out(c, e)
            if o is None:
                continue
            vals = quantities.values(o, ("max_decel_g", "oiv_m_s", "ora_g"))
            for k, x in vals.items():
                if x is not None:
                    w = worst[e][k]
                    worst[e][k] = x if w is None else max(w, x)
            if vals["oiv_m_s"] is not None:
                flags[e].append(vals["oiv_m_s"] <= oiv.maximum
                                and (vals["ora_g"] is None or vals["ora_g"] <= ora.maximum))
    v.table = ["| source | largest `max_decel_g`, g | largest `oiv_m_s`, m/s | largest `ora_g`, g |",
               "|---|---|---|---|"]
    for k in ("report", "emulator", "core"):
        w = worst[k]
        v.table.append(f"| {k} | {_f(w['max_decel_g'])} | {_f(w['oiv_m_s'])} | "
                       f"{_f(w['ora_g'])} |")
    v.on = {"report": CANNOT, **{e: tally(flags[e]) for e in ("emulator", "core")}}
    v.verdict = overall(v.on)
    v.why = ("every run's occupant impact velocity and ridedown acceleration are inside NCHRP "
             "Report 350's limits" if v.verdict == HOLDS else
             "some run exceeds NCHRP Report 350's limits") + \
        ("; 'tolerable' is the report's word without a number: the report's own "
         f"decelerations ({_f(worst['report']['max_decel_g'])} g at most) cannot be judged "
         "without one.")
    return v


CHECKS = (_s54_1, _s54_2, _s54_3, _s54_4, _s62_1, _s62_2, _s62_3, _s62_4, _s63_1, _s63_2,
          _s64_1, _s64_2, _s64_3, _s64_4, _s64_5, _s64_6, _s64_7)


def verdicts(cases: dict[str, Case]) -> list[Verdict]:
    """Every statement of Sections 5.4 and 6.2-6.4, checked on the runs ``cases``
    (:func:`report.figures.run_cases`)."""
    return [check(cases) for check in CHECKS]


def verdicts_page(vs: list[Verdict], command: str) -> str:
    """``docs/report/verdicts.md``."""
    out = ["# The report's statements of Sections 5.4 and 6.2-6.4, with verdicts\n",
           f"Made by `{command}` (with [figures.md](figures.md)). Each statement is quoted "
           "with its line in the OCR text of the report; the computation names its runs and "
           "the quantities it reads from the registry (`engine/quantities.py`; `deck-emulator "
           "summary --help` and docs/json.md define them). The runs: the 18 columns of Tables "
           "11 and 12 as docs/report_full.md builds them, and the three posts at 30 mph built "
           "as `deck-emulator assembly NAME core --speed-mph 30 [--alpha-deg A]` builds them "
           "(steel40's car with VVB and ALPHA set); the emulator runs the listing (`double`, "
           "erratum `ed-direction`) where it can carry the post (not the twin post: no point "
           "U), the core its `legacy` preset. The report's own numbers: "
           f"`deck_emulator.studies.report_tables` ({SOURCE}).\n",
           "Fitted to the report (beside every number below): the steel runs re-run the "
           "report's own deck; the aluminium and twin geometries were read off Tables 11 and "
           "12's own terminal coordinates, with the steel deck's base, arm shape and car; the "
           f"30 mph runs use steel40's car. In the tables, {FITTED_MARK} marks the runs of "
           "the aluminium and twin posts (geometry fitted to the tables). The axes are the "
           "report's XL, YL, ZL (origin on the ground under the base; the car drives to -XL; "
           "the arm reaches over the highway along -YL, so +YL is away from the highway).\n",
           "## Verdicts\n", "| # | section, line | statement | report's numbers | emulator | "
           "core | verdict |", "|---|---|---|---|---|---|---|"]
    for i, v in enumerate(vs, 1):
        short = v.quote if len(v.quote) <= 110 else v.quote[:107].rsplit(" ", 1)[0] + " ..."
        where = f"line{'s' if '-' in v.lines else ''} {v.lines}"
        core = v.on.get("core", CANNOT)
        if "core with the shaft test" in v.on:
            core += f" (with the shaft test: {v.on['core with the shaft test']})"
        out.append(f"| {i} | {v.section}, {where} | {short} | {v.on.get('report', CANNOT)}"
                   f" | {v.on.get('emulator', CANNOT)} | {core} | **{v.verdict}** |")
    out.append("")
    for i, v in enumerate(vs, 1):
        out.append(f"## {i}. Section {v.section}, line{'s' if '-' in v.lines else ''} "
                   f"{v.lines}\n")
        out.append(f"> {v.quote}\n")
        out.append(f"**Computation.** {v.how[:1].upper() + v.how[1:]}\n")
        if v.table:
            out += v.table
            out.append("")
        out.append(f"**Verdict: {v.verdict}.** {v.why[:1].upper() + v.why[1:]}\n")
    return "\n".join(out) + "\n"
