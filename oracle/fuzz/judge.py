"""One program judged: gfortran's checked build first (a program with undefined behaviour is
no test), then the oracle build (the goldens' binary64 flags) against the front end's run of
the job deck (``python -m deck_emulator run JOB --out FILE``, the user's road), byte for byte.

Outcomes (:data:`OUTCOMES`):

* ``oracle-rejected`` -- the checked build refused it or stopped it (a compile error, a runtime
  check of ``-fcheck=all``, an INTEGER overflow of ``-ftrapv``, a REAL read before it was set
  (``-finit-real=snan`` with the trap on invalid operations), a DO that would run no times
  (a guard put before each DO in this build only), a trap, a hang), or its printout changed
  when built again with INTEGERs starting at another value (one read before it was set);
* ``agree`` -- the front end ended normally and printed the oracle build's bytes;
* ``differ`` -- it printed something else, stopped (exit 3) where the oracle ended, or did not
  end within the time limit;
* ``refused`` -- it refused the deck in one line (exit 2): the dialect includes every
  generated program, so each is a broken promise;
* ``traceback`` -- anything else (a Python traceback, another exit status).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import oracle

OUTCOMES = ("agree", "differ", "refused", "traceback", "oracle-rejected")
#: the checked build: the oracle's flags, then every runtime check, a trap on INTEGER overflow,
#: and REALs that start as signalling NaNs (a read before a write traps) and INTEGERs at the
#: largest value (a read before a write overflows or leaves the bounds)
CHECK_FLAGS = ["-fcheck=all", "-ftrapv", "-finit-real=snan", "-finit-integer=2147483647"]
#: ... built again with INTEGERs starting at another value: a printout that changes reads an
#: INTEGER before it is set
CHECK_AGAIN = ["-fcheck=all", "-ftrapv", "-finit-real=snan", "-finit-integer=-7"]
#: the status a zero-trip guard stops the checked build with
ZERO_TRIP_STATUS = 77
RUN_TIMEOUT_S = 5.0
ROOT = Path(__file__).resolve().parents[2]  # the checkout
FRONT_TIMEOUT_S = 60.0


@dataclass
class Verdict:
    outcome: str
    why: str = ""  # one line
    klass: str = ""  # the class a campaign counts it in (see classes.py)
    oracle_text: str = ""
    ours_text: str = ""
    precisions: dict = field(default_factory=dict)  # ibm7094: its comparison


def _statements(lines):
    from deck_emulator.legacy.jobdeck import statements

    return statements(lines)


_DO = re.compile(r"DO(\d+)([A-Z][A-Z0-9]*)=([^,]+),([^,]+)(?:,(.+))?$")


def guarded(lines: list[str]) -> list[str]:
    """The source with ``IF (m2 .LT. m1) STOP 77`` before each DO (its label moved to the
    guard): the checked build stops where a DO would run no times (gfortran runs such a range
    no times, IBM FORTRAN IV once: the generator must never make one)."""
    out = list(lines)
    inserts = []
    for s in _statements(lines):
        m = _DO.match(s.text)
        if not m:
            continue
        m1, m2, m3 = m.group(3), m.group(4), m.group(5)
        cond = f"({m2}).LT.({m1})" if not (m3 and m3.startswith("-")) else f"({m2}).GT.({m1})"
        inserts.append((s.line - 1, cond))
    for index, cond in sorted(inserts, reverse=True):
        card = out[index]
        label = card[:5]
        out[index] = "     " + card[5:]
        guard = f"{label} IF({cond})STOP {ZERO_TRIP_STATUS}"
        pieces = [guard[:72]]
        rest = guard[72:]
        while rest:
            pieces.append("     1" + rest[:66])
            rest = rest[66:]
        out[index:index] = pieces
    return out


def _build(tmp: Path, lines: list[str], name: str, extra: list[str]) -> tuple[Path | None, str]:
    src = tmp / f"{name}.f"
    src.write_text("".join(line + "\n" for line in lines))
    exe = tmp / name
    cmd = ["gfortran", *oracle.COMMON_FLAGS, *oracle.PRECISIONS["r8"], *extra, "-o", str(exe),
           str(src)]
    proc = subprocess.run(cmd, cwd=tmp, capture_output=True, text=True)
    if proc.returncode:
        error = next((line for line in proc.stderr.splitlines() if "Error" in line),
                     proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "?")
        return None, error.strip()
    return exe, ""


def _run(exe: Path, data: list[str], timeout_s: float = RUN_TIMEOUT_S):
    """(stdout, stderr, status or None for a hang)."""
    env = dict(os.environ, GFORTRAN_UNBUFFERED_ALL="1")
    try:
        proc = subprocess.run([str(exe)], input="".join(c + "\n" for c in data).encode(),
                              capture_output=True, env=env, timeout=timeout_s)
    except subprocess.TimeoutExpired:
        return "", "", None
    return (proc.stdout.decode("ascii", "replace"), proc.stderr.decode("ascii", "replace"),
            proc.returncode)


def checked(tmp: Path, lines: list[str], data: list[str]) -> str:
    """'' when the checked build runs the program to its end without a complaint, else why
    (one line)."""
    exe, error = _build(tmp, guarded(lines), "checked", CHECK_FLAGS)
    if exe is None:
        return f"compile: {error}"
    out, err, status = _run(exe, data)
    if status is None:
        return f"no end within {RUN_TIMEOUT_S:g} s"
    if status == ZERO_TRIP_STATUS:
        return "a DO that would run no times"
    if status != 0:
        first = next((line for line in err.splitlines() if line.strip()
                      and not line.startswith(("#", "Backtrace", "\t"))), f"status {status}")
        where = re.search(r"checked\.f:(\d+)", err) or re.search(r"At line (\d+)", err)
        more = next((line.strip() for line in err.splitlines()
                     if line.startswith(("Fortran runtime error", "Error termination"))), "")
        at = f" at line {where.group(1)}: {guarded(lines)[int(where.group(1)) - 1].strip()}" \
            if where else ""
        return f"run: {first.strip()} {more}{at}".replace(f"{tmp}{os.sep}", "")
    again, error = _build(tmp, guarded(lines), "checked-again", CHECK_AGAIN)
    out2, _err, status2 = _run(again, data) if again is not None else ("", "", -1)
    if status2 != 0 or out2 != out:
        return "an INTEGER read before it is set (the printout depends on its start value)"
    return ""


def oracle_run(tmp: Path, lines: list[str], data: list[str]):
    """The oracle build's (stdout, why) -- why '' when it ended normally."""
    exe, error = _build(tmp, lines, "oracle", [])
    if exe is None:
        return "", f"compile: {error}"
    out, err, status = _run(exe, data)
    if status is None:
        return out, f"no end within {RUN_TIMEOUT_S:g} s"
    if status != 0:
        return out, f"status {status}: {err.strip().splitlines()[0] if err.strip() else ''}"
    return out, ""


