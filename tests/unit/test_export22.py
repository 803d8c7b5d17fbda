"""Export 22: a ``.plan`` judged as ArduSub flies it.

1. Vertical legs: ``tests/unit/test_audit22.py`` (AC_WPNav's default ``WPNAV_SPEED_UP``/``_DN``; ArduSub's speed
   command sets the horizontal speed only).
2. A ``MAV_CMD_DO_CHANGE_SPEED`` only where the command changes: with per-leg speeds a 178 followed every waypoint
   (a 1 594-waypoint mission: 3 188 items against AP_Mission's 655 or 1 312 commands).  Oracle: the runs of equal
   commands counted by hand, and the speeds read back leg by leg.
3. A geofence across ±180°: ArduPilot tests it on the stored latitude and longitude as a plane
   (``AC_PolyFence_loader::breached`` → ``Polygon_outside``, no wrap), so a ring with vertices at 179.99° and
   -179.99° is the band round the other side of the Earth; ``mission check`` unwrapped it about the origin and
   passed a mission the vehicle would breach at once.  Oracle: ``Polygon_outside`` transcribed (even-odd crossing
   on integer 1e-7 degrees).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.formats import read_mission, to_qgc_plan
from auvplan.io.missions.readback.deploy_read import file_deploy_check
from auvplan.io.missions.readback.speeds import read_leg_speeds


def polygon_outside(p, ring) -> bool:
    """AP_Math ``Polygon_outside`` on ``(lat, lng)`` in 1e-7 degrees: even-odd crossings of the ray along +x."""
    px, py = (int(round(v * 1e7)) for v in p)
    v = [(int(round(a * 1e7)), int(round(b * 1e7))) for a, b in ring]
    outside = True
    for i in range(len(v)):
        (xi, yi), (xj, yj) = v[i], v[i - 1]
        if (yi > py) == (yj > py):
            continue
        if (px - xi) * (yj - yi) - (xj - xi) * (py - yi) < 0 if yj > yi else \
                (px - xi) * (yj - yi) - (xj - xi) * (py - yi) > 0:
            outside = not outside
    return outside


def test_a_speed_command_only_where_the_command_changes():
    frame_origin = (10.0, 20.0)
    x = np.arange(7) * 100.0
    pts = np.column_stack([x, np.zeros(7), np.full(7, -20.0)])  # level legs: the command is the speed
    speeds = np.array([1.0, 1.0, 1.5, 1.5, 1.5, 1.0])
    doc = to_qgc_plan(pts, frame_origin, speeds)
    cmds = [it["params"][1] for it in doc["mission"]["items"] if it["command"] == 178]
    runs = 1 + int(np.sum(np.diff(speeds) != 0))  # by hand: 1.0 | 1.5 | 1.0
    assert cmds == [1.0, 1.5, 1.0] and len(cmds) == runs  # 7 before (one after every waypoint)
    assert len(doc["mission"]["items"]) == len(pts) + runs


def test_speeds_read_back_leg_by_leg(tmp_path):
    origin = (10.0, 20.0)
    x = np.arange(7) * 100.0
    pts = np.column_stack([x, np.zeros(7), np.full(7, -20.0)])
    speeds = np.array([1.0, 1.0, 1.5, 1.5, 1.5, 1.0])
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(to_qgc_plan(pts, origin, speeds)))
    got = read_leg_speeds(path, len(pts))  # the launch from the home, then the six legs
    assert got == pytest.approx([1.0, *speeds], abs=1e-4)


def _fence_plan(tmp_path, origin, ring_xy, w):
    frame = LocalFrame(*origin)
    doc = to_qgc_plan(w, origin, 1.2)
    lon, lat = frame.inverse(ring_xy[:, 0], ring_xy[:, 1])
    ring = [[float(a), float(b)] for a, b in zip(lat, lon)]
    doc["geoFence"] = {"circles": [], "polygons": [{"inclusion": True, "polygon": ring, "version": 1}], "version": 2}
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(doc))
    return path, ring


@pytest.mark.parametrize(("lat", "lon"), [(-33.0, 179.99), (45.0, -179.995), (-33.0, 170.0)])
def test_a_fence_across_the_antimeridian_is_judged_as_ardupilot_reads_it(tmp_path, lat, lon):
    origin = (lat, lon)
    w = np.array([[-1000.0, 0.0, -30.0], [0.0, 500.0, -30.0], [1000.0, 0.0, -30.0]])  # across 180° at 179.99
    ring_xy = np.array([[-2000.0, -2000.0], [2000.0, -2000.0], [2000.0, 2000.0], [-2000.0, 2000.0]])
    path, ring = _fence_plan(tmp_path, origin, ring_xy, w)
    points = read_mission(path, origin)[0]
    rec, line = file_deploy_check(path, origin, points, "qgc", 50.0, 3000.0)
    frame = LocalFrame(*origin)
    lo, la = frame.inverse(points[:, 0], points[:, 1])
    lo = (np.asarray(lo) + 180.0) % 360.0 - 180.0
    outside = [polygon_outside((a, b), ring) for a, b in zip(la, lo)]  # ArduPilot's own test, waypoint by waypoint
    assert rec["envelope"]["ok"] == (not any(outside)), line
    straddles = max(r[1] for r in ring) - min(r[1] for r in ring) > 180.0
    assert any(outside) == straddles  # the oracle sees the breach exactly when the ring crosses ±180°
    if straddles:
        assert "waypoints outside" in line


def test_a_plan_beyond_ardupilot_s_mission_storage_is_refused_naming_the_limit(tmp_path):
    """AP_Mission holds ``(storage − 4) // 15`` commands, the home included (``num_commands_max``); the most is a
    64 KiB ``BRD_SD_MISSION`` file, 0xFFFF bytes.  Oracle: the StorageManager areas summed by hand."""
    from auvplan.errors import DataError

    sub_16k = 2506 + 2132 + 5204  # StorageMission areas for a non-copter vehicle, 16 KiB of storage
    assert [(b - 4) // 15 for b in (sub_16k, 2 * sub_16k, 0xFFFF)] == [655, 1312, 4368]
    n = 4368  # waypoints: + the leading 178 + the home = 4 370 commands
    pts = np.column_stack([np.arange(n) * 10.0, np.zeros(n), np.full(n, -20.0)])
    with pytest.raises(DataError, match=r"4367 items \+ the home = 4368 commands|4369 items \+ the home = 4370 "
                                        r"commands > AP_Mission's capacity: 655 .* 1312 .* 4368"):
        to_qgc_plan(pts, (10.0, 20.0), 1.0)
    doc = to_qgc_plan(pts[:4366], (10.0, 20.0), 1.0)  # 4 367 items + the home: the most any board holds
    assert len(doc["mission"]["items"]) == 4367
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(doc))
    assert read_mission(path, (10.0, 20.0))[0].shape == (4367, 3)
    doc["mission"]["items"].append(dict(doc["mission"]["items"][-1], doJumpId=4368))
    path.write_text(json.dumps(doc))
    with pytest.raises(DataError, match=r"4368 items \+ the home = 4369 commands > AP_Mission's capacity"):
        read_mission(path, (10.0, 20.0))


def test_pitched_legs_share_a_command_while_they_fly_within_the_band():
    """A seeded terrain-following profile (pitch 0-12°): a 178 after every waypoint before; now each leg's command in
    force, flown at command / cos γ (WPNav), stays within 0.25 % of the planned speed, with far fewer commands."""
    rng = np.random.default_rng(22)
    n = 400
    x = np.cumsum(rng.uniform(20.0, 60.0, n))
    pitch = 12.0 * np.sin(2.0 * np.pi * x[:-1] / 3000.0) + rng.normal(0.0, 0.3, n - 1)  # hills, a little noise
    dz = np.tan(np.radians(pitch)) * np.diff(x)
    pts = np.column_stack([x, np.zeros(n), -200.0 + np.r_[0.0, np.cumsum(dz)]])
    v = 1.5
    items = to_qgc_plan(pts, (10.0, 20.0), v)["mission"]["items"]
    now, cmd = None, []
    for it in items:
        now = it["params"][1] if it["command"] == 178 else now
        cmd += [now] if it["command"] == 16 else []
    d = np.diff(pts, axis=0)
    flown = np.asarray(cmd[1:]) * np.linalg.norm(d, axis=1) / np.abs(d[:, 0])  # by hand: v_xy / cos γ
    assert np.all(np.abs(flown - v) <= 0.0025 * v + 1e-4)
    n178 = sum(it["command"] == 178 for it in items)
    assert n178 < (n - 1) / 2  # 127 (measured); 400 before, one after every waypoint
