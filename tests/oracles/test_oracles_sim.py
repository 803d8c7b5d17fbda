"""Oracle tests for the mutation targets sim, grid (the lattice), world and local (issue #23,
docs/mutants.md section 2).

Each test is an independent computation (Python's ``heapq``, scipy's Dijkstra, the World's exact
segment test, numbers by hand) aimed at mutants of ``tools/mutate.py`` that survived the older tests;
the docstrings name the bug each one catches.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from auvplan._types import Status
from auvplan.guidance.avoidance.local import apf_force
from auvplan.guidance.avoidance.params import AvoidanceParams
from auvplan.planners.grid.heap import _sift_down
from auvplan.planners.grid.heap import pop as _pop
from auvplan.planners.grid.heap import push as _push
from auvplan.planners.grid.lattice import HALF, OFFSETS, edge_states, node_fields, search
from auvplan.sim import Mission, simulate
from auvplan.world import Bounds, Margins, Sphere, Terrain, UniformCurrent, World
from helpers import flat_world


# ---------------------------------------------------------------------- grid: the lattice's seabed shortcut
def _ridge(along: str) -> World:
    """Flat seabed at -100 m with a one-cell ridge (to -60 m, 5 m cells: a tent of slope 8) along x at
    y = 50 m (``along="x"``) or along y at x = 50 m; 10 m minimum altitude."""
    g = np.arange(0.0, 101.0, 5.0)
    z = np.full((g.size, g.size), -100.0)  # (ny, nx)
    if along == "x":
        z[g == 50.0, :] = -60.0
    else:
        z[:, g == 50.0] = -60.0
    return World(Bounds(0, 100, 0, 100, -100, 0), Terrain(g, g, z), margins=Margins(min_altitude=10.0, min_depth=0.0))


@pytest.mark.parametrize("along", ["x", "y"])
def test_lattice_edges_across_a_seabed_ridge_are_exactly_the_free_segments(along):
    """Lattice nodes at the feet of a thin tent ridge, 5 m either side of its crest (10 m steps in x
    and y, 8 m in z, 12 to 52 m above the flat seabed, all free): the edges across the ridge pass
    under its crest or less than 10 m above it, up to 24 m above (the level edge 44 m up passes 4 m
    above the crest; the one descending from 52 to 44 m up passes 8 m above it).  For each of the 13
    directions, the edges the lattice accepts are exactly the pairs of free nodes the World's exact
    segment test calls free, and a dense-sampled seabed under each accepted edge agrees.  The ridge's
    flanks span the whole edge, so the Lipschitz bound (g_a + g_b - |dz| - G L_h) / 2 is the true
    minimum there: a bound fed the wrong horizontal length (|(dx, dz)| for an edge along y), the
    signed dz, or a larger factor accepts an edge through the altitude margin."""
    world = _ridge(along)
    axes = (np.arange(5.0, 100.0, 10.0), np.arange(5.0, 100.0, 10.0), np.arange(-88.0, -47.0, 8.0))
    steps = np.array([10.0, 10.0, 8.0])
    free, alt, obs, _ = node_fields(world, axes, currents=False)
    xyz = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    flat = xyz.reshape(-1, 3)
    assert free.all()
    cut = 0
    for off in HALF:
        got = edge_states(world, free, alt, obs, steps, off, flat.__getitem__).reshape(free.shape)
        a = tuple(slice(max(0, -d), n - max(0, d)) for d, n in zip(off, free.shape))
        b = tuple(slice(max(0, d), n - max(0, -d)) for d, n in zip(off, free.shape))
        seg = np.stack([xyz[a], xyz[b]], axis=-2)
        want = free[a] & free[b] & world.segments_free(seg, moving=False)
        np.testing.assert_array_equal(got[a].astype(bool), want, err_msg=str(off))
        cut += int((free[a] & free[b] & ~want).sum())
        # and independently of the World: the dense-sampled seabed under each accepted edge
        s = np.linspace(0.0, 1.0, 201)[:, None]
        pts = seg[want][:, None, 0] + s * (seg[want][:, None, 1] - seg[want][:, None, 0])
        assert (pts[..., 2] - world.terrain.elevation(pts[..., 0], pts[..., 1]) >= 10.0 - 1e-9).all(), off
    assert cut >= 40  # the ridge does cut edges between free nodes (along the axis across it and diagonals)


def test_lattice_fields_round_down_to_the_nearest_single():
    """``down32``: the largest single-precision value not above each double (the lattice keeps
    altitudes and clearances that way, so they are never optimistic): doubles exactly representable
    in single precision are kept, the others go to the float32 just below."""
    from auvplan.planners.grid.lattice import down32

    rng = np.random.default_rng(3)
    a = np.r_[rng.normal(0.0, 100.0, 2000), 0.5, -3.25, 0.0, 1e-3, -1e-3, 16777217.0]
    b = down32(a)
    assert b.dtype == np.float32
    assert (b.astype(float) <= a).all()
    assert (np.nextafter(b, np.float32(np.inf)).astype(float) > a).all()
    np.testing.assert_array_equal(b[-6:-3], [0.5, -3.25, 0.0])


def test_lattice_node_fields_are_the_worlds_static_clearances():
    """``node_fields`` against the World's own point queries, node by node: free nodes are
    ``World.is_free(moving=False)`` (a moving obstacle parked on some nodes does not count; the island
    and the sphere do), altitudes and obstacle slacks are the World's rounded down to single precision.
    A second lattice of 6 × 2 × 10 000 nodes (no seabed) is evaluated in two slabs of x (100 000 points
    a slab): every slab, the last one too, is filled."""
    from auvplan.planners.grid.lattice import down32
    from auvplan.world.moving import LinearMotion, MovingObstacle

    parked = MovingObstacle(Sphere((0.0, 0.0, 0.0), 40.0), LinearMotion((200.0, 200.0, -60.0), (0.0, 0.0, 0.0)))
    world = replace(_plane_world(land=True), moving=(parked,))
    axes = (np.arange(20.0, 1000.0, 40.0), np.arange(20.0, 800.0, 40.0), np.arange(-130.0, -5.0, 15.0))
    free, alt, obs, cur = node_fields(world, axes, currents=False)
    xyz = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    want = world.is_free(xyz, moving=False)
    np.testing.assert_array_equal(free, want)
    assert not want.all()
    assert (want & ~world.is_free(xyz, moving=True)).sum() > 5  # nodes under the parked obstacle stay free
    c = world.clearances(xyz, moving=False)
    np.testing.assert_array_equal(alt, down32(c["altitude"] + world.margins.min_altitude))
    np.testing.assert_array_equal(obs, down32(c["obstacles"]))
    assert cur.shape == (0, 3)
    big = World(Bounds(0, 100, 0, 10, -10_000, 0), obstacles=(Sphere((50.0, 5.0, -5000.0), 1000.0),),
                margins=Margins(min_depth=0.0))
    axes = (np.arange(0.0, 101.0, 20.0), np.array([0.0, 10.0]), -np.arange(10_000.0))
    free, _, obs, cur = node_fields(big, axes, currents=True)
    xyz = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    np.testing.assert_array_equal(free, big.is_free(xyz, moving=False))
    np.testing.assert_array_equal(obs, down32(big.clearances(xyz, moving=False)["obstacles"]))
    assert cur.shape == (120_000, 3) and not cur.any()


# ---------------------------------------------------------------------- grid: the indexed binary heap
def _check_heap(heap: np.ndarray, hkey: np.ndarray, pos: np.ndarray, key: np.ndarray, size: int,
                members: set[int]) -> None:
    assert set(heap[:size].tolist()) == members
    for i in range(size):
        assert pos[heap[i]] == i
        assert hkey[i] == key[heap[i]]  # the inline key is the node's
        if i:
            assert key[heap[(i - 1) >> 1]] <= key[heap[i]]


def test_lattice_heap_pops_in_heapq_order_with_decrease_key():
    """The search's indexed heap (``_push`` with decrease-key, ``_pop``: last entry to the root,
    ``_sift_down``) against Python's ``heapq`` with lazy deletion, on 3 000 seeded random
    operations over 200 nodes; after every operation the heap property holds and ``pos`` indexes the
    heap.  The heap array is pre-filled with other node ids, so a sift that reads past the heap's end
    takes in a node that was never queued."""
    rng = np.random.default_rng(23)
    n = 200
    heap = rng.permutation(n).astype(np.int32)  # garbage beyond the heap's end
    pos = np.full(n, -1, dtype=np.int32)
    key = rng.uniform(-1.0, 0.0, n)  # stale keys of nodes not queued: smaller than any queued one
    hkey = rng.uniform(-1.0, 0.0, n)  # garbage keys beyond the heap's end, smaller than any queued one
    ref: list[tuple[float, int]] = []
    members: set[int] = set()
    size, popped = 0, 0
    for _ in range(3000):
        u = int(rng.integers(n))
        if rng.random() < 0.6 and u not in members:
            key[u] = rng.uniform(1.0, 100.0)
            size = _push(heap, hkey, pos, size, u, key[u])
            members.add(u)
            heapq.heappush(ref, (key[u], u))
        elif rng.random() < 0.5 and u in members:  # decrease-key
            key[u] = key[u] - rng.uniform(0.0, key[u] - 0.5)
            size = _push(heap, hkey, pos, size, u, key[u])
            heapq.heappush(ref, (key[u], u))
        elif size:
            v = int(heap[0])
            while ref[0][0] != key[ref[0][1]] or ref[0][1] not in members:  # lazy deletion
                heapq.heappop(ref)
            assert v == heapq.heappop(ref)[1]
            members.remove(v)
            size = _pop(heap, hkey, pos, size, -1)  # -1: may be queued again
            assert pos[v] == -1
            popped += 1
        _check_heap(heap, hkey, pos, key, size, members)
    assert popped > 500


def test_lattice_sift_down_reads_nothing_past_the_heap_end():
    """``_sift_down(heap, hkey, pos, size)`` restores a heap whose root key grew: with 2 to 30 of 40
    nodes queued and every node past the end a smaller key, the result is a heap of the same nodes
    (a sift that compares with ``heap[size]`` would take one of those in)."""
    rng = np.random.default_rng(7)
    for _ in range(300):
        n, size = 40, int(rng.integers(2, 31))
        heap = rng.permutation(n).astype(np.int32)
        key = rng.uniform(10.0, 20.0, n)
        key[heap[size:]] = rng.uniform(0.0, 1.0, n - size)
        hkey = key[heap].copy()  # past the end: the smaller keys of nodes not queued
        pos = np.full(n, -1, dtype=np.int32)
        members = heap[:size].tolist()
        s = 0
        for u in members:
            s = _push(heap, hkey, pos, s, u, key[u])
        key[heap[0]] += rng.uniform(0.0, 15.0)
        hkey[0] = key[heap[0]]
        _sift_down(heap, hkey, pos, size)
        _check_heap(heap, hkey, pos, key, size, set(members))


# ---------------------------------------------------------------------- grid: the search against scipy
def _edge_costs(u: np.ndarray, v: np.ndarray, vec: np.ndarray, current: np.ndarray, w_length: float,
                w_energy: float, speed: float, power: float) -> np.ndarray:
    """Independent edge cost: length weight x length + energy weight x power x time, the ground speed
    along the edge c∥ + √(V² − c⊥²) in the mean of the two nodes' currents; ``inf`` where blocked."""
    c = (0.5 * (current[u].astype(float) + current[v].astype(float)))
    ds = np.linalg.norm(vec, axis=1)
    c_par = (c * vec).sum(axis=1) / ds
    c_perp2 = (c * c).sum(axis=1) - c_par**2
    ok = speed**2 > c_perp2
    vg = np.where(ok, c_par + np.sqrt(np.where(ok, speed**2 - c_perp2, 0.0)), 0.0)
    return np.where(ok & (vg > 0), w_length * ds + w_energy * power * ds / np.where(vg > 0, vg, 1.0), np.inf)


