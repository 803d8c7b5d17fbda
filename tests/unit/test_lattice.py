"""The lean lattice of the reference: node fields, the compiled free-edge test, A*, memory per node."""

from __future__ import annotations

import tracemalloc
from dataclasses import replace

import numpy as np
import pytest

from auvplan.cost import CostModel
from auvplan.io.files.limits import lattice_bytes
from auvplan.planners import GridParams, GridReference
from auvplan.planners.core.common import cost_model_for, search_box
from auvplan.planners.grid.lattice import HALF, edge_states, node_fields
from auvplan.sim import planning_problem
from auvplan.world import Bounds, LambOseenVortices, Margins, Sphere, Terrain, UniformCurrent, World


def _ridge_world() -> World:
    """A steep one-cell ridge (40 m over 10 m) across a flat seabed and a sphere above it: many
    lattice edges between free nodes dip under the seabed's margin or into the sphere's."""
    x = np.arange(0.0, 301.0, 10.0)
    z = np.full((x.size, x.size), -100.0)
    z[:, x == 150.0] = -60.0
    return World(Bounds(0, 300, 0, 300, -100, 0), Terrain(x, x, z), obstacles=(Sphere((150.0, 150.0, -30.0), 25.0),),
                 margins=Margins(min_altitude=8.0, min_depth=2.0, obstacle=5.0))


def test_compiled_edge_test_agrees_with_the_exact_segment_test_on_every_edge():
    """Each of the 13 directions on a lattice straddling a steep ridge and a sphere: an edge is free
    exactly when both nodes are free and the World's exact segment test passes (brute force)."""
    world = _ridge_world()
    axes = (np.arange(5.0, 300.0, 13.0), np.arange(5.0, 300.0, 17.0), np.arange(-95.0, -1.0, 9.0))
    free, alt, obs, _ = node_fields(world, axes, currents=False)
    xyz = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    assert np.array_equal(free, world.is_free(xyz, moving=False))
    flat = xyz.reshape(-1, 3)
    steps = np.array([13.0, 17.0, 9.0])
    rejected = 0
    for off in HALF:
        got = edge_states(world, free, alt, obs, steps, off, flat.__getitem__).reshape(free.shape)
        sl_a = tuple(slice(max(0, -d), n - max(0, d)) for d, n in zip(off, free.shape))
        sl_b = tuple(slice(max(0, d), n - max(0, -d)) for d, n in zip(off, free.shape))
        seg = np.stack([xyz[sl_a], xyz[sl_b]], axis=-2)
        want = free[sl_a] & free[sl_b] & world.segments_free(seg, moving=False)
        assert np.array_equal(got[sl_a].astype(bool), want), off
        assert not got[tuple(slice(n - max(0, d), n) if d > 0 else slice(0, 0) for d, n in zip(off, free.shape))].any()
        rejected += int((free[sl_a] & free[sl_b] & ~want).sum())
    assert rejected > 50  # the scene does cut edges between free nodes


def test_astar_finds_the_full_searchs_cost_and_settles_fewer_nodes(salish):
    """With the start given the search is A* (consistent straight-line heuristic): the start's
    best lattice cost is the full Dijkstra's to the last bit of rounding, on fewer settled nodes."""
    _, world, mission = salish
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, name="grid")
    model, (lo, hi) = cost_model_for(prob, spec), search_box(prob)
    full = GridReference(world, prob.goal, model, lo, hi, spec.grid)
    aimed = GridReference(world, prob.goal, model, lo, hi, spec.grid, start=prob.start)
    ids, w = full._connect(prob.start, towards=False)
    assert (w + aimed._dist[ids]).min() == pytest.approx((w + full._dist[ids]).min(), rel=1e-12)
    assert aimed.settled < 0.8 * full.settled
    chain = [int(ids[np.argmin(w + aimed._dist[ids])])]
    while chain[-1] != aimed._goal_id:
        chain.append(int(aimed._next[chain[-1]]))
    assert np.allclose(aimed._dist[chain], full._dist[chain], rtol=1e-12)  # every node on the path is settled
    assert world.path_free(aimed.query(prob.start))


def test_lattice_memory_grows_with_nodes_not_edges():
    """About a million nodes with up to 26 edges each, a current on the cost objective: what the
    reference keeps is 13 bytes a node, and the peak of every numpy buffer while it is built
    (node fields by slabs, one bit per edge, the search) stays under 60 bytes a node."""
    world = World(Bounds(0, 4000, 0, 4000, -500, 0), currents=UniformCurrent((0.3, -0.2, 0.0)),
                  margins=Margins(min_altitude=0.0, min_depth=10.0))
    params = GridParams(cell=20.0, cell_z=20.0, objective="cost")
    GridReference(world, [3800.0, 3500.0, -100.0], CostModel(), np.array([0.0, 0.0, -500.0]),
                  np.array([4000.0, 4000.0, 0.0]), replace(params, cell=400.0))  # compiled code loaded first
    tracemalloc.start()
    try:
        ref = GridReference(world, [3800.0, 3500.0, -100.0], CostModel(), np.array([0.0, 0.0, -500.0]),
                            np.array([4000.0, 4000.0, 0.0]), params)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    held = sum(v.nbytes for v in vars(ref).values() if isinstance(v, np.ndarray) and v.base is None)
    assert ref.nodes > 900_000 and ref.edges > 20 * ref.nodes
    assert held / ref.nodes <= 13.1
    assert peak / ref.nodes < 60
    # the scenario budget's estimate ([limits] memory_mb) is the measured peak within a factor 2, never below
    assert peak <= lattice_bytes(ref.nodes) <= 2.0 * peak


