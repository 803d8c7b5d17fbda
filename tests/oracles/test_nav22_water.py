"""The drift without bottom lock grows over each leg's distance through the water, not over the ground
(``docs/navigation.md``; helper nav22).

Oracle: a level straight leg flown at through-water speed V against a uniform current c along it takes
T = L / (V − c), so the vehicle moves V·T = L·V/(V − c) through the water, and without bottom lock
σ = hypot(σ_fix, rate · V · L / (V − c)); a following current is c < 0; a current linear in time,
c(t) = c0 + a t, gives L = (V − c0) T − a T² / 2 (solved for T); with bottom lock the DVL's error is a share
of the ground distance, whatever the current.  The mission is launched from the surface above its start (wave 17):
the dive of depth d at the launch speed V0 = 1.5 m/s held over the point sinks at sqrt(V0² − c²) and moves
w0 = c · d / sqrt(V0² − c²) through the water, its share without lock adding w0 · rate to D; the legs are flown
after it (in a current that changes in time, from the launch's end).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from auvplan.endurance import traverse
from auvplan.nav import NavParams, check_navigation, navigation_of
from auvplan.sim import Mission
from auvplan.sim.navigation import timed_navigation
from auvplan.world import Bounds, Margins, Terrain, World
from auvplan.world.currents.fields import GriddedCurrent, UniformCurrent

NAV = NavParams(drift_pct=0.5, drift_pct_no_lock=2.0, dvl_range_m=100.0, fix_error_m=3.0, max_error_m=5000.0,
                confidence=2.0)
LEG = np.array([[1000.0, 3000.0, -200.0], [9000.0, 3000.0, -200.0]])  # 8 km east, level


def _world(depth: float, current=None) -> World:
    """A flat seabed (non-square grid), 200 m deep vehicle: no lock over 3 000 m, lock over 250 m."""
    x, y = np.linspace(0.0, 12000.0, 25), np.linspace(0.0, 6000.0, 13)
    w = World(Bounds(0.0, 12000.0, 0.0, 6000.0, -6000.0, 0.0), Terrain(x, y, np.full((13, 25), -depth), name="flat"),
              margins=Margins(min_altitude=20.0, min_depth=0.0), name="flat")
    return w if current is None else replace(w, currents=current)


def _error(world: World, points: np.ndarray, speeds: tuple[float, ...] = ()) -> float:
    """The error at the end as the app budgets it: the mission flown through the current at its legs' speeds."""
    mission = Mission("t", tuple(points[0]), tuple(points[-1]), leg_speeds=speeds)
    nav = timed_navigation(world, mission, navigation_of(world, points, ("",) * len(points), NAV, 1.5))
    return float(nav.check.budget.error_m[-1])


def _closed(d: float) -> float:
    return NAV.confidence * math.hypot(NAV.fix_error_m, d)


def _launch(c: float, depth: float, no_lock: float = 1.0) -> float:
    """The launch's drift: ``depth`` dived at 1.5 m/s held over the point in a steady current of speed ``c``, its
    share ``no_lock`` without lock."""
    return no_lock * NAV.rate(False) * c * depth / math.sqrt(1.5 ** 2 - c * c)


@pytest.mark.parametrize("c", [1.0, 0.5, -0.5])  # head currents (3× and 1.5×) and a following one
def test_no_lock_error_grows_with_the_water_distance_in_a_steady_current(c):
    world = _world(3000.0, UniformCurrent((-c, 0.0, 0.0)))  # against the leg (east) for c > 0
    v, length = 1.5, 8000.0
    got = _error(world, LEG, (v,))
    assert got == pytest.approx(_closed(NAV.rate(False) * v * length / (v - c) + _launch(abs(c), 200.0)), rel=1e-9)
    # still water: the ground distance, as before
    assert _error(_world(3000.0), LEG, (v,)) == pytest.approx(_closed(NAV.rate(False) * length), rel=1e-12)


def test_with_bottom_lock_the_error_is_a_share_of_the_ground_distance_whatever_the_current():
    world = _world(250.0, UniformCurrent((-1.0, 0.0, 0.0)))  # 50 m altitude: lock all along
    # the launch: altitude 250 m at the surface, 50 m at the start, linear: without lock above 100 m, 3/4 of it
    assert _error(world, LEG, (1.5,)) == pytest.approx(_closed(NAV.rate(True) * 8000.0 + _launch(1.0, 200.0, 0.75)),
                                                       rel=1e-9)


