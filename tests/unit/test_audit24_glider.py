"""Audit 24, gliders: a goal within the capture radius of the start (a virtual mooring, a short hop: 447 m with the
default 1 000 m radius).  Every flight reaches it at its first fix, so the nose-at-the-goal pilot's duration is 0 and
the time saved against it is 0/0: a NaN that ``glider.json`` (``allow_nan=False``) refused, `auvplan run` failing with
exit 2 and 'ValueError: Out of range float values are not JSON compliant: nan' after planning and flying.  Oracle by
hand: durations 0, the saving undefined (null), the record valid JSON."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest

from auvplan.app.glider import glider_record


def _track(reach_s: float) -> SimpleNamespace:
    return SimpleNamespace(arrived=True, reach_s=reach_s, arrive_s=reach_s, fixes=np.zeros((1, 3)), energy_j=0.0,
                           pump_j=0.0, inflections=0)


@pytest.mark.parametrize(("flown_s", "naive_s", "saved"), [(0.0, 0.0, None), (3600.0, 7200.0, 50.0)])
def test_glider_record_of_a_goal_within_the_capture_radius_is_json(flown_s, naive_s, saved):
    depart = 1000.0
    plan = SimpleNamespace(arrive_s=depart, result=SimpleNamespace(status=SimpleNamespace(value="EXACT"), message=""),
                           cycle=SimpleNamespace(duration_s=7500.0, speed=0.28), waypoints=np.array([[500.0, 0.0]]),
                           energy_j=0.0, endurance_days=30.0, headings=np.array([0.0]))
    rec = glider_record("near", plan, _track(depart + flown_s), _track(depart + naive_s), depart)
    back = json.loads(json.dumps(rec, allow_nan=False))
    assert back["flown_duration_s"] == flown_s and back["steady_heading_duration_s"] == naive_s
    assert back["saved_vs_steady_heading_pct"] == (pytest.approx(saved) if saved is not None else None)
