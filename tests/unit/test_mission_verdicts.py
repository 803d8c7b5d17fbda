"""``mission check``'s verdict pieces worked by hand: the terrain-following check's legs, extremes and line
(``app.check.terrain_following_check``), the zones a terrain-frame ``.plan`` enters on its straight legs and on its
seabed-following track (``_zone_approach``), and the navigation check of a ``.plan`` (its home is the launch, not a
leg: the same record as the same waypoints in a CSV file)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import shapely

from auvplan.app.check import _zone_approach, terrain_following_check
from auvplan.world import Zone, Zones
from helpers import FLAT_SEA, flat_world


def test_terrain_following_legs_extremes_and_vertices_by_hand():
    """Flat seabed 100 m deep, grid lines every 50 m, min_depth 5 m.  Home on the surface, then items 60, 3, 50
    and 50 m deep, the last three legs following the seabed: the track's vertices are the items and the grid
    crossings (11); item A (60 m, max_depth 55 m) and item B (3 m) are outside the depth band, each charged to the
    leg ending there (0, the launch leg, and 1); the deepest point is A, the shallowest B."""
    w = flat_world(depth=100.0, min_depth=5.0, max_depth=55.0)
    pts = np.array([[355.0, 500.0, 0.0], [355.0, 450.0, -60.0], [400.0, 500.0, -3.0], [600.0, 500.0, -50.0],
                    [800.0, 500.0, -50.0]])
    rec, ok, line = terrain_following_check(w, pts, np.array([False, True, True, True]))
    assert not ok and rec["legs"] == [1, 2, 3] and rec["vertices"] == 11
    assert rec["outside_depth_band_legs"] == [0, 1] and rec["above_surface_legs"] == []
    assert rec["deepest_m"] == pytest.approx(60.0) and rec["shallowest_m"] == pytest.approx(3.0)
    assert "(MAV_FRAME 10: 1, 2, 3)" in line and "outside the depth band (5-55 m) on legs 0, 1;" in line


@pytest.mark.parametrize(("n", "named"), [(5, "1, 2, 3, 4, 5"), (6, "6 legs of 7")])
def test_terrain_following_line_names_up_to_five_legs(n, named):
    w = flat_world(depth=100.0)
    pts = np.array([[100.0 + 100.0 * k, 500.0, -50.0] for k in range(n + 2)])
    pts[1, 2] = -10.0  # the first item the shallowest point
    rec, ok, line = terrain_following_check(w, pts, np.r_[False, np.ones(n, dtype=bool)])
    assert ok and rec["legs"] == list(range(1, n + 1)) and f"(MAV_FRAME 10: {named})" in line
    assert rec["shallowest_m"] == pytest.approx(10.0) and rec["deepest_m"] == pytest.approx(50.0)
    assert line.endswith("; needs an ArduSub that flies terrain-frame items (its Sub::start_command accepting "
                         "ABOVE_TERRAIN): one accepting only ABOVE_HOME says 'BAD NAV AltFrame' and skips each of them")


def test_zones_of_a_terrain_frame_plan_on_its_track():
    """A seabed 100 m deep with a 60 m high ridge (x 500..700, crest at 600): items 50 m above the seabed at x = 200,
    480 and 900.  Zone "crest" (0-55 m deep, x 480.5..900): leg 2, its track from its very first segment on (not leg 1,
    which ends at x = 480);
    zone "straight" (45-55 m deep, x 300..400): the straight leg 1 and its track, the same line (the seabed is flat
    there); zone "under" (45-55 m, x 620..680): only the straight leg 2, which ArduSub does not fly: the track is 2-38
    m deep over the ridge's flank there, and deepens 0.6 m a metre beyond x = 680, so it passes the zone's corner
    (680, 45 m) at 7 / sqrt(1 + 0.6^2) = 6.00 m (the track's vertex at x = 680: 7 m); zone "deep" (70-80 m,
    x 800..850): nothing."""
    from auvplan.world.terrain import Terrain
    from auvplan.world.world import Bounds, Margins, World

    x, y = np.arange(0.0, 1001.0, 20.0), np.array([0.0, 1000.0])
    zb = -100.0 + 60.0 * np.clip(1.0 - np.abs(x - 600.0) / 100.0, 0.0, None)
    t = Terrain(x, y, np.tile(zb, (2, 1)))
    zones = (Zone("crest", shapely.box(480.5, 0.0, 900.0, 1000.0), top=0.0, bottom=55.0),
             Zone("under", shapely.box(620.0, 0.0, 680.0, 1000.0), top=45.0, bottom=55.0),
             Zone("straight", shapely.box(300.0, 0.0, 400.0, 1000.0), top=45.0, bottom=55.0),
             Zone("deep", shapely.box(800.0, 0.0, 850.0, 1000.0), top=70.0, bottom=80.0))
    world = World(Bounds(0.0, 1000.0, 0.0, 1000.0, -100.0, 0.0), t, zones=Zones(zones, t), margins=Margins())
    pts = np.array([[200.0, 500.0, -50.0], [480.0, 500.0, -50.0], [900.0, 500.0, -50.0]])
    got = {z.name: z for z in _zone_approach(world, pts, "ramp", 15.0, np.array([True, True]))}
    assert got["crest"].entered_legs == (2,) and got["crest"].closest_m < 0.0  # inside: a penetration
    assert got["straight"].entered_legs == (1,) and got["deep"].entered_legs == ()
    true = 7.0 / math.sqrt(1.36)  # measured on samples every 25 m: within 12.5 m above the true least distance
    assert got["under"].entered_legs == () and true - 1e-9 <= got["under"].closest_m <= true + 12.5
    assert got["deep"].closest_m == pytest.approx(20.0)  # the straight leg 2 and the track at 50 m, 20 m above it


_NAV_TOML = 'name = "nav-verdicts"\n' + FLAT_SEA + """[navigation]
drift_pct = 0.5
drift_pct_no_lock = 1.5
dvl_range_m = 100.0
fix_error_m = 3.0
max_error_m = 60.0
"""


def test_a_plan_s_navigation_is_the_csv_s_of_the_same_waypoints(tmp_path, capsys):
    """Oracle: the format does not change the waypoints: the .plan's navigation record (its home the launch) is the
    CSV's, leg for leg; three legs, the middle one a 8 km dive long enough to break the 60 m budget."""
    from auvplan.cli import main
    from auvplan.io.missions.formats import mission_csv, to_qgc_plan

    toml = tmp_path / "nav.toml"
    toml.write_text(_NAV_TOML)
    pts = np.array([[1000.0, 6000.0, 0.0], [3000.0, 6000.0, -150.0], [11000.0, 6000.0, -150.0],
                    [15000.0, 6000.0, 0.0]])
    (tmp_path / "m.csv").write_text(mission_csv(pts, (16.0, 145.0), 1.5))
    (tmp_path / "m.plan").write_text(json.dumps(to_qgc_plan(pts, (16.0, 145.0), 1.5)))
    capsys.readouterr()
    main(["mission", "check", str(tmp_path / "m.csv"), str(tmp_path / "m.plan"), "--scenario", str(toml), "--json"])
    recs = [r["navigation"] for r in json.loads(capsys.readouterr().out)]
    csv, plan = recs
    assert [r["leg"] for r in csv["legs"]] == [0, 1, 2] and csv["ok"] is False
    # the .plan's launch (its home to its first item, here the same point) is its leg 0, flown as every leg; its
    # end, the mission's start at the surface, is no fix (audit 23: it was one, which nav22's wait check then failed);
    # its leg k is the CSV's leg k - 1 (each leg named by the waypoint it leaves, the .plan's home its waypoint 0)
    assert [r["leg"] for r in plan["legs"]] == [0, 1, 2, 3]
    assert [{**r, "leg": r["leg"] - 1} for r in plan["legs"][1:]] == csv["legs"]
    assert plan["legs"][0]["clear"] and plan["fixes"] == csv["fixes"] and plan["ok"] == csv["ok"]


