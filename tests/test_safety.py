"""Issue #31: one oracle per way of passing an unsafe mission that the suite once let through.

Each test names the planted bug it kills (the mutation found by hand); the expected values are
computed by hand in the docstrings.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from auvplan.cost import CostModel, evaluate_paths
from auvplan.guidance.formation import FormationParams
from auvplan.guidance.mission import MissionCheck, envelope_hits, fly_check, held_track
from auvplan.guidance.mission_limits import waypoint_limits
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


def test_held_track_reaches_every_held_depth_at_the_pitch():
    """The executor model used by the held check: from -90 m towards -40 m at 15° over a 10 m leg
    it climbs 10 tan 15° = 2.68 m, and carries the change on into the next leg, ending it
    50 / tan 15° = 186.6 m from the start (a corner there), then holds -40 m."""
    trk = held_track([[0.0, 0.0, -90.0], [10.0, 0.0, -40.0], [300.0, 0.0, -40.0]], 15.0)
    slope = math.tan(math.radians(15.0))
    np.testing.assert_allclose(trk, [[0.0, 0.0, -90.0], [10.0, 0.0, -90.0 + 10.0 * slope],
                                     [50.0 / slope, 0.0, -40.0], [300.0, 0.0, -40.0]], atol=1e-9)


# ---------------------------------------------------------------------- mission check: surface, depth band, bounds
_SCENARIO = """
name = "ridge-band"
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 10000.0]
y = [0.0, 2000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "ridge"
depth = 200.0
cell_m = 100.0
ridge_x = 5000.0
ridge_width = 2000.0
height = 150.0
[mission]
start = [500.0, 1000.0, -150.0]
goal = [9500.0, 1000.0, -150.0]
min_altitude_m = 20.0
min_depth_m = 5.0
max_depth_m = 160.0
"""
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
    limits = waypoint_limits(world, [[500.0, 1000.0, 0.0], [600.0, 1000.0, -150.0]], launch=True)
    assert limits.ok and limits.depth_range() == (150.0, 150.0)
    assert waypoint_limits(world, [[500.0, 1000.0, 0.0], [600.0, 1000.0, -150.0]]).outside_depth_band == (0,)


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
