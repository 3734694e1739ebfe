"""The 1967 program, MAIN and SUBROUTINE ED of ``legacy/luminaire.f``, statement for statement.

Fidelity, not beauty. The FORTRAN names are kept (``V1B``, ``THA``, ``PSIFA`` ...), each labelled
statement starts a block of the label machine (:meth:`Program._dispatch` runs block after block,
each returning the label it goes to: a ``GO TO``, an arithmetic IF's branch, or the label that
follows), every arithmetic IF is a three-way branch on ``sign`` with the listing's targets, and
integer variables (``I``, ``M``, ``N``, ``LL``, ``L``) stay Python ints. All real arithmetic goes
through an :class:`~deck_emulator.legacy.arithmetic.Arithmetic`: its number type's operators, its
``decimal`` for every literal and deck field, its ``sin``/``cos``; so the same text runs in
binary64, binary32 or the IBM 7094's words.

Departures from the listing are options, off by default:

* ``errata``: ``"ed-direction"`` (legacy/errata/ed-direction.patch, see CORRECTIONS.md);
* ``step_scale_k``: divide every literal that means "one step" by ``2**k`` (the front end's
  ``legacy.fortran.STEP_LITERALS``);
* ``tha_start``: the start-up value of THA at label 123 (printed: 0.000022);
* ``ed_tolerance``: ED's |DF| tolerance at labels 15 and 16 (printed: .0001 rad). It does not
  shrink with the step, so the listing's scheme stops converging as H is halved (measured by
  ``deck-emulator diff``); tightening it with H restores first order.

Guards end what the 1967 program could not: ED's search without a root, label 108 halving for
ever, a post that never lands, and any non-finite value (see :class:`Limits`); each raises
:class:`EmulatorError` naming the label, the statement's variable, the step and the time.

Speed (binary64): the values are Python floats and the sines and cosines the C library's own;
finiteness is checked once per block, on the variables the block assigns (found in this text
by a pattern, and kept in emulator_tables.py while this text is unchanged), not on every
assignment. When a block leaves a NaN or an infinity, or the
arithmetic raises, the run is replayed from the start in the checking mode, where every
assignment is checked, so the error names the statement exactly as before; the program is
deterministic, so the replay reaches the same point. The other arithmetics always check every
assignment (their own operations trap first anyway).
"""

from __future__ import annotations

import linecache
import math
import operator

from deck_emulator.legacy.arithmetic import Arithmetic, ArithmeticFault, get_arithmetic
from deck_emulator.legacy.printer import Printer, event_for
from deck_emulator.legacy.stops import (  # noqa: F401  (the run and its stops: shared)
    ERRATA, TRACE_ROWS, EmulatorError, Limits, Run, fault_reason, halving_error, time_error,
    trace_row)

from . import emulator_tables as made
from .emulator_text import _assigned_names, read_tables



class _Vars:
    """The variables of one program unit. A variable read before any assignment is zero, as in
    the 7094's cleared core (and gfortran's -fno-automatic -finit-local-zero): INTEGER by
    FORTRAN's implicit rule (I-N) or REAL. Every variable the program text names (``v.NAME``,
    found in this file's text: emulator_tables.py) is set to its zero when the unit is made,
    so that no read needs a ``__getattr__`` fallback (whose mere presence makes every
    attribute read of the class about twice as slow in CPython). Assignments are not checked
    here: the label machine checks each block's variables when the block ends (see
    Program._dispatch)."""

    def __init__(self, isfinite, zero):
        object.__setattr__(self, "_isfinite", isfinite)
        object.__setattr__(self, "_zero", zero)
        for name in _VARIABLES:
            object.__setattr__(self, name, 0 if name[0] in "IJKLMN" else zero)


class _CheckedVars(_Vars):
    """The checking mode: every assignment of a real is checked, and a NaN or an infinity stops
    the run at that statement (as gfortran's trapping build does)."""

    def __setattr__(self, name, value):
        if type(value) is not int and not self._isfinite(value):
            raise _NonFinite(name)
        object.__setattr__(self, name, value)


class _Replay(Exception):
    """The fast run met a non-finite value or a fault: replay the run in the checking mode."""


def _if_float(x, neg, zero, pos):
    """Arithmetic IF on a Python int or float (a minus zero is zero; a NaN goes to zero, as
    ``Arithmetic.sign`` sends it)."""
    return neg if x < 0 else pos if x > 0 else zero


def _square(x):
    return x*x


class _NonFinite(ArithmeticError):
    def __init__(self, name):
        super().__init__(name)
        self.name = name


class ED:
    """SUBROUTINE ED(W1A,W2A,W3A,THDB,PHIDB,PSIDB,HI,D,PSIB,THB): the implicit trapezoid step
    for PSI by a root search on DF. ``L`` and ``DH`` are static and start at zero, as on IBSYS
    (and gfortran with -fno-automatic -finit-local-zero). Returns D."""

    def __init__(self, ar: Arithmetic, errata: tuple[str, ...], max_iterations: int,
                 tolerance: str = ".0001", *, check: bool = True):
        self.ar = ar
        # check D and DH after every label (the checking mode); binary64's unchecked run leaves
        # it to the block that called ED (L44, L57 assign D: a non-finite D replays the run)
        self.check = check
        self.L = 0
        self.DH = ar.decimal("0.0")
        self.H = ar.decimal("0.0")
        self.towards_root = "ed-direction" in errata
        self.max_iterations = max_iterations
        self.iterations = 0
        self.label = 0
        k = ar.decimal
        # .0001 is the listing's |DF| tolerance (labels 15, 16); ``tolerance`` replaces it
        self.K2, self.K015, self.K001, self.K00001 = k("2."), k(".15"), k("0.01"), k(tolerance)

    def __call__(self, W1A, W2A, W3A, THDB, PHIDB, PSIDB, HI, PSIB, THB):
        ar, K2 = self.ar, self.K2
        sin, cos, sign = ar.sin, ar.cos, ar.sign

        # DF(D)=D-((HI/2.)*(W3A+(COS((HI/2.)*(W2A*COS(D)+W1A*SIN(D)+THDB)+THB)/SIN((HI/2.)*
        # (W2A*COS(D)+W1A*SIN(D)+THDB)+THB))*(W1A*COS(D)-W2A*SIN(D))+PSIDB)+PSIB): each
        # subexpression the statement function writes twice is computed once, in the order of
        # its first appearance (the same operations on the same operands: the same value, and a
        # fault at the same point), and DF of the argument it was last called with is that
        # value again (labels 3 and 4 ask DF(DH) twice): the same printout, bit for bit
        last = [None, None]

        def DF(D):
            if D is last[0]:
                return last[1]
            h2 = HI/K2
            cD = cos(D)
            a = W2A*cD
            sD = sin(D)
            x = h2*(a+W1A*sD+THDB)+THB
            value = D-(h2*(W3A+(cos(x)/sin(x))*(W1A*cD-W2A*sD)+PSIDB)+PSIB)
            last[0], last[1] = D, value
            return value

        def IF(x, neg, zero, pos):
            s = sign(x) if type(x) is not int else (x > 0) - (x < 0)
            return neg if s < 0 else zero if s == 0 else pos

        if getattr(ar, "native_float", False):
            IF = _if_float  # noqa: F811  (the same three-way branch, on a float)
        isfinite, check = ar.isfinite, self.check

        # +1 where the erratum makes labels 1 and 15 step towards the root
        up = self.towards_root
        # the static L, DH, H live in this object between calls; within a call they are locals
        # (written back when ED returns or stops)
        L, DH, H = self.L, self.DH, self.H
        iterations, max_iterations = 0, self.max_iterations
        lab = cur = 0  # entry
        D = None
        try:
            while True:
                cur = lab  # the label being executed (named by any error)
                iterations += 1
                if iterations > max_iterations:
                    shown = ", ".join(f"{n} = {ar.to_float(x):.6g}" for n, x in
                                      (("D", D), ("DH", DH), ("H", H)) if x is not None)
                    raise EmulatorError(
                        f"ED's root search did not converge in {max_iterations} iterations "
                        f"({shown or 'before D was set'})",
                        label=f"ED {lab}", guard="ed_iterations")
                if lab == 0:
                    lab = IF(L - 25, 21, 21, 22)  # IF(L-25)21,21,22  (integer)
                elif lab == 21:
                    D = self.K015  # 21 D=.15
                    H = -self.K001
                    lab = IF(DF(D), 1, 20, 10)
                elif lab == 22:
                    D = PSIB  # 22 D=PSIB
                    H = -self.K001
                    lab = IF(DF(D), 1, 20, 10)
                # ROOT GOES NEGATIVE TO POSITIVE
                elif lab == 1:
                    DH = D - H if up else D + H  # 1 DH=D+H  (erratum: D-H)
                    lab = IF(DF(DH), 2, 20, 15)
                elif lab == 2:
                    D = DH
                    lab = 1
                elif lab == 15:
                    DH = D - H / K2 if up else D + H / K2  # 15 DH=D+H/2. (erratum: D-H/2.)
                    lab = IF(abs(DF(DH)) - self.K00001, 20, 20, 4)
                elif lab == 4:
                    lab = IF(DF(DH), 5, 20, 3)
                elif lab == 3:
                    H = H / K2
                    lab = 15
                elif lab == 5:
                    D = DH
                    H = H / K2
                    lab = 15
                # ROOT GOES POSITIVE TO NEGATIVE
                elif lab == 10:
                    DH = D + H
                    lab = IF(DF(DH), 16, 20, 11)
                elif lab == 11:
                    D = DH
                    lab = 10
                elif lab == 16:
                    DH = D + H / K2
                    lab = IF(abs(DF(DH)) - self.K00001, 20, 20, 13)
                elif lab == 13:
                    lab = IF(DF(DH), 12, 20, 14)
                elif lab == 12:
                    H = H / K2
                    lab = 16
                elif lab == 14:
                    D = DH
                    H = H / K2
                    lab = 16
                elif lab == 20:
                    D = DH  # 20 D=DH
                    L = L + 1
                    return D
                if check and (not isfinite(DH) or (D is not None and not isfinite(D))):
                    raise _NonFinite("DH" if not isfinite(DH) else "D")
        finally:
            self.L, self.DH, self.H = L, DH, H
            self.iterations, self.label = iterations, cur


