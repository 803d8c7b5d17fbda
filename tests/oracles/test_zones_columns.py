"""The zones' signed distance of a lattice's nodes column by column (:func:`auvplan.world.zones.exact.
near_distance_kernel`): a point sharing ``x, y`` with the one before it reuses that point's zones and horizontal
distances.  The answers are those of every point measured alone (bit for bit) and of shapely's exact distance."""

from __future__ import annotations

import numpy as np
from benchmarks.zones import random_world


def _columns(rng: np.random.Generator) -> np.ndarray:
    """Lattice-like nodes ``(N, 3)``: columns on a grid (consecutive columns share ``x``, a row's last and the
    next row's first share neither), eight levels each, in the lattice's C order; then random lone points."""
    gx, gy = rng.uniform(-200.0, 3200.0, 12), rng.uniform(-200.0, 3200.0, 10)
    levels = np.sort(rng.uniform(-300.0, 0.0, 8))
    p = np.stack(np.meshgrid(gx, gy, levels, indexing="ij"), axis=-1).reshape(-1, 3)
    lone = np.column_stack([rng.uniform(0.0, 3000.0, (200, 2)), rng.uniform(-300.0, 0.0, 200)])
    return np.vstack([p, lone])


def test_a_column_s_nodes_measure_as_each_node_alone_and_as_shapely():
    rng = np.random.default_rng(21)
    world = random_world(rng, 40)
    zones = world.zones
    p = _columns(rng)
    fast = zones.signed_distance(p)
    order = rng.permutation(p.shape[0])  # no two neighbours share x and y: every point measured alone
    alone = np.empty_like(fast)
    alone[order] = zones.signed_distance(p[order])
    np.testing.assert_array_equal(fast, alone)
    exact = zones.signed_distance(p, exact=True)
    near = exact < 2.0 * zones._grid[2]
    assert near.sum() > 500 and (fast[near] < 0).sum() > 20  # nodes near and inside zones of every band
    assert np.all(fast <= exact + 1e-9)
    np.testing.assert_allclose(fast[near], exact[near], atol=1e-9)
