"""The verdicts of a run: the occupant compartment, and the occupant impact velocity and
ridedown acceleration against each cited limit (:data:`~.safety.CRITERIA`), in the words of
:data:`~.safety.VERDICTS`.

Every answer that rates occupant risk (``summary``, ``core``, ``assembly ... core``, a
sweep's rows) takes its verdicts from :func:`ratings`. The compartment is the roof box of the
car's outline; a strike on it or beside it is ``not judged`` (a rigid car computes no
deformation, and the post is not followed past its first strike), and it ``passes`` only when
the whole post was tested against the car and met none of it (:func:`compartment`; the rules
and their sources: docs/safety.md). OIV and ORA come from the contact pulse, which no later
strike changes. A run that did not end is rated nothing (:func:`ratings` is None; the
registry's ``unavailable`` says why).
"""

from __future__ import annotations

from deck_emulator.vocabulary.events import POINT_NAMES

from . import quantities
from .safety import (COMPARTMENT_LIMITS, NOT_RECHECKED, STANDARDS, VERDICTS,
                     clearance_of, criteria_of, rate, strike_on_car)


#: The readings rated against their limits, beside the occupant compartment.
RATED = ("oiv_m_s", "ora_g")

#: Inside the outline by less than this (ft) is at its surface: the round-off of a strike the
#: core locates on the surface itself.
_AT_SURFACE_FT = 1e-9


def part_name(label: str) -> str:
    """A part of the post by the label an engine or the clearance gives it, in the
    vocabulary's words: ``Q-P`` -> 'the shaft Q-P', ``R`` -> 'the luminaire end R'."""
    return f"the {POINT_NAMES.get(label, label)}"


def _ms(t_s: float) -> str:
    return f"{1000.0 * t_s:.1f} ms"


def _verdict(word: str) -> str:
    assert word in VERDICTS, word  # every verdict word is one of the table's
    return word


def _mash_compartment_limits() -> str:
    rows = "; ".join(c.rule for c in COMPARTMENT_LIMITS.values())
    return (f"{STANDARDS['mash'].name} judges a strike on the occupant compartment by the "
            f"deformation and any penetration it causes (Section 5.2.2 and Appendix E: "
            f"{rows}, {NOT_RECHECKED})")


_RIGID = ("the car is a rigid outline in this model, which computes neither the deformation "
          "nor a penetration")


