"""The corrections record and the named errata, read from the installed package.

``CORRECTIONS.md`` (shipped beside ``luminaire.f``; the checkout's ``legacy/CORRECTIONS.md``
is a link to it) lists every place where the transcription departs from the scanned listing,
numbered, with its reason; what the listing does that the report's equations do not, kept as
printed; and each erratum, with its patch in ``errata/NAME.patch``.  This module reads that one
file into entries a command can list and show; it writes nothing and holds no second copy.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from importlib import resources

from deck_emulator.legacy.stops import ERRATA

__all__ = ["Entry", "entries", "find", "document", "patch", "ERRATA"]


@dataclass(frozen=True)
class Entry:
    """One entry: ``key`` (a departure's number, an erratum's name, or a section's short
    name), ``kind`` (departure, kept, section, erratum), a one-line ``title`` and the
    ``text`` in full."""

    key: str
    kind: str
    title: str
    text: str


def _files():
    return resources.files("deck_emulator.legacy")


def document() -> str:
    """CORRECTIONS.md, whole."""
    return _files().joinpath("CORRECTIONS.md").read_text("utf-8")


def patch(name: str) -> str:
    """The erratum ``name``'s patch to luminaire.f."""
    return _files().joinpath("errata", f"{name}.patch").read_text("utf-8")


def _cells(row: str) -> list[str]:
    return [c.strip() for c in row.strip().strip("|").split(" | ")]


def entries() -> list[Entry]:
    """Every entry of the record, in its order."""
    text = document()
    sections = re.split(r"^## ", text, flags=re.M)[1:]
    out: list[Entry] = []
    for section in sections:
        heading, _, body = section.partition("\n")
        if heading == "Departures":
            rows = [r for r in body.splitlines() if re.match(r"\| \d+ \|", r)]
            header = _cells(next(r for r in body.splitlines() if r.startswith("| #")))
            for row in rows:
                cells = _cells(row)
                full = "\n".join(f"{h}: {c}" for h, c in zip(header[1:], cells[1:]))
                out.append(Entry(cells[0], "departure", f"{cells[1]} -- {cells[-1]}",
                                 f"Departure {cells[0]}\n{full}"))
        elif heading.startswith("Kept as printed"):
            for k, item in enumerate(re.split(r"^\* ", body, flags=re.M)[1:], start=1):
                one = " ".join(item.split())
                out.append(Entry(f"kept-{k}", "kept", one, f"Kept as printed: {one}"))
        else:
            match = re.match(r"Erratum `([^`]+)`", heading)
            if match and match.group(1) in ERRATA:
                name = match.group(1)
                text_ = f"## {heading}\n{body.rstrip()}\n\nThe patch (errata/{name}.patch):\n\n" \
                        f"{patch(name)}"
                out.append(Entry(name, "erratum", heading, text_))
            else:
                plain = heading.lower().replace("`", "").replace("'s", "")
                key = re.sub(r"[^a-z0-9]+", "-", plain).strip("-")
                out.append(Entry(key, "section", heading, f"## {heading}\n{body.rstrip()}\n"))
    return out


def find(key: str) -> Entry:
    """The entry named ``key`` (a departure's number, an erratum's name, a section's key);
    KeyError with the keys there are."""
    for entry in entries():
        if entry.key == key:
            return entry
    raise KeyError(key)