def _undirected(bits, shape):
    """Keep the edge ``u -> u + OFFSETS[s]`` only where its reverse is free too: the lattice's edges are
    undirected (:func:`edge_bits` sets both bits), and the search reads an edge from its far end's bit."""
    n = int(np.prod(shape))
    ijk = np.stack(np.unravel_index(np.arange(n), shape), axis=1)
    out = bits.copy()
    for s, off in enumerate(OFFSETS):
        rev = s + 13 if s < 13 else s - 13
        v = ijk + off
        inside = np.all((v >= 0) & (v < shape), axis=1)
        has = (bits >> np.uint32(s)) & np.uint32(1) == 1
        back = np.zeros(n, dtype=bool)
        back[inside] = (bits[np.ravel_multi_index(tuple(v[inside].T), shape)] >> np.uint32(rev)) & np.uint32(1) == 1
        out[has & ~back] &= ~np.uint32(1 << s)
    return out


def test_lattice_search_is_scipys_dijkstra_with_random_currents_and_edges():
    """A 9 × 8 × 6 lattice (steps 10, 12, 7 m) with 70 % of its directed edges free at random and a
    random current at every node (up to 1.3 m/s against a 1 m/s vehicle: some edges blocked), cost =
    length + energy: the search's cost-to-go is scipy's Dijkstra over the reversed graph whose edges
    are costed independently (:func:`_edge_costs`), the goal linked to 5 nodes; every next-node hop
    realises the cost; A* towards a start (with a valid lower bound per metre) settles fewer nodes
    and finds the same cost for that start, and for a start exactly on a node; a goal-linked node
    whose own link is dear (200) gets its cheaper cost through its neighbours in both searches."""
    rng = np.random.default_rng(23)
    shape = (9, 8, 6)
    n = int(np.prod(shape))
    steps, origin = np.array([10.0, 12.0, 7.0]), np.array([100.0, -50.0, -80.0])
    bits = np.zeros(n, dtype=np.uint32)
    idx = np.arange(n).reshape(shape)
    ijk = np.stack(np.unravel_index(np.arange(n), shape), axis=1)
    src, dst, s_of = [], [], []
    for s, off in enumerate(OFFSETS):
        v = ijk + off
        inside = np.all((v >= 0) & (v < shape), axis=1)
        take = inside & (rng.random(n) < 0.7)
        bits[take] |= np.uint32(1 << s)
        src.append(np.flatnonzero(take))
        dst.append(idx[tuple(v[take].T)])
        s_of.append(np.full(take.sum(), s))
    src, dst, s_of = np.concatenate(src), np.concatenate(dst), np.concatenate(s_of)
    bits = _undirected(bits, shape)
    edge = (bits[src] >> s_of.astype(np.uint32)) & np.uint32(1) == 1
    src, dst, s_of = src[edge], dst[edge], s_of[edge]
    current = (rng.uniform(-1.0, 1.0, (n, 3)) * [1.3, 1.3, 0.4]).astype(np.float32)
    cost = (1.0, 0.8, 1.0, 2.0, False)
    vec = OFFSETS[s_of] * steps
    w = _edge_costs(src, dst, vec, current, *cost[:4])
    assert np.isinf(w).sum() > 20 and np.isfinite(w).sum() > 1500
    near = np.array([idx[7, 6, 4], idx[8, 6, 4], idx[7, 7, 4], idx[7, 6, 5], idx[8, 7, 5]])
    w_goal = rng.uniform(5.0, 15.0, near.size)
    w_goal[4] = 200.0  # cheaper through its neighbours
    dist, nxt, settled = search(shape, bits, steps, origin, current, cost, (near, w_goal))
    keep = np.isfinite(w)
    graph = coo_matrix((np.r_[w[keep], w_goal], (np.r_[dst[keep], np.full(near.size, n)], np.r_[src[keep], near])),
                       shape=(n + 1, n + 1)).tocsr()
    want = dijkstra(graph, indices=n)
    assert settled == np.isfinite(want).sum() - 1 and settled > 0.9 * n
    # rtol 1e-9: rounding, amplified where c∥ + √(V² − c⊥²) cancels (edges the current nearly blocks)
    np.testing.assert_allclose(dist, want, rtol=1e-9)
    # every hop realises the cost-to-go
    reached = np.flatnonzero(np.isfinite(dist[:n]))
    hop = {(int(a), int(b)): c for a, b, c in zip(src[keep], dst[keep], w[keep])}
    hop.update({(int(a), n): c for a, c in zip(near, w_goal)})
    for u in reached:
        assert dist[u] == pytest.approx(hop[(int(u), int(nxt[u]))] + dist[nxt[u]], rel=1e-9)
    # A*: the start at the lattice's other corner, linked to 3 nodes
    start = origin + np.array([0.5, 0.5, 0.5]) * steps
    sn = np.array([idx[0, 0, 0], idx[1, 0, 0], idx[0, 1, 1]])
    ws = rng.uniform(2.0, 6.0, sn.size)
    xyz = origin + ijk * steps
    per_metre = min(float(np.min(w[keep] / np.linalg.norm(vec[keep], axis=1))),
                    float(np.min(ws / np.linalg.norm(xyz[sn] - start, axis=1))))
    d2, _, settled2 = search(shape, bits, steps, origin, current, cost, (near, w_goal), (sn, ws), start,
                             0.9 * per_metre)
    assert (ws + d2[sn]).min() == pytest.approx((ws + want[sn]).min(), rel=1e-9)
    assert settled2 < settled
    assert want[near[4]] < 100.0 and d2[near[4]] == pytest.approx(want[near[4]], rel=1e-9)
    # a start exactly on a node (the heuristic is 0 there, the node linked at cost ~0)
    on = idx[1, 1, 1]
    d3, _, _ = search(shape, bits, steps, origin, current, cost, (near, w_goal),
                      (np.array([on, idx[2, 1, 1]]), np.array([1e-12, 25.0])), xyz[on], 0.9 * per_metre)
    assert min(1e-12 + d3[on], 25.0 + d3[idx[2, 1, 1]]) == pytest.approx(
        min(want[on], 25.0 + want[idx[2, 1, 1]]), rel=1e-9)


