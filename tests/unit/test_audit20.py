"""Audit 20 of wave 14's code (``git diff 00dc173``).

1. A ``.plan``'s ``MAV_CMD_DO_CHANGE_SPEED`` is a horizontal speed.  ArduSub's ``do_change_speed`` sets WPNav's
   horizontal speed (``set_speed_NE_cms``), and WPNav flies a leg at the speed along it that keeps that horizontal
   speed (ArduPilot's ``kinematic_limit`` in ``AP_Math/control.cpp``: ``max_xy / xy_length`` of the unit
   direction, until the vertical limit binds).  The export wrote the planned through-water speed v into the
   command, so ArduSub flew a leg pitched at γ at ``v / cos γ`` (6.4 % more at 20°), and ``mission check`` read the
   command as the speed along the leg: a dive of 90 m over 275 m was judged 289.4 s at 1 m/s where ArduSub takes
   275 s at 1.052 m/s through the water.  Now the export commands ``v cos γ`` and the check flies the command at
   ``v / cos γ``.  Oracles: time = horizontal length / commanded speed, energy = P(v / cos γ) × that time (still
   water), and each written command × the leg's length over its horizontal length = the planned speed (np.hypot).
2. The readers' cache keyed the compiled seabed's bits on the CPU (audit 17), not on whether numba compiles at
   all: ``NUMBA_DISABLE_JIT=1`` runs the kernels as plain Python, whose seabed differs from the compiled one by
   ulps at 54 % of 300 points of marcus-wake (3.6e-12 m at most), so a folder written by one run served its bits
   to the other.  Oracle: the key changes with ``NUMBA_DISABLE_JIT`` and with nothing else.
3. The vector guard refused a FIFO named as a zone file, not one GDAL opens beside it (a shapefile's ``.dbf``,
   ``.shx``, ``.prj``; a FileGDB folder's files): ``validate`` hung for ever.  Oracle: exit 2, one line naming
   the FIFO (a writer unblocks it after 3 s, so the code before the fix fails here instead of hanging).
4. A geographic envelope was tested in the local (azimuthal) frame since audit 17; ArduPilot's fence has straight
   edges in latitude/longitude.  Oracle: shapely in latitude/longitude (the fence's own test).
5. A ``.plan`` item beyond ±90° latitude or ±180° longitude, which AP_Mission refuses at upload, was read as pyproj
   wraps it (180.0005° as -179.9995°) and passed.  Oracle: ArduPilot's check_lat/check_lng ranges.
6. A ``.plan`` geofence's circles were ignored: a mission through an exclusion circle passed 'envelope OK'.
   Oracle: the legs' distance to the centre by hand against the radius, 10 m either side of it.  And only its
   first inclusion polygon was tested, where ArduPilot keeps the vehicle inside every inclusion (by default).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.endurance import EnergyModel
from auvplan.io.data import cache
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.energy import mission_file_energy
from auvplan.io.missions.formats import to_qgc_plan
from auvplan.io.scenario import loader
from helpers import HOLDS

# home on the surface above item 0 (5 m down), a dive of 90 m over 275 m, then 1 000 m level; still water
ITEMS = np.array([[500.0, 1000.0, -5.0], [775.0, 1000.0, -95.0], [1775.0, 1000.0, -95.0]])


def _world(tmp_path):
    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS, encoding="utf-8")
    return loader.build(loader.load(str(scen)))


def _qgc_plan(tmp_path, frame: LocalFrame, speed: float):
    """As QGroundControl writes one: a speed item, then the waypoints (relative altitude)."""
    items = [{"type": "SimpleItem", "command": 178, "frame": 2, "params": [1, speed, -1, 0, 0, 0, 0]}]
    for x, y, z in ITEMS:
        lon, lat = frame.inverse(x, y)
        items.append({"type": "SimpleItem", "command": 16, "frame": 3,
                      "params": [0, 0, 0, None, float(lat), float(lon), float(z)]})
    lon, lat = frame.inverse(*ITEMS[0, :2])
    path = tmp_path / "m.plan"
    path.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": items}}))
    return path


@pytest.mark.parametrize("speed", [1.0, 1.6])
def test_a_speed_command_is_flown_level_so_a_dive_goes_faster_through_the_water(tmp_path, speed):
    world, mission = _world(tmp_path)
    rec, ok, _ = mission_file_energy(world, mission, _qgc_plan(tmp_path, LocalFrame(*world.origin), speed))
    flat, dz = 275.0, 90.0
    along = speed * np.hypot(flat, dz) / flat  # kinematic_limit: max_xy / xy_length (vz 0.33-0.52 m/s: unbound)
    dn = 1.5  # export22: the vertical launch at AC_WPNav's default WPNAV_SPEED_DN (ArduSub's 178 is horizontal)
    assert rec["leg_speeds_mps"] == pytest.approx([dn, along, speed], rel=1e-6)
    assert rec["duration_s"] == pytest.approx(5.0 / dn + (flat + 1000.0) / speed, rel=1e-6)  # was 289.4 s for 275
    power = EnergyModel.from_vehicle(mission.vehicle).power
    want = (float(power(dn)) * 5.0 / dn + float(power(speed)) * 1000.0 / speed
            + float(power(along)) * flat / speed) / 3600.0
    assert ok and rec["energy_wh"] == pytest.approx(want, rel=1e-6)


@pytest.mark.parametrize("speed", [1.5, [0.8, 1.7, 1.2]])
def test_the_export_commands_the_level_speed_that_flies_the_planned_one(tmp_path, speed):
    pts = np.array([[0.0, 0.0, -10.0], [300.0, -40.0, -60.0], [900.0, 400.0, -20.0], [1900.0, 400.0, -20.0]])
    d = np.diff(pts, axis=0)
    plan = to_qgc_plan(pts, (-33.9, 151.3), speed)  # southern and eastern hemispheres
    v = np.broadcast_to(np.asarray(speed, dtype=float), (3,))
    cmd, now = [], None  # the command in force when each waypoint is started (a 178 only where it changes)
    for it in plan["mission"]["items"]:
        if it["command"] == 178:
            now = it["params"][1]
        elif it["command"] == 16:
            cmd.append(now)
    flown = np.asarray(cmd[1:]) * np.linalg.norm(d, axis=1) / np.hypot(d[:, 0], d[:, 1])
    assert flown == pytest.approx(v, rel=0.0025 + 1e-4)  # what ArduSub flies through the water: the plan's speed
    # (within formats.SPEED_BAND, 0.25 %: a new 178 only where the speed the command flies leaves it, export22)
    assert cmd[0] == pytest.approx(v[0] * np.hypot(300.0, 40.0) / np.linalg.norm(d[0]), abs=5e-5)
    # and mission check of it gives the planned time back (still water)
    world, mission = _world(tmp_path)
    path = tmp_path / "e.plan"
    path.write_text(json.dumps(to_qgc_plan(ITEMS, world.origin, v[:2] if np.ndim(speed) else speed)))
    rec = mission_file_energy(world, mission, path)[0]
    legs = np.linalg.norm(np.diff(ITEMS, axis=0), axis=1)
    launch = 1.5  # vertical: at AC_WPNav's default WPNAV_SPEED_DN (not in the file; export22)
    assert rec["duration_s"] == pytest.approx(5.0 / launch + float(np.sum(legs / v[:2])), rel=0.0026)


@pytest.fixture()
def _fresh_stamps():
    for f in (cache.code_stamp, cache.host_stamp):
        f.cache_clear()
    yield
    for f in (cache.code_stamp, cache.host_stamp):
        f.cache_clear()


def test_the_cache_key_tells_compiled_kernels_from_plain_python(monkeypatch, _fresh_stamps):
    def key() -> str:
        for f in (cache.code_stamp, cache.host_stamp):
            f.cache_clear()
        return cache.request_key("seabed-at", ("grid", ((1.0, 2.0),)), [])

    monkeypatch.delenv("NUMBA_DISABLE_JIT", raising=False)
    compiled = key()
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "1")  # the kernels as plain Python: other bits
    assert key() != compiled
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "0")  # numba's own reading: 0 compiles
    assert key() == compiled
    monkeypatch.delenv("NUMBA_DISABLE_JIT")
    assert key() == compiled


# ---------------------------------------------------------------- 3. a FIFO beside a zone file
def _unblock_later(fifo, seconds: float = 3.0):
    """A writer that opens and closes ``fifo`` after ``seconds`` (a reader blocked on it then reads an empty file),
    so that the code before the fix fails this test instead of hanging it."""
    import os
    import threading
    import time

    def run() -> None:
        deadline = time.monotonic() + seconds + 5.0
        time.sleep(seconds)
        while time.monotonic() < deadline:
            try:
                os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))  # ENXIO while no reader: nothing blocked
            except OSError:
                time.sleep(0.05)

    threading.Thread(target=run, daemon=True).start()


@pytest.mark.parametrize("sidecar", ["z.dbf", "z.shx", "Z.PRJ"])
def test_a_fifo_beside_a_shapefile_is_refused_not_waited_on(tmp_path, capsys, sidecar):
    """GDAL opens a shapefile's .dbf/.shx/.prj beside it: a FIFO there blocked ``validate`` for ever (killed after
    20 s) though the guard refused a FIFO named as the file itself."""
    import os

    import shapely
    from pyogrio.raw import write

    from auvplan.cli import main

    geom = np.array([shapely.to_wkb(shapely.box(70.80, -7.0, 70.81, -6.99))], dtype=object)
    write(str(tmp_path / "z.shp"), geom, [np.array(["a"], dtype=object)], ["name"], geometry_type="Polygon",
          crs="EPSG:4326", driver="ESRI Shapefile")
    for p in tmp_path.glob("z.*"):
        if p.name.lower() == sidecar.lower():
            p.unlink()
    os.mkfifo(tmp_path / sidecar)
    _unblock_later(tmp_path / sidecar)
    (tmp_path / "s.toml").write_text(HOLDS + '[[zones]]\nname = "chart"\nfile = "z.shp"\n', encoding="utf-8")
    assert main(["validate", str(tmp_path / "s.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"file = '{tmp_path / 'z.shp'}': '{sidecar}' beside it: is a FIFO" in err, err


def test_a_fifo_inside_a_filegdb_folder_is_refused(tmp_path):
    import os

    from auvplan.errors import DataError
    from auvplan.io.data.vector.guard import check_source

    gdb = tmp_path / "z.gdb"
    gdb.mkdir()
    (gdb / "a00000001.gdbtable").write_bytes(b"\0" * 8)
    check_source(gdb, "src", DataError)  # regular files: read by GDAL
    os.mkfifo(gdb / "a00000004.gdbtable")
    with pytest.raises(DataError, match=r"^src: 'a00000004\.gdbtable' beside it: is a FIFO"):
        check_source(gdb, "src", DataError)
    (tmp_path / "y.geojson").write_text("{}", encoding="utf-8")
    os.mkfifo(tmp_path / "y2.geojson")  # another name: not GDAL's to open
    os.mkfifo(tmp_path / "yz.geojson")
    check_source(tmp_path / "y.geojson", "src", DataError)


# ---------------------------------------------------------------- 4. a geofence's edges as ArduPilot draws them
@pytest.mark.parametrize(("lat0", "lon0"), [(68.0, 15.0), (-68.0, -60.0)])
def test_a_hand_drawn_geofence_is_tested_with_ardupilot_s_straight_latitude_longitude_edges(tmp_path, lat0, lon0):
    """ArduPilot tests its polygon fence with straight edges in latitude/longitude (``Polygon_outside`` on
    ``points_lla``); ``mission check`` tested the local (azimuthal) frame since audit 17, where a 100 km edge at 68°
    bows 494 m poleward of it: a waypoint 300 m inside the local square's poleward side passed, and breached."""
    import shapely

    from auvplan.io.missions.formats import read_mission
    from auvplan.io.missions.readback.deploy_read import file_deploy_check

    frame = LocalFrame(lat0, lon0)
    side = 300.0 if lat0 > 0 else -300.0  # the poleward side
    w = np.array([[0.0, 0.0, -20.0], [0.0, np.sign(side) * 50_000.0 - side, -20.0], [1000.0, 0.0, -20.0]])
    doc = to_qgc_plan(w, (lat0, lon0), 1.0)
    corners = np.array([(-5e4, -5e4), (5e4, -5e4), (5e4, 5e4), (-5e4, 5e4)])
    lon, lat = frame.inverse(corners[:, 0], corners[:, 1])
    doc["geoFence"]["polygons"] = [{"inclusion": True, "version": 1,
                                    "polygon": [[float(a), float(b)] for a, b in zip(lat, lon)]}]
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(doc))
    points = read_mission(path, (lat0, lon0))[0]
    plon, plat = frame.inverse(points[:, 0], points[:, 1])  # the oracle: shapely in latitude/longitude
    inside = shapely.covers(shapely.Polygon(np.column_stack([lon, lat])), shapely.points(plon, plat))
    assert inside.tolist() == [True, True, False, True]  # the second item is outside ArduPilot's fence
    rec, line = file_deploy_check(path, (lat0, lon0), points, "qgc", 50.0, 3000.0)
    assert not rec["envelope"]["ok"] and "(1 waypoints outside)" in line, line
    w[1, 1] = np.sign(side) * 50_000.0 - 2 * side - side  # 900 m inside: inside both
    doc2 = to_qgc_plan(w, (lat0, lon0), 1.0)
    doc2["geoFence"] = doc["geoFence"]
    path.write_text(json.dumps(doc2))
    points = read_mission(path, (lat0, lon0))[0]
    assert file_deploy_check(path, (lat0, lon0), points, "qgc", 50.0, 3000.0)[0]["envelope"]["ok"]


