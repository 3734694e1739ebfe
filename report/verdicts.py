"""The report's statements of Sections 5.4 and 6.2-6.4, each checked by its rule, with a
verdict: holds, does not hold, or cannot be checked (and why) -- ``docs/report/verdicts.md``.

The statements are rows of :data:`report.statements.STATEMENTS` (quote, line of the OCR text,
quantities, rule, prose templates); this module holds the rules (:data:`RULES`) that turn the
runs of :mod:`report.figures` (the 18 columns of Tables 11 and 12 and the three posts at
30 mph, both engines where both run) into a table and a verdict, every value read through the
registry of quantities (:mod:`deck_emulator.engine.quantities`), and the report's own Tables
11 and 12 read by the same definitions (:data:`REPORT_READING`). The rules' building blocks
(:func:`tally`, :func:`increasing`, :func:`significant`) are tested on hand-made cases.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from deck_emulator.engine import attitude, quantities
from deck_emulator.engine.safety import CRITERIA
from deck_emulator.studies.report_tables import REPORT_ALL, SOURCE, report_time_ms_all
from deck_emulator.vocabulary.defaults import LISTING_GROUND_TOLERANCE_FT
from report.figures import ANGLES, POSTS, Case, _num as _f, case_name
from report.statements import STATEMENTS, Statement

__all__ = ["Verdict", "HOLDS", "FAILS", "CANNOT", "UNDECIDED", "tally", "increasing",
           "significant", "verdicts", "verdicts_page", "SIGNIFICANT_FRACTION", "RULES",
           "report_mass_centre"]

HOLDS = "holds"
FAILS = "does not hold"
CANNOT = "cannot be checked"
#: the runs cannot tell: the deciding difference is smaller than the run's own miss
UNDECIDED = "undecided"

#: "Not significantly": our reading, since the report gives none: a change smaller than this
#: fraction of the post's length |PQ|.
SIGNIFICANT_FRACTION = 0.10

ENGINES = ("emulator", "core")
SOURCES = ("report",) + ENGINES
SHAFT = "core with the shaft test"

#: The mark of a run whose post was fitted to the report's tables (the aluminium and twin
#: posts' |PQ| and arm rise were read off Tables 11 and 12's terminal coordinates).
FITTED_MARK = "†"


@dataclass
class Verdict:
    """One statement checked: its row (:class:`~report.statements.Statement`), ``how`` and
    ``why`` (its templates filled), ``table`` (markdown lines of the numbers), ``on``: source
    (report, emulator, core ...) -> verdict, and ``verdict`` overall."""

    statement: Statement
    how: str
    why: str
    table: list[str] = field(default_factory=list)
    on: dict[str, str] = field(default_factory=dict)
    verdict: str = CANNOT

    def __getattr__(self, name):  # key, section, lines, quote: the statement's
        st = self.__dict__.get("statement")
        if st is None:
            raise AttributeError(name)
        return st.line if name == "lines" else getattr(st, name)


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


def counted(flags: dict[str, list]) -> str:
    """'report 3 of 6, emulator 2 of 4, core 5 of 6': the True flags of each source that has
    any (None entries left out)."""
    parts = []
    for k, f in flags.items():
        known = [x for x in f if x is not None]
        if known:
            parts.append(f"{k} {sum(known)} of {len(known)}")
    return ", ".join(parts) or "none"


# --------------------------------------------------------------------------- reading runs


def _out(case: Case | None, engine: str):
    if case is None:
        return None
    return {"emulator": case.emulator, "core": case.core, SHAFT: case.core_shaft}[engine]


def _q(case: Case | None, engine: str, name: str):
    o = _out(case, engine)
    return None if o is None else quantities.value(name, o)


def _end(case, engine) -> str:
    o = _out(case, engine)
    if o is None:
        return "—"
    return o.hit.short() if o.hit else "no hit"


def _on_car(o) -> bool | None:
    return None if o is None or o.hit is None else o.hit.surface.value != "ground"


def _tag(label: str, post: str) -> str:
    return label if post == "steel" else f"{label} {FITTED_MARK}"


def _show(name: str, v) -> str:
    return quantities.QUANTITIES[name].show(v)


def _rep(name: str, fld: str):
    return REPORT_ALL.get(name, {}).get(fld)


def _report_point(name: str, p: str):
    xyz = [_rep(name, f"{ax}{p}L") for ax in "XYZ"]
    return None if any(v is None for v in xyz) else tuple(xyz)


def _rigid_fit(start, now):
    """(rotation, start centroid, now centroid) of the rigid motion that takes the points
    ``start`` closest to ``now`` (least squares, Kabsch)."""
    a, b = np.asarray(start, dtype=float), np.asarray(now, dtype=float)
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((a - ca).T @ (b - cb))
    d = np.sign(np.linalg.det(vt.T @ u.T))
    return vt.T @ np.diag([1.0, 1.0, d]) @ u.T, ca, cb


def report_mass_centre(case: Case):
    """The report's mass centre at the end, (XL, YL, ZL) and the fit's largest misfit (ft):
    our t = 0 P, Q, R and mass centre carried by the rigid motion that brings P, Q, R closest
    to the report's terminal P, Q, R; None where the report printed no such column."""
    now = [_report_point(case.name, p) for p in "PQR"]
    start = [attitude.start_l(case.core, p) for p in ("P", "Q", "R", "CM")]
    if any(v is None for v in now + start):
        return None
    rot, ca, cb = _rigid_fit(start[:3], now)
    moved = [rot @ (np.asarray(p) - ca) + cb for p in start]
    misfit = max(math.dist(m, n) for m, n in zip(moved[:3], now))
    return tuple(float(x) for x in moved[3]), misfit


