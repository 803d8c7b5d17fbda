"""The fixes' planned times (``fixes.csv`` ``t_s``) come from the flight the error budget counts: the launch's dive
from the surface first, then the legs in the current as it is once the dive is over (as the exported ``.plan``'s check
flies them), counted from the arrival at the first waypoint (``docs/navigation.md``; helper nav2, wave 17).

Oracle, an independent integration (RK4, 0.05 s steps) of a current along x that reverses within the mission,
u(t) = U0 − B t (0.8 m/s east at the launch, 0 at 5 000 s, exact in the field's linear time interpolation): the
launch held over the start sinks at sqrt(V² − u²) (V = 1.5 m/s) for 1 000 m; then each straight leg at through-water
speed V has the ground speed ``g = u·e + sqrt(V² − u² + (u·e)²)`` along its direction ``e``; a surface fix waits
``surface_s``.  The fix at 3 551.1 s after the first waypoint (the goal at 6 269.5 s); before, the times were those of
the legs flown from t = 0 (the current's phase 766 s early, the dive's duration): the fix at 3 313.7 s, 237 s earlier
than the flight the budget and the ``.plan``'s check fly (the goal 535 s; in a steady current they agree).
"""

from __future__ import annotations

import math

import numpy as np

from auvplan.nav import NavParams, navigation_of
from auvplan.sim import Mission
from auvplan.sim.navigation import timed_navigation
from auvplan.vehicles import VehicleParams
from auvplan.world import Bounds, Margins, Terrain, World
from auvplan.world.currents.fields import GriddedCurrent

V, U0, B = 1.5, 0.8, 1.6e-4
POINTS = np.array([[1000.0, 3000.0, -1000.0], [5000.0, 3000.0, -1000.0], [7500.0, 3000.0, 0.0],
                   [10000.0, 3000.0, -1000.0], [11000.0, 3000.0, -1000.0]])
KINDS = ("", "", "gps", "", "")
SURFACE_S = 60.0


def _u(t: float) -> float:
    return U0 - B * t


def _integrate(t: float, rate) -> float:
    """Time at which ∫ rate(t) dt from ``t`` reaches 1 (the leg's length normalised): RK4 on the distance."""
    dt, s = 0.05, 0.0
    while True:
        k1 = rate(t)
        k2 = rate(t + dt / 2)
        k4 = rate(t + dt)
        step = dt / 6 * (k1 + 4 * k2 + k4)  # the rate depends on t alone: RK4 is Simpson's rule
        if s + step >= 1.0:
            return t + dt * (1.0 - s) / step
        s, t = s + step, t + dt


def _oracle(launch: bool) -> np.ndarray:
    t = 0.0
    if launch:
        t = _dive()
    arrive = [t]
    for i in range(len(POINTS) - 1):
        d = POINTS[i + 1] - POINTS[i]
        length = float(np.linalg.norm(d))
        e = d / length
        if KINDS[i] == "gps":
            t += SURFACE_S

        def rate(tt: float, ex: float = float(e[0]), length: float = length) -> float:
            ue = _u(tt) * ex
            return (ue + math.sqrt(V * V - _u(tt) ** 2 + ue * ue)) / length
        t = _integrate(t, rate)
        arrive.append(t)
    a = np.array(arrive)
    return a - a[0]


def _world() -> World:
    x, y = np.linspace(0.0, 14000.0, 29), np.linspace(0.0, 6000.0, 13)  # non-square grid
    tt = np.array([0.0, 20000.0])
    u = (U0 - B * tt)[:, None, None, None] * np.ones((2, 2, 2, 2))  # linear in time: the field's interpolation, exact
    cur = GriddedCurrent(x[[0, -1]], y[[0, -1]], np.array([-6000.0, 0.0]), u, np.zeros_like(u), t=tt, name="tide")
    return World(Bounds(0.0, 14000.0, 0.0, 6000.0, -6000.0, 0.0),
                 Terrain(x, y, np.full((13, 29), -3000.0), name="flat"), currents=cur,
                 margins=Margins(min_altitude=20.0, min_depth=0.0), name="flat")


