"""Currents, obstacles and the World's clearance queries."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize

from auvplan.errors import DataError
from auvplan.world import (
    Bounds,
    CircleMotion,
    Ellipsoid,
    GriddedCurrent,
    LambOseenVortices,
    LinearMotion,
    MovingObstacle,
    RandomWalkMotion,
    Sphere,
    UniformCurrent,
    WaypointMotion,
    World,
)
from helpers import flat_world


# ---------------------------------------------------------------- Lamb–Oseen
def test_lamb_oseen_closed_form():
    v = LambOseenVortices([(100.0, -50.0)], [2000.0], [300.0])
    rng = np.random.default_rng(1)
    p = np.c_[rng.uniform(-2000, 2000, (500, 2)), np.zeros(500)]
    u = v.velocity(p)
    dx, dy = p[:, 0] - 100.0, p[:, 1] + 50.0
    r2 = dx**2 + dy**2
    f = 2000.0 / (2 * np.pi * r2) * (1 - np.exp(-r2 / 300.0**2))
    assert np.allclose(u[:, 0], -f * dy, rtol=1e-12) and np.allclose(u[:, 1], f * dx, rtol=1e-12)
    assert np.all(u[:, 2] == 0.0)


def test_lamb_oseen_far_field_and_centre_limit():
    gamma, delta = 5000.0, 100.0
    v = LambOseenVortices([(0.0, 0.0)], [gamma], [delta])
    r = 50 * delta
    speed = np.linalg.norm(v.velocity([[r, 0.0, 0.0]])[0])
    assert speed == pytest.approx(gamma / (2 * np.pi * r), rel=1e-9)
    # solid-body rotation near the centre, continuous through r = 0
    for r in (1e-9, 1e-5, 1e-3):
        s = np.linalg.norm(v.velocity([[r, 0.0, 0.0]])[0])
        assert s == pytest.approx(gamma * r / (2 * np.pi * delta**2), rel=1e-6)
    assert np.all(v.velocity([[0.0, 0.0, 0.0]]) == 0.0)
    # counter-clockwise for positive circulation: north-going on the east side
    assert v.velocity([[delta, 0.0, 0.0]])[0, 1] > 0


def test_lamb_oseen_vorticity_is_the_curl():
    """Document 002's eq. 3 is the vorticity: compare with the curl by finite differences."""
    v = LambOseenVortices([(0.0, 0.0), (300.0, 100.0)], [3000.0, -1000.0], [150.0, 80.0])
    p = np.array([[50.0, 20.0, 0.0], [200.0, -90.0, 0.0], [310.0, 95.0, 0.0]])
    h = 1e-3
    ex, ey = np.array([h, 0, 0]), np.array([0, h, 0])
    curl = (v.velocity(p + ex)[:, 1] - v.velocity(p - ex)[:, 1]) / (2 * h) - (
        v.velocity(p + ey)[:, 0] - v.velocity(p - ey)[:, 0]
    ) / (2 * h)
    assert np.allclose(v.vorticity(p), curl, rtol=1e-5)


def test_lamb_oseen_max_speed_bounds_the_field():
    v = LambOseenVortices([(0.0, 0.0)], [4000.0], [200.0])
    r = np.linspace(0, 2000, 20001)
    s = np.linalg.norm(v.velocity(np.c_[r, np.zeros_like(r), np.zeros_like(r)]), axis=1)
    assert s.max() == pytest.approx(v.max_speed, rel=1e-4)