def _report_spin(case: Case):
    now = [_report_point(case.name, p) for p in "PQR"]
    start = [attitude.start_l(case.core, p) for p in "PQR"]
    if any(v is None for v in now + start):
        return None
    return attitude.spin_deg(*now, *start)


def _report_shift(case: Case, p: str):
    y, y0 = _rep(case.name, f"Y{p}L"), attitude.start_l(case.core, p)
    return None if y is None or y0 is None else y - y0[1]


def _report_cm_yl(case: Case):
    got = report_mass_centre(case)
    return None if got is None else got[0][1]


#: The report's own numbers read by the registry's definitions (quantity -> case -> value),
#: for the columns it printed.
REPORT_READING = {
    "arm_spin_deg": _report_spin,
    "luminaire_yl_shift_ft": lambda c: _report_shift(c, "R"),
    "second_luminaire_yl_shift_ft": lambda c: _report_shift(c, "U"),
    "terminal_cm_yl_ft": _report_cm_yl,
    **{f"terminal_{p.lower()}_{ax.lower()}l_ft": (lambda c, p=p, ax=ax: _rep(c.name, f"{ax}{p}L"))
       for p in "PQRU" for ax in "XYZ"},
}


def _report_value(case: Case | None, name: str):
    if case is None or not case.in_tables or name not in REPORT_READING:
        return None
    return REPORT_READING[name](case)


def _length_ft(case: Case) -> float:
    return math.dist(attitude.start_l(case.core, "P"), attitude.start_l(case.core, "Q"))


def _cases(cases, runs: dict) -> list[Case]:
    out = []
    for mph in runs.get("speeds", (20, 30, 40)):
        for post in runs.get("posts", POSTS):
            for a in runs.get("angles", ANGLES):
                c = cases.get(case_name(post, mph, a))
                if c is not None:
                    out.append(c)
    return out


def _series(cases, runs: dict):
    """(label, post, [case at each step]) of each series ``runs["along"]`` ("alpha": α =
    0°, 15°, 30° at each speed; "speed": 20, 30, 40 mph at each α)."""
    if runs["along"] == "alpha":
        for mph in runs["speeds"]:
            for post in runs["posts"]:
                yield f"{post} {mph} mph", post, [cases.get(case_name(post, mph, a))
                                                  for a in ANGLES]
    else:
        for post in runs["posts"]:
            for a in ANGLES:
                yield f"{post}, {a}°", post, [cases.get(case_name(post, s, a))
                                              for s in runs["speeds"]]


def _flags() -> dict[str, list]:
    return {k: [] for k in SOURCES}


#: The registry's spins tracked over a run (quantity -> the instant it is read at,
#: :func:`deck_emulator.engine.attitude.arm_spin_track`): the report's tables print the end
#: attitude only, which fixes a spin modulo 360 deg, so the report's own numbers cannot carry
#: their sign.
TRACKED_SPINS = {"arm_spin_deg": "end", "arm_spin_release_deg": "release"}


