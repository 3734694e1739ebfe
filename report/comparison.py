"""The report's Tables 11/12 (steel post) beside gfortran's printouts and the emulator's runs:
docs/comparison.md (``python scripts/compare_report.py`` writes it; :func:`write_comparison`).

For every deck in decks/ it takes

* the report's values (``deck_emulator.studies.report_tables``, the only copy of them);
* the gfortran REAL*8 golden ``golden/<deck>[.<erratum>].r8.txt``, read with
  ``deck_emulator.legacy.extract``;
* the emulator in ``double`` with the errata the golden's name gives (it must equal the golden);
* the emulator in ``ibm7094`` (the 1967 machine's arithmetic, default assumptions) with the same
  errata, and, for the angle decks, ``ibm7094`` and ``double`` *as printed* (no erratum), where
  the run's error is caught and reported;

and writes a Markdown page with every value, its difference from the report, and the measured
evidence for the large differences. Nothing is tuned: decks, listing and arithmetic are as they
are in the repository. The file is written whole (temporary file, then rename).
"""

from __future__ import annotations

import datetime as _dt
import math
import platform
import time
from fractions import Fraction
from pathlib import Path

#: The checkout (its golden/ folder holds the compiled listing's printouts).
ROOT = Path(__file__).resolve().parents[1]

from deck_emulator.files import check_output_file, write_file
from deck_emulator.parallel import progress_bar
from deck_emulator.legacy.arithmetic import get_arithmetic
from deck_emulator.legacy.deck import read_deck
from deck_emulator.engine import EmulatorEngine
from deck_emulator.legacy.printer import event_message
from deck_emulator.legacy.extract import INSTANTS, Block, extract, parse_printout
from deck_emulator.studies.report_tables import CASES, REPORT, SOURCE, report_time_ms
from deck_emulator.vocabulary.units import force_in_g, speed_lost_mph

#: The readings of the report's ΔV: the vehicle's speed lost at each instant ``extract`` reads.
DELTA_V_CANDIDATES = INSTANTS
#: The one reported as ``delta_v_crush_mph``: of the four it alone comes near the report.
DELTA_V_DEFINITION = "crush_pulse_end"

DECKS = ("steel40", "steel40_a15", "steel40_a30", "steel20", "steel20_a15", "steel20_a30")
COMMAND = "python scripts/compare_report.py"


# ------------------------------------------------------------------------------------- runs


def golden_path(deck: str) -> tuple[Path, tuple[str, ...]]:
    """The r8 golden of a deck and the errata its name says were applied."""
    plain = ROOT / "golden" / f"{deck}.r8.txt"
    if plain.exists():
        return plain, ()
    found = sorted((ROOT / "golden").glob(f"{deck}.*.r8.txt"))
    if len(found) != 1:
        raise SystemExit(f"no unique r8 golden for {deck}: {found}")
    middle = found[0].name[len(deck) + 1:-len(".r8.txt")]
    return found[0], tuple(middle.split("+"))


def _run(job):
    """Worker: one emulator run, returned as plain data (picklable)."""
    deck_name, precision, errata = job
    deck = read_deck(ROOT / "decks" / f"{deck_name}.dat")
    t0 = time.perf_counter()
    engine = EmulatorEngine(precision=precision, errata=errata, trace=True)
    run, error = engine.execute(deck).run, None  # the program's run itself
    if run.error is not None:
        exc = run.error
        error = dict(message=str(exc), label=str(exc.label), step=exc.step, time=exc.time,
                     guard=exc.guard)
    seconds = time.perf_counter() - t0
    return dict(deck=deck_name, precision=precision, errata=errata, records=list(run.records),
                trace=run.trace, events=run.events, arithmetic=run.arithmetic, error=error,
                seconds=seconds)


def all_runs() -> dict:
    """Every run the page needs, in this process: 20 runs in 18 s, no faster on the two
    workers of a process pool (measured: 17.7 s either way), so no pool; each run's whole
    record (its printout and trace) stays here, where the page reads it."""
    todo = []
    for deck in DECKS:
        _, errata = golden_path(deck)
        todo += [(deck, "double", errata), (deck, "ibm7094", errata)]
        if errata:
            todo += [(deck, "ibm7094", ()), (deck, "double", ())]
    bar = progress_bar(len(todo), desc="compare_report", unit="run")
    results = []
    for job in todo:
        results.append(_run(job))
        bar.update(1)
    bar.close()
    return {(r["deck"], r["precision"], r["errata"]): r for r in results}


# ---------------------------------------------------------------------------------- helpers


def f(x, nd=2, signed=False):
    if x is None:
        return "—"
    if isinstance(x, float) and math.isnan(x):
        return "nan"
    if round(x, nd) == 0:
        x = 0.0  # no "-0.00"
    return f"{x:+.{nd}f}" if signed else f"{x:.{nd}f}"


def cell(value, report, nd=2):
    """'value (Δ)' with Δ = value - report, or just the value when there is no report value."""
    if value is None:
        return "—"
    if report is None or isinstance(report, str):
        return f(value, nd)
    return f"{f(value, nd)} ({f(value - report, nd, signed=True)})"


def event_time(outcome, needle):
    for e in outcome.events:
        if needle in e.message:
            return e.time_s
    return None