def test_lattice_search_by_length_on_a_line():
    """Length objective on a 5 × 1 × 1 lattice (steps 3 m), its edges free both ways but between nodes 2
    and 3: the cost-to-go to the goal linked to the last node (2 m) is 2 + 3 (4 - i) for nodes 3 and 4
    and the others are unreached; with every edge free it is 2 + 3 (4 - i) for all.  On a 6-node line
    (1 m steps, both ways) with the goal linked to nodes 2, 5, 3 and 0 at costs 1, 2, 100 and 3, node 3
    (queued third, at heap position 2 when node 2 is settled) costs 2 through node 2: a search that
    skips the node at some heap position when relaxing finds 4 (through nodes 5 and 4) or 100."""
    shape = (5, 1, 1)
    bits = np.zeros(5, dtype=np.uint32)
    plus = int(np.flatnonzero((OFFSETS == [1, 0, 0]).all(axis=1))[0])
    minus = int(np.flatnonzero((OFFSETS == [-1, 0, 0]).all(axis=1))[0])
    bits[:4] |= np.uint32(1 << plus)
    bits[1:] |= np.uint32(1 << minus)
    dist, nxt, _ = search(shape, bits, np.array([3.0, 1.0, 1.0]), np.zeros(3), np.zeros((0, 3), np.float32), None,
                          (np.array([4]), np.array([2.0])))
    np.testing.assert_allclose(dist, [14.0, 11.0, 8.0, 5.0, 2.0, 0.0])
    np.testing.assert_array_equal(nxt, [1, 2, 3, 4, 5, -1])
    bits[2] &= ~np.uint32(1 << plus)
    bits[3] &= ~np.uint32(1 << minus)
    dist, _, _ = search(shape, bits, np.array([3.0, 1.0, 1.0]), np.zeros(3), np.zeros((0, 3), np.float32), None,
                        (np.array([4]), np.array([2.0])))
    np.testing.assert_allclose(dist, [np.inf, np.inf, np.inf, 5.0, 2.0, 0.0])
    line = np.zeros(6, dtype=np.uint32)
    line[:5] |= np.uint32(1 << plus)
    line[1:] |= np.uint32(1 << minus)
    dist, _, settled = search((6, 1, 1), line, np.ones(3), np.zeros(3), np.zeros((0, 3), np.float32), None,
                              (np.array([2, 5, 3, 0]), np.array([1.0, 2.0, 100.0, 3.0])))
    np.testing.assert_allclose(dist, [3.0, 2.0, 1.0, 2.0, 3.0, 2.0, 0.0])
    assert settled == 6
    # a 7-node line linked to the goal at both ends: after the first pop one node is left in the heap,
    # which must be moved to the root (else it is lost, and the far half is costed through the near one)
    line = np.zeros(7, dtype=np.uint32)
    line[:6] |= np.uint32(1 << plus)
    line[1:] |= np.uint32(1 << minus)
    dist, _, settled = search((7, 1, 1), line, np.ones(3), np.zeros(3), np.zeros((0, 3), np.float32), None,
                              (np.array([0, 6]), np.array([1.0, 1.0])))
    np.testing.assert_allclose(dist, [1.0, 2.0, 3.0, 4.0, 3.0, 2.0, 1.0, 0.0])
    assert settled == 7


# ---------------------------------------------------------------------- sim: the events of simulate
class _Mover:
    """A moving obstacle with an exact centre and velocity (MovingObstacle's velocity is a finite
    difference, which cannot set up an exact tie)."""

    def __init__(self, centre, velocity) -> None:
        self.c, self.v = np.asarray(centre, dtype=float), np.asarray(velocity, dtype=float)

    def center(self, t: float) -> np.ndarray:
        return self.c + t * self.v

    def velocity(self, t: float) -> np.ndarray:
        return self.v


def test_sim_contact_is_penetration_and_names_what_was_hit():
    """Touching at exactly 0 m (the seabed or an obstacle's surface) is not a collision; any depth below
    it is.  The seabed is named first, even with an obstacle penetrated too; at an altitude of 0 to 1 m
    the obstacle the vehicle is deepest in is named (index into the static, then the moving ones)."""
    from auvplan.sim.events import _contact_event

    p = np.array([10.0, 20.0, -30.0])
    assert _contact_event(0.0, [0.0, 5.0], p, 0.0, (), 1.5) is None
    assert _contact_event(math.inf, [], p, 0.0, (), 1.5) is None
    assert _contact_event(-1e-9, [3.0], p, 0.0, (), 1.5) == (Status.COLLISION, "the seabed")
    assert _contact_event(-0.5, [-2.0, 4.0], p, 0.0, (), 1.5) == (Status.COLLISION, "the seabed")
    assert _contact_event(0.0, [3.0, -1e-9], p, 0.0, (), 1.5) == (Status.COLLISION, "obstacle 1")
    assert _contact_event(0.5, [-0.1, 2.0, -0.3], p, 0.0, (), 1.5) == (Status.COLLISION, "obstacle 2")
    # two static obstacles, then two moving ones (the second hit, slower than the vehicle)
    movers = (_Mover((0.0, 0.0, 0.0), (9.0, 0.0, 0.0)), _Mover(p - (1.0, 0.0, 0.0), (1.0, 0.0, 0.0)))
    assert _contact_event(0.5, [1.0, 2.0, 7.0, -0.2], p, 0.0, movers, 1.5) == (Status.COLLISION, "obstacle 3")


@pytest.mark.parametrize(("velocity", "offset", "alt", "status"), [
    ((1.5, 0.0, 0.0), (1.0, 0.0, 0.0), 0.0, Status.UNAVOIDABLE),  # exactly as fast as the vehicle, head on
    ((1.4999, 0.0, 0.0), (1.0, 0.0, 0.0), 5.0, Status.COLLISION),  # slower
    ((0.0, 2.0, 0.0), (1.0, 0.0, 0.0), 5.0, Status.COLLISION),  # fast but tangential: v_o · (p - c) = 0
    ((2.0, 0.0, 0.0), (0.25, 0.0, 0.0), 0.5, Status.UNAVOIDABLE),  # closing, v_o · (p - c) = 0.5 m²/s
    ((-2.0, 0.0, 0.0), (1.0, 0.0, 0.0), 5.0, Status.COLLISION),  # fast but receding
    ((1.2, 0.0, -0.9), (0.0, 0.0, -1.0), 0.2, Status.UNAVOIDABLE),  # |v_o| = 1.5, rising into the vehicle
])
def test_sim_moving_hit_is_unavoidable_when_at_least_as_fast_and_closing_in(velocity, offset, alt, status):
    """A moving obstacle (index 1 after one static) hit with its centre ``offset`` behind the vehicle:
    UNAVOIDABLE exactly when |v_o| >= V (1.5 m/s) and v_o · (p - c) > 0; also within a metre of the
    seabed (0 to 1 m altitude), where the seabed is not the one hit."""
    from auvplan.sim.events import _contact_event

    p = np.array([100.0, -40.0, -60.0])
    mover = _Mover(p - np.asarray(offset), velocity)
    got = _contact_event(alt, [12.0, -0.3], p, 0.0, (mover,), 1.5)
    assert got is not None and got[0] is status and got[1].startswith("obstacle 1")
    assert ("faster than the vehicle" in got[1]) is (status is Status.UNAVOIDABLE)


