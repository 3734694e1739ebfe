"""What several commands do alike: read SOURCE, make the emulator the options ask for, say
why a run stopped, check and write the output files a command names."""

from __future__ import annotations

import io
import os
import shlex

from deck_emulator.errors import UsageError, address_space_mb, process_limits
from deck_emulator.extras import require
from deck_emulator.vocabulary import defaults

from . import PROG, Answer


def load(options, command: str, kinds=("deck", "scene"), given=None, own_program=False):
    """SOURCE read whole (:func:`deck_emulator.engine.sources.load_source`); what the reader
    says (the job deck's program, warnings) is in its ``notes``; ``own_program``: a job
    deck's own FORTRAN may run (through the front end: its ``fortran``)."""
    from deck_emulator.engine.sources import load_source

    return load_source(options.source if given is None else given,
                       card_format=getattr(options, "card_format", "auto"),
                       keypunch=getattr(options, "keypunch", None),
                       section=getattr(options, "section", None),
                       listing_program=getattr(options, "listing_program", False),
                       kinds=kinds, command=command, own_program=own_program)


def deck_file(given: str, command: str, *, with_sha256: bool = False):
    """A deck that a study reads by its file in every worker: a text deck of one $DATA
    section, read once; its ``path`` is the file (a shipped deck's name resolves to its file);
    ``with_sha256``: ``(deck, the SHA-256 of the bytes read)``, what a resume checks.
    Card images and job decks are refused with the one conversion that makes a text deck."""
    from deck_emulator.engine.sources import load_source, parse_deck
    from deck_emulator.legacy.deck import DeckError

    src = load_source(given, kinds=("deck",), command=command)  # refused or not: no notes yet
    path = given if os.path.exists(given) else src.path
    try:
        plain = parse_deck(src.data, path=path)  # the bytes as a worker's read_deck takes them
    except DeckError:
        plain = None
    if plain is None or len(src.decks) != 1 or plain.values != src.decks[0].values:
        kind = "job deck" if len(src.decks) > 1 or src.program else f"{src.card_format} deck"
        raise UsageError(f"{src.name}: a {kind}; {command} reads a text deck of one $DATA "
                         f"section: `{PROG} punch {given} --to text --out deck.dat` (with "
                         "--section N for a job deck) writes one")
    return (plain, src.sha256) if with_sha256 else plain


def engine_scene(source, name: str = "", *, scene_name: str | None = None):
    """The scene the core would solve for ``source`` (a scene or a deck; a deck's scene named
    ``scene_name``, else ``name``); a deck or scene the core cannot solve (a zero mass, no
    impact point S ...) is bad input: one line naming ``name`` (else the deck's file), exit 2."""
    from deck_emulator.vocabulary.scene import Scene, SceneError

    try:
        if isinstance(source, Scene):
            return source.checked()
        return Scene.from_deck(source, name=name if scene_name is None else scene_name)
    except SceneError as exc:
        where = name or getattr(source, "path", None) or "the deck"
        raise UsageError(f"{where}: the core cannot solve it: {exc}") from None


def emulator(options, *, trace: bool = True, fortran=None):
    """The emulator engine the options (:class:`~.options.Emulator`) ask for; ``fortran``: a
    job deck's own program (:attr:`~deck_emulator.engine.sources.Source.fortran`) to run
    instead of the listing, which takes none of the listing's departures."""
    from deck_emulator.engine import EmulatorEngine, Limits

    assumptions = dict(sincos=options.sincos, decimal=options.decimal,
                       output=options.output_rounding)
    arithmetic = {}
    if options.precision == "ibm7094":
        arithmetic = {k: v for k, v in assumptions.items() if v is not None}
    elif any(v is not None for v in assumptions.values()):
        raise UsageError("--sincos, --decimal and --output-rounding are assumptions of "
                         "--precision ibm7094")
    limits = Limits(ed_iterations=options.max_ed_iterations, halvings=options.max_halvings,
                    time_s=options.max_time)
    if fortran is not None:
        departures = [flag for flag, on in (
            ("--erratum", options.erratum), ("--step-scale", options.step_scale),
            ("--tha-start", options.tha_start is not None),
            ("--ed-tolerance", options.ed_tolerance != defaults.LISTING_ED_TOLERANCE)) if on]
        if departures:
            raise UsageError(f"{', '.join(departures)} change the listing's program, and this "
                             "job deck runs its own FORTRAN: punch the change into its cards, "
                             "or run the listing's with --listing-program")
    return EmulatorEngine(precision=options.precision, errata=tuple(options.erratum),
                          step_scale_k=options.step_scale, tha_start=options.tha_start,
                          ed_tolerance=options.ed_tolerance, limits=limits,
                          arithmetic_options=arithmetic, trace=trace, fortran=fortran)


