"""A ``.plan`` makes ArduSub fly the planned speed, and ``mission check`` judges it at the speed it will fly.

QGroundControl never uploads a plan's ``cruiseSpeed``/``hoverSpeed`` (its time estimates): without a
``MAV_CMD_DO_CHANGE_SPEED`` (178) ArduSub flies its ``WPNAV_SPEED`` parameter.  The export writes a leading 178 at
the planned speed; the check reads no speed from ``cruiseSpeed`` and names the legs it judges at the scenario
vehicle's speed (``speed_assumed_legs``).  Oracles: the item's bytes, and length / speed and P(v) t by hand on a
still-water scenario (no current: the ground speed is the water speed).
"""

from __future__ import annotations

import contextlib
import io
import json

import numpy as np
import pytest

from auvplan import cli
from auvplan.endurance import EnergyModel
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.formats import to_qgc_plan
from auvplan.vehicles import VehicleParams

ORIGIN = (48.0, -125.0)
# a plane seabed 50-160 m deep, still water; the vehicle's own speed 1.0 m/s (the plans say 1.5 or per leg)
SCENARIO = """
name = "still"
seed = 1
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [-500.0, 5500.0]
y = [-1500.0, 3500.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 50.0
slope = [-0.01, -0.02]
cell_m = 25.0
[currents]
uniform = [0.0, 0.0, 0.0]
[mission]
start = [200.0, -300.0, -10.0]
goal = [4000.0, 2000.0, -20.0]
min_altitude_m = 5.0
min_depth_m = 2.0
max_depth_m = 300.0
[vehicle]
speed = 1.0
"""
POINTS = np.array([[200.0, -300.0, -10.0], [1500.0, -300.0, -30.0], [1500.0, 1200.0, -30.0],
                   [4000.0, 2000.0, -20.0]])
# the legs as the check flies them: the launch from the home on the surface above the first point, then the items
LEGS = np.r_[10.0, np.linalg.norm(np.diff(POINTS, axis=0), axis=1)]
# each leg's horizontal length over its length (the launch is vertical: 1): WPNav flies a 178's speed v level,
# at v / cos γ along the leg (audit 20)
COS = np.r_[1.0, np.hypot(*np.diff(POINTS, axis=0)[:, :2].T) / LEGS[1:]]


def _check(tmp_path, doc, json_out=True):
    scen = tmp_path / "s.toml"
    scen.write_text(SCENARIO, encoding="utf-8")
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(doc), encoding="utf-8")
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = cli.main(["mission", "check", str(path), "--scenario", str(scen), *(["--json"] if json_out else [])])
    return code, (json.loads(buf.getvalue()) if json_out else buf.getvalue())


def _qgc_written(speed_item_after=None, speed=1.5):
    """A plan as QGroundControl saves one (its keys and item layout): cruise and hover speed 1.5 m/s, no speed
    command unless ``speed_item_after`` (then a 178 at ``speed`` m/s after that waypoint, as QGC writes one)."""
    lon, lat = LocalFrame(*ORIGIN).inverse(POINTS[:, 0], POINTS[:, 1])
    items = []
    for k, (la, lo, z) in enumerate(zip(lat, lon, POINTS[:, 2])):
        items.append({"AMSLAltAboveTerrain": None, "Altitude": float(z), "AltitudeMode": 1, "autoContinue": True,
                      "command": 16, "doJumpId": len(items) + 1, "frame": 3,
                      "params": [0, 0, 0, None, float(la), float(lo), float(z)], "type": "SimpleItem"})
        if k == speed_item_after:
            items.append({"autoContinue": True, "command": 178, "doJumpId": len(items) + 1, "frame": 2,
                          "params": [1, speed, -1, 0, 0, 0, 0], "type": "SimpleItem"})
    return {"fileType": "Plan", "geoFence": {"circles": [], "polygons": [], "version": 2},
            "groundStation": "QGroundControl",
            "mission": {"cruiseSpeed": 1.5, "firmwareType": 3, "globalPlanAltitudeMode": 1, "hoverSpeed": 1.5,
                        "items": items, "plannedHomePosition": [float(lat[0]), float(lon[0]), 0], "vehicleType": 12,
                        "version": 2},
            "rallyPoints": {"points": [], "version": 2}, "version": 1}