# ---------------------------------------------------------------- 5. a position ArduPilot refuses at upload
@pytest.mark.parametrize(("lat", "lon"), [(-60.0003, 180.0005), (-60.0, -180.0005), (90.0005, 179.999)])
def test_a_plan_item_outside_the_latitude_longitude_ranges_is_refused_naming_it(tmp_path, lat, lon):
    """AP_Mission's ``check_lat``/``check_lng`` refuse an item beyond ±90° / ±180° (the upload fails): a ``.plan``
    near the antimeridian with an item at 180.0005° was read as -179.9995° (pyproj wraps) and passed the check."""
    from auvplan.errors import DataError
    from auvplan.io.missions.formats import read_mission

    origin = (-60.0, 179.9995)
    doc = to_qgc_plan(np.array([[0.0, 0.0, -10.0], [20.0, 0.0, -10.0], [40.0, 0.0, -10.0]]), origin, 1.0)
    wps = [it for it in doc["mission"]["items"] if it["command"] == 16]
    assert abs(wps[1]["params"][5]) > 179.9  # the legs near the antimeridian
    kept = wps[1]["params"][4:6]
    wps[1]["params"][4], wps[1]["params"][5] = lat, lon
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(doc))
    with pytest.raises(DataError, match=rf"mission\.items\[2\]: latitude {lat:g}, longitude {lon:g}: outside "
                                        r"\[-90, 90\] x \[-180, 180\], which ArduPilot refuses"):
        read_mission(path, origin)
    wps[1]["params"][4:6] = kept  # in range: read
    path.write_text(json.dumps(doc))
    assert read_mission(path, origin)[0].shape == (4, 3)