def compartment(o) -> dict | None:
    """The occupant compartment's verdict for outcome ``o`` (None for a run that did not
    end): ``verdict``; for the first place the post meets the car (its strike): ``part`` (the
    part of the post), ``surface`` (what of the car it meets: hood, trunk; windshield, roof,
    side glass of the compartment), ``car_part`` (hood, roof, trunk: the outline's box),
    ``in_compartment`` (True, False; None where it is not known), ``where`` (the place on the
    post: ``Q-P 0.73`` is 73 % of the way from Q to P), ``time_s``, ``how`` (``"hit"``: the
    run ends with it; ``"line"``: the post's line, checked over the computed path, is inside
    the outline there), ``depth_ft`` (how far inside the car's outline the computed path goes
    at the most: 0 where it never goes in), ``deepest_surface``, ``deepest_where``,
    ``deepest_time_s`` (where and when that is); ``roof_clearance_before_ft`` (the least
    clearance over the compartment up to the strike); ``clearance_ft`` (the least clearance
    over the car, negative inside), ``contact_test`` and ``reason`` in words; ``criteria``
    the limits it answers."""
    if not o.ended:
        return None
    c = quantities.clearance(o)
    found = []  # (time, part label, where, how, engine's surface, fraction)
    hit = o.hit
    if hit.surface is not None and hit.surface.on_car:
        found.append((hit.time_s, hit.point or "?", hit.point or "?", "hit",
                      hit.surface.value, hit.fraction))
    if c is not None and c.touch_time_s is not None:
        label, *frac = c.touch_where.split()
        found.append((c.touch_time_s, label, c.touch_where, "line", None,
                      float(frac[0]) if frac else None))
    least = None if c is None else c.body_ft
    answer = {"verdict": None, "part": None, "surface": None, "car_part": None,
              "in_compartment": None, "where": None, "time_s": None, "how": None,
              "depth_ft": None, "deepest_surface": None, "deepest_where": None,
              "deepest_time_s": None, "roof_clearance_before_ft": None,
              "clearance_ft": least, "contact_test": o.contact_test, "reason": "",
              "criteria": list(criteria_of("occupant_compartment"))}
    points_only = o.contact_test != "segments"
    if found:
        t, label, where, how, surface, fraction = min(found, key=lambda f: f[0])
        if how == "line":  # the box the line is inside decides; its nearest face says which
            surface = c.touch_surface if c.touch_surface != "roof" else None
        struck = strike_on_car(o, t, label, fraction=fraction, surface=surface)
        deep = least is not None and least < -_AT_SURFACE_FT
        before = clearance_of(o, t)
        roof_before = None if before is None else before.roof_ft
        answer.update(part=part_name(label), surface=struck.face, car_part=struck.car_part,
                      in_compartment=struck.occupant_compartment, where=where, time_s=t,
                      how=how, depth_ft=-least if deep else 0.0,
                      deepest_surface=c.body_surface if deep else None,
                      deepest_where=c.body_where if deep else None,
                      deepest_time_s=c.body_time_s if deep else None,
                      roof_clearance_before_ft=roof_before)
        what = f"{part_name(label)} strikes the {struck.face} at {_ms(t)}"
        if label != where:
            what += f" ({where})"
        through = ("; the model that ran tests only the points P, R and C against the car, so "
                   f"its path goes on through the car ({-least:.3f} ft inside at the most, "
                   f"{c.body_where} over the {c.body_surface} at {_ms(c.body_time_s)}), a path "
                   "a rigid car does not allow" if how == "line" and deep else "")
        if struck.occupant_compartment is None:
            answer.update(verdict=_verdict("not judged"), reason=(
                f"{what}: the run does not say where on the car, so whether it is the "
                "occupant compartment is not known"))
        elif struck.occupant_compartment:
            answer.update(verdict=_verdict("not judged"), reason=(
                f"{what}: the occupant compartment{through}. {_mash_compartment_limits()}; "
                f"{_RIGID}: no verdict, and no pass"))
        else:
            kept = ("the post never passes over the occupant compartment before it"
                    if roof_before is None else
                    f"until then the post stays {roof_before:.3f} ft clear of the occupant "
                    "compartment (roof, windshield, side glass)")
            outside = f"{what}, outside the occupant compartment; {kept}"
            if how == "hit" and not points_only:
                answer.update(verdict=_verdict("not judged"), reason=(
                    f"{outside}; the whole post (its points, the shaft Q-P, the arms) was "
                    f"tested against the car, and the run ends with that strike: what the post "
                    f"does after it, lying on the {struck.face} beside the compartment (sliding "
                    "or turning onto the windshield or the roof), is not computed, so no pass"))
            elif how == "hit":
                answer.update(verdict=_verdict("not judged"), reason=(
                    f"{outside}; the run ends with that strike, but the model that ran tests "
                    "only the points P, R and C against the car, not the shaft and the arms, "
                    "so it gives no pass verdict; the core with --shaft-contact (or --preset "
                    "physical) tests the whole post"))
            else:
                answer.update(verdict=_verdict("not judged"), reason=(
                    f"{outside}{through or ''}: what the post does after {_ms(t)} is not "
                    "computed, so the compartment is not judged past it"))
        return answer
    clear = ("the post never passes over the car" if least is None else
             f"the post's line stays {least:.3f} ft clear of the car at the least (over the "
             f"{c.body_surface} at {_ms(c.body_time_s)}, {c.body_where})")
    if not points_only:
        answer.update(verdict=_verdict("passes"), reason=(
            f"the whole post (its points, the shaft Q-P, the arms) was tested against the car "
            f"and none of it met the car before the run ended ({o.verdict()}); {clear}"))
    else:
        answer.update(verdict=_verdict("not judged"), reason=(
            "the model that ran tests only the points P, R and C against the car (the "
            "listing's checks), not the shaft and the arms, so it gives no pass verdict; "
            f"checked over its computed path, {clear}; the core with --shaft-contact (or "
            "--preset physical) tests the whole post (docs/models.md: which model for a "
            "safety judgement)"))
    return answer


def ratings(o) -> dict | None:
    """Every verdict of outcome ``o`` (None for a run that did not end):
    ``occupant_compartment`` (:func:`compartment`), then for each of :data:`RATED`
    ``{quantity, value, verdicts: {criterion key: word}, reason}``: each read against its
    limits whatever the compartment's verdict (the contact pulse, which no later strike
    changes); ``reason`` says why a value has no verdict."""
    comp = compartment(o)
    if comp is None:
        return None
    out = {"occupant_compartment": comp}
    for name in RATED:
        value = quantities.value(name, o)
        verdicts = {}
        for key, criterion in criteria_of(name).items():
            word = rate(value, criterion)
            if word:
                verdicts[key] = _verdict(word)
        out[name] = {"quantity": name, "value": value, "verdicts": verdicts,
                     "reason": "" if verdicts else
                     quantities.unavailable(o, [name]).get(name, "no value")}
    return out
