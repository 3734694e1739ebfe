#!/usr/bin/env python3
"""Write docs/models.md: the three models (the emulator, the core's legacy preset without and
with the shaft test, the physical preset) side by side on the three posts at 20 and 40 mph,
each number taken from the command's own --json answer.

    python scripts/make_models_doc.py
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "models.md"
PROGRAM = "deck-emulator"

#: (post, speed, how its deck is named to the emulator and to the core)
POSTS = [("steel", 20, "steel20"), ("steel", 40, "steel40"),
         ("aluminium", 20, None), ("aluminium", 40, None),
         ("twin", 20, None), ("twin", 40, None)]

#: (model, the options the core takes for it; None: the emulator, by `summary`)
MODELS = [
    ("emulator (the listing's checks)", None),
    ("core, legacy preset", []),
    ("core, legacy preset, --shaft-contact", ["--shaft-contact"]),
    ("core, physical preset", ["--preset", "physical"]),
]


def answer(args: list[str], folder: Path) -> dict:
    """The --json answer of `deck-emulator ARGS --json` (exit 0 or 3: a run that stopped is a
    row that says so)."""
    done = subprocess.run([sys.executable, "-m", "deck_emulator", *args, "--json"], cwd=folder,
                          capture_output=True, text=True)
    if done.returncode not in (0, 3):
        raise SystemExit(f"make_models_doc: {PROGRAM} {' '.join(args)}: exit "
                         f"{done.returncode}: {done.stderr.strip()}")
    return json.loads(done.stdout)


def commands(post: str, speed: int, deck: str | None, options) -> list[list[str]]:
    """The commands a row is taken from (the last one's answer is the row)."""
    speed_opt = ["--speed-mph", str(speed)]
    if deck is None and options is None:  # the assembly's deck, on the emulator
        name = f"{post}{speed}.dat"
        return [["assembly", post, "deck", *speed_opt, "--out", name], ["summary", name]]
    if deck is None:
        return [["assembly", post, "core", *speed_opt, *options]]
    return [["summary", deck]] if options is None else [["core", deck, *options]]


def _num(x, fmt="{:.2f}") -> str:
    return "—" if x is None else fmt.format(x)


def row(model: str, data: dict) -> str:
    if data.get("refused"):
        return f"| {model} | refused: {data['refused']} | | | | | |"
    if data.get("status") == "stopped":
        return f"| {model} | stopped: {data.get('error', '')} | | | | | |"
    hits = [e["sentence"] for e in data["events"] if e["kind"] == "hit"]
    end = hits[-1].removeprefix("post ") if hits else "no hit"
    q, risk = data["quantities"], data["occupant_risk"]
    ratings = data.get("ratings") or {}
    comp = ratings.get("occupant_compartment", {})
    verdict = comp.get("verdict", "—")
    if comp.get("part"):  # the first strike on the car, as what it is
        verdict += (f": {comp['part']} strikes the {comp['surface']}"
                    + (" (the compartment)" if comp.get("in_compartment") else
                       " (outside the compartment)")
                    + (f", its path {comp['depth_ft']:.2f} ft into the car"
                       if comp.get("depth_ft") else ""))
    return (f"| {model} | {end} | {_num(q.get('delta_v_crush_mph'))} | "
            f"{_num(q.get('delta_v_contact_mph'))} | {_num(risk.get('oiv_m_s'))} | "
            f"{_num(risk.get('ora_g'))} | {verdict} |")


def page(tables: list[tuple[str, list[tuple[str, list[str], dict]]]]) -> str:
    lines = [
        "# Which model for a safety judgement",
        "",
        "Made by `python scripts/make_models_doc.py`: every number below is the `--json` answer "
        "of the command named under its table.",
        "",
        "The project has one model of the post and the car (the report's Chapter III) and four "
        "ways to run it:",
        "",
        f"* **the emulator** (`{PROGRAM} summary DECK`): the 1967 listing as printed. It tests "
        "only the points P, R and C against the car and the ground, so a shaft that passes "
        "into the car is not seen: its run goes on through the car.",
        f"* **the core's legacy preset** (`{PROGRAM} core DECK`): the same model and the "
        "listing's quirks (start-up kick, spring and force cap, friction, hit tolerances), "
        "solved with located events; the same point checks as the listing.",
        f"* **legacy with the shaft test** (`{PROGRAM} core DECK --shaft-contact`): the same, "
        "and the shaft Q-P and the arms P-R, P-U tested as segments against the car's three "
        "solid boxes (docs/shaft_contact.md).",
        f"* **the physical preset** (`{PROGRAM} core DECK --preset physical`): the model "
        "without the listing's quirks, the shaft test on. It has no force cap, so no crush "
        "pulse: its ΔV by the end of the crush pulse is —.",
        "",
        "The aluminium and twin posts are the report's fitted assemblies "
        f"(`{PROGRAM} assembly NAME core --speed-mph MPH`; their emulator rows run the deck "
        f"`{PROGRAM} assembly NAME deck --speed-mph MPH` writes). ΔV crush: "
        "`delta_v_crush_mph`, the speed the car lost by the end of the crush pulse (one of "
        "three readings of the report's DECREASE IN VEHICLE VELOCITY, which the report "
        "defines nowhere; which reading fits which post: docs/report_full.md, 'ΔV and the "
        "maximum deceleration'); ΔV contact: `delta_v_contact_mph`, by the loss of contact. OIV in m/s, "
        "ORA in g (docs/safety.md). Compartment: the occupant-compartment verdict "
        "(`ratings.occupant_compartment`, docs/safety.md), with the first place the post "
        "strikes the car: the occupant compartment is the roof, windshield and side glass, "
        "not the hood or the trunk; `passes` is a model that tested the whole post and found "
        "none of it on the car before the run ended, `not judged` a strike on the "
        "compartment (a rigid car computes no deformation), a strike beside it after which "
        "the post is not followed, or a model that cannot see the shaft.",
        "",
        "## Which to use",
        "",
        "**A safety judgement needs a model that tests the whole post against the car: the "
        f"core with the shaft test, `{PROGRAM} core DECK --shaft-contact`** (or "
        f"`{PROGRAM} assembly NAME core --shaft-contact`). The emulator and the legacy preset "
        "without it check only three points, so a shaft that goes through the hood or the roof "
        "is invisible to them: their compartment verdict is `not judged` at best, and the "
        "hits they report may be hits the post could never make (the post is already in the "
        "car). With the shaft test the legacy preset keeps the listing's spring, force cap and "
        "friction, so its ΔV, OIV and ORA are the report's model's; at 20 mph it ends on the "
        "car in all nine of Table 11's columns, as the report does in eight "
        "(docs/shaft_contact.md). The physical "
        "preset tests the whole post too and answers what the model gives without the "
        "listing's quirks; where the two disagree, take the more cautious answer.",
        "",
        "## One post, one deck",
        "",
        f"An assembly is one post for both engines. `{PROGRAM} assembly NAME deck` writes "
        "the post's deck, each field in its 10 columns to F10.5's five decimals where "
        "they fit (fewer where the number is wider); `assembly NAME emulator` runs that "
        "deck, and `assembly NAME core` builds its scene from the same values as punched "
        "(DELTA 0.14772 for the steel post, not the builder's 0.1477221). The deck as "
        "punched is the right post: it is what the 1967 program read, the report's decks "
        "and the Tables' inputs are five-decimal cards, and the builder's further digits "
        "come from a fitted model of the post (a tapered tube and a curved arm), whose "
        "error (+7 % in A and B against the report's steel deck: docs/report_full.md) is "
        "far larger than the fifth decimal. The twin's second luminaire U, which no "
        "card carries, is taken to the same five decimals. Against the full-precision "
        "values, the core's answers on the fitted posts (Tables 11 and 12's aluminium and "
        "twin columns, legacy preset) moved by at most 3e-6 mph in ΔV, 3e-6 g in "
        "deceleration, 0.002 ms in the hit time and 2e-4 ft in a terminal point. Both "
        "answers carry the values they ran (`deck` in their `--json`, docs/json.md).",
        "",
    ]
    for title, rows in tables:
        lines += [f"## {title}", "",
                  "| model | end | ΔV crush (mph) | ΔV contact (mph) | OIV (m/s) | ORA (g) | "
                  "compartment |",
                  "|---|---|---:|---:|---:|---:|---|"]
        lines += [row(model, data) for model, _, data in rows]
        said = []
        for _, cmds, data in rows:
            said += [f"`{PROGRAM} {' '.join(c)}`" for c in cmds]
            if data.get("refused"):
                said[-1] += " (exit 2: refused)"
        lines += ["", "Commands, in the rows' order: " + "; ".join(said) + ".", ""]
    return "\n".join(lines)


def main() -> int:
    tables = []
    with tempfile.TemporaryDirectory(prefix="models-") as tmp:
        folder = Path(tmp)
        for post, speed, deck in POSTS:
            rows = []
            for model, options in MODELS:
                cmds = commands(post, speed, deck, options)
                refused = None
                for c in cmds[:-1]:
                    done = subprocess.run([sys.executable, "-m", "deck_emulator", *c],
                                          cwd=folder, capture_output=True, text=True)
                    if done.returncode == 2:  # bad input: the post is not the listing's
                        refused = done.stderr.strip().removeprefix(f"{PROGRAM}: error: ")
                        cmds = cmds[:cmds.index(c) + 1]
                        break
                    if done.returncode:
                        raise SystemExit(f"make_models_doc: {PROGRAM} {' '.join(c)}: "
                                         f"{done.stderr.strip()}")
                rows.append((model, cmds, {"refused": refused} if refused else
                             answer(cmds[-1], folder)))
            tables.append((f"{post} post, {speed} mph", rows))
            print(f"{post} {speed} mph", file=sys.stderr)
    PAGE.write_text(page(tables))
    print(f"wrote {PAGE.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