def on_branch(wrapped: float | None, near: float | None) -> float | None:
    """The value of an angle known modulo 360 deg (``wrapped``) nearest ``near``."""
    if wrapped is None or near is None:
        return None
    return wrapped + 360.0 * round((near - wrapped) / 360.0)


def _sign(st, cases):
    """Every run's value of the one quantity has the sign ``runs["sign"]`` (the report's own
    numbers read the same way where it has a reading). A tracked spin (:data:`TRACKED_SPINS`)
    is judged on the engines' tracks; the report's end attitude is shown, and on the branch
    of the core's tracked spin of the same column, but not judged: its sense is not in it."""
    name, sign = st.quantity[0], st.runs["sign"]
    judged = st.runs.get("judged", st.runs["posts"])
    tracked = name in TRACKED_SPINS
    head = ("report's points: end attitude (on the core's branch)" if tracked
            else "report's points")
    table = [f"| run | {head} | emulator | core |", "|---|---|---|---|"]
    flags = _flags()
    branch = []  # the report's spin on the core's branch, judged runs
    worst, steps, swings = None, [], []  # the tracks' least favourable value, what they rest on
    nd = quantities.QUANTITIES[name].digits
    for c in _cases(cases, st.runs):
        vals = {"report": _report_value(c, name),
                **{e: _q(c, e, name) for e in ENGINES}}
        cells = [_f(vals[k], nd) for k in SOURCES]
        if tracked and vals["report"] is not None:
            b = on_branch(vals["report"], vals["core"])
            cells[0] += f" ({_f(b, nd)})"
            if c.post in judged and b is not None:
                branch.append(b * sign > 0)
        table.append(f"| {_tag(c.name, c.post)} | " + " | ".join(cells) + " |")
        if c.post in judged:
            for k, v in vals.items():
                if k != "report" or (c.in_tables and not tracked):
                    flags[k].append(None if v is None else v * sign > 0)
            if tracked:
                for e in ENGINES:
                    o = _out(c, e)
                    tr = None if o is None else attitude.arm_spin_track(o, TRACKED_SPINS[name])
                    if tr is None:
                        continue
                    least = float((tr["spin_deg"] * sign).min()) * sign  # least favourable
                    worst = least if worst is None or least * sign < worst * sign else worst
                    steps.append(tr["largest_step_deg"])
                    swings.append(tr["largest_swing_deg"])
    on = {k: tally(f) for k, f in flags.items()}
    figures = {"counts": counted(flags), "report_note": ""}
    if tracked:
        if branch:
            figures["report_note"] = (
                " The report's tables print the end attitude only, which fixes the spin modulo "
                "360°: its own numbers cannot say which way the arm turned, and are not "
                "judged. Read on the branch of the core's tracked spin of the same column "
                f"(in brackets), {sum(branch)} of {len(branch)} have the sign; the branch is "
                "the core's, not the report's.")
        if steps:
            worst = 0.0 if round(worst, 2) == 0 else worst  # no '-0.00'
            figures["report_note"] += (
                " The tracked spin, at every sample of every run judged, stays "
                f"{'at or below' if sign < 0 else 'at or above'} {worst:+.2f}° (the arm "
                "never turns the other way by more than that); the largest step between two "
                f"samples is {max(steps):.2f}° and the "
                f"post's axis swings at most {max(swings):.1f}° from its start (the tracking "
                "holds while a step is well under a half turn and the swing under 180°).")
    return table, on, figures


def _end_cells(c, flags, judge) -> list[str]:
    """'end, clearance' of each engine's run of ``c`` ('—' where it did not run); each run's
    ``judge(outcome, clearance)`` appended to ``flags[engine]``."""
    cells = []
    for e in ENGINES:
        o = _out(c, e)
        if o is None:
            cells.append("—")
            continue
        body = _q(c, e, "body_clearance_ft")
        cells.append(f"{_end(c, e)}, {_show('body_clearance_ft', body)}")
        flags[e].append(judge(o, body))
    return cells


