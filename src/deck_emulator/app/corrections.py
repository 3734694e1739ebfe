"""``deck-emulator corrections``: the corrections to the scanned listing and the named errata."""

from __future__ import annotations

from deck_emulator.errors import UsageError

from . import Answer, command
from .options import Answering, Common, option, options_class


@options_class
class CorrectionsOptions(Common, Answering):
    key: str | None = option(None, positional=True, metavar="KEY",
                             help="show one entry in full: a departure's number (8), an "
                             "erratum's name (ed-direction) or a note's key")
    all: bool = option(False, help="the whole record and every patch")


def _corrections_list(entries) -> str:
    import textwrap

    kinds = {"departure": "Departures of luminaire.f from the scanned listing",
             "kept": "Kept as printed, although an equation differs",
             "section": "Notes", "erratum": "Errata (applied only with --erratum NAME)"}
    lines = []
    for kind, heading in kinds.items():
        chosen = [e for e in entries if e.kind == kind]
        if chosen:
            lines += ["", heading]
            width = max(len(e.key) for e in chosen)
            lines += [f"  {e.key:<{width}}  "
                      + textwrap.shorten(e.title.replace("**", ""), 100 - width,
                                         placeholder=" ...")
                      for e in chosen]
    lines += ["", "deck-emulator corrections KEY shows one in full; --all the whole record."]
    return "\n".join(lines[1:]) + "\n"


@command("corrections", CorrectionsOptions,
         help="the corrections to the scanned listing and the named errata",
         description="Every place where the transcribed listing (luminaire.f) departs from the "
         "report's scanned listing, with its reason; what is kept as printed; the named errata "
         "and their patches. Read from the installed package.", core=False)
def corrections(o: CorrectionsOptions) -> Answer:
    from deck_emulator.legacy import corrections as record

    if o.all and o.key:
        raise UsageError("corrections: give an entry's KEY or --all, not both")
    entries = record.entries()
    if o.key:
        try:
            entries = [record.find(o.key)]
        except KeyError:
            keys = ", ".join(e.key for e in entries)
            raise UsageError(f"corrections {o.key}: no such entry (there are: {keys})") from None
    listed = not (o.key or o.all)  # the list: keys and titles, not the full texts
    result = {"entries": [{k: v for k, v in vars(e).items() if not (listed and k == "text")}
                          for e in entries]}
    if o.all:
        text = record.document() + "".join(
            f"\n## errata/{n}.patch\n\n{record.patch(n)}" for n in record.ERRATA)
    elif o.key:
        text = entries[0].text.rstrip("\n") + "\n"
    else:
        text = _corrections_list(entries)
    return Answer("corrections", "luminaire.f", result=result, text=text, json=o.json, out=o.out)
