"""The verdicts of a run: the occupant compartment, and the occupant impact velocity and
ridedown acceleration against each cited limit (:data:`~.safety.CRITERIA`), in the words of
:data:`~.safety.VERDICTS`.

Every answer that rates occupant risk (``summary``, ``core``, ``assembly ... core``, a
sweep's rows) takes its verdicts from :func:`ratings`, so none can say "preferred" beside a
post that went into the car:

* **the occupant compartment** fails when any part of the post (its points, the shaft Q-P,
  the arms) enters the car's body before the run ends: the run ends with the post striking
  the car (the model's own test), or the post's line, checked over the computed path
  (:func:`~.safety.body_clearance`), is inside the car's outline (what the listing, which
  tests only P, R and C, runs through). It passes only when the model that ran tested the
  whole post against the car (``Outcome.contact_test == "segments"``) and no part entered;
  a model that tests only the points gives no pass verdict: ``not judged``, and why.
* **OIV and ORA** are read against every cited limit; beside a compartment that fails, a
  value within its limits is ``not rated`` (the test fails whatever it is).

A run that did not end is rated nothing (:func:`ratings` is None; the registry's
``unavailable`` says why).
"""

from __future__ import annotations

from deck_emulator.vocabulary.events import POINT_NAMES

from . import quantities
from .safety import VERDICTS, criteria_of, rate

__all__ = ["ratings", "compartment", "RATED", "part_name"]

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


def compartment(o) -> dict | None:
    """The occupant compartment's verdict for outcome ``o`` (None for a run that did not
    end): ``verdict``; for a failure ``part`` (the part of the post that enters first),
    ``surface``, ``where`` (the place on the post: ``Q-P 0.73`` is 73 % of the way from Q
    to P), ``time_s`` (when it enters), ``depth_ft`` (how far inside the car's outline the
    computed path goes at most: 0 where the run ends at the strike), ``deepest_surface``,
    ``deepest_where``, ``deepest_time_s`` (where and when that is); ``clearance_ft`` (the least clearance over the car, negative
    inside), ``contact_test`` and ``reason`` in words; ``criteria`` the limits it answers."""
    if not o.ended:
        return None
    c = quantities.clearance(o)
    found = []  # (time, part label, surface, where, how it was found)
    hit = o.hit
    if hit.surface is not None and hit.surface.on_car:
        found.append((hit.time_s, hit.point or "?", hit.surface.value, hit.point or "?",
                      "hit"))
    if c is not None and c.touch_time_s is not None:
        label = c.touch_where.split()[0]
        found.append((c.touch_time_s, label, c.touch_surface, c.touch_where, "line"))
    least = None if c is None else c.body_ft
    answer = {"verdict": None, "part": None, "surface": None, "where": None, "time_s": None,
              "depth_ft": None, "deepest_surface": None, "deepest_where": None,
              "deepest_time_s": None,
              "clearance_ft": least, "contact_test": o.contact_test, "reason": "",
              "criteria": list(criteria_of("occupant_compartment"))}
    rigid = ("the car is a rigid outline in this model: a post that reaches it is judged a "
             "failure, and how far it would go in is not computed")
    if found:
        t, label, surface, where, how = min(found)
        deep = least is not None and least < -_AT_SURFACE_FT
        answer.update(verdict=_verdict("fails"), part=part_name(label), surface=surface,
                      where=where, time_s=t, depth_ft=-least if deep else 0.0,
                      deepest_surface=c.body_surface if deep else None,
                      deepest_where=c.body_where if deep else None,
                      deepest_time_s=c.body_time_s if deep else None)
        if how == "hit":
            answer["reason"] = (f"the run ends with {part_name(label)} striking the {surface} "
                                f"at {_ms(t)}; {rigid}")
        else:
            answer["reason"] = (
                f"{part_name(label)} enters the car's outline over the {surface} at {_ms(t)} "
                f"({where}); the model that ran tests "
                + ("only the points P, R and C against the car, so its run goes on through "
                   f"the car, {-least:.3f} ft inside at the most ({c.body_where} over the "
                   f"{c.body_surface} at {_ms(c.body_time_s)})"
                   if o.contact_test == "points" and deep else "the whole post")
                + f"; {rigid}")
        return answer
    clear = ("the post never passes over the car" if least is None else
             f"the post's line stays {least:.3f} ft clear of the car at the least (over the "
             f"{c.body_surface} at {_ms(c.body_time_s)}, {c.body_where})")
    if o.contact_test == "segments":
        answer.update(verdict=_verdict("passes"), reason=(
            f"the whole post (its points, the shaft Q-P, the arms) was tested against the car "
            f"and none of it entered the car's body before the run ended ({o.verdict()}); "
            f"{clear}"))
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
    ``{quantity, value, verdicts: {criterion key: word}, reason}``."""
    comp = compartment(o)
    if comp is None:
        return None
    out = {"occupant_compartment": comp}
    fails = comp["verdict"] == "fails"
    for name in RATED:
        value = quantities.value(name, o)
        verdicts, withheld = {}, False
        for key, criterion in criteria_of(name).items():
            word = rate(value, criterion)
            if fails and word in ("preferred", "acceptable"):
                word, withheld = "not rated", True
            if word:
                verdicts[key] = _verdict(word)
        out[name] = {"quantity": name, "value": value, "verdicts": verdicts,
                     "reason": ("the occupant compartment fails" if withheld else "")}
    return out