@pytest.mark.parametrize("objective", ["length", "cost"])
def test_field_equals_scipy_dijkstra_on_the_same_graph(objective):
    """The compiled cost-to-go field (inline-key heap, precomputed direction steps and lengths) is
    scipy.sparse.csgraph's Dijkstra on the same graph: the free edges of :func:`edge_states`, each
    weighted by its length or by :func:`auvplan.planners.grid.lattice.dijkstra._edge_weight`'s cost in a
    sheared current (mean of the two nodes' currents), and the goal's links."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    from auvplan.cost import energy_mode, propulsion_power
    from auvplan.planners.grid.lattice import OFFSETS
    from auvplan.planners.grid.lattice.dijkstra import _edge_weight
    world = replace(_ridge_world(), currents=LambOseenVortices(np.array([[120.0, 200.0]]), np.array([300.0]),
                                                               np.array([60.0])))
    model = CostModel()
    params = GridParams(cell=13.0, cell_z=9.0, objective=objective)
    ref = GridReference(world, [280.0, 260.0, -40.0], model, np.array([0.0, 0.0, -100.0]),
                        np.array([300.0, 300.0, 0.0]), params)
    free, alt, obs, cur = node_fields(world, ref.axes, currents=True)
    steps = np.array([ref.cell, ref.cell, ref.cell_z])
    n, shape = ref.nodes, ref.shape
    vec = OFFSETS * steps
    args = (model.w_length, model.w_energy * model.scale, model.speed, propulsion_power(model), energy_mode(model))
    rows, cols, wts = [], [], []
    for s, off in enumerate(OFFSETS):
        src = np.flatnonzero(edge_states(world, free, alt, obs, steps, off, ref._coords))
        dst = src + int((off[0] * shape[1] + off[1]) * shape[2] + off[2])
        w = np.array([_edge_weight(u, v, s, vec, cur, objective == "cost", *args) for u, v in zip(src, dst)])
        rows += [src]
        cols += [dst]
        wts += [w]
    near, w_goal = ref._connect(ref.goal, towards=True)
    keep = np.isfinite(w_goal)
    rows.append(near[keep])
    cols.append(np.full(int(keep.sum()), n))
    wts.append(np.maximum(w_goal[keep], 1e-12))
    r, c, w = np.concatenate(rows), np.concatenate(cols), np.concatenate(wts)
    ok = np.isfinite(w)
    graph = coo_matrix((w[ok], (r[ok], c[ok])), shape=(n + 1, n + 1)).tocsr()
    want = dijkstra(graph.T, indices=n)[:n].reshape(shape)  # reversed: from the goal over incoming edges
    got = ref.cost_to_go
    assert np.array_equal(np.isfinite(got), np.isfinite(want))
    assert np.isfinite(want).sum() > 0.5 * free.sum()
    fin = np.isfinite(want)
    assert np.allclose(got[fin], want[fin], rtol=1e-12, atol=0.0)


def test_heap_pops_in_key_order_after_decrease_keys():
    """The indexed heap with inline keys against sorting: 2 000 random keys queued, a third of them
    lowered in place (decrease-key), then popped: the keys come out sorted, each node once, each with
    its last key, and ``pos`` marks every popped node."""
    from auvplan.planners.grid.heap import pop, push

    rng = np.random.default_rng(5)
    n = 2000
    key = rng.uniform(0.0, 100.0, n)
    heap, hkey, pos = np.empty(n, np.int32), np.empty(n), np.full(n, -1, np.int32)
    size = 0
    for u in range(n):
        size = push(heap, hkey, pos, size, u, key[u])
    for u in rng.choice(n, n // 3, replace=False):
        key[u] -= rng.uniform(0.0, key[u])
        size = push(heap, hkey, pos, size, int(u), key[u])
    out, keys = [], []
    while size:
        out.append(int(heap[0]))
        keys.append(float(hkey[0]))
        size = pop(heap, hkey, pos, size, -2)
    assert sorted(out) == list(range(n))
    assert keys == sorted(keys)
    assert np.array_equal(np.array(keys), key[out])
    assert (pos == -2).all()


def test_column_slopes_bound_the_seabeds_rise_within_a_cell_of_each_column(salish):
    """The local slope of :func:`lattice_slopes` is a Lipschitz constant of the real seabed round each
    column: for random point pairs within one cell of a column, the seabed's difference is at most
    that slope times their horizontal distance; it never exceeds the terrain's steepest slope and is
    well below it on most columns (else the local bound would gain nothing)."""
    from auvplan.planners.grid.lattice import lattice_slopes

    _, world, _ = salish
    t = world.terrain
    assert t is not None
    cell = 2.5 * t.dx
    ax = np.arange(t.x[0] + 3.0, t.x[-1], cell)
    ay = np.arange(t.y[0] + 7.0, t.y[-1], cell)
    shape = (ax.size, ay.size, 2)
    xyz = np.stack(np.meshgrid(ax, ay, np.array([-10.0, -5.0]), indexing="ij"), axis=-1).reshape(-1, 3)
    slope = lattice_slopes(world, shape, (cell, cell, 5.0), xyz.__getitem__)
    assert slope.shape == shape[:2] and np.all(slope <= t.max_slope) and np.median(slope) < 0.5 * t.max_slope
    rng = np.random.default_rng(35)
    i, j = rng.integers(0, ax.size, 20_000), rng.integers(0, ay.size, 20_000)
    p, q = (np.stack([ax[i], ay[j]], axis=1) + rng.uniform(-cell, cell, (20_000, 2)) for _ in range(2))
    rise = np.abs(t.elevation(p[:, 0], p[:, 1]) - t.elevation(q[:, 0], q[:, 1]))
    assert np.all(rise <= slope[i, j] * np.linalg.norm(p - q, axis=1) * (1 + 1e-9) + 1e-9)
