"""A survey's export flown with depth held per leg (MOOS-IvP): every leg's envelope and the executor's track
clear the seabed by ``min_altitude`` (oracle: the exact held-depth check of ``auvplan mission check``,
:func:`~auvplan.io.missions.readback.readers.check_mission_file`, on the written ``mission.moos``).

The hard case is real: a side-scan survey with a tie line on the flank of the Mariana arc (shipped ETOPO1,
resampled to 500 m), whose main-to-tie-line turn and transit legs climb the slope.  Before survey22 the
route passed the 3D-line test only: its ``mission.moos`` had a least held altitude of -45.16 m (leg 161).
"""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.guidance.mission.flycheck import fly_check
from auvplan.io.missions.formats import to_moos
from auvplan.io.missions.readback.readers import check_mission_file
from auvplan.io.results.survey import survey_params
from auvplan.io.scenario.build import build
from auvplan.io.scenario.loader import loads
from auvplan.survey.held import held_failures, held_safe
from auvplan.survey.mission import TURN, plan_survey

SCENARIO = """
name = "arc-flank-sidescan"
seed = 1
[origin]
lat = 16.2
lon = 144.4
[bounds]
x = [137000.0, 143000.0]
y = [97000.0, 103000.0]
z = [-6000.0, 0.0]
[terrain]
builtin = "etopo1-mariana"
resample_m = 500.0
[mission]
start = [138800.0, 98800.0, {z}]
goal = [138800.0, 98800.0, {z}]
min_altitude_m = 20.0
[vehicle]
speed = 1.5
[planner]
name = "grid"
[survey]
polygon_xy = [[139000.0, 99000.0], [140000.0, 99000.0], [140000.0, 100000.0], [139000.0, 100000.0]]
sensor = "sidescan"
range_m = 150.0
mounting = "auv"
altitude_m = 30.0
overlap = [0.10, 0.20]
tie_lines = 1
"""


@pytest.fixture(scope="module")
def flank_survey():
    """(world, plan) of the survey, the launch 40 m above the seabed."""
    world, _ = build(loads(SCENARIO.format(z=-2000.0), source="flank.toml"))
    zb = float(world.seabed(np.array([138800.0]), np.array([98800.0]))[0])
    sc = loads(SCENARIO.format(z=zb + 40.0), source="flank.toml")
    world, mission = build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, None, "flank.toml: [survey]")
    return world, plan_survey(world, mission, params, sc.seed)


def test_survey_mission_moos_passes_the_held_depth_check(flank_survey, tmp_path):
    world, plan = flank_survey
    assert plan.status.ok, plan.message
    path = tmp_path / "mission.moos"
    path.write_text(to_moos(plan.route, 1.5), encoding="utf-8")
    for pitch in (15.0, 20.0):
        check, fmt = check_mission_file(path, world, pitch)
        assert fmt == "moos" and check.semantics == "held"
        assert check.ok, check.as_dict()
        assert check.min_altitude_m >= world.margins.min_altitude - 1e-3  # the envelope of every leg
        assert check.executor_min_altitude_m >= world.margins.min_altitude  # the vehicle's own track
    ramp = fly_check(world, plan.route, "ramp")  # and still along the straight 3D legs
    assert ramp.ok and ramp.min_altitude_m >= world.margins.min_altitude - 1e-6


def test_the_fix_only_adds_points_on_the_legs(flank_survey):
    """Every inserted point lies on the 3D line of its neighbours (the route flown is the same line), and a
    survey line keeps its label; the legs that needed it are long, climbing joins or line legs."""
    world, plan = flank_survey
    r = plan.route
    a, b, c = r[:-2], r[1:-1], r[2:]
    u = np.cross(b - a, c - a)
    on_line = np.linalg.norm(u, axis=1) <= 1e-6 * np.linalg.norm(b - a, axis=1) * np.linalg.norm(c - a, axis=1) + 1e-9
    assert on_line.sum() >= 20  # the split points (collinear with both neighbours)
    lab = plan.labels
    la, lm, lb = lab[:-2][on_line], lab[1:-1][on_line], lab[2:][on_line]
    assert np.all((la != lb) <= (lm < 0))  # a point between a line and a join is not on the line
    assert np.all((lm >= 0) <= (la == lm) | (lb == lm))  # a point on a line is among that line's points
    assert not held_failures(world, r)[0].any()


def test_a_leg_that_cannot_be_fixed_is_named(flank_survey):
    """A leg whose own 3D line is below min_altitude cannot be made safe by splitting: the survey says which."""
    world, _ = flank_survey
    x = np.array([139200.0, 139800.0])
    y = np.array([99500.0, 99500.0])
    zb = world.seabed(x, y)
    route = np.column_stack([x, y, zb + 5.0])  # 5 m above the seabed where 20 m are required
    out, lab, message = held_safe(world, route, np.array([TURN, TURN]), 15.0, 2.5, {TURN: "a turn"})
    assert message.startswith("leg ") and "(a turn," in message and "held-depth" in message
    assert (lab == TURN).all() and out.shape[0] > 2  # split down to the shortest leg, then said
    _, lab, message = held_safe(world, route, np.array([3, TURN]), 15.0, 2.5)  # from line 3 into a turn
    assert lab[0] == 3 and (lab[1:] == TURN).all() and "held-depth" in message  # the join's points are the turn's
    assert np.linalg.norm(np.diff(out, axis=0), axis=1).min() >= 2.5
