"""Issue #31: one oracle per way of passing an unsafe mission that the suite once let through.

Each test names the planted bug it kills (the mutation found by hand); the expected values are
computed by hand in the docstrings.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from test_mission import _RIDGE_TOML

from auvplan.cost import CostModel, evaluate_paths
from auvplan.guidance.formation.keeping import FormationParams
from auvplan.guidance.mission.envelopes import envelope_hits, envelopes_free, leg_floors
from auvplan.guidance.mission.flycheck import MissionCheck, fly_check, held_track
from auvplan.guidance.mission.limits import waypoint_limits
from auvplan.planners.grid.lattice import edge_states, node_fields
from auvplan.sim.formation import _contact
from auvplan.world import Bounds, Ellipsoid, LinearMotion, Margins, MovingObstacle, Sphere, Terrain, World


def _step_world() -> World:
    """A flat seabed 100 m deep rising to 60 m deep at x = 100 m (a 40 m step over one 5 m cell)."""
    x = np.arange(0.0, 301.0, 5.0)
    y = np.array([-50.0, 50.0])
    z = np.where(x[None, :] >= 100.0, -60.0, -100.0) * np.ones((2, 1))
    return World(Bounds(0, 300, -50, 50, -150, 0), Terrain(x, y, z), margins=Margins(min_altitude=5.0))


def test_a_held_depth_mission_whose_executor_hits_a_step_fails_although_its_envelopes_clear_it():
    """Planted bug: ``MissionCheck.ok`` reads only the envelope altitude.  A 50 m climb over 10 m
    (0, -90) -> (10, -40), then level at -40 m over the step: the envelopes keep 10 m (leg 0 at
    its deeper end over the 100 m seabed) and 20 m (leg 1 over the 60 m step); a MOOS vehicle
    climbing at 15° reaches x = 100 m at -90 + 100 tan 15° = -63.20 m, 3.20 m under the step."""
    world = _step_world()
    w = np.array([[0.0, 0.0, -90.0], [10.0, 0.0, -40.0], [300.0, 0.0, -40.0]])
    check = fly_check(world, w, "held", 15.0)
    assert check.min_altitude_m == pytest.approx(10.0, abs=1e-9)
    assert check.executor_min_altitude_m == pytest.approx(-90.0 + 100.0 * math.tan(math.radians(15.0)) + 60.0,
                                                          abs=1e-6)
    assert check.executor_min_altitude_m == pytest.approx(-3.205, abs=1e-3)
    assert not check.ok and not check.as_dict()["ok"]
    assert fly_check(world, w, "held", 90.0).ok  # a vehicle that climbs vertically clears the step
    # the rule itself: either altitude below the requirement fails
    base = dict(semantics="held", min_altitude_leg=0, min_obstacle_distance_m=np.inf, obstacle_hits=0,
                leg_altitude_m=np.array([10.0]), required_altitude_m=5.0, obstacle_margin_m=0.0)
    assert MissionCheck(min_altitude_m=10.0, executor_min_altitude_m=6.0, **base).ok
    assert not MissionCheck(min_altitude_m=10.0, executor_min_altitude_m=4.0, **base).ok
    assert not MissionCheck(min_altitude_m=4.0, executor_min_altitude_m=10.0, **base).ok


def test_a_leg_two_metres_from_a_long_ellipsoid_meets_its_five_metre_margin():
    """Planted bug: the envelope inflates an ellipsoid by ``margin / max(semi_axes)``.  Semi-axes
    (20, 2, 2) and a 5 m margin: a leg along x at y = 4 m (2 m from the surface) is within the
    margin.  Inflating by 1 + 5/2 (the least axis, conservative) covers it; by 1 + 5/20 the body is
    only 2.5 m wide and the leg passes.  A leg at y = 8 m (6 m off) is clear either way."""
    ell = Ellipsoid((0.0, 0.0, -50.0), (20.0, 2.0, 2.0))
    a, b = np.array([[-30.0, 4.0, -50.0]]), np.array([[30.0, 4.0, -50.0]])
    assert envelope_hits(ell, a, b, 5.0)[0]
    assert not envelope_hits(ell, a + [0.0, 4.0, 0.0], b + [0.0, 4.0, 0.0], 5.0)[0]
    world = World(Bounds(-100, 100, -100, 100, -100, 0), obstacles=(ell,), margins=Margins(obstacle=5.0))
    w = np.vstack([a, b])
    for semantics in ("held", "ramp"):
        check = fly_check(world, w, semantics)
        assert check.obstacle_hits == 1 and not check.ok, semantics
        assert check.min_obstacle_distance_m == pytest.approx(2.0, abs=0.05)


def test_a_ramp_leg_inside_the_obstacle_margin_fails():
    """Planted bug: the ramp formats' check tests obstacles with margin 0.  A leg 3 m from the
    surface of a 10 m sphere, the obstacle margin 5 m: one hit under both semantics; with a 2 m
    margin none."""
    sphere = Sphere((0.0, 0.0, -50.0), 10.0)
    w = np.array([[-40.0, 13.0, -50.0], [40.0, 13.0, -50.0]])
    level = np.array([[-40.0, 15.0, -50.0], [40.0, 15.0, -50.0]])  # exactly the margin away: not within it
    assert not envelope_hits(sphere, level[0], level[1], 5.0)[0] and envelope_hits(sphere, level[0], level[1], 5.01)[0]
    for margin, hits in ((5.0, 1), (2.0, 0)):
        world = World(Bounds(-100, 100, -100, 100, -100, 0), obstacles=(sphere,), margins=Margins(obstacle=margin))
        for semantics in ("ramp", "held"):
            check = fly_check(world, w, semantics)
            assert check.obstacle_hits == hits and check.ok == (hits == 0), (margin, semantics)
            assert check.min_obstacle_distance_m == pytest.approx(3.0, abs=1e-9)


def test_a_path_below_the_floor_of_the_bounds_is_charged_by_the_amount():
    """Planted bug: the cost's point slack drops ``z - zmin`` (the floor of the bounds).  Bounds
    z in [-100, 0] and no depth limit (max_depth = inf): a leg ending 7 m below the floor is one
    violation charged 1e4 + 100 x 7 m; the same leg ending 3 m above the floor costs nothing."""
    world = World(Bounds(0, 1000, 0, 1000, -100, 0))
    paths = np.array([[[500.0, 500.0, -50.0], [500.0, 500.0, -107.0]],
                      [[500.0, 500.0, -50.0], [500.0, 500.0, -97.0]]])
    terms = evaluate_paths(world, paths, CostModel())
    np.testing.assert_array_equal(terms.violations, [1, 0])
    np.testing.assert_allclose(terms.terrain, [1e4 + 700.0, 0.0])


def test_the_lattice_never_clears_a_climbing_edge_past_a_sphere_at_its_midpoint():
    """Planted bug: the lattice's 'sure free' shortcut compares the nodes' obstacle slack with half
    the horizontal length of an edge instead of half its 3D length.  10 m cells, the edge
    (0, 0, -60) -> (10, 0, -50) (offset (1, 0, 1)), a 0.5 m sphere at its midpoint: both nodes are
    sqrt(50) - 0.5 = 6.57 m from it, more than the horizontal half-length 5 m but less than the
    3D half-length 7.07 m, so only the exact test can decide, and it finds the sphere."""
    world = World(Bounds(-20, 30, -20, 20, -100, 0), obstacles=(Sphere((5.0, 0.0, -55.0), 0.5),))
    axes = (np.array([0.0, 10.0]), np.array([0.0]), np.array([-60.0, -50.0]))
    free, alt, obs, _ = node_fields(world, axes, currents=False)
    assert free.all()
    np.testing.assert_allclose(obs[0, 0, 0], math.sqrt(50.0) - 0.5, atol=1e-4)
    xyz = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    steps = np.array([10.0, 1.0, 10.0])
    climb = edge_states(world, free, alt, obs, steps, (1, 0, 1), xyz.__getitem__).reshape(free.shape)
    assert climb[0, 0, 0] == 0  # (0, 0, -60) -> (10, 0, -50) passes through the sphere
    level = edge_states(world, free, alt, obs, steps, (1, 0, 0), xyz.__getitem__).reshape(free.shape)
    assert level[0, 0, 0] == 1 and level[0, 0, 1] == 1  # the level edges pass 5 m above / below it


def test_segments_free_places_the_moving_obstacles_at_the_given_time():
    """Planted bug: ``World.segments_free`` freezes the moving obstacles at t = 0.  A 5 m sphere
    starting at x = -200 m and moving east at 2 m/s sits on the segment x in [-20, 20] (at the
    origin) at t = 100 s: blocked then, free at t = 0 and at t = 200 s (x = 200 m); moving=False
    ignores it; one that appears at t = 150 s does not block at t = 100 s."""
    seg = np.array([[[-20.0, 0.0, -50.0], [20.0, 0.0, -50.0]]])
    mover = MovingObstacle(Sphere((0.0, 0.0, 0.0), 5.0), LinearMotion((-200.0, 0.0, -50.0), (2.0, 0.0, 0.0)))
    world = World(Bounds(-500, 500, -500, 500, -100, 0), moving=(mover,))
    assert world.segments_free(seg, 0.0)[0]
    assert not world.segments_free(seg, 100.0)[0]
    assert not world.segments_free(seg, t=100.0, moving=True)[0]
    assert world.segments_free(seg, 200.0)[0]
    assert world.segments_free(seg, 100.0, moving=False)[0]
    assert not world.path_free(seg[0], 100.0, moving=True) and world.path_free(seg[0], 100.0)
    late = World(world.bounds, moving=(MovingObstacle(mover.shape, mover.motion, appears=150.0),))
    assert late.segments_free(seg, 100.0)[0]


def test_two_hulls_closer_than_contact_m_are_a_contact():
    """Planted bug: the formation loop's contact rule tests the centres' distance against 0 instead
    of ``contact_m``.  contact_m = 2 m: centres 1.16 m or 1.99 m apart are a contact, 2.0 m is not;
    the seabed (altitude < 0) and an obstacle (signed distance < 0) come first."""
    fp = FormationParams(contact_m=2.0)
    names = ("lead", "f1", "f2")
    assert _contact(0, [], 10.0, {1: 1.16}, names, fp) == "vehicle f1 (centres 1.16 m apart)"
    assert _contact(0, [], 10.0, {1: 5.0, 2: 1.99}, names, fp) == "vehicle f2 (centres 1.99 m apart)"
    assert _contact(0, [3.0], 10.0, {1: 2.0, 2: 30.0}, names, fp) == ""
    assert _contact(0, [3.0, -0.1], 10.0, {1: 1.0}, names, fp) == "obstacle 1"
    assert _contact(0, [3.0], -0.1, {1: 1.0}, names, fp) == "the seabed"
    # contact is penetration, as in the single-vehicle loop: touching (0 m) or 0.5 m away is not
    assert _contact(0, [0.0, 0.5], 0.0, {}, names, fp) == "" and _contact(0, [0.5], 0.5, {}, names, fp) == ""


def test_held_track_reaches_every_held_depth_at_the_pitch():
    """The executor model used by the held check: from -90 m towards -40 m at 15° over a 10 m leg
    it climbs 10 tan 15° = 2.68 m, and carries the change on into the next leg, ending it
    50 / tan 15° = 186.6 m from the start (a corner there), then holds -40 m."""
    trk = held_track([[0.0, 0.0, -90.0], [10.0, 0.0, -40.0], [300.0, 0.0, -40.0]], 15.0)
    slope = math.tan(math.radians(15.0))
    np.testing.assert_allclose(trk, [[0.0, 0.0, -90.0], [10.0, 0.0, -90.0 + 10.0 * slope],
                                     [50.0 / slope, 0.0, -40.0], [300.0, 0.0, -40.0]], atol=1e-9)


# ---------------------------------------------------------------------- mission check: surface, depth band, bounds
# test_mission's ridge with a depth band whose floor (160 m) lies above the ridge's foot (200 m)
_SCENARIO = _RIDGE_TOML.replace('name = "ridge-check"', 'name = "ridge-band"').replace(
    "max_depth_m = 300.0", "max_depth_m = 160.0")
_HEADER = "x,y,z,lat,lon,depth,time\n"


def _csv(path, rows):
    path.write_text(_HEADER + "".join(f"{x},{y},{z},,,{-z},0\n" for x, y, z in rows))
    return str(path)


@pytest.fixture()
def scenario_file(tmp_path):
    """The ridge scenario (seabed 200 m deep, crest 50 m deep at x = 5 km) with the band 5-160 m."""
    (tmp_path / "s.toml").write_text(_SCENARIO)
    return str(tmp_path / "s.toml")


def test_mission_check_fails_a_mission_that_leaves_the_water(tmp_path, scenario_file, capsys):
    """A CSV waypoint 500 m above the surface over the 200 m deep seabed (x = 1 km): the old check
    said OK (its least altitude, 50 m at the start, is fine); now FAIL naming the waypoint."""
    from auvplan.cli import main

    f = _csv(tmp_path / "up.csv", [(500.0, 1000.0, -150.0), (1000.0, 1000.0, 500.0), (2000.0, 1000.0, -150.0)])
    assert main(["mission", "check", f, "--scenario", scenario_file]) == 1
    out = capsys.readouterr().out
    assert out.startswith(f"{f} (csv, depth ramp): FAIL — 1 waypoint above the sea surface (waypoint 1 is 500.00 m "
                          "above it); least altitude 50.00 m")
    assert "depth band" not in out and "bounds" not in out  # named once, for what it breaks
    assert main(["mission", "check", f, "--scenario", scenario_file, "--json"]) == 1
    rec = json.loads(capsys.readouterr().out)
    assert not rec["ok"] and rec["limits"]["above_surface"] == [1] and rec["limits"]["shallowest_m"] == -500.0


def test_mission_check_fails_a_leg_deeper_than_max_depth_or_shallower_than_min_depth(tmp_path, scenario_file, capsys):
    """max_depth_m = 160: a waypoint at 175 m (25 m above the 200 m seabed, so the altitude is
    fine) fails; min_depth_m = 5: one at 2 m fails; 5 m and 160 m exactly pass."""
    from auvplan.cli import main

    deep = _csv(tmp_path / "deep.csv", [(500.0, 1000.0, -150.0), (1000.0, 1000.0, -175.0), (2000.0, 1000.0, -150.0)])
    assert main(["mission", "check", deep, "--scenario", scenario_file]) == 1
    out = capsys.readouterr().out
    assert ("FAIL — 1 waypoint outside the depth band (waypoint 1 at depth 175.00 m, deeper than max_depth_m = 160); "
            "least altitude 25.00 m") in out
    shallow = _csv(tmp_path / "shallow.csv", [(500.0, 1000.0, -150.0), (1000.0, 1000.0, -2.0)])
    assert main(["mission", "check", shallow, "--scenario", scenario_file]) == 1
    assert "(waypoint 1 at depth 2.00 m, shallower than min_depth_m = 5)" in capsys.readouterr().out
    edges = _csv(tmp_path / "edges.csv", [(500.0, 1000.0, -160.0), (1000.0, 1000.0, -5.0)])
    assert main(["mission", "check", edges, "--scenario", scenario_file]) == 0
    assert ": OK — least altitude" in capsys.readouterr().out


def test_mission_check_names_a_waypoint_outside_the_bounds(tmp_path, scenario_file, capsys):
    """x = 12 km is 2 km east of the bounds: named as outside the bounds (the leg also crosses the
    crest 100 m below its depth, reported as the altitude it is)."""
    from auvplan.cli import main

    f = _csv(tmp_path / "east.csv", [(500.0, 1000.0, -150.0), (12000.0, 1000.0, -150.0)])
    assert main(["mission", "check", f, "--scenario", scenario_file]) == 1
    assert ("FAIL — 1 waypoint outside the scenario bounds (waypoint 1: x = 12000.00 not in [0, 10000]); "
            "least altitude -100.00 m") in capsys.readouterr().out


def test_mission_check_refuses_too_few_waypoints_and_a_bad_pitch(tmp_path, scenario_file, capsys):
    """One waypoint (CSV) or a .plan with no item (its home only): exit 2, one line naming the
    file.  --pitch must be a finite angle in (0, 90]."""
    from auvplan.cli import main

    one = _csv(tmp_path / "one.csv", [(500.0, 1000.0, -150.0)])
    assert main(["mission", "check", one, "--scenario", scenario_file]) == 2
    err = capsys.readouterr().err
    assert err == f"auvplan: error: {one}: the mission has 1 waypoint; at least 2 are needed (a start and a goal)\n"
    plan = tmp_path / "empty.plan"
    plan.write_text(json.dumps({"mission": {"plannedHomePosition": [48.0, -125.0, 0], "items": []}}))
    assert main(["mission", "check", str(plan), "--scenario", scenario_file]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "empty.plan: the mission has 1 waypoint" in err
    ok = _csv(tmp_path / "ok.csv", [(500.0, 1000.0, -150.0), (1000.0, 1000.0, -150.0)])
    for bad in ("nan", "inf", "0", "-5", "90.5", "steep"):
        assert main(["mission", "check", ok, "--scenario", scenario_file, "--pitch", bad]) == 2, bad
        assert "--pitch" in capsys.readouterr().err
    assert main(["mission", "check", ok, "--scenario", scenario_file, "--pitch", "90"]) == 0
    world = World(Bounds(0, 10, 0, 10, -10, 0))
    with pytest.raises(ValueError, match="at least 2 waypoints"):
        fly_check(world, [[1.0, 1.0, -1.0]])
    with pytest.raises(ValueError, match="pitch_deg"):
        fly_check(world, [[1.0, 1.0, -1.0], [2.0, 1.0, -1.0]], pitch_deg=0.0)


def test_the_depth_band_under_each_format_and_the_launch_point_of_a_plan(tmp_path, scenario_file):
    """MOOS (held) and QGC (ramp from a surface home): a mission within the band passes in both,
    the .plan's home at the surface being the launch point; a waypoint 2 m deep fails in both."""
    from auvplan.io.missions import formats
    from auvplan.io.scenario import loader as sc

    world, _ = sc.build(sc.loads(_SCENARIO, "s.toml"))
    good = np.array([[500.0, 1000.0, -150.0], [1500.0, 1000.0, -100.0], [2500.0, 1000.0, -150.0]])
    bad = good.copy()
    bad[1, 2] = -2.0
    for w, ok in ((good, True), (bad, False)):
        (tmp_path / "m.moos").write_text(formats.to_moos(w, 1.5))
        (tmp_path / "m.plan").write_text(json.dumps(formats.to_qgc_plan(w, (48.0, -125.0), 1.5)))
        for name, first in (("m.moos", 0), ("m.plan", 1)):  # the plan's waypoint 0 is its home
            check, _ = formats.check_mission_file(tmp_path / name, world)
            assert check.ok == ok and check.limits is not None, name
            assert check.limits.outside_depth_band == (() if ok else (first + 1,)), name
            assert check.limits.launch == (name == "m.plan")
    limits = waypoint_limits(world, [[600.0, 1000.0, 0.0], [600.0, 1000.0, -150.0]], launch=True)
    assert limits.ok and limits.depth_range() == (150.0, 150.0)
    assert waypoint_limits(world, [[600.0, 1000.0, 0.0], [600.0, 1000.0, -150.0]]).outside_depth_band == (0,)
    # fix20: a home 100 m from above the first item is no launch point (ArduSub dives the straight leg from it)
    offset = waypoint_limits(world, [[500.0, 1000.0, 0.0], [600.0, 1000.0, -150.0]], launch=True)
    assert offset.outside_depth_band == (0,) and not offset.launch and offset.launch_run_m == 100.0
    launched = waypoint_limits(world, [[600.0, 1000.0, 0.0], [600.0, 1000.0, -2.0], [700.0, 1000.0, -150.0]], True)
    assert launched.outside_depth_band == (1,) and launched.depth_range() == (2.0, 150.0)


