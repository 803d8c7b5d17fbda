"""audit18: a ``.plan``'s hold at depth (a waypoint's or a timed loiter's param 1, wave 17) is flown holding the
point: ArduSub's position controller keeps the vehicle on the item against the current (``do_nav_wp`` /
``do_loiter_time`` keep the destination as the target), so it spends the power of moving through the water at the
current's speed, not the hotel power of a vehicle at rest (a surface fix's drift).  An hour held in 0.5 m/s was
counted at hotel power: 'energy EXACT' short by the propulsion of that hour.

Oracle: in a steady uniform current c, the energy with a 1 h hold minus the energy without is ``P(|c|)`` × 1 h
(EnergyModel.power), the duration 3600 s longer; in still water, hotel power (wave 17's figure unchanged)."""

from __future__ import annotations

import json

import pytest

from auvplan.endurance import EnergyModel
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.energy import mission_file_energy
from auvplan.io.scenario import loader
from helpers import HOLDS

_SCENARIO = HOLDS.replace('name = "holds"', 'name = "holds in a current"')


def _plan(frame: LocalFrame, hold: float) -> str:
    def item(x: float, p1: float = 0.0) -> dict:
        lon, lat = frame.inverse(x, 1000.0)
        return {"type": "SimpleItem", "command": 19 if p1 else 16, "frame": 3,
                "params": [p1, 0, 0, None, float(lat), float(lon), -15.0]}

    lon, lat = frame.inverse(500.0, 1000.0)
    return json.dumps({"mission": {"cruiseSpeed": 1.5, "plannedHomePosition": [float(lat), float(lon), 0],
                                   "items": [item(500.0), item(1500.0, hold), item(2500.0)]}})


@pytest.mark.parametrize("current", [(0.0, 0.5, 0.0), (0.0, 0.0, 0.0)], ids=["0.5 m/s", "still"])
def test_an_hour_held_against_a_current_costs_the_power_of_that_current(tmp_path, current):
    scen = tmp_path / "s.toml"
    scen.write_text(_SCENARIO + f"[currents]\nuniform = {list(current)}\n")
    world, mission = loader.build(loader.load(str(scen)))
    frame = LocalFrame(*world.origin)
    rec = {}
    for hold in (0.0, 3600.0):
        path = tmp_path / f"m{hold:.0f}.plan"
        path.write_text(_plan(frame, hold))
        rec[hold] = mission_file_energy(world, mission, path)[0]
    power = EnergyModel.from_vehicle(mission.vehicle).power(float(sum(c * c for c in current)) ** 0.5)
    assert rec[3600.0]["duration_s"] - rec[0.0]["duration_s"] == pytest.approx(3600.0, abs=1e-6)
    assert rec[3600.0]["energy_wh"] - rec[0.0]["energy_wh"] == pytest.approx(float(power), rel=1e-9)
