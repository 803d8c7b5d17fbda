"""A mission with a vertical leg fitted to the pitch limit (docwalk20).

A survey's transit out ends straight above its first line's start when the floor lifts the last vertex (a
sidescan held 30 m above a 5 km deep seabed, launched 40 m above it): the fit changed depth along the track
within the pitch limit, so both vertices of the vertical leg took one place, a 0.000 m leg no merge could
remove (both the mission's corners), and ``auvplan survey`` ended INFEASIBLE ("leg 16: 0.000 m long < the
shortest leg 0.1 m").  Oracles: the contract of ``fit_mission`` (no leg shorter than ``FITTED_LEG_M``, no leg
steeper than the limit, the ends kept exactly) and the horizontal track, which the fit may not change (every
fitted point on the input's horizontal polyline, every corner away from a vertical leg kept).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import LineString, Point

from auvplan.guidance.mission.fit import _plumb_kept, fit_mission
from auvplan.path.flyable import VehicleLimits, leg_pitch_deg
from auvplan.path.legs import FITTED_LEG_M
from helpers import RIDGE, build_toml

LIMITS = VehicleLimits(max_pitch_deg=20.0, turn_radius_m=10.0)

# a vertical leg inside (x = 500) and a near-vertical one (0.4 m across, 10 m down) at the end (x = 1800)
MISSION = np.array([[100.0, 200.0, -30.0], [500.0, 200.0, -30.0], [500.0, 200.0, -45.0], [800.0, 300.0, -40.0],
                    [1800.0, 200.0, -30.0], [1800.4, 200.0, -40.0]])


@pytest.mark.parametrize("mission", [MISSION, MISSION[2:], MISSION[::-1]], ids=["inside-and-end", "start", "reversed"])
def test_a_vertical_leg_is_fitted_without_a_leg_shorter_than_the_minimum(mission: np.ndarray) -> None:
    world, _ = build_toml(RIDGE)
    fit = fit_mission(mission, world, LIMITS)
    out = fit.waypoints
    assert fit.ok, fit.message
    assert np.linalg.norm(np.diff(out, axis=0), axis=1).min() >= FITTED_LEG_M
    assert np.abs(leg_pitch_deg(out)).max() <= LIMITS.max_pitch_deg
    np.testing.assert_array_equal(out[[0, -1]], mission[[0, -1]])
    track = LineString(mission[:, :2])
    assert max(track.distance(Point(p)) for p in out[:, :2]) < 1e-6
    corner = (800.0, 300.0)  # the corner between the vertical legs keeps its place
    assert np.any(np.hypot(out[:, 0] - corner[0], out[:, 1] - corner[1]) < 1e-9)


def test_a_mission_without_steep_short_legs_keeps_every_vertex() -> None:
    """Only a horizontal span whose leg at the profile's steepest is shorter than the minimum goes: a
    2.5 m horizontal step stays (the reach is 2.5 m · cos(atan(tan 19°)) ≈ 2.36 m)."""
    w = np.array([[0.0, 0.0, -30.0], [100.0, 0.0, -30.0], [102.5, 0.0, -31.0], [200.0, 50.0, -30.0]])
    reach = FITTED_LEG_M / math.hypot(1.0, math.tan(math.radians(19.0)))
    assert _plumb_kept(w, reach).tolist() == [0, 1, 2, 3]
    assert _plumb_kept(w, 2.6).tolist() == [0, 1, 3]
    steps = np.array([[0.0, 0.0, -30.0], [100.0, 0.0, -30.0], [101.5, 0.0, -35.0], [103.0, 0.0, -40.0],
                      [200.0, 50.0, -40.0]])  # measured from the vertex kept (100), not the one dropped (101.5)
    assert _plumb_kept(steps, reach).tolist() == [0, 1, 3, 4]
    end = np.vstack([w, [[200.0, 50.0, -40.0], [200.0, 50.0, -50.0]]])  # two vertical legs at the end
    assert _plumb_kept(end, reach).tolist() == [0, 1, 2, 5]


def test_a_steep_short_step_that_fits_keeps_its_corners() -> None:
    """A 2.45 m horizontal step rising 0.8 m (2.58 m long, 18.1°: within the limit and over the minimum) keeps
    both its corners through the fit (a reach of the full 2.5 m would drop one)."""
    world, _ = build_toml(RIDGE)
    w = np.array([[100.0, 200.0, -30.0], [400.0, 200.0, -30.0], [402.45, 200.0, -29.2], [700.0, 250.0, -29.2]])
    out = fit_mission(w, world, LIMITS).waypoints
    for x, y in w[:, :2]:
        assert np.any(np.hypot(out[:, 0] - x, out[:, 1] - y) < 1e-9), (x, y)