def _clears(st, cases):
    """The car passes under: the run ends on the ground and no segment of the post is ever
    inside the car's outline in free flight; the least clearance and how many runs clear by
    less than the listing's band are figures of the verdict."""
    band = LISTING_GROUND_TOLERANCE_FT["P"]
    table = ["| run | report's end | emulator: end, clearance ft | core: end, clearance ft |",
             "|---|---|---|---|"]
    flags = _flags()
    margins = []
    def judge(o, body):
        ok = None if o.hit is None else (not _on_car(o) and (body is None or body >= 0.0))
        if ok and body is not None:
            margins.append(body)
        return ok

    for c in _cases(cases, st.runs):
        cells = _end_cells(c, flags, judge)
        rep = _rep(c.name, "comment")
        if rep is not None:
            flags["report"].append("GROUND" in rep)
        table.append(f"| {_tag(c.name, c.post)} | {rep or 'not run'} | {cells[0]} | {cells[1]} |")
    on = {k: tally(f) for k, f in flags.items()}
    return table, on, {"counts": counted(flags), "band": f"{band:.1f}",
                       "least": f"{min(margins):.3f}" if margins else "—",
                       "inside": f"{sum(m < band for m in margins)} of {len(margins)}"}


def _edge(st, cases):
    table = ["| run | report YRL | emulator YRL, moved | core YRL, moved | core YUL |",
             "|---|---|---|---|---|"]
    ys, twin = [], []
    for c in _cases(cases, st.runs):
        cells = []
        for e in ENGINES:
            y, m = _q(c, e, "terminal_r_yl_ft"), _q(c, e, "luminaire_yl_shift_ft")
            cells.append("—" if y is None else f"{_f(y)}, {_f(m)}")
            if y is not None:
                (twin if c.post == "twin" else ys).append(y)
        table.append(f"| {_tag(c.name, c.post)} | {_f(_rep(c.name, 'YRL'))} | {cells[0]} | "
                     f"{cells[1]} | {_f(_q(c, 'core', 'terminal_u_yl_ft'))} |")
    return table, {s: CANNOT for s in SOURCES}, {
        "lo": f"{min(ys):.2f}", "hi": f"{max(ys):.2f}", "gap": f"{-min(ys):.1f}",
        "twin": f"{min(twin):.2f}"}


def _dist(a, b):
    return None if a is None or b is None else math.dist(a, b)


def _alpha_change(st, cases):
    table = ["| post, speed | |PQ| ft | source | path of R, ft | path of CM, ft | "
             "end of P, Q, R moved, ft |", "|---|---|---|---|---|---|"]
    flags = _flags()
    largest = {k: (0.0, "") for k in flags}
    for mph in st.runs["speeds"]:
        for post in st.runs["posts"]:
            a, b = cases.get(case_name(post, mph, 0)), cases.get(case_name(post, mph, 15))
            if a is None or b is None:
                continue
            length = _length_ft(a)
            rows = [(e, _out(a, e), _out(b, e)) for e in ENGINES]
            if a.in_tables and b.in_tables:
                rows.append(("report", None, None))
            for src, oa, ob in rows:
                if src != "report" and (oa is None or ob is None):
                    continue
                if src == "report":
                    ends = [_dist(_report_point(a.name, p), _report_point(b.name, p))
                            for p in "PQR"]
                    paths = []
                else:
                    ends = [_dist(attitude.point_at_end_l(oa, p), attitude.point_at_end_l(ob, p))
                            for p in "PQR"]
                    paths = [attitude.largest_distance_ft(oa, ob, k) for k in ("R", "CM")]
                for p, d in zip("PQR", ends):
                    if d is not None and d > largest[src][0]:
                        largest[src] = (d, f"{p} of {post} {mph} mph")
                flags[src].append(not any(significant(d, length) for d in ends + paths[:1]
                                          if d is not None))
                table.append(f"| {_tag(f'{post} {mph} mph', post)} | {length:.2f} | {src} | "
                             + (" | ".join(_f(d) for d in paths) if paths else "— | —")
                             + " | " + ", ".join(_f(d) for d in ends) + " |")
    return table, {k: tally(f) for k, f in flags.items()}, {
        "counts": counted(flags), "fraction": f"{100 * SIGNIFICANT_FRACTION:.0f}",
        "largest": "; ".join(f"{k} {d:.1f} ft ({w})" for k, (d, w) in largest.items() if w)}


