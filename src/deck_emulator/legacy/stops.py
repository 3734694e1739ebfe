"""What a run of the 1967 program gives, and how it stops: the run's records, trace and events
(:class:`Run`), its guards (:class:`Limits`, :class:`EmulatorError`) and the errata, apart from
the FORTRAN front end (:mod:`deck_emulator.legacy.fortran`) that runs it, so that the layers
above read them without loading it."""

from __future__ import annotations

from dataclasses import dataclass, field

from deck_emulator.vocabulary import defaults
from deck_emulator.vocabulary.choices import ERRATA
from deck_emulator.vocabulary.events import Event


class EmulatorError(RuntimeError):
    """The run cannot go on: a guard fired or the arithmetic trapped."""

    def __init__(self, reason, *, label, variable=None, step=0, time=None, guard=None):
        self.reason, self.label, self.variable = reason, label, variable
        self.step, self.time, self.guard = step, time, guard
        where = f"label {label}" + (f", assigning {variable}" if variable else "")
        when = f"step {step}" + (f", t = {time:.6f} s" if time is not None else "")
        super().__init__(f"{reason} at {where} ({when})")


def fault_reason(exc) -> str:
    """What an exception of the arithmetic (or a non-finite value) means, for the message."""
    return {"_NonFinite": "non-finite value (NaN or infinity)",
            "ZeroDivisionError": "division by zero",
            "FloatingPointError": f"floating-point exception ({exc})",
            "ArithmeticFault": f"arithmetic fault ({exc})",
            "OverflowError": "overflow",
            "ValueError": "invalid argument to an intrinsic"}[type(exc).__name__]


#: The trace: the row the program records where a step is accepted (labels 41 and 400), where
#: the post leaves the vehicle (42: the last contact values) and at STOP (82), by phase: the
#: row's key -> the listing's variable (None: 0.0, no such variable in that phase).
TRACE_ROWS = {
    "contact": dict(t="Q", XCM="XCMA", YYCM="YYCMA", ZZCM="ZZCMA", VV="VVA", SV="SVA", FS="FSA",
                    XP="XPA", YYP="YYPA", ZZP="ZZPA", XQ="XQA", YYQ="YYQA", ZZQ="ZZQA",
                    XR="XRA", YYR="YYRA", ZZR="ZZRA", TH="THA", PHI="PHIA", PSI="PSIA",
                    V1="V1A", V2="V2A", V3="V3A", W1="W1A", W2="W2A", W3="W3A"),
    "free": dict(t="T", XCM="XCMFA", YYCM="YYCMFA", ZZCM="ZZCMFA", VV="VVFA", SV="SVFA", FS=None,
                 XP="XPFA", YYP="YYPFA", ZZP="ZZPFA", XQ="XQFA", YYQ="YYQFA", ZZQ="ZZQFA",
                 XR="XRFA", YYR="YYRFA", ZZR="ZZRFA", XC="XCFA", YYC="YYCFA", ZZC="ZZCFA",
                 TH="THFA", PHI="PHIFA", PSI="PSIFA", V1="V1FA", V2="V2FA", V3="V3FA",
                 W1="W1FA", W2="W2FA", W3="W3FA"),
}


def trace_row(phase: str, values, to_float) -> dict:
    """One row of the trace: ``values`` of TRACE_ROWS[phase]'s variables (None skipped), in
    its order, as floats."""
    row, it = {"phase": phase}, iter(values)
    for key, name in TRACE_ROWS[phase].items():
        row[key] = 0.0 if name is None else to_float(next(it))
    return row


@dataclass(frozen=True)
class Limits:
    """Bounds on what the 1967 program leaves unbounded."""

    ed_iterations: int = defaults.ED_ITERATIONS  # per call of ED
    halvings: int = defaults.HALVINGS  # consecutive halvings at label 108, no step accepted
    time_s: float = defaults.EMULATOR_T_MAX_S  # simulated time (the report needs about 1 s)
    #: statements a run executes, across its units, loops and calls (the front end's budget),
    #: at the listing's step: a program whose step is halved k times takes 2**k times as many
    #: steps and gets 2**k times this (:meth:`budget`)
    statements: int = defaults.PROGRAM_STATEMENTS

    def budget(self, step_scale_k: int = 0) -> int:
        """The statements a run at the listing's step / 2**``step_scale_k`` may execute."""
        return self.statements * 2 ** step_scale_k


@dataclass
class Run:
    """What one run of the program produced."""

    records: list[str]
    trace: list[dict] = field(default_factory=list)  # accepted steps, floats
    events: list[Event] = field(default_factory=list)  # what FORMATs 355, 100, 97-248 reported
    arithmetic: str = "double"
    errata: tuple[str, ...] = ()
    step_scale_k: int = 0
    error: EmulatorError | None = None
    #: which WRITE printed which records, in order, where the run was asked to keep them
    #: (the front end's ``Runner.keep_writes``): (index of its first record in ``records``,
    #: unit, the card of the WRITE statement, its FORMAT's label, the values of its list as
    #: floats)
    writes: list[tuple[int, str, int, int, tuple[float, ...]]] = field(default_factory=list)

    def text(self) -> str:
        return "".join(r + "\n" for r in self.records)