class Reading:
    """A printout's instants and values (``extract``) with the report's ΔV readings and
    maximum deceleration computed from them by their one formula each."""

    def __init__(self, printout, deck):
        d = deck.values
        self.printed = extract(printout, deck)
        self.delta_v_candidates_mph = {
            c: None if v is None else speed_lost_mph(d["VVB"], v)
            for c, v in self.printed.vehicle_speed_fps.items()}
        self.delta_v_crush_mph = self.delta_v_candidates_mph[DELTA_V_DEFINITION]
        fsa = self.printed.max_fsa_lb
        self.max_decel_g = None if fsa is None else force_in_g(fsa, d["WV"], d["G"])

    def __getattr__(self, name):
        return getattr(self.printed, name)


def rows_for(outcome):
    """The comparable quantities of one outcome, keyed like the report's fields."""
    t = outcome.terminal
    ms = (lambda s: None if s is None else 1000.0 * s)
    out = {
        "delta_v_crush_mph": outcome.delta_v_crush_mph,
        "max_decel_g": outcome.max_decel_g,
    }
    for p in ("P", "R", "Q", "C"):
        pt = t.get(p)
        for ax in ("X", "Y", "Z"):
            out[f"{ax}{p}L"] = None if pt is None else getattr(pt, f"{ax}L")
    out["terminal_ms"] = ms(outcome.hit_time_s)
    out["first_spring_ms"] = ms(event_time(outcome, "FIRST SPRING"))
    out["vehicle_ms"] = ms(event_time(outcome, "THE VEHICLE"))
    out["hit"] = outcome.hit
    return out


ROWS = [  # (key, label, decimals, report key)
    ("delta_v_crush_mph", f"ΔV, mph ({DELTA_V_DEFINITION})", 3, "delta_v_crush_mph"),
    ("max_decel_g", "max deceleration, g (printed FSA/(WV·G))", 3, "max_decel_g"),
    ("XPL", "XPL, ft", 2, "XPL"), ("YPL", "YPL, ft", 2, "YPL"), ("ZPL", "ZPL, ft", 2, "ZPL"),
    ("XRL", "XRL, ft", 2, "XRL"), ("YRL", "YRL, ft", 2, "YRL"), ("ZRL", "ZRL, ft", 2, "ZRL"),
    ("XQL", "XQL, ft", 2, "XQL"), ("YQL", "YQL, ft", 2, "YQL"), ("ZQL", "ZQL, ft", 2, "ZQL"),
    ("XCL", "XCL, ft (C = Q in the deck)", 2, None), ("YCL", "YCL, ft", 2, None),
    ("ZCL", "ZCL, ft", 2, None),
    ("terminal_ms", "time of the terminal event, ms", 1, "time"),
    ("first_spring_ms", "lost contact with first spring, ms", 1, None),
    ("vehicle_ms", "lost contact with the vehicle, ms", 1, None),
]


def trace_at(trace, t):
    return min(trace, key=lambda r: abs(r["t"] - t))


def shaft_meets_hood_front(trace, d):
    """First time (s) after the post has been clear of it that the post's axis, the straight
    line Q-P, crosses the vehicle's front plane XV = XBUMP = SV - HLEN at or below the hood
    height HHV and between the fenders: the "front of the car" in the listing's own vehicle
    profile. The listing tests only the points P, R and C, never the shaft. Returns (t, height
    of the crossing above the ground) or None."""
    ca, sa = math.cos(d["ALPHA"]), math.sin(d["ALPHA"])
    armed = False
    for r in trace:
        if r["phase"] != "free":
            continue
        xb = r["SV"] - d["HLEN"]
        xq, xp = r["XQ"] * ca - r["YYQ"] * sa, r["XP"] * ca - r["YYP"] * sa
        yq, yp = r["XQ"] * sa + r["YYQ"] * ca, r["XP"] * sa + r["YYP"] * ca
        if (xq - xb) * (xp - xb) >= 0:
            armed = True  # the shaft does not reach the front plane
            continue
        s = (xb - xq) / (xp - xq)
        z = r["ZZQ"] + s * (r["ZZP"] - r["ZZQ"])
        y = yq + s * (yp - yq)
        below = z <= d["HHV"] and d["YLFEN"] <= y <= d["YRFEN"]
        if not below:
            armed = True
        elif armed:
            return r["t"], z + d["HEIGHT"]
    return None


def shaft_height_at_front(r, d):
    """Height above the ground at which the line Q-P crosses XV = XBUMP (None if it does not)."""
    ca, sa = math.cos(d["ALPHA"]), math.sin(d["ALPHA"])
    xb = r["SV"] - d["HLEN"]
    xq, xp = r["XQ"] * ca - r["YYQ"] * sa, r["XP"] * ca - r["YYP"] * sa
    if (xq - xb) * (xp - xb) >= 0:
        return None
    s = (xb - xq) / (xp - xq)
    return r["ZZQ"] + s * (r["ZZP"] - r["ZZQ"]) + d["HEIGHT"]


def contact_steps(trace):
    return [r for r in trace if r["phase"] == "contact"]


def crush_end_every_step(trace, vv0, fconst):
    """ΔV (mph) at the first accepted step whose FSA equals FCONST after one above it."""
    c = contact_steps(trace)
    for a, b in zip(c, c[1:]):
        if a["FS"] > fconst and b["FS"] == fconst:
            return speed_lost_mph(vv0, b["VV"]), b["t"]
    return None, None


