"""Audit 15 of wave 12's code: each test failed on the code before its fix."""

from __future__ import annotations

import contextlib
import io
import json
import math

import numpy as np
import pytest
import shapely

_TRENCH = """
name = "trench"
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 10000.0]
y = [0.0, 2000.0]
z = [-400.0, 0.0]
[terrain.synthetic]
kind = "ridge"
depth = 200.0
cell_m = 100.0
ridge_x = 5000.0
ridge_width = 2000.0
height = -100.0
[mission]
start = [500.0, 1000.0, -150.0]
goal = [9500.0, 1000.0, -150.0]
min_altitude_m = 20.0
min_depth_m = 5.0
max_depth_m = 350.0
follow_altitude_m = 25.0
"""


def _check_json(path, scenario) -> tuple[int, dict]:
    from auvplan import cli

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = cli.main(["mission", "check", str(path), "--scenario", str(scenario), "--json"])
    return code, json.loads(buf.getvalue())


@pytest.mark.parametrize(("headroom", "frame"), [(1e-5, 3), (1e-3, 10)])
def test_a_plan_s_terrain_frame_leg_keeps_the_pitch_limit_once_written(tmp_path, headroom, frame):
    """Oracle: a trench 100 m deep on 2 km flanks, sloping atan(0.05) = 2.8624 deg; items 25.0004 and 25.0006 m
    above its rims at x = 4 and 6 km (the straight leg level, 225 m deep, clear of the seabed).  Following the
    seabed, the leg dives and climbs at 2.8624 deg, ``headroom`` under the limit; the file's millimetre altitudes
    (25.000, 25.001) add 1 mm of rise over 2 km, +1.9e-5 deg: with 1e-5 deg of headroom the written leg broke the
    limit (the export wrote it in the terrain frame, mission check of that file: 2.8624338 > 2.8624152, exit 1);
    it is now written at its planned depth (frame 3, the level straight leg), and with 1e-3 deg it stays terrain."""
    from auvplan.io.missions.deploy import deploy_info
    from auvplan.io.missions.formats import to_qgc_plan
    from auvplan.io.scenario import loader as sc_io

    limit = math.degrees(math.atan(0.05)) + headroom
    scen = tmp_path / "s.toml"
    scen.write_text(_TRENCH + f"[vehicle]\nmax_pitch_deg = {limit!r}\n")
    world, mission = sc_io.build(sc_io.load(str(scen)))
    rims = [float(world.seabed(x, 1000.0)) for x in (4000.0, 6000.0)]
    assert rims == pytest.approx([-250.0, -250.0])
    w = np.array([[4000.0, 1000.0, rims[0] + 25.0004], [6000.0, 1000.0, rims[1] + 25.0006]])
    doc = to_qgc_plan(w, world.origin, 1.5, deploy=deploy_info(world, mission, w, 1.5, None, None))
    assert [i["frame"] for i in doc["mission"]["items"]] == [2, 10, frame]  # the leading DO_CHANGE_SPEED, the items
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(doc))
    code, rec = _check_json(path, scen)
    assert code == 0 and rec["ok"] is True and rec["vehicle"]["violations"] == []
    assert rec["vehicle"]["max_pitch_deg"] <= limit