def test_gridded_current_is_linear_in_space_and_time():
    x = np.linspace(0, 1000, 5)
    y = np.linspace(0, 500, 3)
    z = np.array([-100.0, 0.0])
    t = np.array([0.0, 100.0])
    T, Z, Y, X = np.meshgrid(t, z, y, x, indexing="ij")
    u = 0.001 * X + 0.002 * Y + 0.003 * Z + 0.004 * T
    v = -u
    g = GriddedCurrent(x, y, z, u, v, None, t)
    p = np.array([[123.0, 321.0, -37.0], [999.0, 1.0, -99.0]])
    out = g.velocity(p, 42.0)
    want = 0.001 * p[:, 0] + 0.002 * p[:, 1] + 0.003 * p[:, 2] + 0.004 * 42.0
    assert np.allclose(out[:, 0], want) and np.allclose(out[:, 1], -want) and np.allclose(out[:, 2], 0)
    # clamped outside (deeper than the deepest level)
    assert np.allclose(g.velocity([[123.0, 321.0, -500.0]], 0.0)[0, 0], 0.001 * 123 + 0.002 * 321 - 0.3)


@pytest.mark.parametrize("levels, times", [(4, 3), (1, 1), (3, 1)])
def test_gridded_current_matches_scipy_on_uneven_axes(levels, times):
    """Independent oracle: scipy's RegularGridInterpolator on random data and uneven axes, with
    points and times outside the grid clamped to its faces."""
    from scipy.interpolate import RegularGridInterpolator

    rng = np.random.default_rng(levels * 10 + times)
    x = np.cumsum(rng.uniform(50, 400, 9))
    y = np.cumsum(rng.uniform(50, 400, 7))
    z = -np.cumsum(rng.uniform(10, 300, levels))[::-1]
    t = np.cumsum(rng.uniform(100, 900, times))
    u, v, w = (rng.normal(size=(times, levels, y.size, x.size)) for _ in range(3))
    g = GriddedCurrent(x, y, z, u, v, w, t if times > 1 else None)
    p = rng.uniform([x[0] - 300, y[0] - 300, z[0] - 100], [x[-1] + 300, y[-1] + 300, z[-1] + 100], (2000, 3))
    for when in (t[0] - 50.0, t[0] + 0.37 * (t[-1] - t[0]), t[-1] + 50.0):
        got = g.velocity(p, when if times > 1 else 0.0)
        axes = [a if a.size > 1 else np.r_[a, a + 1.0] for a in (t, z, y, x)]
        data = np.stack([u, v, w], axis=-1)
        data = np.tile(data, [2 if a.size == 1 else 1 for a in (t, z, y, x)] + [1])
        lo, hi = [a[0] for a in axes], [a[-1] for a in axes]
        q = np.clip(np.c_[np.full(len(p), when), p[:, 2], p[:, 1], p[:, 0]], lo, hi)
        want = RegularGridInterpolator(axes, data)(q)
        assert np.allclose(got, want, rtol=1e-12, atol=1e-12)


def test_world_rejects_current_grid_that_does_not_cover_bounds():
    x = np.linspace(0, 500, 3)
    g = GriddedCurrent(x, x, np.zeros(1), np.zeros((1, 3, 3)), np.zeros((1, 3, 3)), name="small")
    with pytest.raises(DataError, match="does not cover"):
        World(Bounds(0, 1000, 0, 1000, -100, 0), currents=g)


# ---------------------------------------------------------------- obstacles
def _numerical_ellipsoid_distance(e: Ellipsoid, p: np.ndarray) -> float:
    """Independent oracle: min |q - p| subject to Σ q_i²/a_i² = 1 (SLSQP from several starts)."""
    a = np.asarray(e.semi_axes)
    pb = e.to_body(p)
    cons = {"type": "eq", "fun": lambda q: (q / a) @ (q / a) - 1.0, "jac": lambda q: 2 * q / a**2}
    starts = [pb / np.sqrt(((pb / a) ** 2).sum())] + [s * a * np.eye(3)[k] for k in range(3) for s in (1, -1)]
    best = np.inf
    for q0 in starts:
        r = minimize(lambda q: (q - pb) @ (q - pb), q0, jac=lambda q: 2 * (q - pb), constraints=[cons],
                     method="SLSQP", options={"ftol": 1e-15, "maxiter": 500})
        if r.success and abs(cons["fun"](r.x)) < 1e-10:
            best = min(best, np.sqrt(r.fun))
    return float(best)


