"""The pitch and depth of a leg flown following the seabed (``flown_pitch_depth``), against the analytic track over
a saddle cell: elevation ``h u v`` (bilinear), so along the diagonal it is ``h t^2`` and the track's tangent at the
far end is twice its chord."""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.guidance.mission.terrain_legs import flown_pitch_depth
from auvplan.world import Terrain


@pytest.mark.parametrize(("length", "width", "h"), [(100.0, 100.0, 30.0), (80.0, 200.0, -40.0)])
def test_the_steepest_pitch_is_the_track_s_tangent_not_its_chord(length, width, h):
    """A non-square cell ``length x width``; the leg from (0, 0) to the far corner 10 m above the seabed then 20 m:
    ``z(t) = -100 + h t^2 + 10 + 10 t``, steepest ``|dz/dt|`` at an end, over the horizontal length."""
    x, y = np.array([0.0, length]), np.array([0.0, width])
    terrain = Terrain(x, y, np.array([[-100.0, -100.0], [-100.0, -100.0 + h]]), name="saddle")
    a = np.array([0.0, 0.0, -90.0])
    b = np.array([length, width, -100.0 + h + 20.0])
    plain = np.array([0.0, width, -50.0])  # an unmarked leg after it: the straight leg's pitch and depth
    pitch, depth = flown_pitch_depth(terrain, [a, b, plain], [True, False])
    horizontal = math.hypot(length, width)
    tangent = max(abs(10.0), abs(2.0 * h + 10.0)) / horizontal
    chord = abs(h + 10.0) / horizontal
    assert tangent > 1.5 * chord
    assert pitch[0] == pytest.approx(math.degrees(math.atan(tangent)), rel=1e-9)
    t = np.linspace(0.0, 1.0, 100_001)
    z = -90.0 + h * t**2 + 10.0 * t
    assert depth[0] == pytest.approx(float(-z.min()), abs=1e-6)
    assert pitch[1] == pytest.approx(math.degrees(math.atan2(abs(-50.0 - b[2]), length)), rel=1e-12)
    assert depth[1] == pytest.approx(max(-b[2], 50.0))
    back, back_depth = flown_pitch_depth(terrain, [b, a], [True])  # the same curve flown the other way
    assert back[0] == pytest.approx(math.degrees(math.atan(tangent)), rel=1e-9)  # its steepest end is its first
    assert back_depth[0] == pytest.approx(depth[0], abs=1e-9)


@pytest.mark.parametrize(("x0", "y0", "dx", "dy"), [(123456.789, 98765.4321, 7.3, 14.6), (0.1, 0.7, 0.3, 0.3),
                                                    (-19014.98, -19472.26, 500.31, 499.33)])
def test_a_leg_through_grid_nodes_has_the_plane_s_pitch(x0, y0, dx, dy):
    """Oracle: a plane seabed ``0.01 x + 0.02 y``, so a leg holding 20 m above it climbs at the plane's slope along
    it exactly.  Legs from node to node (their x and y grid lines crossed at parameters a rounding apart: the sliver
    between them was a piece of 1e-15 whose depth differences, divided by its length, read 5.98 deg for 1.28 on the
    first grid), along a grid line, and ending on one."""
    x, y = x0 + dx * np.arange(40), y0 + dy * np.arange(40)
    gx, gy = np.meshgrid(x - x0, y - y0)
    terrain = Terrain(x, y, -100.0 + 0.01 * gx + 0.02 * gy, name="plane")
    ends = [((2, 3), (30, 31)), ((30, 31), (2, 3)), ((5, 2), (5, 37)), ((1, 1), (33, 17)), ((0, 0), (39, 39))]
    for (i0, j0), (i1, j1) in ends:
        a, b = np.array([x[i0], y[j0], 0.0]), np.array([x[i1], y[j1], 0.0])
        a[2], b[2] = terrain.elevation(a[0], a[1]) + 20.0, terrain.elevation(b[0], b[1]) + 20.0
        pitch, depth = flown_pitch_depth(terrain, [a, b], [True])
        slope = abs(0.01 * (b[0] - a[0]) + 0.02 * (b[1] - a[1])) / math.hypot(*(b[:2] - a[:2]))
        assert pitch[0] == pytest.approx(math.degrees(math.atan(slope)), abs=1e-9)
        assert depth[0] == pytest.approx(-min(a[2], b[2]), abs=1e-9)
