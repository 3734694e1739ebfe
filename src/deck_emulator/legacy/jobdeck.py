"""Whole decks as they went into the reader: IBSYS job decks in any card format.

A deck of data cards alone (``$DATA`` and eight cards) is a plain deck and reads exactly as
:func:`deck_emulator.legacy.deck.parse_deck` reads it; any other arrangement of ``$`` cards is
a job deck, each ``$DATA`` (or ``$ENTRY``) section a deck of its own, run in turn.  FORTRAN
source the deck carries is compared statement by statement with ``legacy/luminaire.f``.  The
job deck's layout and the comparison's rules: docs/emulator.md, "Job decks".
"""

from __future__ import annotations

from dataclasses import dataclass, field

from deck_emulator.legacy import listing_lines
from deck_emulator.legacy.cardimage import END_CARDS, card_texts, read_images
from deck_emulator.legacy.deck import CARD_COLUMNS, Deck, DeckError, parse_deck
from deck_emulator.vocabulary.listing_writes import is_comment, is_continuation

__all__ = ["Job", "parse_job", "Statement", "statements", "listing_lines",
           "compare_source", "job_deck_texts", "data_deck_texts"]

#: the largest deck file read (a job deck with its source is ~100 KB)
MAX_BYTES = 1 << 22
LISTING_NAME = "legacy/luminaire.f"
# Control cards that end a section and start none.
_DATA_STARTS = ("$DATA", "$ENTRY")


@dataclass(frozen=True)
class Statement:
    """One FORTRAN statement of a job deck's source: its label, its text and its cards."""

    label: str
    text: str  # columns 7-72 of the card and its continuations, blanks removed
    line: int  # card (or line) where it starts, 1-based
    #: (card or line number, columns 1-72 padded with blanks) of each of its cards: what a
    #: Hollerith text keeps (its blanks) and where a column is (the FORTRAN front end's)
    cards: tuple[tuple[int, str], ...] = field(default=(), repr=False, compare=False)


def statements(lines: list[str], numbers: list[int] | None = None) -> list[Statement]:
    """The FORTRAN statements of fixed-form source lines (see the module docstring);
    ``numbers`` are the lines' card or line numbers (default 1, 2, ...)."""
    result: list[Statement] = []
    for number, raw in zip(numbers or range(1, len(lines) + 1), lines):
        line = raw[:72]
        if is_comment(line):
            continue
        body = "".join(line[6:].split())
        card = ((number, line.ljust(72)),)
        if is_continuation(line) and result:
            last = result[-1]
            result[-1] = Statement(last.label, last.text + body, last.line, last.cards + card)
            continue
        result.append(Statement("".join(line[:5].split()), body, number, card))
    return result


def _shown(s: Statement) -> str:
    return f"{s.label + ' ' if s.label else ''}{s.text}"


_DIFFERS = "source: NOT the listing's program"


def compare_source(source: list[tuple[int, str]]) -> str:
    """One line: whether the source cards ((file card number, text) pairs) are the
    listing's program, or the first statement where they differ."""
    deck = statements([text for _, text in source], [number for number, _ in source])
    listing = statements(listing_lines())
    differs = f"{_DIFFERS} ({LISTING_NAME}): "
    for index, (mine, theirs) in enumerate(zip(deck, listing), start=1):
        if (mine.label, mine.text) != (theirs.label, theirs.text):
            return (f"{differs}statement {index} differs, deck card {mine.line} "
                    f"{_shown(mine)!r} against listing line {theirs.line} {_shown(theirs)!r}")
    if len(deck) < len(listing):
        nxt = listing[len(deck)]
        return (f"{differs}the deck's source ends after {len(deck)} statements; the listing "
                f"goes on at line {nxt.line} {_shown(nxt)!r}")
    if len(deck) > len(listing):
        extra = deck[len(listing)]
        return (f"{differs}the deck has more statements than the listing's {len(listing)}, "
                f"from card {extra.line} {_shown(extra)!r}")
    return (f"source: the same program as the listing ({LISTING_NAME}), {len(listing)} "
            "statements (columns 73-80 and blanks ignored)")


@dataclass(frozen=True)
class Job:
    """A deck read whole: its card format, its data decks in order, and what its source
    is (None when it carries none)."""

    path: str | None
    card_format: str
    decks: tuple[Deck, ...]
    source_verdict: str | None = None
    control_cards: tuple[str, ...] = field(default=(), repr=False)
    cards: int = 0  # cards in the file, control cards and source included
    #: the cards before the first $DATA (or $ENTRY) section, control cards and FORTRAN
    #: source, when the deck carries source (what its compile listing lists); () otherwise
    program_cards: tuple[str, ...] = field(default=(), repr=False)

    @property
    def program_differs(self) -> bool:
        """The deck carries FORTRAN that is not the listing's program."""
        return bool(self.source_verdict) and self.source_verdict.startswith(_DIFFERS)


def _is_control(text: str) -> bool:
    return text.startswith("$") or text[:4].lower() in END_CARDS


def _word(text: str) -> str:
    return text.split()[0].upper() if text.strip() else text