def test_a_held_executor_never_leaves_the_range_of_the_waypoint_depths():
    """The reason the depth band is checked at the waypoints under the held semantics: 200 random
    missions, pitches 1-90°: every corner of the executor's track lies between the shallowest and
    the deepest waypoint."""
    rng = np.random.default_rng(31)
    for _ in range(200):
        n = int(rng.integers(2, 8))
        w = np.column_stack([np.cumsum(rng.uniform(1, 300, n)), np.zeros(n), rng.uniform(-200, -5, n)])
        trk = held_track(w, float(rng.uniform(1.0, 90.0)))
        assert trk[:, 2].min() >= w[:, 2].min() - 1e-9 and trk[:, 2].max() <= w[:, 2].max() + 1e-9


def test_leg_floors_is_the_highest_seabed_under_a_leg_plus_min_altitude():
    """Over the 40 m step (5 m cells, min_altitude 5 m): a leg wholly before the step has floor
    -100 + 5 = -95 m, one reaching x = 97.5 m (half way up the cell's ramp) -80 + 5 = -75 m, one
    over the step -60 + 5 = -55 m, whatever the legs' depths; without a seabed the floor is -inf."""
    world = _step_world()
    a = np.array([[0.0, 0.0, -90.0], [0.0, 10.0, -10.0], [50.0, -20.0, -30.0]])
    b = np.array([[90.0, 0.0, -20.0], [97.5, 10.0, -99.0], [250.0, 20.0, -30.0]])
    np.testing.assert_allclose(leg_floors(world, a, b), [-95.0, -75.0, -55.0], atol=1e-9)
    np.testing.assert_allclose(leg_floors(world, a[0], b[0]), [-95.0], atol=1e-9)
    open_water = World(world.bounds)
    floors = leg_floors(open_water, a[:2], b[:2])
    assert floors.shape == (2,) and np.all(floors == -np.inf)


