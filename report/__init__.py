"""The report's pages, built beside the package from its answers, never shipped with it.

One module a page: :mod:`.full` and :mod:`.page` (docs/report_full.md: all 18 columns of
Tables 11 and 12, Chapter V's crash test), :mod:`.figures`, :mod:`.verdicts` and
:mod:`.drawing` (docs/report/: Figures 22-29 and the statements of Sections 5.4 and 6.2-6.4),
:mod:`.comparison` (docs/comparison.md), :mod:`.shaft_contact` (docs/shaft_contact.md).
They read the package's engines, quantities and the report's own numbers
(``deck_emulator.studies.report_tables``); ``python -m report`` builds every page (each
script in ``scripts/`` builds one)."""
