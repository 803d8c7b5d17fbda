"""A ``.plan`` read as its vehicle flies it (``io.missions.qgc_items`` and the readers that share its walk), the
cases wave 13's tests left open (found by mutation, docs/mutants.md section 5): a command that is not a number, a
pattern with no generated items, the frames the reader accepts and refuses, a relay switched off, a geographic file
without an origin, and ``check_mission_file`` measuring a terrain-frame leg on its seabed-following track."""

from __future__ import annotations

import json

import numpy as np
import pytest
from test_qgc_items import _item, _plan, _survey

from auvplan.errors import DataError
from auvplan.guidance.mission.flycheck import fly_check
from auvplan.guidance.mission.terrain_legs import check_as_flown
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.formats import check_mission_file, read_mission, to_moos
from auvplan.io.missions.readback import deploy_files
from auvplan.io.missions.readback.deploy_read import read_deploy
from auvplan.io.missions.readback.qgc_items import plan_items
from auvplan.io.missions.readback.readers import parse_qgc_plan
from auvplan.io.missions.readback.speeds import read_leg_speeds
from auvplan.io.missions.readback.terrain_frame import terrain_legs
from auvplan.world import Bounds, Margins, Terrain, World

ORIGIN = (16.0, 145.0)
FRAME = LocalFrame(*ORIGIN)


def _relay(on: bool) -> dict:
    return {"type": "SimpleItem", "autoContinue": True, "command": 181, "doJumpId": 0, "frame": 2,
            "params": [0, 1 if on else 0, 0, 0, 0, 0, 0]}


@pytest.mark.parametrize("command", ["16", True, 16.0, None])
def test_a_command_that_is_not_a_mav_cmd_number_is_named(command):
    item = _item(FRAME, 3000.0, 6000.0, -100.0)
    item["command"] = command
    with pytest.raises(DataError, match=rf"^QGC plan: mission\.items\[0\]\.command = {command!r}: not a MAV_CMD"):
        plan_items(_plan(ORIGIN, (0.0, 0.0), [item]))


@pytest.mark.parametrize("generated", [[], None, {}])
def test_a_pattern_without_generated_items_is_refused_not_skipped(generated):
    """A survey whose ``Items`` is empty (or missing) has nothing to check: refused, never read as no leg."""
    survey = _survey(FRAME, [(5000.0, 6000.0)], -100.0)
    survey["TransectStyleComplexItem"]["Items"] = generated
    doc = _plan(ORIGIN, (0.0, 0.0), [_item(FRAME, 3000.0, 6000.0, -100.0), survey])
    with pytest.raises(DataError, match=r"mission\.items\[1\]\.TransectStyleComplexItem\.Items: no generated"):
        plan_items(doc)


def test_a_relay_switched_off_is_an_off_event():
    """Relay on after waypoint 0 (the first item), off after waypoint 1: the events (0, on), (1, off)."""
    doc = _plan(ORIGIN, (0.0, 0.0), [_item(FRAME, 3000.0, 6000.0, -100.0), _relay(True),
                                     _item(FRAME, 4000.0, 6000.0, -100.0), _relay(False)])
    assert deploy_files._qgc(doc).payload_events == [(0, True), (1, False)]


@pytest.mark.parametrize("fr", [3, 6])
def test_the_relative_altitude_frames_are_read_alike(fr):
    """Frames 3 (MAV_FRAME_GLOBAL_RELATIVE_ALT) and 6 (its _INT twin): the item at its altitude, home on the surface."""
    doc = _plan(ORIGIN, (1000.0, 6000.0), [_item(FRAME, 3000.0, 6000.0, -100.0, fr=fr)])
    got = parse_qgc_plan(doc, FRAME)
    assert np.allclose(got, [[1000.0, 6000.0, 0.0], [3000.0, 6000.0, -100.0]], atol=1e-6)