def test_parallelogram_distance_by_hand():
    """Distance from the origin to o + s e1 + t e2 (s, t in [0, 1]), by hand: a square 5 m below whose
    plane the origin projects into (5 m); a sheared one (e1 . e2 = 2, as an ellipsoid's body frame makes
    of an envelope) with the foot inside (5 m) and outside, near its corner (1, 1, 5) from o + e2 + ...;
    a 1 mm square (the plane, 5 m exactly, not the edges' 5.000000025 m); a vertical segment (e1 = 0);
    a point."""
    from auvplan.guidance.mission.envelopes import _parallelogram_distance

    o = np.array([[-1.0, -1.0, 5.0], [-1.5, -1.0, 5.0], [1.0, 1.0, 5.0], [-5e-4, -5e-4, 5.0], [3.0, 4.0, -1.0],
                  [3.0, 4.0, 0.0]])
    e1 = np.array([[2.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1e-3, 0.0, 0.0], [0.0, 0.0, 0.0],
                   [0.0, 0.0, 0.0]])
    e2 = np.array([[0.0, 2.0, 0.0], [1.0, 2.0, 0.0], [1.0, 2.0, 0.0], [0.0, 1e-3, 0.0], [0.0, 0.0, 2.0],
                   [0.0, 0.0, 0.0]])
    want = [5.0, 5.0, math.sqrt(1.0 + 1.0 + 25.0), 5.0, 5.0, 5.0]
    np.testing.assert_allclose(_parallelogram_distance(o, e1, e2), want, rtol=0, atol=1e-12)
    # the foot of the perpendicular past the far edges (s or t = 1.5): the nearest points are on those edges
    o2 = np.array([[-1.0, -1.5, 5.0], [-1.5, -1.0, 5.0]])
    e1b, e2b = np.array([[2.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0], [0.0, 2.0, 0.0]])
    np.testing.assert_allclose(_parallelogram_distance(o2, e1b, e2b), [math.sqrt(25.25)] * 2, rtol=0, atol=1e-12)
    # against dense sampling on random sheared parallelograms
    rng = np.random.default_rng(7)
    o, e1, e2 = (rng.uniform(-3, 3, (40, 3)) for _ in range(3))
    s, t = np.meshgrid(np.linspace(0, 1, 201), np.linspace(0, 1, 201))
    pts = o[:, None] + s.reshape(1, -1, 1) * e1[:, None] + t.reshape(1, -1, 1) * e2[:, None]
    sampled = np.linalg.norm(pts, axis=-1).min(axis=1)
    got = _parallelogram_distance(o, e1, e2)
    assert np.all(got <= sampled + 1e-12) and np.all(sampled - got < 0.05)