class Program:
    """MAIN of the listing, over one arithmetic, for one deck."""

    def __init__(self, deck, arithmetic: Arithmetic | str = "double", *, errata=(),
                 step_scale_k: int = 0, tha_start: str | None = None, ed_tolerance: str = ".0001",
                 limits: Limits = Limits(), trace: bool = True, checking: bool = False):
        self.ar = get_arithmetic(arithmetic) if isinstance(arithmetic, str) else arithmetic
        unknown = set(errata) - set(ERRATA)
        if unknown:
            raise ValueError(f"unknown erratum {sorted(unknown)}: known are {sorted(ERRATA)}")
        self.errata = tuple(errata)
        self.k = int(step_scale_k)
        if self.k < 0:
            raise ValueError("step_scale_k must be >= 0")
        self.tha_start = tha_start
        self.limits = limits
        self.deck = deck
        self.keep_trace = trace
        self.options = dict(errata=errata, step_scale_k=step_scale_k, tha_start=tha_start,
                            ed_tolerance=ed_tolerance, limits=limits, trace=trace)
        # binary64 runs unchecked and checks once per block; an arithmetic whose every value is
        # finite (the 7094's words: overflow faults) runs unchecked; binary32 checks every
        # assignment. A fault in an unchecked run replays it in the checking mode.
        native = bool(getattr(self.ar, "native_float", False))
        self.fast = (native or bool(getattr(self.ar, "always_finite", False))) and not checking
        self.check_blocks = native and self.fast
        self._underflows_at_start = getattr(getattr(self.ar, "indicators", None), "underflows", 0)
        self.v = (_Vars if self.fast else _CheckedVars)(self.ar.isfinite, self.ar.decimal("0.0"))
        # the literals of the program text, converted by the arithmetic once per run
        self._consts = {text: self.ar.decimal(text) for text in _LITERALS}
        if tha_start is not None:
            self._consts[tha_start] = self.ar.decimal(tha_start)
        self._steps = {}
        for text in _STEP_LITERALS:
            c = self._consts[text]
            for _ in range(self.k):
                c = c / self._consts["2."]
            self._steps[text] = c
        self.K = self._consts.__getitem__  # K("0.01"): a literal of the program text
        self.KSTEP = self._steps.__getitem__  # KSTEP("0.0004"): a literal meaning one step
        if self.fast:
            self.P2 = _square  # X**2 is X*X, one multiplication, in every arithmetic
        if self.check_blocks:
            self.IF = _if_float
        self.free_flight = False
        self.ed = ED(self.ar, self.errata, limits.ed_iterations, ed_tolerance,
                     check=not self.check_blocks)
        self.ed_tolerance = ed_tolerance
        rounding = getattr(self.ar, "format_rounding", lambda: "nearest")()
        self.printer = Printer(self.ar.exact, rounding, binary=getattr(self.ar, "binary", False))
        self.run_ = Run(records=self.printer.records, arithmetic=self.ar.describe(),
                        errata=self.errata, step_scale_k=self.k)
        self.label = "START"
        self.step = 0
        self.halvings = 0
        self.checked_point = None  # the point the free-flight checks are on: P, R or C

    # -- helpers -------------------------------------------------------------------------------
    # K(text): a literal of the program text, converted by the arithmetic once per run (bound in
    # __init__ to a dict look-up); KSTEP(text): a literal that means one step, divided by 2**k
    # under ``step_scale_k``. Both tables are made from this file's text (_LITERALS).

    def IF(self, x, neg, zero, pos):
        """Arithmetic IF: three-way branch on the sign of x (a minus zero is zero)."""
        s = self.ar.sign(x) if type(x) is not int else (x > 0) - (x < 0)
        return neg if s < 0 else zero if s == 0 else pos

    def P2(self, x):
        """X**2."""
        return self.ar.ipow(x, 2)

    def time(self):
        """Simulated time: Q in contact, T in free flight."""
        return self.ar.to_float(self.v.T if self.free_flight else self.v.Q)

    def _record(self, phase: str):
        if not self.keep_trace:
            return
        v = self.v
        row = trace_row(phase, [getattr(v, n) for n in TRACE_ROWS[phase].values() if n],
                        self.ar.to_float)
        self.run_.trace.append(row)

    def _event(self, label: int, t):
        self.run_.events.append(event_for(label, self.ar.to_float(t), self.checked_point))

    # -- the label machine ---------------------------------------------------------------------
    def run(self) -> Run:
        """Run to STOP. Raises EmulatorError (with ``.run`` holding the records so far)."""
        try:
            with self.ar.trapping():
                self._dispatch()
        except _Replay:
            return self._replay()
        except EmulatorError as exc:
            if exc.guard == "ed_iterations":  # raised inside ED, which knows no step or time
                exc = EmulatorError(exc.reason, label=exc.label, step=self.step,
                                    time=self.time(), guard=exc.guard)
            self._fail(exc)
        except (_NonFinite, ZeroDivisionError, FloatingPointError, ArithmeticFault, OverflowError,
                ValueError) as exc:
            if isinstance(exc, ValueError) and "math domain" not in str(exc):
                raise
            if self.fast:  # name the statement as the checking mode does
                return self._replay()
            variable = exc.name if isinstance(exc, _NonFinite) else _assigned_variable(exc)
            label = self.ed.label if variable in ("D", "DH") or _in_ed(exc) else self.label
            label = f"ED {label}" if _in_ed(exc) or variable in ("D", "DH") else label
            self._fail(EmulatorError(fault_reason(exc), label=label, variable=variable, step=self.step,
                                     time=self.time(), guard="arithmetic"))
        return self.run_

    def _replay(self) -> Run:
        """The run again from the start in the checking mode (see the module docstring)."""
        indicators = getattr(self.ar, "indicators", None)
        if indicators is not None:  # count the 7094's underflows of one run only
            indicators.underflows = self._underflows_at_start
        return Program(self.deck, self.ar, checking=True, **self.options).run()

    def _fail(self, exc: EmulatorError):
        self.run_.error = exc
        exc.run = self.run_
        raise exc

    def _dispatch(self):
        blocks = self._blocks()
        checks = self._checks()
        IF = self.IF
        if not self.check_blocks:
            lab = "START"
            while lab is not None:
                self.label = lab
                if lab in checks:
                    if lab in _CHECK_STARTS:
                        self.checked_point = _CHECK_STARTS[lab]
                    x, neg, zero, pos = checks[lab]
                    lab = IF(x(), neg, zero, pos)
                else:
                    lab = blocks[lab]()
            return
        # binary64: each block's assigned reals are checked when the block ends.  One look-up
        # a label: label -> (block, the getter of its assigned values), label -> (check,
        # targets, the point a series of checks starts on); the IF is _if_float's, inline.
        v, isfinite = self.v, math.isfinite
        steps = {lab: (fn, _ASSIGNED.get(fn.__name__)) for lab, fn in blocks.items()}
        tests = {lab: (*check, _CHECK_STARTS.get(lab)) for lab, check in checks.items()}
        lab = "START"
        while lab is not None:
            self.label = lab
            test = tests.get(lab)
            if test is not None:
                x, neg, zero, pos, point = test
                if point is not None:
                    self.checked_point = point
                x = x()
                lab = neg if x < 0 else pos if x > 0 else zero  # IF(x)neg,zero,pos
                continue
            block, got = steps[lab]
            try:
                nxt = block()
            except EmulatorError:  # a guard: genuine only if the block's values are finite
                if got is not None and not isfinite(sum(got(v))):
                    raise _Replay from None
                raise
            if got is not None and not isfinite(sum(got(v))):
                raise _Replay  # (or the sum overflowed: the replay then runs to the end)
            lab = nxt
        if not all(isfinite(x) for x in vars(v).values() if type(x) is float):
            raise _Replay

    def _blocks(self):
        return {
            "START": self.L_start, 125: self.L125, 123: self.L123, 44: self.L44, 124: self.L124,
            83: self.L83, 84: self.L84, 356: self.L356, 357: self.L357, 358: self.L358,
            501: self.L501, 502: self.L502, 504: self.L504, 600: self.L600, 102: self.L102,
            101: self.L101, 104: self.L104, 85: self.L85, 105: self.L105, 107: self.L107,
            106: self.L106, 87: self.L87, 88: self.L88, 54: self.L54, 55: self.L55, 43: self.L43,
            56: self.L56, 350: self.L350, 351: self.L351, 352: self.L352, 353: self.L353,
            108: self.L108, 41: self.L41, 354: self.L354, 42: self.L42, 57: self.L57,
            80: self.L80, 98: self.L98, 77: self.L77, 82: self.L82,
            140: self.L140, 96: self.L96, 93: self.L93, 109: self.L109, 236: self.L236,
            238: self.L238, 240: self.L240, 247: self.L247, 400: self.L400,
        }

    def L_start(self):
        v, K, ar = self.v, self.K, self.ar
        d = self.deck
        for name in d.values:  # READ(5,1)...READ(5,130): the fields, converted by the arithmetic
            setattr(v, name, ar.decimal(d.fields[name]))
        sin, cos = ar.sin, ar.cos
        v.HI = self.KSTEP("0.0004")
        v.E = K("0.0")
        v.I = 0
        v.M = 0
        v.H = self.KSTEP("0.0004")
        v.Q = K("0.0")
        v.LL = 0
        v.N = 0
        v.K = 0
        v.YPO = v.YYPO*cos(v.DELTA)+v.ZZPO*sin(v.DELTA)
        v.ZPO = -v.YYPO*sin(v.DELTA)+v.ZZPO*cos(v.DELTA)
        v.YQO = v.YYQO*cos(v.DELTA)+v.ZZQO*sin(v.DELTA)
        v.ZQO = -v.YYQO*sin(v.DELTA)+v.ZZQO*cos(v.DELTA)
        v.YSO = v.YYSO*cos(v.DELTA)+v.ZZSO*sin(v.DELTA)
        v.ZSO = -v.YYSO*sin(v.DELTA)+v.ZZSO*cos(v.DELTA)
        v.YTO = v.YYTO*cos(v.DELTA)+v.ZZTO*sin(v.DELTA)
        v.ZTO = -v.YYTO*sin(v.DELTA)+v.ZZTO*cos(v.DELTA)
        v.YRO = v.YYRO*cos(v.DELTA)+v.ZZRO*sin(v.DELTA)
        v.ZRO = -v.YYRO*sin(v.DELTA)+v.ZZRO*cos(v.DELTA)
        v.YCO = v.YYCO*cos(v.DELTA)+v.ZZCO*sin(v.DELTA)
        v.ZCO = -v.YYCO*sin(v.DELTA)+v.ZZCO*cos(v.DELTA)
        v.XVSO = v.XSO*cos(v.ALPHA)-v.YYSO*sin(v.ALPHA)
        v.XVTO = v.XTO*cos(v.ALPHA)-v.YYTO*sin(v.ALPHA)
        # DELTA and ALPHA never change after the READ: their cosines and sines, just computed
        # above, serve the free flight's every COS(DELTA) ... SIN(ALPHA) (the same values)
        self.trig_delta_alpha = (cos(v.DELTA), sin(v.DELTA), cos(v.ALPHA), sin(v.ALPHA))
        if self.check_blocks and not all(map(math.isfinite, (getattr(v, n) for n in d.values))):
            raise _Replay
        return 125

    def L125(self):  # 125 CONTINUE
        self.step += 1
        return self.IF(self.v.Q - self.KSTEP("0.0004"), 123, 44, 44)

    def L123(self):  # 123: the start-up of the first step
        v, K = self.v, self.K
        v.W1A = K("0.0")
        v.W2A = K("0.0545")
        v.W3A = K("0.0")
        v.FSB = K("10000.0")
        v.F1B = -K("10000.0")
        v.THDA = K("0.0545")
        v.PHIDA = K("0.0")
        v.PSIDA = K("0.0")
        v.THA = K(self.tha_start) if self.tha_start is not None else self.KSTEP("0.000022")
        v.PHIA = K("0.0")
        v.PSIA = K("0.0")
        return 124

    def L44(self):  # 44: angular velocities 1,2,3; Euler angles; their rates
        v, K, ar = self.v, self.K, self.ar
        sin, cos = ar.sin, ar.cos
        H, A, B, C = v.H, v.A, v.B, v.C
        v.W1A = ((H*v.T1B)/A)+H*(((B-C)/A)*v.W2B*v.W3B)+v.W1B
        v.W2A = (H/B)*v.T2B+H*(((C-A)/B)*v.W1B*v.W3B)+v.W2B
        v.W3A = (H/C)*v.T3B+H*(((A-B)/C)*v.W1B*v.W2B)+v.W3B
        # CALL ED(W1A,W2A,W3A,THDB,PHIDB,PSIDB,HI,D,PSIB,THB)
        v.D = self.ed(v.W1A, v.W2A, v.W3A, v.THDB, v.PHIDB, v.PSIDB, v.HI, v.PSIB, v.THB)
        v.PSIA = v.D
        v.PSIAD = v.PSIA*K("57.3")
        v.PFORK = (v.W1A*cos(v.PSIA))-(v.W2A*sin(v.PSIA))
        v.THA = (H/K("2."))*(v.W2A*cos(v.PSIA)+v.W1A*sin(v.PSIA)+v.THDB)+v.THB
        v.THAD = v.THA*K("57.3")
        v.PHIA = (H/K("2."))*((((sin(v.THA))*v.PFORK)/((cos(v.THA))*cos(v.THA)-K("1.0")))+v.PHIDB)+v.PHIB
        v.PHIAD = v.PHIA*K("57.3")
        v.THDA = (v.W2A/cos(v.PSIA))+((sin(v.PSIA))/cos(v.PSIA))*v.PFORK
        v.PHIDA = (-K("1.0")/sin(v.THA))*v.PFORK
        v.PSIDA = v.W3A-(cos(v.THA))*v.PHIDA
        return 124

    def _rotation(self, SQ, ET, ZE, CH):
        """The nine parenthesised rotation terms of a point's statements (eq. 3.21), from the
        rotation parameters (SQUIG, ETA, ZETA, CHI), in the order _point uses them: every
        point of a step has the same nine, so they are computed once per step.  Each is the
        listing's own grouping, and the same operations on the same operands give the same
        value in every arithmetic (X**2 is one multiplication, X*X, in each), so the points
        come out bit for bit as if each statement computed them (the goldens and the ibm7094
        printouts check it).  One thing differs: the 7094's underflow count (never printed)
        counts an underflowing square once per step rather than once per use."""
        P2 = self.P2
        SQ2, ET2, ZE2, CH2 = P2(SQ), P2(ET), P2(ZE), P2(CH)
        SQET, ZECH, SQZE, ETCH, ETZE, SQCH = (SQ*ET), (ZE*CH), (SQ*ZE), (ET*CH), (ET*ZE), (SQ*CH)
        return ((SQ2-ET2-ZE2+CH2), (SQET-ZECH), (SQZE+ETCH),
                (SQET+ZECH), (-SQ2+ET2-ZE2+CH2), (ETZE-SQCH),
                (SQZE-ETCH), (ETZE+SQCH), (-SQ2-ET2+ZE2+CH2))

    def _point(self, XO, YO, ZO, CM, ROT):
        """The three statements XxA=..., YxA=..., ZxA=... of a point of the post (eq. 3.21),
        written once with the listing's grouping; ROT = self._rotation(SQUIG, ETA, ZETA, CHI):
        XxA=XCMA+(XxO)*(SQUIGA**2-ETAA**2-ZETAA**2+CHIA**2)+(2.*YxO)*((SQUIGA*ETAA)-(ZETAA*CHIA))
        +(2.*ZxO)*((SQUIGA*ZETAA)+(ETAA*CHIA)), and likewise YxA and ZxA."""
        K2 = self.K("2.")
        R11, R12, R13, R21, R22, R23, R31, R32, R33 = ROT
        XCM, YCM, ZCM = CM
        X = XCM+(XO)*(R11)+(K2*YO)*(R12)+(K2*ZO)*(R13)
        Y = YCM+(K2*XO)*(R21)+(YO)*(R22)+(K2*ZO)*(R23)
        Z = ZCM+(K2*XO)*(R31)+(K2*YO)*(R32)+(ZO)*(R33)
        return X, Y, Z

    def L124(self):  # 124: velocities, translations, direction cosines, points, differences
        v, K, ar = self.v, self.K, self.ar
        sin, cos = ar.sin, ar.cos
        H, W = v.H, v.W
        K2 = K("2.")
        v.V1A = H*((v.F1B/W)+v.V2B*v.W3B-v.V3B*v.W2B)+v.V1B
        v.V2A = H*((v.F2B/W)+v.V3B*v.W1B-v.V1B*v.W3B)+v.V2B
        v.V3A = H*((v.F3B/W)+v.V1B*v.W2B-v.V2B*v.W1B)+v.V3B
        v.VVA = v.VVB+(H/v.WV)*v.FSB
        v.S1A = (H/K2)*(v.V1A+v.V1B)
        v.S2A = (H/K2)*(v.V2A+v.V2B)
        v.S3A = (H/K2)*(v.V3A+v.V3B)
        v.SVA = (H/K2)*(v.VVA+v.VVB)+v.SVB
        THA, PHIA, PSIA = v.THA, v.PHIA, v.PSIA
        v.DIRC1X = (((-sin(PHIA))*sin(PSIA))+((cos(THA))*cos(PHIA))*cos(PSIA))
        v.DIRC1Y = (((cos(PHIA))*sin(PSIA))+((cos(THA))*sin(PHIA))*cos(PSIA))
        v.DIRC1Z = ((-sin(THA))*cos(PSIA))
        v.DIRC2X = (((-sin(PHIA))*cos(PSIA))-((cos(THA))*cos(PHIA))*sin(PSIA))
        v.DIRC2Y = (((cos(PHIA))*cos(PSIA))-((cos(THA))*sin(PHIA))*sin(PSIA))
        v.DIRC2Z = ((sin(THA))*sin(PSIA))
        v.DIRC3X = ((sin(THA))*cos(PHIA))
        v.DIRC3Y = ((sin(THA))*sin(PHIA))
        v.DIRC3Z = cos(THA)
        v.XCMA = v.S1A*v.DIRC1X+v.S2A*v.DIRC2X+v.S3A*v.DIRC3X+v.XCMB
        v.YCMA = v.S1A*v.DIRC1Y+v.S2A*v.DIRC2Y+v.S3A*v.DIRC3Y+v.YCMB
        v.ZCMA = v.S1A*v.DIRC1Z+v.S2A*v.DIRC2Z+v.S3A*v.DIRC3Z+v.ZCMB
        DELTA, ALPHA = v.DELTA, v.ALPHA
        v.YYCMA = v.YCMA*cos(DELTA)-v.ZCMA*sin(DELTA)
        v.ZZCMA = v.YCMA*sin(DELTA)+v.ZCMA*cos(DELTA)
        v.SQUIGA = sin(THA/K2)*sin((PSIA-PHIA)/K2)
        v.ETAA = sin(THA/K2)*cos((PSIA-PHIA)/K2)
        v.ZETAA = cos(THA/K2)*sin((PSIA+PHIA)/K2)
        v.CHIA = cos(THA/K2)*cos((PSIA+PHIA)/K2)
        rot, cm = self._rotation(v.SQUIGA, v.ETAA, v.ZETAA, v.CHIA), (v.XCMA, v.YCMA, v.ZCMA)
        v.XPA, v.YPA, v.ZPA = self._point(v.XPO, v.YPO, v.ZPO, cm, rot)
        v.YYPA = v.YPA*cos(DELTA)-v.ZPA*sin(DELTA)
        v.ZZPA = v.YPA*sin(DELTA)+v.ZPA*cos(DELTA)
        v.XQA, v.YQA, v.ZQA = self._point(v.XQO, v.YQO, v.ZQO, cm, rot)
        v.YYQA = v.YQA*cos(DELTA)-v.ZQA*sin(DELTA)
        v.ZZQA = v.YQA*sin(DELTA)+v.ZQA*cos(DELTA)
        v.XSA, v.YSA, v.ZSA = self._point(v.XSO, v.YSO, v.ZSO, cm, rot)
        v.YYSA = v.YSA*cos(DELTA)-v.ZSA*sin(DELTA)
        v.ZZSA = v.YSA*sin(DELTA)+v.ZSA*cos(DELTA)
        v.XVSA = v.XSA*cos(ALPHA)-v.YYSA*sin(ALPHA)
        v.YVSA = v.XSA*sin(ALPHA)+v.YYSA*cos(ALPHA)
        v.XRA, v.YRA, v.ZRA = self._point(v.XRO, v.YRO, v.ZRO, cm, rot)
        v.YYRA = v.YRA*cos(DELTA)-v.ZRA*sin(DELTA)
        v.ZZRA = v.YRA*sin(DELTA)+v.ZRA*cos(DELTA)
        v.XVRA = v.XRA*cos(ALPHA)-v.YYRA*sin(ALPHA)
        v.YVRA = v.XRA*sin(ALPHA)+v.YYRA*cos(ALPHA)
        v.XTA, v.YTA, v.ZTA = self._point(v.XTO, v.YTO, v.ZTO, cm, rot)
        v.YYTA = v.YTA*cos(DELTA)-v.ZTA*sin(DELTA)
        v.ZZTA = v.YTA*sin(DELTA)+v.ZTA*cos(DELTA)
        v.XVTA = v.XTA*cos(ALPHA)-v.YYTA*sin(ALPHA)
        v.YVTA = v.XTA*sin(ALPHA)+v.YYTA*cos(ALPHA)
        # DIFFERENCE CALCULATIONS
        v.POSLEN = abs(v.XVSA-v.XVSO)
        v.TDISP = abs(v.XVTA-v.XVTO)
        v.CARLEN = abs(v.SVA-v.SVO)
        v.DIFF = v.POSLEN-v.CARLEN
        v.DIFFT = v.TDISP-v.CARLEN
        # CALCULATION OF FORCES
        return self.IF(v.Q-self.KSTEP(".0004"), 83, 84, 84)

    def L83(self):
        self.v.FSA = self.K("1320.0")
        return 85

    def L84(self):
        return self.IF(self.v.DIFF-self.K("0.01"), 356, 356, 357)

    def L356(self):
        v = self.v
        v.FSA = abs(v.CK*((v.SVO-v.SVA)-(v.XVSO-v.XVSA)))
        v.FSA = self.K("0.8")*v.FSA
        return 358

    def L357(self):
        v = self.v
        v.FSA = abs(v.CT*((v.SVO-v.SVA)-(v.XVTO-v.XVTA)))
        v.FSA = self.K("0.8")*v.FSA
        v.ZSA = v.ZTA
        v.XSA = v.XTA
        v.YSA = v.YTA
        return 358

    def L358(self):
        return self.IF(self.v.LL-20*2**self.k, 600, 501, 501)  # IF(LL-20)600,501,501

    def L501(self):
        return self.IF(self.v.DIFF-self.v.DIFFB, 600, 502, 502)

    def L502(self):
        return self.IF(self.v.FSA-self.v.FCONST, 600, 504, 504)

    def L504(self):
        self.v.FSA = self.v.FCONST
        return 600

    def L600(self):
        return self.IF(self.v.XQA+self.K("0.083333"), 101, 101, 102)

    def L102(self):
        return self.IF(self.v.XQA+self.K("0.083333")-self.K("0.004"), 101, 101, 104)

    def L101(self):
        self.v.FFXA = self.K("0.0")
        return 105

    def L104(self):  # 104 CONTINUE
        return 85

    def L85(self):
        v, K = self.v, self.K
        v.CFA = K("0.25")
        v.FNAC = K("635.0")
        v.T = K("300.0")
        v.FFXA = K("3.1")*v.T
        return 105

    def L105(self):
        return self.IF(self.v.XQA+self.K("0.4166"), 107, 107, 106)

    def L107(self):
        self.v.FNA = self.K("0.0")
        return 106

    def L106(self):  # forces and torques, then the time step
        v, K, ar = self.v, self.K, self.ar
        sin, cos = ar.sin, ar.cos
        DELTA, ALPHA, W, G = v.DELTA, v.ALPHA, v.W, v.G
        v.FFYA = K("0.0")
        v.FSXA = v.FSA*cos(ALPHA)
        v.FSYA = v.FSA*sin(ALPHA)
        FFXA, FSXA, FSYA, FNA, FFYA = v.FFXA, v.FSXA, v.FSYA, v.FNA, v.FFYA
        v.F1A = (FFXA-FSXA)*(v.DIRC1X)+(FSYA*cos(DELTA)+FNA*sin(DELTA)-W*G*sin(DELTA)-FFYA*cos(DELTA))*(v.DIRC1Y)+(FFYA*sin(DELTA)+FNA*cos(DELTA)-W*G*cos(DELTA)-FSYA*sin(DELTA))*(v.DIRC1Z)  # noqa: E501
        v.F2A = (FFXA-FSXA)*(v.DIRC2X)+(FSYA*cos(DELTA)+FNA*sin(DELTA)-W*G*sin(DELTA)-FFYA*cos(DELTA))*(v.DIRC2Y)+(FFYA*sin(DELTA)+FNA*cos(DELTA)-W*G*cos(DELTA)-FSYA*sin(DELTA))*(v.DIRC2Z)  # noqa: E501
        v.F3A = (FFXA-FSXA)*(v.DIRC3X)+(FSYA*cos(DELTA)+FNA*sin(DELTA)-W*G*sin(DELTA)-FFYA*cos(DELTA))*(v.DIRC3Y)+(FFYA*sin(DELTA)+FNA*cos(DELTA)-W*G*cos(DELTA)-FSYA*sin(DELTA))*(v.DIRC3Z)  # noqa: E501
        # CALCULATION OF TORQUES
        XQA, YQA, ZQA, XSA, YSA, ZSA = v.XQA, v.YQA, v.ZQA, v.XSA, v.YSA, v.ZSA
        XCMA, YCMA, ZCMA = v.XCMA, v.YCMA, v.ZCMA
        v.TXA = (FFYA*cos(DELTA))*(ZQA-ZCMA)+(FNA*cos(DELTA))*(YQA-YCMA)-(FNA*sin(DELTA))*(ZQA-ZCMA)+(FFYA*sin(DELTA))*(YQA-YCMA)-(FSYA*cos(DELTA))*(ZSA-ZCMA)-(FSYA*sin(DELTA))*(YSA-YCMA)  # noqa: E501
        v.TYA = FFXA*(ZQA-ZCMA)-(FNA*cos(DELTA))*(XQA-XCMA)-FSXA*(ZSA-ZCMA)-(FFYA*sin(DELTA))*(XQA-XCMA)+(FSYA*sin(DELTA))*(XSA-XCMA)  # noqa: E501
        v.TZA = -FFXA*(YQA-YCMA)-(FFYA*cos(DELTA))*(XQA-XCMA)+FSXA*(YSA-YCMA)+(FSYA*cos(DELTA))*(XSA-XCMA)+(FNA*sin(DELTA))*(XQA-XCMA)  # noqa: E501
        v.T1A = (v.TXA*v.DIRC1X)+(v.TYA*v.DIRC1Y)+(v.TZA*v.DIRC1Z)
        v.T2A = (v.TXA*v.DIRC2X)+(v.TYA*v.DIRC2Y)+(v.TZA*v.DIRC2Z)
        v.T3A = (v.TXA*v.DIRC3X)+(v.TYA*v.DIRC3Y)+(v.TZA*v.DIRC3Z)
        # TIME CALCULATION
        v.LL = v.LL+1
        v.Q = v.Q+v.H
        v.E = v.E+self.KSTEP(".0004")
        if self.ar.to_float(v.Q) > self.limits.time_s:
            raise time_error(self.limits.time_s, "contact", 106, self.step,
                             self.ar.to_float(v.Q))
        return self.IF(v.E-K("0.0016"), 54, 87, 87)

    def L87(self):
        self.v.E = self.K("0.0")
        return 88

    def L88(self):  # 88: the contact-phase printout
        v, w = self.v, self.printer.write
        w(15, v.VVA)
        w(19, v.SVA)
        w(120, v.THAD)
        w(121, v.PHIAD)
        w(122, v.PSIAD)
        w(20, v.XCMA)
        w(27, v.XPA)
        w(33, v.XSA)
        w(30, v.XQA)
        w(206, v.YYCMA)
        w(200, v.YYPA, v.XRA)
        w(202, v.YYSA, v.YYRA)
        w(204, v.YYQA, v.ZZRA)
        w(207, v.ZZCMA)
        w(201, v.ZZPA)
        w(203, v.ZZSA)
        w(205, v.ZZQA)
        w(39, v.FSA)
        w(53, v.DIFF)
        w(40, v.Q)
        return 54

    def L54(self):
        return self.IF(self.v.M-1, 55, 354, 350)

    def L55(self):
        return self.IF(self.v.DIFF, 41, 354, 43)

    def L43(self):
        return self.IF(self.v.DIFF-self.K("0.01"), 56, 56, 108)

    def L56(self):
        self.v.M = 1
        return 88

    def L350(self):
        return self.IF(self.v.N-1, 351, 42, 351)

    def L351(self):
        return self.IF(self.v.DIFFT, 41, 42, 352)

    def L352(self):
        return self.IF(self.v.DIFFT-self.K("0.01"), 353, 353, 108)

    def L353(self):
        self.v.N = 1
        return 88

    def L108(self):  # 108: back up and halve the step
        v = self.v
        self.halvings += 1
        if self.halvings > self.limits.halvings:
            f = self.ar.to_float
            raise halving_error(self.limits.halvings, f(v.H), f(v.DIFF), f(v.DIFFT), 108,
                                self.step, self.time())
        v.Q = v.Q-v.H
        v.H = v.H/self.K("2.")
        v.HI = v.HI/self.K("2.")
        return 44

    def L41(self):  # 41: the step is accepted, A values become B values
        v = self.v
        self.halvings = 0
        self._record("contact")
        v.V1B = v.V1A
        v.V2B = v.V2A
        v.V3B = v.V3A
        v.W1B = v.W1A
        v.W2B = v.W2A
        v.W3B = v.W3A
        v.T1B = v.T1A
        v.T2B = v.T2A
        v.T3B = v.T3A
        v.F1B = v.F1A
        v.F2B = v.F2A
        v.F3B = v.F3A
        v.DIFFB = v.DIFF
        v.VVB = v.VVA
        v.THB = v.THA
        v.PHIB = v.PHIA
        v.PSIB = v.PSIA
        v.THDB = v.THDA
        v.PHIDB = v.PHIDA
        v.PSIDB = v.PSIDA
        v.FSB = v.FSA
        v.SVB = v.SVA
        v.XCMB = v.XCMA
        v.YCMB = v.YCMA
        v.ZCMB = v.ZCMA
        return 125

    def L354(self):  # POST LOSES CONTACT WITH FIRST SPRING
        v = self.v
        v.M = 2
        v.H = self.KSTEP("0.0004")
        v.HI = self.KSTEP("0.0004")
        self.printer.write(355)
        self._event(355, v.Q)
        return 41

    def L42(self):  # POST LOSES CONTACT WITH THE VEHICLE
        v = self.v
        self.free_flight = True
        self.printer.write(100)
        self._event(100, v.Q)
        self._record("contact")
        v.H = self.KSTEP("0.0004")
        v.HI = self.KSTEP("0.0004")
        v.E = self.K("0.0")
        v.XCMFB = v.XCMA
        v.YCMFB = v.YCMA
        v.ZCMFB = v.ZCMA
        v.THDFB = v.THDA
        v.PHIDFB = v.PHIDA
        v.PSIDFB = v.PSIDA
        v.THFB = v.THA
        v.PHIFB = v.PHIA
        v.PSIFB = v.PSIA
        v.W1FB = v.W1A
        v.W2FB = v.W2A
        v.W3FB = v.W3A
        v.V1FB = v.V1A
        v.V2FB = v.V2A
        v.V3FB = v.V3A
        v.VVFB = v.VVA
        v.TF = v.Q
        v.SVFB = v.SVA
        return 57

    def L57(self):  # 57, 59: one free-flight step
        v, K, ar = self.v, self.K, self.ar
        sin, cos = ar.sin, ar.cos
        self.step += 1
        H, A, B, C = v.H, v.A, v.B, v.C
        K2 = K("2.")
        v.T = v.TF+H  # 59
        if ar.to_float(v.T) > self.limits.time_s:
            raise time_error(self.limits.time_s, "free", 59, self.step, ar.to_float(v.T))
        v.W1FA = H*((B-C)/A)*v.W2FB*v.W3FB+v.W1FB
        v.W2FA = H*((C-A)/B)*v.W1FB*v.W3FB+v.W2FB
        v.W3FA = H*((A-B)/C)*v.W1FB*v.W2FB+v.W3FB
        # CALL ED(W1FA,W2FA,W3FA,THDFB,PHIDFB,PSIDFB,HI,D,PSIFB,THFB)
        v.D = self.ed(v.W1FA, v.W2FA, v.W3FA, v.THDFB, v.PHIDFB, v.PSIDFB, v.HI, v.PSIFB, v.THFB)
        v.PSIFA = v.D
        v.PSIFAD = v.PSIFA*K("57.3")
        v.PFORKF = (v.W1FA*(cos_PSIFA := cos(v.PSIFA)))-(v.W2FA*(sin_PSIFA := sin(v.PSIFA)))
        v.THFA = (H/K2)*(v.W2FA*cos_PSIFA+v.W1FA*sin_PSIFA+v.THDFB)+v.THFB
        v.THFAD = v.THFA*K("57.3")
        v.PHIFA = (H/K2)*(((((sin_THFA := sin(v.THFA)))*v.PFORKF)/(((cos_THFA := cos(v.THFA)))*cos_THFA-K("1.0")))+v.PHIDFB)+v.PHIFB
        v.PHIFAD = v.PHIFA*K("57.3")
        v.THDFA = (v.W2FA/cos_PSIFA)+((sin_PSIFA)/cos_PSIFA)*v.PFORKF
        v.PHIDFA = (-K("1.0")/sin_THFA)*v.PFORKF
        v.PSIDFA = v.W3FA-(cos_THFA)*v.PHIDFA
        # FORCE CALCULATIONS (FREE)
        W, G = v.W, v.G
        cosD, sinD, cosA, sinA = self.trig_delta_alpha
        THFB, PHIFB, PSIFB = v.THFB, v.PHIFB, v.PSIFB
        v.F1FB = W*G*cosD*(sin_THFB := sin(THFB))*(cos_PSIFB := cos(PSIFB))-W*G*sinD*((cos_PHIFB := cos(PHIFB))*(sin_PSIFB := sin(PSIFB))+(cos_THFB := cos(THFB))*(sin_PHIFB := sin(PHIFB))*cos_PSIFB)  # noqa: E501
        v.F2FB = -W*G*cosD*sin_THFB*sin_PSIFB-W*G*sinD*(cos_PHIFB*cos_PSIFB-cos_THFB*sin_PHIFB*sin_PSIFB)  # noqa: E501
        v.F3FB = -W*G*cosD*cos_THFB-W*G*sinD*sin_THFB*sin_PHIFB
        # LINEAR VELOCITY CALCUALTIIONS (FREE)
        v.V1FA = H*((v.F1FB/W)+v.V2FB*v.W3FB-v.V3FB*v.W2FB)+v.V1FB
        v.V2FA = H*((v.F2FB/W)+v.V3FB*v.W1FB-v.V1FB*v.W3FB)+v.V2FB
        v.V3FA = H*((v.F3FB/W)+v.V1FB*v.W2FB-v.V2FB*v.W1FB)+v.V3FB
        v.VVFA = v.VVFB
        v.S1FA = (H/K2)*(v.V1FA+v.V1FB)
        v.S2FA = (H/K2)*(v.V2FA+v.V2FB)
        v.S3FA = (H/K2)*(v.V3FA+v.V3FB)
        v.SVFA = (H/K2)*(v.VVFA+v.VVFB)+v.SVFB
        v.XBUMP = v.SVFA-v.HLEN
        v.XENTOP = v.SVFA+v.TLEN
        v.XTAIL = v.XENTOP+v.TRLEN
        # X,Y,Z TRANSLATIONS OF MASS CENTER (FREE)
        THFA, PHIFA, PSIFA = v.THFA, v.PHIFA, v.PSIFA
        S1FA, S2FA, S3FA = v.S1FA, v.S2FA, v.S3FA
        v.XCMFA = (S1FA)*((-(sin_PHIFA := sin(PHIFA)))*(sin_PSIFA)+((cos_THFA)*((cos_PHIFA := cos(PHIFA)))*(cos_PSIFA)))+(S2FA)*((-sin_PHIFA)*(cos_PSIFA)-((cos_THFA)*(cos_PHIFA)*sin_PSIFA))+(S3FA)*((sin_THFA)*cos_PHIFA)+v.XCMFB  # noqa: E501
        v.YCMFA = (S1FA)*((cos_PHIFA)*(sin_PSIFA)+((cos_THFA)*(sin_PHIFA)*cos_PSIFA))+(S2FA)*((cos_PHIFA)*(cos_PSIFA)-((cos_THFA)*(sin_PHIFA)*sin_PSIFA))+(S3FA)*((sin_THFA)*sin_PHIFA)+v.YCMFB  # noqa: E501
        v.ZCMFA = (S1FA)*(-sin_THFA)*(cos_PSIFA)+((S2FA)*(sin_THFA)*(sin_PSIFA))+(S3FA)*(cos_THFA)+v.ZCMFB  # noqa: E501
        v.YYCMFA = v.YCMFA*cosD-v.ZCMFA*sinD
        v.ZZCMFA = v.YCMFA*sinD+v.ZCMFA*cosD
        # CALCULATION OF ROTATION PARAMETERS (FREE)
        v.SQUIFA = sin(THFA/K2)*sin((PSIFA-PHIFA)/K2)
        v.ETAFA = sin(THFA/K2)*cos((PSIFA-PHIFA)/K2)
        v.ZETAFA = cos(THFA/K2)*sin((PSIFA+PHIFA)/K2)
        v.CHIFA = cos(THFA/K2)*cos((PSIFA+PHIFA)/K2)
        rot, cm = self._rotation(v.SQUIFA, v.ETAFA, v.ZETAFA, v.CHIFA), (v.XCMFA, v.YCMFA, v.ZCMFA)
        v.XPFA, v.YPFA, v.ZPFA = self._point(v.XPO, v.YPO, v.ZPO, cm, rot)
        v.YYPFA = v.YPFA*cosD-v.ZPFA*sinD
        v.ZZPFA = v.YPFA*sinD+v.ZPFA*cosD
        v.XVPFA = v.XPFA*cosA-v.YYPFA*sinA
        v.YVPFA = v.XPFA*sinA+v.YYPFA*cosA
        v.XQFA, v.YQFA, v.ZQFA = self._point(v.XQO, v.YQO, v.ZQO, cm, rot)
        v.YYQFA = v.YQFA*cosD-v.ZQFA*sinD
        v.ZZQFA = v.YQFA*sinD+v.ZQFA*cosD
        v.XRFA, v.YRFA, v.ZRFA = self._point(v.XRO, v.YRO, v.ZRO, cm, rot)
        v.YYRFA = v.YRFA*cosD-v.ZRFA*sinD
        v.ZZRFA = v.YRFA*sinD+v.ZRFA*cosD
        v.XVRFA = v.XRFA*cosA-v.YYRFA*sinA
        v.YVRFA = v.XRFA*sinA+v.YYRFA*cosA
        v.XCFA, v.YCFA, v.ZCFA = self._point(v.XCO, v.YCO, v.ZCO, cm, rot)
        v.YYCFA = v.YCFA*cosD-v.ZCFA*sinD
        v.ZZCFA = v.YCFA*sinD+v.ZCFA*cosD
        v.XVCFA = v.XCFA*cosA-v.YYCFA*sinA
        v.YVCFA = v.XCFA*sinA+v.YYCFA*cosA
        v.E = v.E+self.KSTEP("0.0002")
        return self.IF(v.E-K("0.008"), 77, 80, 80)

    def L80(self):
        self.v.E = self.K("0.0")
        return 98

    def L98(self):  # 98: the free-flight printout
        v, w = self.v, self.printer.write
        w(60, v.THFAD)
        w(61, v.PHIFAD)
        w(62, v.PSIFAD)
        w(63, v.XCMFA)
        w(64, v.XPFA)
        w(66, v.XQFA)
        w(113, v.XRFA)
        w(131, v.XCFA)
        w(208, v.YYCMFA)
        w(210, v.YYPFA)
        w(212, v.YYQFA)
        w(216, v.YYRFA)
        w(132, v.YYCFA)
        w(209, v.ZZCMFA)
        w(211, v.ZZPFA)
        w(213, v.ZZQFA)
        w(217, v.ZZRFA)
        w(133, v.ZZCFA)
        w(75, v.SVFA)
        w(76, v.T)
        return 77

    def L77(self):
        return self.IF(self.v.I-1, 81, 82, 81)

    def L82(self):  # STOP
        self._record("free")
        return None

    def _hit(self, fmt: int):
        self.v.I = 1
        self.printer.write(fmt)
        self._event(fmt, self.v.T)
        return 98

    def L140(self):
        return self._hit(134)

    def L96(self):
        return self._hit(97)

    def L93(self):
        return self._hit(99)

    def L109(self):
        return self._hit(110)

    def L236(self):
        return self._hit(237)

    def L238(self):
        return self._hit(239)

    def L240(self):
        return self._hit(242)

    def L247(self):
        return self._hit(248)

    def L400(self):  # 400: the free step is accepted
        v = self.v
        self._record("free")
        v.TF = v.T
        v.THFB = v.THFA
        v.PHIFB = v.PHIFA
        v.PSIFB = v.PSIFA
        v.VVFB = v.VVFA
        v.V1FB = v.V1FA
        v.V2FB = v.V2FA
        v.V3FB = v.V3FA
        v.W1FB = v.W1FA
        v.W2FB = v.W2FA
        v.W3FB = v.W3FA
        v.THDFB = v.THDFA
        v.PHIDFB = v.PHIDFA
        v.PSIDFB = v.PSIDFA
        v.XCMFB = v.XCMFA
        v.YCMFB = v.YCMFA
        v.ZCMFB = v.ZCMFA
        v.SVFB = v.SVFA
        return 57

    def _checks(self):
        """Labels 81 to 462: the ground and vehicle checks, pure arithmetic IFs, as a table
        label -> (expression, negative, zero, positive), in the listing's order."""
        v, K = self.v, self.K
        k01, k001 = K("0.1"), K("0.01")
        return {
            # ground: P, Q, R, C
            81: (lambda: v.ZZPFA+v.HEIGHT, 91, 93, 91),
            91: (lambda: abs(v.ZZPFA+v.HEIGHT)-k01, 93, 93, 94),
            94: (lambda: v.ZZQFA+v.HEIGHT, 95, 96, 95),
            95: (lambda: abs(v.ZZQFA+v.HEIGHT)-k001, 96, 96, 111),
            111: (lambda: v.ZZRFA+v.HEIGHT, 103, 109, 103),
            103: (lambda: abs(v.ZZRFA+v.HEIGHT)-k01, 109, 109, 230),
            230: (lambda: v.ZZCFA+v.HEIGHT, 141, 140, 141),
            141: (lambda: abs(v.ZZCFA+v.HEIGHT)-k01, 140, 140, 500),
            # CHECK ON THE POINT P (500 CONTINUE)
            500: (lambda: v.YVPFA-v.YLFEN, 112, 250, 249),
            249: (lambda: v.YVPFA-v.YRFEN, 250, 250, 112),
            250: (lambda: v.XVPFA-v.XBUMP, 112, 231, 232),
            232: (lambda: v.XVPFA-v.SVFA, 231, 233, 234),
            231: (lambda: v.ZZPFA-v.HHV, 235, 236, 235),
            235: (lambda: abs(v.ZZPFA-v.HHV)-k01, 236, 236, 112),
            233: (lambda: v.ZZPFA-v.HTV, 238, 240, 241),
            241: (lambda: abs(v.ZZPFA-v.HTV)-k01, 240, 240, 112),
            234: (lambda: v.XVPFA-v.SVFA-k01, 233, 233, 243),
            243: (lambda: v.XVPFA-v.XENTOP, 233, 240, 244),
            244: (lambda: v.XVPFA-v.XTAIL, 245, 245, 112),
            245: (lambda: v.ZZPFA-v.HTRV, 246, 247, 246),
            246: (lambda: abs(v.ZZPFA-v.HTRV)-k01, 247, 247, 112),
            # CHECK ON THE POINT R (112 CONTINUE)
            112: (lambda: v.YVRFA-v.YLFEN, 300, 251, 252),
            252: (lambda: v.YVRFA-v.YRFEN, 251, 251, 300),
            251: (lambda: v.XVRFA-v.XBUMP, 300, 253, 254),
            254: (lambda: v.XVRFA-v.SVFA, 253, 255, 256),
            253: (lambda: v.ZZRFA-v.HHV, 257, 236, 257),
            257: (lambda: abs(v.ZZRFA-v.HHV)-k01, 236, 236, 300),
            255: (lambda: v.ZZRFA-v.HTV, 238, 240, 258),
            258: (lambda: abs(v.ZZRFA-v.HTV)-k01, 240, 240, 300),
            256: (lambda: v.XVRFA-v.SVFA-k01, 255, 255, 259),
            259: (lambda: v.XVRFA-v.XENTOP, 255, 240, 260),
            260: (lambda: v.XVRFA-v.XTAIL, 261, 261, 300),
            261: (lambda: v.ZZRFA-v.HTRV, 262, 247, 262),
            262: (lambda: abs(v.ZZRFA-v.HTRV)-k01, 247, 247, 300),
            # CHECK ON THE POINT C (300 CONTINUE); falling out of 462 goes to 400
            300: (lambda: v.YVCFA-v.YLFEN, 400, 451, 452),
            452: (lambda: v.YVCFA-v.YRFEN, 451, 451, 400),
            451: (lambda: v.XVCFA-v.XBUMP, 400, 453, 454),
            454: (lambda: v.XVCFA-v.SVFA, 453, 455, 456),
            453: (lambda: v.ZZCFA-v.HHV, 457, 236, 457),
            457: (lambda: abs(v.ZZCFA-v.HHV)-k01, 236, 236, 400),
            455: (lambda: v.ZZCFA-v.HTV, 238, 240, 458),
            458: (lambda: abs(v.ZZCFA-v.HTV)-k01, 240, 240, 400),
            456: (lambda: v.XVCFA-v.SVFA-k01, 455, 455, 459),
            459: (lambda: v.XVCFA-v.XENTOP, 455, 240, 460),
            460: (lambda: v.XVCFA-v.XTAIL, 461, 461, 400),
            461: (lambda: v.ZZCFA-v.HTRV, 462, 247, 462),
            462: (lambda: abs(v.ZZCFA-v.HTRV)-k01, 247, 247, 400),
        }


