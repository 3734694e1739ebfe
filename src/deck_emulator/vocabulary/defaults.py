"""Every default of the program, one row each: the core's tolerances and bounds, the listing's
step, the grids outcomes are sampled on.

Every layer reads its defaults from here -- the core's ``simulate``, :class:`CoreEngine`,
``deck_emulator.run``, the command line's options and their help, the studies -- so that
``CoreEngine()``, ``deck_emulator.run(..., engine="core")`` and ``deck-emulator core`` are
the same run.  A study that deliberately runs at other settings names its row here too, with
the reason beside it.  Nothing here imports anything (the cache folder reads os when asked):
the command line shows these as its options' defaults without loading numpy or scipy.
"""

# ------------------------------------------------------------------- the listing's own

#: the listing's integration step, s (its literal 0.0004: DELT, and the other literals that
#: mean one step, legacy/fortran's STEP_LITERALS)
LISTING_STEP_S = 0.0004
#: the steps the listing takes before it caps the spring force (IF(LL-20))
LISTING_CAP_STEPS = 20
#: the listing's ground tolerances of its hit tests, ft (labels 91, 95, 103, 141); U (a second
#: luminaire, which the listing has not got) is given R's
LISTING_GROUND_TOLERANCE_FT = {"P": 0.1, "Q": 0.01, "R": 0.1, "C": 0.1, "U": 0.1}
#: ED's |DF| tolerance at labels 15 and 16, rad, as punched (a text: the option ``ed_tolerance``
#: replaces this literal of the listing's statements)
LISTING_ED_TOLERANCE = ".0001"
#: the start-up tilt THA at label 123, rad, as punched (the option ``tha_start`` replaces it)
LISTING_THA_START = "0.000022"

#: the line printer's print positions after the carriage control column (its 132-column
#: forms: the pages of --pages and the forms of the --html dossier)
PRINT_POSITIONS = 132

#: the job decks' made programs kept in the user's cache folder at most (legacy/fortran: the
#: least recently used go)
PROGRAM_CACHE_ENTRIES = 64
#: the largest kept made program read back, bytes (the listing's is about 130 kB): a larger
#: file in an entry's place is not read, and the code is made again
PROGRAM_CACHE_MAX_BYTES = 16 << 20


def user_cache_folder() -> str:
    """The package's folder in the user's cache (``$XDG_CACHE_HOME``, else ``~/.cache``): what
    is made once and kept between runs (a program's made code; numba's machine code where the
    package's own folder cannot be written)."""
    import os

    home = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(home, "deck_emulator")


# ------------------------------------------------------------------- reading a SOURCE

#: the longest a SOURCE that is a FIFO or a pipe may keep its reader waiting for its next
#: bytes (no writer yet, or a writer gone silent), s: a deck is a few hundred bytes, which any
#: writer has sent long before; past it the command is refused rather than left hanging
SOURCE_WAIT_S = 60.0

#: the largest scene file read, bytes (a scene TOML is about 2 kB; a card deck's bound is
#: legacy.jobdeck.MAX_BYTES)
MAX_SCENE_BYTES = 1 << 20
#: what a scene or assembly file (TOML) may hold besides (vocabulary.toml_limits, checked before
#: it is parsed): arrays and inline tables nested at most so deep (a scene nests three), keys
#: of at most so many dotted parts (a scene's have one to three), runs of at most so many
#: digits (a double has 17 significant digits; the parser converts any integer, and Python
#: refuses one of more than 4,300)
MAX_TOML_DEPTH = 16
MAX_TOML_KEY_PARTS = 16
MAX_TOML_DIGITS = 100

# ------------------------------------------------------------------- the emulator's bounds

