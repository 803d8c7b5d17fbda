"""Corridor surveys, tie lines, side-scan nadir gaps, areas from files and derived bounds (issue 54).

Oracles: the rounded centre line's radius (circles through its vertices), the frame's round trip, an
independent ray cast of the swath edges (written here from scratch: a 0.1 m march of the outer beam over
the seabed auvplan reads) against the reported overlap, shapely's crossing test for the tie lines, and
the nadir gaps rebuilt from the lines and covered by the neighbours' swaths."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from auvplan.cli import main
from auvplan.io.results.survey import survey_params
from auvplan.io.scenario import loader as scenario_io
from auvplan.survey.lines.frame import CurveFrame, round_corners
from auvplan.survey.lines.placement import LineParams, place_lines
from auvplan.survey.lines.swath import Sensor
from auvplan.survey.mission import plan_survey
from auvplan.survey.run import planned_coverage
from helpers import SLOPING_PLANE


def _radii(p):
    a, b, c = p[:-2], p[1:-1], p[2:]
    cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    ok = cross > 1e-9 * np.linalg.norm(b - a, axis=1) * np.linalg.norm(c - b, axis=1)
    r = np.linalg.norm(b - a, axis=1) * np.linalg.norm(c - b, axis=1) * np.linalg.norm(a - c, axis=1)
    return r[ok] / (2 * cross[ok])


def test_rounded_centre_line_and_its_parallels_turn_within_the_radius():
    pts = np.array([[0.0, 0.0], [3000.0, 0.0], [4500.0, 2600.0], [7000.0, 2600.0], [7000.0, 5000.0]])
    r = 400.0
    rounded = round_corners(pts, r)
    np.testing.assert_allclose(rounded[[0, -1]], pts[[0, -1]])
    assert _radii(rounded).min() >= 0.95 * r  # arcs of r, sampled every degree
    frame = CurveFrame(rounded, 0.98 * r)
    rng = np.random.default_rng(7)
    s, n = rng.uniform(0.0, frame.length, 500), rng.uniform(-0.9 * r, 0.9 * r, 500)
    s2, n2 = frame.to_sn(*frame.from_sn(s, n))
    np.testing.assert_allclose(s2, s, atol=0.5)
    np.testing.assert_allclose(n2, n, atol=0.05)
    for off in (-0.75 * r, -0.5 * r, 0.5 * r, 0.75 * r):  # parallels: simple, and turning with ~ r - |n|
        ss = np.linspace(0.0, frame.length, 3000)
        par = np.column_stack(frame.from_sn(ss, np.full(ss.size, off)))
        assert shapely.LineString(par).is_simple
        assert _radii(par[::3]).min() >= (r - abs(off)) * 0.9


PLANE = '\nname = "plane-corridor"' + SLOPING_PLANE + """[survey]
centerline_xy = [[0.0, 0.0], [2000.0, 0.0], [3300.0, 1500.0], [4800.0, 1500.0]]
widths_m = [240.0, 300.0, 300.0, 200.0]
opening_deg = 120.0
overlap = [0.10, 0.20]
tie_lines = 3
"""


def _edge(seabed, x, y, z, ux, uy, half_angle, t_max):
    """Independent outer-beam edge: march 0.1 m along the ray until it is under the seabed, then bisect."""
    t = np.arange(0.0, t_max, 0.1)
    below = z - t / math.tan(half_angle) <= seabed(x + t * ux, y + t * uy)
    j = int(np.argmax(below))
    lo, hi = t[j - 1], t[j]
    for _ in range(30):
        m = 0.5 * (lo + hi)
        if z - m / math.tan(half_angle) <= float(seabed(np.array([x + m * ux]), np.array([y + m * uy]))[0]):
            hi = m
        else:
            lo = m
    return 0.5 * (lo + hi)


def _ray_cast_overlaps(world, plan, params, centerline, count=40, seed=3):
    """Overlap of adjacent main lines on cuts across the rounded centre line, by an independent ray cast."""
    rng = np.random.default_rng(seed)
    cl = shapely.LineString(centerline)
    lines = [shapely.LineString(p[:, :2]) for p in plan.line_waypoints()]
    z = [float(p[0, 2]) for p in plan.line_waypoints()]
    beta = math.radians(params.sensor.opening_deg) / 2
    out = []
    for s in rng.uniform(0.05, 0.95, count) * cl.length:
        p0, p1 = np.asarray(cl.interpolate(s - 1.0).coords)[0], np.asarray(cl.interpolate(s + 1.0).coords)[0]
        t = (p1 - p0) / np.linalg.norm(p1 - p0)
        nrm = np.array([t[1], -t[0]])  # to the right of the direction of travel along the centre line
        q = np.asarray(cl.interpolate(s).coords)[0]
        cut = shapely.LineString([q - 2000.0 * nrm, q + 2000.0 * nrm])
        edges = []
        for ln, zs in zip(lines, z):
            hit = cut.intersection(ln)
            if hit.is_empty:
                edges.append(None)
                continue
            x, y = np.asarray(hit.coords)[0] if hit.geom_type == "Point" else np.asarray(hit.geoms[0].coords)[0]
            off = float((np.array([x, y]) - q) @ nrm)
            r = _edge(world.seabed, x, y, zs, nrm[0], nrm[1], beta, 3000.0)
            left = _edge(world.seabed, x, y, zs, -nrm[0], -nrm[1], beta, 3000.0)
            edges.append((off - left, off + r))
        half = 0.5 * params.area.intersection(cut).length
        for a, b in zip(edges[:-1], edges[1:]):
            if a is None or b is None or not (b[0] < half and a[1] > -half):
                continue
            out.append((a[1] - b[0]) / min(a[1] - a[0], b[1] - b[0]))
    return np.array(out)


@pytest.fixture(scope="module")
def plane_corridor():
    sc = scenario_io.loads(PLANE, "plane-corridor.toml")
    world, mission = scenario_io.build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, None, "plane-corridor: [survey]")
    return world, mission, params, plan_survey(world, mission, params, 2)


def test_corridor_lines_follow_the_bends_and_cover_it(plane_corridor):
    world, _, params, plan = plane_corridor
    assert plan.status.ok, plan.message
    assert len(plan.lines.lines) >= 2
    for p in plan.line_waypoints():  # parallels of the rounded centre line: none crosses itself at a bend
        assert shapely.LineString(p[:, :2]).is_simple
    assert plan.min_turn_radius_m >= params.turn_radius_m * (1 - 1e-6)
    cov = planned_coverage(world, plan, params)
    assert cov.coverage_pct >= 99.5
    assert 10.0 - 1e-6 <= cov.overlap_min_pct and cov.overlap_max_pct <= 20.0 + 1.0
    # the per-vertex widths: 240 m at the start, 200 m at the end of the corridor
    frame = params.frame
    for s, w in ((5.0, 240.0), (frame.length - 5.0, 200.0)):
        x, y = frame.from_sn(np.array([s, s]), np.array([-400.0, 400.0]))
        cut = shapely.LineString(np.column_stack([x, y]))
        assert params.area.intersection(cut).length == pytest.approx(w, rel=0.02)
    ray = _ray_cast_overlaps(world, plan, params, np.asarray(frame.line.coords))
    assert ray.size >= 15
    assert ray.min() >= 0.10 - 0.01 and ray.max() <= 0.20 + 0.02
    assert abs(100 * ray.min() - cov.overlap_min_pct) < 0.15


def test_tie_lines_cross_every_main_line(plane_corridor):
    _, _, params, plan = plane_corridor
    mains = [shapely.LineString(p[:, :2]) for p in plan.line_waypoints()]
    ties = [shapely.LineString(p[:, :2]) for p in plan.tie_waypoints()]
    assert len(ties) == params.tie_lines == 3
    for tie in ties:
        assert all(tie.crosses(m) for m in mains)
    n = len(mains)
    assert set(np.unique(plan.labels[plan.labels >= n])) == {n, n + 1, n + 2}


def test_sidescan_nadir_gaps_are_covered_by_the_neighbours():
    """A side-scan at 20 m altitude over a sloping plane: every line's nadir gap lies in its neighbours' swaths."""
    def seabed(x, y):
        return -(60.0 + 0.02 * np.asarray(x, float))

    sensor = Sensor("sidescan", range_m=100.0, mounting="auv", altitude_m=20.0, nadir_deg=90.0)
    area = shapely.box(0.0, 0.0, 1500.0, 1000.0)
    lines = place_lines(seabed, area, sensor, 0.0, LineParams(0.10, 0.20, station_m=25.0, step_m=1.0))
    assert lines.complete
    ov = np.concatenate(lines.overlaps())
    assert ov.min() >= 0.10 - 1e-9
    swaths, gaps = [], []
    for ln in lines.lines:  # rebuilt from the lines: a flat seabed under a small slope, so the gap is ~ 20 m
        a = ln.active
        x, y = ln.c[a], lines.stations[a]
        h = ln.z[a] - seabed(x, y)
        np.testing.assert_allclose(h, 20.0, atol=1e-6)
        g = np.column_stack([x - ln.gap_left[a], x + ln.gap_right[a]])
        np.testing.assert_allclose(g[:, 1] - g[:, 0], 40.0, rtol=0.03)  # 2 h tan 45°, the slope's 1 % aside
        gaps.append(shapely.Polygon(np.r_[np.column_stack([g[:, 0], y]), np.column_stack([g[::-1, 1], y[::-1]])]))
        e = np.column_stack([x - ln.left[a], x + ln.right[a]])
        band_l = shapely.Polygon(np.r_[np.column_stack([e[:, 0], y]), np.column_stack([g[::-1, 0], y[::-1]])])
        band_r = shapely.Polygon(np.r_[np.column_stack([g[:, 1], y]), np.column_stack([e[::-1, 1], y[::-1]])])
        swaths.append(band_l.union(band_r))
    covered = total = 0.0
    for i, gap in enumerate(gaps):
        inside = gap.intersection(area)
        others = shapely.union_all([s for j, s in enumerate(swaths) if j != i])
        covered += inside.intersection(others).area
        total += inside.area
    assert total > 0 and covered / total >= 0.999  # the share of the gaps' area the neighbours cover
    union = shapely.union_all(swaths)
    assert union.intersection(area).area / area.area >= 0.995


AWAY = """
name = "away"
seed = 1
[terrain]
builtin = "matplotlib-topobathy"
resample_m = 500.0
[currents]
uniform = [0.0, 0.0, 0.0]
[mission]
start = {{ lat = 48.065, lon = -124.93, depth = 2.0 }}
goal = {{ lat = 48.065, lon = -124.93, depth = 2.0 }}
min_altitude_m = 10.0
min_depth_m = 2.0
max_depth_m = 400.0
[vehicle]
speed = 2.0
[planner]
name = "iabc"
population = 16
iterations = 12
control_points = 3
samples = 60
[survey]
polygon = [[48.0738, -124.8911], [48.0734, -124.8575], [48.0958, -124.8571], [48.0963, -124.8908]]
overlap = [0.10, 0.20]
heading_deg = 0.0
{extra}
"""


def test_an_area_away_from_the_launch_without_bounds_is_planned(tmp_path, capsys):
    scen = tmp_path / "away.toml"
    scen.write_text(AWAY.format(extra=""))
    sc = scenario_io.load(str(scen))
    world, mission = scenario_io.build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, sc.base_dir, "away: [survey]")
    start = np.asarray(mission.start[:2])
    assert shapely.Point(start).distance(params.area) > 1500.0  # the area is kilometres from the launch
    plan = plan_survey(world, mission, params, 1)
    assert plan.status.ok, plan.message


@pytest.mark.parametrize(("change", "needle"), [
    ("[4800.0, 1500.0]]", "not inside the [bounds]"),  # the corridor's end beyond the bounds
    ("[4800.0, 1500.0], [5400.0, 1500.0]]", "widths_m"),  # a vertex without its width
])
def test_validate_runs_the_survey_checks_before_it_says_ok(tmp_path, capsys, change, needle):
    scen = tmp_path / "bad.toml"
    scen.write_text(PLANE.replace("[4800.0, 1500.0]]", change.replace("[4800.0", "[7800.0", 1)
                                  if "5400" not in change else change))
    assert main(["validate", str(scen)]) == 2
    out, err = capsys.readouterr()
    assert "OK" not in out and "[survey]" in err and needle in err and err.count("\n") == 1


@pytest.mark.parametrize("driver", ["GPKG", "ESRI Shapefile"])
def test_centre_line_from_a_projected_vector_file(tmp_path, driver):
    """A centre line written in UTM zone 10 N (EPSG:32610) gives the corridor of the same line in lat/lon."""
    import pyogrio
    from pyproj import Transformer

    from auvplan.io.data.vector.areas import read_line_lonlat

    lonlat = np.array([[-124.17, 48.345], [-124.07, 48.30], [-123.93, 48.29]])
    e, n = Transformer.from_crs("EPSG:4326", "EPSG:32610", always_xy=True).transform(lonlat[:, 0], lonlat[:, 1])
    path = tmp_path / ("line.gpkg" if driver == "GPKG" else "line.shp")
    pyogrio.raw.write(path, np.array([shapely.to_wkb(shapely.LineString(np.column_stack([e, n])))], dtype=object),
                      [], [], geometry_type="LineString", crs="EPSG:32610", driver=driver)
    back = read_line_lonlat(path, "", "test: [survey]")
    np.testing.assert_allclose(back, lonlat, atol=1e-7)
