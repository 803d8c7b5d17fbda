"""Survey lines clipped by a charted zone, the gaps bridged by transits that go round it (oracle: shapely's
intersection of every route leg with the footprint, which reaches surface to seabed; the lines on both
sides of the zone still flown)."""

from __future__ import annotations

import numpy as np
import shapely
from test_survey_mission import AREA, SCENARIO

from auvplan.io.results.survey import survey_params
from auvplan.io.scenario.build import build
from auvplan.io.scenario.loader import loads
from auvplan.survey.mission import TRANSIT, plan_survey

ZONE = [[700.0, 620.0], [1000.0, 620.0], [1000.0, 780.0], [700.0, 780.0]]  # metres: a box inside the area


def test_lines_are_clipped_by_a_zone_and_the_gaps_bridged_round_it():
    text = SCENARIO.format(area=AREA, mounting="surface", extra="") + \
        f'\n[[zones]]\nname = "exclusion"\npolygon = {ZONE}\n'
    sc = loads(text, source="survey.toml")
    world, mission = build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, None, "survey.toml: [survey]")
    plan = plan_survey(world, mission, params, sc.seed)
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