def test_parallelogram_distance_at_exactly_the_degeneracy_threshold_is_the_edges():
    """The guard ``det > 1e-12 max(a11 a22, 1e-300)`` is strict: a parallelogram whose determinant equals
    the threshold exactly counts as degenerate and its distance is the edges'.  The one exact case: a
    square of side L = 1e-78 (orthogonal edges, det = a11 a22 = L^4 = 1e-312, below 1e-300, so the
    threshold is 1e-12 * 1e-300 = 1e-312, equal in floating point), the origin at its centre in its
    plane: the edges are L / 2 away (the plane's distance would be 0).  A square of side 2 m (det = 16, far
    above the threshold) with the same origin: the plane, 0."""
    from auvplan.guidance.mission.envelopes import _parallelogram_distance

    side = 1e-78
    assert side**4 == 1e-12 * 1e-300  # the boundary itself, exact in floating point
    o = np.array([[-side / 2, -side / 2, 0.0], [-1.0, -1.0, 0.0]])
    e1 = np.array([[side, 0.0, 0.0], [2.0, 0.0, 0.0]])
    e2 = np.array([[0.0, side, 0.0], [0.0, 2.0, 0.0]])
    got = _parallelogram_distance(o, e1, e2)
    assert got[0] == pytest.approx(side / 2, rel=1e-12, abs=0.0)
    assert got[1] == 0.0