def block_times(records, kind):
    return [b.time for b in parse_printout(records) if isinstance(b, Block) and b.kind == kind]


# ----------------------------------------------------------------------------- 7094 facts


def e_counter_facts():
    """The contact print counter E under the 7094 (chopped FAD) and binary64."""
    ar = get_arithmetic("ibm7094")
    k4, k16, zero = ar.decimal(".0004"), ar.decimal("0.0016"), ar.decimal("0.0")
    e, sums = zero, []
    for _ in range(5):
        e = e + k4
        sums.append(e)
    ulp16 = Fraction(1, 2**36)  # 0.0016 is in [2^-10, 2^-9): 27-bit fraction, ulp 2^-36
    steps_7094 = next(i + 1 for i, s in enumerate(sums) if ar.sign(s - k16) >= 0)
    e64, n64 = 0.0, 0
    while True:
        e64 += 0.0004
        n64 += 1
        if e64 - 0.0016 >= 0:
            break
    return dict(
        chop0004=k4.exact(), chop0016=k16.exact(), four_times=4 * k4.exact(),
        sum4=sums[3].exact(), sum4_minus_0016_ulps=(sums[3].exact() - k16.exact()) / ulp16,
        sum3_exact=3 * k4.exact(), sum3=sums[2].exact(), steps_7094=steps_7094, steps_64=n64,
        octal4=sums[3].octal(), octal16=k16.octal())


def free_counter_steps(precision):
    ar = get_arithmetic(precision)
    k2, k8, e, n = ar.decimal("0.0002"), ar.decimal("0.008"), ar.decimal("0.0"), 0
    while True:
        e = e + k2
        n += 1
        if ar.sign(e - k8) >= 0:
            return n


def cos2_minus_1(precision, tha: float):
    from deck_emulator.legacy.arithmetic.ibm7094 import Word
    ar = get_arithmetic(precision)
    x = Word.from_fraction(Fraction(tha)) if precision == "ibm7094" else tha
    c = ar.cos(x)
    return ar.to_float(c * c - ar.decimal("1.0"))


# ---------------------------------------------------------------------------------- the page