def test_a_plan_s_vehicle_legs_are_numbered_as_the_rest_of_its_report(tmp_path):
    """Oracle: the legs by hand.  A ``.plan`` read home first: leg 0 the launch, leg 1 the flat one from x = 3 to 4
    km, leg 2 across a ridge 150 m high on 300 m flanks (26.57 deg as flown > 20), whose track, 25 m above the
    crest, enters a 0-30 m band over it.  The vehicle line judged the legs after the launch and numbered them from
    there: 'leg 1: pitch 26.6°' named the flat leg of the terrain-following and zone lines (its JSON
    ``max_pitch_leg`` and ``violations[].leg`` 1 for their 2)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from test_edges12_surfaces import _RIDGE, _plan

    scen = tmp_path / "s.toml"
    scen.write_text(_RIDGE.split("[[zones]]")[0].replace("ridge_width = 2000.0", "ridge_width = 300.0")
                    + '[vehicle]\nmax_pitch_deg = 20.0\n[[zones]]\nname = "crest"\n'
                    + "polygon = [[4900.0, 0.0], [5100.0, 0.0], [5100.0, 2000.0], [4900.0, 2000.0]]\n"
                    + "top_m = 0.0\nbottom_m = 30.0\n")
    path = tmp_path / "steep.plan"
    path.write_text(_plan([(3000.0, 1000.0, 10, 25.0), (4000.0, 1000.0, 10, 25.0), (6000.0, 1000.0, 10, 25.0)]))
    code, rec = _check_json(path, scen)
    v = rec["vehicle"]
    assert code == 1 and rec["terrain_following"]["legs"] == [1, 2]
    (zone,) = rec["zones"]
    assert zone["entered_legs"] == [2]
    assert v["max_pitch_leg"] == 2 and [(x["leg"], x["limit"]) for x in v["violations"]] == [(2, "max_pitch_deg")]
    assert v["violations"][0]["text"].startswith("leg 2: pitch 26.6°")


def test_a_terrain_frame_leg_across_a_saddle_cell_is_measured_on_its_curve():
    """Oracle: the analytic track.  A saddle cell 100 x 200 m (corners 100 m deep, the far one 140 m): along its
    diagonal the seabed is ``-100 - 40 t^2``, and a leg 30 m above it flies ``-70 - 40 t^2``, 78.1-82.1 m deep over
    a box round the middle (t = 0.45..0.55, shapely on the track sampled every 1e-4): inside a 0-85 m band.  The
    track was the one chord between the items (no grid line crossed, no extremum), 88-92 m deep there: the zone
    'OK', and the held 30 m read as 20 m (the chord's altitude at the middle)."""
    from auvplan.app.check import _zone_approach
    from auvplan.guidance.mission.terrain_legs import check_as_flown
    from auvplan.world import Zone, Zones
    from auvplan.world.terrain import Terrain
    from auvplan.world.world import Bounds, Margins, World

    t = Terrain(np.array([0.0, 100.0]), np.array([0.0, 200.0]), np.array([[-100.0, -100.0], [-100.0, -140.0]]))
    box = shapely.box(45.0, 90.0, 55.0, 110.0)
    world = World(Bounds(0.0, 100.0, 0.0, 200.0, -200.0, 0.0), t, margins=Margins(min_altitude=25.0),
                  zones=Zones((Zone("band", box, top=0.0, bottom=85.0),), t))
    pts = np.array([[0.0, 0.0, -70.0], [100.0, 200.0, -110.0]])
    s = np.linspace(0.0, 1.0, 10_001)
    depth = 70.0 + 40.0 * s**2
    over = shapely.contains_xy(box, 100.0 * s, 200.0 * s)
    assert over.any() and depth[over].max() < 85.0  # the track is in the band over the box
    (zone,) = _zone_approach(world, pts, "ramp", 15.0, np.array([True]))
    assert zone.entered_legs == (1,)
    check = check_as_flown(world, pts, np.array([True]), launch=False)
    assert check.min_altitude_m == pytest.approx(30.0, abs=0.011) and check.ok


_BUMP = """
name = "bump"
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 2000.0]
y = [0.0, 2000.0]
z = [-100.0, 0.0]
[terrain.synthetic]
kind = "ridge"
depth = 40.0
cell_m = 10.0
ridge_x = 1100.0
ridge_width = 30.0
height = 4.0
[mission]
start = [500.0, 1000.0, -15.0]
goal = [1500.0, 1000.0, -15.0]
min_altitude_m = 20.0
max_depth_m = 90.0
follow_altitude_m = 25.0
"""


@pytest.mark.parametrize("limit", ["min_depth_m = 12.0\n", 'min_depth_m = 5.0\n[[zones]]\nname = "shoal"\n'
                                   "polygon = [[1090.0, 0.0], [1110.0, 0.0], [1110.0, 2000.0], [1090.0, 2000.0]]\n"
                                   "top_m = 0.0\nbottom_m = 13.0\n"])
def test_a_plan_s_terrain_frame_leg_keeps_what_its_straight_leg_keeps(tmp_path, limit):
    """Oracle: by hand.  A 4 m bump (crest 36 m deep at x = 1.1 km, 30 m flanks) on a 40 m deep seabed; items 15 m
    deep (25 m above it) at x = 1.0, 1.2 and 1.3 km: the straight legs pass the crest 21 m above it (as a CSV:
    exit 0).  ArduSub following the seabed on leg 1 climbs with the bump to 11 m deep: above a 12 m min_depth_m, or
    into a 0-13 m zone over the crest.  The export wrote it in the terrain frame (only its pitch, 7.6 deg, was
    judged) and mission check of that .plan failed (exit 1); it is now written at its planned depth."""
    from auvplan.io.missions.deploy import deploy_info
    from auvplan.io.missions.formats import to_qgc_plan
    from auvplan.io.scenario import loader as sc_io

    scen = tmp_path / "s.toml"
    scen.write_text(_BUMP.replace("max_depth_m = 90.0\n", "max_depth_m = 90.0\n" + limit.split("[[zones]]")[0])
                    + ("[[zones]]" + limit.split("[[zones]]")[1] if "[[zones]]" in limit else ""))
    world, mission = sc_io.build(sc_io.load(str(scen)))
    assert float(world.seabed(1100.0, 1000.0)) == pytest.approx(-36.0)
    w = np.array([[1000.0, 1000.0, -15.0], [1200.0, 1000.0, -15.0], [1300.0, 1000.0, -15.0]])
    csv = tmp_path / "m.csv"
    csv.write_text("x,y,z\n" + "\n".join(f"{x},{y},{z}" for x, y, z in w) + "\n")
    assert _check_json(csv, scen)[0] == 0
    doc = to_qgc_plan(w, world.origin, 1.5, deploy=deploy_info(world, mission, w, 1.5, None, None))
    assert [i["frame"] for i in doc["mission"]["items"]] == [2, 10, 3, 10]  # the leading DO_CHANGE_SPEED, the items
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(doc))
    code, rec = _check_json(path, scen)
    assert code == 0 and rec["ok"] is True and rec["terrain_following"]["legs"] == [2]


