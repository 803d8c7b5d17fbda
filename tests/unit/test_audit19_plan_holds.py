"""Audit 19: a ``.plan``'s holds as ArduPilot stores and flies them.

* ``AP_Mission::mavlink_int_to_mission_cmd`` copies a waypoint's or a timed loiter's param 1 (a float) into the
  16-bit ``cmd.p1``: a hold that truncates over 65535 s or below 0 is not the hold the vehicle flies (the
  conversion is undefined: it wraps on one platform and saturates on another); 65535.5 and -0.5 truncate to 65535
  and 0, which fit: held so (edges21, the C++ rule the executor's ``cmd.p1 = packet.param1`` follows).
  ``read_holds`` clamped 1e9 to 65535 s and read -5 as no
  hold: now refused (exit 2), naming the item and its value.
* ArduSub's ``verify_nav_wp`` waits the hold out at every waypoint, the last one too, before the mission completes;
  the budget held only at the start of a leg, so the last item's hold was left out of the file's energy and time.
  Oracle: with a hold at the last item the duration grows by the hold and the energy by the hotel power times it
  (still water: ArduSub holds against no current)."""

from __future__ import annotations

import json

import pytest

from auvplan.endurance import EnergyModel
from auvplan.errors import DataError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.energy import mission_file_energy
from auvplan.io.missions.readback.speeds import read_holds
from auvplan.io.scenario import loader
from helpers import HOLDS

_SCENARIO = HOLDS


def _plan(tmp_path, holds: list[object], command: int = 16):
    frame = LocalFrame(-7.0, 70.8)
    items = []
    for x, p1 in zip((500.0, 1500.0, 2500.0), holds):
        lon, lat = frame.inverse(x, 1000.0)
        items.append({"type": "SimpleItem", "command": command, "frame": 3,
                      "params": [p1, 0, 0, None, float(lat), float(lon), -15.0]})
    lon, lat = frame.inverse(500.0, 1000.0)
    path = tmp_path / "m.plan"
    path.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": items}}))
    return path


@pytest.mark.parametrize("hold", [65536, 70000, 1e9, -5, -1])
@pytest.mark.parametrize("command", [16, 19])
def test_a_hold_ardupilot_cannot_store_in_16_bits_is_refused_naming_the_item(tmp_path, hold, command):
    path = _plan(tmp_path, [0, hold, 0], command)
    with pytest.raises(DataError, match=rf"m\.plan: QGC plan: mission\.items\[1\]\.params\[0\] = {hold!r}: a hold"):
        read_holds(path, 4)


@pytest.mark.parametrize(("hold", "want"), [(65535, 65535.0), (65534.9, 65534.0), (0, None), (None, None),
                                            (65535.5, 65535.0), (-0.5, None)])  # C++ truncates: both fit 16 bits
def test_a_hold_within_16_bits_is_read_in_whole_seconds(tmp_path, hold, want):
    got = read_holds(_plan(tmp_path, [0, hold, 0]), 4)
    assert (got is None) if want is None else got.tolist() == [0.0, 0.0, want, 0.0]


@pytest.mark.parametrize("command", [16, 19])
def test_the_last_item_s_hold_is_flown_before_the_mission_completes(tmp_path, command):
    scen = tmp_path / "s.toml"
    scen.write_text(_SCENARIO)
    world, mission = loader.build(loader.load(str(scen)))
    rec = {hold: mission_file_energy(world, mission, _plan(tmp_path, [0, 0, hold], command))[0] for hold in (0, 1800.9)}
    hotel = float(EnergyModel.from_vehicle(mission.vehicle).power(0.0))
    assert rec[1800.9]["duration_s"] - rec[0]["duration_s"] == pytest.approx(1800.0, abs=1e-6)  # whole seconds
    assert rec[1800.9]["energy_wh"] - rec[0]["energy_wh"] == pytest.approx(hotel * 0.5, rel=1e-9)
    assert len(rec[1800.9]["leg_speeds_mps"]) == len(rec[0]["leg_speeds_mps"]) == 3  # the file's legs, no more


def test_a_reserve_broken_in_the_last_item_s_hold_is_named_so_not_a_leg_the_file_lacks(tmp_path):
    """3 legs (0-2) and 3000 s held at the last item on a 35 Wh battery: the hold breaks the reserve, not 'leg 3'."""
    scen = tmp_path / "s.toml"
    scen.write_text(_SCENARIO + "[vehicle]\nbattery_wh = 35.0\n")
    world, mission = loader.build(loader.load(str(scen)))
    rec, ok, line = mission_file_energy(world, mission, _plan(tmp_path, [0, 0, 3000]))
    assert not ok and rec["energy_status"] == "RESERVE_BROKEN"
    assert line.endswith("the reserve is entered in the hold at the last item") and "leg 3" not in line