# ---------------------------------------------------------------- 6. a geofence's circles
@pytest.mark.parametrize(("lat0", "lon0"), [(48.0, -125.0), (-33.9, 151.3)])
def test_a_mission_through_an_exclusion_circle_of_its_geofence_fails_the_envelope(tmp_path, lat0, lon0):
    """QGroundControl's geofence holds circles too (``{"circle": {"center": [lat, lon], "radius": r}, "inclusion":
    false}``) and ArduPilot keeps the vehicle out of an exclusion circle; ``mission check`` read only the polygons:
    a mission straight through a 200 m exclusion circle passed 'envelope OK'.  Oracle: the leg's distance to the
    circle's centre by hand (0 m through it, 400 m beside it) against its radius."""
    from auvplan.io.missions.formats import read_mission
    from auvplan.io.missions.readback.deploy_read import file_deploy_check

    frame = LocalFrame(lat0, lon0)
    w = np.array([[0.0, 0.0, -20.0], [3000.0, 0.0, -20.0]])
    doc = to_qgc_plan(w, (lat0, lon0), 1.0)
    box = np.array([(-1000.0, -1000.0), (4000.0, -1000.0), (4000.0, 1000.0), (-1000.0, 1000.0)])
    lon, lat = frame.inverse(box[:, 0], box[:, 1])
    doc["geoFence"]["polygons"] = [{"inclusion": True, "version": 1,
                                    "polygon": [[float(a), float(b)] for a, b in zip(lat, lon)]}]
    path = tmp_path / "m.plan"
    ns = to_qgc_plan(np.array([[1500.0, -900.0, -20.0], [1500.0, 900.0, -20.0]]), (lat0, lon0), 1.0)["mission"]
    # an east-west leg beside a centre north of it, a north-south leg beside one east of it: 190 m (inside the
    # 200 m circle) and 215 m (outside the 64-gon around it, 200.24 m)
    for (dx, dy), ok in [((0.0, 0.0), False), ((0.0, 190.0), False), ((0.0, 215.0), True), ((190.0, 0.0), False),
                         ((215.0, 0.0), True)]:
        doc["mission"] = ns if dx else to_qgc_plan(w, (lat0, lon0), 1.0)["mission"]
        clon, clat = frame.inverse(np.array([1500.0 + dx]), np.array([dy]))
        doc["geoFence"]["circles"] = [{"circle": {"center": [float(clat[0]), float(clon[0])], "radius": 200.0},
                                       "inclusion": False, "version": 1}]
        path.write_text(json.dumps(doc))
        points = read_mission(path, (lat0, lon0))[0]
        rec, line = file_deploy_check(path, (lat0, lon0), points, "qgc", 50.0, 3000.0)
        assert rec["envelope"]["ok"] is ok, line
        assert ok or "crosses exclusion polygon [0]" in line, line
    # an inclusion circle alone is the envelope: the mission 3 km long leaves a 1 km one
    doc["mission"] = to_qgc_plan(w, (lat0, lon0), 1.0)["mission"]
    clon, clat = frame.inverse(np.array([0.0]), np.array([0.0]))
    doc["geoFence"] = {"polygons": [], "version": 2,
                       "circles": [{"circle": {"center": [float(clat[0]), float(clon[0])], "radius": 1000.0},
                                    "inclusion": True, "version": 1}]}
    path.write_text(json.dumps(doc))
    rec, line = file_deploy_check(path, (lat0, lon0), read_mission(path, (lat0, lon0))[0], "qgc", 50.0, 3000.0)
    assert not rec["envelope"]["ok"] and "leaves the envelope's polygon (1 waypoints outside)" in line, line


