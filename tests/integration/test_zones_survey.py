"""Survey lines clipped by a charted zone, the gaps bridged by transits that go round it (oracle: shapely's
intersection of every route leg with the footprint, which reaches surface to seabed; the lines on both
sides of the zone still flown)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from test_survey_mission import AREA, SCENARIO

from auvplan.io.results.survey import survey_params
from auvplan.io.scenario.build import build
from auvplan.io.scenario.loader import loads
from auvplan.path.flyable import VehicleLimits
from auvplan.path.legs import helm_check
from auvplan.survey.mission import TRANSIT, plan_survey

ZONE = [[700.0, 620.0], [1000.0, 620.0], [1000.0, 780.0], [700.0, 780.0]]  # metres: a box inside the area


def zone_survey(zone: str) -> tuple:
    """(world, params, plan) of the test survey with one ``[[zones]]`` table's body added."""
    sc = loads(SCENARIO.format(area=AREA, mounting="surface", extra="") + f"\n[[zones]]\n{zone}\n",
               source="survey.toml")
    world, mission = build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, None, "survey.toml: [survey]")
    return world, params, plan_survey(world, mission, params, sc.seed)


@pytest.fixture(scope="module")
def box_survey():
    """The survey round the box zone, planned once for the tests below."""
    return zone_survey(f'name = "exclusion"\npolygon = {ZONE}')


def test_lines_are_clipped_by_a_zone_and_the_gaps_bridged_round_it(box_survey):
    _, _, plan = box_survey
    assert plan.status.ok, plan.message
    box = shapely.Polygon(ZONE)
    legs = shapely.linestrings(np.stack([plan.route[:-1, :2], plan.route[1:, :2]], axis=1))
    assert not shapely.intersects(legs, box).any()
    on_line = plan.labels >= 0
    cut = [k for k in range(len(plan.lines.lines))
           if (plan.route[plan.labels == k, 0].min() < 1000.0 and plan.route[plan.labels == k, 0].max() > 700.0)]
    assert cut  # lines over the zone's x-range ...
    for k in cut:  # ... are flown south and north of it
        y = plan.route[plan.labels == k, 1]
        assert y.min() < 620.0 and y.max() > 780.0
    assert (plan.labels == TRANSIT).any() and on_line.sum() > 0


# a zone with sharp corners, concave ones among them: an arrowhead whose notch is 8 degrees wide
ARROW = [[650.0, 550.0], [1150.0, 700.0], [650.0, 850.0], [1100.0, 700.0]]


def test_lines_and_transits_keep_out_of_a_zone_with_sharp_concave_corners():
    """Every leg of the clipped route (lines, turns, bridging transits) against the arrowhead's footprint by
    shapely (surface to seabed: any touch is an entry), and the lines still flown on both sides of it."""
    _, params, plan = zone_survey(f'name = "arrow"\npolygon = {ARROW}')
    assert plan.status.ok, plan.message
    arrow = shapely.Polygon(ARROW)
    legs = shapely.linestrings(np.stack([plan.route[:-1, :2], plan.route[1:, :2]], axis=1))
    assert not shapely.intersects(legs, arrow).any()
    assert (plan.labels == TRANSIT).any()
    # the bridges round the arrow join the lines by turns a helm flies at the vehicle's radius, as `mission
    # check` judges the exported waypoints (their corners turned at 6.0 m against 10 m before)
    report = helm_check(plan.route, VehicleLimits(90.0, params.turn_radius_m), min_leg=0.0)
    assert report.tightest_turn_m >= params.turn_radius_m * (1.0 - 1e-9), report.violations[:2]


def test_coverage_leaves_the_no_go_area_out_of_its_denominator(box_survey):
    """coverage_pct of the plan against shapely's own: the footprints' union over the area less the zone,
    divided by that area; no_go_m2 is the zone's part of the area, and no gap lies inside the zone."""
    from auvplan.survey.run import planned_coverage

    world, params, plan = box_survey
    cov = planned_coverage(world, plan, params)
    box = shapely.Polygon(ZONE)
    rest = params.area.difference(box)
    union = shapely.union_all([f for f in cov.footprints if not f.is_empty])
    theirs = 100.0 * shapely.area(shapely.intersection(rest, union)) / rest.area
    assert cov.no_go_m2 == pytest.approx(shapely.area(shapely.intersection(params.area, box)), rel=1e-9)
    assert cov.area_m2 == pytest.approx(rest.area, rel=1e-9)
    assert cov.coverage_pct == pytest.approx(theirs, abs=1e-6)
    assert all(shapely.area(shapely.intersection(g, box)) < 1e-6 for g in cov.gaps)
