"""The bounds on one run of the core, with no import of the solver (the command line shows
them as its options' defaults without loading scipy)."""

#: the largest step the solver may take (s)
DEFAULT_MAX_STEP_S = 0.005
#: simulated time at most (s)
DEFAULT_T_MAX_S = 10.0
#: bound on the right-hand-side evaluations of one run (DOP853 takes about 12 a step)
DEFAULT_MAX_EVALUATIONS = 5_000_000
#: bound on the wall time of one run (s)
DEFAULT_MAX_WALL_S = 60.0