#: the emulator's bounds on what the listing leaves unbounded (legacy.stops.Limits):
#: iterations of one call of ED, consecutive step halvings at label 108 with no step accepted,
#: simulated time, s (the report needs about 1 s)
ED_ITERATIONS = 100_000
HALVINGS = 40
EMULATOR_T_MAX_S = 5.0
#: statements a run of a FORTRAN program (legacy/fortran: a job deck's own, the listing) may
#: execute, counted across its units, loops and calls (a block's statements when it starts),
#: before it stops as a runaway (exit 3, naming the statement): legacy.stops.Limits.statements,
#: which a caller may set; 2.6 times what the longest run of the listing takes (docs/scale.md,
#: 'Bounds'); a run that takes more steps on purpose (the error study's H/2**k) passes its own
#: budget, scaled with its steps
PROGRAM_STATEMENTS = 5_000_000
#: what a program of the front end's dialect may hold, refused beyond in one line naming the
#: card, its columns and the statement kind (none of them is reached by the listing):
#: continuation cards of one statement (IBM FORTRAN IV's 19: 20 cards of 66 columns);
#: parentheses, argument lists and .NOT. nested in one expression (the made Python's own
#: parser stops at 200 parentheses); the made code's frames one inside the next, 2 a
#: subprogram's call and 1 a statement function's reference (Python's own stack stops at
#: 1,000); the elements of one unit's arrays (the 7094's 32,768 words of core); the digits of
#: a constant or label
PROGRAM_CONTINUATIONS = 19
PROGRAM_NESTING = 40
PROGRAM_CALL_DEPTH = 200
PROGRAM_ARRAY_ELEMENTS = 32_768
PROGRAM_CONSTANT_DIGITS = 40

# ------------------------------------------------------------------- the core

#: a speed (mph) as a deck's VVB (ft/s): -(mph * 88/60) cut towards zero to this many
#: decimals, as the report's decks were punched (40 mph -58.66, steel20.dat's 20 mph -29.33;
#: studies.sweep.vvb_for), for every study that makes a deck of a speed
VVB_DECIMALS = 2

#: the core's model options by default, for every door (the command line's --preset, the
#: engine's CoreEngine): legacy, the listing's quirks, the one comparable with the report
CORE_PRESET = "legacy"
#: the core's integration method: DOP853, or Radau for a contact its springs make stiff
CORE_METHOD = "auto"
#: the core's relative and absolute tolerances (solve_ivp's rtol, atol; the compiled DOP853's)
CORE_RTOL = 1e-10
CORE_ATOL = 1e-10
#: the tightest tolerance the core takes: below it (about 45 ulps of 1.0) the step-size control
#: of solve_ivp cannot meet it and ends in infinities, naming nothing
MIN_TOLERANCE = 1e-14
#: a reference solution's tolerances (the error study's reference, diff's second core column):
#: two orders tighter than the default
REFERENCE_RTOL = 1e-12
REFERENCE_ATOL = 1e-12
#: the tolerance the error study checks its reference at (with Radau and LSODA)
REFERENCE_CHECK_RTOL = 1e-13
#: the largest step the solver may take, s
MAX_STEP_S = 0.005
#: simulated time at most, s
T_MAX_S = 10.0
#: bound on the right-hand-side evaluations of one run (DOP853 takes about 12 a step)
MAX_EVALUATIONS = 5_000_000
#: bound on the wall time of one run, s, and of one batch of runs of the compiled core (its
#: scenes past it are stopped: a starved or suspended machine; a study runs them on resume)
MAX_WALL_S = 60.0
#: how closely the compiled batch (core/batch.py) answers as the scipy path (solve_ivp, the
#: reference) at the default tolerances: event and hit times within this, s; positions within
#: this, ft; speeds lost within this, mph, and decelerations within this, g (tests/core and
#: tests/engine hold it, on the shipped decks and assemblies)
BATCH_AGREE_TIME_S = 1e-6
BATCH_AGREE_POSITION_FT = 1e-4
BATCH_AGREE_DELTA_V_MPH = 1e-6
BATCH_AGREE_DECEL_G = 1e-6
#: the grid a core outcome's arrays are sampled on: in contact with the car, and in free flight, s
SAMPLE_CONTACT_S = 0.0002
SAMPLE_FREE_S = 0.001
#: the sampled arrays a core outcome carries unless a study asks for fewer (what each is:
#: engine.quantities.ARRAYS): the car's, the post's points, the force on the car
OUTCOME_ARRAYS = ("car", "points", "pulse")

# ------------------------------------------------------------------- the scenes' bounds

#: the largest approach angle ALPHA a scene may be given, deg (0 to this, both included): the
#: commands that set the angle (sweep --angles, assembly --alpha-deg) and the stability study,
#: whose largest angle it is (the emulator ends there as the core does: docs/study/stability)
MAX_APPROACH_ANGLE_DEG = 90.0
#: the speeds a command may set a scene's car to, mph (assembly --speed-mph; both included)
SPEED_RANGE_MPH = (1.0, 200.0)
#: the most times diff halves the listing's step (--max-k): 2**8 = 256 times its steps
MAX_HALVINGS = 8