def _one_exception(st, cases):
    """Exactly one of the 20 mph runs ends on the ground; with the shaft test, a strike that
    comes less before the run's ground hit than the column misses the report's end by cannot
    decide the order of the two."""
    table = ["| column | report | emulator: end, clearance ft | core: end, clearance ft | "
             "core with the shaft test: end, ms before the ground hit (column's end miss, ms) |",
             "|---|---|---|---|---|"]
    flags = {"report": [], "emulator": [], "core": [], SHAFT: []}
    through = {e: 0 for e in ENGINES}
    undecided = []
    for c in _cases(cases, st.runs):
        rep = _rep(c.name, "comment")
        flags["report"].append("CAR" in rep)
        cells = _end_cells(c, flags, lambda o, body: bool(_on_car(o)))
        for e in ENGINES:
            body = _q(c, e, "body_clearance_ft")
            through[e] += body is not None and body < 0
        o, off = c.core_shaft, c.core
        cell = "—" if o is None else _end(c, SHAFT)
        if o is not None and o.hit is not None:
            flags[SHAFT].append(bool(_on_car(o)))
            rt = report_time_ms_all(c.name)
            if _on_car(o) and "GROUND" in rep and not _on_car(off) and rt \
                    and off.hit_time_s is not None:  # the shaft test against the report
                lead = 1000 * (off.hit_time_s - o.hit_time_s)
                miss = 1000 * off.hit_time_s - rt
                cell += f", {lead:.1f} ({miss:+.1f})"
                if lead < abs(miss):
                    undecided.append((c.name, lead, miss))
        table.append(f"| {_tag(c.name, c.post)} | {rep} | {' | '.join(cells)} | {cell} |")
    on = {}
    for k, f in flags.items():
        n, hit = len(f), sum(f)
        on[k] = CANNOT if not n else HOLDS if hit == n - 1 else FAILS
    n, hit = len(flags[SHAFT]), sum(flags[SHAFT])
    if on[SHAFT] == FAILS and hit - len(undecided) <= n - 1 <= hit:  # either way: 8 of 9
        on[SHAFT] = UNDECIDED
    if undecided:
        words = "; ".join(f"{n}'s strike comes {lead:.1f} ms before R lands, in a column whose "
                          f"end misses the report's by {miss:+.1f} ms" for n, lead, miss in undecided)
        und = (f"the one more than the report's 8 is undecided: {words}. Which end comes "
               "first there is within the column's own miss, so the runs cannot say whether "
               "that column is the report's exception.")
    else:
        und = "no strike is closer to its ground hit than the column's own miss."
    return table, on, {"counts": counted(flags), "through_emulator": through["emulator"],
                       "through_core": through["core"],
                       "shaft_n": f"{sum(flags[SHAFT])} of {len(flags[SHAFT])}",
                       "undecided": und}


def _cannot(st, cases):
    return [], {s: CANNOT for s in SOURCES}, {}


def _both(*parts: str) -> str:
    """A statement of several parts holds on a source only where every part does; it fails
    where any part fails; else it cannot be checked there."""
    if FAILS in parts:
        return FAILS
    if all(p == HOLDS for p in parts):
        return HOLDS
    return CANNOT


