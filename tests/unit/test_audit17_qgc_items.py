"""Audit 17: a QGroundControl ``.plan`` read as ArduSub executes it (:mod:`auvplan.io.missions.readback.qgc_items`).

``MAV_CMD_NAV_LOITER_UNLIM`` (17) never completes in ArduSub (``Sub::verify_loiter_unlimited`` returns false):
the vehicle holds that point until the mission is stopped, and no item after it is flown.  It was read as a
waypoint wherever it stood, so ``mission check`` judged (and passed) the legs after it, its energy and its
surface goal, none of which the vehicle flies.  Oracle: ArduSub's mission logic (ArduSub/commands_logic.cpp)."""

from __future__ import annotations

from typing import Any

import pytest

from auvplan.errors import DataError
from auvplan.io.missions.readback.qgc_items import plan_items


def _wp(command: int, lat: float, lon: float, alt: float) -> dict[str, Any]:
    return {"type": "SimpleItem", "autoContinue": True, "command": command, "doJumpId": 1, "frame": 3,
            "params": [0, 0, 0, None, lat, lon, alt], "AMSLAltAboveTerrain": None, "Altitude": alt, "AltitudeMode": 1}


def _speed(v: float) -> dict[str, Any]:
    return {"type": "SimpleItem", "autoContinue": True, "command": 178, "doJumpId": 1, "frame": 2,
            "params": [1, v, -1, 0, 0, 0, 0]}


def _doc(items: list[dict[str, Any]]) -> dict[str, Any]:
    return {"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
            "mission": {"version": 2, "firmwareType": 3, "vehicleType": 12, "cruiseSpeed": 1.0, "hoverSpeed": 1.0,
                        "globalPlanAltitudeMode": 1, "plannedHomePosition": [-7.0, 70.8, 0], "items": items}}


def test_an_unlimited_loiter_before_the_last_position_is_refused_naming_it():
    items = [_wp(16, -7.0, 70.81, -20.0), _wp(17, -7.0, 70.82, -20.0), _speed(2.0), _wp(16, -7.0, 70.83, -0.01)]
    with pytest.raises(DataError, match=r"LOITER_UNLIM \(17\).*never flown\) at mission\.items\[1\]"):
        plan_items(_doc(items))


def test_an_unlimited_loiter_as_the_last_position_is_its_point():
    # what a mission's end does anyway (exit_mission: the vehicle holds its last point); a command after it is fine
    items = [_wp(16, -7.0, 70.81, -20.0), _wp(17, -7.0, 70.82, -20.0), _speed(2.0)]
    got = [(it.command, it.moves) for it in plan_items(_doc(items))]
    assert got == [(16, True), (17, True), (178, False)]


def test_a_timed_loiter_still_reads_as_its_point_before_other_items():
    items = [_wp(19, -7.0, 70.81, -20.0), _wp(16, -7.0, 70.83, -20.0)]
    assert [it.moves for it in plan_items(_doc(items))] == [True, True]
