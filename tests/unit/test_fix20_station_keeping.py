"""fix20: a hold on station (an ArduSub waypoint's or timed loiter's hold: its position controller keeps the
vehicle on the item) in a current faster than the vehicle can move through the water.  The budget held the item
at ``P(|c|)`` whatever |c| — a 2 m/s current held by a vehicle whose top speed is 1.5 m/s was 'energy EXACT' —
while a leg the current blocks was ``INFEASIBLE``.  Now the hold is ``INFEASIBLE`` too, naming the waypoint.

The last item's hold is the budget's own (``Traverse.end_hold``), not a leg of no length appended by the file's
reader: the legs stay the file's, the figures the same.

Oracles: the current's speed against ``max_speed`` by hand (a steady uniform current; a surge ``1 + sin`` that
passes 1.8 m/s for 819 s of every 4000 s, held across a whole period or over a stretch where it stays below);
``P(|c|)`` × hold for the energy at the boundary (|c| = max_speed holds)."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, replace

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.endurance import EnergyModel
from auvplan.endurance.budget import mission_budget
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.energy import mission_file_energy
from auvplan.io.scenario import loader
from auvplan.world.currents.fields import CurrentField
from helpers import HOLDS

PERIOD = 4000.0


@dataclass(frozen=True)
class _Surge(CurrentField):
    """``(1 + sin(2π t / PERIOD), 0, 0)`` m/s everywhere: above 1.8 m/s while sin > 0.8."""

    def velocity(self, points, t=0.0):
        p = np.asarray(points, dtype=float)
        out = np.zeros(p.shape)
        out[..., 0] = 1.0 + math.sin(2.0 * math.pi * t / PERIOD)
        return out

    @property
    def steady(self) -> bool:
        return False

    @property
    def max_speed(self) -> float:
        return 2.0


def _world(tmp_path, extra: str = ""):
    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS + extra)
    return loader.build(loader.load(str(scen)))


def _plan(tmp_path, holds, command: int = 16):
    frame = LocalFrame(-7.0, 70.8)
    items = []
    for x, p1 in zip((500.0, 1500.0, 2500.0), holds):
        lon, lat = frame.inverse(x, 1000.0)
        items.append({"type": "SimpleItem", "command": command, "frame": 3,
                      "params": [p1, 0, 0, None, float(lat), float(lon), -15.0]})
    lon, lat = frame.inverse(100.0, 1000.0)  # the launch leg runs +x too (a vertical one is blocked by any 2 m/s)
    path = tmp_path / "m.plan"
    path.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": items}}))
    return path


_VEHICLE = "[vehicle]\nspeed = 1.5\nmax_speed = 1.5\n"


@pytest.mark.parametrize(("holds", "waypoint", "command"),
                         [([0, 600, 0], 2, 16), ([0, 0, 600], 3, 19), ([0, 0, 600], 3, 16), ([0, 600, 600], 2, 19)])
def test_a_hold_in_a_current_faster_than_the_vehicle_is_infeasible_naming_the_waypoint(tmp_path, command, holds,
                                                                                       waypoint):
    """2 m/s along the track (+x): every leg makes headway (2 + 1.5 m/s over ground) but no hold can be kept."""
    world, mission = _world(tmp_path, _VEHICLE + "[currents]\nuniform = [2.0, 0.0, 0.0]\n")
    rec, ok, line = mission_file_energy(world, mission, _plan(tmp_path, holds, command))
    assert not ok and rec["energy_status"] == "INFEASIBLE" and rec["energy_wh"] == math.inf
    assert f"the hold at waypoint {waypoint}: the current (2.00 m/s" in line
    assert "beats the vehicle's top speed 1.5 m/s: it cannot hold its position" in line
    free = mission_file_energy(world, mission, _plan(tmp_path, [0, 0, 0], command))[0]
    assert free["energy_status"] == "EXACT"  # the same legs without the holds fly


@pytest.mark.parametrize("current", [1.5, 0.9])
def test_a_hold_at_or_below_the_top_speed_is_kept_at_the_power_of_the_current(tmp_path, current):
    world, mission = _world(tmp_path, _VEHICLE + f"[currents]\nuniform = [{current}, 0.0, 0.0]\n")
    rec = {h: mission_file_energy(world, mission, _plan(tmp_path, [0, h, h]))[0] for h in (0, 900)}
    assert rec[900]["energy_status"] == "EXACT"
    power = float(EnergyModel.from_vehicle(mission.vehicle).power(current))
    assert rec[900]["energy_wh"] - rec[0]["energy_wh"] == pytest.approx(power * 1800 / 3600, rel=1e-9)
    assert rec[900]["duration_s"] - rec[0]["duration_s"] == pytest.approx(1800.0, abs=1e-6)
    assert len(rec[900]["leg_speeds_mps"]) == 3  # the file's legs (home → 3 items), the last hold in the last leg


def _surge_budget(tmp_path, hold_at: int, hold: float, depart: float, max_speed: float):
    world, _ = _world(tmp_path)
    world = replace(world, currents=_Surge())
    route = np.array([[0.0, 0.0, -15.0], [1000.0, 0.0, -15.0], [2000.0, 0.0, -15.0]])
    dwell = np.zeros(3)
    dwell[hold_at] = hold
    model = EnergyModel(max_speed=max_speed)
    return mission_budget(world, route, model, 1.2, depart, 50.0, None, dwell, dwell > 0)


@pytest.mark.parametrize("hold_at", [0, 1, 2])
def test_a_time_varying_current_blocks_the_hold_only_when_it_passes_the_top_speed(tmp_path, hold_at):
    """A whole period held: its 819 s above 1.8 m/s hold ≥ 3 of the 16 samples (250 s apart) → INFEASIBLE at 1.8 m/s,
    EXACT at 2.05 m/s; 1000 s held from t = 2000 s (sin ≤ 0: at most 1 m/s) → EXACT at 1.8 m/s."""
    b = _surge_budget(tmp_path, hold_at, PERIOD, 0.0, 1.8)
    assert b.status is Status.INFEASIBLE and f"the hold at waypoint {hold_at}: the current" in b.message
    assert _surge_budget(tmp_path, hold_at, PERIOD, 0.0, 2.05).status is Status.EXACT
    if hold_at == 0:  # held from the departure: t = 2000..3000 s, the current 1 + sin ≤ 1 m/s
        assert _surge_budget(tmp_path, 0, 1000.0, 2000.0, 1.8).status is Status.EXACT


def test_a_hold_past_a_blocked_leg_is_not_named(tmp_path):
    """The leg the current blocks comes first: the message names it, not a hold the vehicle never reaches."""
    world, mission = _world(tmp_path, _VEHICLE + "[currents]\nuniform = [-2.0, 0.0, 0.0]\n")
    line = mission_file_energy(world, mission, _plan(tmp_path, [600, 600, 600]))[2]
    assert "leg 0: the current beats the vehicle" in line and "the hold at" not in line
