"""An Outcome is a value: once its engine has made it, no field can be assigned, no array
written, no sequence or mapping changed -- so the answers the registry computes from it (and
keeps in its memo) cannot go stale.  Every array attribute is walked, not a chosen few."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from deck_emulator.engine import CoreEngine, EmulatorEngine, quantities
from deck_emulator.engine.outcome import Outcome
from deck_emulator.vocabulary.events import Event, EventKind


@pytest.fixture(scope="module", params=["emulator", "core"])
def made(request):
    """The report's steel post at 40 mph as each engine makes it (every array asked for)."""
    engine = EmulatorEngine() if request.param == "emulator" else CoreEngine()
    return engine.run("steel40")


def _arrays(o):
    """Every array an outcome exposes, by a name saying where: its array fields and the
    arrays of its mapping fields."""
    for f in dataclasses.fields(o):
        v = getattr(o, f.name)
        if isinstance(v, np.ndarray):
            yield f.name, v
        elif hasattr(v, "items"):
            for k, a in v.items():
                if isinstance(a, np.ndarray):
                    yield f"{f.name}[{k!r}]", a


def test_every_array_refuses_a_write(made):
    arrays = dict(_arrays(made))
    # the fields an engine fills: none may be missing from the walk
    assert {"t", "sv", "vv", "free", "pulse_t", "pulse_g", "points['P']",
            "points['CM']"} <= set(arrays)
    for where, a in arrays.items():
        assert a.size, where  # a real run fills each of them
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 1
        with pytest.raises(ValueError, match="read-only"):
            a[...] = 0


def test_no_field_sequence_or_mapping_changes(made):
    with pytest.raises(dataclasses.FrozenInstanceError):
        made.vv = np.zeros(3)
    with pytest.raises(AttributeError):
        made.events.clear()
    with pytest.raises(AttributeError):
        made.flags.append("x")
    with pytest.raises(TypeError):
        made.points["P"] = np.zeros((1, 3))
    with pytest.raises(TypeError):
        made.terminal["P"] = (0.0, 0.0, 0.0)
    # the registry's answers read the same run before and after the attempts
    before = quantities.values(made, ("delta_v_crush_mph", "delta_v_contact_mph"))
    for _, a in _arrays(made):
        with pytest.raises(ValueError):
            a[:] = 0
    assert quantities.values(made, before) == before


finite = st.floats(-1e3, 1e3, allow_nan=False)


@given(st.lists(st.tuples(finite, finite), min_size=2, max_size=30))
@settings(max_examples=60, deadline=None)
def test_a_hand_made_outcome_is_a_value_too(samples):
    """Built from the caller's own lists and arrays: the outcome's arrays refuse a write, and
    a change to the caller's list after the making changes nothing of the outcome."""
    t = np.cumsum(np.abs([s[0] for s in samples])) + np.arange(len(samples))
    vv = [s[1] for s in samples]
    events = [Event(EventKind.LOST_VEHICLE, float(t[-1]))]
    o = Outcome("emulator", "hand", t=t, vv=vv, sv=np.zeros(len(vv)),
                points={"CM": np.zeros((len(vv), 3))}, events=events)
    before = o.car_velocity(float(t[-1]))
    vv[-1] += 1.0
    events.clear()
    assert o.car_velocity(float(t[-1])) == before and o.vehicle_contact_lost_s == float(t[-1])
    arrays = dict(_arrays(o))
    assert {"t", "sv", "vv", "points['CM']"} <= set(arrays)
    for a in arrays.values():
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 1
