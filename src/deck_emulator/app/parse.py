"""``deck-emulator parse``: read a card deck and print its 64 values."""

from __future__ import annotations

from . import Answer, command
from . import common
from .options import option, options_class, Source


@options_class
class ParseOptions(Source):
    json: bool = option(False, help="print one JSON object: values (name -> value, READ "
                        "order) and the cards' fields with their columns and units "
                        "(docs/json.md)")


@command("parse", ParseOptions, help="read a card deck and print its 64 values",
         description="Read a $DATA card deck (8 cards, FORMAT(8F10.5)) with the 1967 input "
         "rules and print the values under their READ-list names.", core=False)
def parse(o: ParseOptions) -> Answer:
    from deck_emulator.present.answers import parse_result, render_parse

    src = common.load(o, "parse", kinds=("deck",))
    deck = src.deck("parse")
    result = parse_result(deck)
    answer = Answer("parse", str(deck.path), result=result, json=o.json, said=list(src.notes))
    answer.text = None if o.json else render_parse(answer.document())  # the document once
    return answer