#: said while numba first compiles the core's batch (what it costs: docs/scale.md); a single
#: scene compiles nothing
COMPILING = f"{PROG}: compiling the core once, about 75 s of CPU"


def compile_core(quiet: bool) -> None:
    """Before a command's first run of the core after an install (or an upgrade): the wait
    for numba's compilation, said as what it is (:func:`deck_emulator.engine.compile_core`)."""
    from deck_emulator.engine import compile_core as compile_once
    from deck_emulator.parallel import busy

    need_address_space("the core")  # below it the compiler aborts the process: no line
    compile_once(lambda: busy(COMPILING, quiet=quiet))


def need_address_space(what: str) -> None:
    """A UsageError (one line) when this process may use less address space than ``what``
    needs (the row ``MIN_ADDRESS_SPACE_MB``)."""
    space = address_space_mb()
    if space is not None and space < defaults.MIN_ADDRESS_SPACE_MB:
        raise UsageError(f"{what} need{'s' if what == 'the core' else ''} "
                         f"{defaults.MIN_ADDRESS_SPACE_MB} MB of address space at the least, "
                         f"under the limits of {', '.join(process_limits())}: raise them")


def with_progress(quiet: bool, engine, source, *, execute: bool = False, watch=None,
                  scene=None):
    """``engine.run(source)`` with the progress display (stderr, a terminal only);
    ``execute``: the emulator's ``engine.execute(source)`` (the program's run, no Outcome);
    ``watch``: called with the emulator's program before it runs (``run --html`` keeps it);
    ``scene``: the core's scene of ``source``, already built (:func:`engine_scene`).
    The core is compiled first where this install has not yet and the run is on the scipy
    path (:func:`compile_core`); one scene on the batch's path runs its functions uncompiled
    (:meth:`~deck_emulator.engine.CoreEngine.run`)."""
    from deck_emulator.parallel import busy

    if engine.name != "emulator":
        if engine.batched is False or engine.method != "auto":  # the scipy path: compiled
            compile_core(quiet)  # (a single scene on the batch's path compiles nothing)
        with busy(f"{PROG}: {engine.name} running", quiet=quiet):
            return engine.run(source, scene=scene)
    programs = []

    def status() -> str:
        return f"step {programs[0].step}" if programs else ""

    def watching(program) -> None:
        programs.append(program)
        if watch is not None:
            watch(program)

    with busy(f"{PROG}: emulator running", quiet=quiet, status=status):
        return (engine.execute if execute else engine.run)(source, watch=watching)


def stopped(out) -> str:
    """Why a run stopped, and what would let it go on."""
    return f"{out.error}" + (f" -- {out.hint}" if out.hint else "")


def odd_deck_notes(out) -> list[str]:
    """Why a well-formed but physically odd deck gives odd numbers (or stops): the run's
    scene, in the deck's names."""
    values = out.scene.deck_values() if out.scene is not None else {}
    notes = []
    for name, what in (("W", "the post's mass"), ("WV", "the car's mass")):
        if values.get(name, 1.0) <= 0:
            notes.append(f"{name} = {values[name]:g} slug: {what} is not positive; what follows "
                         "is what the equations give, not physics")
    for name in ("A", "B", "C"):
        if values.get(name, 1.0) <= 0:
            notes.append(f"{name} = {values[name]:g} slug ft^2: a principal moment of inertia of "
                         "the post is not positive, so the run is not physical")
    if values.get("G", 1.0) <= 0:
        from deck_emulator.vocabulary.units import G_FT_S2

        notes.append(f"G = {values['G']:g} ft/s^2: no gravity (the report's is {G_FT_S2:g}); a "
                     "deceleration in g divides by WV*G, so the printed ones are not given, and "
                     "the post comes down only by the motion the car gave it")
    if values.get("VVB", -1.0) == 0:
        notes.append("VVB = 0: the car does not move, so nothing strikes the post")
    return notes


