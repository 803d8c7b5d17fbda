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
