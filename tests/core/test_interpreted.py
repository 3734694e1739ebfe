"""A single scene runs the batch's path with the core's functions as plain Python (no numba
loaded); a batch runs them compiled.  The one-shape rule: the same scene gives the same
numbers either way, bit for bit -- the compiled functions do the same IEEE operations in the
same order (numba without fast-math).  Checked in a fresh process, which runs the scenes
before and after numba compiles the functions."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

pytest.importorskip("numba")

SCRIPT = r"""
import dataclasses, json, sys
import numpy as np
from deck_emulator import decks
from deck_emulator.legacy.deck import read_deck
from deck_emulator.vocabulary.scene import LEGACY, PHYSICAL, Scene
from deck_emulator.core import batch, laws

cases = json.loads(sys.argv[1])
scenes, options = [], []
for deck, speed_factor, preset in cases:
    s = Scene.from_deck(read_deck(decks.path(deck)))
    if s.vehicle is not None:
        v = s.vehicle
        s = dataclasses.replace(s, vehicle=dataclasses.replace(
            v, initial_velocity_ft_s=v.initial_velocity_ft_s * speed_factor))
    scenes.append(s)
    options.append(LEGACY if preset == "legacy" else PHYSICAL)

def numbers(results):
    out = []
    for r in results:
        if isinstance(r, Exception):
            out.append(repr(r))
            continue
        t = r.trajectory
        grid = np.linspace(float(t.t_start), float(t.t_end), 41)
        out.append([r.hit.message if r.hit else None, r.hit.time_s if r.hit else None,
                    r.nfev, r.integrator, r.max_decel_g, r.delta_v_contact_mph,
                    t.state(grid).tolist()])
    return out

plain = numbers(batch.simulate_batch(scenes, options, compile=False))
assert "numba" not in sys.modules, "the plain run loaded numba"
laws.compile_functions()
assert laws.compiled()
compiled = numbers(batch.simulate_batch(scenes, options))
print(json.dumps({"plain": plain, "compiled": compiled}))
"""


def _run(cases) -> dict:
    out = subprocess.run([sys.executable, "-c", SCRIPT, json.dumps(cases)],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def test_the_report_s_decks_give_the_same_numbers_plain_and_compiled():
    cases = [[d, 1.0, "legacy"] for d in ("steel40", "steel20_a30")] + [
        ["steel40_a15", 1.0, "physical"]]
    got = _run(cases)
    assert got["plain"] == got["compiled"]
    assert all(isinstance(r, list) and r[0] for r in got["plain"])  # each ran to its hit


@settings(max_examples=3, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.sampled_from(["steel40", "steel20", "steel40_a30"]),
                          st.floats(0.5, 1.5), st.sampled_from(["legacy", "physical"])),
                min_size=1, max_size=2))
def test_a_scene_gives_the_same_numbers_alone_and_in_a_batch(cases):
    got = _run([list(c) for c in cases])
    assert got["plain"] == got["compiled"]


def test_one_scene_loads_neither_numba_nor_scipy():
    """A single run (the engine's ``run``, what ``core``, ``summary``, ``assembly`` and the API
    call) starts no compiler: no numba, no scipy imported, the batch's path taken."""
    out = subprocess.run([sys.executable, "-c", (
        "import sys\n"
        "from deck_emulator.engine import CoreEngine\n"
        "o = CoreEngine().run('steel40')\n"
        "print(o.error, o.hit_message is not None, 'numba' in sys.modules, "
        "'scipy' in sys.modules)\n")], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["None", "True", "False", "False"]
