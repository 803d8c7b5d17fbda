"""``guidance.mission.terrain_legs``' edges by hand: a mission of one waypoint (no leg: no pitch, no depth), and a
``.plan`` whose terrain-frame legs are checked in a world without a seabed (nothing to follow: the straight legs,
as ``fly_check`` flies them, down to the leg it names, -1 without a seabed)."""

from __future__ import annotations

import numpy as np

from auvplan.guidance.mission.flycheck import fly_check
from auvplan.guidance.mission.terrain_legs import check_as_flown, flown_track
from auvplan.world import Bounds, Margins, Sphere, World
from helpers import flat_world


def test_one_waypoint_is_a_track_of_one_point_with_no_leg_pitch_or_depth():
    terrain = flat_world().terrain
    assert terrain is not None
    flown = flown_track(terrain, [[10.0, 20.0, -50.0]], [])
    assert np.array_equal(flown.track, [[10.0, 20.0, -50.0]])
    assert flown.leg.shape == flown.pitch.shape == flown.depth.shape == (0,)


def test_terrain_frame_legs_without_a_seabed_are_checked_as_the_straight_legs():
    """No seabed, a sphere of 20 m on the second leg: every figure is fly_check's ("ramp"), the least altitude
    infinite on no leg (-1), the sphere hit once, at its depth 18.9 m inside."""
    world = World(Bounds(0.0, 1000.0, 0.0, 1000.0, -200.0, 0.0), obstacles=(Sphere((500.0, 500.0, -50.0), 20.0),),
                  margins=Margins(min_altitude=5.0))
    pts = np.array([[100.0, 500.0, 0.0], [480.0, 500.0, -50.0], [900.0, 520.0, -60.0]])
    got = check_as_flown(world, pts, [False, True])
    want = fly_check(world, pts, "ramp", launch=True)
    assert got.min_altitude_leg == want.min_altitude_leg == -1 and got.min_altitude_m == np.inf
    assert got.obstacle_hits == want.obstacle_hits == 1
    assert got.min_obstacle_distance_m == want.min_obstacle_distance_m < -18.0
    assert np.array_equal(got.leg_altitude_m, want.leg_altitude_m) and got.ok is want.ok is False