def _dive() -> float:
    """The launch's duration: held over the start, sinking at sqrt(V² − u²) for 1 000 m."""
    return _integrate(0.0, lambda tt: math.sqrt(V * V - _u(tt) ** 2) / -POINTS[0, 2])


def test_fix_times_are_the_launched_flights_in_a_reversing_current():
    world = _world()
    nav = NavParams(drift_pct=0.3, drift_pct_no_lock=1.0, dvl_range_m=100.0, fix_error_m=3.0, max_error_m=3000.0,
                    confidence=2.0, fixes="none", surface_s=SURFACE_S)
    mission = Mission("t", tuple(POINTS[0]), tuple(POINTS[-1]), navigation=nav,
                      vehicle=VehicleParams(speed=V, max_pitch_deg=30.0))
    plan = timed_navigation(world, mission, navigation_of(world, POINTS, KINDS, nav, V))
    expected, from_zero = _oracle(launch=True), _oracle(launch=False)
    assert expected[-1] < 9000.0  # the current stays below V (and reverses at 5 000 s, within the mission)
    assert plan.vertex_times_s is not None and plan.launch_water_m is not None
    np.testing.assert_allclose(plan.vertex_times_s, expected, atol=0.5)
    np.testing.assert_allclose(plan.times_s, expected[[2]], atol=0.5)  # fixes.csv's t_s
    assert abs(expected[2] - from_zero[2]) > 50.0  # the legs flown from t = 0 would put the fix elsewhere in time


def test_a_fix_period_is_timed_on_the_launched_flight():
    """``fixes = 2500`` on one level leg of 12 km at 1 000 m, the same current: after the dive (T_d, integrated) the
    ground speed is V + u(T_d + τ), so the distance flown by τ after the first waypoint is
    s(τ) = g0 τ − B τ² / 2 with g0 = V + U0 − B T_d, and τ(s) = (g0 − sqrt(g0² − 2 B s)) / B (closed form); the timer
    fires on the route's samples (every 50 m) as in ``test_nav23_periodic``: fixes at 4.95 and 8.90 km.  Before, on the
    legs flown from t = 0 (g0 = V + U0): at 5.25 and 9.50 km."""
    from auvplan.sim.navigation import navigation_plan

    route = np.array([[1000.0, 3000.0, -1000.0], [13000.0, 3000.0, -1000.0]])
    nav = NavParams(drift_pct=0.3, drift_pct_no_lock=1.0, dvl_range_m=100.0, fix_error_m=3.0, max_error_m=3000.0,
                    confidence=2.0, fixes=2500.0, surface_s=SURFACE_S)
    mission = Mission("t", tuple(route[0]), tuple(route[-1]), navigation=nav,
                      vehicle=VehicleParams(speed=V, max_pitch_deg=30.0))
    plan = navigation_plan(_world(), mission, route)
    assert plan is not None
    s = np.linspace(0.0, 12000.0, 241)

    def timer(g0: float) -> list[float]:
        tau = (g0 - np.sqrt(g0 * g0 - 2.0 * B * s)) / B
        out, t0 = [], 0.0
        while (k := int(np.searchsorted(tau, t0 + nav.fixes, side="left"))) < s.size - 1:
            if 1000.0 / math.tan(math.radians(0.999 * 30.0)) <= s[k] <= s[-1] - 1000.0 / math.tan(
                    math.radians(0.999 * 30.0)):  # a surfacing within the leg (the climb and dive at the pitch limit)
                out.append(float(s[k]))
            t0 = float(tau[k])
        return out
    expected, from_zero = timer(V + U0 - B * _dive()), timer(V + U0)
    assert len(expected) == 2 and abs(from_zero[0] - expected[0]) > 250.0
    np.testing.assert_allclose(plan.fixes.s, expected, atol=50.0 + 1e-9)  # to one sample of the traverse's rounding
