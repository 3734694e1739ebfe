"""Many core scenes at once: ``CoreEngine.run_batch`` gives what ``run`` gives scene by scene
(the single-scene path is the reference), one scene's failure spoils no other, and the one
plug-in point (``_simulate_many``) hands the whole batch to a batched solver when the core has
one, falling back to the reference path when that solver cannot take the batch."""

from __future__ import annotations

import math

import numpy as np
import pytest

import deck_emulator.core as core
from deck_emulator.decks import path as deck_path
from deck_emulator.engine import CoreEngine, quantities
from deck_emulator.legacy.deck import read_deck
from deck_emulator.vocabulary import defaults


def _scenes():
    """A few decks and one typed scene: the report's steel post at 40 mph, 20 mph at 15 deg,
    40 mph at 30 deg, and the twin-arm assembly (a scene with a second luminaire)."""
    from deck_emulator.core.assembly import load_assembly, mass_properties
    from deck_emulator.engine.assemblies import to_scene

    asm, _, _ = load_assembly("twin")
    twin = to_scene(asm, mass_properties(asm), template="steel40")
    return [read_deck(deck_path(n)) for n in ("steel40", "steel20_a15", "steel40_a30")] + [twin]


def _same(a, b):
    """Two outcomes of the same scene agree in everything the studies read: name, scene,
    error, events, hit, every registry quantity, terminal points and the sampled arrays."""
    assert a.name == b.name and a.scene == b.scene and a.error == b.error
    assert a.settings == b.settings and a.hit_message == b.hit_message
    assert a.events == b.events
    qa, qb = quantities.values(a, quantities.names()), quantities.values(b, quantities.names())
    assert qa.keys() == qb.keys()
    for k in qa:
        x, y = qa[k], qb[k]
        assert (x is None) == (y is None), k
        if x is not None:
            assert x == y or (math.isnan(x) and math.isnan(y)), k
    assert a.terminal == b.terminal
    if a.t is not None or b.t is not None:
        assert np.array_equal(a.t, b.t)
        assert a.points.keys() == b.points.keys()
        for k in a.points:
            assert np.array_equal(a.points[k], b.points[k], equal_nan=True), k


@pytest.mark.parametrize("trace", [False, True])
def test_run_batch_is_run_scene_by_scene(trace):
    engine = CoreEngine(trace=trace, batched=False)
    scenes = _scenes()
    names = ["a", "", "c", "twin"]
    one_by_one = [engine.run(s, name=n) for s, n in zip(scenes, names)]
    together = engine.run_batch(scenes, names=names)
    assert len(together) == len(scenes)
    assert [o.name for o in together] == ["a", "steel20_a15", "c", "twin"]
    assert all(o.error is None and o.hit is not None for o in together)
    for a, b in zip(together, one_by_one):
        _same(a, b)
        assert a.run_s > 0


def test_one_bad_scene_spoils_no_other():
    """A deck the core refuses (W = 0: no post mass) between two good ones: its outcome says
    why, as ``run``'s does, and its neighbours are whole."""
    good = read_deck(deck_path("steel40"))
    bad = good.with_values(W=0.0)
    # the reference path, so that the neighbours can be compared with ``run`` exactly (the
    # compiled batch agrees with it within tolerances: tests/core/test_core_batch.py)
    engine = CoreEngine(trace=False, batched=False)
    got = engine.run_batch([good, bad, good])
    alone = engine.run(bad)
    assert got[1].error is not None and "post mass must be positive" in got[1].error
    assert got[1].error == alone.error and got[1].scene == alone.scene
    _same(got[0], engine.run(good))
    _same(got[2], got[0])
    assert engine.run_batch([]) == []
    with pytest.raises(ValueError, match="2 names for 1 scenes"):
        engine.run_batch([good], names=["a", "b"])