@pytest.mark.parametrize(("fr", "seabed"), [(0, None), (2, None), (11, None), (10, None)])
def test_a_frame_the_reader_cannot_place_is_refused_naming_the_item(fr, seabed):
    """An absolute (0), mission (2) or unknown (11) frame, and the terrain frame (10) without a seabed to place it
    on: refused, naming the item and its frame."""
    doc = _plan(ORIGIN, (1000.0, 6000.0), [_item(FRAME, 3000.0, 6000.0, -100.0), _item(FRAME, 4000.0, 6000.0,
                                                                                          20.0, fr=fr)])
    with pytest.raises(DataError, match=rf"^QGC plan: mission\.items\[1\]\.frame = {fr}: expected 3 \(relative"):
        parse_qgc_plan(doc, FRAME, seabed)


def test_a_geographic_file_needs_an_origin_and_a_local_one_does_not(tmp_path):
    plan = tmp_path / "m.plan"
    plan.write_text(json.dumps(_plan(ORIGIN, (0.0, 0.0), [_item(FRAME, 3000.0, 6000.0, -100.0)])))
    with pytest.raises(DataError, match=r"a qgc mission is geographic: the scenario needs an \[origin\]$"):
        read_mission(plan)
    csv = tmp_path / "m.csv"
    csv.write_text("x,y,z\n0,0,-10\n100,0,-20\n")
    pts, semantics, fmt = read_mission(csv)
    assert fmt == "csv" and semantics == "ramp" and np.array_equal(pts, [[0.0, 0.0, -10.0], [100.0, 0.0, -20.0]])


def _ridge_world() -> World:
    """A ridge 40 m high across x = 1000 m over a seabed 100 m deep (5 m cells), min_depth 5 m."""
    x, y = np.arange(0.0, 2001.0, 5.0), np.arange(0.0, 401.0, 5.0)
    z = np.broadcast_to(-100.0 + 40.0 * np.exp(-(((x - 1000.0) / 30.0) ** 2)), (y.size, x.size)).copy()
    return World(Bounds(0.0, 2000.0, 0.0, 400.0, -150.0, 0.0), Terrain(x, y, z, name="ridge"),
                 margins=Margins(min_altitude=10.0, min_depth=5.0), origin=ORIGIN)


def test_check_mission_file_measures_a_terrain_frame_leg_on_its_track(tmp_path):
    """Home on the surface, then two items 20 m above the seabed across the ridge, the second leg in the terrain
    frame: the check is check_as_flown's (the track holds 20 m over the crest; the home exempt from the 5 m
    depth band as the launch), not the straight leg's (20 m under the crest).  A follow of the wrong length, or
    for a held-depth file, is an error of the caller."""
    world = _ridge_world()
    items = [_item(FRAME, 200.0, 200.0, 20.0, fr=10), _item(FRAME, 1800.0, 200.0, 20.0, fr=10)]
    plan = tmp_path / "m.plan"
    plan.write_text(json.dumps(_plan(ORIGIN, (200.0, 200.0), items)))  # home above item 0: the launch (fix20)
    follow = terrain_legs(plan)
    assert follow.tolist() == [False, True]
    pts, _, _ = read_mission(plan, ORIGIN, world.seabed)
    got, fmt = check_mission_file(plan, world, 15.0, follow)
    want = check_as_flown(world, pts, follow, launch=True)
    straight = fly_check(world, pts, "ramp", launch=True)
    assert fmt == "qgc" and got.min_altitude_m == want.min_altitude_m == pytest.approx(20.0, abs=0.05)
    assert straight.min_altitude_m == pytest.approx(-20.0, abs=0.05)
    assert got.limits is not None and got.limits.outside_depth_band == () and got.limits.above_surface == ()
    with pytest.raises(ValueError, match=r"^follow: 3 flags for a ramp mission of 3 waypoints$"):
        check_mission_file(plan, world, 15.0, np.array([False, True, True]))
    moos = tmp_path / "m.moos"
    moos.write_text(to_moos(np.array([[100.0, 200.0, -50.0], [300.0, 200.0, -50.0], [500.0, 200.0, -60.0]]), 1.5))
    with pytest.raises(ValueError, match=r"^follow: 2 flags for a held mission of 3 waypoints$"):
        check_mission_file(moos, world, 15.0, np.array([False, True]))


