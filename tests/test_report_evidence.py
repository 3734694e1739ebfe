"""Issue 24: the report page's evidence -- the candidate readings of ΔV (registry quantities),
the provenance of every column, the cells that equal an input or a symmetry, and the two
doubtful cells of the source. Every expected value is a hand computation or the report's
printed number, never the implementation's output."""

from __future__ import annotations

import math

import numpy as np
import pytest

from deck_emulator.engine.outcome import Outcome
from deck_emulator.engine.quantities import QUANTITIES, value
from deck_emulator.events import Event, EventKind

MPH = 88.0 / 60.0  # ft/s in one mph (written out: the hand computation's own factor)


def _hand_outcome(events, t=(0.0, 0.01, 0.02, 0.03), vv=(-58.66, -58.0, -57.0, -56.5)):
    return Outcome("emulator", "hand", t=np.array(t), vv=np.array(vv), events=list(events))


def test_first_spring_delta_v_reads_the_cars_speed_at_the_event():
    """A hand-built history: the car at -58.66 ft/s, -57.0 ft/s at 20 ms when the post loses
    the first spring: 1.66 ft/s lost = 1.66 / (88/60) mph."""
    out = _hand_outcome([Event(EventKind.LOST_FIRST_SPRING, 0.02)])
    assert value("delta_v_first_spring_mph", out) == pytest.approx(1.66 / MPH, abs=1e-12)


def test_first_spring_delta_v_between_two_samples_is_linear():
    """At 15 ms, halfway between -58.0 and -57.0 ft/s: -57.5, so 1.16 ft/s lost."""
    out = _hand_outcome([Event(EventKind.LOST_FIRST_SPRING, 0.015)])
    assert value("delta_v_first_spring_mph", out) == pytest.approx(1.16 / MPH, abs=1e-12)


def test_first_spring_delta_v_is_none_without_the_event_or_outside_the_run():
    assert value("delta_v_first_spring_mph", _hand_outcome([])) is None
    late = _hand_outcome([Event(EventKind.LOST_FIRST_SPRING, 0.5)])
    assert value("delta_v_first_spring_mph", late) is None


def test_the_three_delta_v_readings_are_registry_quantities_in_mph():
    from deck_emulator.studies.report_full import DECEL_CANDIDATES, DELTA_V_CANDIDATES

    for name in DELTA_V_CANDIDATES:
        assert QUANTITIES[name].unit == "mph" and name.endswith("_mph")
    for name in DECEL_CANDIDATES:
        assert QUANTITIES[name].unit == "g" and name.endswith("_g")