def test_envelopes_free_at_the_depth_band_the_bounds_and_the_floor_exactly():
    """Band 5-100 m, bounds x, y in [0, 300], flat seabed 150 m deep with min_altitude 5 (floor -145 m,
    deeper than the band, so the band decides) and over the step world (floor exactly -95 m then -55 m):
    each leg's envelope is free exactly when both ends keep every limit, the limits themselves included."""
    x = np.arange(0.0, 301.0, 5.0)
    flat = World(Bounds(0, 300, -50, 50, -200, 0), Terrain(x, np.array([-50.0, 50.0]), np.full((2, x.size), -150.0)),
                 margins=Margins(min_altitude=5.0, min_depth=5.0, max_depth=100.0))
    a = np.array([[10.0, 0.0, -5.0], [10.0, 0.0, -50.0], [10.0, 0.0, -50.0], [10.0, 0.0, -4.9], [10.0, 0.0, -50.0],
                  [10.0, 0.0, -50.0], [10.0, 0.0, -50.0]])
    b = np.array([[90.0, 0.0, -100.0], [90.0, 0.0, -100.1], [90.0, 0.0, -4.0], [90.0, 0.0, -50.0],
                  [310.0, 0.0, -50.0], [90.0, 60.0, -50.0], [90.0, -20.0, -60.0]])
    np.testing.assert_array_equal(envelopes_free(flat, a, b), [True, False, False, False, False, False, True])
    step = _step_world()
    a = np.array([[0.0, 0.0, -95.0], [0.0, 0.0, -95.001], [120.0, 0.0, -55.0], [120.0, 0.0, -20.0]])
    b = np.array([[90.0, 0.0, -40.0], [90.0, 0.0, -40.0], [250.0, 0.0, -10.0], [250.0, 0.0, -55.001]])
    np.testing.assert_array_equal(envelopes_free(step, a, b), [True, False, True, False])
    # MissionCheck.ok at exactly the required altitude
    base = dict(semantics="ramp", min_altitude_leg=0, min_obstacle_distance_m=np.inf, obstacle_hits=0,
                leg_altitude_m=np.array([5.0]), required_altitude_m=5.0, obstacle_margin_m=0.0)
    assert MissionCheck(min_altitude_m=5.0, **base).ok and MissionCheck(min_altitude_m=5.0 - 1e-6, **base).ok
    assert not MissionCheck(min_altitude_m=5.0 - 2e-6, **base).ok
    assert not MissionCheck(min_altitude_m=9.0, executor_obstacle_hits=1, **base).ok
    assert not MissionCheck(**{**base, "obstacle_hits": 1}, min_altitude_m=9.0).ok