def test_ellipsoid_distance_matches_numerical_minimisation():
    e = Ellipsoid((10.0, -5.0, 3.0), (6.0, 3.0, 2.0), yaw=0.4, pitch=-0.3, roll=0.2)
    rng = np.random.default_rng(7)
    pts = np.asarray(e.center) + rng.normal(0, 6, (12, 3))
    d = e.distance(pts)
    for p, dk in zip(pts, d):
        ref = _numerical_ellipsoid_distance(e, p)
        assert abs(abs(dk) - ref) < 1e-6
    inside = ((e.to_body(pts) / np.asarray(e.semi_axes)) ** 2).sum(axis=1) < 1
    assert np.all((d < 0) == inside)


def test_ellipsoid_ray_distance_overestimates_and_lower_bound_holds():
    e = Ellipsoid((0.0, 0.0, 0.0), (3.0, 1.0, 1.0))
    rng = np.random.default_rng(3)
    p = rng.normal(0, 4, (2000, 3))
    p = p[e.distance(p) > 0]
    true = e.distance(p)
    assert np.all(e.ray_distance(p) >= true - 1e-9)
    assert np.all(e.lower_bound_distance(p) <= true + 1e-9)
    assert (e.ray_distance(p) / true).max() > 1.3  # the document's distance overstates clearance


def test_sphere_distance_and_segments():
    s = Sphere((0.0, 0.0, 0.0), 2.0)
    assert s.distance([[5.0, 0.0, 0.0]])[0] == pytest.approx(3.0)
    seg = np.array([[[-5.0, 1.9, 0.0], [5.0, 1.9, 0.0]], [[-5.0, 2.5, 0.0], [5.0, 2.5, 0.0]]])
    assert s.segments_hit(seg).tolist() == [True, False]
    assert s.segments_hit(seg, margin=1.0).tolist() == [True, True]


def test_ellipsoid_segment_test_is_exact_without_margin_and_conservative_with_one():
    e = Ellipsoid((0.0, 0.0, 0.0), (4.0, 1.0, 1.0), yaw=0.5)
    rng = np.random.default_rng(11)
    a = rng.uniform(-6, 6, (3000, 3))
    b = rng.uniform(-6, 6, (3000, 3))
    seg = np.stack([a, b], axis=1)
    s = np.linspace(0, 1, 2001)
    dmin = np.array([e.distance(a[k] + s[:, None] * (b[k] - a[k])).min() for k in range(300)])
    hit0 = e.segments_hit(seg[:300])
    assert np.array_equal(hit0[np.abs(dmin) > 1e-3], (dmin < 0)[np.abs(dmin) > 1e-3])
    hit1 = e.segments_hit(seg[:300], margin=0.5)
    assert np.all(hit1[dmin < 0.5 - 1e-3])  # never misses a contact within the margin


def test_motion_models():
    lin = LinearMotion((0.0, 0.0, -10.0), (1.0, 2.0, 0.0))
    assert np.allclose(lin.position(3.0), [3.0, 6.0, -10.0])
    circ = CircleMotion((0.0, 0.0, -5.0), 10.0, 40.0)
    assert np.allclose(circ.position(10.0), [0.0, 10.0, -5.0], atol=1e-9)
    assert circ.speed == pytest.approx(2 * np.pi * 10 / 40)
    wp = WaypointMotion(np.array([[0.0, 0, 0], [10.0, 0, 0]]), 1.0, loop=True)
    assert np.allclose(wp.position(15.0), [5.0, 0, 0])  # on the way back
    rw1 = RandomWalkMotion((0.0, 0.0, -5.0), 1.0, 0.2, seed=4, bounds=(-50, 50, -50, 50))
    rw2 = RandomWalkMotion((0.0, 0.0, -5.0), 1.0, 0.2, seed=4, bounds=(-50, 50, -50, 50))
    t = np.arange(0, 3000, 7.0)
    track = rw1.position(t)
    assert np.array_equal(track, rw2.position(t))
    assert np.all(np.abs(track[:, :2]) <= 50 + 1e-9)
    step = np.linalg.norm(np.diff(rw1.position(np.arange(0, 100.0)), axis=0), axis=1)
    assert np.all(step <= 1.0 + 1e-9)