def test_the_deploy_record_counts_the_walk_s_terrain_frame_legs(tmp_path):
    """A loiter and a survey's generated item in the terrain frame count as altitude legs, as the reader's; the
    launch leg (home to item 0) never, as the terrain-following check's legs."""
    survey = _survey(FRAME, [(5000.0, 6000.0), (6000.0, 6000.0)], 30.0)
    survey["TransectStyleComplexItem"]["Items"][0]["frame"] = 10
    loiter = _item(FRAME, 3000.0, 6000.0, 25.0, 19, fr=10, radius=0)
    plan = tmp_path / "m.plan"
    plan.write_text(json.dumps(_plan(ORIGIN, (1000.0, 6000.0), [loiter, survey])))
    assert read_deploy(plan).altitude_legs == 1 == int(terrain_legs(plan).sum())  # the launch leg's never counted
    # after a first item at its depth, both legs into them (consist19: the deploy line counted items, launch too)
    plan.write_text(json.dumps(_plan(ORIGIN, (1000.0, 6000.0), [_item(FRAME, 2000.0, 6000.0, -50.0), loiter, survey])))
    assert read_deploy(plan).altitude_legs == 2 == int(terrain_legs(plan).sum())


def test_a_plan_s_home_is_the_launch_and_a_csv_s_first_point_is_not(tmp_path):
    """Relative-altitude items (no terrain frame) checked with a 5 m depth band: the .plan's home on the surface
    is its launch, exempt; the same points in a CSV file start on the surface, outside the band (waypoint 0).
    fix20: only a home above item 0 is exempt; one 200 m away starts ArduSub's straight dive (waypoint 0)."""
    world = _ridge_world()
    items = [_item(FRAME, 300.0, 200.0, -30.0), _item(FRAME, 500.0, 200.0, -30.0)]
    away = tmp_path / "away.plan"
    away.write_text(json.dumps(_plan(ORIGIN, (100.0, 200.0), items)))
    limits = check_mission_file(away, world)[0].limits
    assert limits is not None and limits.outside_depth_band == (0,) and limits.launch_run_m == pytest.approx(200.0)
    plan = tmp_path / "m.plan"
    plan.write_text(json.dumps(_plan(ORIGIN, (300.0, 200.0), items)))
    pts, _, _ = read_mission(plan, ORIGIN)
    csv = tmp_path / "m.csv"
    csv.write_text("x,y,z\n" + "".join(f"{float(x)!r},{float(y)!r},{float(z)!r}\n" for x, y, z in pts))
    got = {path.suffix: check_mission_file(path, world)[0].limits for path in (plan, csv)}
    assert got[".plan"] is not None and got[".plan"].outside_depth_band == ()
    assert got[".csv"] is not None and got[".csv"].outside_depth_band == (0,)


def test_a_waypoint_at_the_earth_s_circumference_is_read_and_one_beyond_is_named(tmp_path):
    """The bound is 4e7 m from the origin, inclusive: a waypoint exactly there is read; the first one past it is
    named, not one at it."""
    at = tmp_path / "at.csv"
    at.write_text("x,y,z\n40000000,0,-10\n0,40000000,-10\n")
    assert read_mission(at)[0][:, :2].max() == 4.0e7
    past = tmp_path / "past.csv"
    past.write_text("x,y,z\n40000000,0,-10\n50000000,0,-10\n")
    with pytest.raises(DataError, match=r"past\.csv: waypoint 1 = \(5e\+07, 0, -10\) m lies over 4e\+07 m"):
        read_mission(past)