# ------------------------------------------------------------------- the studies' own settings

#: where a command that runs many scenes (sweep, sensitivity, the studies) keeps them as they
#: finish, inside its output folder, for --resume
SCENE_STORE = ".scenes"
#: longest wait for an external Dask scheduler (--scheduler) to take the connection, and then
#: again to answer as a scheduler, s: an address where nothing, or something else, listens is
#: refused after it (each stage its own bound: which one ran out does not hang on the other)
SCHEDULER_CONNECT_S = 10.0
#: longest wait for a worker of an external cluster (at the start, and whenever every worker is
#: gone while scenes remain) before the run ends as failed, s (--worker-wait)
WORKER_WAIT_S = 60.0
#: the waits --worker-wait may be given, s (both included)
WORKER_WAIT_RANGE_S = (1.0, 86400.0)
#: files the embedded runner needs open in its command beside those open before it starts
#: its workers, and more for each worker process (its pipe, its sentinel, the forkserver's
#: handing over), as measured (docs/scale.md, 'Bounds'); a command checks them against the
#: open-file limit before it starts the workers
POOL_FILES = 8
POOL_WORKER_FILES = 3
#: times a batch of scenes is run again on a new worker after the one running it died (killed,
#: out of memory) before its scenes are stored failed (as Dask's allowed-failures, 3)
WORKER_DEATHS_PER_BATCH = 3

#: the stability study's core (and the studies' one-scene core runs, studies.common.run_core):
#: its grid holds scenes up to 1e10 lb/ft springs and 120 mph, where 1e-9 keeps the stiff rows
#: within the runs' wall bound; docs/study/stability was made at it
STUDY_RTOL = 1e-9
#: the stability study's simulated-time bound, s
STUDY_T_MAX_S = 3.0
#: the stability study's emulator bounds, tighter than the emulator's own (ED_ITERATIONS,
#: HALVINGS) so that its hundreds of runs on a 2-core machine stay within minutes: iterations
#: of ED, consecutive halvings (its simulated time is STUDY_T_MAX_S)
STABILITY_ED_ITERATIONS = 20_000
STABILITY_HALVINGS = 30
#: the stability study's agreement between the engines: hit times within this, s, and launch
#: energies within this fraction of each other
STABILITY_AGREE_HIT_S = 0.01
STABILITY_AGREE_KE = 0.10
#: the error study's grid: the points in time the trajectories are compared on
ERROR_GRID_POINTS = 2001
#: the error study's timing: every run (emulator, scipy core, compiled core) once untimed (its
#: answer, and the process warmed up), then this many times, each the wall time of the whole
#: engine call; a point's time is their median, shown with their least and largest
ERROR_TIMED_REPS = 5
#: the BLAS threads every run of the error study runs with (threadpoolctl, in each run): Radau's
#: LU factorisations round differently with 1 and 2 OpenBLAS threads (docs/scale.md, 'Bounds'),
#: and the default count is the machine's cores; 1 is the same on every machine
STUDY_BLAS_THREADS = 1

# ------------------------------------------------------------------- the studies' bounds

#: the most values one axis of a sweep's grid may have
MAX_SWEEP_GRID = 10_000
#: the largest base sample size N of a sensitivity study (a power of two)
MAX_SENSITIVITY_N = 1 << 16
#: a sensitivity study's outcome whose most common value holds in at least this fraction of
#: the scenes gets no indices: constant, or nearly ("constant in 509 of 512 scenes"), so that
#: the few scenes that differ would decide every index (studies.sensitivity.analyse)
SENSITIVITY_CONSTANT_FRACTION = 0.99
#: an index whose 95 % interval, clipped to [0, 1], spans more than this much of [0, 1] is
#: printed as "not resolved at this N", not as a number (studies.sensitivity)
SENSITIVITY_UNRESOLVED_SPAN = 0.5

# ------------------------------------------------------------------- the machine's limits

#: the least address space (ulimit -v) a command that runs the core or starts its own worker
#: processes is started under, MB, refused below it in one line before any work: below it
#: numba's compiler and OpenBLAS abort the process outright (docs/scale.md, 'Bounds')
MIN_ADDRESS_SPACE_MB = 800
