"""``deck-emulator summary``: run a deck and print its outcomes (events, hit, delta-V,
deceleration, P/Q/R)"""

from __future__ import annotations

from deck_emulator.engine.quantities import definitions_help

from . import Answer, command, common
from .options import Answering, Emulator, options_class, trajectory_option


@options_class
class SummaryOptions(Emulator, Answering):
    trajectory: str | None = trajectory_option()


def _summary_description() -> str:
    return ("Run the emulated program and print what the report's Tables 11 and 12 give: the "
            "events as sentences, the hit, the car's speed change in mph, the largest printed "
            "deceleration in g, P, Q, R at the hit in XL, YL, ZL; then the occupant-risk numbers "
            "and the cited limits they are judged by. The two speed changes: "
            + definitions_help() + ". --json: the same as one JSON object (docs/json.md).")


@command("summary", SummaryOptions,
         help="run a deck and print its outcomes (events, hit, delta-V, deceleration, P/Q/R)",
         description=_summary_description)
def summary(o: SummaryOptions) -> Answer:
    from deck_emulator.engine import errata

    src = common.load(o, "summary", kinds=("deck",))
    deck = src.deck("summary")
    common.check_out(o.out)
    common.check_trajectory(o.trajectory)
    engine = common.emulator(o)
    out = common.with_progress(o.quiet, engine, deck)
    written = common.write_trajectory(o.trajectory, out)
    settings = {"arithmetic": engine.arithmetic().describe(),
                "assumptions": dict(getattr(engine.arithmetic(), "assumptions", {}) or {}),
                "errata": errata.describe(out.errata)}
    if not settings["assumptions"]:
        settings.pop("assumptions")
    answer = common.outcome_answer("summary", out, str(deck.path), settings, o)
    answer.notes += list(out.notes) + list(out.flags)
    answer.text = common.rendered(answer)
    answer.said = list(src.notes) + ([written] if written else [])
    return answer