def failed(out, source) -> str:
    """A stopped run in one line: the engine's line, its hint, and why the deck is odd."""
    notes = odd_deck_notes(out)
    if out.settings.startswith("arithmetic single") and "PHIA" in (out.error or ""):
        notes.append("in binary32 COS(THA) rounds to 1.0 at step 2 and the listing divides "
                     "by zero, where gfortran's trapping single-precision build stops too "
                     "(golden/*.r4.trap; README, 'Single precision')")
    return f"{source}: {stopped(out)}" + "".join(f"; {n}" for n in notes)


def check_out(path: str | None) -> None:
    """The output file's folder must exist and be writable: checked before any work."""
    if path:
        from deck_emulator.files import check_output_file

        check_output_file(path)


def check_trajectory(path: str | None) -> None:
    if path:
        require("frames")
        if not path.endswith((".csv", ".parquet")):
            raise UsageError(f"--trajectory {path}: a .csv or .parquet file")
        check_out(path)


def write_trajectory(path: str | None, out) -> str | None:
    """The outcome's :meth:`~deck_emulator.engine.Outcome.trajectory_frame` to ``path``
    (written whole or not at all), what a stopped run computed included; the line to say."""
    if not path:
        return None

    from deck_emulator.files import write_file

    frame = out.trajectory_frame()
    if path.endswith(".parquet"):
        buffer = io.BytesIO()
        frame.to_parquet(buffer, index=False)
        write_file(path, buffer.getvalue())
    else:
        write_file(path, frame.to_csv(index=False))
    return f"wrote the trajectory ({len(frame)} samples) to {path}"


def scheduler(options):
    """The external cluster the options name (None: the embedded one, whose worker processes
    this process starts: refused under too small an address space); imported when asked, so
    that a command that runs no study does not load the scene runner."""
    if not options.scheduler:
        need_address_space("the worker processes")
        return None
    from deck_emulator.studies.cluster import Scheduler
    from deck_emulator.vocabulary.defaults import WORKER_WAIT_S

    wait = options.worker_wait
    return Scheduler(options.scheduler, WORKER_WAIT_S if wait is None else float(wait))


def outputs_result(out_dir) -> dict:
    """The JSON keys of a command that writes a folder: the files it holds."""
    return {"outputs": sorted(os.path.join(out_dir, n) for n in os.listdir(out_dir)
                              if not n.startswith(".")
                              and os.path.isfile(os.path.join(out_dir, n)))}


def outcome_answer(name: str, out, source: str, settings: dict, o) -> Answer:
    """An outcome as the answer of ``summary``, ``core`` or ``assembly`` (its text made by
    :func:`rendered` once the caller's notes are in): the registry's quantities, and for a
    run that stopped what it reached, status ``stopped``, and why."""
    from deck_emulator.present.answers import outcome_result

    answer = Answer(name, source, settings=settings, result=outcome_result(out),
                    notes=odd_deck_notes(out), json=o.json, out=o.out)
    if out.error is not None:  # what it reached is answered; the status says it stopped
        answer.status, answer.error = "stopped", failed(out, source)
    return answer


def rendered(answer: Answer) -> str | None:
    """The answer's text, made from its document; None for a JSON answer, which prints the
    document itself (:meth:`Answer.printed`): the document is made once either way."""
    from deck_emulator.present.answers import render_outcome

    return None if answer.json else render_outcome(answer.document())


def study_answer(name: str, o, run) -> Answer:
    """A study's command: the deck checked, the folder checked, the study run, its lines.
    ``run(deck, sha256, jobs, command)``: the deck read (None: the study's own) and the
    SHA-256 of its bytes."""
    from deck_emulator.files import check_output_dir

    require("studies")
    text = sha256 = None
    if o.deck:  # read once: the study and its workers take this deck, its store this SHA-256
        text, sha256 = deck_file(o.deck, f"study {name}", with_sha256=True)
        engine_scene(text, name=text.path)  # both engines run it: exit 2
    check_output_dir(o.out)  # before any work, and before the study makes the folder
    jobs = o.jobs or os.cpu_count() or 1
    typed = o.command_line or shlex.join(  # called from Python: the command it stands for
        ["deck-emulator", "study", name, *([o.deck] if o.deck else []), "--out", o.out,
         *(["--quick"] if o.quick else []), "--jobs", str(jobs)])
    compile_core(o.quiet)  # both engines run every scene
    summary, lines = run(text, sha256, jobs, typed)
    answer = Answer(f"study {name}", o.deck or "steel40", json=o.json)
    answer.said = [f"study {name}: {line}" for line in
                   lines + [f"wrote {o.out} in {summary['wall_s']:.0f} s"]]
    answer.result = outputs_result(o.out)
    return answer
