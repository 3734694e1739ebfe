"""The API takes the command line's names and forms for the errata: ``erratum=`` as
``--erratum``, one name or a list of names (a string is never split into its letters)."""

from __future__ import annotations

import json

import pytest

import deck_emulator
from deck_emulator.cli import main
from deck_emulator.errors import UsageError

#: steel40 at 15 deg stops in ED as printed; the ed-direction erratum lets it run to its hit
#: (legacy/CORRECTIONS.md)
DECK, ERRATUM = "steel40_a15", "ed-direction"


@pytest.fixture(scope="module")
def by_the_command_line():
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["summary", DECK, "--erratum", ERRATUM, "--json"]) == 0
    return json.loads(buf.getvalue())


@pytest.mark.parametrize("options", [
    {"erratum": ERRATUM}, {"errata": ERRATUM}, {"erratum": [ERRATUM]}, {"errata": (ERRATUM,)},
    {"erratum": ERRATUM, "errata": [ERRATUM]},
])
def test_every_form_runs_to_the_hit_the_command_line_gives(options, by_the_command_line):
    out = deck_emulator.run(DECK, **options)
    assert out.error is None and out.hit is not None
    assert out.errata == (ERRATUM,)
    assert out.hit_time_s == by_the_command_line["quantities"]["hit_time_s"]


def test_an_unknown_name_is_named_whole():
    with pytest.raises(ValueError, match=r"\['no-such-erratum'\]"):
        deck_emulator.run(DECK, erratum="no-such-erratum")


def test_two_different_answers_to_one_question_are_refused():
    with pytest.raises(UsageError, match="once"):
        deck_emulator.run(DECK, erratum=ERRATUM, errata=())