def test_held_track_at_the_steepest_pitch_and_on_short_legs():
    """90° is capped at 89.99° (slope tan 89.99° = 5729.58): a 57.2958 m climb ends 0.01 m into the
    leg.  A 0.2 m leg asking 0.1 m at 15° (needs 0.373 m) gets 0.2 tan 15° = 0.0536 m of it and the
    next leg the rest.  The library refuses a pitch outside (0, 90] and flies 0.5°."""
    slope = math.tan(math.radians(89.99))
    trk = held_track([[0.0, 0.0, -100.0], [100.0, 0.0, -100.0 + 57.2958], [200.0, 0.0, 0.0]], 90.0)
    assert trk[1, 0] == pytest.approx(57.2958 / slope, abs=1e-9) and trk[1, 0] == pytest.approx(0.01, abs=1e-6)
    short = held_track([[0.0, 0.0, -10.0], [0.2, 0.0, -9.9], [100.0, 0.0, -9.9]], 15.0)
    np.testing.assert_allclose(short[1], [0.2, 0.0, -10.0 + 0.2 * math.tan(math.radians(15.0))], atol=1e-12)
    world = World(Bounds(-10, 300, -10, 10, -200, 0))
    w = [[0.0, 0.0, -10.0], [200.0, 0.0, -11.0]]
    assert fly_check(world, w, "held", 0.5).pitch_deg == 0.5
    for bad in (0.0, -1.0, 90.5, float("nan")):
        with pytest.raises(ValueError, match="pitch_deg"):
            fly_check(world, w, "held", bad)


def test_sampled_ellipsoid_distance_is_the_exact_one_to_the_sampling():
    """An ellipsoid with equal semi-axes is a sphere, whose rectangle distance is exact: the 0.25 m
    sampled distance over random envelopes (a vertical leg, short and long legs) is never below it and
    at most 0.03 m above it (half the grid's diagonal squared over the radius, here far less)."""
    from auvplan.guidance.mission.envelopes import _sampled_rect_distance, _sphere_rect_distance, envelope_corners

    sphere, round_ellipsoid = Sphere((0.0, 0.0, -50.0), 6.0), Ellipsoid((0.0, 0.0, -50.0), (6.0, 6.0, 6.0))
    rng = np.random.default_rng(3)
    a = rng.uniform([-30, -30, -70], [30, 30, -30], (25, 3))
    b = a + rng.uniform([-20, -20, -15], [20, 20, 15], (25, 3))
    b[0, :2] = a[0, :2]  # a vertical leg
    b[1] = a[1] + [0.1, 0.0, 0.0]  # a 0.1 m leg
    o, e1, e2 = envelope_corners(a, b)
    exact = _sphere_rect_distance(sphere, o, e1, e2)
    sampled = _sampled_rect_distance(round_ellipsoid, o, e1, e2, 0.25)
    assert np.all(sampled >= exact - 1e-9) and np.all(sampled - exact < 0.03)


def test_held_and_ramp_meet_different_obstacles_and_report_distances_within_200_m():
    """A leg climbing 60 m over 80 m passes 35 m under a 5 m sphere at x = -20 (the 3D line is at -65 m
    there): the ramp formats clear it, a held depth may sit anywhere in [-80, -20] m, so the envelope
    meets it.  The least obstacle distance is reported for obstacles within 200 m of a leg's
    envelope (by hand: 100 m from a 150 m sphere 250 m off, 100 m beside a 150 m tall envelope, near
    the far end of a 1 km leg, 199.5 m), inf beyond (200.5 m)."""
    bounds = Bounds(-2000, 2000, -2000, 2000, -400, 0)
    w = np.array([[-40.0, 0.0, -80.0], [40.0, 0.0, -20.0]])
    world = World(bounds, obstacles=(Sphere((-20.0, 0.0, -30.0), 5.0),))
    ramp, held = fly_check(world, w, "ramp"), fly_check(world, w, "held")
    assert ramp.obstacle_hits == 0 and ramp.ok and held.obstacle_hits == 1 and not held.ok
    cases = [  # (waypoints, sphere, least distance)
        ([[-40.0, 0.0, -50.0], [40.0, 0.0, -50.0]], Sphere((0.0, 250.0, -50.0), 150.0), 100.0),
        ([[-40.0, 0.0, -200.0], [40.0, 0.0, -50.0]], Sphere((0.0, 101.0, -120.0), 1.0), 100.0),
        ([[-1000.0, 0.0, -50.0], [0.0, 0.0, -50.0]], Sphere((10.0, 0.0, -50.0), 5.0), 5.0),
        ([[-40.0, 0.0, -50.0], [40.0, 0.0, -50.0]], Sphere((0.0, 204.5, -50.0), 5.0), 199.5),
        ([[-40.0, 0.0, -50.0], [40.0, 0.0, -50.0]], Sphere((0.0, 205.5, -50.0), 5.0), np.inf),
        ([[-40.0, 0.0, -50.0], [40.0, 0.0, -50.0]], Sphere((0.0, 205.0, -50.0), 5.0), np.inf),  # 200 m exactly
    ]
    for pts, sphere, want in cases:
        check = fly_check(World(bounds, obstacles=(sphere,)), pts, "held")
        assert check.min_obstacle_distance_m == pytest.approx(want, abs=1e-9), (pts, sphere)


