"""The glider's closed loop and dive-cycle planning pieces (issue 58) on synthetic worlds with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.planners.timeopt.glider import DepthAveragedCurrent, cycle, endurance_days, surfacings
from auvplan.sim.glider import fly_glider
from auvplan.vehicles.glider import GliderParams, crab_heading, yo_timing
from auvplan.world import Bounds, World
from auvplan.world.currents.fields import CurrentField, UniformCurrent

BOX = Bounds(-60000.0, 60000.0, -60000.0, 60000.0, -1000.0, 0.0)


class Shear(CurrentField):
    """East current growing linearly with depth: u = a + b·depth."""

    def __init__(self, a: float, b: float) -> None:
        self.a, self.b = a, b

    def velocity(self, points, t=0.0):
        p = np.asarray(points, dtype=float)
        out = np.zeros_like(p)
        out[..., 0] = self.a + self.b * (-p[..., 2])
        return out

    @property
    def max_speed(self):
        return abs(self.a) + abs(self.b) * 1000.0


def test_crab_heading_cancels_the_cross_current():
    """The heading's through-water velocity plus the current points along the course."""
    rng = np.random.default_rng(58)
    for _ in range(50):
        course, v = rng.uniform(-math.pi, math.pi), rng.uniform(0.2, 0.4)
        c = rng.uniform(-0.15, 0.15, 2)
        h = crab_heading(course, v, c)
        g = v * np.array([math.sin(h), math.cos(h)]) + c
        assert abs(g[0] * math.cos(course) - g[1] * math.sin(course)) < 1e-12  # no cross-track component
        assert g @ [math.sin(course), math.cos(course)] > 0


def test_depth_average_of_a_linear_shear_is_its_mid_depth_value():
    """Averaged over climb_depth..dive_depth (or min_altitude above a flat seabed), exactly."""
    w = World(BOX, currents=Shear(0.1, 0.001))
    dac = DepthAveragedCurrent(w, 10.0, 200.0, 10.0)
    v = dac.velocity(np.array([[0.0, 0.0, -5.0], [1000.0, 5.0, -150.0]]), 0.0)
    np.testing.assert_allclose(v[:, 0], 0.1 + 0.001 * 105.0, rtol=1e-12)
    assert np.all(v[:, 1:] == 0.0)


def test_cycle_and_endurance_add_up():
    """A cycle is yos x (dive + climb) + the surface legs + the surface time; endurance = battery / mean power."""
    g = GliderParams(yos=4, surface_time_s=900.0)
    c, yo = cycle(g), yo_timing(g, g.climb_depth_m, g.dive_depth_m)
    top = g.climb_depth_m / -yo.w_dive + g.climb_depth_m / yo.w_climb
    assert c.duration_s == pytest.approx(4 * (yo.dive_s + yo.climb_s) + top + 900.0)
    assert c.energy_j == pytest.approx(c.duration_s * g.hotel_w + 900.0 * g.surface_power_w + 4 * yo.pump_j)
    assert endurance_days(g) == pytest.approx(g.battery_wh * 3600.0 * c.duration_s / c.energy_j / 86400.0)
    timed = cycle(GliderParams(yos=9, surface_every_s=5000.0))  # surface_every_s caps the yos per cycle
    assert timed.underwater_s < 5000.0 + yo.dive_s + yo.climb_s + top


def test_surfacings_are_on_the_path_every_cycle():
    pts = np.array([[0.0, 0.0], [1000.0, 0.0], [1000.0, 2000.0]])
    xy, ts = surfacings(pts, [0.0, 1000.0, 3000.0], 700.0)
    np.testing.assert_allclose(ts, [700.0, 1400.0, 2100.0, 2800.0, 3000.0])
    np.testing.assert_allclose(xy, [[700, 0], [1000, 400], [1000, 1100], [1000, 1800], [1000, 2000]])


@pytest.mark.parametrize("current", [(0.0, 0.0), (0.0, 0.1), (0.12, -0.05), (-0.2, 0.1)])
def test_loop_estimates_a_uniform_current_and_holds_its_course(current):
    """Uniform current: every depth-averaged estimate after the first is the current; the fixes stay near
    the course line (the heading corrected), and in still water the cycle's distance is the flight model's."""
    g = GliderParams(dive_depth_m=100.0, yos=2, capture_radius_m=500.0)
    w = World(BOX, currents=UniformCurrent((*current, 0.0)))
    goal = np.array([0.0, 12000.0])
    tr = fly_glider(w, g, (0.0, 0.0), [goal], 0.0, dt=10.0)
    assert tr.arrived and tr.reason == "arrived"
    np.testing.assert_allclose(tr.dac[1:], np.tile(current, (len(tr.dac) - 1, 1)), atol=1e-9)
    # from the first fix on the current is known: the fixes lie on the line from it to the goal (the
    # underwater crab at the cycle's mean speed over-corrects as much as the surface drift under-corrects;
    # exactly without a cross current, within 0.1 % of the leg with one: the 10 s steps time the phases)
    a, d = tr.fixes[1, 1:], goal - tr.fixes[1, 1:]
    rel = tr.fixes[1:, 1:] - a
    off = np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0]) / np.hypot(*d)
    tol = 1e-6 if current[0] == 0.0 else 1e-3 * 12000.0
    assert off.max() < tol
    told = fly_glider(w, g, (0.0, 0.0), [goal], 0.0, dt=10.0, dac0=current)  # known from the start
    assert np.abs(told.fixes[:, 1]).max() < tol
    assert tr.xyz[:, 2].min() == pytest.approx(-100.0) and tr.xyz[:, 2].max() <= 0.0
    assert tr.inflections == 2 * (len(tr.fixes) - 1)
    if current == (0.0, 0.0):
        c = cycle(g)
        assert np.hypot(*np.diff(tr.fixes[:2, 1:], axis=0)[0]) == pytest.approx(c.distance_m, rel=0.01)


def test_loop_keeps_min_altitude_over_a_shallow_seabed():
    """Over 60 m of water with a 10 m altitude the yos turn at 50 m, not at dive_depth_m."""
    from auvplan.world.terrain import Terrain

    x = np.linspace(-60000.0, 60000.0, 7)
    terrain = Terrain(x, x, np.full((7, 7), -60.0))
    w = World(BOX, terrain=terrain, currents=UniformCurrent((0.0, 0.0, 0.0)))
    tr = fly_glider(w, GliderParams(dive_depth_m=200.0), (0.0, 0.0), [(0.0, 3000.0)], 0.0, min_altitude=10.0)
    assert tr.arrived
    assert tr.xyz[:, 2].min() == pytest.approx(-50.0)


def test_loop_surfaces_every_surface_every_s():
    """With surface_every_s the glider surfaces at the first top after that long, not after yos yos."""
    g = GliderParams(dive_depth_m=100.0, yos=50, surface_every_s=2500.0, capture_radius_m=500.0)
    w = World(BOX, currents=UniformCurrent((0.0, 0.0, 0.0)))
    tr = fly_glider(w, g, (0.0, 0.0), [(0.0, 6000.0)], 0.0)
    yo = yo_timing(g, g.climb_depth_m, g.dive_depth_m)
    gaps = np.diff(tr.fixes[:, 0])[:-1]  # (the last cycle ends at the goal)
    assert len(gaps) >= 2
    assert np.all(gaps >= 2500.0 + g.surface_time_s) and np.all(gaps <= 2500.0 + yo.dive_s + yo.climb_s
                                                                 + g.surface_time_s + 60.0)
