"""Audit 24, the survey's files and checks.  ``gaps.geojson`` of a survey across the antimeridian: the area and its
gaps were written with the longitudes ``LocalFrame.inverse`` gives, 179.99 beside -179.99, a polygon 359.99° wide
drawn as a band round the Earth by every viewer that joins longitudes on a plane (the mission exports cut theirs,
RFC 7946 §3.1.9).  Oracles: no ring's step longer than 180° of longitude, every longitude in [-180, 180], and the
pieces projected back into the local frame (pyproj, independently of the writer) making the area the survey
measured, to 0.1 %."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

sys.path.insert(0, str(Path(__file__).parent))

from test_survey_mission import AREA, SCENARIO  # noqa: E402

from auvplan.io.data.geo import LocalFrame  # noqa: E402
from auvplan.io.results.survey import survey_params, write_survey  # noqa: E402
from auvplan.io.scenario import loader as scenario_io  # noqa: E402
from auvplan.sim import RunRecord  # noqa: E402
from auvplan.survey.coverage import lawnmower  # noqa: E402
from auvplan.survey.mission import plan_survey  # noqa: E402
from auvplan.survey.run import SurveyRun, planned_coverage  # noqa: E402


@pytest.mark.parametrize("lon0", [179.99, 179.985, -125.0])
def test_gaps_geojson_is_cut_at_the_antimeridian(tmp_path, lon0):
    text = SCENARIO.format(area=AREA, mounting="surface", extra="").replace("lon = -125.0", f"lon = {lon0}")
    sc = scenario_io.loads(text, "s.toml")
    world, mission = scenario_io.build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, None, "s")
    plan = plan_survey(world, mission, params, 2)
    cov = planned_coverage(world, plan, params)
    mower = lawnmower(world.seabed, params.area, params.sensor, plan.lines.heading, 0.1, -2.0, 60.0)
    run = SurveyRun(plan, RunRecord("s", 2, None, plan.route, np.empty((0, 3)), None), cov, None, mower, float("nan"))
    write_survey(tmp_path, run, params, world.origin)
    feats = json.loads((tmp_path / "gaps.geojson").read_text())["features"]
    area = [f for f in feats if f["properties"]["kind"] == "area"]
    assert len(area) == 1
    frame = LocalFrame(*world.origin)
    pieces = []
    g = area[0]["geometry"]
    polys = [g["coordinates"]] if g["type"] == "Polygon" else g["coordinates"]
    for poly in polys:
        ring = np.asarray(poly[0], dtype=float)
        assert np.abs(ring[:, 0]).max() <= 180.0
        assert np.abs(np.diff(ring[:, 0])).max() < 180.0
        pieces.append(shapely.Polygon(np.column_stack(frame.forward(ring[:, 0], ring[:, 1]))))
    assert len(pieces) == (2 if abs(lon0) > 179.0 else 1)
    assert shapely.union_all(pieces).area == pytest.approx(params.area.area, rel=1e-3)


def test_an_auv_altitude_under_min_altitude_is_bad_input(tmp_path, capsys):
    """``[survey] altitude_m = 3`` under ``[mission] min_altitude_m = 5``: every line is flown closer to the seabed
    than allowed.  `validate` said OK and `survey` planned 108 lines before failing INFEASIBLE on 7 445 segments
    (exit 1); the contract is exit 2 with one line naming the file, the key and the value."""
    from auvplan.cli import main

    scen = tmp_path / "alt.toml"
    scen.write_text(SCENARIO.format(area=AREA, mounting="auv", extra="altitude_m = 3.0"))
    assert main(["validate", str(scen)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "alt.toml" in err and "altitude_m = 3" in err and "min_altitude_m" in err
    scen.write_text(SCENARIO.format(area=AREA, mounting="auv", extra="altitude_m = 5.0"))  # at the limit: fine
    assert main(["validate", str(scen)]) == 0
