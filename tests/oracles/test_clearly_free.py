"""``validate``'s start and goal decided without a compiled kernel (issue 56), against the compiled seabed.

:meth:`Terrain.elevation_bounds` (numpy) must lie within its bound of :meth:`Terrain.elevation` (the
compiled kernel, fused multiply-adds) everywhere, edges and outside included, on a rough non-square grid
with an origin far from zero; :meth:`World.clearly_free` may say True only where :meth:`World.explain`
finds nothing, also for points within a rounding of ``min_altitude`` above the seabed and about a turned
ellipsoid at the obstacle margin (its distance a compiled foot-point search).
"""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.world import Bounds, Margins, Sphere, Terrain, World


def _terrain() -> Terrain:
    rng = np.random.default_rng(56)
    x = 350_000.0 + np.arange(37) * 412.5  # far from zero: the cell fractions carry the coordinates' rounding
    y = -90_000.0 + np.arange(23) * 250.0
    z = -3800.0 + 900.0 * rng.standard_normal((y.size, x.size))
    return Terrain(x, y, z, name="rough")


def _points(t: Terrain, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    x0, x1, y0, y1 = t.extent
    px = rng.uniform(x0 - 500.0, x1 + 500.0, n)
    py = rng.uniform(y0 - 500.0, y1 + 500.0, n)
    px[: n // 4] = rng.choice(t.x, n // 4)  # on grid lines, where the cell chosen may differ
    py[n // 4: n // 2] = rng.choice(t.y, n // 2 - n // 4)
    return px, py


def test_numpy_elevation_is_within_its_bound_of_the_compiled_one():
    t = _terrain()
    px, py = _points(t, 4000, np.random.default_rng(1))
    exact = t.elevation(px, py)
    est, err = t.elevation_bounds(px, py)
    assert np.all(np.abs(est - exact) <= err)
    assert np.all(err < 1e-6) and np.all(err > 0.0)  # a bound, and not a vacuous one


@pytest.mark.parametrize("with_sphere", [False, True])
def test_clearly_free_only_where_explain_finds_nothing(with_sphere):
    t = _terrain()
    b = Bounds(t.x[0], t.x[-1], t.y[0], t.y[-1], -6000.0, 0.0)
    obstacles = (Sphere((t.x[10], t.y[10], -3000.0), 400.0),) if with_sphere else ()
    w = World(b, t, obstacles=obstacles, margins=Margins(min_altitude=25.0, obstacle=10.0))
    rng = np.random.default_rng(2)
    px, py = _points(t, 600, rng)
    inside = (px >= b.xmin) & (px <= b.xmax) & (py >= b.ymin) & (py <= b.ymax)
    px, py = px[inside], py[inside]
    _, err = t.elevation_bounds(px, py)
    # heights just above, at and below min_altitude (within the bound), and well clear
    dz = np.concatenate([rng.uniform(-2.0, 2.0, px.size // 2) * err[: px.size // 2],
                         rng.uniform(5.0, 500.0, px.size - px.size // 2)])
    pz = t.elevation(px, py) + 25.0 + dz
    said, free = 0, 0
    for p in np.column_stack([px, py, pz]):
        if not p[2] < 0.0:
            continue
        clear, why = w.clearly_free(p), w.explain(p)
        assert not (clear and why), (p, why)
        said += clear
        free += not why
    assert said >= 0.4 * free  # the fast path is taken for most free points (those well clear)



def test_clearly_free_near_a_turned_ellipsoid_only_where_explain_finds_nothing():
    """Points about an ellipsoid turned by yaw, pitch and roll, at the obstacle margin and around it: the
    lower bound never calls free a point the compiled foot-point distance puts within the margin."""
    from auvplan.world import Ellipsoid

    e = Ellipsoid((0.0, 0.0, -500.0), (300.0, 120.0, 60.0), yaw=0.7, pitch=0.3, roll=-0.5)
    w = World(Bounds(-1000.0, 1000.0, -1000.0, 1000.0, -1000.0, 0.0), None, obstacles=(e,),
              margins=Margins(obstacle=15.0))
    rng = np.random.default_rng(3)
    u = rng.normal(size=(200, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    pts = np.asarray(e.center) + u * rng.uniform(40.0, 700.0, (200, 1))
    said = 0
    for p in pts:
        clear, why = w.clearly_free(p), w.explain(p)
        assert not (clear and why), (p, why)
        said += clear
    assert said > 50


def _long_grid(nx: int, ny: int) -> Terrain:
    """A rough grid centred on the origin, long along one axis: at its far end the cell fractions carry the
    rounding of thousands of cells (``fx`` large) while the other axis' fraction is small."""
    rng = np.random.default_rng(nx * 10 + ny)
    x = (np.arange(nx) - nx // 2) * 7.3
    y = (np.arange(ny) - ny // 2) * 5.1
    return Terrain(x, y, -3800.0 + 900.0 * rng.standard_normal((ny, nx)), name="long")


@pytest.mark.parametrize(("nx", "ny"), [(8001, 5), (5, 8001)])
def test_the_bound_covers_the_compiled_seabed_along_a_long_grid_centred_on_the_origin(nx, ny):
    """Oracle: the compiled kernel.  A grid centred on the origin (its first node far on the negative side) and
    8 000 cells long one way: the far half's fractions are ~4 000 cells from the grid's first node; the numpy
    value must stay within the bound of the compiled one there too (the bound measured from the first node,
    each magnitude counted positive)."""
    t = _long_grid(nx, ny)
    rng = np.random.default_rng(7)
    x0, x1, y0, y1 = t.extent
    px = rng.uniform(0.5 * x1, x1, 20_000) if nx > ny else rng.uniform(x0, x1, 20_000)
    py = rng.uniform(0.5 * y1, y1, 20_000) if ny > nx else rng.uniform(y0, y1, 20_000)
    est, err = t.elevation_bounds(px, py)
    assert np.all(np.abs(est - t.elevation(px, py)) <= err) and np.all(err > 0.0)


def test_the_bound_is_64_roundings_of_the_terms_times_the_fractions_size():
    """Pinned by hand (the docstring's bound): one cell of a 3 x 2 grid whose first node is off the origin;
    a = 10, b = -4, c = 6, e = 2 at (x, y) = (130, -45): u = 0.5, v = 0.25, fx = 1.5, fy = 0.25."""
    t = Terrain(np.array([100.0, 120.0, 140.0]), np.array([-50.0, -30.0]),
                np.array([[0.0, 10.0, 6.0], [0.0, 16.0, 14.0]]))
    zb, err = t.elevation_bounds(130.0, -45.0)
    assert float(zb) == pytest.approx(10.0 - 4.0 * 0.5 + 6.0 * 0.25 + 2.0 * 0.125)
    eps = np.finfo(float).eps
    assert float(err) == pytest.approx(64.0 * eps * (10.0 + 4.0 + 6.0 + 2.0) * (2.0 + 1.5 + 0.25), rel=1e-12, abs=0.0)


def test_clearly_free_refuses_what_is_not_one_finite_point():
    """Oracle: the contract (one finite point, else "not clearly": False, never an error or True)."""
    t = _terrain()
    w = World(Bounds(t.x[0], t.x[-1], t.y[0], t.y[-1], -6000.0, 0.0), t, margins=Margins(min_altitude=25.0))
    free = (t.x[5], t.y[5], float(t.elevation(t.x[5], t.y[5])) + 200.0)
    assert w.clearly_free(free) and not w.explain(free)
    assert not w.clearly_free([free, free])
    for k in range(3):
        for bad in (np.nan, np.inf, -np.inf):
            p = list(free)
            p[k] = bad
            assert w.clearly_free(p) is False


def test_clearly_free_at_exactly_zero_slack_and_a_moving_obstacle():
    """Oracle: :meth:`World.explain`.  No seabed: points exactly at the surface margin and at the bounds' face
    (slack 0: free) and half a metre inside them are clearly free; a point inside a moving sphere at ``t``
    (where it has moved to) is not, one clear of it is."""
    from auvplan.world.moving import LinearMotion, MovingObstacle

    mover = MovingObstacle(Sphere((0.0, 0.0, 0.0), 50.0), LinearMotion((0.0, 0.0, -500.0), (10.0, 0.0, 0.0)))
    w = World(Bounds(-1000.0, 1000.0, -1000.0, 1000.0, -1000.0, 0.0), None, moving=(mover,),
              margins=Margins(min_depth=4.0, max_depth=900.0, obstacle=5.0))
    for p in ((0.0, 500.0, -4.0), (0.0, 500.0, -4.5), (-1000.0, 500.0, -300.0), (-999.5, 500.0, -300.0),
              (0.0, 500.0, -900.0), (0.0, 500.0, -899.5)):
        assert not w.explain(p) and w.clearly_free(p), p
    inside = (300.0, 0.0, -500.0)  # the sphere's centre at t = 30 s
    assert w.explain(inside, 30.0) and not w.clearly_free(inside, 30.0)
    assert not w.explain(inside, 0.0) and w.clearly_free(inside, 0.0)


def test_clearly_free_keeps_its_pad_of_a_micrometre_per_metre_off_an_ellipsoid():
    """Pinned: on a turned ellipsoid's shortest axis the lower bound is the distance itself, so the pad
    (1 + R) um (R its largest semi-axis) decides: within the margin (``explain`` objects) never clearly free,
    half a pad outside it not clearly free yet, half a micrometre beyond the pad clearly free."""
    from auvplan.world import Ellipsoid

    e = Ellipsoid((0.0, 0.0, -500.0), (300.0, 120.0, 60.0), yaw=0.7, pitch=0.3, roll=-0.5)
    w = World(Bounds(-1000.0, 1000.0, -1000.0, 1000.0, -1000.0, 0.0), None, obstacles=(e,),
              margins=Margins(obstacle=15.0))
    pad = 1e-6 * (1.0 + e.bounding_radius)
    axis = e.to_body(np.asarray(e.center) + np.eye(3))[:, 2]  # the shortest semi-axis' direction in the world
    for off, free, clear in ((-0.5 * pad, False, False), (0.5 * pad, True, False), (pad + 0.5e-6, True, True)):
        p = np.asarray(e.center) + axis * (60.0 + 15.0 + off)
        assert (not w.explain(p), w.clearly_free(p)) == (free, clear), off


def test_the_bound_covers_the_compiled_seabed_beside_isolated_cliffs_on_grid_lines():
    """Oracle: the compiled kernel.  40 grids of nodes 0.5 m deep with one in seven raised or sunk 300 m to 5 km
    (cliffs beside flat cells), non-square cells of 0.5-3 m up to 1 000 km from the origin, points on the grid lines
    (where the kernel may take the neighbouring cell, on either side) and between them."""
    rng = np.random.default_rng(14)
    for _ in range(40):
        nx, ny = int(rng.integers(4, 30)), int(rng.integers(4, 30))
        x = float(rng.choice([0.0, 1e6, -1e6])) + np.arange(nx) * rng.uniform(0.5, 3.0)
        y = float(rng.choice([0.0, 7e5, -3e5])) + np.arange(ny) * rng.uniform(0.5, 3.0)
        z = np.where(rng.random((ny, nx)) < 0.15, rng.choice([300.0, -300.0, 5000.0], (ny, nx)), -0.5)
        t = Terrain(x, y, z)
        px, py = rng.uniform(x[0], x[-1], 3000), rng.uniform(y[0], y[-1], 3000)
        px[:1000], py[1000:2000] = rng.choice(x, 1000), rng.choice(y, 1000)
        est, err = t.elevation_bounds(px, py)
        assert np.all(np.abs(est - t.elevation(px, py)) <= err)
