"""What a disagreement is an instance of: a short class name a campaign counts.

Without shrinking, a class is read from the evidence at hand: a refusal's or a traceback's
message (numbers, paths and names taken out), a stop's reason, or the kind of the first
difference between the printouts (:func:`difference_kind`).  A shrunk program (shrink.py)
is matched against the constructs of the classes issue 46 lists (:data:`KNOWN`): the first
whose pattern its cards hold names it; one matching none is ``unlisted``, to be read by hand.
"""

from __future__ import annotations

import re

#: (class, what the minimal program holds: a regular expression over its statements, blanks
#: removed, one a line) -- issue 46's classes, in the order they are tried
KNOWN = (
    ("X**0 or K**0 (issue 46)", r"\*\*0(?!\d)"),
    ("Fw.0 (issue 46)", r"^\d*FORMAT\(.*F\d+\.0(?!\d)"),
    ("trailing nX (issue 46)", r"^\d*FORMAT\(.*(\d+X\)$|^\d*FORMAT\(\d+X\)$)"),
    ("statement function named ABS, SIN or COS (issue 46)", r"^(ABS|SIN|COS)\([A-Z0-9]+\)="),
    ("READ in a subprogram (issue 46)", r"(?s)^(SUBROUTINE|FUNCTION).*^READ\("),
    ("CALL S(I, A(I)) (issue 46)", r"^CALL[A-Z0-9]+\(.*\b([A-Z][A-Z0-9]*)\b.*\(\1\)"),
    ("X**4..X**6 (issue 46)", r"\*\*[4-6](?!\d)"),
    ("SIN or COS after a DO (issue 46)", r"(?s)^DO\d.*(SIN|COS)\("),
)
_WATCHED = {97, 99, 100, 106, 108, 110, 134, 237, 239, 242, 248, 355}


def _norm(text: str) -> str:
    text = re.sub(r"(/[^\s:]+)+(\.job|\.f)?:?", "", text)  # paths
    text = re.sub(r"\b\d+(\.\d+)?\b", "N", text)
    return re.sub(r"\s+", " ", text).strip()[:90]


def difference_kind(ours: str, theirs: str) -> str:
    """The first difference between two printouts, by kind."""
    a, b = ours.splitlines(), theirs.splitlines()
    for x, y in zip(a, b):
        if x == y:
            continue
        if x.rstrip() == y.rstrip():
            return "trailing blanks"
        if "*" in y and "*" not in x:
            return "asterisks in gfortran's field, a number in ours"
        if "*" in x and "*" not in y:
            return "asterisks in ours, a number in gfortran's"
        if y.count(".") > x.count("."):
            return "a decimal point lost"
        if len(x) == len(y):
            diff = [k for k, (p, q) in enumerate(zip(x, y)) if p != q]
            if len(diff) <= 2 and all(x[k].isdigit() and y[k].isdigit() for k in diff):
                return "last digits of a value"
            return "another value"
        return "another record"
    if len(a) != len(b):
        return "fewer records" if len(a) < len(b) else "more records"
    return "other bytes"


def classify(source: list[str], verdict) -> str:
    """The class of an unshrunk program's verdict (see the module docstring)."""
    o, why = verdict.outcome, verdict.why
    if o == "agree":
        return ""
    if o == "oracle-rejected":
        return "checked build: " + _norm(why)
    if o == "refused":
        if "missing card: it should hold" in why or "it should hold" in why:
            return "$DATA section read as the listing's deck (issue 46)"
        return "refused: " + _norm(re.sub(r"^.*?error: ", "", why))
    if o == "traceback":
        m = re.search(r"(\w+(Error|Exception)|KeyError|NameError)", why)
        return "traceback: " + (m.group(1) if m else "") + ": " + _norm(why)[:60]
    if why.startswith("the front end stopped"):
        if "halved" in why or "time passed the limit" in why:
            return "the listing's watched labels (issue 46)"
        return "stopped: " + _norm(why.split(": ", 1)[1] if ": " in why else why)
    if why.startswith("the front end did not end"):
        return "no end"
    return "printed: " + difference_kind(verdict.ours_text, verdict.oracle_text)


def classify_cards(cards: list[str], outcome: str, why: str) -> str:
    """The class of a shrunk program (its job deck's cards), or '' if none of :data:`KNOWN`."""
    from deck_emulator.legacy.jobdeck import statements

    from .front import split_job

    source, _ = split_job(cards)
    stmts = statements(source)
    text = "\n".join(s.text for s in stmts)
    labels = {int(s.label) for s in stmts if s.label.strip().isdigit()}
    if outcome == "refused" and "it should hold" in why:
        return "$DATA section read as the listing's deck (issue 46)"
    for name, pattern in KNOWN:
        if re.search(pattern, text, re.M):
            return name
    if labels & _WATCHED:
        return "the listing's watched labels (issue 46)"
    names = set(re.findall(r"\bL(\d+)\b", text))
    if any(int(n) in labels for n in names):
        return "a variable named L<label> (issue 46)"
    return "unlisted"