def test_fly_check_reports_the_least_distance_over_every_leg_and_obstacle_and_the_lowest_leg():
    """Three legs: the first 45 m from a 5 m sphere, the second 35 m (its end (40, 0) is 64 m from
    the centre; its nearest point (40, 50) 35 m), the third more than 200 m away; a far sphere listed
    first must not hide a near one.  A unit round ellipsoid 1.5 m off a leg reports 0.5 m to the 0.25 m
    sampling (0.5035 m; 1.25 m sampling would say 0.519 m).  The lowest leg is named (-1 without a
    seabed); a waypoint 0.5 m above the surface is above it."""
    bounds = Bounds(-2000, 2000, -2000, 2000, -400, 0)
    near = Sphere((0.0, 50.0, -50.0), 5.0)
    w = [[-40.0, 0.0, -50.0], [40.0, 0.0, -50.0], [40.0, 600.0, -50.0], [1000.0, 600.0, -50.0]]
    check = fly_check(World(bounds, obstacles=(Sphere((1900.0, -1900.0, -50.0), 5.0), near)), w, "held")
    assert check.min_obstacle_distance_m == pytest.approx(35.0, abs=1e-9) and check.min_altitude_leg == -1
    one = fly_check(World(bounds, obstacles=(near,)), w[:2] + [[40.0, -600.0, -50.0], [1000.0, -600.0, -50.0]])
    assert one.min_obstacle_distance_m == pytest.approx(45.0, abs=1e-9)
    ball = World(bounds, obstacles=(Ellipsoid((0.0, 0.0, -50.0), (1.0, 1.0, 1.0)),))
    d = fly_check(ball, [[-7.3, 1.5, -50.0], [8.0, 1.5, -50.0]], "ramp").min_obstacle_distance_m
    assert 0.5 <= d < 0.51
    step = fly_check(_step_world(), [[0.0, 0.0, -90.0], [10.0, 0.0, -40.0], [300.0, 0.0, -40.0]], "ramp")
    assert step.min_altitude_leg == 0 and step.leg_altitude_m.tolist() == pytest.approx([10.0, 20.0])
    assert waypoint_limits(World(bounds), [[0.0, 0.0, -10.0], [5.0, 0.0, 0.5]]).above_surface == (1,)


# ---------------------------------------------------------------------- the mission readers
_MOOS = """// start: 10.000, 20.000, 30.000   (deploy point)
Behavior = BHV_Waypoint
{
  points = 100,200,7:300,400,7
}
Behavior = BHV_ConstantDepth
{
  condition = DEPLOY = true
  condition = WPT_INDEX = 0
  depth = 40
}
Behavior = BHV_ConstantDepth
{
  condition = WPT_INDEX == 1
  depth = 50.5
}
"""


def test_parse_moos_reads_the_deploy_point_the_points_and_each_legs_held_depth():
    """x, y of each point (a third value ignored), the depth its leg's WPT_INDEX holds (`=` or `==`),
    the deploy point from the `// start:` line; every missing piece a DataError naming it."""
    from auvplan.errors import DataError
    from auvplan.io.missions import formats

    np.testing.assert_array_equal(formats.parse_moos(_MOOS), [[10, 20, -30], [100, 200, -40], [300, 400, -50.5]])
    other = "Behavior = BHV_ConstantDepth\n{\n  condition = RETURN = true\n  depth = 5\n}\n"  # not a leg's
    np.testing.assert_array_equal(formats.parse_moos(_MOOS + other), formats.parse_moos(_MOOS))
    no_start = _MOOS.replace("// start: 10.000, 20.000, 30.000   (deploy point)\n", "")
    np.testing.assert_array_equal(formats.parse_moos(no_start), [[100, 200, -40], [300, 400, -50.5]])
    for broken, match in ((_MOOS.replace("BHV_Waypoint", "BHV_Loiter"), "no BHV_Waypoint block"),
                          (_MOOS.replace("points", "polygon"), "no BHV_Waypoint block"),
                          (_MOOS.replace("100,200,7", "100;200"), "not x,y pairs"),
                          (_MOOS.replace("WPT_INDEX == 1", "WPT_INDEX = 2"), "WPT_INDEX = 1")):
        with pytest.raises(DataError, match=match):
            formats.parse_moos(broken)


def test_parse_qgc_plan_keeps_the_waypoints_of_relative_altitude_frames_only():
    """Home on the surface, then every MAV_CMD_NAV_WAYPOINT (16) item; other commands skipped; frames 3
    and 6 (relative altitude) read, any other frame a DataError naming the item."""
    from auvplan.errors import DataError
    from auvplan.io.data.geo import LocalFrame
    from auvplan.io.missions import formats

    frame = LocalFrame(48.0, -125.0)
    lon, lat = frame.inverse(np.array([0.0, 100.0, 200.0]), np.array([0.0, 50.0, -30.0]))

    def item(k, command=16, fr=3, z=-20.0):
        return {"command": command, "frame": fr, "params": [0, 0, 0, None, lat[k], lon[k], z]}

    doc = {"mission": {"plannedHomePosition": [lat[0], lon[0], 0],
                       "items": [item(1), item(2, command=178), item(2, fr=6, z=-35.0)]}}
    np.testing.assert_allclose(formats.parse_qgc_plan(doc, frame), [[0, 0, 0], [100, 50, -20], [200, -30, -35]],
                               atol=1e-6)
    doc["mission"]["items"].append(item(1, fr=0))
    with pytest.raises(DataError, match=r"items\[3\].frame = 0"):
        formats.parse_qgc_plan(doc, frame)
    with pytest.raises(DataError, match="missing or malformed"):
        formats.parse_qgc_plan({"mission": {"items": []}}, frame)


