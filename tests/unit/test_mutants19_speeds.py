"""Round 6 of docs/mutants.md: what the speeds' rewrite's tests missed (``io/missions/readback/speeds.py``'s holds and
the QGC writer's leading ``MAV_CMD_DO_CHANGE_SPEED``), each case worked by hand.

* A ``MAV_CMD_NAV_LOITER_UNLIM`` (17) as the last position holds nothing the budget counts: its param 1 is no hold
  (ArduSub loiters there until the operator acts); only a waypoint's (16) or a timed loiter's (19) param 1 is.
* A hold of exactly 1 s is a hold (whole seconds: 0.999 s floors to none).
* The writer rounds the speed to 0.1 mm/s (4 decimals), writes its leading speed command only for a positive speed,
  and a one-point plan (no leg) still carries the speed given (none for no speed).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.formats import to_qgc_plan
from auvplan.io.missions.readback.speeds import read_holds, read_leg_speeds

ORIGIN = (-7.0, 70.8)


def _plan(tmp_path, items: list[tuple[int, object]]):
    """A ``.plan``: the home at x = 500 m, then one item ``(command, param 1)`` every 1 km east, 15 m deep."""
    frame = LocalFrame(*ORIGIN)
    rows = []
    for k, (command, p1) in enumerate(items):
        lon, lat = frame.inverse(1500.0 + 1000.0 * k, 1000.0)
        rows.append({"type": "SimpleItem", "command": command, "frame": 3,
                     "params": [p1, 0, 0, None, float(lat), float(lon), -15.0]})
    lon, lat = frame.inverse(500.0, 1000.0)
    path = tmp_path / "m.plan"
    path.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": rows}}))
    return path


def test_a_loiter_unlim_at_the_end_holds_nothing_the_budget_counts(tmp_path):
    # its param 1 (here 7, and 1e9: no 16-bit hold either) is not a hold: the holds are the timed ones only
    assert read_holds(_plan(tmp_path, [(16, 0), (19, 5), (17, 7)]), 4).tolist() == [0.0, 0.0, 5.0, 0.0]
    assert read_holds(_plan(tmp_path, [(16, 0), (19, 5), (17, 1e9)]), 4).tolist() == [0.0, 0.0, 5.0, 0.0]
    assert read_holds(_plan(tmp_path, [(16, 0), (16, 0), (17, 0)]), 4) is None  # no hold anywhere


@pytest.mark.parametrize(("hold", "want"), [(1, [0.0, 0.0, 1.0, 0.0]), (1.0, [0.0, 0.0, 1.0, 0.0]), (0.999, None)])
def test_a_hold_of_one_second_is_a_hold_and_less_is_none(tmp_path, hold, want):
    got = read_holds(_plan(tmp_path, [(16, 0), (16, hold), (16, 0)]), 4)
    assert got is None if want is None else got.tolist() == want


def _speeds(doc: dict) -> list[float]:
    return [it["params"][1] for it in doc["mission"]["items"] if it["command"] == 178]


def test_the_written_speed_is_rounded_to_a_tenth_of_a_millimetre_per_second(tmp_path):
    pts = np.array([[0.0, 0.0, -10.0], [300.0, 0.0, -10.0], [600.0, 0.0, -10.0]])
    doc = to_qgc_plan(pts, ORIGIN, 1.23456)
    assert _speeds(doc) == [1.2346]
    assert doc["mission"]["items"][0]["command"] == 178  # the launch's speed, before the first waypoint
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(doc))
    assert read_leg_speeds(path, 3).tolist() == [1.2346] * 3  # the launch from home and both legs


def test_no_leading_speed_command_without_a_positive_speed():
    pts = np.array([[0.0, 0.0, -10.0], [300.0, 0.0, -10.0]])
    assert _speeds(to_qgc_plan(pts, ORIGIN, 0.0)) == []  # 0 is ArduSub's "unchanged": not written
    assert _speeds(to_qgc_plan(pts, ORIGIN, 0.25)) == [0.25]


def test_a_one_point_plan_carries_the_speed_given_and_none_without_one():
    pt = np.array([[0.0, 0.0, -10.0]])
    doc = to_qgc_plan(pt, ORIGIN, 1.5)
    assert [it["command"] for it in doc["mission"]["items"]] == [178, 16]
    assert _speeds(doc) == [1.5]
    assert [it["command"] for it in to_qgc_plan(pt, ORIGIN, np.zeros(0))["mission"]["items"]] == [16]