def test_a_run_that_fails_in_the_solver_is_kept_as_run_keeps_it(monkeypatch):
    """A run the core ends with CoreError (here its wall-time bound, as test_core_outcomes
    sets it) is an outcome with that error in the batch too."""
    engine = CoreEngine(trace=False, max_wall_s=1e-9, batched=False)
    decks = _scenes()[:2]
    got = engine.run_batch(decks)
    assert all(o.error and o.error.startswith("CoreError") for o in got)
    assert [o.error.split(":")[0] for o in got] == [engine.run(d).error.split(":")[0]
                                                     for d in decks]


def _agrees(got, ref):
    """The compiled batch's outcome ``got`` answers as the reference path's ``ref`` within
    the core's stated agreement (vocabulary.defaults, BATCH_AGREE_*): the same events and hit
    in the same order, their times, the terminal points and the speeds lost and decelerations
    within it."""
    assert got.error == ref.error
    if ref.error is not None:
        return
    assert got.trajectory.integrator == "compiled" and ref.trajectory.integrator == "scipy"
    assert got.hit_message == ref.hit_message
    assert [(e.kind, e.point, e.surface) for e in got.events] == [
        (e.kind, e.point, e.surface) for e in ref.events]
    assert all(abs(a.time_s - b.time_s) <= defaults.BATCH_AGREE_TIME_S
               for a, b in zip(got.events, ref.events))
    for name, tol in (("delta_v_contact_mph", defaults.BATCH_AGREE_DELTA_V_MPH),
                      ("delta_v_crush_mph", defaults.BATCH_AGREE_DELTA_V_MPH),
                      ("max_decel_g", defaults.BATCH_AGREE_DECEL_G)):
        a, b = quantities.value(name, got), quantities.value(name, ref)
        assert (a is None) == (b is None) and (a is None or abs(a - b) <= tol), name
    assert got.terminal.keys() == ref.terminal.keys()
    for k, p in ref.terminal.items():
        assert max(abs(x - y) for x, y in zip(p, got.terminal[k])) <= (
            defaults.BATCH_AGREE_POSITION_FT), k


def test_the_plug_in_point_hands_the_whole_batch_to_the_compiled_core(monkeypatch):
    """The engine hands the scenes the core accepts to the real compiled batch in one call
    (recorded on the way, its answers untouched) with the engine's options and wall bound,
    and what comes back agrees with the reference path (scipy) within the core's stated
    agreement; batched=False, or a method of solve_ivp's own, never calls it."""
    pytest.importorskip("numba")
    calls = []
    compiled = core.simulate_batch

    def recording(scenes, options, **kw):
        calls.append((len(scenes), options, kw))
        return compiled(scenes, options, **kw)

    monkeypatch.setattr(core, "simulate_batch", recording)
    good = read_deck(deck_path("steel40"))
    decks = [good, good.with_values(W=0.0), read_deck(deck_path("steel20_a15"))]
    engine = CoreEngine(trace=False)  # batched=None: the batched core, since it is there
    got = engine.run_batch(decks)
    assert len(calls) == 1 and calls[0][0] == 2  # one call; the refused scene never reaches it
    assert calls[0][1] == engine.model_options()
    assert calls[0][2]["max_wall_s"] == defaults.MAX_WALL_S  # the defaults' row
    assert got[1].error is not None and "post mass must be positive" in got[1].error
    reference = CoreEngine(trace=False, batched=False)
    for a, d in zip(got, decks):
        _agrees(a, reference.run(d))
    calls.clear()
    CoreEngine(trace=False, batched=False).run_batch(decks)
    CoreEngine(trace=False, method="DOP853").run_batch(decks[:1])
    assert calls == []


def test_an_engines_own_wall_bound_bounds_its_batch():
    """CoreEngine(max_wall_s=...) bounds a run_batch through the compiled core as it bounds one
    run: here 0 s, passed before either scene starts."""
    pytest.importorskip("numba")
    good = read_deck(deck_path("steel40"))
    got = CoreEngine(trace=False, batched=True, max_wall_s=0.0).run_batch([good, good])
    assert all(o.error and "max_wall_s = 0 s" in o.error for o in got)


