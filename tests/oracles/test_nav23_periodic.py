"""``fixes = <period>`` times its fixes through the World's current, as the planned fixes' times are
(``docs/navigation.md``, "The best fixed period"; helper nav, wave 17).

Oracle: a level straight leg flown east at through-water speed V = 1.5 m/s against a head current that grows in time,
c(t) = c0 + a t (c0 = 0.5 m/s, a = 2·10⁻⁵ m/s²), has the ground speed V − c0 − a t, so the distance flown by t is
s(t) = (V − c0) t − a t² / 2 and the time at s is t(s) = ((V − c0) − sqrt((V − c0)² − 2 a s)) / a.  The timer fires
``period`` seconds after the start and after each fix: each fix lies at the first sample of the route's profile whose
t(s) reaches the last fix's time plus the period.  Before: the profile's times were s / V (still water): the first fix
at 6.0 km instead of 3.84 km, one fix instead of two.
"""

from __future__ import annotations

import math

import numpy as np

from auvplan.nav import NavParams
from auvplan.sim import Mission
from auvplan.sim.navigation import navigation_plan
from auvplan.vehicles import VehicleParams
from auvplan.world import Bounds, Margins, Terrain, World
from auvplan.world.currents.fields import GriddedCurrent

V, C0, A = 1.5, 0.5, 2e-5
ROUTE = np.array([[1000.0, 3000.0, -100.0], [11000.0, 3000.0, -100.0]])


def _t(s: np.ndarray) -> np.ndarray:
    g0 = V - C0
    return (g0 - np.sqrt(g0 * g0 - 2.0 * A * s)) / A


def test_periodic_fixes_are_timed_through_a_current_that_changes_in_time():
    x, y = np.linspace(0.0, 12000.0, 25), np.linspace(0.0, 6000.0, 13)  # non-square grid
    tt = np.array([0.0, 30000.0])
    u = -(C0 + A * tt)[:, None, None, None] * np.ones((2, 2, 2, 2))  # against the leg, linear in time (exact)
    cur = GriddedCurrent(x[[0, -1]], y[[0, -1]], np.array([-6000.0, 0.0]), u, np.zeros_like(u), t=tt, name="tide")
    world = World(Bounds(0.0, 12000.0, 0.0, 6000.0, -6000.0, 0.0),
                  Terrain(x, y, np.full((13, 25), -3000.0), name="flat"), currents=cur,
                  margins=Margins(min_altitude=20.0, min_depth=0.0), name="flat")
    nav = NavParams(drift_pct=0.3, drift_pct_no_lock=1.0, dvl_range_m=100.0, fix_error_m=3.0, max_error_m=300.0,
                    confidence=2.0, fixes=4000.0, surface_s=60.0)
    mission = Mission("t", tuple(ROUTE[0]), tuple(ROUTE[-1]), navigation=nav,
                      vehicle=VehicleParams(speed=V, max_pitch_deg=20.0))
    plan = navigation_plan(world, mission, ROUTE)
    assert plan is not None and plan.fixes.ok
    # the independent timer on the profile's samples (every 50 m along the track)
    s = np.linspace(0.0, 10000.0, 201)
    t = _t(s)
    expected, t0 = [], 0.0
    while (k := int(np.searchsorted(t, t0 + nav.fixes, side="left"))) < s.size - 1:
        expected.append(s[k])
        t0 = float(t[k])
    assert len(expected) == 2 and abs(expected[0] - 3840.0) <= 50.0  # s(4000 s) = 4000 − 160 m
    np.testing.assert_allclose(plan.fixes.s, expected, atol=50.0 + 1e-9)  # to one sample of the traverse's rounding
    # still water would have put one fix at 6 km
    assert math.isclose(V * nav.fixes, 6000.0) and np.all(np.abs(plan.fixes.s - 6000.0) > 1000.0)
