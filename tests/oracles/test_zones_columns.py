"""The zones' signed distance of a lattice's nodes column by column (:func:`auvplan.world.zones.exact.
near_distance_kernel`): a point sharing ``x, y`` with the one before it reuses that point's zones and horizontal
distances.  The answers are those of every point measured alone (bit for bit) and of shapely's exact distance."""

from __future__ import annotations

import numpy as np
import shapely
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


def _two_squares():  # noqa: ANN202
    """Zone A over [-60, -20] x [-100, -40] (depths 10-40 m), zone B over [900, 940]^2 (surface to the seabed):
    the grid's cell is 32.5 m (span 1 040 m / 32), so points within 65 m of a footprint are measured exactly."""
    from auvplan.world.zones import Zone, Zones

    a = Zone("a", shapely.box(-60.0, -100.0, -20.0, -40.0), top=10.0, bottom=40.0)
    return Zones((a, Zone("b", shapely.box(900.0, 900.0, 940.0, 940.0))), None)


def test_the_reuse_of_a_column_s_zones_is_decided_on_x_and_y_of_the_point_before():
    """A lone column (its first point shares x, y with its last), a point whose x and y equal the y of the one
    before (x differs), a point whose y equals the z of the one before (x shared): every answer is shapely's
    (mutants21: each such point was measured with the zones of another)."""
    zones = _two_squares()
    column = np.array([[-10.0, -10.0, -5.0], [-10.0, -10.0, -25.0], [-10.0, -10.0, -50.0]])
    x_is_y = np.array([[5.0, -15.0, -20.0], [-15.0, -15.0, -20.0]])  # 2nd: x = y = the 1st's y
    y_is_z = np.array([[-10.0, -30.0, -45.0], [-10.0, -45.0, -20.0]])  # 2nd: y = the 1st's z, x shared
    for p in (column, x_is_y, y_is_z):
        exact = zones.signed_distance(p, exact=True)
        assert np.all(exact < 2.0 * zones._grid[2])  # all measured by the kernel, none capped
        np.testing.assert_allclose(zones.signed_distance(p), exact, atol=1e-9)
    # by hand: the column 10 m east of A's edge x = -20 and 30 m north of y = -40 (hypot(10, 30) with the
    # band's vertical term), (-15, -15) 5 m east and 25 m north of A's corner (-20, -40), (-10, -45) 10 m east
    # of A, inside its y-range
    np.testing.assert_allclose(zones.signed_distance(column), [np.hypot(np.hypot(10, 30), 5.0), np.hypot(10, 30),
                                                              np.hypot(np.hypot(10, 30), 10.0)], atol=1e-9)
    np.testing.assert_allclose(zones.signed_distance(x_is_y)[1], np.hypot(5.0, 25.0), atol=1e-9)
    np.testing.assert_allclose(zones.signed_distance(y_is_z)[1], 10.0, atol=1e-9)


def test_a_point_by_the_grid_s_last_cell_reads_only_the_grid_s_cells():
    """A point beyond the top-right corner of the last zone scans up to the grid's last cell and no further
    (a scan past the last column reads past the cell table); its distance is shapely's: 5 sqrt(2) m."""
    zones = _two_squares()
    x0, y0, cell, nx, ny = zones._grid[:5]
    p = np.array([[945.0, 945.0, -20.0], [950.0, 930.0, -20.0]])
    i, j = np.floor((p[:, 0] - x0) / cell), np.floor((p[:, 1] - y0) / cell)
    assert np.all(i + 2 >= nx - 1) and np.all(j + 2 >= ny - 1)  # the scans reach the last column and row
    np.testing.assert_allclose(zones.signed_distance(p), [5.0 * np.sqrt(2.0), 10.0], atol=1e-9)
    np.testing.assert_allclose(zones.signed_distance(p), zones.signed_distance(p, exact=True), atol=1e-9)


def test_the_grid_s_edge_rows_and_columns_list_no_zone_their_neighbours_do_not():
    """The premise of skipping the edge rows and columns being harmless (docs/mutants.md section 8): the
    grid starts one cell before the lowest footprint and ends at least one after the highest, so its first and
    last row and column meet a footprint at most on their inner edge, shared with the next row or column."""
    rng = np.random.default_rng(8)
    for zones in (random_world(rng, 40).zones, random_world(rng, 7).zones, _two_squares()):
        *_, nx, ny, start, ids = zones._grid[:7]
        cells = [[set(ids[start[j * nx + i]:start[j * nx + i + 1]].tolist()) for i in range(nx)] for j in range(ny)]
        for i in range(nx):
            assert cells[0][i] <= cells[1][i] and cells[ny - 1][i] <= cells[ny - 2][i]
        for j in range(ny):
            assert cells[j][0] <= cells[j][1] and cells[j][nx - 1] <= cells[j][nx - 2]