def test_a_batch_the_batched_core_refuses_runs_on_the_reference_path(monkeypatch):
    def refuses(scenes, options, **kw):
        raise core.CoreError("this batch is beyond me")

    monkeypatch.setattr(core, "simulate_batch", refuses, raising=False)
    decks = _scenes()[:2]
    got = CoreEngine(trace=False).run_batch(decks)
    reference = CoreEngine(trace=False, batched=False)
    for a, d in zip(got, decks):
        ref = reference.run(d)
        # the fall-back is named, first among the outcome's notes, with why
        assert a.notes[0] == ("the compiled batch could not take this batch of 2 scenes "
                              "(CoreError: this batch is beyond me): this scene ran on the "
                              "scipy path (solve_ivp), one scene at a time")
        assert a.notes[1:] == ref.notes
        _same(a, ref)


def test_a_batch_answered_for_too_few_scenes_is_named_and_run_again(monkeypatch):
    monkeypatch.setattr(core, "simulate_batch", lambda scenes, options, **kw: [],
                        raising=False)
    got = CoreEngine(trace=False).run_batch(_scenes()[:1])
    assert "it answered for 0 of 1 scenes" in got[0].notes[0]
    assert got[0].error is None and got[0].trajectory.integrator == "scipy"


def test_batched_true_without_a_batched_core_says_so(monkeypatch):
    monkeypatch.setattr(core, "simulate_batch", None, raising=False)  # as if not there
    with pytest.raises(ValueError, match="no simulate_batch"):
        CoreEngine(batched=True).run_batch([read_deck(deck_path("steel40"))])


def test_each_quantity_says_which_arrays_it_reads():
    """The registry's declarations the engine is asked by: the hit's time and the ΔVs read
    none (the events and the core's dense solution), the occupant-risk pulse the car's
    velocity over the contact, the clearances the post's points too."""
    assert quantities.arrays_for(["hit_time_s", "delta_v_crush_mph",
                                  "delta_v_contact_mph", "max_decel_g"]) == ()
    assert quantities.arrays_for(["oiv_m_s", "hit_time_s"]) == ("car",)
    assert quantities.arrays_for(["roof_clearance_ft"]) == ("car", "points")
    assert all(set(q.reads) <= set(quantities.ARRAYS) for q in quantities.QUANTITIES.values())
    assert not any("pulse" in q.reads for q in quantities.QUANTITIES.values())


@pytest.mark.parametrize("arrays", [(), ("car",), ("car", "points"), ("pulse",)])
def test_an_engine_asked_for_fewer_arrays_gives_the_same_numbers(arrays):
    """An outcome made with only the arrays ``arrays`` gives every quantity that reads no
    other array the very value (bit for bit) of the outcome made with every array, on the
    compiled batch a study runs, for runs that end and one that ends without a hit; the
    arrays not asked for are not made."""
    scenes = _scenes()
    for kw in ({}, {"t_max_s": 0.05}):  # 50 ms: in contact still, no hit
        full = CoreEngine(**kw).run_batch(scenes)
        lean = CoreEngine(arrays=arrays, **kw).run_batch(scenes)
        for a, b in zip(full, lean):
            assert a.events == b.events and a.error == b.error and (a.hit is None) == bool(kw)
            for name, q in quantities.QUANTITIES.items():
                if set(q.reads) <= set(arrays):
                    x, y = q.of(a), q.of(b)
                    assert x == y or (x is None and y is None) or (
                        math.isnan(x) and math.isnan(y)), (name, x, y)
            assert (b.t.size > 0) == bool({"car", "points"} & set(arrays))
            assert bool(b.points) == ("points" in arrays)
            assert (b.pulse_t.size > 0) == ("pulse" in arrays)