def _speed(v: float) -> dict:
    return {"type": "SimpleItem", "autoContinue": True, "command": 178, "doJumpId": 0, "frame": 2,
            "params": [1, v, -1, 0, 0, 0, 0]}


def test_leg_speeds_keep_the_speed_a_zero_command_leaves_and_take_a_slow_one(tmp_path):
    """A DO_CHANGE_SPEED of 1.2 m/s after item 1, one of 0 (ArduPilot: unchanged) after item 2, one of 0.8 m/s
    after item 3: the legs into items 1 to 4 at NaN (before any command: not in the file), 1.2, 1.2, 0.8; a plan
    with no command carries none."""
    items = [_item(FRAME, 3000.0, 6000.0, -100.0), _speed(1.2), _item(FRAME, 4000.0, 6000.0, -100.0), _speed(0.0),
             _item(FRAME, 5000.0, 6000.0, -100.0), _speed(0.8), _item(FRAME, 6000.0, 6000.0, -100.0)]
    doc = _plan(ORIGIN, (1000.0, 6000.0), items)
    plan = tmp_path / "m.plan"
    plan.write_text(json.dumps(doc))
    np.testing.assert_array_equal(read_leg_speeds(plan, 4), [np.nan, 1.2, 1.2, 0.8])
    doc["mission"]["items"] = [it for it in items if it["command"] == 16]
    plan.write_text(json.dumps(doc))
    assert read_leg_speeds(plan, 4) is None


@pytest.mark.parametrize("bad", ["nan", "-inf", "0", "-1", "inf"])
def test_a_csv_whose_leg_speed_is_not_a_speed_is_named(tmp_path, bad):
    """A leg speed of nan is that leg's speed not in the file (judged at the vehicle's, the others kept: docwalk
    18); -inf, 0 or -1 is refused naming the leg as not positive (docwalk 18), +inf as over 100 m/s (audit 17)."""
    path = tmp_path / "m.csv"
    path.write_text(f"x,y,z,speed\n0,0,-10,1.0\n100,0,-10,1.2\n200,0,-10,{bad}\n300,0,-10,1.4\n")
    if bad == "inf":
        with pytest.raises(DataError, match=r"m\.csv: leg 1's speed inf m/s \(carried by the file\) is over 100"):
            read_leg_speeds(path, 3)
    elif bad == "nan":
        np.testing.assert_array_equal(read_leg_speeds(path, 3), [1.2, np.nan, 1.4])
    else:
        want = rf"m\.csv: leg 1's speed {bad} m/s \(carried by the file\) is not positive"
        with pytest.raises(DataError, match=want):
            read_leg_speeds(path, 3)
    path.write_text("x,y,z,speed\n0,0,-10,1.0\n100,0,-10,1.2\n200,0,-10,1.3\n300,0,-10,1.4\n")
    assert read_leg_speeds(path, 3).tolist() == [1.2, 1.3, 1.4]


def test_items_on_the_equator_or_the_prime_meridian_are_read():
    """Audit 17 refuses an item within 1e-7 deg of (0, 0) (ArduSub's 'current position'); one on the equator at
    5 deg west, or on the prime meridian at 3 deg south, is a point like any other: read, 100 m deep."""
    frame = LocalFrame(-1.5, -2.5)
    items = [{"type": "SimpleItem", "autoContinue": True, "command": 16, "doJumpId": 0, "frame": 3,
              "params": [0, 0, 0, None, lat, lon, -100.0]} for lat, lon in ((0.0, -5.0), (-3.0, 0.0))]
    doc = {"mission": {"plannedHomePosition": [-1.5, -2.5, 0], "items": items}}
    got = parse_qgc_plan(doc, frame)
    x, y = frame.forward(np.array([-5.0, 0.0]), np.array([0.0, -3.0]))
    assert np.allclose(got[1:], np.column_stack([x, y, [-100.0, -100.0]]), atol=1e-6)