#: The labels where the listing starts checking a point against the car: 500 CONTINUE (P),
#: 112 CONTINUE (R), 300 CONTINUE (C).
_CHECK_STARTS = {500: "P", 112: "R", 300: "C"}


def _frames(exc):
    import traceback  # here: only a run that stopped reads its traceback

    return [f for f in traceback.extract_tb(exc.__traceback__) if f.filename == __file__]


def _in_ed(exc) -> bool:
    frames = _frames(exc)
    return any(f.name in ("__call__", "DF") for f in frames)


def _assigned_variable(exc) -> str | None:
    """The variable on the left of the statement that trapped (from the traceback's line)."""

    for f in reversed(_frames(exc)):
        line = (f.line or linecache.getline(f.filename, f.lineno)).strip()
        if f.name == "DF":  # ED's statement function, whichever of its lines trapped
            return "DF"
        if "=" in line and not line.startswith(("return", "if ", "elif ")):
            target = line.split("=", 1)[0].strip()
            name = target.split(",")[0].strip()
            for prefix in ("v.", "self."):
                if name.startswith(prefix):
                    name = name[len(prefix):]
            if name.isidentifier():
                return name
    return None


def _getter(names):
    get = operator.attrgetter(*names)
    return get if len(names) > 1 else (lambda v: (get(v),))


