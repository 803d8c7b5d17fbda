"""Audit 17: the time a ``.plan`` holds at a position counts in its energy.  ArduSub holds a
``MAV_CMD_NAV_WAYPOINT`` or a ``MAV_CMD_NAV_LOITER_TIME`` for its param 1 in whole seconds (``do_nav_wp`` /
``do_loiter_time``: ``loiter_time_max = cmd.p1``) before the next leg; the timed loiter read as its point (wave 13)
and a waypoint's hold were judged as if passed through: an hour's hold at depth, its hotel energy and the currents
an hour later, left out of ``mission check``'s 'energy EXACT'.  Oracle: the difference with and without the hold is
the hotel power times the hold (the vehicle's power at rest), and the duration the hold itself."""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.endurance import EnergyModel
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.energy import mission_file_energy
from auvplan.io.missions.readback.speeds import read_holds
from auvplan.io.scenario import loader
from helpers import HOLDS

_SCENARIO = HOLDS


def _plan(frame: LocalFrame, hold: object, command: int) -> str:
    def item(x: float, cmd: int = 16, p1: object = 0) -> dict:
        lon, lat = frame.inverse(x, 1000.0)
        return {"type": "SimpleItem", "command": cmd, "frame": 3,
                "params": [p1, 0, 0, None, float(lat), float(lon), -15.0]}

    lon, lat = frame.inverse(500.0, 1000.0)
    items = [item(500.0), item(1500.0, command, hold), item(2500.0)]
    home = [float(lat), float(lon), 0]
    return json.dumps({"mission": {"cruiseSpeed": 1.5, "plannedHomePosition": home, "items": items}})


@pytest.mark.parametrize("command", [16, 19])
def test_an_hour_held_at_a_position_costs_its_hotel_energy_and_time(tmp_path, command):
    scen = tmp_path / "s.toml"
    scen.write_text(_SCENARIO)
    world, mission = loader.build(loader.load(str(scen)))
    frame = LocalFrame(*world.origin)
    rec = {}
    for hold in (0, 3600.7):
        path = tmp_path / f"m{hold}.plan"
        path.write_text(_plan(frame, hold, command))
        rec[hold] = mission_file_energy(world, mission, path)[0]
    hotel = EnergyModel.from_vehicle(mission.vehicle).power(0.0)
    assert rec[3600.7]["duration_s"] - rec[0]["duration_s"] == pytest.approx(3600.0, abs=1e-6)  # whole seconds
    assert rec[3600.7]["energy_wh"] - rec[0]["energy_wh"] == pytest.approx(float(hotel), rel=1e-9)


@pytest.mark.parametrize(("hold", "want"), [(None, None), ("long", None), (2.9, 2.0)])
def test_a_hold_is_read_as_ardusub_stores_it(tmp_path, hold, want):
    frame = LocalFrame(-7.0, 70.8)
    path = tmp_path / "m.plan"
    path.write_text(_plan(frame, hold, 19))
    got = read_holds(path, 4)
    assert got is None if want is None else np.array_equal(got, [0.0, 0.0, want, 0.0])
