"""The simulated drift (``Mission.nav_drift``, ``auvplan.sim.drift``) grows as the budget does: with bottom lock over
the distance over the ground, without it over the distance through the water (``docs/navigation.md``, "Simulated
drift"; helper nav, wave 17).

Oracle: the same seed draws the same fix error and drift direction ``u``, so the true error at the end is
``|e_fix + D u|`` with ``D = rate · W`` and a fix error of 1 mm: the ratio of the errors of two flights (a head current
and still water) is the ratio of their ``W``, recomputed independently from each recorded track, ``Σ |Δp − c Δt|``
(through the water) without lock, ``Σ |Δp|`` (over the ground) with lock.  Against 0.5 m/s at 1.5 m/s the water run is
1.5× the ground run.  Before: the simulated error grew with the ground distance in both (ratio 1.0 without lock,
against the budget's 1.5).
"""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.nav import NavParams
from auvplan.sim import Mission, SimParams, simulate
from auvplan.world import Bounds, Margins, Terrain, World
from auvplan.world.currents.fields import UniformCurrent

ROUTE = np.array([[1000.0, 3000.0, -100.0], [7000.0, 3000.0, -100.0]])
NAV = NavParams(drift_pct=0.5, drift_pct_no_lock=2.0, dvl_range_m=100.0, fix_error_m=0.001, max_error_m=5000.0,
                confidence=2.0, fixes="none")


def _flight(depth: float, c: float) -> tuple[float, float, float, float]:
    """A flight's final true error, its horizontal runs over the ground and through the water, and its drift ``D``
    summed step by step (m)."""
    x, y = np.linspace(0.0, 8000.0, 17), np.linspace(0.0, 6000.0, 9)  # non-square grid
    world = World(Bounds(0.0, 8000.0, 0.0, 6000.0, -6000.0, 0.0), Terrain(x, y, np.full((9, 17), -depth), name="flat"),
                  currents=UniformCurrent((-c, 0.0, 0.0)), margins=Margins(min_altitude=20.0, min_depth=0.0),
                  name="flat")
    mission = Mission("t", tuple(ROUTE[0]), tuple(ROUTE[-1]), navigation=NAV, nav_drift=True,
                      sim=SimParams(dt=1.0, record_every=1))
    r = simulate(world, mission, route=ROUTE, rng=7)
    assert r.arrived and r.nav_error is not None
    dp = np.diff(r.position[:, :2], axis=0)
    dt = np.diff(r.t)
    ground = np.hypot(*dp.T)
    water = np.hypot(dp[:, 0] + c * dt, dp[:, 1])
    # the drift step by step, lock by the altitude recorded at its start (the launch's dive from the surface, wave 18,
    # loses it above dvl_range_m even over the shallow seabed)
    lock = r.altitude[:-1] <= NAV.dvl_range_m
    drift = float(np.sum(np.where(lock, ground * NAV.rate(True), water * NAV.rate(False))))
    return float(r.nav_error[-1]), float(ground.sum()), float(water.sum()), drift


@pytest.mark.parametrize(("depth", "lock"), [(3000.0, False), (150.0, True)])
def test_the_true_drift_grows_over_the_water_without_lock_and_over_the_ground_with_it(depth, lock):
    e_c, g_c, w_c, d_c = _flight(depth, 0.5)
    e_s, g_s, w_s, d_s = _flight(depth, 0.0)
    assert w_s == pytest.approx(g_s, rel=1e-9)  # still water: the two runs agree
    assert w_c / g_c == pytest.approx(1.5 / (1.5 - 0.5), rel=0.02)  # V / (V − c) on a head current
    run_c, run_s = (g_c, g_s) if lock else (w_c, w_s)
    assert d_c / d_s == pytest.approx(run_c / run_s, rel=0.02)  # the legs' runs (the dive's share aside)
    assert e_c / e_s == pytest.approx(d_c / d_s, rel=2e-3)