def test_every_inclusion_of_a_geofence_holds_the_mission(tmp_path):
    """ArduPilot keeps the vehicle inside every inclusion polygon and circle of its fence (their intersection,
    unless FENCE_OPTIONS asks for their union); ``mission check`` tested the first inclusion polygon only."""
    from auvplan.io.missions.formats import read_mission
    from auvplan.io.missions.readback.deploy_read import file_deploy_check

    origin = (48.0, -125.0)
    frame = LocalFrame(*origin)
    w = np.array([[0.0, 0.0, -20.0], [3000.0, 0.0, -20.0]])
    doc = to_qgc_plan(w, origin, 1.0)

    def box(x0: float, x1: float) -> dict:
        lon, lat = frame.inverse(np.array([x0, x1, x1, x0]), np.array([-500.0, -500.0, 500.0, 500.0]))
        return {"inclusion": True, "version": 1, "polygon": [[float(a), float(b)] for a, b in zip(lat, lon)]}

    path = tmp_path / "m.plan"
    for second, ok in [((-1000.0, 4000.0), True), ((-1000.0, 2000.0), False)]:  # the mission reaches x = 3000 m
        doc["geoFence"]["polygons"] = [box(-1000.0, 4000.0), box(*second)]
        path.write_text(json.dumps(doc))
        rec, line = file_deploy_check(path, origin, read_mission(path, origin)[0], "qgc", 50.0, 3000.0)
        assert rec["envelope"]["ok"] is ok, line
        assert ok or "leaves the fence's inclusion 2 (1 waypoints outside)" in line, line
    clon, clat = frame.inverse(np.array([0.0]), np.array([0.0]))  # and an inclusion circle of 1 km beside them
    doc["geoFence"]["polygons"] = [box(-1000.0, 4000.0)]
    doc["geoFence"]["circles"] = [{"circle": {"center": [float(clat[0]), float(clon[0])], "radius": 1000.0},
                                   "inclusion": True, "version": 1}]
    path.write_text(json.dumps(doc))
    rec, line = file_deploy_check(path, origin, read_mission(path, origin)[0], "qgc", 50.0, 3000.0)
    assert not rec["envelope"]["ok"] and "leaves the fence's inclusion 2" in line, line
