"""``deck-emulator diff``: run the emulator and the modern core on a deck and compare them."""

from __future__ import annotations

import os

from deck_emulator.errors import RunFailed, UsageError
from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.choices import ARITHMETICS

from . import Answer, command
from . import common
from .groups import Cluster
from .options import Answering, Errata, max_k, option, options_class, Source, tolerance


@options_class
class DiffOptions(Source, Errata, Cluster, Answering):
    precision: str = option("double", choices=ARITHMETICS,
                            help="the emulator's arithmetic at k = 0 (must run the deck to its "
                            "end)")
    max_k: int = option(4, parse=max_k, metavar="K",
                        help=f"halve the step up to K times, 0 <= K <= {defaults.MAX_HALVINGS} "
                        f"(default %(default)s; K = {defaults.MAX_HALVINGS} runs the listing's "
                        f"steps {2 ** defaults.MAX_HALVINGS} times over)")
    rtol: float = option(defaults.CORE_RTOL, parse=tolerance,
                         help="the core's tolerance, rtol = atol, 0 < RTOL < 1 (default "
                         "%(default)g)")
    as_printed_ed: bool = option(False, help="keep ED's tolerance "
                                 f"{defaults.LISTING_ED_TOLERANCE} at every k (the scheme "
                                 "then does not converge)")
    as_printed_rows: bool = option(False, help="run the halved steps with only the errata asked "
                                   "for (default: with ed-direction as well, since as printed "
                                   "ED walks away from its root on every deck once the step is "
                                   "halved, and the run stops: exit 3)")
    html: str | None = option(None, metavar="FILE.html",
                              help="also write the diff as one self-contained HTML page: the "
                              "emulator and the core side by side with their differences, and "
                              "the convergence (docs/dossier.md)")
    store: str | None = option(None, metavar="DIR",
                               help="keep the runs in DIR as they finish (default: a temporary "
                               "folder)")


@command("diff", DiffOptions,
         help="run the emulator and the modern core on a deck and compare them",
         description="Side by side: the emulator (the listing as printed, or with errata) and "
         "the core's legacy preset; then both again as the step is halved k = 0..K times, with "
         "the observed order of convergence. The halved steps apply the erratum ed-direction "
         "(said in the table's heading) unless --as-printed-rows: as printed, ED does not find "
         "its root once the step is halved. Exit status 3 when any run stopped (the table says "
         "which and why).")
def diff(o: DiffOptions) -> Answer:
    common.require("studies")
    from deck_emulator.studies.diff import DiffStopped, diff_deck, format_diff

    src = common.load(o, "diff", kinds=("deck",))
    deck = src.deck("diff")
    common.engine_scene(deck, name=src.name)  # the core must be able to solve it: exit 2
    common.check_out(o.out)
    if o.html:
        from .dossier import check_html

        check_html(o.html, o.out)
    if o.resume and not o.store:
        raise UsageError("--resume needs --store DIR (the folder the runs were stored in)")
    common.compile_core(o.quiet)
    try:
        data = diff_deck(deck, precision=o.precision, errata=tuple(o.erratum),
                         ks=range(o.max_k + 1), rtol=o.rtol, atol=o.rtol,
                         tighten_ed=not o.as_printed_ed,
                         ed_direction_rows=not o.as_printed_rows, jobs=o.jobs,
                         scheduler=common.scheduler(o), store_dir=o.store, resume=o.resume,
                         quiet=o.quiet, desc="deck-emulator: diff",
                         # the file's SHA-256 from the bytes read above (a resume checks it)
                         files={deck.path: src.sha256} if deck.path and src.data is not None
                         and os.path.isfile(deck.path) else {})
    except DiffStopped as exc:
        raise RunFailed(str(exc)) from None
    text = format_diff(data)
    settings = {k: data.pop(k) for k in ("precision", "errata", "row_errata", "core_method",
                                         "core_rtol", "ed_tolerance_scaled")}
    data.pop("deck")
    stopped = next((r["stopped"] for r in data["convergence"] if r.get("stopped")), None)
    said = list(src.notes)
    if o.html:
        from deck_emulator.files import write_file
        from deck_emulator.present.dossier import diff_page

        write_file(o.html, diff_page(name=src.name, text=text, data=data, settings=settings,
                                     stopped=stopped))
        said.append(f"wrote the diff's page to {o.html}")
    return Answer("diff", src.name, settings=settings, notes=list(src.notes),
                  said=said, result=data, text=text, json=o.json, out=o.out,
                  status="stopped" if stopped else "ok", error=stopped)