def test_zones_of_a_plan_whose_second_leg_is_a_straight_item():
    """As above with leg 2 in a straight frame (ArduSub flies it as the line between its items, 50 m deep): it
    enters "crest" (0-55 m) and "under" (45-55 m) on its own line; leg 1 (terrain frame, over the flat seabed: its
    track the same line) enters "straight"; "deep" stays 20 m below both."""
    from auvplan.world.terrain import Terrain
    from auvplan.world.world import Bounds, Margins, World

    x, y = np.arange(0.0, 1001.0, 20.0), np.array([0.0, 1000.0])
    zb = -100.0 + 60.0 * np.clip(1.0 - np.abs(x - 600.0) / 100.0, 0.0, None)
    t = Terrain(x, y, np.tile(zb, (2, 1)))
    zones = (Zone("crest", shapely.box(480.5, 0.0, 900.0, 1000.0), top=0.0, bottom=55.0),
             Zone("under", shapely.box(620.0, 0.0, 680.0, 1000.0), top=45.0, bottom=55.0),
             Zone("straight", shapely.box(300.0, 0.0, 400.0, 1000.0), top=45.0, bottom=55.0),
             Zone("deep", shapely.box(800.0, 0.0, 850.0, 1000.0), top=70.0, bottom=80.0))
    world = World(Bounds(0.0, 1000.0, 0.0, 1000.0, -100.0, 0.0), t, zones=Zones(zones, t), margins=Margins())
    pts = np.array([[200.0, 500.0, -50.0], [480.0, 500.0, -50.0], [900.0, 500.0, -50.0]])
    got = {z.name: z for z in _zone_approach(world, pts, "ramp", 15.0, np.array([True, False]))}
    assert got["crest"].entered_legs == (2,) and got["under"].entered_legs == (2,)
    assert got["straight"].entered_legs == (1,) and got["deep"].entered_legs == ()
    assert got["under"].closest_m == pytest.approx(-5.0)  # 50 m deep in the 45-55 m band: 5 m inside either face
    assert got["deep"].closest_m == pytest.approx(20.0)
