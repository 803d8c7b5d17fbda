"""Issue #31: one oracle per way of passing an unsafe mission that the suite once let through.

Each test names the planted bug it kills (the mutation found by hand); the expected values are
computed by hand in the docstrings.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.cost import CostModel, evaluate_paths
from auvplan.guidance.formation import FormationParams
from auvplan.guidance.mission import MissionCheck, envelope_hits, fly_check, held_track
from auvplan.planners.lattice import edge_states, node_fields
from auvplan.sim_formation import _contact
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