def test_sim_arrival_progress_and_deadlock_rules_at_their_boundaries():
    """Arrival at exactly the radius (3-4-5 triangle) counts, only on the last leg; progress must beat
    the best by more than 1 m (exactly 1 m is not progress, 1.5 m is); deadlock after more than
    ``deadlock_time`` without progress and only once the avoidance's escapes have given up (asked only
    when the time is up)."""
    from auvplan.sim.events import PROGRESS_STEP, _arrived, _deadlocked, _progressed

    assert _arrived(True, (3.0, 4.0, 0.0), (0.0, 0.0, 0.0), 5.0)
    assert not _arrived(True, (3.0, 4.0, 0.0), (0.0, 0.0, 0.0), 4.999)
    assert not _arrived(False, (3.0, 4.0, 0.0), (0.0, 0.0, 0.0), 5.0)
    assert PROGRESS_STEP == 1.0
    assert not _progressed(11.0, 10.0) and _progressed(11.5, 10.0) and _progressed(0.5, -1.0)
    assert not _progressed(10.5, 10.0) and not _progressed(9.0, 10.0)
    asked = []

    def stalled(answer: bool):
        return lambda: asked.append(answer) or answer

    assert not _deadlocked(70.0, 10.0, 60.0, None) and _deadlocked(70.1, 10.0, 60.0, None)
    assert not _deadlocked(70.0, 10.0, 60.0, stalled(False)) and asked == []
    assert _deadlocked(70.1, 10.0, 60.0, stalled(False)) and asked == [False]
    assert not _deadlocked(70.1, 10.0, 60.0, stalled(True)) and asked == [False, True]


def _head_current(ground_speed: float) -> World:
    """Open water with a current along -x of V - ``ground_speed`` (V = 1.5 m/s)."""
    return World(Bounds(-5000, 5000, -500, 500, -100, 0), currents=UniformCurrent((ground_speed - 1.5, 0.0, 0.0)))


def test_sim_a_creeping_vehicle_is_not_deadlocked():
    """Against a current that leaves 0.025 m/s of ground speed, the vehicle gains 1.5 m of route
    progress a minute, so every 60 s window beats the best by more than 1 m: no deadlock, TIMEOUT at
    max_time (300 s) 7.5 m along.  At 0.015 m/s (0.9 m a minute) the run is deadlocked at the first
    step more than 60 s after its last progress, the first step (t = 0.1 s: 1.5 mm beat the initial best
    of -1 m by more than 1 m), i.e. at t = 60.2 s."""
    from auvplan.sim import SimParams

    m = Mission("creep", (0, 0, -20), (1000, 0, -20), route=((0, 0, -20), (1000, 0, -20)),
                sim=SimParams(deadlock_time=60.0, max_time=300.0))
    r = simulate(_head_current(0.025), m, guidance="los", rng=0, avoidance="none")
    assert r.status is Status.TIMEOUT and [e[1] for e in r.events] == ["timeout"]
    assert r.position[-1, 0] == pytest.approx(7.5, abs=0.05)
    r = simulate(_head_current(0.015), m, guidance="los", rng=0, avoidance="none")
    assert r.status is Status.DEADLOCK and r.t[-1] == pytest.approx(60.2, abs=1e-9)


def test_sim_an_obstacle_on_the_seabed_hit_half_a_metre_above_it():
    """Level flight 0.5 m above a flat seabed (100 m) into a sphere (5 m) resting there, then into a
    sphere moving head on at 3 m/s (twice the vehicle's speed): the events name the obstacle, not the
    seabed (the vehicle is above it), a COLLISION and an UNAVOIDABLE hit."""
    from auvplan.world.moving import LinearMotion, MovingObstacle

    route = ((100.0, 500.0, -99.5), (600.0, 500.0, -99.5))
    m = Mission("low", route[0], route[-1], route=route)
    world = flat_world(depth=100.0, size=1000.0, obstacles=(Sphere((300.0, 500.0, -99.5), 5.0),))
    r = simulate(world, m, guidance="los", rng=0, avoidance="none")
    assert r.status is Status.COLLISION and "hit obstacle 0" in r.events[-1][2]
    assert 0.0 < r.altitude[-1] < 1.0 and r.position[-1, 0] == pytest.approx(295.0, abs=1.0)
    moving = MovingObstacle(Sphere((0.0, 0.0, 0.0), 5.0), LinearMotion((500.0, 500.0, -99.5), (-3.0, 0.0, 0.0)))
    world = replace(flat_world(depth=100.0, size=1000.0), moving=(moving,))
    r = simulate(world, m, guidance="los", rng=0, avoidance="none")
    assert r.status is Status.UNAVOIDABLE and "hit obstacle 0 (moving" in r.events[-1][2]
    assert 0.0 < r.altitude[-1] < 1.0


# ---------------------------------------------------------------------- world: point and segment tests
def _plane_world(land: bool = False) -> World:
    """Bounds 0-1000 m x 0-800 m x -200-0 m over a plane seabed z = -150 + 0.05 x (-150 to -100 m);
    depth band 10-140 m, 5 m above the seabed, 2 m from a sphere (60 m at (500, 400, -70)); with
    ``land``, an island x 700-900, y 600-700 m (burnt into the seabed)."""
    import shapely

    from auvplan.world import Land

    g = np.arange(0.0, 1001.0, 50.0)
    z = np.broadcast_to(-150.0 + 0.05 * g[None, :], (g[g <= 800.0].size, g.size))
    return World(Bounds(0, 1000, 0, 800, -200, 0), Terrain(g, g[g <= 800.0], z),
                 obstacles=(Sphere((500.0, 400.0, -70.0), 60.0),),
                 margins=Margins(min_altitude=5.0, min_depth=10.0, max_depth=140.0, obstacle=2.0),
                 land=Land(shapely.box(700.0, 600.0, 900.0, 700.0)) if land else None)


def test_world_clearances_and_is_free_by_hand():
    """Slack of each constraint by hand at three points of the plane world: altitude z + 150 - 0.05 x - 5,
    surface -z - 10, maximum depth 140 + z, bounds, sphere |p - c| - 62; a point with a slack of exactly 0
    (on the minimum depth, on the sphere's margin) is free, one 1 mm beyond is not."""
    w = _plane_world()
    p = np.array([[100.0, 200.0, -120.0], [150.0, 400.0, -10.0], [500.0, 462.0, -70.0]])
    c = w.clearances(p)
    np.testing.assert_allclose(c["altitude"], [-120 + 150 - 5 - 5, -10 + 150 - 7.5 - 5, -70 + 150 - 25 - 5])
    np.testing.assert_allclose(c["surface"], [110.0, 0.0, 60.0])
    np.testing.assert_allclose(c["max_depth"], [20.0, 130.0, 70.0])
    np.testing.assert_allclose(c["bounds"], [80.0, 10.0, 70.0])
    np.testing.assert_allclose(c["obstacles"], [math.dist(q, (500, 400, -70)) - 62.0 for q in p], atol=1e-12)
    assert c["obstacles"][2] == 0.0
    np.testing.assert_array_equal(w.is_free(p), [True, True, True])
    np.testing.assert_array_equal(w.is_free(p + [0.0, 0.0, 0.001]), [True, False, True])
    np.testing.assert_array_equal(w.is_free(p - [0.0, 0.001, 0.0]), [True, True, False])