def _energy(st, cases):
    """Two parts: the energy rises with the speed (every engine's runs), and it goes with
    striking the car (the core with the shaft test only: the emulator and the core without it
    test only points against the car, and their 20 mph runs pass through its outline, so they
    cannot read the second part). The statement holds on a source where both parts do."""
    table = ["| post, α | engine | 20 mph | 30 mph | 40 mph |", "|---|---|---|---|---|"]
    flags = {e: [] for e in ENGINES + (SHAFT,)}
    for label, post, series in _series(cases, st.runs):
        for e in ENGINES + (SHAFT,):
            vals = [_q(c, e, "launch_ke_ftlb") for c in series]
            if all(x is None for x in vals):
                continue
            flags[e].append(increasing(vals))
            table.append(f"| {_tag(label, post)} | {e} | "
                         + " | ".join(_show("launch_ke_ftlb", x) for x in vals) + " |")
    first = {e: tally(f) for e, f in flags.items()}
    parts, separated = [], []
    for post in st.runs["posts"]:
        got = {True: [], False: []}
        for c in _cases(cases, {**st.runs, "posts": (post,)}):
            ke, car = _q(c, SHAFT, "launch_ke_ftlb"), _on_car(c.core_shaft)
            if ke is not None and car is not None:
                got[car].append(ke)
        if got[True] and got[False]:
            ok = max(got[True]) < min(got[False])
            separated.append(ok)
            parts.append(f"{post}: the runs that strike the car {min(got[True]):.0f}-"
                         f"{max(got[True]):.0f} ft·lb, those that clear it "
                         f"{min(got[False]):.0f}-{max(got[False]):.0f}")
    second = {"emulator": CANNOT, "core": CANNOT, SHAFT: tally(separated)}
    table += ["", "| post | the core with the shaft test: launch energy of the runs that strike "
              "the car / clear it |", "|---|---|"] + [
        f"| {p.split(':')[0]} | {p.split(': ', 1)[1]} |" for p in parts]
    table += ["", "| source | first part: the energy rises with the speed | second part: it goes "
              "with striking the car | the statement |", "|---|---|---|---|"]
    on = {"report": CANNOT}
    for e in ENGINES + (SHAFT,):
        on[e] = _both(first[e], second[e])
        table.append(f"| {e} | {first[e]} | {second[e]} | {on[e]} |")
    rises = [e for e in first if first[e] == HOLDS]
    return table, on, {
        "first": ("the first part holds on every source that runs: the energy the car imparts "
                  "(ft·lb) rises with the speed in every series of the emulator, the core and "
                  "the core with the shaft test") if len(rises) == len(first) else (
                 "the first part: the energy rises with the speed in every series on "
                 + (", ".join(rises) or "no source") + " only"),
        "second": ("The second part, as far as runs read it (the core with the shaft test): "
                   + ("the launch energy separates the ends in every post" if
                      second[SHAFT] == HOLDS
                      else "the launch energy does not separate the ends in every post")
                   + " (" + "; ".join(parts) + "): less energy goes with striking the car; a "
                   "run cannot show more than that it goes with it. The emulator and the core "
                   "without the shaft test cannot read it: they test only the points P, R, C "
                   "against the car, and their 20 mph runs pass through the car's outline "
                   "(6.2, line 1728, above), so on them the statement, which holds only where "
                   "both its parts do, cannot be checked.")}


def _by_point(st, cases):
    """|XL| falls and YL rises with α, read point by point; the verdict of each source names
    the points for which it holds."""
    table = ["| post, speed, point | source | XL at 0°, 15°, 30° | YL at 0°, 15°, 30° | "
             "holds |", "|---|---|---|---|---|"]
    by = {p: _flags() for p in st.runs["points"]}
    for mph in st.runs["speeds"]:
        for post in st.runs["posts"]:
            series = [cases.get(case_name(post, mph, a)) for a in ANGLES]
            for p in st.runs["points"]:
                if p == "U" and post != "twin":
                    continue
                qx, qy = f"terminal_{p.lower()}_xl_ft", f"terminal_{p.lower()}_yl_ft"
                rows = []
                if all(c is not None and c.in_tables for c in series):
                    rows.append(("report", [_report_value(c, qx) for c in series],
                                 [_report_value(c, qy) for c in series]))
                for e in ENGINES:
                    xs = [_q(c, e, qx) for c in series]
                    if not all(x is None for x in xs):
                        rows.append((e, xs, [_q(c, e, qy) for c in series]))
                for src, xs, ys in rows:
                    ok_x = increasing([None if x is None else -abs(x) for x in xs])
                    ok_y = increasing(ys)
                    ok = None if ok_x is None or ok_y is None else ok_x and ok_y
                    by[p][src].append(ok)
                    table.append(f"| {_tag(f'{post} {mph} mph', post)}, {p} | {src} | "
                                 + ", ".join(_f(x) for x in xs) + " | "
                                 + ", ".join(_f(y) for y in ys) + " | "
                                 + ("yes" if ok else "no") + " |")
    on = {}
    for src in SOURCES:
        holds = [p for p in by if tally(by[p][src]) == HOLDS]
        known = [p for p in by if tally(by[p][src]) != CANNOT]
        on[src] = (CANNOT if not known else HOLDS if holds == known else FAILS if not holds
                   else f"holds for {', '.join(holds)}; not for "
                        + ", ".join(p for p in known if p not in holds))
    share = {p: sum(sum(x is True for x in f) for f in by[p].values())
             / max(1, sum(sum(x is not None for x in f) for f in by[p].values())) for p in by}
    best = max(share, key=share.get)
    return table, on, {"by_point": "; ".join(f"{p}: {counted(f)}" for p, f in by.items()),
                       "best": f"The point that follows it most often is {best} "
                               f"({counted(by[best])}); the statement names no point, so no "
                               "one point's series is its verdict."}