def build(runs: dict, seconds: float) -> str:
    L: list[str] = []
    w = L.append
    today = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d")
    decks = {n: read_deck(ROOT / "decks" / f"{n}.dat") for n in DECKS}
    goldens, outcomes, rows = {}, {}, {}
    equal_records = {}
    for n in DECKS:
        gp, errata = golden_path(n)
        goldens[n] = (gp, errata)
        text = gp.read_text()
        og = Reading(text, decks[n])
        od = Reading(runs[(n, "double", errata)]["records"], decks[n])
        oi = Reading(runs[(n, "ibm7094", errata)]["records"], decks[n])
        outcomes[n] = dict(golden=og, double=od, ibm7094=oi)
        rows[n] = {k: rows_for(o) for k, o in outcomes[n].items()}
        equal_records[n] = (text.splitlines() == runs[(n, "double", errata)]["records"],
                            og.printed == od.printed)
    arith_7094 = runs[("steel40", "ibm7094", ())]["arithmetic"]

    w("# The report's Tables 11 and 12 beside the listing's printouts")
    w("")
    w(f"Made by `{COMMAND}` on {today} (UTC), in {seconds:.0f} s wall time (one process) "
      f"on {platform.python_implementation()} {platform.python_version()}; "
      "regenerate with the same command. Every number below is measured by that script; "
      "nothing is tuned.")
    w("")
    w("Sources:")
    w(f"* **report** — TTI Research Report 75-9, Table 11 (20 mph) and Table 12 (40 mph), "
      f"STEEL POST columns ({SOURCE}, lines 1748-1794), kept in `deck_emulator.studies.report_tables`;")
    w("* **gfortran r8** — `golden/<deck>[.ed-direction].r8.txt`, the listing compiled with "
      "gfortran `-fdefault-real-8` (see `golden/MANIFEST.txt`), read by `deck_emulator.legacy.extract`;")
    w("* **double** — `EmulatorEngine(precision='double', errata=...)`, the emulator in IEEE binary64, "
      "with the errata the golden's name gives;")
    w(f"* **ibm7094** — `EmulatorEngine(precision='ibm7094', errata=...)`: {arith_7094}; same errata.")
    w("")
    w("How each value is read from a printout (details in the docstring of "
      "`src/deck_emulator/legacy/extract.py`):")
    w("* coordinates: the block printed after `THE POST HAS HIT ...` (label 98), turned into the "
      "report's axes by XL = XX − XQO, YL = YY − YYQO, ZL = ZZ + HEIGHT (origin on the ground "
      "under the base of the post; the printout's origin is the post's initial mass centre, the "
      "ground is ZZ = −HEIGHT);")
    w("* times: a `LOST CONTACT` message gets the TIME of the block printed just before it (the "
      "step that lost contact, printed by labels 56/353 through `GO TO 88`); the hit gets the "
      "TIME of the block printed just after it;")
    w("* maximum deceleration: the largest FSA printed in a contact block over WV·G — over the "
      "printed blocks only (every 4th step in binary64, every 5th under the 7094);")
    w(f"* ΔV: |VVB| − |VVA| in mph (1 mph = 88/60 ft/s) at the end of the crush pulse "
      f"(`{DELTA_V_DEFINITION}`: the first contact block whose FSA is the FCONST cap, 1200 lb); "
      "why this one: see *Where they differ and why*.")
    w("")
    w("Each cell is `value (value − report)`. The report rounds to 2 decimals (0.01 mph, 0.01 g, "
      "0.01 ft) and to 0.4 ms.")
    w("")

    # ---------------------------------------------------------------- per-deck tables
    w("## Deck by deck")
    w("")
    for n in DECKS:
        mph, alpha, table = CASES[n]
        gp, errata = goldens[n]
        rep = REPORT[n]
        same_rec, same_out = equal_records[n]
        w(f"### `{n}` — {mph} mph, α = {alpha}° (report Table {table})")
        w("")
        w(f"Golden `{gp.relative_to(ROOT)}`; errata {', '.join(errata) if errata else 'none (as printed)'}. "
          f"Emulator double vs golden: records {'identical' if same_rec else 'DIFFERENT'}, "
          f"extracted outcome {'identical' if same_out else 'DIFFERENT'}.")
        w("")
        w("| quantity | report | gfortran r8 | emulator double | emulator ibm7094 |")
        w("|---|---|---|---|---|")
        for key, label, nd, rkey in ROWS:
            rv = None
            if rkey == "time":
                rv = report_time_ms(n)
            elif rkey is not None:
                rv = rep[rkey]
            vals = [cell(rows[n][k][key], rv, nd) for k in ("golden", "double", "ibm7094")]
            w(f"| {label} | {f(rv, nd) if rv is not None else '—'} | " + " | ".join(vals) + " |")
        w(f"| terminal event | {rep['comment']} | " + " | ".join(
            (rows[n][k]['hit'] or '—').replace('THE POST HAS ', '') for k in ("golden", "double", "ibm7094"))
          + " |")
        w("")

    # ---------------------------------------------------------------- delta-V candidates
    w("## ΔV: four candidate definitions")
    w("")
    w("Decrease of the vehicle's speed, mph, at four instants, from the printouts (r8 golden, and "
      "the ibm7094 run); the last column is the crush-pulse end taken at every step from the "
      "emulator's trace (double), not only at the printed ones.")
    w("")
    w("| deck | report | " + " | ".join(f"r8 {c}" for c in DELTA_V_CANDIDATES)
      + " | 7094 crush_pulse_end | 7094 vehicle_contact_lost | every step: crush end (double) |")
    w("|---|---|" + "---|" * (len(DELTA_V_CANDIDATES) + 3))
    dv_err = {c: [] for c in DELTA_V_CANDIDATES}
    dv_err_7094 = []
    step_dv = {}
    for n in DECKS:
        d = decks[n].values
        rv = REPORT[n]["delta_v_crush_mph"]
        og, oi = outcomes[n]["golden"], outcomes[n]["ibm7094"]
        cg = og.delta_v_candidates_mph
        for c in DELTA_V_CANDIDATES:
            dv_err[c].append(cg[c] - rv)
        dv_err_7094.append(oi.delta_v_candidates_mph["crush_pulse_end"] - rv)
        sdv, st = crush_end_every_step(runs[(n, "double", goldens[n][1])]["trace"], d["VVB"],
                                       d["FCONST"])
        step_dv[n] = (sdv, st)
        w(f"| `{n}` | {f(rv)} | " + " | ".join(cell(cg[c], rv, 3) for c in DELTA_V_CANDIDATES)
          + f" | {cell(oi.delta_v_candidates_mph['crush_pulse_end'], rv, 3)}"
          + f" | {cell(oi.delta_v_candidates_mph['vehicle_contact_lost'], rv, 3)}"
          + f" | {cell(sdv, rv, 3)} at {f(1000 * st, 1)} ms |")
    w("")
    w("Mean absolute difference from the report over the six decks (r8): " + ", ".join(
        f"{c} {sum(abs(x) for x in v) / len(v):.3f} mph" for c, v in dv_err.items()) + ".")
    w("")

    # ---------------------------------------------------------------- as printed under 7094
    w("## The angle decks as printed (no erratum)")
    w("")
    w("The ED root search as printed walks away from its root once ψ passes its fixed start "
      "value 0.15 rad (legacy/CORRECTIONS.md, erratum `ed-direction`); gfortran's as-printed "
      "builds of these decks do not end within the goldens' time limit of 5 s (`TIMEOUT_S` in "
      "scripts/make_goldens.py; golden/MANIFEST.txt). Run here as printed, "
      "each bounded by the emulator's ED guard (100 000 iterations per call). (The 0° decks "
      "need no erratum: their ibm7094 runs in the tables above are the listing as printed, and "
      "they run to the end.)")
    w("")
    w("| deck | arithmetic | outcome | accepted steps | ψ (PSIA) at the last accepted step, rad | run time, s |")
    w("|---|---|---|---|---|---|")
    for n in DECKS:
        if not goldens[n][1]:
            continue
        for prec in ("ibm7094", "double"):
            r = runs[(n, prec, ())]
            steps = contact_steps(r["trace"])
            psi = steps[-1]["PSI"] if steps else None
            outcome = "finished: " + event_message(r["events"][-1]) if r["error"] is None else \
                "`EmulatorError`: " + r["error"]["message"]
            w(f"| `{n}` | {prec} | {outcome} | {len(steps)} | {f(psi, 5)} | {r['seconds']:.1f} |")
    w("")

    # ---------------------------------------------------------------- where and why
    w("## Where they differ and why")
    w("")
    # ΔV
    w("### ΔV: the report's figure is nearest the speed lost in the crush pulse")
    w("")
    s40 = [n for n in DECKS if CASES[n][0] == 40]
    s20 = [n for n in DECKS if CASES[n][0] == 20]

    def rng(vals):
        return f"{min(vals):+.3f} to {max(vals):+.3f}"

    def errs(c, names):
        return [outcomes[n]["golden"].delta_v_candidates_mph[c] - REPORT[n]["delta_v_crush_mph"]
                for n in names]

    rest = [outcomes[n]["golden"].delta_v_candidates_mph["vehicle_contact_lost"]
            - outcomes[n]["golden"].delta_v_crush_mph for n in DECKS]
    w("The speed the vehicle has lost when the post leaves it (`vehicle_contact_lost`, which the "
      "free flight keeps unchanged to the end of the run, `end_of_run`) is far above the "
      f"report's figure: by {rng(errs('vehicle_contact_lost', s40))} mph at 40 mph and "
      f"{rng(errs('vehicle_contact_lost', s20))} mph at 20 mph; at the loss of the first spring "
      f"by {rng(errs('first_spring_lost', s40))} and {rng(errs('first_spring_lost', s20))} mph. "
      "The speed lost by the end of the crush pulse — the first ~22 ms, until label 504 caps the "
      "spring force at FCONST = 1200 lb — is within "
      f"{rng(errs('crush_pulse_end', s40))} mph of the report at 40 mph "
      f"(steel40: {f(outcomes['steel40']['golden'].delta_v_crush_mph, 3)} against "
      f"{f(REPORT['steel40']['delta_v_crush_mph'])}), the only "
      "candidate of the four that comes near. It is what the car loses to the post's impact "
      "proper; the report's figure would then leave out what follows, the constant 1200 lb "
      "FCONST drag and the second spring (another "
      f"{min(rest):.2f}-{max(rest):.2f} mph up to the loss of the vehicle). At 20 mph the same "
      f"definition falls {min(-x for x in errs('crush_pulse_end', s20)):.3f} to "
      f"{max(-x for x in errs('crush_pulse_end', s20)):.3f} mph short of the report ("
      + ", ".join(f(REPORT[n]['delta_v_crush_mph']) for n in s20) + "), and the report's rise with α "
      f"at 20 mph ({REPORT['steel20_a30']['delta_v_crush_mph'] - REPORT['steel20']['delta_v_crush_mph']:+.2f} mph "
      "from 0° to 30°) is larger than the listing's "
      f"({outcomes['steel20_a30']['golden'].delta_v_crush_mph - outcomes['steel20']['golden'].delta_v_crush_mph:+.3f}). "
      "Taking the step at which FSA first equals FCONST from every step instead of every "
      f"printed 4th moves it by at most "
      f"{max(abs(step_dv[n][0] - outcomes[n]['golden'].delta_v_crush_mph) for n in DECKS):.3f} mph, "
      "and the 7094's arithmetic by "
      f"{max(abs(outcomes[n]['ibm7094'].delta_v_crush_mph - outcomes[n]['golden'].delta_v_crush_mph) for n in DECKS):.3f} mph: "
      "neither closes the 20 mph gap. So the crush-pulse reading fits 40 mph to "
      f"{max(abs(x) for x in errs('crush_pulse_end', s40)):.2f} mph and is "
      "the best of the four at 20 mph, but it does not reproduce the report's 20 mph column; "
      "the report does not say how it measured ΔV, and the listing reaches the report's "
      f"{f(REPORT['steel20']['delta_v_crush_mph'])} mph for steel20 at no distinguished instant (it is "
      f"passed at {f(1000 * _dv_crossing(runs[('steel20', 'double', ())]['trace'], decks['steel20'].values['VVB'], REPORT['steel20']['delta_v_crush_mph']), 1)} ms, "
      "in the middle of the FCONST phase).")
    w("")

    # max decel
    w("### Maximum deceleration")
    w("")
    md = {n: (outcomes[n]["golden"].max_decel_g - REPORT[n]["max_decel_g"],
              outcomes[n]["ibm7094"].max_decel_g - REPORT[n]["max_decel_g"]) for n in DECKS}
    every = {}
    for n in DECKS:
        tr = contact_steps(runs[(n, "double", goldens[n][1])]["trace"])
        d = decks[n].values
        every[n] = max(r["FS"] for r in tr) / (d["WV"] * d["G"])
    w("The listing's peak spring force over WV·G is above the report in every deck: by "
      f"{rng([md[n][0] for n in s40])} g at 40 mph and {rng([md[n][0] for n in s20])} g at 20 mph "
      f"(r8), {rng([md[n][1] for n in DECKS])} g under the 7094. Sampling is not the cause: "
      "taken at every step (emulator trace) the peak is higher still ("
      + ", ".join(f"{n} {every[n]:.3f}" for n in DECKS)
      + " g), and the 7094 printout, which samples every 5th step, is still "
      f"{min(md[n][1] for n in DECKS):+.3f} g or more off. Dividing by the 3200 lb vehicle's "
      "mass (99.5 slug) instead of the deck's WV = 100.0 slug would raise the figures further. "
      "The report's values are "
      f"{min(md[n][0] / outcomes[n]['golden'].max_decel_g for n in DECKS) * 100:.1f} to "
      f"{max(md[n][0] / outcomes[n]['golden'].max_decel_g for n in DECKS) * 100:.1f} % lower than "
      "the r8 printouts'; the cause is not found in the listing or the deck.")
    w("")

    # 20 mph
    w("### 20 mph: \"POST HITS FRONT OF CAR\" is not a message the listing can print")
    w("")
    w("The listing ends a run with one of eight texts (FORMATs 134, 97, 99, 110, 237, 239, 242, "
      "248): the ground with point P, Q, R or C, or the hood, windshield, top or trunk of the "
      "vehicle, and it tests only the three points P (top of the post), R (end of the arm) and "
      "C. There is no \"front of car\". For the 20 mph decks every run here ends with "
      "`THE POST HAS HIT THE GROUND WITH POINT C`: in the steel decks C is the base point Q "
      "(XCO, YYCO, ZZCO = XQO, YYQO, ZZQO), and while Q's ground test (labels 94/95) needs "
      "|ZZQFA + HEIGHT| ≤ 0.01 ft, C's (labels 230/141) needs only ≤ 0.1 ft, so the base "
      "landing is announced as point C. That happens "
      + ", ".join(f"{f(rows[n]['golden']['terminal_ms'], 1)} ms ({n})" for n in s20)
      + " — later than the report's "
      + ", ".join(f(report_time_ms(n), 1) for n in s20) + " ms \"time to hit car\".")
    w("")
    w("The report's 20 mph rows match the post's state at the report's time, in the same "
      "motion: the emulator's state (double, every-step trace) at the step nearest the report's "
      "time has P, R and Q near where the report puts them, and at that moment the post's shaft "
      "is crossing the car's front plane just above the hood's height:")
    w("")
    w("| deck | report time, ms | P (XL, YL, ZL) report / listing | R report / listing | "
      "Q report / listing | shaft Q–P at the car's front plane XV = XBUMP, ft above ground (hood: "
      f"{decks['steel20'].values['HHV'] + decks['steel20'].values['HEIGHT']:.2f}) | shaft first meets the hood's front edge, ms |")
    w("|---|---|---|---|---|---|---|")
    lags, devs, heights = [], [], []
    for n in s20:
        d = decks[n].values
        tr = runs[(n, "double", goldens[n][1])]["trace"]
        tms = report_time_ms(n)
        r = trace_at(tr, tms / 1000.0)
        rep = REPORT[n]

        def pl(p, r=r, d=d):
            return (r[f"X{p}"] - d["XQO"], r[f"YY{p}"] - d["YYQO"], r[f"ZZ{p}"] + d["HEIGHT"])

        def tri(v):
            return "(" + ", ".join(f"{x:.2f}" for x in v) + ")"

        for p in ("P", "R", "Q"):
            devs += [abs(a - rep[f"{ax}{p}L"]) for a, ax in zip(pl(p), "XYZ")]
        meet = shaft_meets_hood_front(tr, d)
        if meet:
            lags.append(1000 * meet[0] - tms)
        hz = shaft_height_at_front(r, d)
        if hz is not None:
            heights.append(hz - (d["HHV"] + d["HEIGHT"]))
        w(f"| `{n}` | {tms:.1f} | {tri([rep['XPL'], rep['YPL'], rep['ZPL']])} / {tri(pl('P'))} | "
          f"{tri([rep['XRL'], rep['YRL'], rep['ZRL']])} / {tri(pl('R'))} | "
          f"{tri([rep['XQL'], rep['YQL'], rep['ZQL']])} / {tri(pl('Q'))} | "
          f"{f(hz)} | {f(1000 * meet[0], 1) if meet else '—'} |")
    w("")
    meets40 = {n: shaft_meets_hood_front(runs[(n, "double", goldens[n][1])]["trace"],
                                         decks[n].values) for n in s40}
    w(f"At the report's times the listing's P, R and Q lie within {max(devs):.2f} ft of the "
      f"report's (against up to {_max_coord(rows, 'golden', s20, all_axes=True):.2f} ft at the "
      "listing's own end of run, tables above), and the "
      f"shaft crosses the front plane {min(heights):.2f}-{max(heights):.2f} ft above the hood. "
      "The evidence thus points to the report having ended the 20 mph cases when the post's "
      "*shaft* came down on the front of the car — something the program does not test (it "
      "checks points, not the post between them) — judged outside the program, e.g. from the "
      "printed trajectory or a plot. In the listing's own vehicle profile (front plane "
      "XBUMP = SV − HLEN, hood height HHV, fenders YLFEN-YRFEN) the line Q–P first meets the "
      f"hood's front edge {min(lags):.1f}-{max(lags):.1f} ms after the report's times; where "
      "exactly the report put the front of the car is not stated. In the 40 mph runs the shaft "
      + ("never meets it after separation"
         if not any(meets40.values()) else
         "meets it at " + ", ".join(f"{n} {1000 * m[0]:.1f} ms" for n, m in meets40.items() if m))
      + ", consistent with the report's \"the support assembly clears the vehicle in all cases\" "
      "at 40 mph.")
    w("")

    # ZRL 0.00
    w("### The report's ZRL = 0.00 at 40 mph")
    w("")
    w("The listing announces a ground hit by R when |ZZRFA + HEIGHT| ≤ 0.1 ft (labels 111/103), "
      "and the block printed after the message is that step's; so the printed ZRL at the hit is "
      "anywhere in [−0.1, 0.1] ("
      + ", ".join(f"{n} {f(rows[n]['golden']['ZRL'], 3)}" for n in s40)
      + " ft). The report prints 0.00 in all three columns (and ZPL = 0.00 for the aluminium post "
      "at 30°, where P hits): the point that hits was evidently set to the ground, not copied.")
    w("")

    # 7094
    ef = e_counter_facts()
    st40 = runs[("steel40", "double", ())]
    si40 = runs[("steel40", "ibm7094", ())]
    td, ti = contact_steps(st40["trace"]), contact_steps(si40["trace"])
    c2d = cos2_minus_1("double", td[1]["TH"])
    c2i = cos2_minus_1("ibm7094", ti[1]["TH"])
    ncd = len(block_times(st40["records"], "contact"))
    nci = len(block_times(si40["records"], "contact"))
    w("### The IBM 7094's digits against binary64")
    w("")
    w("Measured on the runs above (steel40 unless said):")
    w("")
    w("* **The contact print counter E.** `E=E+.0004` then `IF(E-0.0016)54,87,87`. Under the "
      "7094, 0.0004 and 0.0016 are chopped on conversion; 4 × chop(0.0004) is "
      + ("*exactly* chop(0.0016)" if ef['four_times'] == ef['chop0016'] else
         f"{float(ef['four_times'] - ef['chop0016']):+.3e} from chop(0.0016)")
      + f", but E is a running sum of chopped "
      f"FADs: the third addition, 0.0008 + 0.0004, loses its last bit "
      f"(3 × chop(0.0004) − E₃ = {float(ef['sum3_exact'] - ef['sum3']):.3e}), so after four steps "
      f"E = {float(ef['sum4']):.13f} (octal {ef['octal4']}) is "
      f"{abs(ef['sum4_minus_0016_ulps'])} unit of 2⁻³⁶ (its last place) below chop(0.0016) (octal "
      f"{ef['octal16']}). The test fails, and the counter reaches 0.0016 after "
      f"{ef['steps_7094']} steps instead of {ef['steps_64']}: the 7094 prints a contact block "
      f"every 2.0 ms, not every 1.6 ms ({nci} contact blocks against {ncd} in binary64). This "
      "changes what is printed, not the motion — but the printed maximum deceleration is "
      "sampled at other steps. The free-flight counter (`E=E+0.0002` to 0.008, one step of "
      f"0.0004 s each) needs {free_counter_steps('ibm7094')} steps under the 7094 and "
      f"{free_counter_steps('double')} in binary64 (binary64's sum of 40 × 0.0002 is also just "
      "below 0.008): free-flight blocks come every 16.4 ms in both.")
    w(f"* **`COS(THA)*COS(THA)-1.0` at the start.** At the second step THA = "
      f"{td[1]['TH']:.5e} rad; binary64 gives cos²−1 = {c2d:.4e} (≈ −THA²); the 7094 chops "
      "cos(THA) to the largest word below 1, 1 − 2⁻²⁷, and its square to 1 − 2⁻²⁶, so "
      f"cos²−1 = {c2i:.4e}, {c2i / c2d:.1f} times too large. (In binary32 the same expression is "
      "0 and the program divides by zero — golden/*.r4.trap.) PHIA, which divides by it, moves "
      f"{td[1]['PHI'] / ti[1]['PHI']:.1f} times less in that step ({td[1]['PHI']:.4e} against "
      f"{ti[1]['PHI']:.4e} rad); the difference shrinks as THA grows, but φ is still "
      f"{100 * abs(ti[50]['PHI'] / td[50]['PHI'] - 1):.0f} % apart at step 51 "
      f"(t = {td[50]['t']:.4f} s), and the spring force follows (FSA {td[3]['FS']:.2f} against "
      f"{ti[3]['FS']:.2f} lb at step 4).")
    psi = {}
    for n in DECKS:
        a = contact_steps(runs[(n, "double", goldens[n][1])]["trace"])[:60]
        b = contact_steps(runs[(n, "ibm7094", goldens[n][1])]["trace"])[:60]
        psi[n] = max(abs(x["PSI"] - y["PSI"]) for x, y in zip(a, b))
    w("* **ED's tolerance quantises ψ.** ED accepts a root when |DF| ≤ 0.0001, stepping from "
      "0.15 (or PSIB) by 0.01 and halving; the accepted ψ lies on that grid, and which grid point "
      "passes the test depends on the last bits of DF. Over the first 60 steps ψ differs between "
      "the two arithmetics by up to " + ", ".join(f"{n} {psi[n]:.1e}" for n in DECKS)
      + f" rad (steel40, step 21: {td[20]['PSI']:.6e} against {ti[20]['PSI']:.6e}), far more "
      "than the rounding of one operation (2⁻²⁶ relative).")
    ev = []
    for n in DECKS:
        og, oi = outcomes[n]["golden"], outcomes[n]["ibm7094"]
        a, b = event_time(og, "FIRST SPRING"), event_time(oi, "FIRST SPRING")
        ev.append(f"{n} {1000 * (b - a):+.1f}")
    nearer, farther, same = _closer_count(rows)
    w("* **Consequences.** The 7094 runs lose the first spring at another step ("
      + ", ".join(ev) + " ms against binary64), and end "
      + ", ".join(f"{n} {rows[n]['ibm7094']['terminal_ms'] - rows[n]['golden']['terminal_ms']:+.1f}"
                  for n in DECKS)
      + " ms apart. The terminal coordinates move by up to "
      + f"{max(abs(rows[n]['ibm7094'][k] - rows[n]['golden'][k]) for n in DECKS for k in ('XPL','YPL','ZPL','XRL','YRL','ZRL','XQL','YQL','ZQL')):.2f}"
      + " ft; the events and the hit messages are the same in every deck. The 7094 is not "
      f"nearer the report, rather the opposite: of the {nearer + farther + same} numeric cells of the "
      f"six tables it is nearer in {nearer}, farther in {farther}, equally far in {same} "
      "(at the table's precision).")
    gaps = sorted({runs[(n, "double", ())]["error"]["step"] - runs[(n, "ibm7094", ())]["error"]["step"]
                   for n in DECKS if goldens[n][1]
                   and runs[(n, "double", ())]["error"] and runs[(n, "ibm7094", ())]["error"]})
    w("* **The angle decks as printed** hang in ED under the 7094 too (table above): the "
      "truncating arithmetic does not rescue ED's search; it fails when ψ passes 0.15 rad, "
      f"{' or '.join(str(g) for g in gaps)} step(s) earlier than in binary64.")
    w("")
    w("### What remains")
    w("")
    w("After ΔV's definition, the 20 mph stopping rule and the ZRL convention, the listing and the "
      "report still differ by up to "
      f"{_max_coord(rows, 'golden', s40):.2f} ft in the 40 mph terminal coordinates (e.g. steel40 "
      f"YQL {f(rows['steel40']['golden']['YQL'])} against {f(REPORT['steel40']['YQL'])}) and by "
      + ", ".join(f"{rows[n]['golden']['terminal_ms'] - report_time_ms(n):+.1f}" for n in s40)
      + " ms in the 40 mph ground-hit times. The 7094's arithmetic does not close these gaps "
      f"(ibm7094: up to {_max_coord(rows, 'ibm7094', s40):.2f} ft, "
      + ", ".join(f"{rows[n]['ibm7094']['terminal_ms'] - report_time_ms(n):+.1f}" for n in s40)
      + " ms). The report's parameter-study decks are not printed (only the 40 mph, 0° deck is, "
      "in the appendix; the five others here are reconstructed, see decks/README.md), so a "
      "different input for the study cannot be excluded.")
    w("")
    w("## Run times")
    w("")
    w("Wall-clock seconds of each emulator run in this invocation (worker processes share the "
      "machine, so these vary with its load).")
    w("")
    w("| deck | double, s | ibm7094, s |")
    w("|---|---|---|")
    for n in DECKS:
        e = goldens[n][1]
        w(f"| `{n}` | {runs[(n, 'double', e)]['seconds']:.2f} | {runs[(n, 'ibm7094', e)]['seconds']:.2f} |")
    w("")
    return "\n".join(L)


