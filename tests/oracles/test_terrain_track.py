"""``terrain_track`` (a ``.plan``'s terrain-frame legs, flown at the commanded altitude above the seabed) against
dense sampling on random bilinear grids and against crests worked by hand.

The track must stay on its legs' horizontal segments (no vertex past a leg's end), each vertex on the commanded
altitude above the seabed, between two vertices monotone in depth (so its shallowest and deepest points are
vertices); a grid-line crossing is a vertex also where the leg is exactly 1 m long along an axis; a single
waypoint is a track of one point and no leg.
"""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.guidance.mission.terrain_legs import terrain_track
from auvplan.world.terrain import Terrain


def _dense(t: Terrain, a: np.ndarray, b: np.ndarray, ha: float, hb: float, n: int = 4001) -> np.ndarray:
    s = np.linspace(0.0, 1.0, n)
    xy = a[:2] + s[:, None] * (b[:2] - a[:2])
    return t.elevation(xy[:, 0], xy[:, 1]) + ha + s * (hb - ha)


@pytest.mark.parametrize("seed", range(6))
def test_the_track_stays_on_its_legs_and_holds_the_sampled_extremes(seed):
    """Oracle: dense sampling (4 001 points a leg) on a random non-square grid off the origin, four legs in any
    direction (some along a grid axis), every other one terrain-following."""
    rng = np.random.default_rng(seed)
    nx, ny = int(rng.integers(3, 12)), int(rng.integers(3, 12))
    x = -2.0e5 + np.cumsum(rng.uniform(20.0, 80.0, nx)) if seed % 2 else 5.0e4 + np.arange(nx) * 37.5
    y = 3.0e5 + np.arange(ny) * float(rng.uniform(15.0, 90.0))
    t = Terrain(x, y, rng.uniform(-150.0, -20.0, (ny, nx))) if seed % 2 == 0 else \
        Terrain(np.linspace(x[0], x[-1], nx), y, rng.uniform(-150.0, -20.0, (ny, nx)))
    x0, x1, y0, y1 = t.extent
    w = np.column_stack([rng.uniform(x0, x1, 5), rng.uniform(y0, y1, 5), rng.uniform(-15.0, -5.0, 5)])
    w[2, 1] = w[1, 1]  # a leg along x
    w[4, 0] = w[3, 0]  # a leg along y
    follow = np.array([True, False, True, True])
    track, leg = terrain_track(t, w, follow)
    assert leg.size == track.shape[0] - 1 and np.array_equal(np.unique(leg), np.arange(4))
    assert np.array_equal(track[0], w[0])
    for k in range(4):
        a, b = w[k], w[k + 1]
        seg = np.flatnonzero(leg == k)
        on = track[np.r_[seg[0], seg + 1]]  # the leg's vertices, its start included
        assert np.array_equal(on[-1], b) and np.array_equal(on[0], a if k == 0 else track[seg[0]])
        if not follow[k]:
            assert seg.size == 1
            continue
        s = ((on[:, :2] - a[:2]) @ (b[:2] - a[:2])) / float((b[:2] - a[:2]) @ (b[:2] - a[:2]))
        assert np.all(np.diff(s) > 0.0) and s[0] == 0.0 and abs(s[-1] - 1.0) < 1e-12  # in order, none past b
        np.testing.assert_allclose(on[:, :2], a[:2] + s[:, None] * (b[:2] - a[:2]), atol=1e-6)
        ha, hb = a[2] - float(t.elevation(a[0], a[1])), b[2] - float(t.elevation(b[0], b[1]))
        np.testing.assert_allclose(on[:, 2], t.elevation(on[:, 0], on[:, 1]) + ha + s * (hb - ha), atol=1e-9)
        z = _dense(t, a, b, ha, hb)
        assert on[:, 2].max() >= z.max() - 1e-9 and on[:, 2].min() <= z.min() + 1e-9


def test_a_one_metre_leg_across_a_crest_has_its_vertex_on_the_crest():
    """By hand: a V-shaped crest (40 m deep) on the grid line x = 100; a leg exactly 1 m long (99.875 to
    100.875 m) held 10 m above the seabed: the shallowest point is the crest's, 30 m deep, a vertex at x = 100
    (the quadratic through the leg's ends and middle puts its extremum outside the leg)."""
    t = Terrain(np.array([99.0, 100.0, 101.0]), np.array([0.0, 10.0]), np.array([[-50.0, -40.0, -50.0]] * 2))
    w = np.array([[99.875, 5.0, -41.25 + 10.0], [100.875, 5.0, -48.75 + 10.0]])
    track, leg = terrain_track(t, w, [True])
    assert track[:, 2].max() == pytest.approx(-30.0, abs=1e-12)
    assert np.any(track[:, 0] == 100.0) and leg.tolist() == [0] * (track.shape[0] - 1)


def test_a_single_waypoint_is_a_track_of_one_point_and_no_leg():
    t = Terrain(np.array([0.0, 10.0]), np.array([0.0, 10.0]), np.full((2, 2), -50.0))
    track, leg = terrain_track(t, [[5.0, 5.0, -20.0]], [])
    assert track.tolist() == [[5.0, 5.0, -20.0]] and leg.size == 0 and leg.dtype == np.intp
    with pytest.raises(ValueError, match="follow has 1 flags for 0 legs"):
        terrain_track(t, [[5.0, 5.0, -20.0]], [True])


def test_a_leg_ending_before_its_depth_turns_has_no_vertex_past_its_end():
    """By hand: one cell, seabed -300 + 60 u v; the diagonal leg to (90, 90) descends from 125 m to 5 m above it:
    depth -175 + (48.6 s - 120) s, monotone on the leg (its turning point at s = 120 / 97.2 lies past the end)."""
    t = Terrain(np.array([0.0, 100.0]), np.array([0.0, 100.0]), np.array([[-300.0, -300.0], [-300.0, -240.0]]))
    w = np.array([[0.0, 0.0, -175.0], [90.0, 90.0, -300.0 + 48.6 + 5.0]])
    track, leg = terrain_track(t, w, [True])
    assert np.array_equal(track[-1], w[-1]) and (leg == 0).all()
    s = track[:, 0] / 90.0  # the vertices within SAG_M of the curve (audit 15), all on the leg, none past its end
    assert (np.diff(s) > 0.0).all() and s[-1] == 1.0 and (np.diff(track[:, 2]) < 0.0).all()
    np.testing.assert_allclose(track[:-1, 2], -175.0 + (48.6 * s[:-1] - 120.0) * s[:-1], atol=1e-9)
    assert (48.6 * np.diff(s) ** 2 / 4.0).max() <= 0.01


def test_the_flown_pitch_of_short_and_vertical_terrain_frame_legs():
    """By hand on a flat seabed: a 0.5 m leg climbing 0.1 m flies at atan(0.2) (not a vertical one); a leg with no
    horizontal length is level (0 deg) when it keeps its depth, vertical (90 deg) when it changes it."""
    from auvplan.guidance.mission.terrain_legs import flown_pitch_depth

    t = Terrain(np.array([0.0, 10.0]), np.array([0.0, 10.0]), np.full((2, 2), -50.0))
    w = np.array([[2.0, 2.0, -20.0], [2.5, 2.0, -19.9], [2.5, 2.0, -19.9], [2.5, 2.0, -25.0]])
    pitch, depth = flown_pitch_depth(t, w, [True, True, True])
    np.testing.assert_allclose(pitch, [np.degrees(np.arctan(0.2)), 0.0, 90.0], rtol=1e-9)
    np.testing.assert_allclose(depth, [20.0, 19.9, 25.0])