def _rises(st, cases):
    name = st.quantity[0]
    table = ["| post, speed | source | at 0°, 15°, 30° (ft) | holds |", "|---|---|---|---|"]
    flags = _flags()
    misfits = []
    for label, post, series in _series(cases, st.runs):
        rows = []
        if all(c is not None and c.in_tables for c in series):
            rows.append(("report", [_report_value(c, name) for c in series]))
            if name == "terminal_cm_yl_ft":
                misfits += [report_mass_centre(c)[1] for c in series]
        for e in ENGINES:
            ys = [_q(c, e, name) for c in series]
            if not all(y is None for y in ys):
                rows.append((e, ys))
        for src, ys in rows:
            ok = increasing(ys)
            flags[src].append(ok)
            table.append(f"| {_tag(label, post)} | {src} | " + ", ".join(_f(y) for y in ys)
                         + f" | {'yes' if ok else 'no'} |")
    return table, {k: tally(f) for k, f in flags.items()}, {
        "counts": counted(flags), "misfit": f"{max(misfits):.2f}" if misfits else "—"}


def _r_first(st, cases):
    table = ["| run | report | core |", "|---|---|---|"]
    flags = {"report": [], "core": []}
    for c in _cases(cases, st.runs):
        rep = _rep(c.name, "comment")
        if rep is not None and "GROUND" in rep:
            flags["report"].append("POINT R" in rep or "POINTS R" in rep)
        if c.core.hit is not None and not _on_car(c.core):
            flags["core"].append(c.core.hit.point in ("R", "R&U"))
        table.append(f"| {_tag(c.name, c.post)} | {rep or 'not run'} | {_end(c, 'core')} |")
    return table, {"report": tally(flags["report"]), "emulator": CANNOT,
                   "core": tally(flags["core"])}, {"counts": counted(flags)}


def _limits(st, cases):
    oiv, ora = CRITERIA["nchrp350_oiv"], CRITERIA["nchrp350_ora"]
    flags = _flags()
    worst = {k: {"max_decel_g": None, "oiv_m_s": None, "ora_g": None} for k in flags}

    def keep(src, k, x):
        if x is not None:
            w = worst[src][k]
            worst[src][k] = x if w is None else max(w, x)

    for c in _cases(cases, st.runs):
        keep("report", "max_decel_g", _rep(c.name, "max_decel_g"))
        for e in ENGINES:
            o = _out(c, e)
            if o is None:
                continue
            vals = quantities.values(o, ("max_decel_g", "oiv_m_s", "ora_g"))
            for k, x in vals.items():
                keep(e, k, x)
            if vals["oiv_m_s"] is not None:
                flags[e].append(vals["oiv_m_s"] <= oiv.maximum
                                and (vals["ora_g"] is None or vals["ora_g"] <= ora.maximum))
    table = ["| source | largest `max_decel_g`, g | largest `oiv_m_s`, m/s | largest `ora_g`, g |",
             "|---|---|---|---|"]
    for k in SOURCES:
        table.append(f"| {k} | " + " | ".join(_f(worst[k][q]) for q in worst[k]) + " |")
    on = {"report": CANNOT, **{e: tally(flags[e]) for e in ENGINES}}
    return table, on, {
        "oiv": f"{oiv.source} ({oiv.label()})", "ora": f"{ora.source} ({ora.label()})",
        "within": "every run's occupant impact velocity and ridedown acceleration are inside "
                  "NCHRP Report 350's limits" if overall(on) == HOLDS else
                  "some run exceeds NCHRP Report 350's limits",
        "report_max": _f(worst["report"]["max_decel_g"])}


