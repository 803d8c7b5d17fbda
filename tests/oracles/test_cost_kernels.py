"""The objective's fast paths against their plain counterparts: the compiled spline sampling, the seabed
box bound before the exact walk, and a uniform current passed as one vector."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import BSpline

from auvplan.cost import CostModel, evaluate_paths, segment_energy
from auvplan.path import clamped_knots, sample_population
from auvplan.world import Margins, UniformCurrent, World
from auvplan.world.kernels.terrain import BOX_CELLS, box_floor_kernel, lipschitz_bound_kernel


@pytest.mark.parametrize("k", [4, 8, 11])
@pytest.mark.parametrize("order", [0, 1, 2])
def test_spline_sampling_matches_scipy_per_path(k, order):
    rng = np.random.default_rng(k + 10 * order)
    control = rng.uniform(-3e5, 3e5, (2, 3, k, 3))
    for n in (2, 57, 200):
        got = sample_population(control, n, order)
        assert got.shape == (2, 3, n, 3)
        u = np.linspace(0.0, 1.0, n)
        for idx in np.ndindex(2, 3):
            spline = BSpline(clamped_knots(k), control[idx], 3)
            want = (spline.derivative(order) if order else spline)(u)
            scale = np.abs(want).max() + 1.0
            assert np.allclose(got[idx], want, rtol=0.0, atol=1e-12 * scale)
    one = sample_population(control[0, 0], 9, order)  # no leading axis
    assert np.array_equal(one, sample_population(control[:1, :1], 9, order)[0, 0])


def _segments(terrain, rng, n):
    """Random segments over (and around) a real seabed, 10 m to 4 km long, near and far above it."""
    x0, x1, y0, y1 = terrain.extent
    a = np.column_stack([rng.uniform(x0 - 2000, x1 + 2000, n), rng.uniform(y0 - 2000, y1 + 2000, n)])
    step = rng.normal(size=(n, 2))
    step *= (10.0 ** rng.uniform(1.0, np.log10(4000.0), n) / np.linalg.norm(step, axis=1))[:, None]
    b = a + step
    za = terrain.elevation(a[:, 0], a[:, 1]) + rng.uniform(-50.0, 800.0, n)
    zb = terrain.elevation(b[:, 0], b[:, 1]) + rng.uniform(-50.0, 800.0, n)
    return np.column_stack([a, za]), np.column_stack([b, zb])


def test_box_floor_is_a_lower_bound_and_the_highest_node_under_the_box(marcus):
    _, world, _ = marcus
    t = world.terrain
    coef, x0, y0, dx, dy, _ = t.kernel_data
    rng = np.random.default_rng(3)
    a, b = _segments(t, rng, 3000)
    exact = t.min_altitude_between(a, b)  # the exact walk, no bound
    nx, ny = t.x.size - 1, t.y.size - 1
    scanned = 0
    for p, q, e in zip(a, b, exact, strict=True):
        floor = box_floor_kernel(t.cell_max, x0, y0, dx, dy, *p, *q)
        assert floor <= e
        lo = np.clip(np.floor((np.minimum(p[:2], q[:2]) - (x0, y0)) / (dx, dy)), 0, (nx - 1, ny - 1)).astype(int)
        hi = np.clip(np.floor((np.maximum(p[:2], q[:2]) - (x0, y0)) / (dx, dy)), 0, (nx - 1, ny - 1)).astype(int)
        if np.prod(hi - lo + 1) > BOX_CELLS:
            assert floor == -math.inf
            continue
        scanned += 1
        top = t.z[lo[1]:hi[1] + 2, lo[0]:hi[0] + 2].max()  # the nodes of the cells the box meets
        assert floor == pytest.approx(min(p[2], q[2]) - top, abs=1e-5)
    assert scanned > 2000
    assert box_floor_kernel(t.cell_max, x0, y0, dx, dy, math.nan, 0.0, -10.0, 1.0, 1.0, -10.0) == -math.inf


def test_bounded_cost_is_bit_identical_to_the_exact_cost_and_the_box_decides(marcus):
    _, world, _ = marcus
    t = world.terrain
    rng = np.random.default_rng(5)
    n, s = 60, 150
    x0, x1, y0, y1 = t.extent
    start = np.column_stack([rng.uniform(x0, x1, n), rng.uniform(y0, y1, n)])[:, None]
    end = np.column_stack([rng.uniform(x0, x1, n), rng.uniform(y0, y1, n)])[:, None]
    xy = start + np.linspace(0.0, 1.0, s)[:, None] * (end - start)
    z = t.elevation(xy[..., 0], xy[..., 1]) + rng.uniform(60.0, 600.0, (n, 1)) + rng.normal(0.0, 30.0, (n, s))
    p = np.concatenate([xy, z[..., None]], axis=-1)
    w = World(world.bounds, t, UniformCurrent((0.2, -0.1, 0.0)), (), margins=Margins(min_altitude=100.0))
    model = CostModel()
    exact, fast = evaluate_paths(w, p, model, exact=True), evaluate_paths(w, p, model)
    assert 0 < (exact.violations > 0).sum() < n
    for key in ("total", "length", "terrain", "energy", "energy_j", "duration_s", "violations"):
        assert np.array_equal(getattr(fast, key), getattr(exact, key)), key
    assert np.all(fast.min_clearance <= exact.min_clearance)
    # the box bound cleared segments the Lipschitz bound could not (and the walk was not needed)
    coef, gx0, gy0, dx, dy, lip = t.kernel_data
    a, b = p[:, :-1].reshape(-1, 3), p[:, 1:].reshape(-1, 3)
    ga, gb = t.altitude(a), t.altitude(b)
    decided = sum(lipschitz_bound_kernel(lip, *pa, *pb, g1, g2) < 100.0
                  <= box_floor_kernel(t.cell_max, gx0, gy0, dx, dy, *pa, *pb)
                  for pa, pb, g1, g2 in zip(a, b, ga, gb, strict=True))
    assert decided > 0.05 * len(a)


class _SameEverywhere(UniformCurrent):
    """A uniform current seen as a general field (the vector filled at every midpoint)."""


def test_uniform_current_as_one_vector_matches_the_filled_field(marcus):
    _, world, _ = marcus
    rng = np.random.default_rng(8)
    p = np.stack([np.linspace(world.bounds.xmin, world.bounds.xmax, 40) + rng.normal(0, 500, (7, 40)),
                  np.linspace(world.bounds.ymin, world.bounds.ymax, 40) + rng.normal(0, 500, (7, 40)),
                  rng.uniform(-1500.0, -50.0, (7, 40))], axis=-1)
    for vector in ((0.3, -0.2, 0.0), (1.2, 1.0, 0.0)):  # the second beats the vehicle on some segments
        one = World(world.bounds, world.terrain, UniformCurrent(vector), ())
        filled = World(world.bounds, world.terrain, _SameEverywhere(vector), ())
        for energy in ("physical", "document", "document-vehicle"):
            model = CostModel(energy=energy)
            got, want = evaluate_paths(one, p, model), evaluate_paths(filled, p, model)
            for key in ("total", "energy", "energy_j", "duration_s", "violations"):
                assert np.array_equal(getattr(got, key), getattr(want, key)), (vector, energy, key)
            for x, y in zip(segment_energy(one, p[:, :-1], p[:, 1:], model),
                            segment_energy(filled, p[:, :-1], p[:, 1:], model), strict=True):
                assert np.array_equal(x, y)
    assert (evaluate_paths(one, p, CostModel()).violations > 0).any()  # blocked segments were exercised