def parse_job(data: bytes, path: str | None = None, card_format: str = "auto",
              keypunch: str | None = None) -> Job:
    """Parse a deck file's bytes; see the module docstring."""
    if not isinstance(data, (bytes, bytearray)):
        raise TypeError(f"parse_job needs bytes, not {type(data).__name__}")
    data = bytes(data)
    images = read_images(data, card_format, path=path)
    texts = card_texts(images, keypunch, path=path)

    # a plain deck: control cards (if any) only before the data cards, at most one $DATA
    first_data = next((i for i, t in enumerate(texts) if not _is_control(t)), len(texts))
    words = [_word(t) for t in texts if _is_control(t)]
    plain = (not any(_is_control(t) for t in texts[first_data:])
             and "$IBFTC" not in words and words.count("$DATA") <= 1)
    if plain:
        if images.format == "text" and not (data.startswith(b"~") or b"\n~" in data):
            deck = parse_deck(data, path=path)  # exactly the reader of text decks
        else:
            deck = parse_deck("\n".join(texts), path=path)
        return Job(path, images.format, (deck,), None, tuple(t for t in texts if _is_control(t)),
                   cards=len(texts))

    sections: list[tuple[int, list[str]]] = []  # (file card number of the $DATA card, cards)
    source: list[tuple[int, str]] = []
    controls: list[str] = []
    state = "control"
    for number, text in enumerate(texts, start=1):
        if _is_control(text):
            controls.append(text)
            word = _word(text)
            if word in _DATA_STARTS:
                if sections and state == "data" and not sections[-1][1] and \
                        _word(texts[sections[-1][0] - 1]) == "$ENTRY":
                    sections.pop()  # $ENTRY directly followed by $DATA: one section
                sections.append((number, []))
                state = "data"
            elif word == "$IBFTC":
                state = "source"
            else:
                state = "control"
            continue
        if state == "source":
            source.append((number, text))
        elif state == "data":
            sections[-1][1].append(text)
        elif text.strip():
            raise DeckError(f"a card outside any $IBFTC or $DATA section (after the control "
                            f"card {controls[-1].strip()!r})" if controls else
                            "a card before any control card in a job deck",
                            file_card=number, path=path)
    if not sections:
        raise DeckError("job deck without a $DATA (or $ENTRY) card: no data cards for the "
                        "8 READ statements", path=path)
    # a text file that ends inside its last $DATA section with no line end may be cut short:
    # that section is read as the file ends, so the deck reader's cut-short check sees it
    unended = (images.format == "text" and not data.endswith((b"\n", b"\r"))
               and state == "data" and not _is_control(texts[-1]))
    decks = []
    verdict = compare_source(source) if source else None
    own = bool(verdict) and verdict.startswith(_DIFFERS)
    for index, (number, cards) in enumerate(sections, start=1):
        where = f"{path + ': ' if path else ''}$DATA section {index} (card {number} of the file)"
        end = "" if (unended and index == len(sections)) or not cards else "\n"
        try:
            decks.append(parse_deck("\n".join(cards) + end, path=where))
        except DeckError:
            if not own:
                raise
            # the deck's own FORTRAN reads its cards by its own FORMATs (checked as it reads
            # them), not as the listing's deck
            decks.append(Deck(where, {}, {}, tuple(c[:CARD_COLUMNS] for c in cards)))
    program = tuple(texts[:sections[0][0] - 1]) if source else ()
    return Job(path, images.format, tuple(decks), verdict, tuple(controls), cards=len(texts),
               program_cards=program)


# ------------------------------------------------------------------------- writing


def data_deck_texts(decks: list[Deck]) -> list[str]:
    """Card texts of plain data decks: a ``$DATA`` card and 8 data cards each."""
    texts: list[str] = []
    for deck in decks:
        texts += ["$DATA", *(card.rstrip(" ") for card in deck.cards)]
    return texts


def _punchable(line: str) -> str:
    """A comment card's text on a 1967 keypunch: capitals, and characters the FORTRAN
    set lacks (the transcription's ``;``) punched as blanks."""
    allowed = set("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 =+-*/(),.$'")
    return "".join(ch if ch in allowed else " " for ch in line.upper())


def job_deck_texts(decks: list[Deck], job_name: str = "LUMIN") -> list[str]:
    """Card texts of a whole IBSYS job deck: control cards, the listing's source (its
    ``C$`` comment lines as the control cards they stand for; its comment cards in capitals
    with the characters no keypunch had, such as ``;``, left blank), ``$ENTRY``, and each
    deck's ``$DATA`` section."""
    texts = [f"$JOB           {job_name}", "$EXECUTE       IBJOB", "$IBJOB"]
    for line in listing_lines():
        line = line.rstrip()
        if line.startswith("C$"):
            if _word(line[1:]) not in ("$EXECUTE", "$IBJOB"):  # those head the job already
                texts.append(line[1:])
            continue
        texts.append(_punchable(line) if line[:1] in ("C", "*") else line)
    texts += ["$ENTRY         MAIN", *data_deck_texts(decks), "$IBSYS"]
    assert all(len(t) <= CARD_COLUMNS for t in texts)
    return texts
