"""Geographic positions in scenarios ({lat, lon, depth | altitude}), derived [origin] and [bounds]."""

from __future__ import annotations

import csv
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from pyproj import Geod

from auvplan import cli
from auvplan.errors import DataError
from auvplan.io.scenario import loader as scenario_io
from auvplan.io.scenario.inputs.geoinput import bounds_margin
from auvplan.planners import plan
from auvplan.sim.pipeline import planning_problem

# The salish-shelf crossing written as an operator would: degrees, a depth and an altitude.
GEO = """
name = "salish-ll"
seed = 1
[terrain]
builtin = "matplotlib-topobathy"
resample_m = 1000.0
[currents]
uniform = [0.2, 0.05, 0.0]
[mission]
start = { lat = 48.095, lon = -125.683, depth = 200.0 }
goal = { lat = 48.500, lon = -124.612, altitude = 30.0 }
min_altitude_m = 10.0
min_depth_m = 5.0
max_depth_m = 800.0
[planner]
name = "iabc"
population = 20
budget = 400
"""


def _twin(sc: scenario_io.Scenario, world_bounds: tuple[float, ...], start: tuple[float, ...],
          goal: tuple[float, ...]) -> str:
    """The same mission in metres: [origin], [bounds] and metre triples written out (repr floats)."""
    x0, x1, y0, y1 = world_bounds
    assert sc.origin is not None
    return GEO.replace("[mission]", f"[origin]\nlat = {sc.origin.lat!r}\nlon = {sc.origin.lon!r}\n[bounds]\n"
                       f"x = [{x0!r}, {x1!r}]\ny = [{y0!r}, {y1!r}]\n[mission]").replace(
        "{ lat = 48.095, lon = -125.683, depth = 200.0 }", f"[{start[0]!r}, {start[1]!r}, {start[2]!r}]").replace(
        "{ lat = 48.500, lon = -124.612, altitude = 30.0 }", f"[{goal[0]!r}, {goal[1]!r}, {goal[2]!r}]")


def test_latlon_scenario_plans_the_same_path_as_its_metre_twin() -> None:
    sc = scenario_io.loads(GEO, "geo.toml")
    world, mission = scenario_io.build(sc)
    b = world.bounds
    twin = scenario_io.loads(_twin(sc, (b.xmin, b.xmax, b.ymin, b.ymax), mission.start, mission.goal), "twin.toml")
    assert twin.geo is None and twin.origin == sc.origin
    world2, mission2 = scenario_io.build(twin)
    np.testing.assert_array_equal(world.terrain.z, world2.terrain.z)  # type: ignore[union-attr]
    assert mission.start == mission2.start and mission.goal == mission2.goal
    a = plan(planning_problem(world, mission), mission.planner, 1)
    c = plan(planning_problem(world2, mission2), mission2.planner, 1)
    assert a.status.ok and c.status.ok
    np.testing.assert_array_equal(a.path, c.path)


def test_projection_depth_and_altitude_against_independent_geodesy() -> None:
    text = GEO.replace("[mission]", "[origin]\nlat = 48.095\nlon = -125.683\n[mission]")
    sc = scenario_io.loads(text, "geo.toml")
    world, mission = scenario_io.build(sc)
    assert mission.start[:2] == pytest.approx((0.0, 0.0), abs=1e-6)  # the start is the origin
    assert mission.start[2] == -200.0  # depth -> z = -depth
    # azimuthal equidistant about the origin: |(x, y)| is the geodesic distance, atan2(x, y) its azimuth
    az, _, dist = Geod(ellps="WGS84").inv(-125.683, 48.095, -124.612, 48.500)
    gx, gy, gz = mission.goal
    assert np.hypot(gx, gy) == pytest.approx(dist, rel=1e-9)
    assert np.degrees(np.arctan2(gx, gy)) == pytest.approx(az, abs=1e-7)
    assert gz - float(world.seabed(gx, gy)) == pytest.approx(30.0, abs=1e-9)  # altitude above the seabed


