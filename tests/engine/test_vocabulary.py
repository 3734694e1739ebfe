"""One vocabulary outside: the README's command table, run. Every command takes SOURCE the same
way (a shipped deck's name, a text deck, a card image, a job deck, a scene) or refuses a kind
in one line; every command has --json, whose answer begins with the same keys."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[2]
KINDS = ("shipped name", "text deck", "card image", "job deck", "scene")
ENVELOPE = ["schema", "command", "source", "settings", "status", "notes"]


def readme_table() -> dict[str, dict[str, str]]:
    """command -> column -> cell, from the README's table."""
    text = (ROOT / "README.md").read_text()
    block = text.split("| command | shipped name |", 1)[1].split("\n\n", 1)[0]
    cols = ["command", *KINDS, "--json", "exit statuses"]
    rows = {}
    for line in block.splitlines()[2:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        rows[cells[0]] = dict(zip(cols, cells))
    return rows


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """One file of each kind, made from the shipped steel40 by the tool itself."""
    d = tmp_path_factory.mktemp("kinds")
    paths = {"shipped name": "steel40", "text deck": str(d / "steel40.dat"),
             "card image": str(d / "steel40.cbn"), "job deck": str(d / "steel40.job"),
             "scene": str(d / "steel40.toml")}
    assert main(["punch", "steel40", "--to", "text", "--out", paths["text deck"]]) == 0
    assert main(["punch", "steel40", "--to", "cbn", "--out", paths["card image"]]) == 0
    assert main(["punch", "steel40", "--job", "--out", paths["job deck"]]) == 0
    assert main(["scene", "steel40", "--out", paths["scene"]]) == 0
    return paths


#: The quick form of each command of the table (SOURCE goes where {} is).
QUICK = {
    "`parse`": ["parse", "{}"],
    "`run`": ["run", "{}", "--out", "{out}"],
    "`summary`": ["summary", "{}", "--quiet"],
    "`diff`": ["diff", "{}", "--max-k", "0", "--quiet", "--jobs", "1"],
    "`core`": ["core", "{}", "--quiet"],
    "`scene`": ["scene", "{}"],
    "`plot`": ["plot", "{}", "--out", "{out}.png", "--quiet", "--engine", "core"],
    "`punch`": ["punch", "{}", "--to", "text"],
}


@pytest.mark.parametrize("command", list(QUICK))
def test_each_command_takes_every_kind_of_source_as_the_readme_says(command, inputs, capsys,
                                                                    tmp_path):
    row = readme_table()[command]
    for kind in KINDS:
        argv = [a.replace("{}", inputs[kind]).replace("{out}", str(tmp_path / "out"))
                for a in QUICK[command]]
        code = main(argv)
        err = capsys.readouterr().err
        if row[kind].startswith("refused"):
            assert code == 2, (command, kind, err)
            lines = [x for x in err.splitlines() if x.startswith("deck-emulator: error:")]
            assert len(lines) == 1 and "Traceback" not in err, err
            assert "deck-emulator core" in lines[0] or "scene" in lines[0]  # names the way out
        else:
            assert code == 0, (command, kind, err)


@pytest.mark.parametrize("argv", [
    ["sweep", "--speeds", "40", "--angles", "0", "--base-deck", "{}", "--out", "{out}"],
    ["study", "error", "{}", "--out", "{out}", "--quick"],
    ["study", "stability", "--deck", "{}", "--out", "{out}", "--quick"],
    ["sensitivity", "--deck", "{}", "--out", "{out}", "--quick"],
])
@pytest.mark.parametrize("kind", ["card image", "job deck", "scene"])
def test_the_studies_refuse_what_they_cannot_read_in_one_line_naming_the_conversion(
        argv, kind, inputs, capsys, tmp_path):
    out = tmp_path / "out"
    code = main([a.replace("{}", inputs[kind]).replace("{out}", str(out)) for a in argv])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err
    lines = [x for x in err.splitlines() if x.startswith("deck-emulator: error:")]
    assert len(lines) == 1
    assert "punch" in lines[0] or "core" in lines[0]
    assert not out.exists()  # nothing written


def test_the_studies_take_a_shipped_name_and_a_text_deck(inputs):
    from deck_emulator.app.common import deck_file as _deck_file

    assert Path(_deck_file("steel40", "study error").path).name == "steel40.dat"
    assert _deck_file(inputs["text deck"], "study error").path == inputs["text deck"]


def test_every_command_has_json(capsys):
    commands = ["parse", "run", "summary", "diff", "core", "scene", "plot", "punch", "sweep",
                "sensitivity", "assembly"]
    for command in commands + ["study error", "study stability"]:
        assert main([*command.split(), "--help"]) == 0
        assert "--json" in capsys.readouterr().out, command
    table = readme_table()
    assert all(row["--json"] == "yes" for row in table.values())


@pytest.mark.parametrize("argv", [
    ["parse", "steel40", "--json"],
    ["punch", "steel40", "--json"],
    ["run", "steel40", "--json"],
    ["scene", "steel40", "--json"],
    ["summary", "steel40", "--json", "--quiet"],
    ["core", "steel40", "--json", "--quiet"],
    ["assembly", "twin", "props", "--json"],
])
def test_every_answer_begins_with_the_same_keys(argv, capsys):
    assert main(argv) == 0
    answer = json.loads(capsys.readouterr().out)
    assert list(answer)[:len(ENVELOPE)] == ENVELOPE
    assert answer["command"] == argv[0] and answer["status"] == "ok"
    assert answer["schema"] == 2


def test_a_job_deck_runs_its_own_program_or_none(inputs, tmp_path, capsys):
    text = Path(inputs["job deck"]).read_text()
    assert "HI=0.0004" in text
    changed = tmp_path / "changed.job"
    changed.write_text(text.replace("HI=0.0004", "HI=0.0002", 1))
    out = tmp_path / "printout.txt"
    # run runs the deck's own FORTRAN (tests/legacy/test_fortran.py: as gfortran does) ...
    assert main(["run", str(changed), "--out", str(out), "--quiet"]) == 0
    first = capsys.readouterr().err.splitlines()[0]
    assert "own FORTRAN runs" in first and "NOT the listing's program" in first
    assert "HI=0.0002" in first
    # ... a command that runs only the listing refuses it
    assert main(["summary", str(changed), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "NOT the listing's program" in err and "HI=0.0002" in err
    assert main(["run", str(changed), "--listing-program", "--out", str(out)]) == 0
    first = capsys.readouterr().err.splitlines()[0]
    assert "--listing-program" in first and "LISTING's program" in first
    assert main(["run", inputs["job deck"], "--out", str(tmp_path / "same.txt")]) == 0
    assert "the same program as the listing" in capsys.readouterr().err


def test_a_job_deck_with_two_sections_is_chosen_by_section(tmp_path, capsys):
    from deck_emulator.decks import path
    from deck_emulator.legacy.deck import read_deck
    from deck_emulator.legacy.jobdeck import job_deck_texts

    two = tmp_path / "two.job"
    decks = [read_deck(path("steel40")), read_deck(path("steel20"))]
    two.write_text("\n".join(job_deck_texts(decks)) + "\n")
    assert main(["summary", str(two), "--quiet"]) == 2
    assert "--section N (1 to 2)" in capsys.readouterr().err
    assert main(["parse", str(two), "--section", "2", "--json"]) == 0
    values = json.loads(capsys.readouterr().out)["values"]
    assert values == dict(decks[1].values)
    assert main(["parse", str(two), "--section", "3"]) == 2
    assert "holds 2 $DATA section(s)" in capsys.readouterr().err


def test_the_reports_deck_diffs_with_no_options(capsys):
    """As printed, ED walks away from its root once the step is halved: with no options the
    halved steps take ed-direction, say so, and every row ends: exit 0. As printed
    (--as-printed-rows) the rows say where it stopped and what lets it run: exit 3."""
    assert main(["diff", "steel40", "--max-k", "1", "--quiet", "--jobs", "1"]) == 0
    out = capsys.readouterr().out
    assert "stopped" not in out and "errata: ed-direction, since as printed ED walks away" in out
    assert main(["diff", "steel40", "--max-k", "1", "--quiet", "--jobs", "1",
                 "--as-printed-rows"]) == 3
    out = capsys.readouterr().out
    assert re.search(r"^ 1 .*stopped: the emulator stopped at k = 1", out, re.M)
    assert "--erratum ed-direction lets it run" in out
    assert "cannot run this deck from k = 1 on" in out


def test_a_sweep_with_a_stopped_scene_writes_its_tables_rates_nothing_for_it_and_exits_3(
        tmp_path, capsys):
    """steel40 at 15 deg needs the ed-direction erratum (decks/README.md): without it the scene
    stops early. The tables are written, its row says why and what would let it run, no
    rating is given for it, exit 3."""
    import csv

    out = tmp_path / "sw"
    assert main(["sweep", "--speeds", "40", "--angles", "0,15", "--jobs", "1", "--quiet",
                 "--out", str(out)]) == 3
    err = capsys.readouterr().err
    assert "steel40_a15 stopped early" in err and "--erratum ed-direction" in err
    rows = {r["scene"]: r for r in csv.DictReader((out / "sweep.csv").open())}
    stopped, ran = rows["steel40_a15"], rows["steel40"]
    assert stopped["error"] and "ed-direction" in stopped["stopped_hint"]
    assert stopped["nchrp350_oiv_rating"] == stopped["nchrp350_ora_rating"] == ""
    assert stopped["compartment_verdict"] == ""
    assert ran["error"] == "" and ran["nchrp350_oiv_rating"] and ran["stopped_hint"] == ""
    # the emulator tests only P, R and C: the compartment is not judged, never passed
    assert ran["compartment_verdict"] == "not judged"
    assert (out / "sweep.md").is_file()