def test_world_clearance_and_segments():
    w = flat_world(depth=100.0, min_altitude=5.0, min_depth=2.0,
                   obstacles=(Sphere((500.0, 500.0, -50.0), 20.0),), obstacle=3.0)
    p = np.array([[100.0, 100.0, -50.0], [100.0, 100.0, -97.0], [500.0, 500.0, -50.0], [100.0, 100.0, -1.0]])
    c = w.clearances(p)
    assert c["altitude"][0] == pytest.approx(45.0) and c["altitude"][1] == pytest.approx(-2.0)
    assert c["obstacles"][2] == pytest.approx(-23.0) and c["surface"][3] == pytest.approx(-1.0)
    assert w.is_free(p).tolist() == [True, False, False, False]
    assert "seabed" in w.explain(p[1]) and "static obstacle" in w.explain(p[2])
    seg = np.array([[[0.0, 500.0, -50.0], [1000.0, 500.0, -50.0]], [[0.0, 100.0, -50.0], [1000.0, 100.0, -50.0]]])
    assert w.segments_free(seg).tolist() == [False, True]


def test_moving_obstacles_in_clearance():
    mo = MovingObstacle(Sphere((0, 0, 0), 5.0), LinearMotion((0.0, 500.0, -50.0), (10.0, 0.0, 0.0)),
                        disappears=60.0)
    w = flat_world(depth=100.0)
    w = World(w.bounds, w.terrain, moving=(mo,), margins=w.margins)
    p = np.array([[300.0, 500.0, -50.0]])
    assert w.clearances(p, t=30.0)["moving"][0] == pytest.approx(-5.0)
    assert w.clearances(p, t=0.0)["moving"][0] == pytest.approx(295.0)
    assert np.isinf(w.clearances(p, t=61.0)["moving"][0])  # removed mid-mission
    assert not w.is_free(p, t=30.0)[0] and w.is_free(p, t=30.0, moving=False)[0]


def test_uniform_current_shape():
    u = UniformCurrent((0.1, -0.2, 0.0))
    assert u.velocity(np.zeros((4, 7, 3))).shape == (4, 7, 3)
    assert u.max_speed == pytest.approx(np.hypot(0.1, 0.2))


def test_ellipsoid_segment_test_with_a_margin_is_exact():
    """Against a brute-force minimum of the true distance along each segment."""
    e = Ellipsoid((1.0, -2.0, 0.5), (4.0, 1.5, 1.0), yaw=0.5, pitch=0.3)
    rng = np.random.default_rng(12)
    a = rng.uniform(-7, 7, (400, 3))
    b = a + rng.normal(size=(400, 3)) * 3
    seg = np.stack([a, b], axis=1)
    s = np.linspace(0, 1, 4001)
    dmin = np.array([e.distance(a[k] + s[:, None] * (b[k] - a[k])).min() for k in range(len(a))])
    hit = e.segments_hit(seg, margin=0.5)
    clear = np.abs(dmin - 0.5) > 1e-4
    assert np.array_equal(hit[clear], (dmin < 0.5)[clear])
    assert (hit[clear] != e.segments_hit(seg, margin=0.0)[clear]).sum() >= 5  # the margin band is exercised
    from auvplan.geometry import point_segment_distance

    k = 1.0 + 0.5 / 1.0  # the scaled ellipsoid a conservative test would use
    scaled = point_segment_distance(np.zeros(3), e.to_body(a) / (np.array(e.semi_axes) * k),
                                    e.to_body(b) / (np.array(e.semi_axes) * k)) < 1.0
    assert (scaled & ~hit).sum() >= 5  # segments it would have rejected although they keep the margin