def _energy_wh(speeds):
    model = EnergyModel.from_vehicle(VehicleParams(speed=1.0))
    return float(np.sum(model.power(speeds) * LEGS / speeds)) / 3600.0


def test_the_export_begins_with_a_speed_command_at_the_planned_speed():
    """Byte-level: the first item, before any NAV item, is QGC's own "Mission Start" speed item (speed type 1, the
    speed in param 2, throttle -1, MAV_FRAME_MISSION)."""
    items = to_qgc_plan(POINTS[[0, 2, 3]] * [1, 1, 0] - [0, 0, 20], ORIGIN, 1.5)["mission"]["items"]  # level legs
    assert json.dumps(items[0]) == ('{"type": "SimpleItem", "autoContinue": true, "command": 178, "doJumpId": 1, '
                                    '"frame": 2, "params": [1, 1.5, -1, 0, 0, 0, 0]}')
    assert [it["command"] for it in items] == [178, 16, 16, 16]
    assert [it["doJumpId"] for it in items] == [1, 2, 3, 4]
    # the speed is horizontal (audit 20: WPNav keeps a 178's speed level): the climbs and dives of POINTS are
    # commanded at 1.5 cos γ, after its waypoint where the command changes (export22: not where it stays)
    items = to_qgc_plan(POINTS, ORIGIN, 1.5)["mission"]["items"]
    now, flown = None, []  # a 178 only where the speed the command in force flies leaves 0.25 % (export22)
    for it in items:
        now = it["params"][1] if it["command"] == 178 else now
        flown += [now] if it["command"] == 16 else []
    assert np.asarray(flown[1:]) / COS[1:] == pytest.approx(np.full(3, 1.5), rel=0.0025 + 1e-4)
    assert sum(it["command"] == 178 for it in items) == 1  # pitches of 0.9-0.2°: cos γ within the band


def test_a_plan_qgc_wrote_without_a_speed_command_is_judged_at_the_vehicle_s_speed_and_says_so(tmp_path):
    """cruiseSpeed 1.5 is not what the vehicle flies: every leg with a horizontal run judged at the scenario's 1.0
    m/s, named; the vertical launch at WPNAV_SPEED_DN, as with a speed command (the command sets the horizontal
    speed only: export2, wave 17; it was judged at 1.0 m/s here and at 1.5 with a command)."""
    code, rec = _check(tmp_path, _qgc_written())
    assert code == 0 and rec["speed_assumed_legs"] == [1, 2, 3] and rec["speed_assumed_mps"] == 1.0
    assert rec["energy"]["leg_speeds_mps"] == pytest.approx([1.5, 1.0, 1.0, 1.0])
    assert rec["energy"]["duration_s"] == pytest.approx(LEGS[0] / 1.5 + LEGS[1:].sum() / 1.0, rel=1e-9)
    _, text = _check(tmp_path, _qgc_written(), json_out=False)
    assert (f"{tmp_path / 'm.plan'}: leg speeds (no MAV_CMD_DO_CHANGE_SPEED above 0 before them) not in the file: "
            "ArduSub flies its WPNAV_SPEED parameter; judged at 1 m/s (legs 1-3)\n") in text


@pytest.mark.parametrize("after, speed", [(0, 0.0), (0, -1.0), (3, 1.5)])
def test_speed_commands_that_set_no_leg_s_speed_are_named_as_such(tmp_path, after, speed):
    """A 178 whose speed is 0 or -1 (ArduSub keeps the speed it has) or one after the last position sets no leg's
    speed: every leg judged at the vehicle's 1.0 m/s (the vertical launch at WPNAV_SPEED_DN), and the line does not
    say the file has no speed command."""
    code, rec = _check(tmp_path, _qgc_written(speed_item_after=after, speed=speed))
    assert code == 0 and rec["speed_assumed_legs"] == [1, 2, 3]
    _, text = _check(tmp_path, _qgc_written(speed_item_after=after, speed=speed), json_out=False)
    assert "leg speeds (no MAV_CMD_DO_CHANGE_SPEED above 0 before them) not in the file" in text


