"""What the commands' ``--html`` pages are made from (issue 49): the program that printed, as
its listing and its WRITE statements (read from the front end's parse of its cards), and the
checks of the page's file name.  The pages themselves are :mod:`deck_emulator.present.dossier`'s."""

from __future__ import annotations

from deck_emulator.errors import UsageError


def check_html(path: str | None, *others: str | None) -> None:
    """``--html FILE.html``: a .html (or .htm) file whose folder is writable, not another
    output of the command; checked before any work."""
    if not path:
        return
    from deck_emulator.files import check_distinct, check_output_file

    if not path.lower().endswith((".html", ".htm")):
        raise UsageError(f"--html {path}: the dossier is an HTML page; name a .html file")
    check_distinct(path, *[o for o in others if o])
    check_output_file(path)


def program_listing(program, title: str):
    """The front end's ``program`` (:class:`deck_emulator.legacy.fortran.Program`: the cards
    that ran, the listing's with its errata or a job deck's own) as the page's
    :class:`~deck_emulator.present.dossier.Program`: each card with its number (the number
    the run's statements carry: its line), its internal statement number and unit, and each
    WRITE statement with its FORMAT's card and the names of its list."""
    from deck_emulator.legacy.jobdeck import statements
    from deck_emulator.present.dossier import ListedCard, Program, WriteStatement

    lines = program.lines
    numbers = list(range(1, len(lines) + 1))
    units = sorted((u.card, name) for name, u in program.units.items())

    def unit_of(card: int) -> str | None:
        found = None
        for start, name in units:
            if start <= card:
                found = name
        return found

    isn_of: dict[int, int] = {}
    formats: dict[tuple[str | None, int], tuple[int, str]] = {}
    for isn, st in enumerate(statements(lines, numbers), start=1):
        isn_of[st.line] = isn
        if st.label and st.text.upper().startswith("FORMAT("):
            # as punched: the first card's columns 1-72, each continuation's 7-72
            text = (st.cards[0][1][:72] + "".join(card[6:72] for _, card in st.cards[1:]))
            formats[(unit_of(st.line), int(st.label))] = (st.line, text.rstrip())
    writes = {}
    for name, unit in program.units.items():
        for st in unit.statements:
            if st.kind != "write":
                continue
            fmt = st.args[0]
            card, text = formats.get((name, fmt), (None, ""))
            writes[(name, st.card)] = WriteStatement(
                st.card, name, st.text, fmt, card, _list_names(st.text), text.strip())
    cards = tuple(ListedCard(n, text, isn_of.get(n), unit_of(n))
                  for n, text in zip(numbers, lines))
    return Program(title, cards, writes)


def _list_names(text: str) -> tuple[str, ...]:
    """The items of a WRITE statement's list as punched (``WRITE(6,200)YYPA,XRA``: YYPA,
    XRA), split at the commas outside parentheses."""
    depth, start = 0, None
    for i, ch in enumerate(text):  # the end of the control list WRITE(6,n)
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                start = i + 1
                break
    if start is None:
        return ()
    items, depth, item = [], 0, ""
    for ch in text[start:]:
        if ch == "," and depth == 0:
            items.append(item)
            item = ""
            continue
        depth += (ch == "(") - (ch == ")")
        item += ch
    if item:
        items.append(item)
    return tuple(items)