#: How the front end is reached: ``job`` -- the user's command on the job deck;
#: ``program`` -- its Python API on the deck's FORTRAN and data cards (front.py)
ROADS = ("job", "program")


def front_end(tmp: Path, job: list[str], precision: str = "double",
              timeout_s: float = FRONT_TIMEOUT_S, env_path: str | None = None,
              road: str = "job", in_process: bool = False):
    """The front end on the job deck, as a user runs it: (outcome, text printed, one line).
    ``in_process``: in this process (the tests': no timeout, no interpreter started).

    outcome: 'normal' (exit 0), 'stopped' (exit 3), 'refused' (exit 2, one line),
    'traceback' (anything else), 'hang' (no end within ``timeout_s``)."""
    path = tmp / "fuzz.job"
    path.write_text("".join(c + "\n" for c in job))
    out = tmp / f"out-{precision}.txt"
    if out.exists():
        out.unlink()
    if in_process:
        return _in_process(path, out, precision, road)
    env = dict(os.environ)
    if env_path is not None:
        env["PYTHONPATH"] = env_path
    try:
        cmd = ([sys.executable, "-m", "deck_emulator", "run", str(path), "--out", str(out),
                "--quiet", "--precision", precision] if road == "job" else
               [sys.executable, "-m", "oracle.fuzz.front", str(path), precision, str(out)])
        if road == "program":  # (the checkout's oracle/ importable from the temporary folder)
            env["PYTHONPATH"] = os.pathsep.join(filter(None, [env.get("PYTHONPATH"), str(ROOT)]))
        proc = subprocess.run(cmd,
                              capture_output=True, text=True, timeout=timeout_s, env=env,
                              cwd=tmp)
    except subprocess.TimeoutExpired:
        return "hang", out.read_text() if out.exists() else "", \
            f"no end within {timeout_s:g} s"
    text = out.read_text() if out.exists() else ""
    err = proc.stderr.strip()
    lines = [line for line in err.splitlines() if "the job deck's own FORTRAN runs" not in line]
    last = lines[-1] if lines else ""
    if "Traceback" in err:
        return "traceback", text, last
    if proc.returncode == 0:
        return "normal", text, ""
    if proc.returncode == 3:
        return "stopped", text, last
    if proc.returncode == 2 and len(lines) == 1:
        return "refused", text, last
    return "traceback", text, f"status {proc.returncode}: {last}"