def _source_tables() -> dict:
    """What the program reads from its own text (:func:`deck_emulator.legacy.emulator_text.tables`
    of this file): from emulator_tables.py when it was made from this very text (its checksum
    says so), else from the text now (the pattern pass, ~2 ms, once per process).
    tests/cli/test_start.py fails while emulator_tables.py is stale."""

    return read_tables(__file__, made)


_TABLES = _source_tables()


def __getattr__(name):  # the pattern reader (tests/legacy/test_emulator.py), imported when asked
    if name == "_assigned_names":

        return _assigned_names
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
#: block method name -> a function giving the values the block assigned (integers included:
#: they are always finite and sum with the reals).
_ASSIGNED = {name: _getter(names) for name, names in _TABLES["ASSIGNED"].items()}
#: Every literal the program text writes as K("...") or KSTEP("..."), and the ones ED binds.
_LITERALS = _TABLES["LITERALS"]
_STEP_LITERALS = _TABLES["STEP_LITERALS"]
#: Every variable the program text names as v.NAME (each unit starts with them all zero).
_VARIABLES = _TABLES["VARIABLES"]


def run_deck(deck, precision: str | Arithmetic = "double", *, errata=(), step_scale_k: int = 0,
             tha_start: str | None = None, ed_tolerance: str = ".0001", limits: Limits = Limits(),
             trace: bool = True) -> Run:
    """Run the 1967 program on a deck. Raises EmulatorError when a guard fires or the arithmetic
    traps; the error's ``run`` holds the records printed up to then."""
    return Program(deck, precision, errata=errata, step_scale_k=step_scale_k, tha_start=tha_start,
                   ed_tolerance=ed_tolerance, limits=limits, trace=trace).run()
