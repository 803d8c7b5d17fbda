"""Round 10's survivors of the launch in ``nav/budget.py`` (docs/mutants.md section 10): ``mission_budget`` with the
launch's dive (``launch_water_m``) on what the suite's launches never varied — bottom lock gained half way down the
dive, legs whose distance through the water is not their ground length (per-leg speeds and currents), holds at a
waypoint and at the last one, and still water.

Oracle, in closed form on a flat seabed 300 m deep (DVL range 200 m): σ grows by ``drift_pct`` per metre over the
ground with bottom lock and by ``drift_pct_no_lock`` per metre through the water without it; the dive from the surface
(altitude 300 m) to a start at altitude 100 m has lock over its lower half, so it adds ``w0 / 2`` metres of water
without lock; a hold of ``H`` metres through the water without lock adds ``H`` before the leg that leaves it (the last
waypoint's after arrival); ``error = confidence × hypot(fix_error_m, D)``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.nav.budget import mission_budget
from auvplan.nav.params import NavParams
from auvplan.world import Bounds, Margins, Terrain, World

NAV = NavParams(drift_pct=0.3, drift_pct_no_lock=1.7, dvl_range_m=200.0, fix_error_m=4.0, max_error_m=900.0,
                confidence=2.5)
LOCK, FREE = 0.003, 0.017  # NAV's rates per metre, by hand


def _world() -> World:
    x, y = np.linspace(0.0, 9000.0, 23), np.linspace(0.0, 5000.0, 11)  # non-square cells
    return World(Bounds(0.0, 9000.0, 0.0, 5000.0, -1000.0, 0.0), Terrain(x, y, np.full((11, 23), -300.0), name="f"),
                 margins=Margins(min_altitude=10.0, min_depth=0.0), name="flat")


def _error(d: float) -> float:
    return 2.5 * math.hypot(4.0, d)


def test_lock_gained_half_way_down_the_dive():
    """Start 200 m deep (altitude 100 m): the dive has lock below 100 m of depth, half of it."""
    p = np.array([[1000.0, 2000.0, -200.0], [3000.0, 2000.0, -200.0], [3000.0, 3500.0, -200.0]])
    w0 = 800.0
    b = mission_budget(_world(), p, ("", "", ""), NAV, launch_water_m=w0)
    d0 = 0.5 * w0 * FREE
    np.testing.assert_allclose(b.error_m, [_error(d0), _error(d0 + 2000.0 * LOCK), _error(d0 + 3500.0 * LOCK)],
                               rtol=1e-12)
    np.testing.assert_allclose(b.leg_lock, [1.0, 1.0], rtol=0.0, atol=0.0)


@pytest.mark.parametrize("launch", [None, 650.0])
@pytest.mark.parametrize("moving", [False, True], ids=["still-water", "per-leg-water"])
def test_water_legs_and_holds_after_the_launch(launch, moving):
    """At 50 m (altitude 250 m: no lock anywhere), legs of 1 000, 800 and 1 200 m over the ground through 1 300,
    500 and 1 200.5 m of water (or still water), holds of 150 m at waypoint 1 and 90 m at the last."""
    p = np.array([[1000.0, 1000.0, -50.0], [2000.0, 1000.0, -50.0], [2000.0, 1800.0, -50.0],
                  [3200.0, 1800.0, -50.0]])
    ground = np.array([1000.0, 800.0, 1200.0])
    water = np.array([1300.0, 500.0, 1200.5]) if moving else ground
    held = np.array([0.0, 150.0, 0.0, 90.0])
    b = mission_budget(_world(), p, ("", "", "", ""), NAV, held_water_m=held,
                       water_m=water if moving else None, launch_water_m=launch)
    d0 = 0.0 if launch is None else launch * FREE  # no lock on the dive either
    d = d0 + FREE * np.cumsum(np.r_[0.0, water] + np.r_[0.0, held[:-1]])  # on arrival at each waypoint
    np.testing.assert_allclose(b.leg_error_m, [_error(v) for v in d[1:]], rtol=1e-12)
    want = [_error(v) for v in d[:-1]] + [_error(d[-1] + 90.0 * FREE)]  # the last after its hold
    np.testing.assert_allclose(b.error_m, want, rtol=1e-12)
    assert b.max_error_m == pytest.approx(want[-1], rel=1e-12) and want[-1] > b.leg_error_m[-1]
    assert b.kinds == ("", "", "", "") and b.leg_lock.shape == (3,) and not b.leg_lock.any()
