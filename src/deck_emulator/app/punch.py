"""``deck-emulator punch``: punch a deck's data cards (or a whole job deck) in a card image
format."""

from __future__ import annotations

from deck_emulator.vocabulary.choices import CARD_FORMATS, KEYPUNCH_CODES

from . import Answer, command
from . import common
from .options import option, options_class, Source


@options_class
class PunchOptions(Source):
    to: str = option("text", choices=CARD_FORMATS, help="card format to punch")
    code: str = option("026", choices=KEYPUNCH_CODES,
                       help="keypunch code of the punched holes (default 026)")
    job: bool = option(False, help="punch a whole IBSYS job deck")
    out: str | None = option(None, metavar="FILE", help="write to FILE (default: stdout)")
    json: bool = option(False, help="print the punched cards' texts as one JSON object "
                        "(docs/json.md)")


@command("punch", PunchOptions,
         help="punch a deck's data cards (or a whole job deck) in a card image format",
         description="Read a deck (any card format) and punch its data cards, in the report's "
         "layout (8F10.5, a $DATA card first), as text, binary, column binary (cbn) or BCD "
         "card images, in the 026 or 029 keypunch code.  --job punches a whole IBSYS job "
         "deck: control cards, the listing's FORTRAN source and the data.", core=False)
def punch(o: PunchOptions) -> Answer:
    from deck_emulator.legacy.cardimage import write_images
    from deck_emulator.legacy.deck import DeckError
    from deck_emulator.legacy.jobdeck import data_deck_texts, job_deck_texts

    src = common.load(o, "punch", kinds=("deck",))
    common.check_out(o.out)
    texts = job_deck_texts(list(src.decks)) if o.job else data_deck_texts(list(src.decks))
    try:
        data = write_images(texts, o.to, o.code)
    except DeckError as err:
        raise DeckError(f"cannot punch in the {o.code} code: {err}") from None
    # the JSON: the punched cards as text, whatever the format they were punched in
    return Answer("punch", src.name, settings={"to": o.to, "code": o.code, "job": o.job},
                  notes=list(src.notes), said=list(src.notes),
                  result={"cards": texts, "bytes": len(data)}, text=data, json=o.json,
                  out=o.out)