def _segments_free_by_hand(w: World, seg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Independent segment test for the plane world: the depth band and the bounds at both ends
    (convex), the altitude over the plane is linear along the segment (ends decide), the sphere by the
    closest point of the segment (projection clipped to [0, 1]); the island by shapely on the trace.
    Returns the answer and where it is known: with land, the seabed is burnt (raised above the surface)
    in every cell touching the island, so only traces crossing it or two cells (100 m) clear of it count."""
    import shapely

    a, b = seg[:, 0], seg[:, 1]
    m = w.margins
    ends = seg.reshape(-1, 3)
    inside = ((ends[:, 0] >= 0) & (ends[:, 0] <= 1000) & (ends[:, 1] >= 0) & (ends[:, 1] <= 800)
              & (ends[:, 2] >= -200) & (ends[:, 2] <= 0)).reshape(-1, 2).all(axis=1)
    depth = ((-seg[..., 2] >= m.min_depth) & (-seg[..., 2] <= m.max_depth)).all(axis=1)
    alt = (seg[..., 2] + 150.0 - 0.05 * seg[..., 0] >= m.min_altitude).all(axis=1)
    c = np.array([500.0, 400.0, -70.0])
    d = b - a
    t = np.clip(((c - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0.0, 1.0)
    sphere = np.linalg.norm(a + t[:, None] * d - c, axis=1) >= 60.0 + m.obstacle
    ok = inside & depth & alt & sphere
    known = np.ones(ok.shape, dtype=bool)
    if w.land is not None:
        gap = shapely.distance(shapely.linestrings(seg[..., :2]), shapely.box(700.0, 600.0, 900.0, 700.0))
        ok &= gap > 0
        known = (gap == 0) | (gap >= 100.0)
    return ok, known


@pytest.mark.parametrize("land", [False, True])
def test_world_segments_free_in_batches_is_the_test_by_hand(land):
    """600 seeded segments (up to 250 m long, some leaving the box, the depth band, some crossing the
    sphere, the seabed's margin or the island; the first one through the sphere between two free ends)
    tested as one (20, 30, 2, 3) batch, as (600, 2, 3) and one by one: all three are the independent
    test by hand (:func:`_segments_free_by_hand`) wherever that is known."""
    w = _plane_world(land)
    rng = np.random.default_rng(23 + land)
    a = rng.uniform([-30.0, -30.0, -160.0], [1030.0, 830.0, 5.0], (600, 3))
    if land:  # a third of them around the island
        a[:200] = rng.uniform([650.0, 550.0, -60.0], [950.0, 750.0, -10.0], (200, 3))
    b = a + rng.normal(0.0, 1.0, (600, 3)) * [120.0, 120.0, 30.0]
    seg = np.stack([a, b], axis=1)
    seg[0] = [[420.0, 400.0, -70.0], [580.0, 400.0, -70.0]]
    want, known = _segments_free_by_hand(w, seg)
    assert known.sum() > 400 and 100 < want[known].sum() < 400
    got = w.segments_free(seg.reshape(20, 30, 2, 3))
    assert got.shape == (20, 30)
    np.testing.assert_array_equal(got.reshape(-1)[known], want[known])
    np.testing.assert_array_equal(w.segments_free(seg), got.reshape(-1))
    np.testing.assert_array_equal([bool(w.segments_free(s)) for s in seg[:60]], got.reshape(-1)[:60])
    # both ends free but the segment not: the interior decides
    ends_free = w.is_free(seg).all(axis=1)
    assert ends_free[0] and not want[0]
    np.testing.assert_array_equal(w.segments_free(seg[ends_free], ends_free=True), got.reshape(-1)[ends_free])


def test_world_segment_at_its_limits_and_paths():
    """A segment exactly 5 m above the seabed at both ends (the plane: the whole segment) is free, as is
    one exactly on the minimum depth and one tangent to the sphere's margin (62 m from the centre); 1 mm
    closer they are not.  A single point in the sphere is not a free path; a path with one blocked leg
    is not free."""
    w = _plane_world()
    on = np.array([[[100.0, 100.0, -140.0], [300.0, 100.0, -130.0]],  # altitude exactly 5 m (z = -145 + 0.05 x + 5)
                   [[100.0, 100.0, -10.0], [300.0, 150.0, -10.0]],  # depth exactly 10 m
                   [[400.0, 462.0, -70.0], [600.0, 462.0, -70.0]]])  # tangent to the sphere's margin
    np.testing.assert_array_equal(w.segments_free(on), [True, True, True])
    np.testing.assert_array_equal(w.segments_free(on - [0.0, 0.001, 0.001]), [False, True, False])
    np.testing.assert_array_equal(w.segments_free(on + [0.0, 0.0, 0.001]), [True, False, True])
    assert not w.path_free(np.array([[500.0, 400.0, -70.0]]))
    assert w.path_free(np.array([[100.0, 100.0, -50.0]]))
    assert not w.path_free(np.array([[100.0, 100.0, -50.0], [300.0, 400.0, -70.0], [700.0, 400.0, -70.0]]))
    assert w.path_free(np.array([[100.0, 100.0, -50.0], [300.0, 100.0, -50.0], [300.0, 300.0, -50.0]]))


def test_world_sphere_tangent_segment_is_not_a_hit():
    """``Sphere.segments_hit``: a segment whose closest approach is exactly the radius plus the margin
    (4 m: 3 + 1) does not hit (touching is allowed, as a point with zero slack is free); 1 mm closer it
    does."""
    s = Sphere((0.0, 0.0, 0.0), 3.0)
    seg = np.array([[[-10.0, 4.0, 0.0], [10.0, 4.0, 0.0]], [[-10.0, 3.999, 0.0], [10.0, 3.999, 0.0]],
                    [[0.0, 0.0, 9.0], [0.0, 0.0, 4.0]], [[0.0, 0.0, 9.0], [0.0, 0.0, 3.999]]])
    np.testing.assert_array_equal(s.segments_hit(seg, margin=1.0), [False, True, False, True])


def test_world_ellipsoid_distance_near_deep_inside_and_in_batches():
    """A rotated ellipsoid (6 × 3 × 2.5 m): signed distances of 24 points -- 8 within 3 % of the surface
    (inside and out), 8 deep inside (at a tenth of the semi-axes: the nearest surface point is near the
    minor axis, the bisection's root close to -A_min²), 8 outside -- given as a (4, 6, 3) batch, are
    the SLSQP minimum of |q - p| on the surface (``test_world``'s oracle), with the sign of the body-frame
    quadric; the batch's shape is kept.  The lower bound (s - 1) A_min is below the distance outside,
    and for a sphere-shaped ellipsoid (4, 4, 4) it *is* the distance, |p - c| - 4, batch shape kept."""
    from test_world import _numerical_ellipsoid_distance

    from auvplan.world import Ellipsoid

    e = Ellipsoid((10.0, -5.0, 3.0), (6.0, 3.0, 2.5), yaw=0.4, pitch=-0.3, roll=0.2)
    rng = np.random.default_rng(29)
    u = rng.normal(size=(24, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    scale = np.r_[rng.uniform(0.97, 1.03, 8), np.full(8, 0.1), rng.uniform(1.3, 3.0, 8)]
    body = u * np.asarray(e.semi_axes) * scale[:, None]
    pts = np.asarray(e.center) + body @ e._rot.T
    assert np.allclose(e.to_body(pts), body)
    d = e.distance(pts.reshape(4, 6, 3))
    assert d.shape == (4, 6)
    want = np.array([_numerical_ellipsoid_distance(e, p) for p in pts])
    np.testing.assert_allclose(np.abs(d.reshape(-1)), want, rtol=1e-7, atol=1e-7)
    np.testing.assert_array_equal(d.reshape(-1) < 0, scale < 1.0)
    assert (e.lower_bound_distance(pts[16:]) <= want[16:] + 1e-9).all()
    ball = Ellipsoid((1.0, 2.0, -3.0), (4.0, 4.0, 4.0))
    q = rng.uniform(-20.0, 20.0, (3, 5, 3))
    exact = np.linalg.norm(q - (1.0, 2.0, -3.0), axis=-1) - 4.0
    np.testing.assert_allclose(ball.lower_bound_distance(q), exact, atol=1e-12)
    np.testing.assert_allclose(ball.distance(q), exact, atol=1e-9)


def test_world_thin_ellipsoid_segment_test_with_a_margin():
    """An ellipsoid thinner than a metre (4 × 1.5 × 0.5 m, rotated) with a 0.8 m margin: 400 seeded
    segments hit exactly where their dense-sampled least distance (401 points, 3.5 cm apart at most) is
    below the margin (away from ±5 mm of it); the prefilter ellipsoid scaled by 1 + margin / A_min must contain every
    point within the margin, else a segment passing 0.5-0.8 m from the thin side is missed.  Without a
    margin, a segment tangent to the surface (along x at y = b, axis-aligned) touches but does not hit."""
    from auvplan.world import Ellipsoid

    e = Ellipsoid((5.0, -3.0, -20.0), (4.0, 1.5, 0.5), yaw=0.3, pitch=0.2)
    rng = np.random.default_rng(31)
    centre = np.asarray(e.center)
    a = centre + rng.uniform(-6.0, 6.0, (400, 3)) * [1.0, 0.6, 0.4]
    b = centre + rng.uniform(-6.0, 6.0, (400, 3)) * [1.0, 0.6, 0.4]
    s = np.linspace(0.0, 1.0, 401)[None, :, None]
    dmin = e.distance(a[:, None] + s * (b - a)[:, None]).min(axis=1)
    hit = e.segments_hit(np.stack([a, b], axis=1), margin=0.8)
    clear = np.abs(dmin - 0.8) > 5e-3
    np.testing.assert_array_equal(hit[clear], (dmin < 0.8)[clear])
    assert ((dmin > 0.5) & (dmin < 0.8)).sum() >= 10 and (dmin > 0.8).sum() >= 50
    flat = Ellipsoid((0.0, 0.0, 0.0), (4.0, 2.0, 1.0))
    seg = np.array([[[-6.0, 2.0, 0.0], [6.0, 2.0, 0.0]], [[-6.0, 1.999, 0.0], [6.0, 1.999, 0.0]]])
    np.testing.assert_array_equal(flat.segments_hit(seg), [False, True])


# ---------------------------------------------------------------------- local: document 004's avoidance
def test_local_key_waypoints_hold_up_a_path_over_two_ridges_and_ignore_moving_obstacles():
    """A path 8 m above a seabed with two ridges (crests -60 m at x = 300 and 700 m, flat -100 m), a
    point every 10 m: the key waypoints keep every stored segment free, the first and last point once
    each, and more than the ends (the straight line clips the ridges); the same with the document's
    seabed stepping.  A level path in open water with only a moving obstacle parked on it keeps its
    ends alone (key waypoints are about the static world), with either method."""
    from auvplan.guidance.avoidance.local import key_waypoints
    from auvplan.world.moving import LinearMotion, MovingObstacle

    g = np.arange(0.0, 1001.0, 50.0)
    z = np.full((g.size, g.size), -100.0)
    z[:, (g == 300.0) | (g == 700.0)] = -60.0
    world = World(Bounds(0, 1000, 0, 1000, -100, 0), Terrain(g, g, z), margins=Margins(min_altitude=5.0))
    x = np.arange(0.0, 1001.0, 10.0)
    path = np.c_[x, np.full(x.size, 500.0), world.terrain.elevation(x, np.full(x.size, 500.0)) + 8.0]
    assert world.path_free(path)
    for method in ("exact", "stepping"):
        keys = key_waypoints(path, world, method, step=1.0)
        assert len(keys) >= 4 and (keys[0] == path[0]).all() and (keys[-1] == path[-1]).all()
        assert not (keys[-1] == keys[-2]).all()
        assert world.segments_free(np.stack([keys[:-1], keys[1:]], axis=1), moving=False).all()
    # a path whose last leg is blocked (through a sphere): every point is kept, the last one once
    blocked = World(Bounds(0, 1000, 0, 1000, -100, 0), obstacles=(Sphere((150.0, 500.0, -50.0), 10.0),))
    three = np.array([[0.0, 500.0, -50.0], [100.0, 500.0, -50.0], [200.0, 500.0, -50.0]])
    np.testing.assert_array_equal(key_waypoints(three, blocked), three)
    level = np.c_[x, np.full(x.size, 500.0), np.full(x.size, -70.0)]
    open_world = World(Bounds(0, 1000, 0, 1000, -100, 0), moving=(
        MovingObstacle(Sphere((0.0, 0.0, 0.0), 20.0), LinearMotion((500.0, 500.0, -70.0), (0.0, 0.0, 0.0))),))
    np.testing.assert_array_equal(key_waypoints(level, open_world), level[[0, -1]])
    np.testing.assert_array_equal(key_waypoints(level, open_world, "stepping", step=1.0), level[[0, -1]])


def test_local_apf_force_with_one_obstacle_beyond_the_radius_and_one_very_close():
    """Obstacles at 0.5 m (centre 0.7 m away, closer than a metre) and 12 m (beyond r = 10 m): only the
    first repels, with |F_rep| = k₂ (1/0.5 - 1/10) d_g^w₃ / 0.5^w₂ along the unit vector from its centre."""
    p = AvoidanceParams(k_att=3.0, w_att=0.5, k_rep=7.0, w_obs=1.5, w_goal=2.0, radius=10.0)
    f = apf_force([0.0, 0.0, 0.0], [16.0, 0.0, 0.0], [[0.0, 0.7, 0.0], [0.0, -20.0, 0.0]], [0.5, 12.0], p)
    rep = 7.0 * (1 / 0.5 - 1 / 10.0) * 16.0**2 / 0.5**1.5
    np.testing.assert_allclose(f, [3.0 * 4.0, -rep, 0.0], rtol=1e-12)


def test_local_minimum_detector_radius_ring_and_extra_coordinates():
    """r₁ = 3 m, ε₂ = 3, a point a second; positions may carry more than three entries (only x, y, z
    count).  Points exactly 3 m away count, 2.5 m too (6.25 <= 9), 4 m not; after 3 points near the origin
    and 25 far ones the ring (50 entries) still holds the first three: back at the origin, trapped."""
    from auvplan.guidance.avoidance.local import MinimumDetector

    det = MinimumDetector(3.0, 3, 1.0)
    det.buf[:] = np.inf  # unwritten entries count as far away
    assert not det.update(np.array([0.0, 0.0, 0.0, 99.0]), 0.0)
    assert not det.update(np.array([3.0, 0.0, 0.0, -99.0]), 1.0)
    assert det.update(np.array([0.0, 0.0, 0.0, 5.0]), 2.0)  # 0, 3 and 0 m: three within r₁
    det = MinimumDetector(3.0, 3, 1.0)
    det.buf[:] = np.inf
    got = [det.update(np.array([x, 0.0, 0.0]), float(t)) for t, x in enumerate((0.0, 2.5, 0.0))]
    assert got == [False, False, True]
    det = MinimumDetector(3.0, 3, 1.0)
    det.buf[:] = np.inf
    for t, x in enumerate((0.0, 3.5, 4.0)):
        assert not det.update(np.array([x, 0.0, 0.0]), float(t))  # 4 m from 0 m: r₁³ = 27 would count it
    det = MinimumDetector(3.0, 3, 1.0)
    det.buf[:] = np.inf
    for t in range(3):
        det.update(np.array([0.1 * t, 0.0, 0.0]), float(t))
    for t in range(3, 28):
        assert not det.update(np.array([100.0 * t, 0.0, 0.0]), float(t))
    assert det.update(np.zeros(3), 28.0)


def _la(world: World, keys, **params):
    from test_oracles import _local

    return _local(world, keys, **params)


_BENT = [(0.0, 0.0, -50.0), (100.0, 0.0, -50.0), (200.0, 0.0, -50.0), (200.0, 100.0, -50.0), (200.0, 200.0, -50.0)]


def test_local_goal_advance_at_its_boundaries():
    """Document 004's next goal (arrive 10 m): a key abeam of the vehicle (dot product exactly 0) or
    0.5 m² ahead is not behind; a key exactly 10 m away is reached; "behind" is measured along the
    *next* leg (keys bent at 90°, offset far from the origin); a moving obstacle whose margin is 0.5 m
    short of a key does not occupy it."""
    from auvplan.world.moving import LinearMotion, MovingObstacle

    world = World(Bounds(-5000, 5000, -500, 500, -100, 0))
    la = _la(world, _BENT)
    for p, want in (((100.0, 30.0, -50.0), 1), ((99.995, 30.0, -50.0), 1), ((100.0, 0.0, -40.0), 2),
                    ((100.0, 0.0, -39.999), 1), ((120.0, -50.0, -50.0), 2)):
        la.goal_index = 1
        la._advance_goal(np.array(p), 0.0)
        assert la.goal_index == want, p
    far = [(x - 1000.0, y, z) for x, y, z in _BENT]
    la = _la(world, far)
    la._advance_goal(np.array([-950.0, 0.0, -50.0]), 0.0)  # before key 1: (50, 0, 0) . (100, 0, 0) > 0
    assert la.goal_index == 1
    parked = MovingObstacle(Sphere((0.0, 0.0, 0.0), 5.0), LinearMotion((200.0, 7.5, -50.0), (0.0, 0.0, 0.0)))
    la = _la(World(world.bounds, moving=(parked,), margins=Margins(obstacle=2.0)), _BENT)
    la._advance_goal(np.array([105.0, 0.0, -50.0]), 0.0)
    assert la.goal_index == 2 and la.skipped == 0


def test_local_escapes_draw_a_free_sub_goal_and_widen_within_one_stall():
    """The escape's candidates (angle, radius r √U(¼, 1), dz, with the generator's draws copied): half
    of them blocked by a sphere, the sub-goal is the first free one; with every candidate blocked (the
    vehicle deep inside a huge sphere) no escape happens and False is returned.  Within one stall the
    k-th escape draws within k × 60 m, counting only this stall's escapes (3 earlier ones do not)."""
    from auvplan._types import as_rng
    from auvplan.guidance.avoidance.local import _random_free_point

    def draws(rng, radius):
        ang, rad = rng.uniform(0, 2 * np.pi, 64), radius * np.sqrt(rng.uniform(0.25, 1.0, 64))
        dz = rng.uniform(-0.2, 0.2, 64) * radius
        return np.c_[rad * np.cos(ang), rad * np.sin(ang), dz]

    p = np.array([0.0, 0.0, -50.0])
    half = World(Bounds(-500, 500, -500, 500, -100, 0), obstacles=(Sphere((60.0, 0.0, -50.0), 60.0),))
    cand = p + draws(as_rng(4), 60.0)
    ok = half.is_free(cand)
    assert not ok.all() and ok.any() and not ok[0]
    np.testing.assert_array_equal(_random_free_point(half, p, 60.0, 0.0, as_rng(4)), cand[np.argmax(ok)])
    trapped = _la(World(Bounds(-5000, 5000, -500, 500, -5000, 0), obstacles=(Sphere((0.0, 0.0, -2000.0), 1500.0),)),
                  [(0.0, 0.0, -2000.0), (100.0, 0.0, -2000.0)])
    assert trapped._escape(np.array([0.0, 0.0, -2000.0]), 0.0) is False and trapped.escapes == 0
    assert trapped.mode == "route" and trapped.subgoal is None
    assert _la(half, [(0.0, 0.0, -50.0), (-100.0, 0.0, -50.0)])._escape(p, 0.0) is True
    from test_oracles import _KEYS, _open_water

    la = _la(_open_water(), _KEYS)
    la.escapes = 3  # escapes of an earlier stall
    rng = as_rng(0)
    first, second = draws(rng, 60.0), draws(rng, 120.0)
    q = np.array([50.0, 0.0, -50.0])
    assert la.stalled(q, 10.0, since=5.0) and la.escapes == 4
    np.testing.assert_allclose(la.subgoal, q + first[0], atol=1e-9)
    la.subgoal = None  # reached, still no progress: the second escape of this stall
    assert la.stalled(q, 12.0, since=5.0) and la.escapes == 5
    np.testing.assert_allclose(la.subgoal, q + second[0], atol=1e-9)


class _Base:
    """A path follower that records the obstacles it is given."""

    name, route = "stub", None

    def __init__(self) -> None:
        self.seen: list = []

    def reset(self) -> None:
        pass

    def command(self, x, y, z, current, speed, obstacles, dt):
        from auvplan.guidance.following.route import RoutePoint

        self.seen.append(list(obstacles))
        return 0.25, 0.0, RoutePoint(0, 0.0, 0.0, 0.0, 0.0, -50.0, 0.0, False)


def test_local_command_passes_static_obstacles_to_the_base_and_counts_apf_steps():
    """The base follower gets the static obstacles only, as (cx, cy, distance); a moving obstacle exactly
    at the repulsion radius (30 m) switches to the APF; each APF step counts as one decision and its
    (small, non-negative) time adds up."""
    from auvplan.guidance.avoidance.local import LocalAvoidance

    base = _Base()
    world = World(Bounds(-5000, 5000, -500, 500, -100, 0))
    la = LocalAvoidance(base, np.array(_BENT), world, AvoidanceParams(name="apf"), 1.5, rng=0)
    static = (60.0, 5.0, 8.0, False, (60.0, 5.0, -50.0))
    far = (90.0, 5.0, 30.5, True, (90.0, 5.0, -50.0), 1, np.zeros(3), 5.0)
    psi, pitch, _ = la.command(np.array([50.0, 0.0, -50.0]), 0.0, np.zeros(3), [static, far], 0.1)
    assert base.seen[-1] == [(60.0, 5.0, 8.0)] and pitch is None and la.mode == "route" and la.decisions == 0
    at = (90.0, 5.0, 30.0, True, (90.0, 5.0, -50.0), 1, np.zeros(3), 5.0)
    for k in range(3):
        _, pitch, _ = la.command(np.array([50.0 + k, 0.0, -50.0]), 0.1 * (k + 1), np.zeros(3), [static, at], 0.1)
        assert pitch is not None and la.mode == "apf"
    assert la.decisions == 3 and 0.0 <= la.decision_time < 60.0


def test_local_apf_command_goals_sub_goals_distances_and_the_sloped_seabed_floor():
    """In APF mode with a moving obstacle near: at exactly the arrive distance (10 m) of the
    penultimate key the goal moves on to the last key, and stays there when that is reached too; the
    command's course is the APF force's with the obstacles' *distances*; while a sub-goal is followed a
    trapped detector does not start another escape; over a seabed sloping in x (z = -150 + 0.05 x) the
    dive floor uses the altitude under the vehicle (5 m above the margin at x = 100, y = 600: 7.5°; the
    seabed also slopes in y, 0.02), and does not apply 25 m above the margin."""
    world = World(Bounds(-5000, 5000, -500, 500, -100, 0))
    la = _la(world, _BENT)
    la.mode, la.goal_index = "apf", 3
    near = [(210.0, 110.0, 20.0, True, (210.0, 110.0, -50.0))]
    course, _, _ = la._apf_command(np.array([200.0, 90.0, -50.0]), 0.0, near, 0.3, None)
    assert la.goal_index == 4
    f = apf_force(np.array([200.0, 90.0, -50.0]), np.array(_BENT[4]), np.array([near[0][4]]), np.array([20.0]),
                  la.params)
    assert course == pytest.approx(math.atan2(f[0], f[1]), abs=1e-12)
    la._apf_command(np.array([200.0, 195.0, -50.0]), 1.0, near, 0.3, None)
    assert la.goal_index == 4
    la = _la(world, _BENT, minimum_count=3)
    la.mode, la.subgoal = "apf", np.array([150.0, 50.0, -50.0])
    for t in range(5):
        la._apf_command(np.array([100.0, 0.0, -50.0]), float(t), [], 0.3, None)
    assert la.escapes == 0 and (la.subgoal == [150.0, 50.0, -50.0]).all()
    g = np.arange(-100.0, 1101.0, 100.0)
    plane = -150.0 + 0.05 * g[None, :] + 0.02 * (g[:, None] - 600.0)  # (ny, nx): sloping in x and y
    slope = World(Bounds(0, 1000, 0, 1000, -200, 0), Terrain(g, g, plane), margins=Margins(min_altitude=5.0))
    la = _la(slope, [(0.0, 600.0, -100.0), (300.0, 600.0, -200.0), (600.0, 600.0, -100.0)])
    la.mode = "apf"
    _, pitch, _ = la._apf_command(np.array([100.0, 600.0, -135.0]), 0.0, [], 0.3, None)
    assert pitch == pytest.approx(math.radians(10.0) * (1.0 - 5.0 / 20.0), abs=1e-12)
    p = np.array([100.0, 600.0, -115.0])  # 25 m above the margin: beyond 2 x arrive, the dive is not floored
    f = apf_force(p, np.array([300.0, 600.0, -200.0]), np.empty((0, 3)), np.empty(0), la.params)
    _, pitch, _ = la._apf_command(p, 1.0, [], 0.3, None)
    assert pitch == pytest.approx(math.atan2(f[2], math.hypot(f[0], f[1])), abs=1e-12) and pitch < -0.3


def test_lattice_astar_heuristic_is_c_min_times_the_distance_to_the_start():
    """A*'s heuristic at every node of a 7 × 5 × 4 lattice (offset origin, unequal steps) is
    ``c_min`` times the node's straight distance to the start, computed from the node's own (i, j, k);
    ``c_min = 0`` (Dijkstra) gives 0 everywhere."""
    from auvplan.planners.grid.lattice.dijkstra import _heuristic

    shape = (7, 5, 4)
    steps, origin = np.array([0.7, 1.9, 0.4]), np.array([120.0, -35.0, -60.0])
    start = np.array([121.3, -31.2, -59.1])
    ijk = np.stack(np.unravel_index(np.arange(int(np.prod(shape))), shape), axis=1)
    want = np.linalg.norm(origin + ijk * steps - start, axis=1)
    for c_min in (0.5, 2.5):
        got = [_heuristic(u, shape[1], shape[2], origin, steps, start, c_min) for u in range(want.size)]
        np.testing.assert_allclose(got, c_min * want, rtol=1e-12)
    assert all(_heuristic(u, shape[1], shape[2], origin, steps, start, 0.0) == 0.0 for u in range(want.size))


def test_lattice_astar_finds_each_starts_dijkstra_cost_on_an_obstacle_lattice():
    """A 12 × 10 × 4 lattice of sub-metre steps (edges cost less than 1) with two walls of removed
    nodes, cost = length through the cost path (no current), the goal linked to three nodes and, dearly
    (5), to a fourth whose cost through its neighbours is 0.5: for 12 random starts linked to the 8
    nodes of their cell at their distances, A* (c_min = 1, the length bound: a consistent heuristic)
    finds the least start cost that scipy's Dijkstra over the same graph gives, and settles exactly the
    nodes whose Dijkstra cost plus distance to the start is below that least cost, plus the best link's
    node (with c_min = 0.5: exactly those with cost plus half the distance below it); the dear link's
    node gets its cheap cost; with ``c_min = 0`` and a start given the search is
    the full Dijkstra."""
    rng = np.random.default_rng(14)
    shape = (12, 10, 4)
    n = int(np.prod(shape))
    steps, origin = np.array([0.5, 0.6, 0.3]), np.array([10.0, 20.0, -5.0])
    idx = np.arange(n).reshape(shape)
    ijk = np.stack(np.unravel_index(np.arange(n), shape), axis=1)
    blocked = np.zeros(shape, dtype=bool)
    blocked[6, 1:, :] = True  # a wall with a gap at j = 0
    blocked[3, :8, 1:] = True
    bits = np.zeros(n, dtype=np.uint32)
    src, dst, length, s_of = [], [], [], []
    for s, off in enumerate(OFFSETS):
        v = ijk + off
        inside = np.all((v >= 0) & (v < shape), axis=1)
        ok = inside.copy()
        ok[inside] &= ~blocked[tuple(v[inside].T)]
        ok &= ~blocked.reshape(-1) & (rng.random(n) < 0.85)
        bits[ok] |= np.uint32(1 << s)
        src.append(np.flatnonzero(ok))
        dst.append(idx[tuple(v[ok].T)])
        length.append(np.full(ok.sum(), np.linalg.norm(off * steps)))
        s_of.append(np.full(ok.sum(), s))
    src, dst, length, s_of = np.concatenate(src), np.concatenate(dst), np.concatenate(length), np.concatenate(s_of)
    bits = _undirected(bits, shape)
    edge = (bits[src] >> s_of.astype(np.uint32)) & np.uint32(1) == 1
    src, dst, length = src[edge], dst[edge], length[edge]
    near = np.array([idx[11, 9, 3], idx[10, 9, 3], idx[11, 8, 2], idx[11, 9, 2]])
    w_goal = np.array([0.2, 0.7, 0.5, 5.0])
    still = np.zeros((n, 3), np.float32)
    cost = (1.0, 0.0, 1.0, 0.0, False)  # length, through the cost path (its floor, its currents)
    full, _, settled_full = search(shape, bits, steps, origin, still, cost, (near, w_goal))
    graph = coo_matrix((np.r_[length, w_goal], (np.r_[dst, np.full(near.size, n)], np.r_[src, near])),
                       shape=(n + 1, n + 1)).tocsr()
    want = dijkstra(graph, indices=n)
    np.testing.assert_allclose(full, want, rtol=1e-12)
    assert want[near[3]] < 1.0
    xyz = origin + ijk * steps
    cube = np.array([[a, b, c] for a in (0, 1) for b in (0, 1) for c in (0, 1)])
    tried = 0
    for trial in range(12):
        cell = np.array([rng.integers(0, shape[0] - 1), rng.integers(0, shape[1] - 1), rng.integers(0, shape[2] - 1)])
        start = origin + (cell + rng.uniform(0.02, 0.98, 3)) * steps
        sn = idx[tuple((cell + cube).T)]
        ws = np.linalg.norm(xyz[sn] - start, axis=1)
        d, _, settled = search(shape, bits, steps, origin, still, cost, (near, w_goal), (sn, ws), start, 1.0)
        best = (ws + want[sn]).min()
        if not np.isfinite(best):
            continue
        tried += 1
        assert (ws + d[sn]).min() == pytest.approx(best, rel=1e-12), trial
        f = want[:n] + np.linalg.norm(xyz - start, axis=1)
        assert settled == np.count_nonzero(f < best) + 1, trial
        if f[near[3]] < best:
            assert d[near[3]] == pytest.approx(want[near[3]], rel=1e-12)
        # half the bound (still consistent): the first link settled need not be the best one
        d, _, settled = search(shape, bits, steps, origin, still, cost, (near, w_goal), (sn, ws), start, 0.5)
        assert (ws + d[sn]).min() == pytest.approx(best, rel=1e-12), trial
        assert settled == np.count_nonzero(want[:n] + 0.5 * np.linalg.norm(xyz - start, axis=1) < best), trial
    assert tried >= 8
    start = xyz[idx[10, 8, 2]] + 0.5 * steps
    sn = idx[tuple((np.array([10, 8, 2]) + cube).T)]
    ws = np.linalg.norm(xyz[sn] - start, axis=1)
    d, _, settled = search(shape, bits, steps, origin, still, cost, (near, w_goal), (sn, ws), start, 1.0)
    assert (ws + d[sn]).min() == pytest.approx((ws + want[sn]).min(), rel=1e-12)
    assert settled < 0.2 * settled_full
    d0, _, settled0 = search(shape, bits, steps, origin, still, cost, (near, w_goal), (sn, ws), start, 0.0)
    np.testing.assert_allclose(d0, want, rtol=1e-12)
    assert settled0 == settled_full


@pytest.mark.parametrize("max_time", [120.0, 60.25])
def test_sim_the_final_sample_off_the_recording_grid_is_the_state_at_its_time(max_time):
    """The same deterministic run recorded every step and every 7th step: the samples they share agree
    exactly, the final one included, which is off the 7-step grid (1 200 and 603 steps; a timeout).
    The final state used to be taken one step after its time stamp (the vehicle stepped once more
    after the last step), and its obstacle distances with the default exact range, not the run's."""
    from auvplan.sim import SimParams
    from auvplan.world.moving import LinearMotion, MovingObstacle

    route = ((100.0, 500.0, -60.0), (900.0, 500.0, -60.0))
    moving = MovingObstacle(Sphere((0.0, 0.0, 0.0), 5.0), LinearMotion((400.0, 420.0, -60.0), (0.0, 0.4, 0.0)))
    world = replace(flat_world(depth=100.0, size=1000.0, obstacles=(Sphere((300.0, 540.0, -60.0), 8.0),)),
                    moving=(moving,))
    runs = [simulate(world, Mission("grid", route[0], route[-1], route=route,
                                    sim=SimParams(max_time=max_time, record_every=every)),
                     guidance="los", rng=0, avoidance="none") for every in (1, 7)]
    full, sparse = runs
    assert full.status is sparse.status is Status.TIMEOUT
    n_steps = int(math.ceil(max_time / 0.1))
    assert n_steps % 7 != 0 and sparse.t[-1] == full.t[-1] == pytest.approx(n_steps * 0.1)
    at = np.searchsorted(full.t, sparse.t)
    np.testing.assert_array_equal(full.t[at], sparse.t)
    for name in ("position", "heading", "speed", "altitude", "obstacle_distance", "progress"):
        np.testing.assert_array_equal(getattr(full, name)[at], getattr(sparse, name), err_msg=name)
