"""The mission a fix plan makes (audit of issue 52's fixes): a surfacing keeps out of no-go zones and
obstacles, never lifts the start or the goal, and a vertical leg of the route survives it.

Oracles, independent of the fix planner: the World's exact segment test (``segments_free``, the test
every planner's path passes) on the mission's legs; the closed form of the error model with no bottom
lock (``2 σ = 2 √(σ_fix² + (rate · s)²)``: the last point a fix can be put at); the envelope
``max(z_route(s), −tanθ |s − s_f|)`` evaluated at the route's vertices.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from auvplan.nav import NavParams, check_navigation, plan_navigation
from auvplan.nav.fixes import PITCH_SHARE
from auvplan.nav.surfacing import CLIMB_SLACK_DEG
from auvplan.world import Bounds, Margins, Sphere, World, Zone, Zones

NAV = NavParams(drift_pct=0.3, drift_pct_no_lock=1.0, max_error_m=200.0, confidence=2.0, fix_error_m=5.0)
REACH = math.sqrt((200.0 / 2) ** 2 - 5.0**2) / 0.01  # the distance after a fix at which 2σ reaches E (m)
TAN = math.tan(math.radians(min(PITCH_SHARE * 20.0, 20.0 - CLIMB_SLACK_DEG)))  # the climbs' slope (19.95°)


def _world(**kw) -> World:
    return World(Bounds(-1000, 40000, -2000, 2000, -1000, 0), margins=Margins(0, 0, 1000), **kw)


def _legs(points: np.ndarray) -> np.ndarray:
    return np.stack([points[:-1], points[1:]], axis=1)


@pytest.mark.parametrize("blocker", ["zone", "sphere"])
def test_a_surfacing_keeps_out_of_a_no_go_zone_and_an_obstacle(blocker):
    """A 12 km route at 500 m needs one fix, anywhere in [12 km − REACH, REACH]; a firing range (0–100 m) or a
    buoy's sphere at the surface over the first candidates: the fix goes past it, the mission passes the
    World's exact segment test and the budget (before: the fix surfaced inside the zone and the plan said
    ok; under the sphere the plan failed its own check, though a fix further on keeps everything)."""
    route = np.array([[0.0, 0.0, -500.0], [12000.0, 0.0, -500.0]])
    if blocker == "zone":
        world = _world(zones=Zones((Zone("firing range", shapely.box(1500, -1000, 3000, 1000), 0.0, 100.0),)))
    else:
        world = _world(obstacles=[Sphere((2500.0, 0.0, 0.0), 300.0)])
    p = plan_navigation(world, route, NAV, 20.0, 1.5, compare=False)
    assert p.ok, p.message
    assert world.segments_free(_legs(p.points), moving=False).all()
    assert p.kinds.count("gps") == 1
    s_fix = float(p.points[p.kinds.index("gps"), 0])
    assert 12000.0 - REACH <= s_fix <= REACH
    assert check_navigation(world, p.points, p.kinds, NAV).ok


def test_no_fix_lifts_the_start_or_the_goal():
    """A 10.1 km route at 500 m: one fix, and a surfacing at the first candidate (250 m) would be the cheapest
    (its climb cut short by the start).  The mission must still start and end where the route does, so the
    fix is at least 500 / tanθ from either end (before: the start was lifted to 91 m)."""
    route = np.array([[0.0, 0.0, -500.0], [10100.0, 0.0, -500.0]])
    p = plan_navigation(_world(), route, NAV, 20.0, 1.5, compare=False)
    assert p.ok, p.message
    np.testing.assert_array_equal(p.points[[0, -1]], route)
    s_fix = p.points[[k == "gps" for k in p.kinds], 0]
    assert s_fix.size == 1 and 500.0 / TAN <= s_fix[0] <= 10100.0 - 500.0 / TAN
    pitch = np.abs(np.diff(p.points[:, 2])) / np.hypot(*np.diff(p.points[:, :2], axis=0).T)
    assert pitch.max() <= math.tan(math.radians(20.0))


def test_periodic_fixes_skip_a_surfacing_that_would_lift_the_goal():
    """``fixes = 600`` s at 1.5 m/s on a 9.1 km route: the timer fires every 900 m; where a climb to the surface
    from 500 m (500 / tanθ = 1.38 km) does not fit after the start or a dive before the goal, the fix is skipped,
    so the mission still starts and ends where the route does (before: the fixes 900 m after the start and
    100 m before the goal lifted them)."""
    route = np.array([[0.0, 0.0, -500.0], [9100.0, 0.0, -500.0]])
    nav = NavParams(drift_pct=0.3, drift_pct_no_lock=1.0, max_error_m=200.0, confidence=2.0, fix_error_m=5.0,
                    fixes=600.0)
    p = plan_navigation(_world(), route, nav, 20.0, 1.5)
    np.testing.assert_array_equal(p.points[[0, -1]], route)
    s_fix = p.points[[k == "gps" for k in p.kinds], 0]
    timer = np.arange(900.0, 9100.0, 900.0)
    np.testing.assert_allclose(s_fix, timer[(timer >= 500.0 / TAN) & (9100.0 - timer >= 500.0 / TAN)], atol=1e-6)


def test_vertical_legs_survive_the_fixes():
    """A route that dives vertically at the start, steps down vertically mid-way and climbs vertically to the
    goal: every vertex is in the mission at its envelope depth ``max(z, −tanθ |s − s_f|)`` over its own
    (x, y), the start and the goal unchanged (before: the first vertical dive was lost and the mission
    began at 273 m instead of 10 m); every other leg within the pitch limit; the error within E."""
    route = np.array([[0, 0, -10.0], [0, 0, -500], [20000, 0, -500], [20000, 0, -800], [30000, 0, -800],
                      [30000, 0, -20]])
    p = plan_navigation(_world(), route, NAV, 20.0, 1.5, compare=False)
    assert p.ok, p.message
    np.testing.assert_array_equal(p.points[[0, -1]], route[[0, -1]])
    fixes = p.points[[k == "gps" for k in p.kinds], 0]
    assert fixes.size == 3 and fixes[0] <= REACH
    for v in route:  # the envelope at the vertex (its x is its horizontal distance s)
        z = max(v[2], *(-TAN * abs(v[0] - f) for f in fixes))
        assert np.any(np.all(np.abs(p.points - [v[0], v[1], z]) <= 1e-6, axis=1)), (v, z)
    h = np.hypot(*np.diff(p.points[:, :2], axis=0).T)
    slope = np.abs(np.diff(p.points[:, 2]))[h > 0] / h[h > 0]
    assert slope.max() <= math.tan(math.radians(20.0))
    assert p.check.budget.max_error_m <= NAV.max_error_m


def test_an_obstacle_within_the_error_is_named_not_an_infinite_altitude():
    """A leg passing 40 m from a sphere with 70 m of error and no seabed: the check fails naming the obstacle
    (before: "the seabed or an obstacle comes within inf m")."""
    world = _world(obstacles=[Sphere((3000.0, 340.0, -500.0), 300.0)])
    route = np.array([[0.0, 0.0, -500.0], [6000.0, 0.0, -500.0]])
    c = check_navigation(world, route, ("", ""), NAV)
    assert world.segments_free(_legs(route), moving=False).all()
    assert not c.ok and "static obstacle" in c.message and "inf" not in c.message, c.message


def test_a_mission_that_goes_nowhere_needs_no_fix_and_an_impossible_budget_is_a_status():
    """Start = goal: nothing travelled, the launch fix's 2 × 5 m holds, no fix (before: "no choice of fixes",
    not ok).  A budget of 10.01 m at 2σ with 5 m fixes: the 250 m candidates already reach 11.2 m, so no plan
    exists: ok False with the reason naming max_error_m, no exception."""
    here = np.array([[0.0, 0.0, -500.0], [0.0, 0.0, -500.0]])
    still = plan_navigation(_world(), here, NAV, 20.0, 1.5, compare=False)
    assert still.ok and "gps" not in still.kinds and still.check.budget.max_error_m == 2 * 5.0
    tight = NavParams(drift_pct_no_lock=1.0, max_error_m=10.01, confidence=2.0, fix_error_m=5.0)
    route = np.array([[0.0, 0.0, -500.0], [10000.0, 0.0, -500.0]])
    p = plan_navigation(_world(), route, tight, 20.0, 1.5, compare=False)
    assert not p.ok and "max_error_m = 10.01 m" in p.message


def test_a_probability_given_as_the_confidence_is_refused():
    """``[mission] confidence = 0.95`` is a probability; ``[navigation] confidence`` a multiple of σ: 0.95 there
    would budget 0.95 σ, 59 % of a circular error, not 95 % (before: accepted without a word).  Exit 2's error names
    the file, the key and the value."""
    from auvplan.errors import ScenarioError
    from auvplan.io.scenario import loader

    text = ('name = "t"\n[bounds]\nx = [0.0, 1000.0]\ny = [0.0, 1000.0]\nz = [-500.0, 0.0]\n[mission]\n'
            'start = [100.0, 100.0, -400.0]\ngoal = [900.0, 900.0, -400.0]\nmin_depth_m = 0.0\n[navigation]\n')
    assert loader.loads(text + "confidence = 1.0\n", "t.toml").navigation.confidence == 1.0
    with pytest.raises(ScenarioError, match=r"t\.toml: \[navigation\].*confidence.*0\.95.*not a probability"):
        loader.loads(text + "confidence = 0.95\n", "t.toml")