def test_each_leg_at_its_own_speed_and_a_climb():
    """Two level legs at 1.0 and 2.0 m/s against 0.6 m/s, then a climb of 300 m over 4 km at 1.8 m/s: its
    horizontal water run is sqrt((V T)² − Δz²), T = L / g, g the ground speed with |g ê − c| = V."""
    c = 0.6
    world = _world(3000.0, UniformCurrent((-c, 0.0, 0.0)))
    pts = np.array([[1000.0, 3000.0, -500.0], [4000.0, 3000.0, -500.0], [7000.0, 3000.0, -500.0],
                    [11000.0, 3000.0, -200.0]])
    speeds = (1.0, 2.0, 1.8)
    d_water = 3000.0 * 1.0 / (1.0 - c) + 3000.0 * 2.0 / (2.0 - c)
    length = math.hypot(4000.0, 300.0)
    e = np.array([4000.0, 0.0, 300.0]) / length  # the climb: ground speed g with |g e − c| = V
    cur = np.array([-c, 0.0, 0.0])
    g = float(e @ cur + math.sqrt((e @ cur) ** 2 - cur @ cur + 1.8 ** 2))
    t = length / g
    d_water += math.sqrt((1.8 * t) ** 2 - 300.0 ** 2)
    d = NAV.rate(False) * d_water + _launch(c, 500.0)
    assert _error(world, pts, speeds) == pytest.approx(_closed(d), rel=1e-9)
    # the same legs all at the cruise speed (no leg speeds): another water distance
    assert _error(world, pts) != pytest.approx(_closed(d), rel=1e-3)


def test_a_current_that_changes_in_time():
    """c(t) = 0.2 + 2e-5 t against the leg (linear between the grid's two times: exact in time)."""
    c0, a, v, length = 0.2, 2e-5, 1.5, 8000.0
    tt = np.array([0.0, 20000.0])
    x, y, z = np.array([0.0, 12000.0]), np.array([0.0, 6000.0]), np.array([-6000.0, 0.0])
    u = -(c0 + a * tt)[:, None, None, None] * np.ones((2, 2, 2, 2))
    world = _world(3000.0, GriddedCurrent(x, y, z, u, np.zeros_like(u), t=tt, name="tide"))
    # the launch: 200 m dived at 1.5 m/s, sinking at sqrt(1.5² − c(t)²) (its end t0 by bisection on the integral,
    # Simpson's rule on 2 000 intervals), w0 = c0 t0 + a t0² / 2 through the water; the leg flown from t0
    def sunk(t_end: float) -> float:
        ts = np.linspace(0.0, t_end, 2001)
        f = np.sqrt(1.5 ** 2 - (c0 + a * ts) ** 2)
        return float((t_end / 6000.0) * (f[0] + f[-1] + 4.0 * f[1:-1:2].sum() + 2.0 * f[2:-1:2].sum()))
    lo, hi = 0.0, 1000.0
    for _ in range(60):
        lo, hi = ((lo + hi) / 2, hi) if sunk((lo + hi) / 2) < 200.0 else (lo, (lo + hi) / 2)
    t0 = (lo + hi) / 2
    w0 = c0 * t0 + a * t0 * t0 / 2.0
    c1 = c0 + a * t0
    t1 = ((v - c1) - math.sqrt((v - c1) ** 2 - 2.0 * a * length)) / a
    assert _error(world, LEG, (v,)) == pytest.approx(_closed(NAV.rate(False) * (v * t1 + w0)), rel=2e-4)
    # the planned times are the mission's from its start at t = 0 (the launch not among them)
    t = ((v - c0) - math.sqrt((v - c0) ** 2 - 2.0 * a * length)) / a
    assert traverse(world, LEG, v).times[-1] == pytest.approx(t, rel=2e-4)


def test_mission_check_and_the_budget_take_the_water_distance_and_a_vertical_leg_keeps_its_share():
    c = 0.5
    world = _world(3000.0, UniformCurrent((0.0, c, 0.0)))  # across the track: V·T = L·V/sqrt(V² − c²)
    pts = np.array([[1000.0, 3000.0, -200.0], [1000.0, 3000.0, -900.0], [9000.0, 3000.0, -900.0]])
    v = 1.5
    w = traverse(world, pts, v).leg_water_m()
    # the dive held over the point: ground speed sqrt(V² − c²) down, c·T across through the water
    assert w[0] == pytest.approx(c * 700.0 / math.sqrt(v * v - c * c), rel=1e-9)
    assert w[1] == pytest.approx(8000.0 * v / math.sqrt(v * v - c * c), rel=1e-9)
    got = check_navigation(world, pts, ("", "", ""), NAV, water_m=w).budget.error_m[-1]
    assert got == pytest.approx(_closed(NAV.rate(False) * w.sum()), rel=1e-9)


def test_a_dwell_is_no_leg_s_water_even_where_the_sub_steps_miss_the_vertex_by_rounding():
    """Still water: each leg's water distance is its horizontal length, a surface dwell between them or not (the
    dwell's node repeats the vertex, which the last sub-step reaches only to rounding: before, its 120 s counted as
    180 m of the next leg's water run, 3.9× on a 62.5 m leg of mariana-nav)."""
    pts = np.array([[1000.1, 3000.3, -200.7], [1062.6, 3000.3, -177.9], [1125.1, 3000.3, -0.7],
                    [7000.3, 3100.9, -200.1]])
    h = np.hypot(*np.diff(pts[:, :2], axis=0).T)
    for dwell in (None, [0.0, 0.0, 120.0, 0.0], [0.0, 300.0, 120.0, 0.0]):
        w = traverse(_world(3000.0), pts, 1.5, dwell=dwell).leg_water_m()
        np.testing.assert_allclose(w, h, rtol=1e-9)