def _in_process(path: Path, out: Path, precision: str, road: str):
    import contextlib
    import io
    import traceback

    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            if road == "job":
                from deck_emulator.cli import main

                status = main(["run", str(path), "--out", str(out), "--quiet", "--precision",
                               precision])
            else:
                from .front import main

                status = main([str(path), precision, str(out)])
    except Exception:  # (a defect of the front end: the outcome 'traceback', its last line)
        return "traceback", out.read_text() if out.exists() else "", \
            traceback.format_exc().strip().splitlines()[-1]
    text = out.read_text() if out.exists() else ""
    lines = [line for line in err.getvalue().strip().splitlines()
             if "the job deck's own FORTRAN runs" not in line]
    last = lines[-1] if lines else ""
    if status == 0:
        return "normal", text, ""
    if status == 3:
        return "stopped", text, last
    if status == 2 and len(lines) == 1:
        return "refused", text, last
    return "traceback", text, f"status {status}: {last}"


def first_difference(ours: str, theirs: str) -> str:
    a, b = ours.splitlines(), theirs.splitlines()
    for i, (x, y) in enumerate(zip(a, b), start=1):
        if x != y:
            return f"record {i}: front end {x!r}, gfortran {y!r}"
    if len(a) != len(b):
        return f"{len(a)} records from the front end, {len(b)} from gfortran"
    return "the same records, other bytes (line ends)"


def judge(tmp: Path, lines: list[str], data: list[str], job: list[str], *,
          ibm7094: bool = True, env_path: str | None = None, road: str = "job",
          fail_first: str | None = None, in_process: bool = False) -> Verdict | None:
    """The verdict on one program (see the module docstring).  ``fail_first`` (the
    shrinker's): the outcome sought -- the front end runs first, and a program whose outcome
    is another gives None without the checked build's cost."""
    if fail_first is None:
        why = checked(tmp, lines, data)
        if why:
            return Verdict("oracle-rejected", why)
    theirs, why = oracle_run(tmp, lines, data)
    if why:
        return None if fail_first else Verdict("oracle-rejected", f"oracle build: {why}")
    ending, ours, why = front_end(tmp, job, env_path=env_path, road=road,
                                  in_process=in_process)
    v = Verdict("agree", oracle_text=theirs, ours_text=ours)
    if ending == "normal":
        if ours != theirs:
            v.outcome, v.why = "differ", first_difference(ours, theirs)
    elif ending in ("stopped", "hang"):
        how = "stopped" if ending == "stopped" else "did not end"
        v.outcome, v.why = "differ", f"the front end {how}: {why}"
    else:
        v.outcome, v.why = ending, why
    if fail_first is not None:
        if v.outcome != fail_first:
            return None
        why = checked(tmp, lines, data)
        if why:
            return Verdict("oracle-rejected", why)
    if ibm7094 and v.outcome in ("agree", "differ"):
        from .tolerance import compare_within

        ending7, ours7, why7 = front_end(tmp, job, "ibm7094", env_path=env_path, road=road,
                                         in_process=in_process)
        if ending7 == "normal":
            v.precisions["ibm7094"] = compare_within(ours7, theirs)
            if v.precisions["ibm7094"][0] == "beyond":
                v.precisions["ibm7094"] = _bounded(job, ours7, theirs,
                                                   v.precisions["ibm7094"][1])
        else:
            v.precisions["ibm7094"] = (ending7, why7)
    return v


def _bounded(job: list[str], ours7: str, theirs: str, plain: str) -> tuple[str, str]:
    """A 7094 printout beyond the plain tolerance, judged by its run's own error bound
    (bound.py): within it, beyond it, or withheld (the runs part)."""
    from deck_emulator.legacy.stops import EmulatorError

    from .bound import compare_bounded, lockstep

    try:
        found, records, fields = lockstep(job)
    except EmulatorError as exc:
        return "beyond", f"{plain}; the lockstep run stopped: {exc}"
    status, why = compare_bounded(ours7, theirs, records, found, fields)
    return status, f"{why} (plain tolerance: {plain})"