def test_derived_origin_and_bounds() -> None:
    sc = scenario_io.loads(GEO, "geo.toml")
    assert sc.origin is not None and sc.geo is not None and sc.geo.origin_derived and sc.geo.bounds_derived
    assert (sc.origin.lat, sc.origin.lon) == pytest.approx((0.5 * (48.095 + 48.5), 0.5 * (-125.683 - 124.612)))
    world, mission = scenario_io.build(sc)
    xs, ys = (mission.start[0], mission.goal[0]), (mission.start[1], mission.goal[1])
    pad = bounds_margin(max(np.ptp(xs), np.ptp(ys)))
    assert pad == pytest.approx(0.25 * np.ptp(xs))
    b, t = world.bounds, world.terrain
    assert t is not None
    want = (max(min(xs) - pad, t.x[0]), min(max(xs) + pad, t.x[-1]), max(min(ys) - pad, t.y[0]),
            min(max(ys) + pad, t.y[-1]))
    assert (b.xmin, b.xmax, b.ymin, b.ymax) == pytest.approx(want, abs=1.0)
    assert b.ymin > min(ys) - pad + 1000.0  # the south side was clipped to the data


def test_data_that_do_not_cover_the_mission_name_the_side() -> None:
    sc = scenario_io.loads(GEO.replace("lat = 48.095", "lat = 47.0"), "geo.toml")
    with pytest.raises(DataError, match=r"\[mission\] start .*beyond the data's south side"):
        scenario_io.build(sc)


def test_geographic_obstacle_and_moving_positions() -> None:
    text = GEO + """
[[obstacles]]
center = { lat = 48.3, lon = -125.1, depth = 100.0 }
radius = 500.0
[[moving]]
radius = 50.0
motion = "waypoints"
speed = 1.0
points = [{ lat = 48.3, lon = -125.0, depth = 50.0 }, { lat = 48.31, lon = -125.0, depth = 50.0 }]
"""
    sc = scenario_io.loads(text, "geo.toml")
    assert sc.obstacles[0].center[2] == -100.0
    pts = sc.moving[0].motion.points
    assert pts[1, 1] - pts[0, 1] == pytest.approx(Geod(ellps="WGS84").inv(-125.0, 48.3, -125.0, 48.31)[2], rel=1e-3)


@pytest.mark.parametrize("old, new, key, value", [
    ("lat = 48.095", "lat = 95.0", "start.lat", "95.0"),
    ("lon = -124.612", "lon = 400.0", "goal.lon", "400.0"),
    ("depth = 200.0", "depth = 200.0, altitude = 5.0", "start", "'altitude': 5.0"),
    ("depth = 200.0", "dept = 200.0", "start.dept", "200.0"),
    ("altitude = 30.0", "altitude = -3.0", "goal.altitude", "-3.0"),
    ("lon = -125.683", 'lon = "W125"', "start.lon", "'W125'"),
    ("lat = 48.500, ", "", "goal", "'lon': -124.612"),
])
def test_bad_geographic_input_exits_2_naming_file_key_and_value(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                                old: str, new: str, key: str, value: str) -> None:
    f = tmp_path / "bad.toml"
    f.write_text(GEO.replace(old, new, 1))
    assert cli.main(["validate", str(f)]) == 2
    err = capsys.readouterr().err
    assert str(f) in err and f"[mission] {key} = " in err and value in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


def test_results_keep_lat_lon_beside_x_y(tmp_path: Path) -> None:
    f = tmp_path / "geo.toml"
    f.write_text(GEO)
    assert cli.main(["-q", "plan", str(f), "--out", str(tmp_path / "out")]) == 0
    with open(tmp_path / "out" / "path.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["x", "y", "z", "lat", "lon"]
    assert (float(rows[0]["lat"]), float(rows[0]["lon"])) == pytest.approx((48.095, -125.683), abs=1e-8)
    assert (float(rows[-1]["lat"]), float(rows[-1]["lon"])) == pytest.approx((48.5, -124.612), abs=1e-8)
    metrics = json.loads((tmp_path / "out" / "metrics.json").read_text())
    assert len(metrics["waypoints_lat_lon"]) == len(metrics["waypoints"]) == len(rows)
    assert metrics["waypoints_lat_lon"][0] == pytest.approx([48.095, -125.683], abs=1e-8)


def test_metre_scenarios_are_untouched() -> None:
    sc = scenario_io.load("salish-shelf")
    assert sc.geo is None
    assert replace(sc.mission).start == (5000.0, 5000.0, -200.0)
