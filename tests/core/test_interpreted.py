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
                    r.nfev, r.integrator, t.peak_force(), t.peak_force(True), r.contact_end_s,
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


FORMS_SCRIPT = r"""
import json, math, sys
import numpy as np
from deck_emulator import decks
from deck_emulator.legacy.deck import read_deck
from deck_emulator.vocabulary.scene import LEGACY, PHYSICAL, Scene
from deck_emulator.core import batch, dop853, laws, sliding
from deck_emulator.core.kinematics import ContactMode
from deck_emulator.core.model import assemble

MODULES = {"dop853": dop853, "batch": batch, "laws": laws}


def bits(x):
    if isinstance(x, np.ndarray):
        return [bits(v) for v in x.tolist()] if x.ndim else bits(x.item())
    if isinstance(x, (tuple, list)):
        return [bits(v) for v in x]
    if x is None or isinstance(x, (bool, np.bool_)):
        return x if x is None else bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    return float(x).hex()


def call(name, *args, out=()):
    # the function as its module has it now, on copies of the arguments: its answer and the
    # arrays it wrote
    module, _, function = name.partition(".")
    a = [np.array(v, copy=True) if isinstance(v, np.ndarray) else v for v in args]
    r = getattr(MODULES[module], function)(*a)
    return bits([r] + [a[i] for i in out])


def answers():
    # every function on the same drawn arguments, by name: its answer and what it wrote
    seed, specials, deck, preset, mode = json.loads(sys.argv[1])
    rng = np.random.default_rng(seed)
    model = assemble(Scene.from_deck(read_deck(decks.path(deck))),
                     LEGACY if preset == "legacy" else PHYSICAL)
    contact = ContactMode(**mode)
    P, M = model.law_parameters, model.mode_vector(contact)
    n = 15

    def noisy(v, scale):
        # around ``v``, with signed zeros where the draw says
        out = np.asarray(v, dtype=float) + rng.normal(scale=scale, size=np.shape(v))
        flat = out.reshape(-1)
        for k in specials:
            flat[k % flat.size] = -0.0 if k % 2 else 0.0
        return out

    y = noisy(model.y0, 0.05)
    y[6:10] /= np.linalg.norm(y[6:10])
    f = noisy(np.zeros(n), 10.0)
    h, t = float(rng.uniform(1e-5, 1e-3)), float(rng.uniform(0.0, 0.1))
    K = noisy(np.zeros((dop853.N_EXT, n)), 10.0)
    acc, ytmp, y_new = np.zeros(7), np.zeros(n), np.zeros(n)
    F = noisy(np.zeros((dop853.N_F, n)), 1e-3)
    scale = 1e-10 + np.abs(y) * 1e-10
    got = {}
    for phase in (dop853.PHASE_CONTACT, dop853.PHASE_FREE):
        got[f"_rhs {phase}"] = call("dop853._rhs", phase, t, y, P, M, acc, np.zeros(n),
                                    out=[6])
        got[f"_rk_step {phase}"] = call("dop853._rk_step", phase, t, y, f, h, P, M, K, acc,
                                        ytmp, y_new, out=[7, 9, 10])
        got[f"_dense {phase}"] = call("dop853._dense", phase, t, h, y, noisy(y, 1e-4), f, P,
                                      M, K, acc, ytmp, F, out=[8, 10, 11])
    got["_error_norm"] = call("dop853._error_norm", K, h, scale)
    got["_step_scale"] = call("dop853._step_scale", y, noisy(y, 1e-3), 1e-10, 1e-10, scale,
                              out=[4])
    got["_finite"] = call("dop853._finite", y)
    got["_finite, not"] = call("dop853._finite", np.where(np.arange(n) == seed % n, np.inf, y))
    got["_interp"] = call("dop853._interp", t, h, y, F, t + 0.3 * h, ytmp, out=[5])
    steps = 4
    hs = rng.uniform(1e-4, 1e-3, steps)
    ts = np.concatenate(([t], t + np.cumsum(hs)))
    y_olds = noisy(np.tile(y, (steps, 1)), 1e-3)
    Fs = noisy(np.zeros((steps, dop853.N_F, n)), 1e-4)
    tq = np.sort(rng.uniform(ts[0] - 1e-4, ts[-1] + 1e-4, 9))
    got["dense_eval"] = call("dop853.dense_eval", ts, ts[:-1], hs, y_olds, Fs, tq)
    if preset == "physical":
        free = model.checks.events() + (model.segment_checks.events()
                                        if model.segment_checks is not None else [])
        rows = (model.checks.A, model.checks.const, model.checks.letters)
    else:
        free, rows = [], (np.zeros((0, 1)), np.zeros(0), np.zeros(0, dtype=np.int64))
    specs = [s for s in sliding.contact_events(model, contact) if s.code is not None] + free
    EV = np.array([[s.code[0], s.code[1], s.direction, 1.0] for s in specs]).reshape(-1, 4)
    pairs = (model.segment_checks.table if model.segment_checks is not None
             else np.zeros((0, 7)))
    z = np.zeros(3 * rows[2].size + 1)
    got["_events_all"] = call("dop853._events_all", t, y, P, M, EV, *rows, pairs, z,
                              np.zeros(len(EV)), out=[10])
    for k in range(len(EV)):
        got[f"_event {k}"] = call("dop853._event", k, t, y, P, M, EV, *rows, pairs, z)
    g = noisy(np.zeros(len(EV)), 1.0)
    got["_crossed"] = call("dop853._crossed", g, noisy(g, 1.0), EV,
                           np.zeros(len(EV), dtype=np.int64), out=[3])
    got["_force_at"] = call("batch._force_at", float(tq[4]), ts, ts[:-1], hs, y_olds, Fs, P, M,
                            np.zeros(n))
    got["segment_max_force"] = call("batch.segment_max_force", ts, ts[:-1], hs, y_olds, Fs, P,
                                    M)
    got["vehicle_forces"] = call("laws.vehicle_forces", tq,
                                 noisy(np.tile(y, (9, 1)).T, 1e-3), P, M)
    return got


plain = answers()  # the plain forms: nothing compiled yet in this process
assert not laws.compiled() and "numba" not in sys.modules
laws.compile_functions()
compiled = answers()
print(json.dumps({name: plain[name] == compiled[name] for name in plain}))
"""

MODES = [{}, {"cap_engaged": True}, {"cap_sliding": True}, {"window": "kick"},
         {"contact_point": "T"}, {"friction_on": True, "friction_stick": True}]


@settings(max_examples=3, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1), st.lists(st.integers(0, 10**6), max_size=4),
       st.sampled_from(["steel40", "steel20_a30", "steel40_a15"]),
       st.sampled_from(["legacy", "physical"]), st.sampled_from(MODES))
def test_each_plain_form_does_the_compiled_function_s_arithmetic(seed, specials, deck, preset,
                                                                 mode):
    """Every function with a plain-Python form (rows of numpy arrays, or the laws over Python
    floats) gives the compiled function's numbers bit for bit -- its answer and every array
    it writes -- on states, stages and dense outputs drawn around a scene's, with signed
    zeros among them, in every kind of contact mode."""
    out = subprocess.run([sys.executable, "-c", FORMS_SCRIPT,
                          json.dumps([seed, specials, deck, preset, mode])],
                         capture_output=True, text=True, check=True)
    same = json.loads(out.stdout)
    assert same and all(same.values()), [name for name, ok in same.items() if not ok]
