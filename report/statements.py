"""The report's statements, one row each: the quote, its line in the OCR text of the report,
the registry quantities it is checked by, the rule that turns their values into a verdict
(a function of :data:`report.verdicts.RULES`), the runs the rule reads, and the prose in two
templates (``how``: the computation; ``why``: the verdict's reasons, filled with the figures
the rule computes). Every page that quotes the report reads its words from here:
docs/report/verdicts.md (Sections 5.4 and 6.2-6.4), docs/report/figures.md (what the text says
of Figures 24 and 29) and docs/report_full.md (Chapter V's statements on the crash test).

``runs``: ``posts``, ``speeds``, ``angles`` (the cases, every combination; twin and the
30 mph runs included where named), ``judged`` (the posts the verdict counts, the rest shown),
``sign`` (-1: the value must be negative, +1 positive), ``along`` (a series over ``"alpha"``
or ``"speed"``), ``points`` (the post's points a series is read for).
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["Statement", "STATEMENTS", "by_key", "quote_of"]


@dataclass(frozen=True)
class Statement:
    key: str
    section: str
    line: str
    quote: str
    quantity: tuple[str, ...]
    rule: str
    how: str
    why: str
    runs: dict = field(default_factory=dict)


ALL = ("aluminium", "steel", "twin")
SINGLE = ("aluminium", "steel")
SPEEDS = (20, 30, 40)

STATEMENTS: tuple[Statement, ...] = (
    Statement(
        "5.4-1", "5.4 (1)", "1692",
        "The luminaire support arm rotates clockwise when the post is struck by the vehicle in "
        "the manner described in Chapter III.",
        ("arm_spin_release_deg",), "sign",
        "every run of the three posts at 20, 30 and 40 mph and α = 0°, 15°, 30°: "
        "`arm_spin_release_deg` (the post's spin about its own axis from t = 0 to the moment "
        "the car lets go; for the upright post the rotation about ZL, clockwise seen from "
        "above is negative). Clockwise is read as seen from above (the report's ZL points up; "
        "Section 6.4 says the same arm turns negatively about ZL). The twin post is shown, "
        "not judged (two arms).",
        "single-arm runs turning clockwise by the time the car lets go: {counts}. The report "
        "prints no attitude at the end of the contact, so its own numbers cannot carry this "
        "check.{report_note}",
        dict(posts=ALL, speeds=SPEEDS, judged=SINGLE, sign=-1)),
    Statement(
        "5.4-2", "5.4 (2)", "1693",
        "For vehicular speeds of 30 miles/hr and 40 miles/hr, the vehicle is seen to pass "
        "under the post and not be struck by the post on its return path to the ground.",
        ("body_clearance_ft",), "clears",
        "every post at 30 and 40 mph, α = 0°, 15°, 30°: the run's end (the engine's hit event: "
        "ground or a part of the car) and `body_clearance_ft` (the least height of the post's "
        "segments Q-P, P-R, P-U above the car's outline in free flight; negative: the shaft or "
        "an arm passes through the car, which the listing's tests of points P, R, C, U do not "
        "see). A run holds when it ends on the ground and the clearance is not negative.",
        "runs in which the car passes under: {counts} (the report printed no 30 mph run). "
        "The margin is thin: the least clearance is {least} ft, and {inside} of the runs that "
        "pass under clear the car by less than the listing's own {band} ft band (the distance "
        "at which its tests take a point to touch a surface): with that band as contact they "
        "would strike it. The verdict holds on the exact outline only.",
        dict(posts=ALL, speeds=(30, 40))),
    Statement(
        "5.4-3", "5.4 (3)", "1694-1696",
        "The rotation of the support arm for the vehicular speeds mentioned previously is large "
        "enough so that the luminaire comes to rest at the edge of the highway and therefore "
        "does not cause an unsafe condition for other motorists.",
        ("terminal_r_yl_ft", "luminaire_yl_shift_ft", "terminal_u_yl_ft"), "edge",
        "every post at 30 and 40 mph: `terminal_r_yl_ft` (YL of the luminaire end R at the "
        "hit; +YL away from the highway), `luminaire_yl_shift_ft` (how far R has moved across "
        "the road since t = 0, where it reached 10 to 10.5 ft out over the highway) and, for "
        "the twin post, `terminal_u_yl_ft`.",
        "the report places no edge of the highway (no lateral position of the post from the "
        "pavement is given), and every run ends at the post's first hit: where the luminaire "
        "comes to rest after it is not computed by the listing or the core. What is computed: "
        "the single arm's R lands between YL = {lo} and {hi} ft, so the statement would hold "
        "if the pavement ended at YL ≤ {lo} ft (the base at least {gap} ft from it), and fail "
        "otherwise; the twin post's R lands as far out as YL = {twin} ft.",
        dict(posts=ALL, speeds=(30, 40))),
    Statement(
        "5.4-4", "5.4 (4)", "1698",
        "Variations of up to 15 degrees in the angle Alpha do not significantly affect the "
        "trajectory of the luminaire support assembly for the speeds considered.",
        ("terminal_p_xl_ft",), "alpha_change",
        "each post at 30 and 40 mph, α = 0° against α = 15°: the largest distance between the "
        "two runs' paths of the luminaire end R and of the mass centre at the same instants "
        "(`engine.attitude.largest_distance_ft`, over the time both ran), and the distance "
        "between their terminal points P, Q, R (`terminal_*_ft`). 'Significant' is our reading "
        "(the report gives none): at least {fraction} % of the post's length |PQ|. The report's "
        "own Table 12 (40 mph) is read the same way.",
        "cases where α = 15° changes nothing significantly: {counts}. The largest move of a "
        "terminal point: {largest}.",
        dict(posts=ALL, speeds=(30, 40))),
    Statement(
        "6.2-1", "6.2", "1728",
        "The reader may observe from Table 11 that for a vehicular velocity of 20 miles per "
        "hour the support post, with one exception, strikes the vehicle before striking the "
        "ground.",
        ("hit_time_s", "body_clearance_ft"), "one_exception",
        "the nine 20 mph columns: the run's end (hit event: the car or the ground) on the "
        "emulator and the core, which test the points P, R, C, U against the car as the "
        "listing does, with `body_clearance_ft` (< 0: the post's shaft or arm passes through "
        "the car's outline, which those tests do not see); and the core with the shaft test "
        "(`--shaft-contact`: the shaft Q-P and the arms checked as segments against the car, "
        "docs/shaft_contact.md). The statement holds for a source when exactly 8 of 9 runs "
        "strike the car first. A run with the shaft test whose strike comes less before its "
        "ground hit (the run without the test) than the column's own end misses the report's "
        "(`hit_time_s`) cannot decide which comes first.",
        "runs that strike the car: {counts}. Counting a shaft or arm that passes through the "
        "car's outline as a strike: emulator {through_emulator}, core {through_core} runs do. "
        "The report ends its 20 mph runs on the shaft meeting the car (its words: 'front of "
        "car', 'top of car'), a test the listing as printed does not have. With that test the "
        "core strikes the car in {shaft_n} columns; {undecided}",
        dict(posts=ALL, speeds=(20,))),
    Statement(
        "6.2-2", "6.2", "1728",
        "Table 12 shows that for a vehicular velocity of 40 miles per hour the support assembly "
        "clears the vehicle in all cases.",
        ("body_clearance_ft",), "clears",
        "the nine 40 mph columns: the run's end and `body_clearance_ft` (as for 5.4 (2)).",
        "runs that clear the car: {counts}. The least clearance is {least} ft; {inside} of the "
        "runs that clear pass within the listing's {band} ft band.",
        dict(posts=ALL, speeds=(40,))),
    Statement(
        "6.2-3", "6.2", "1730",
        "The overall behavior of the support post assembly for the two vehicular velocities "
        "considered is very similar.",
        (), "cannot",
        "none: the report names no measure of similarity.",
        "'very similar' names no quantity and no tolerance; the other statements of this page "
        "compare the two speeds on named quantities (the end, the arm's spin, the terminal "
        "points)."),
    Statement(
        "6.2-4", "6.2", "1730",
        "In the case of a vehicular velocity of 20 miles per hour the slower moving vehicle "
        "imparts less energy to the support assembly and causes it to encounter the vehicle "
        "before striking the ground.",
        ("launch_ke_ftlb",), "energy",
        "each post and α at 20, 30 and 40 mph: `launch_ke_ftlb` (the post's kinetic energy, "
        "translation and rotation, when the car lets go). The first part holds when the "
        "energy rises with the speed in every series. The second ('causes it to encounter the "
        "vehicle') is read as far as runs can read a cause: on the core with the shaft test "
        "(which ends on the car as the report's 20 mph runs do), does the energy separate the "
        "runs that strike the car from those that clear it, post by post? The statement "
        "holds on a source only where both parts hold there.",
        "{first}. {second} The report prints no energy.",
        dict(posts=ALL, speeds=SPEEDS, along="speed")),
    Statement(
        "6.3-1", "6.3", "1734",
        "The study showed that an increase in the vehicular approach angle α caused the support "
        "post assembly to have a smaller absolute terminal coordinate in the XL direction and a "
        "larger one in the YL direction. [...] This conclusion is obtained by assuming that the "
        "post does not first encounter the vehicle and the terminal coordinates are taken as "
        "the coordinates describing the position of the assembly when it strikes the ground.",
        ("terminal_p_xl_ft", "terminal_p_yl_ft"), "by_point",
        "each post at 40 mph (every column ends on the ground in Table 12) and 30 mph, for each "
        "of its points P, Q, R (U): `terminal_{{p}}_xl_ft`, `terminal_{{p}}_yl_ft` at α = 0°, "
        "15°, 30°. A series holds when |XL| falls and YL rises from each angle to the next; "
        "the report's own Table 12 is read the same way. The statement names no point, so "
        "the verdict is given point by point.",
        "series (post, speed, point) that follow the statement, by point: {by_point}. {best}",
        dict(posts=ALL, speeds=(40, 30), along="alpha", points=("P", "Q", "R", "U"))),
    Statement(
        "6.3-2", "6.3", "1734",
        "This fact gives the assembly a tendency to fall more in the direction away from the "
        "highway as the angle α is increased.",
        ("terminal_cm_yl_ft",), "rises",
        "each post at 30 and 40 mph: `terminal_cm_yl_ft` (YL of the post's mass centre at the "
        "hit) at α = 0°, 15°, 30°: holds when it rises with α. The report prints no mass "
        "centre, but its P, Q, R at the end fix its rigid post's place: its mass centre is "
        "read there, the body's t = 0 points and mass centre carried onto the report's P, Q, "
        "R by the rigid motion that fits them best (least squares; it leaves the report's points "
        "at most {misfit} ft from the carried ones).",
        "series in which the mass centre lands further from the highway as α grows: {counts}.",
        dict(posts=ALL, speeds=(30, 40), along="alpha")),
    Statement(
        "6.4-1", "6.4", "1740",
        "From the values presented for point R in Tables 11 and 12 and from Figure 24, it is "
        "clear that regardless of the vehicular speed, type of post used, or vehicular "
        "approach angle, the tendency is for the single luminaire support arm to have a "
        "negative rotation (according to the right hand rule) about the ZL axis.",
        ("arm_spin_deg",), "sign",
        "the 12 single-arm columns (and the single-arm posts at 30 mph): `arm_spin_deg` (the "
        "post's spin about its own axis from t = 0 to the hit, read from P, Q, R and tracked "
        "continuously over the run's samples, so a turn past a half turn keeps its sense), "
        "and the spin of one attitude (`engine.attitude.spin_deg`, within a half turn either "
        "way) applied to the report's own terminal P, Q, R with our t = 0 points. For a post "
        "lying on the ground 'about ZL' needs a reading: the spin about the post's own axis "
        "is the rotation about ZL while the post stands; the report gives none.",
        "negative spins at the end, tracked: {counts}: every single-arm run turns clockwise."
        "{report_note}",
        dict(posts=SINGLE, speeds=SPEEDS, sign=-1)),
    Statement(
        "6.4-2", "6.4", "1740",
        "This rotation causes the support arm to rotate in a direction away from the highway "
        "after the post is impacted and not strike the highway causing an unsafe condition "
        "for other motorists.",
        ("luminaire_yl_shift_ft",), "sign",
        "the 12 single-arm columns and the single-arm posts at 30 mph: "
        "`luminaire_yl_shift_ft` (YL of R at the hit less its YL at t = 0: positive is away "
        "from the highway); the report's YRL less our t = 0 YL of R.",
        "runs in which the luminaire end moves away from the highway: {counts}; whether it "
        "then strikes the highway cannot be checked: the report places no edge of the "
        "pavement (see 5.4 (3)).",
        dict(posts=SINGLE, speeds=SPEEDS, sign=+1)),
    Statement(
        "6.4-3", "6.4", "1742",
        "The case involving the support post with twin luminaires shows that here the "
        "tendency is for the rotation to be positive about the ZL axis. This is shown in "
        "Figure 29.",
        ("arm_spin_deg",), "sign",
        "the twin post at α = 15° and 30° (at α = 0° the twin post is symmetric about the car's "
        "path and has no reason to turn), 20, 30 and 40 mph: `arm_spin_deg` (tracked over the "
        "run), and the spin of one attitude (`engine.attitude.spin_deg`) on the report's own "
        "terminal P, Q, R. The twin post runs on the core only (the listing has no point U).",
        "positive spins, tracked: {counts}.{report_note}",
        dict(posts=("twin",), speeds=SPEEDS, angles=(15, 30), sign=+1)),
    Statement(
        "6.4-4", "6.4", "1742-1744",
        "A positive rotation causes point U to displace towards the highway but for the cases "
        "investigated this effect always causes the striking point to increase in the "
        "direction away from the assumed edge of the pavement.",
        ("second_luminaire_yl_shift_ft",), "sign",
        "the twin post at α = 15° and 30°, 20, 30 and 40 mph: `second_luminaire_yl_shift_ft` "
        "(YL of U at the hit less its YL at t = 0; negative is towards the highway); the "
        "report's YUL less our t = 0 YL of U. The second half ('the striking point ... away "
        "from the assumed edge') cannot be checked: the report never gives the edge it "
        "assumed.",
        "U moves towards the highway: {counts} (the first half); the second half cannot be "
        "checked (no edge of the pavement is given).",
        dict(posts=("twin",), speeds=SPEEDS, angles=(15, 30), sign=-1)),
    Statement(
        "6.4-5", "6.4", "1744",
        "Tables 11 and 12 reveal that for these cases, the point R is the first to contact the "
        "ground.",
        ("hit_time_s",), "r_first",
        "the twin post's runs that end on the ground (20, 30, 40 mph, every α): the hit event's "
        "point. 'R&U' (both in the listing's 0.1 ft ground band at one step) counts as R "
        "first, as the report's own 'POINTS R&U' does.",
        "ground hits led by R: {counts}.",
        dict(posts=("twin",), speeds=SPEEDS)),
    Statement(
        "6.4-6", "6.4", "1744",
        "As the vehicle approach angle is increased, the terminal position of the point R "
        "increases in the direction away from the highway. The same effect had been noticed "
        "in the case of the single luminaire support assembly.",
        ("terminal_r_yl_ft",), "rises",
        "each post at 20, 30 and 40 mph: `terminal_r_yl_ft` at α = 0°, 15°, 30°: holds when it "
        "rises with α; the report's YRL likewise.",
        "series in which R lands further from the highway as α grows: {counts}.",
        dict(posts=ALL, speeds=SPEEDS, along="alpha")),
    Statement(
        "6.4-7", "6.4", "1746",
        "The values of the maximum vehicle deceleration presented in Tables 11 and 12 show that "
        "in all the cases considered the impact forces are kept within tolerable limits.",
        ("max_decel_g", "oiv_m_s", "ora_g"), "limits",
        "every run (20, 30, 40 mph): `max_decel_g` (the report's maximum vehicle deceleration), "
        "judged by the only limits this project can cite (the report names none): `oiv_m_s` "
        "against {oiv} and `ora_g` against {ora}, a standard of 1993 the report could not "
        "know. The report's own decelerations are set beside them.",
        "{within}; 'tolerable' is the report's word without a number: the report's own "
        "decelerations ({report_max} g at most) cannot be judged without one.",
        dict(posts=ALL, speeds=SPEEDS)),
    # Chapter V, the crash test: judged on docs/report_full.md by report.page
    Statement(
        "5.5-1", "5.5", "1704",
        "It can be seen in Figure 18 that the model post lags the crash test post in this "
        "initial phase of the motion and overtakes it in the final phase.",
        ("theta_deg",), "crash_lead",
        "θ of our full run at 70 and 270 ms against the test's (Table 8), and θ at 270 ms of "
        "our free flight from the test's 70 ms state (Table 9's way).",
        "ours is {lead70} the test at 70 ms and {lead270} it at 270 ms: θ at 70 ms {t70} "
        "(test 25.0°), θ from the test's 70 ms state at 270 ms {t270_free} (test 122.0°); "
        "our full run at 270 ms: {t270}"),
    Statement(
        "5.3-1", "5.3", "1682",
        "The biggest discrepancy in Table 10 between model and crash test results is seen for "
        "the value of the angular velocity.",
        ("thetadot_rad_s",), "crash_spin",
        "θ̇ at the loss of contact, the report's model and ours, against the test's 8.75 rad/s "
        "(Table 10).",
        "report: 12.50 vs 8.75 (+43 %); ours {ours} vs 8.75 ({pct})"),
)


def by_key(key: str) -> Statement:
    return next(s for s in STATEMENTS if s.key == key)


def quote_of(*keys: str) -> tuple[str, str]:
    """(lines, words) of the statements ``keys`` quoted together (consecutive in the text):
    the figures' page quotes what the text says of a figure this way."""
    rows = [by_key(k) for k in keys]
    first, last = rows[0].line.split("-")[0], rows[-1].line.split("-")[-1]
    return (first if first == last else f"{first}-{last}"), " ".join(r.quote for r in rows)