def test_read_mission_by_suffix(tmp_path):
    """The suffix decides (any case); an unknown one, or a geographic format without an origin, is a
    DataError naming the file; each format's semantics."""
    from auvplan.errors import DataError
    from auvplan.io.missions import formats

    (tmp_path / "M.BHV").write_text(_MOOS)
    w, semantics, fmt = formats.read_mission(tmp_path / "M.BHV")
    assert (semantics, fmt, w.shape) == ("held", "moos", (3, 3))
    (tmp_path / "m.txt").write_text("x")
    with pytest.raises(DataError, match="m.txt: unknown mission format '.txt'"):
        formats.read_mission(tmp_path / "m.txt")
    for suffix in (".plan", ".gpx", ".geojson", ".kml"):
        (tmp_path / f"m{suffix}").write_text("{}")
        with pytest.raises(DataError, match=f"m{suffix}: a .* mission is geographic"):
            formats.read_mission(tmp_path / f"m{suffix}")
    _csv(tmp_path / "m.csv", [(1.0, 2.0, -3.0), (4.0, 5.0, -6.0)])
    w, semantics, fmt = formats.read_mission(tmp_path / "m.csv")
    assert (semantics, fmt) == ("ramp", "csv") and w.tolist() == [[1, 2, -3], [4, 5, -6]]
    (tmp_path / "nan.csv").write_text(_HEADER + "1,2,-3,,,3,0\n4,5,nan,,,6,1\n")
    with pytest.raises(DataError, match="nan.csv: the mission has a waypoint that is not finite"):
        formats.check_mission_file(tmp_path / "nan.csv", World(Bounds(0, 10, 0, 10, -10, 0)))


def test_geojson_and_kml_missions_are_the_features_named_mission(tmp_path):
    """The flown track comes first in these files; the mission is the feature / placemark named
    'mission', wherever it is."""
    from auvplan.errors import DataError
    from auvplan.io.data.geo import LocalFrame
    from auvplan.io.missions import formats

    frame = LocalFrame(48.0, -125.0)
    lon, lat = frame.inverse(np.array([0.0, 100.0, 7.0]), np.array([0.0, 50.0, 9.0]))
    mission = [[lon[0], lat[0], -20.0], [lon[1], lat[1], -30.0]]
    track = [[lon[2], lat[2], -5.0], [lon[1], lat[1], -6.0], [lon[0], lat[0], -7.0]]
    doc = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "track"}, "geometry": {"type": "LineString", "coordinates": track}},
        {"type": "Feature", "properties": None, "geometry": {"type": "LineString", "coordinates": track}},
        {"type": "Feature", "properties": {"name": "mission"}, "geometry": {"type": "LineString",
                                                                              "coordinates": mission}}]}
    (tmp_path / "m.geojson").write_text(json.dumps(doc))
    want = [[0.0, 0.0, -20.0], [100.0, 50.0, -30.0]]
    np.testing.assert_allclose(formats.read_mission(tmp_path / "m.geojson", (48.0, -125.0))[0], want, atol=1e-6)

    def placemark(name, pts):
        return (f"<Placemark><name>{name}</name><LineString><coordinates>"
                + " ".join(f"{float(x)!r},{float(y)!r},{float(z)!r}" for x, y, z in pts)
                + "</coordinates></LineString></Placemark>")

    kml = (f'<kml xmlns="http://www.opengis.net/kml/2.2"><Document>{placemark("track", track)}'
           f'{placemark("mission", mission)}</Document></kml>')
    (tmp_path / "m.kml").write_text(kml)
    np.testing.assert_allclose(formats.read_mission(tmp_path / "m.kml", (48.0, -125.0))[0], want, atol=1e-6)
    doc["features"].pop()
    (tmp_path / "t.geojson").write_text(json.dumps(doc))
    with pytest.raises(DataError, match="no feature with properties.name = 'mission'"):
        formats.read_mission(tmp_path / "t.geojson", (48.0, -125.0))


def test_a_path_inside_a_half_metre_obstacle_margin_is_a_violation():
    """Obstacle margin 0.5 m: a leg passing 0.3 m from a 5 m sphere's surface (its ends 40 m away) is
    one violation charged at least 1e4 + 100 x 1 m; 0.7 m from it, none."""
    world = World(Bounds(-100, 100, -100, 100, -100, 0), obstacles=(Sphere((0.0, 0.0, -50.0), 5.0),),
                  margins=Margins(obstacle=0.5))
    paths = np.array([[[-40.0, 5.3, -50.0], [40.0, 5.3, -50.0]], [[-40.0, 5.7, -50.0], [40.0, 5.7, -50.0]]])
    terms = evaluate_paths(world, paths, CostModel())
    np.testing.assert_array_equal(terms.violations, [1, 0])
    assert terms.terrain[0] >= 1e4 + 100.0 and terms.terrain[1] == 0.0


def test_the_sampled_ellipsoid_distance_uses_a_grid_of_at_most_a_quarter_metre_with_both_ends():
    """A unit round ellipsoid 1.5 m beside the middle of a held leg's envelope: a grid with both ends
    and spacing <= 0.25 m (at most 2001 x 501 points) holds the midpoint when the number of intervals
    is even, so the report is exactly 0.5 m for a 20 m leg rising 10 m (80 x 40 intervals), a 600 m
    leg (capped: 2000 intervals) and a 200 m rise (capped: 500); a 0.2 m leg is sampled at its ends
    only: sqrt(1.5^2 + 0.1^2) - 1 m."""
    world = World(Bounds(-400, 400, -400, 400, -400, 0), obstacles=(Ellipsoid((0.0, 0.0, -250.0), (1.0, 1.0, 1.0)),))
    for (x0, z0), (x1, z1), want in (((-10.0, -255.0), (10.0, -245.0), 0.5), ((-300.0, -250.0), (300.0, -250.0), 0.5),
                                     ((-5.0, -350.0), (5.0, -150.0), 0.5),
                                     ((-0.1, -250.0), (0.1, -250.0), math.hypot(1.5, 0.1) - 1.0)):
        check = fly_check(world, [[x0, 1.5, z0], [x1, 1.5, z1]], "held")
        assert check.min_obstacle_distance_m == pytest.approx(want, abs=1e-9), (x0, z0)
