"""The built-in survey on real sloped bathymetry (shelf-survey: the Juan de Fuca shelf, matplotlib's
topobathy.npz): planned coverage and overlap bounds, lines saved against the fixed lawnmower."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.io.results.survey import survey_params
from auvplan.io.scenario import loader as scenario_io
from auvplan.survey.coverage import lawnmower
from auvplan.survey.mission import plan_survey
from auvplan.survey.run import planned_coverage


@pytest.fixture(scope="module")
def shelf():
    sc = scenario_io.load("shelf-survey")
    world, mission = scenario_io.build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, sc.base_dir, "shelf-survey: [survey]")
    return world, mission, params, plan_survey(world, mission, params, sc.seed)


def test_builtin_survey_covers_the_area_with_every_overlap_in_bounds(shelf):
    world, _, params, plan = shelf
    assert plan.status.ok, plan.message
    cov = planned_coverage(world, plan, params)
    assert cov.coverage_pct >= 99.5
    assert len(cov.overlap) == len(plan.lines.lines) - 1 and all(o.size for o in cov.overlap)
    assert 10.0 - 1e-6 <= cov.overlap_min_pct and cov.overlap_max_pct <= 20.0 + 1e-6
    depth = -world.seabed(*np.asarray(params.area.exterior.coords).T)
    assert depth.max() - depth.min() > 40.0  # a real slope: the area shoals by more than 40 m


def test_builtin_survey_mission_has_no_leg_shorter_than_the_vehicle_allows(shelf):
    """`mission check` failed every export of shelf-survey (and strait-corridor) on the vehicle's helm: the
    transits out and home began and ended with legs of 7 and 2 cm beside the launch point (shortest leg 0.1 m)."""
    from auvplan.path.legs import helm_check, shortest_leg
    from auvplan.sim.pipeline import vehicle_limits

    _, mission, _, plan = shelf
    lim = vehicle_limits(mission.vehicle)
    assert np.linalg.norm(np.diff(plan.route, axis=0), axis=1).min() >= shortest_leg(lim)
    assert helm_check(plan.route, lim).ok
    np.testing.assert_allclose(plan.route[[0, -1]], [mission.start, mission.goal], atol=1e-9)
    assert plan.labels.shape == (len(plan.route),)


def test_builtin_survey_saves_lines_against_the_fixed_lawnmower(shelf):
    world, _, params, plan = shelf
    mower = lawnmower(world.seabed, params.area, params.sensor, plan.lines.heading, params.lines.overlap_min,
                      -world.margins.min_depth, params.run_in_m)
    # the lawnmower's spacing: the flat swath 2 D tan(60°) at the shallowest depth below the 2 m draft
    assert mower.spacing_m == pytest.approx(0.9 * 2 * (mower.shallowest_m - 2.0) * np.tan(np.radians(60.0)))
    assert mower.lines - len(plan.lines.lines) >= 3
    flown_lines = sum(float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) for p in plan.line_waypoints())
    assert flown_lines < mower.line_length_m
    assert plan.min_turn_radius_m >= params.turn_radius_m * (1 - 1e-6)


def test_builtin_survey_flown_in_the_cross_current_covers_99_percent(shelf):
    from dataclasses import replace

    from auvplan.sim import RunRecord, simulate
    from auvplan.survey.run import flown_coverage

    world, mission, params, plan = shelf
    speed = np.hypot(*np.asarray(world.currents.velocity(np.array([[65000.0, 4000.0, -2.0]]), 0.0))[0, :2])
    assert speed > 0.19  # a real cross-current on the north-south lines
    sim = simulate(world, replace(mission, route=tuple(map(tuple, plan.route.tolist()))), route=plan.route, rng=1,
                   avoidance="none", keys=np.empty((0, 3)))
    assert sim.status.ok
    cov, t_lines = flown_coverage(world, plan, params, RunRecord("shelf-survey", 1, None, plan.route,
                                                                  np.empty((0, 3)), sim))
    assert cov.coverage_pct >= 99.0
    assert 0 < t_lines < sim.t[-1]
    # the lines were placed with the crab margin of the 0.2 m/s cross-current: the flown overlap keeps the floor
    cross = 0.2  # the current across the north-south lines (m/s)
    assert plan.overlap_margin == pytest.approx(1 - np.sqrt(1 - (cross / mission.vehicle.speed) ** 2), rel=1e-6)
    assert cov.overlap_min_pct >= 10.0


def test_sidescan_on_the_shelf_every_nadir_gap_is_covered_by_the_neighbours(shelf):
    """A side-scan (150 m range, 15 m altitude, 90° blind cone) over the real shelf: the gaps rebuilt from the
    lines (c - g-, c + g+ at every station) lie inside the other lines' swath footprints (share: 100 %)."""
    import shapely

    from auvplan.survey.coverage import footprints, measure
    from auvplan.survey.lines.placement import place_lines
    from auvplan.survey.lines.swath import Sensor

    world, _, params, _ = shelf
    sensor = Sensor("sidescan", range_m=150.0, mounting="auv", altitude_m=15.0, nadir_deg=90.0)
    lines = place_lines(world.seabed, params.area, sensor, 0.0, params.lines)
    assert lines.complete
    fr = lines.geom
    fps, gaps = [], []
    for ln in lines.lines:
        a = ln.active
        s = lines.stations[a]
        p = np.column_stack([*fr.from_sn(s, ln.c[a]), ln.z[a]])
        fps += footprints(world.seabed, sensor, p, fr.right(s), np.zeros(s.size, dtype=np.int64), 1, 2.0)
        left = np.column_stack(fr.from_sn(s, ln.c[a] - ln.gap_left[a]))
        right = np.column_stack(fr.from_sn(s, ln.c[a] + ln.gap_right[a]))
        gaps.append(shapely.Polygon(np.r_[left, right[::-1]]).buffer(0))
        assert np.nanmin(ln.gap_left[a] + ln.gap_right[a]) > 25.0  # ~ 2 h tan 45° = 30 m over the gentle slope
    cov = measure(params.area, lines, fps)
    assert cov.coverage_pct >= 99.99 and cov.overlap_min_pct >= 10.0 - 1e-6
    total = covered = 0.0
    for i, g in enumerate(gaps):
        inside = g.intersection(params.area)
        covered += inside.intersection(shapely.union_all([f for j, f in enumerate(fps) if j != i])).area
        total += inside.area
    assert total > 1e6 and covered / total >= 0.9999
