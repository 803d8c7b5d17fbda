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
