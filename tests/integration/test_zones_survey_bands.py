"""A charted zone whose depth band the survey lines fly over (a cable's band a metre above the seabed, under a
surface-mounted multibeam's lines): the zone is surveyed, so it is not the "not surveyed" area ``no_go_m2``
of the coverage (test_zones_survey's zones reach surface to seabed: the band is what they never varied)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from test_zones_survey import ZONE, zone_survey

from auvplan.survey.run import planned_coverage


def test_a_zone_the_lines_fly_over_is_surveyed_not_no_go():
    """Oracle: shapely — the plan's line legs cross the zone, and the coverage is the footprints' union over
    the whole area divided by the whole area (no_go_m2 = 0)."""
    world, params, plan = zone_survey(f'name = "cable"\npolygon = {ZONE}\nabove_seabed_m = 1.0')
    assert plan.status.ok, plan.message
    lab = plan.labels
    on = (lab[:-1] >= 0) & (lab[:-1] == lab[1:])
    legs = shapely.linestrings(np.stack([plan.route[:-1, :2], plan.route[1:, :2]], axis=1)[on])
    assert shapely.intersects(legs, shapely.Polygon(ZONE)).sum() >= 2  # flown over, line after line
    cov = planned_coverage(world, plan, params)
    union = shapely.union_all([f for f in cov.footprints if not f.is_empty])
    theirs = 100.0 * shapely.area(shapely.intersection(params.area, union)) / params.area.area
    assert cov.no_go_m2 == 0.0
    assert cov.area_m2 == pytest.approx(params.area.area, rel=1e-12)
    assert cov.coverage_pct == pytest.approx(theirs, abs=1e-6)
