"""The 1967 path: the card deck, the program (legacy/luminaire.f, run by the FORTRAN front end),
the line printer."""


def listing_lines() -> list[str]:
    """The lines of the listing: the package's copy of ``legacy/luminaire.f`` (read by the
    vocabulary, which reads the listing's words from it)."""
    from deck_emulator.vocabulary.listing_writes import listing_lines as lines

    return lines()