#: rule name (a statement's ``rule``) -> function(statement, cases) -> (table, on, figures)
RULES = {"sign": _sign, "clears": _clears, "edge": _edge, "alpha_change": _alpha_change,
         "one_exception": _one_exception, "cannot": _cannot, "energy": _energy,
         "by_point": _by_point, "rises": _rises, "r_first": _r_first, "limits": _limits}


def _fill(template: str, figures: dict) -> str:
    text = template.format(**figures)
    return text[:1].upper() + text[1:]


def check(st: Statement, cases: dict[str, Case]) -> Verdict:
    """One statement judged by its rule on the runs ``cases``."""
    table, on, figures = RULES[st.rule](st, cases)
    return Verdict(st, _fill(st.how, figures), _fill(st.why, figures), table, on, overall(on))


def verdicts(cases: dict[str, Case]) -> list[Verdict]:
    """Every statement of Sections 5.4 and 6.2-6.4, checked on the runs ``cases``
    (:func:`report.figures.run_cases`)."""
    return [check(st, cases) for st in STATEMENTS if st.rule in RULES]


def verdicts_page(vs: list[Verdict], command: str) -> str:
    """``docs/report/verdicts.md``."""
    out = ["# The report's statements of Sections 5.4 and 6.2-6.4, with verdicts\n",
           f"Made by `{command}` (with [figures.md](figures.md)). Each statement is a row of "
           "`report/statements.py`: quoted with its line in the OCR text of the report, the "
           "quantities it is checked by (the registry, `engine/quantities.py`; `deck-emulator "
           "summary --help` and docs/json.md define them) and its rule (`report/verdicts.py`). "
           "The runs: the 18 columns of Tables 11 and 12 as docs/report_full.md builds them, "
           "and the three posts at 30 mph; the emulator runs the listing (`double`, erratum "
           "`ed-direction`) where it can carry the post (not the twin post: no point U), the "
           "core its `legacy` preset. The report's own numbers: "
           f"`deck_emulator.studies.report_tables` ({SOURCE}).\n",
           "Where each run's inputs come from: the steel runs at 20 and 40 mph are the "
           "report's own decks (`decks/steel*.dat`); the steel runs at 30 mph are the report's "
           "deck `decks/steel40.dat` with VVB and ALPHA set by the sweep's rules "
           "(`deck-emulator sweep`); none of their inputs was fitted. The aluminium and twin "
           "posts are the assembly builder's (`assemblies/aluminium.toml`, `twin.toml`): their "
           "|PQ| and arm rise were fitted to Tables 11 and 12's own terminal coordinates, their "
           "base weight and arm shape carried over from the builder's calibration on the steel "
           "deck, and their car is the steel deck's of the same speed and angle (steel40's car "
           f"with VVB and ALPHA set at 30 mph). {FITTED_MARK} marks every run of those two "
           "posts: fitted, beside every number it touches. The axes are the report's XL, YL, "
           "ZL (origin on the ground under the base; the car drives to -XL; the arm reaches "
           "over the highway along -YL, so +YL is away from the highway).\n",
           "## Verdicts\n", "| # | section, line | statement | report's numbers | emulator | "
           "core | verdict |", "|---|---|---|---|---|---|---|"]
    for i, v in enumerate(vs, 1):
        short = v.quote if len(v.quote) <= 110 else v.quote[:107].rsplit(" ", 1)[0] + " ..."
        where = f"line{'s' if '-' in v.lines else ''} {v.lines}"
        core = v.on.get("core", CANNOT)
        if SHAFT in v.on:
            core += f" (with the shaft test: {v.on[SHAFT]})"
        out.append(f"| {i} | {v.section}, {where} | {short} | {v.on.get('report', CANNOT)}"
                   f" | {v.on.get('emulator', CANNOT)} | {core} | **{v.verdict}** |")
    out.append("")
    for i, v in enumerate(vs, 1):
        out.append(f"## {i}. Section {v.section}, line{'s' if '-' in v.lines else ''} "
                   f"{v.lines}\n")
        out.append(f"> {v.quote}\n")
        out.append(f"**Computation.** {v.how}\n")
        if v.table:
            out += v.table
            out.append("")
        out.append(f"**Verdict: {v.verdict}.** {v.why}\n")
    return "\n".join(out) + "\n"