def test_legs_before_a_late_speed_command_are_named_and_the_rest_fly_its_speed(tmp_path):
    code, rec = _check(tmp_path, _qgc_written(speed_item_after=1))  # the 178 is mission.items[2]
    # the 178's speed is level (audit 20); the vertical launch at WPNAV_SPEED_DN before it too (export2)
    want = np.array([1.5, 1.0, 1.5, 1.5]) / np.r_[1.0, 1.0, COS[2:]]
    assert code == 0 and rec["speed_assumed_legs"] == [1] and rec["energy"]["leg_speeds_mps"] == pytest.approx(want)
    assert rec["energy"]["duration_s"] == pytest.approx(float(np.sum(LEGS / want)), rel=1e-9)
    _, text = _check(tmp_path, _qgc_written(speed_item_after=1), json_out=False)
    assert ("leg speeds before mission.items[2] not in the file: ArduSub flies its WPNAV_SPEED parameter; judged at "
            "1 m/s (legs 1)") in text


def test_the_export_is_judged_at_its_planned_speed(tmp_path):
    """A leading 178 at 1.5 m/s on a vehicle whose own speed is 1.0: time L / 1.5 and energy P(1.5) L / 1.5."""
    code, rec = _check(tmp_path, to_qgc_plan(POINTS, ORIGIN, 1.5))
    assert code == 0 and rec["speed_assumed_legs"] == [] and rec["speed_assumed_mps"] is None
    # (the export writes lat/lon to 1e-9 degree: its legs are the planned ones to 0.1 mm)
    # (the export writes lat/lon to 1e-9 degree, and each leg's level speed 1.5 cos γ to 1e-4 m/s)
    assert rec["energy"]["duration_s"] == pytest.approx(LEGS.sum() / 1.5, rel=0.0026)  # export22: SPEED_BAND
    assert rec["energy"]["energy_wh"] == pytest.approx(_energy_wh(np.full(4, 1.5)), rel=0.008)  # launch: WPNAV_SPEED_DN
    assert "leg speeds" not in _check(tmp_path, to_qgc_plan(POINTS, ORIGIN, 1.5), json_out=False)[1]


def test_per_leg_speeds_are_kept(tmp_path):
    """Three legs at 0.8, 1.7, 1.2 m/s: the launch at the first leg's (the leading item), then each leg's own."""
    v = np.array([0.8, 1.7, 1.2])
    doc = to_qgc_plan(POINTS, ORIGIN, v)
    items = doc["mission"]["items"]
    assert [it["params"][1] for it in items if it["command"] == 178] == pytest.approx(
        v * COS[1:], abs=5e-5)  # level speeds (audit 20), each once: where the command changes (export22)
    assert [it["command"] for it in items] == [178, 16, 16, 178, 16, 178, 16]
    lon, lat = LocalFrame(*ORIGIN).inverse(np.array([-400.0, 5400.0, 5400.0, -400.0]),
                                           np.array([-1400.0, -1400.0, 3400.0, 3400.0]))
    doc["geoFence"]["polygons"] = [{"inclusion": True, "polygon": [[float(a), float(b)] for a, b in zip(lat, lon)],
                                    "version": 1}]  # the envelope: its predicted time, after the launch, too
    code, rec = _check(tmp_path, doc)
    want = np.r_[1.5, v]  # the launch is vertical: at AC_WPNav's default WPNAV_SPEED_DN (export22)
    assert code == 0 and rec["speed_assumed_legs"] == [] and rec["energy"]["leg_speeds_mps"] == pytest.approx(
        want, abs=1e-4)
    assert rec["energy"]["duration_s"] == pytest.approx(float(np.sum(LEGS / want)), rel=1e-4)
    # the envelope's time-out judged against the same duration, the launch included (consist19)
    assert rec["deploy"]["envelope"]["predicted_s"] == rec["energy"]["duration_s"]
    assert rec["energy"]["energy_wh"] == pytest.approx(_energy_wh(want), rel=1e-4)


def test_a_format_without_speeds_names_every_leg_judged_at_the_vehicle_s_speed(tmp_path):
    from auvplan.io.missions.formats import to_gpx

    scen = tmp_path / "s.toml"
    scen.write_text(SCENARIO, encoding="utf-8")
    path = tmp_path / "m.gpx"
    path.write_text(to_gpx(POINTS, ORIGIN), encoding="utf-8")
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert cli.main(["mission", "check", str(path), "--scenario", str(scen), "--json"]) == 0
    rec = json.loads(buf.getvalue())
    assert rec["speed_assumed_legs"] == [0, 1, 2] and rec["speed_assumed_mps"] == 1.0
    assert rec["energy"]["duration_s"] == pytest.approx(LEGS[1:].sum() / 1.0, rel=1e-7)