def _dv_crossing(trace, vv0, target_mph):
    for r in contact_steps(trace):
        if speed_lost_mph(vv0, r["VV"]) >= target_mph:
            return r["t"]
    return None


NUM_KEYS = ("delta_v_crush_mph", "max_decel_g", "XPL", "YPL", "ZPL", "XRL", "YRL", "ZRL", "XQL",
            "YQL", "ZQL", "terminal_ms")


def _max_coord(rows, which, names, all_axes=False):
    keys = ("XPL", "YPL", "ZPL", "XRL", "YRL", "XQL", "YQL", "ZQL") + (("ZRL",) if all_axes else ())
    return max(abs(rows[n][which][k] - REPORT[n][k]) for n in names for k in keys)


def _closer_count(rows):
    """Numeric cells where the ibm7094 value is nearer the report than r8, farther, equal."""
    nearer = farther = same = 0
    for n in DECKS:
        for k in NUM_KEYS:
            rv = report_time_ms(n) if k == "terminal_ms" else REPORT[n][k]
            nd = 1 if k == "terminal_ms" else (3 if k in ("delta_v_crush_mph", "max_decel_g") else 2)
            a = round(abs(rows[n]["golden"][k] - rv), nd)
            b = round(abs(rows[n]["ibm7094"][k] - rv), nd)
            nearer += b < a
            farther += b > a
            same += b == a
    return nearer, farther, same


def write_comparison(out) -> float:
    """Run every deck, write the page to ``out`` whole or not at all (its folder is checked
    before the runs); returns the seconds it took."""
    check_output_file(out)
    t0 = time.perf_counter()
    runs = all_runs()
    text = build(runs, time.perf_counter() - t0)
    write_file(out, text)
    return time.perf_counter() - t0