def test_a_plan_s_navigation_is_judged_on_its_terrain_frame_track(tmp_path):
    """Oracle: the analytic ridge (crest 50 m deep at x = 5 km on 2 km flanks, slope 0.075).  Items 25 m above the
    seabed at x = 3.5 and 6.5 km: ArduSub flies 25 m above the flanks, so within a horizontal error r the seabed
    comes at most 0.075 r higher: least uncertain altitude 25 - 0.075 r (a lower bound's sampling may read a little
    under it).  The navigation check measured the straight leg (137.5 m deep, through the crest): 'least altitude
    within it -87.6 m — TOUCHES', navigation FAIL, exit 1, on a file whose seabed check reads 25 m."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from test_edges12_surfaces import _RIDGE, _plan

    scen = tmp_path / "s.toml"
    scen.write_text(_RIDGE.split("[[zones]]")[0].replace("min_depth_m = 5.0", "min_depth_m = 0.0")
                    + "[navigation]\ndrift_pct = 0.5\ndrift_pct_no_lock = 1.5\ndvl_range_m = 100.0\n"
                    + "fix_error_m = 3.0\nmax_error_m = 60.0\n")
    path = tmp_path / "low.plan"
    path.write_text(_plan([(3500.0, 1000.0, 10, 25.0), (6500.0, 1000.0, 10, 25.0)]))
    code, rec = _check_json(path, scen)
    launch, leg = rec["navigation"]["legs"]  # the launch (leg 0, the home down to the first item) flown too
    least = 25.0 - 0.075 * leg["nav_error_m"]
    assert launch["leg"] == 0 and launch["clear"] and leg["leg"] == 1 and leg["clear"]
    assert least - 0.5 <= leg["uncertain_altitude_m"] <= least + 0.01
    assert leg["lock"] == 1.0 and rec["navigation"]["ok"] and code == 0 and rec["min_altitude_m"] == pytest.approx(25.0)
