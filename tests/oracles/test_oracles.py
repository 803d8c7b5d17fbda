"""Oracle tests aimed at the bugs that matter (issue #23, docs/mutants.md).

Each test is a small independent computation -- a hand-derived number, an exact solution or a
brute-force check -- written so that a specific, plausible one-line bug in a safety-relevant
function makes it fail.  docs/mutants.md lists the planted bug each test was checked against.
"""

from __future__ import annotations

import copy
import math
import os
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator
from scipy.optimize import brentq

from auvplan._types import Status
from auvplan.cost import CostModel, evaluate_paths, segment_energy
from auvplan.errors import DataError
from auvplan.guidance.avoidance.local import apf_force
from auvplan.guidance.avoidance.params import AvoidanceParams
from auvplan.guidance.following.hybrid import HybridParams, hybrid_force
from auvplan.guidance.following.route import RouteTracker
from auvplan.optim import Problem, Termination, minimize
from auvplan.optim.bee import IABC, IABCParams, chaotic_uniform_population, rank_probabilities
from auvplan.optim.ga import polynomial_mutation, sbx
from auvplan.planners import GridParams, GridReference
from auvplan.planners.core.params import FlowParams
from auvplan.planners.flow.elements import sphere_exact_velocity
from auvplan.planners.flow.field import SAG_PAD, FlowField
from auvplan.planners.swarm.problem import along_track_order
from auvplan.sim import Mission, simulate
from auvplan.world import Bounds, Margins, Sphere, Terrain, UniformCurrent, World
from helpers import flat_world


# ---------------------------------------------------------------------- terrain: the Lipschitz shortcut
def thin_ridge() -> Terrain:
    """Flat seabed at -100 m with a one-node ridge rising to -60 m at x = 100 (10 m cells)."""
    x = np.arange(0.0, 301.0, 10.0)
    y = np.arange(0.0, 101.0, 10.0)
    z = np.full((y.size, x.size), -100.0)
    z[:, x == 100.0] = -60.0
    return Terrain(x, y, z, name="thin ridge")


def _dense_min_altitude(t: Terrain, seg: np.ndarray, n: int = 8001) -> np.ndarray:
    """Dense-sampled minimum altitude, the seabed interpolated independently of ``Terrain``
    (scipy's bilinear ``RegularGridInterpolator`` on the same nodes; segments inside the grid)."""
    s = np.linspace(0.0, 1.0, n)[None, :, None]
    pts = seg[:, None, 0] + s * (seg[:, None, 1] - seg[:, None, 0])
    seabed = RegularGridInterpolator((t.y, t.x), t.z, method="linear")(pts[..., [1, 0]])
    return (pts[..., 2] - seabed).min(axis=1)


def test_descending_segment_over_a_thin_ridge_is_caught_below_the_threshold():
    """From (90, 50, -30) down to (110, 50, -70): the ends are 70 m and 30 m above the flat
    seabed, the crest at x = 100 is passed at z = -50, 10 m above it.  The shortcut's bound
    (g_a + g_b - |Δz| - G L_h) / 2 = (70 + 30 - 40 - 4 * 20) / 2 = -10 m is below a 20 m
    threshold, so the exact walk must run and report 10 m."""
    t = thin_ridge()
    assert t.max_slope == pytest.approx(4.0)  # 40 m over one 10 m cell
    down = np.array([[[90.0, 50.0, -30.0], [110.0, 50.0, -70.0]]])
    up = down[:, ::-1]
    for seg in (down, up):
        assert t.segment_min_altitude(seg, threshold=20.0)[0] == pytest.approx(10.0, abs=1e-9)
        assert t.segments_below(seg, altitude=20.0)[0]
    lb = t.altitude_lower_bound(np.array([70.0]), np.array([30.0]), -40.0, 20.0)
    assert lb[0] == pytest.approx(-10.0)
    # where the bound clears the threshold it is what the segment test returns (at equality too)
    for threshold in (-50.0, -10.0):
        assert t.segment_min_altitude(down, threshold=threshold)[0] == pytest.approx(-10.0, abs=1e-12)


def test_bounded_altitude_never_exceeds_the_sampled_minimum_over_a_ridge():
    """Random ascending and descending segments across the ridge: with a threshold the result is
    a lower bound of the dense-sampled minimum everywhere and the exact value below it."""
    t = thin_ridge()
    rng = np.random.default_rng(11)
    n = 200
    xa, xb = rng.uniform(60, 100, n), rng.uniform(100, 140, n)
    ya, yb = rng.uniform(20, 80, n), rng.uniform(20, 80, n)
    za, zb = rng.uniform(-90, 60, n), rng.uniform(-90, 60, n)
    seg = np.stack([np.c_[xa, ya, za], np.c_[xb, yb, zb]], axis=1)
    dense = _dense_min_altitude(t, seg)
    for threshold in (5.0, 20.0, 50.0):
        bounded = t.segment_min_altitude(seg, threshold=threshold)
        assert np.all(bounded <= dense + 1e-6)
        below = dense < threshold - 0.05
        assert below.sum() > 20 and (~below).sum() > 20
        np.testing.assert_allclose(bounded[below], dense[below], atol=0.05)
        assert np.array_equal(t.segments_below(seg, threshold)[below | (dense > threshold + 0.05)],
                              below[below | (dense > threshold + 0.05)])


def test_max_slope_of_a_twisted_surface():
    """z = x y / 100 on [0, 100]²: bilinear, so represented exactly; |∇z| = |(y, x)| / 100 is
    largest at the corner (100, 100): √2."""
    x = np.linspace(0.0, 100.0, 11)
    gx, gy = np.meshgrid(x, x)
    t = Terrain(x, x, gx * gy / 100.0)
    assert t.max_slope == pytest.approx(math.sqrt(2.0), rel=1e-12)


def _offset_terrain() -> Terrain:
    """Random bilinear seabed on a grid whose origin is far from (0, 0): 20 m x 25 m cells,
    x in [1000, 1400], y in [-700, -400]."""
    rng = np.random.default_rng(23)
    x, y = np.arange(1000.0, 1401.0, 20.0), np.arange(-700.0, -399.0, 25.0)
    return Terrain(x, y, -100.0 + rng.normal(0.0, 15.0, (y.size, x.size)), name="offset")


def _scipy_altitude(t: Terrain, pts: np.ndarray) -> np.ndarray:
    """Altitude above the bilinear seabed, independently: scipy's interpolator on the nodes, the
    surface held at its edge values beyond the extent (clamped coordinates)."""
    q = np.stack([np.clip(pts[..., 1], t.y[0], t.y[-1]), np.clip(pts[..., 0], t.x[0], t.x[-1])], axis=-1)
    return pts[..., 2] - RegularGridInterpolator((t.y, t.x), t.z, method="linear")(q)


def test_exact_segment_minimum_on_an_offset_grid_and_beyond_its_extent():
    """Segments over a grid far from the origin, some leaving the extent: the exact minimum equals
    the dense-sampled one (scipy) to within the sampling's reach (slope x spacing); with a threshold
    it is a lower bound everywhere and exact below the threshold; passing the true end altitudes
    changes nothing."""
    t = _offset_terrain()
    rng = np.random.default_rng(7)
    n = 60
    a = np.c_[rng.uniform(950, 1450, n), rng.uniform(-750, -350, n), rng.uniform(-110, -40, n)]
    b = a + np.c_[rng.uniform(-150, 150, n), rng.uniform(-150, 150, n), rng.uniform(-30, 30, n)]
    seg = np.stack([a, b], axis=1)
    s = np.linspace(0.0, 1.0, 6001)[None, :, None]
    dense = _scipy_altitude(t, seg[:, None, 0] + s * (seg[:, None, 1] - seg[:, None, 0])).min(axis=1)
    tol = (t.max_slope + 1.0) * np.linalg.norm(b - a, axis=1) / 6000
    exact = t.segment_min_altitude(seg)
    assert np.all(exact <= dense + 1e-9) and np.all(exact >= dense - tol)
    ends = (_scipy_altitude(t, a), _scipy_altitude(t, b))
    np.testing.assert_allclose(t.segment_min_altitude(seg, end_altitudes=ends), exact, atol=1e-9)
    threshold = float(np.median(dense))
    bounded = t.segment_min_altitude(seg, threshold=threshold, end_altitudes=ends)
    assert np.all(bounded <= dense + 1e-9)
    below = dense < threshold - 1.0
    assert below.sum() >= 20
    np.testing.assert_allclose(bounded[below], exact[below], atol=1e-9)
    np.testing.assert_array_equal(t.segments_below(seg, threshold)[below], True)
    np.testing.assert_allclose(t.altitude(a), ends[0], atol=1e-9)
    # the same segments as a (3, 20) batch, end altitudes and threshold included
    batch = t.segment_min_altitude(seg.reshape(3, 20, 2, 3), threshold, tuple(e.reshape(3, 20) for e in ends))
    assert batch.shape == (3, 20)
    np.testing.assert_allclose(batch.reshape(-1), bounded, atol=1e-9)


def test_a_segment_exactly_at_the_altitude_limit_is_not_below_it():
    """Over the flat part of the ridge terrain (seabed -100 m) a level segment at -80 m is exactly
    20 m up: not below a 20 m limit (the World calls it free: altitude >= min_altitude), but below
    a limit a hair higher."""
    t = thin_ridge()
    seg = np.array([[[150.0, 20.0, -80.0], [290.0, 80.0, -80.0]]])
    assert t.segment_min_altitude(seg, threshold=20.0)[0] == 20.0
    assert not t.segments_below(seg, altitude=20.0)[0]
    assert t.segments_below(seg, altitude=20.0 + 1e-9)[0]


def test_plane_on_an_offset_grid_has_its_exact_slope_and_a_read_only_surface():
    """z = -80 + 0.01 x + 0.05 y on a grid far from the origin (dx = 20 m, dy = 25 m): the
    bilinear surface is the plane, its steepest slope hypot(0.01, 0.05) exactly; the smallest grid
    (2 x 2 nodes) is a valid terrain; the surface arrays cannot be written (the kernels and the
    cached slope rely on it); an axis that does not advance is rejected."""
    x, y = np.arange(1000.0, 1401.0, 20.0), np.arange(-700.0, -399.0, 25.0)
    gx, gy = np.meshgrid(x, y)
    t = Terrain(x, y, -80.0 + 0.01 * gx + 0.05 * gy)
    assert t.max_slope == pytest.approx(math.hypot(0.01, 0.05), rel=1e-9)
    assert t.elevation_at(1234.5, -567.8) == pytest.approx(-80.0 + 12.345 - 28.39, abs=1e-9)
    small = Terrain(x[:2], y[:2], -80.0 + 0.01 * gx[:2, :2] + 0.05 * gy[:2, :2])
    assert small.max_slope == pytest.approx(math.hypot(0.01, 0.05), rel=1e-9)
    assert small.elevation_at(1010.0, -690.0) == pytest.approx(-80.0 + 10.1 - 34.5, abs=1e-9)
    for array in (t.x, t.y, t.z, t.kernel_data[0]):
        assert not array.flags.writeable
    with pytest.raises(DataError, match="ascending"):
        Terrain(np.zeros(3), y[:2], np.zeros((2, 3)))
    # one twisted 1 m cell z = 2 v - u v: ∇z = (-v, 2 - u), steepest √5 at the corner u = 0, v = 1
    assert Terrain(np.arange(2.0), np.arange(2.0), np.array([[0.0, 0.0], [2.0, 1.0]])).max_slope == \
        pytest.approx(math.sqrt(5.0), rel=1e-12)


def test_elevation_of_a_point_off_the_grid_or_undefined():
    """Beyond the extent the surface is held at its edge (the corner node's value off a corner);
    a NaN coordinate gives NaN, not a value of some cell."""
    t = _offset_terrain()
    assert t.elevation_at(900.0, -800.0) == pytest.approx(t.z[0, 0], abs=1e-12)
    assert t.elevation_at(1500.0, -300.0) == pytest.approx(t.z[-1, -1], abs=1e-12)
    assert t.elevation_at(1500.0, t.y[3]) == pytest.approx(t.z[3, -1], abs=1e-12)
    assert t.elevation_at(t.x[0] + 1e-9, t.y[0] + 1e-9) == pytest.approx(t.z[0, 0], abs=1e-6)
    assert t.elevation_at(t.x[-1], t.y[-1]) == pytest.approx(t.z[-1, -1], abs=1e-12)
    assert math.isnan(t.elevation_at(math.nan, -500.0)) and math.isnan(t.elevation_at(1200.0, math.nan))


# ---------------------------------------------------------------------- grid: edges and their direction
def _wall_world() -> World:
    """Seabed at -200 m with a one-node wall up to -100 m along x = 110 (10 m terrain cells)."""
    x = np.arange(0.0, 201.0, 10.0)
    z = np.full((x.size, x.size), -200.0)
    z[:, x == 110.0] = -100.0
    return World(Bounds(0, 200, 0, 200, -200, 0), Terrain(x, x, z),
                 margins=Margins(min_altitude=5.0, min_depth=0.0))


def test_every_edge_of_the_cost_to_go_tree_is_free():
    """The lattice nodes at x = 100 and 120 are 20 m apart on both sides of a 10 m wide wall: the
    nodes are free, the edges between them below the crest are not.  Every hop of every node's
    cheapest path (the Dijkstra predecessor tree) must pass the World's exact segment test."""
    world = _wall_world()
    goal = np.array([180.0, 100.0, -160.0])
    params = GridParams(cell=20.0, cell_z=20.0, objective="length")
    ref = GridReference(world, goal, CostModel(), np.array([0.0, 0.0, -200.0]), np.array([200.0, 200.0, 0.0]),
                        params)
    assert np.allclose(ref.axes[0], np.arange(0.0, 201.0, 20.0))
    ids = np.flatnonzero(np.isfinite(ref._dist[:-1]))
    assert ids.size > 500
    nxt = ref._next[ids]
    end = np.where(nxt[:, None] == ref._goal_id, goal, ref._coords(np.minimum(nxt, ref.nodes - 1)))
    seg = np.stack([ref._coords(ids), end], axis=1)
    assert world.segments_free(seg, moving=False).all()
    # a start beyond the wall at the wall's foot has to climb over the crest
    path = ref.query([20.0, 100.0, -160.0])
    assert world.path_free(path) and path[:, 2].max() >= -100.0 + 5.0
    crest = np.interp(110.0, path[:, 0], path[:, 2]) if np.all(np.diff(path[:, 0]) > 0) else path[:, 2].max()
    assert crest >= -95.0


def test_grid_costs_each_edge_in_its_own_direction():
    """Uniform current of 0.5 m/s along +x, vehicle at 1.5 m/s, cost = length + still-water-metre
    energy: per metre 1 + V / (V ± c), i.e. 1.75 with the current and 2.5 against it (the straight
    line is both the shortest and the fastest path in a uniform current, so it is optimal).  Starts
    on both sides of the goal along x."""
    world = World(Bounds(0, 400, 0, 400, -400, 0), currents=UniformCurrent((0.5, 0.0, 0.0)),
                  margins=Margins(min_depth=0.0))
    goal = np.array([200.0, 200.0, -200.0])
    ref = GridReference(world, goal, CostModel(speed=1.5), np.array([0.0, 0.0, -400.0]),
                        np.array([400.0, 400.0, 0.0]), GridParams(cell=40.0, cell_z=40.0, objective="cost"))
    ix = {float(v): i for i, v in enumerate(ref.axes[0])}
    j, k = int(np.argmin(np.abs(ref.axes[1] - 200.0))), int(np.argmin(np.abs(ref.axes[2] + 200.0)))
    for d in (40.0, 120.0, 200.0):
        upstream = ref.cost_to_go[ix[200.0 - d], j, k]  # travels +x, with the current
        downstream = ref.cost_to_go[ix[200.0 + d], j, k]  # travels -x, against it
        assert upstream == pytest.approx(1.75 * d, rel=1e-9)
        assert downstream == pytest.approx(2.5 * d, rel=1e-9)
    # the same holds across the y axis, where the current is a pure cross current:
    # ground speed √(V² - c²) = √2 m/s each way
    iy = {float(v): i for i, v in enumerate(ref.axes[1])}
    i = ix[200.0]
    for d in (40.0, 160.0):
        for y in (200.0 - d, 200.0 + d):
            assert ref.cost_to_go[i, iy[y], k] == pytest.approx(d * (1.0 + 1.5 / math.sqrt(2.0)), rel=1e-9)


def test_cost_to_go_equals_scipys_dijkstra_over_the_free_lattice():
    """Independent graph: every pair of free lattice nodes one step apart (26-neighbourhood) whose
    segment the World calls free, weighed by its length, plus the goal linked to the free nodes
    within two cells by a free segment; scipy's Dijkstra from the goal over the reversed edges must
    give the cost-to-go of every node (seabed ridge and three spheres in the way; the boundary
    nodes included)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    x = np.arange(0.0, 201.0, 10.0)
    z = np.full((x.size, x.size), -200.0)
    z[:, (x >= 90.0) & (x <= 110.0)] = -130.0
    world = World(Bounds(0, 200, 0, 200, -200, 0), Terrain(x, x, z),
                  obstacles=(Sphere((60.0, 60.0, -150.0), 25.0), Sphere((150.0, 140.0, -120.0), 30.0),
                             Sphere((100.0, 180.0, -170.0), 15.0)),
                  margins=Margins(min_altitude=5.0, min_depth=0.0, obstacle=2.0))
    goal = np.array([180.0, 30.0, -150.0])
    ref = GridReference(world, goal, CostModel(), np.array([0.0, 0.0, -200.0]), np.array([200.0, 200.0, -60.0]),
                        GridParams(cell=25.0, cell_z=20.0, objective="length"))
    xyz = np.stack(np.meshgrid(*ref.axes, indexing="ij"), axis=-1).reshape(-1, 3)
    free = ref.free.reshape(-1)
    n = xyz.shape[0]
    idx = np.arange(n).reshape(ref.shape)
    src, dst = [], []
    for off in [(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1) if (i, j, k) != (0, 0, 0)]:
        a = tuple(slice(max(0, -d), m - max(0, d)) for d, m in zip(off, ref.shape))
        b = tuple(slice(max(0, d), m - max(0, -d)) for d, m in zip(off, ref.shape))
        src.append(idx[a].reshape(-1))
        dst.append(idx[b].reshape(-1))
    src, dst = np.concatenate(src), np.concatenate(dst)
    keep = free[src] & free[dst]
    src, dst = src[keep], dst[keep]
    ok = world.segments_free(np.stack([xyz[src], xyz[dst]], axis=1), moving=False)
    src, dst = src[ok], dst[ok]
    w = np.linalg.norm(xyz[dst] - xyz[src], axis=1)
    steps = np.array([ref.cell, ref.cell, ref.cell_z])
    near = np.flatnonzero(free & np.all((xyz >= goal - 2.01 * steps) & (xyz < goal + 2.01 * steps), axis=1))
    near = near[world.segments_free(np.stack([xyz[near], np.broadcast_to(goal, (near.size, 3))], axis=1),
                                    moving=False)]
    # reversed graph: an edge u -> v becomes v -> u, the goal (node n) the source
    rows = np.concatenate([dst, np.full(near.size, n)])
    cols = np.concatenate([src, near])
    data = np.concatenate([w, np.maximum(np.linalg.norm(xyz[near] - goal, axis=1), 1e-12)])
    graph = coo_matrix((data, (rows, cols)), shape=(n + 1, n + 1)).tocsr()
    want = dijkstra(graph, indices=n)[:n]
    assert np.isfinite(want).sum() > 0.8 * free.sum() and (~free).sum() > 50
    np.testing.assert_allclose(ref.cost_to_go.reshape(-1), want, rtol=1e-12)


def test_grid_costs_with_a_weaker_current_with_a_vertical_part():
    """Uniform current c = (0.3, 0, 0.2) m/s, V = 1.5 m/s, cost = length + V x time: along ±x the
    ground speed is ±0.3 + √(V² - 0.2²), along ±z ±0.2 + √(V² - 0.3²); straight lines are the
    cheapest lattice paths in a uniform current."""
    world = World(Bounds(0, 400, 0, 400, -400, 0), currents=UniformCurrent((0.3, 0.0, 0.2)),
                  margins=Margins(min_depth=0.0))
    goal = np.array([200.0, 200.0, -200.0])
    ref = GridReference(world, goal, CostModel(speed=1.5), np.array([0.0, 0.0, -400.0]),
                        np.array([400.0, 400.0, 0.0]), GridParams(cell=40.0, cell_z=40.0, objective="cost"))
    i, j, k = (int(np.argmin(np.abs(ax - g))) for ax, g in zip(ref.axes, goal))
    gx, gz = math.sqrt(1.5**2 - 0.2**2), math.sqrt(1.5**2 - 0.3**2)
    # rel 1e-6: the lattice keeps node currents in float32 (0.3 and 0.2 stored to ~1e-8)
    for d in (40.0, 120.0):
        s = int(round(d / 40.0))
        assert ref.cost_to_go[i - s, j, k] == pytest.approx(d * (1 + 1.5 / (gx + 0.3)), rel=1e-6)  # with the current
        assert ref.cost_to_go[i + s, j, k] == pytest.approx(d * (1 + 1.5 / (gx - 0.3)), rel=1e-6)  # against it
        assert ref.cost_to_go[i, j, k - s] == pytest.approx(d * (1 + 1.5 / (gz + 0.2)), rel=1e-6)  # rising with it
        assert ref.cost_to_go[i, j, k + s] == pytest.approx(d * (1 + 1.5 / (gz - 0.2)), rel=1e-6)  # sinking


# ---------------------------------------------------------------------- energy with a vertical current
def _ground_speed(e: np.ndarray, c: np.ndarray, speed: float) -> float:
    """Independent solution: the ground speed g > 0 along ŝ with |g ŝ - c| = V (root finding)."""
    s = e / np.linalg.norm(e)
    return brentq(lambda g: np.linalg.norm(g * s - c) - speed, 1e-9, speed + np.linalg.norm(c) + 1.0)


@pytest.mark.parametrize("c", [(0.0, 0.0, -0.5), (0.0, 0.0, 0.4), (0.2, -0.3, 0.35), (-0.1, 0.25, -0.6)])
def test_energy_and_duration_with_a_vertical_current(c):
    """A dive of 100 m down and 60 m east, and a climb: the vertical current speeds up or slows
    the vehicle along the track (e.g. a straight dive of 100 m in a 0.5 m/s down-welling at
    1.5 m/s takes 50 s, not 66.7 s)."""
    c = np.asarray(c)
    world = World(Bounds(-500, 500, -500, 500, -500, 0), currents=UniformCurrent(tuple(c)))
    model = CostModel(speed=1.5)
    power = model.hotel_power + model.drag_k * model.speed**3
    for b in ([60.0, 0.0, -300.0], [0.0, 0.0, -300.0], [-40.0, 30.0, -150.0]):
        a, b = np.array([0.0, 0.0, -200.0]), np.array(b)
        e = b - a
        t = np.linalg.norm(e) / _ground_speed(e, c, 1.5)
        _, joules, seconds, blocked = segment_energy(world, a, b, model)
        assert not blocked and seconds == pytest.approx(t, rel=1e-9) and joules == pytest.approx(power * t, rel=1e-9)
        terms = evaluate_paths(world, np.stack([a, b])[None], model)
        assert terms.duration_s[0] == pytest.approx(t, rel=1e-9)
        assert terms.energy[0] == pytest.approx(model.scale * power * t, rel=1e-9)
    if c[0] == c[1] == 0.0:
        _, _, seconds, _ = segment_energy(world, np.array([0.0, 0.0, -200.0]), np.array([0.0, 0.0, -300.0]), model)
        assert seconds == pytest.approx(100.0 / (1.5 - c[2]))


def test_path_cost_counts_each_violating_segment_by_hand():
    """Four 3-point paths in a box far from the origin (x in [1000, 2000]), min depth 5 m, a 10 m
    sphere with a 5 m margin: a clean path; one whose last point is 3 m deep (1 violating segment,
    2 m deep); one starting 10 m west of the box (1 segment, 10 m); one whose first leg passes
    2 m from the sphere with both ends ~90 m away (1 segment, charged the 1 m minimum).  A repeated
    point (zero-length leg) costs nothing, with either energy model; a 0.5 m leg along a 0.5 m/s
    current takes 0.5 / (1.5 + 0.5) s."""
    world = World(Bounds(1000, 2000, -500, 500, -300, 0), obstacles=(Sphere((1500.0, 0.0, -100.0), 10.0),),
                  margins=Margins(min_depth=5.0, max_depth=250.0, obstacle=5.0))
    paths = np.array([
        [[1100.0, 0.0, -50.0], [1200.0, 0.0, -50.0], [1300.0, 0.0, -50.0]],
        [[1100.0, 0.0, -50.0], [1200.0, 0.0, -50.0], [1300.0, 0.0, -3.0]],
        [[990.0, 0.0, -50.0], [1200.0, 0.0, -50.0], [1300.0, 0.0, -50.0]],
        [[1410.0, 12.0, -100.0], [1590.0, 12.0, -100.0], [1590.0, 200.0, -100.0]],
    ])
    terms = evaluate_paths(world, paths, CostModel())
    np.testing.assert_array_equal(terms.violations, [0, 1, 1, 1])
    np.testing.assert_allclose(terms.terrain, [0.0, 1e4 + 100.0 * 2.0, 1e4 + 100.0 * 10.0, 1e4 + 100.0 * 1.0])
    for energy in ("physical", "document"):
        still = np.array([[[1100.0, 0.0, -50.0], [1100.0, 0.0, -50.0], [1200.0, 0.0, -50.0]]])
        t = evaluate_paths(world, still, CostModel(energy=energy))
        assert t.length[0] == 100.0 and t.duration_s[0] == pytest.approx(100.0 / 1.5)
        assert np.isfinite(t.energy[0]) and t.violations[0] == 0
    flowing = World(Bounds(1000, 2000, -500, 500, -300, 0), currents=UniformCurrent((0.5, 0.0, 0.0)))
    t = evaluate_paths(flowing, np.array([[[1100.0, 0.0, -50.0], [1100.5, 0.0, -50.0]]]), CostModel())
    assert t.duration_s[0] == pytest.approx(0.25, rel=1e-12)


# ---------------------------------------------------------------------- the simulator's seabed event
def test_a_dive_into_the_seabed_ends_in_collision():
    """The route goes down to 150 m over a 100 m deep flat seabed: the run must stop at the
    seabed with a collision event, not fly on underground."""
    world = flat_world(depth=100.0, size=1000.0)
    route = ((100.0, 500.0, -20.0), (400.0, 500.0, -150.0), (900.0, 500.0, -150.0))
    r = simulate(world, Mission("dive", route[0], route[-1], route=route), guidance="los", rng=0)
    assert r.status is Status.COLLISION and not r.arrived
    assert r.events[-1][1] == "collision" and "seabed" in r.events[-1][2]
    assert r.altitude[-1] < 0.0 and r.altitude[-1] > -1.0  # stopped within one step of contact
    assert r.position[-1, 2] == pytest.approx(-100.0, abs=1.0)
    assert np.all(r.altitude[:-1] >= 0.0)
    assert r.metrics["collisions"] == 1


# ---------------------------------------------------------------------- the flow planner's sphere field
def test_planner_sphere_field_is_the_exact_image_solution():
    """The FlowField of one sphere is the sink plus its exact image in the (inflated) sphere: it
    matches :func:`sphere_exact_velocity` everywhere and has no normal flux on the surface."""
    c, a, target, margin = np.array([5.0, -3.0, 2.0]), 6.0, np.array([40.0, 30.0, -20.0]), 1.5
    field = FlowField([Sphere(tuple(c), a)], target, FlowParams(), margin=margin)
    inflated = a * (1.0 + SAG_PAD) + margin
    rng = np.random.default_rng(4)
    p = c + rng.normal(size=(500, 3)) * 15.0
    p = p[(np.linalg.norm(p - c, axis=1) > inflated + 0.1) & (np.linalg.norm(p - target, axis=1) > 0.5)]
    np.testing.assert_allclose(field.velocity(p), sphere_exact_velocity(p, c, inflated, target), rtol=1e-10,
                               atol=1e-15)
    n = rng.normal(size=(1000, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    u = field.velocity(c + inflated * n)
    assert np.max(np.abs((u * n).sum(axis=1)) / np.linalg.norm(u, axis=1)) < 1e-9


# ---------------------------------------------------------------------- IABC: one iteration with fixed draws
def test_one_iabc_iteration_mutates_the_worst_and_keeps_only_improvements():
    """Drive IABC by hand: after the employed and onlooker phases (no candidate improves), the
    mutation phase must ask for Gaussian moves of the worst ``mutation_fraction`` sources with the
    decayed sigma, drawn from the optimiser's own generator; worse mutants are rejected, better
    ones replace their source, and the iteration counter advances once."""
    n, dim = 10, 3
    params = IABCParams(variant="document", mutation_fraction=0.3, sigma=0.1, sigma_final=0.01, max_iterations=11,
                        limit=1000)
    opt = IABC(np.full(dim, -1.0), np.full(dim, 1.0), n, params, rng=5)
    X0 = opt.ask()
    f0 = np.arange(n, dtype=float)[::-1] * 1.0  # source 0 is the worst, source 9 the best
    opt.tell(X0, f0)
    for _ in range(2):  # employed, onlooker: every candidate is worse
        V = opt.ask()
        assert V.shape == (n, dim)
        opt.tell(V, np.full(n, 1e9))
    assert opt.iteration == 0
    draws = copy.deepcopy(opt.rng).normal(0.0, 1.0, size=(3, dim))
    M = opt.ask()
    worst = np.array([2, 1, 0])  # ascending f order, last three: f = 7, 8, 9
    assert M.shape == (3, dim)
    expected = np.clip(X0[worst] + draws * 0.1 * 2.0, -1.0, 1.0)  # iteration 0: sigma = 0.1 of the span 2
    np.testing.assert_allclose(M, expected, rtol=1e-12)
    # the worst source's mutant improves, the other two do not
    opt.tell(M, np.array([7.5, 8.5, 3.0]))
    assert opt.iteration == 1
    np.testing.assert_array_equal(opt.X[[2, 1]], X0[[2, 1]])
    np.testing.assert_array_equal(opt.f[[2, 1]], [7.0, 8.0])
    np.testing.assert_array_equal(opt.X[0], M[2])
    assert opt.f[0] == 3.0 and opt.trials[0] == 0
    np.testing.assert_array_equal(opt.X[3:], X0[3:])
    # the next ask is the next iteration's employed phase, with sigma decayed to 0.1 - 0.09 / 10
    assert opt.ask().shape == (n, dim)


def test_rank_probabilities_by_hand():
    """Linear ranking, N = 4: p = (s - (2s - 2) r / 3) / 4 for ranks r = 0..3 (0 the best).
    s = 2: 1/2, 1/3, 1/6, 0; s = 1.5: 3/8, 7/24, 5/24, 1/8 -- whatever the scale of the values."""
    f = np.array([5e5 + 30, 5e5, 5e5 + 10, 5e5 + 20])  # ranks 3, 0, 1, 2
    np.testing.assert_allclose(rank_probabilities(f, 2.0), [0.0, 1 / 2, 1 / 3, 1 / 6], rtol=1e-12)
    np.testing.assert_allclose(rank_probabilities(f * 1e-6, 1.5), [1 / 8, 3 / 8, 7 / 24, 5 / 24], rtol=1e-12)


def test_improved_iabc_onlookers_draw_by_rank_and_random_sources_are_repaired():
    """The improved colony by hand: the chaotic initial sources go through the problem's repair
    (here: each row sorted), and the onlookers are the generator's draws with the linear-ranking
    probabilities (not eq. 21's, which are uniform within 1e-5 at costs ~1e5)."""
    n, dim = 6, 4
    opt = IABC(np.zeros(dim), np.ones(dim), n, IABCParams(limit=1000), rng=3)
    opt.repair = lambda X: np.sort(X, axis=1)
    draws = copy.deepcopy(opt.rng)
    X0 = opt.ask()
    np.testing.assert_array_equal(X0, np.sort(chaotic_uniform_population(n, dim, 4.0, draws), axis=1))
    f0 = 1e5 + np.array([3.0, 0.0, 5.0, 1.0, 4.0, 2.0])
    opt.tell(X0, f0)
    opt.tell(opt.ask(), np.full(n, np.inf))  # employed phase: nothing improves
    expected = copy.deepcopy(opt.rng).choice(n, size=n, p=[2 / 15, 1 / 3, 0.0, 4 / 15, 1 / 15, 1 / 5])
    opt.ask()
    np.testing.assert_array_equal(opt._idx, expected)


def test_along_track_order_by_hand():
    """Start (0, 0, 0), goal (10, 10, 0): projections on the axis are x + y; the points
    (8, 0), (1, 1), (2, 9) (projections 8, 2, 11) come out as (1, 1), (8, 0), (2, 9)."""
    problem = SimpleNamespace(start=np.zeros(3), goal=np.array([10.0, 10.0, 0.0]))
    X = np.array([[8.0, 0.0, -1.0, 1.0, 1.0, -2.0, 2.0, 9.0, -3.0]])
    np.testing.assert_array_equal(along_track_order(problem, X), [[1.0, 1.0, -2.0, 8.0, 0.0, -1.0, 2.0, 9.0, -3.0]])


def test_seeded_iabc_keeps_its_random_sources_unrepaired():
    """With seeds (the lattice's arrangements) the repair is not applied: the seeds sit in the first
    rows as given and the other sources are the plain chaotic ones."""
    problem = Problem(lambda X: X.sum(axis=1), np.zeros(4), np.ones(4), x0=[[0.9, 0.1, 0.5, 0.2]], budget=6,
                      repair=lambda X: np.sort(X, axis=1))
    opt = IABC(np.zeros(4), np.ones(4), 6, IABCParams(), rng=8)
    draws = copy.deepcopy(opt.rng)
    minimize(problem, opt, Termination(max_iterations=None, max_evaluations=6))
    chaos = chaotic_uniform_population(6, 4, 4.0, draws)
    np.testing.assert_array_equal(opt.X[0], [0.9, 0.1, 0.5, 0.2])
    np.testing.assert_array_equal(opt.X[1:], chaos[1:])


# ---------------------------------------------------------------------- GA operators with fixed draws
class FixedDraws:
    """A stand-in generator whose ``random`` returns prescribed arrays in turn."""

    def __init__(self, *arrays):
        self.arrays = list(arrays)

    def random(self, size):
        out = np.broadcast_to(np.asarray(self.arrays.pop(0), dtype=float), size)
        return np.array(out)


def test_sbx_spread_factor_with_fixed_draws():
    """Deb's SBX: β = (2u)^(1/(η+1)) for u ≤ 1/2, (1/(2(1-u)))^(1/(η+1)) otherwise, and
    |c1 - c2| = β |p1 - p2| about the parents' mean.  η = 1: u = 1/4 → β = √½, u = 3/4 → β = √2."""
    p1, p2 = np.array([[0.2, 0.2]]), np.array([[0.6, 0.6]])
    rng = FixedDraws([[0.25, 0.75]], [0.0], [[0.0, 0.0]])  # u, crossover per pair, per coordinate
    c1, c2 = sbx(p1, p2, 1.0, 1.0, 0.0, 1.0, rng)
    beta = np.array([math.sqrt(0.5), math.sqrt(2.0)])
    np.testing.assert_allclose(c1[0], 0.4 - 0.5 * beta * 0.4, rtol=1e-12)
    np.testing.assert_allclose(c2[0], 0.4 + 0.5 * beta * 0.4, rtol=1e-12)
    # no crossover where the per-coordinate coin says so
    c1, c2 = sbx(p1, p2, 1.0, 1.0, 0.0, 1.0, FixedDraws([[0.25, 0.75]], [0.0], [[0.9, 0.0]]))
    assert c1[0, 0] == 0.2 and c2[0, 0] == 0.6


def test_polynomial_mutation_with_fixed_draws():
    """Deb's polynomial mutation, η = 1, x = 0.2 in [0, 1] (δ₁ = 0.2, δ₂ = 0.8):
    u = 1/4: δ = (2u + (1 - 2u)(1 - δ₁)²)^½ - 1 = √0.82 - 1;
    u = 3/4: δ = 1 - (2(1 - u) + 2(u - ½)(1 - δ₂)²)^½ = 1 - √0.52."""
    X = np.full((1, 3), 0.2)
    out = polynomial_mutation(X, 1.0, 0.5, 0.0, 1.0, FixedDraws([[0.25, 0.75, 0.25]], [[0.0, 0.0, 0.9]]))
    np.testing.assert_allclose(out[0], [0.2 + math.sqrt(0.82) - 1.0, 0.2 + 1.0 - math.sqrt(0.52), 0.2], rtol=1e-12)


# ---------------------------------------------------------------------- APF with distinct exponents
def test_apf_force_with_distinct_exponents():
    """|F_att| = k₁ d_g^w₁, |F_rep| = k₂ (1/d_o - 1/r) d_g^w₃ / d_o^w₂ with w₁ = 0.5, w₂ = 1.5,
    w₃ = 2: goal 16 m east, obstacle 4 m north (surface 2 m away), r = 10 m."""
    p = AvoidanceParams(k_att=3.0, w_att=0.5, k_rep=7.0, w_obs=1.5, w_goal=2.0, radius=10.0)
    f = apf_force([1.0, 2.0, -5.0], [17.0, 2.0, -5.0], [[1.0, 6.0, -5.0]], [2.0], p)
    att = 3.0 * 16.0**0.5
    rep = 7.0 * (1 / 2.0 - 1 / 10.0) * 16.0**2 / 2.0**1.5
    np.testing.assert_allclose(f, [att, -rep, 0.0], rtol=1e-12)
    # beyond r only the attraction is left; a distance exactly r repels with zero force
    np.testing.assert_allclose(apf_force([0, 0, 0], [0, 0, -4.0], [[5, 0, 0]], [10.5], p), [0, 0, -6.0])
    np.testing.assert_allclose(apf_force([0, 0, 0], [0, 0, -4.0], [[5, 0, 0]], [10.0], p), [0, 0, -6.0], atol=1e-12)


def test_apf_force_at_and_near_the_goal_and_with_two_obstacles():
    """At the goal the attraction is zero (not 0/0); 0.5 m from it it is k₁ 0.5^w₁; two obstacles'
    repulsions add (mutmut survivors of apf_force, docs/mutants.md)."""
    p = AvoidanceParams(k_att=3.0, w_att=0.5, k_rep=7.0, w_obs=1.5, w_goal=2.0, radius=10.0)
    f = apf_force([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], np.empty((0, 3)), np.empty(0), p)
    assert f.shape == (3,) and np.all(f == 0.0)
    np.testing.assert_allclose(apf_force([0, 0, 0], [0.5, 0, 0], np.empty((0, 3)), [], p), [3.0 * 0.5**0.5, 0, 0])
    two = apf_force([0, 0, 0], [16.0, 0, 0], [[0, 4.0, 0], [0, -8.0, 0]], [2.0, 5.0], p)
    rep = [7.0 * (1 / d - 1 / 10.0) * 16.0**2 / d**1.5 for d in (2.0, 5.0)]
    np.testing.assert_allclose(two, [3.0 * 4.0, -rep[0] + rep[1], 0.0], rtol=1e-12)


# ---------------------------------------------------------------------- hybrid guidance: the lateral bias
@pytest.mark.parametrize("obstacle_y, side", [(0.0, +1.0), (8.0, +1.0), (-8.0, -1.0)])
def test_hybrid_lateral_bias_pushes_away_from_the_obstacle_side(obstacle_y, side):
    """Leg due east from the origin (right normal = south, (0, -1)); vehicle on the route at
    (0, 0).  An obstacle ahead (on the route) or on the port side (north) gets a push to starboard
    (south); one on the starboard side a push to port.  Expected forces by hand:
    attraction (k_X Δ, 0); repulsion mag (1/d - 1/P_o) / d² m_r ρ from the obstacle; bias
    ±b mag along the normal."""
    p = HybridParams(lateral_bias=1.5, current_compensation=False, goal_power=1.0, influence=25.0,
                     k_repulse=100.0, lookahead=15.0, k_heading=1.0)
    ox, d, target = 10.0, 5.0, 12.5
    f = hybrid_force(math.pi / 2, 0.0, p, 0.0, 0.0, [(ox, obstacle_y, d)], target, (-50.0, 0.0))
    mag = 100.0 * (1 / d - 1 / 25.0) / d**2 * (target / 25.0)
    r = np.array([-ox, -obstacle_y]) / math.hypot(ox, obstacle_y)
    expected = np.array([15.0, 0.0]) + mag * r + side * 1.5 * mag * np.array([0.0, -1.0])
    np.testing.assert_allclose(f, expected, rtol=1e-12, atol=1e-12)


# ---------------------------------------------------------------------- route: leg switching at the radius
def test_route_switches_leg_at_the_switch_radius():
    """Legs (0,0) → (100,0) → (100,100), switch radius 12 m: the second leg becomes active at
    88 m along the first, not before and not only at its end."""
    route = RouteTracker([[0, 0, -10], [100, 0, -10], [100, 100, -30]], 12.0)
    rp = route.update(87.9, 1.0)
    assert rp.leg == 0 and rp.progress == pytest.approx(87.9) and not rp.last
    rp = route.update(88.1, 1.0)
    assert rp.leg == 1 and rp.last and rp.course == pytest.approx(0.0)
    assert rp.cross == pytest.approx(-11.9)  # 11.9 m to port (west) of the northbound leg
    assert rp.progress == pytest.approx(100.0 + 1.0)
    route.reset()
    assert route.update(50.0, 0.0).leg == 0 and RouteTracker(route.w, 0.5).update(99.6, 0.0).leg == 1


# ---------------------------------------------------------------------- io.tables: the optional-field error
def test_optional_field_of_the_wrong_type_is_a_scenario_error():
    """``x: float | None`` given a string: a ScenarioError naming the key (was ``raise "<str>"``,
    a TypeError traceback; found by mypy)."""
    from dataclasses import dataclass

    from auvplan.errors import ScenarioError
    from auvplan.io.scenario.tables import build_dataclass

    @dataclass(frozen=True)
    class Spec:
        x: float | None = None

    with pytest.raises(ScenarioError, match="x"):
        build_dataclass(Spec, {"x": "deep"}, "s.toml: [t]")
    assert build_dataclass(Spec, {"x": 2}, "s.toml: [t]").x == 2.0


# ---------------------------------------------------------------------- the simulator's other events
def _open_water(current=(0.0, 0.0, 0.0)) -> World:
    return World(Bounds(-5000, 5000, -500, 500, -100, 0), currents=UniformCurrent(current))


def test_deadlock_is_declared_one_step_after_the_deadlock_time():
    """A 2 m/s current head on against a 1.5 m/s vehicle: the route progress never gains 1 m, so
    without avoidance the run ends in DEADLOCK at the first step after ``deadlock_time`` (60 s):
    t = 60.1 s with dt = 0.1 s; the vehicle has been pushed back, never forward."""
    from auvplan.sim import SimParams

    m = Mission("dl", (0, 0, -20), (1000, 0, -20), route=((0, 0, -20), (1000, 0, -20)),
                sim=SimParams(deadlock_time=60.0))
    r = simulate(_open_water((-2.0, 0.0, 0.0)), m, guidance="hybrid", rng=0, avoidance="none")
    assert r.status is Status.DEADLOCK and r.events[-1][1] == "deadlock" and len(r.events) == 1
    assert r.t[-1] == pytest.approx(60.1, abs=1e-9)
    assert r.position[-1, 0] < 0.0 and r.metrics["collisions"] == 0


def test_arrival_at_the_radius_and_timeout_at_max_time():
    """A 300 m straight leg at 1.5 m/s in still open water: arrival is declared at the first step
    within 10 m of the goal (x ≥ 290 m, not before: ~193 s after the start); with
    ``max_time = 50`` s the same run ends in TIMEOUT after 500 steps, 75 m out."""
    from auvplan.sim import SimParams

    route = ((0.0, 0.0, -20.0), (300.0, 0.0, -20.0))
    m = Mission("arrive", route[0], route[-1], route=route)
    r = simulate(_open_water(), m, guidance="los", rng=0, avoidance="none")
    assert r.status is Status.EXACT and r.arrived and r.events[-1][1] == "arrival" and len(r.events) == 1
    d = np.linalg.norm(r.position - np.array(route[-1]), axis=1)
    assert d[-1] <= 10.0 < d[-2]  # stopped at the first recorded step inside the radius
    assert 290.0 / 1.5 < r.t[-1] < 290.0 / 1.5 + 10.0
    m = Mission("late", route[0], route[-1], route=route, sim=SimParams(max_time=50.0))
    r = simulate(_open_water(), m, guidance="los", rng=0, avoidance="none")
    assert r.status is Status.TIMEOUT and not r.arrived and r.events[-1][1] == "timeout"
    assert r.t[-1] == pytest.approx(50.0) and 60.0 < r.position[-1, 0] < 76.0


def test_collision_names_the_obstacle_that_was_hit():
    """Two spheres: the first well off the route, the second on it; LOS flies straight into the
    second, which the event must name (index 1) at its surface: distance 0 to -1.5 m (one step).
    An ellipsoid thin along the track (semi-axes 5, 30, 5 m) is hit at its surface x = 145 m, not
    where a bounding-sphere bound would put it (x = 120 m).  The scene lies at y = 500 m, z = -20 m
    (so that a mixed-up coordinate cannot go unnoticed)."""
    from auvplan.world.obstacles import Ellipsoid

    route = ((0.0, 500.0, -20.0), (300.0, 500.0, -20.0))
    mission = Mission("hit", route[0], route[-1], route=route)
    w = World(Bounds(-500, 500, 0, 1000, -100, 0),
              obstacles=(Sphere((100.0, 700.0, -20.0), 10.0), Sphere((150.0, 500.0, -20.0), 10.0)))
    r = simulate(w, mission, guidance="los", rng=0, avoidance="none")
    assert r.status is Status.COLLISION and "obstacle 1" in r.events[-1][2]
    assert r.position[-1, 0] == pytest.approx(140.0, abs=1.0)
    assert -1.0 < r.obstacle_distance[-1, 1] < 0.0 and np.all(r.obstacle_distance[:-1] >= 0.0)
    w = World(Bounds(-500, 500, 0, 1000, -100, 0), obstacles=(Ellipsoid((150.0, 500.0, -20.0), (5.0, 30.0, 5.0)),))
    r = simulate(w, mission, guidance="los", rng=0, avoidance="none")
    assert r.status is Status.COLLISION and "obstacle 0" in r.events[-1][2]
    assert r.position[-1, 0] == pytest.approx(145.0, abs=1.0)
    assert -1.0 < r.obstacle_distance[-1, 0] < 0.0


# ---------------------------------------------------------------------- local avoidance: the trap detector
def test_minimum_detector_counts_only_the_points_it_has_seen():
    """Document 004's local-minimum test by hand: r₁ = 2 m, ε₂ = 3 points, one point a second.
    Points are remembered once per second only; the vehicle is trapped when 3 remembered points
    lie within 2 m of the current one, and no longer once it has moved away; the ring buffer
    (50 entries) never counts more points than it holds."""
    from auvplan.guidance.avoidance.local import MinimumDetector

    det = MinimumDetector(radius=2.0, count=3, every=1.0)
    assert not det.update(np.zeros(3), 0.0) and det.n == 1
    assert not det.update(np.zeros(3), 0.5) and det.n == 1  # too soon: not remembered
    assert not det.update(np.array([1.0, 0.0, 0.0]), 1.0) and det.n == 2
    assert det.update(np.array([0.0, 1.5, 0.0]), 2.0) and det.n == 3  # 3 points within 2 m of (0, 1.5, 0)
    assert det.update(np.array([0.0, 1.5, 0.0]), 2.5)  # between records the last answer holds
    assert not det.update(np.array([10.0, 0.0, 0.0]), 3.0) and det.n == 4
    for k in range(60):
        det.update(np.array([100.0 + 10.0 * k, 0.0, 0.0]), 4.0 + k)
    assert det.n == 50
    det.reset()
    assert det.n == 0 and not det.update(np.zeros(3), 100.0)


# ---------------------------------------------------------------------- local avoidance: document 004's logic by hand
def _local(world: World, keys, base: str = "los", **params):
    from auvplan.guidance.avoidance.local import LocalAvoidance
    from auvplan.sim import make_guidance

    route = np.asarray(keys, dtype=float)
    m = Mission("local", tuple(route[0]), tuple(route[-1]), route=tuple(map(tuple, route)))
    return LocalAvoidance(make_guidance(base, route, m), route, world, AvoidanceParams(name="apf", **params), 1.5,
                          rng=0)


_KEYS = [(0.0, 0.0, -50.0), (100.0, 0.0, -50.0), (200.0, 0.0, -50.0), (300.0, 0.0, -50.0)]


def test_apf_goal_skips_key_waypoints_behind_reached_or_occupied():
    """Keys every 100 m along x (arrive radius 10 m): from x = 150 the next goal is key 2 (key 1 is
    behind); from x = 195 key 3 (key 2 reached); the last key is never skipped, even when reached;
    from x = -50 key 1 stays; a parked moving obstacle on key 2 makes the goal skip it."""
    from auvplan.world.moving import LinearMotion, MovingObstacle

    world = _open_water()
    la = _local(world, _KEYS)
    for x, want in ((150.0, 2), (195.0, 3), (295.0, 3), (-50.0, 1), (95.0, 2)):
        la.goal_index = 1
        la._advance_goal(np.array([x, 0.0, -50.0]), 0.0)
        assert la.goal_index == want, x
    parked = MovingObstacle(Sphere((0.0, 0.0, 0.0), 5.0), LinearMotion((200.0, 0.0, -50.0), (0.0, 0.0, 0.0)))
    la = _local(World(world.bounds, moving=(parked,)), _KEYS)
    la._advance_goal(np.array([50.0, 0.0, -50.0]), 0.0)
    assert la.goal_index == 1 and la.skipped == 0
    la._advance_goal(np.array([105.0, 0.0, -50.0]), 0.0)
    assert la.goal_index == 3 and la.skipped == 1


def test_apf_command_heading_pitch_and_the_seabed_floor():
    """In APF mode the command is the APF force's course atan2(Fx, Fy) and pitch
    atan2(Fz, |F_h|); within 2 x arrive (20 m) of the altitude margin a dive is floored at
    10° x (1 - alt / 20 m) nose-up: at 5 m above the margin, 7.5°."""
    world = flat_world(depth=100.0, size=1000.0, min_altitude=5.0)
    keys = [(400.0, 400.0, -40.0), (600.0, 700.0, -94.0), (900.0, 900.0, -60.0)]
    la = _local(world, keys)
    la.mode = "apf"
    p = np.array([500.0, 520.0, -40.0])
    f = apf_force(p, np.array(keys[1]), np.empty((0, 3)), np.empty(0), la.params)
    course, pitch, _ = la._apf_command(p, 0.0, [], 0.0, None)
    assert course == pytest.approx(math.atan2(f[0], f[1]), abs=1e-12)
    assert pitch == pytest.approx(math.atan2(f[2], math.hypot(f[0], f[1])), abs=1e-12) and pitch < 0.0
    low = np.array([500.0, 520.0, -90.0])  # 10 m above the seabed, 5 m above the margin
    course, pitch, _ = la._apf_command(low, 1.0, [], 0.0, None)
    assert pitch == pytest.approx(math.radians(10.0) * (1.0 - 5.0 / 20.0), abs=1e-12)


def test_only_moving_obstacles_within_the_radius_switch_to_apf():
    """Document 004 avoids moving obstacles: a static one nearby leaves the base follower in
    charge (pitch None), a moving one within r = 30 m switches to the APF (a pitch command)."""
    la = _local(_open_water(), _KEYS, base="hybrid")
    static = (60.0, 5.0, 8.0, False, (60.0, 5.0, -50.0))
    psi, pitch, _ = la.command(np.array([50.0, 0.0, -50.0]), 0.0, np.zeros(3), [static], 0.1)
    assert pitch is None and la.mode == "route"
    moving = (60.0, 5.0, 8.0, True, (60.0, 5.0, -50.0), 0, np.zeros(3), 5.0)
    psi, pitch, _ = la.command(np.array([50.0, 0.0, -50.0]), 0.1, np.zeros(3), [moving], 0.1)
    assert pitch is not None and la.mode == "apf"


def test_escape_sub_goal_with_the_generators_draws_and_its_time_limit():
    """A stall runs document 004's escape: the sub-goal is the first free candidate of the
    draws angle ~ U(0, 2π), radius r √U(¼, 1), dz ~ U(-0.2, 0.2) r (copied from a generator with the
    same seed; r = 60 m, open water: the first candidate); the mode switches to APF; after
    ``escape_time`` (300 s) of one stall the escapes give up (a deadlock may be declared)."""
    from auvplan._types import as_rng

    la = _local(_open_water(), _KEYS)
    rng = as_rng(0)
    ang, rad = rng.uniform(0, 2 * np.pi, 64), 60.0 * np.sqrt(rng.uniform(0.25, 1.0, 64))
    dz = rng.uniform(-0.2, 0.2, 64) * 60.0
    p = np.array([50.0, 0.0, -50.0])
    assert la.stalled(p, 10.0, since=0.0)
    want = p + np.array([rad[0] * math.cos(ang[0]), rad[0] * math.sin(ang[0]), dz[0]])
    np.testing.assert_allclose(la.subgoal, want, rtol=0, atol=1e-9)
    assert la.escapes == 1 and la.mode == "apf"
    assert la.stalled(p, 309.9, since=0.0)
    assert not la.stalled(p, 310.0, since=0.0)


def test_the_moving_obstacle_that_hits_decides_unavoidable():
    """Scene at y = 500 m: a static sphere far off (index 0, the farthest), a moving sphere coming head
    on down the route (1) and a slow one far off (2).  At 3 m/s (twice the vehicle's speed) the hit
    is UNAVOIDABLE and names obstacle 1; at 0.5 m/s it is a plain COLLISION (the vehicle could have
    avoided it).  Recording every 7th step still ends on the final state, and far obstacles are
    recorded at the lower bound |p - c| - r (exact for spheres)."""
    from auvplan.sim import SimParams
    from auvplan.world.moving import LinearMotion, MovingObstacle

    route = ((0.0, 500.0, -20.0), (600.0, 500.0, -20.0))
    for speed, status in ((3.0, Status.UNAVOIDABLE), (0.5, Status.COLLISION)):
        moving = (MovingObstacle(Sphere((0.0, 0.0, 0.0), 5.0), LinearMotion((400.0, 500.0, -20.0), (-speed, 0.0, 0.0))),
                  MovingObstacle(Sphere((0.0, 0.0, 0.0), 5.0), LinearMotion((100.0, 900.0, -20.0), (0.2, 0.0, 0.0))))
        w = World(Bounds(-500, 1000, 0, 1000, -100, 0), obstacles=(Sphere((300.0, 20.0, -20.0), 10.0),), moving=moving)
        m = Mission("hit", route[0], route[-1], route=route, sim=SimParams(record_every=7))
        r = simulate(w, m, guidance="los", rng=0, avoidance="none")
        assert r.status is status and "obstacle 1" in r.events[-1][2], (speed, r.events[-1])
        assert r.t[-1] == pytest.approx(r.events[-1][0]) and r.obstacle_distance[-1, 1] < 0.0
        assert r.obstacle_distance[-1, 0] > r.obstacle_distance[-1, 2] > 0.0
        far = np.linalg.norm(r.position - np.array([300.0, 20.0, -20.0]), axis=1) - 10.0
        np.testing.assert_allclose(r.obstacle_distance[:, 0], far, rtol=1e-9)


def test_world_bounds_depth_band_and_two_point_paths_by_hand():
    """Box x in [1000, 2000], y in [-500, 500], z in [-300, 0], depth band 5-250 m: the slack of a
    point is its least distance to a face (by hand); a segment with one end outside the box is not
    free; one exactly at the maximum depth is; a two-point path through a sphere is not free
    although both of its points are."""
    w = World(Bounds(1000, 2000, -500, 500, -300, 0), obstacles=(Sphere((1500.0, 0.0, -100.0), 10.0),),
              margins=Margins(min_depth=5.0, max_depth=250.0, obstacle=0.0))
    pts = np.array([[1010.0, 0.0, -100.0], [1950.0, 0.0, -100.0], [1500.0, -480.0, -100.0],
                    [1500.0, 470.0, -100.0], [1500.0, 0.0, -290.0], [1500.0, 0.0, -8.0]])
    np.testing.assert_allclose(w.bounds.slack(pts), [10.0, 50.0, 20.0, 30.0, 10.0, 8.0])
    seg = np.array([[[1100.0, 0.0, -50.0], [1200.0, 0.0, -50.0]],
                    [[1100.0, 0.0, -50.0], [990.0, 0.0, -50.0]],
                    [[1100.0, 0.0, -250.0], [1200.0, 0.0, -250.0]],
                    [[1100.0, 0.0, -50.0], [1200.0, 0.0, -251.0]]])
    np.testing.assert_array_equal(w.segments_free(seg), [True, False, True, False])
    through = np.array([[1400.0, 0.0, -100.0], [1600.0, 0.0, -100.0]])
    assert w.is_free(through).all() and not w.path_free(through)
    assert w.path_free(through[:1]) and w.path_free(np.array([[1400.0, 0.0, -100.0], [1400.0, 50.0, -100.0]]))


def test_apf_mode_at_a_key_waypoint_returns_to_the_route_or_heads_for_the_next():
    """Reaching a key waypoint in APF mode: with no moving obstacle near, the base follower takes
    over again (no pitch command); with one near, the goal moves on to the next key."""
    la = _local(_open_water(), _KEYS)
    la.mode, la.goal_index = "apf", 1
    _, pitch, _ = la._apf_command(np.array([98.0, 0.0, -50.0]), 0.0, [], 0.3, None)
    assert pitch is None and la.mode == "route" and la.goal_index == 1
    la.mode = "apf"
    near = [(120.0, 20.0, 25.0, True, (120.0, 20.0, -50.0))]
    _, pitch, _ = la._apf_command(np.array([98.0, 0.0, -50.0]), 1.0, near, 0.3, None)
    assert pitch is not None and la.mode == "apf" and la.goal_index == 2


def test_planner_sphere_field_clearance_and_the_sink_by_hand():
    """Two spheres (radii 6 and 3 m, margin 1.5 m): the field's clearance is the distance to the
    nearest sphere minus its radius and the margin (negative inside); the target sink's velocity is
    -m r / (4π |r|³) also within a metre of the target (0.5 m: 4 m / (4π 0.25) = 1.27 m/s)."""
    from auvplan.planners.flow.elements import sink_velocity

    field = FlowField([Sphere((0.0, 0.0, -50.0), 6.0), Sphere((40.0, 0.0, -50.0), 3.0)],
                      np.array([100.0, 0.0, -50.0]), FlowParams(), margin=1.5)
    p = np.array([[0.0, 10.0, -50.0], [30.0, 0.0, -50.0], [40.0, 0.0, -47.0], [0.0, 0.0, -53.0]])
    np.testing.assert_allclose(field.clearance(p), [10.0 - 7.5, 10.0 - 4.5, 3.0 - 4.5, 3.0 - 7.5], atol=1e-12)
    target = np.array([100.0, 0.0, -50.0])
    u = sink_velocity(target + np.array([0.0, 0.5, 0.0]), target, m=4.0)
    np.testing.assert_allclose(u, [0.0, -4.0 / (4 * math.pi * 0.25), 0.0], rtol=1e-12)


def test_free_edges_are_exactly_the_free_lattice_segments():
    """A 3 x 3 x 2 lattice (10 m) with two 2 m spheres sitting on lattice edges, 2.5 m from one end
    (both end nodes free: 0.5 m and 5.5 m from the surface): the edges :func:`free_edges` returns for
    each of the 13 offsets are exactly the pairs of free nodes whose segment the World's exact test
    calls free (the obstacle shortcut may only skip the exact test where it cannot matter)."""
    from auvplan.planners.grid.lattice import HALF, free_edges

    world = World(Bounds(-1, 21, -1, 21, -21, 0),
                  obstacles=(Sphere((2.5, 0.0, -10.0), 2.0), Sphere((10.0, 17.5, -20.0), 2.0)),
                  margins=Margins(min_depth=0.0, obstacle=0.0))
    axes = (np.array([0.0, 10.0, 20.0]), np.array([0.0, 10.0, 20.0]), np.array([-20.0, -10.0]))
    shape = (3, 3, 2)
    xyz = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    slack = world.clearances(xyz, moving=False)
    free = (np.minimum.reduce(list(slack.values())) >= 0.0).reshape(shape)
    assert free.all()
    ids = np.arange(xyz.shape[0]).reshape(shape)
    steps = np.array([10.0, 10.0, 10.0])
    blocked = 0
    for off in HALF:
        src, dst = free_edges(world, free, slack["altitude"].reshape(shape), slack["obstacles"].reshape(shape),
                              steps, off, xyz.__getitem__)
        a = tuple(slice(max(0, -d), n - max(0, d)) for d, n in zip(off, shape))
        b = tuple(slice(max(0, d), n - max(0, -d)) for d, n in zip(off, shape))
        s, d = ids[a].reshape(-1), ids[b].reshape(-1)
        ok = world.segments_free(np.stack([xyz[s], xyz[d]], axis=1), moving=False)
        blocked += int((~ok).sum())
        assert sorted(zip(src.tolist(), dst.tolist())) == sorted(zip(s[ok].tolist(), d[ok].tolist())), off
    assert blocked >= 2


def test_push_out_puts_points_on_the_ray_from_the_centre_just_outside_the_flow_sphere():
    """Points inside the flow surfaces of two spheres (flow radii A = 7.512 and 4.506 m) are moved along
    the ray from their sphere's centre to A + eps·max(A) (eps relative to the largest radius): by hand,
    (0, 3, -50) → (0, A₀(1 + eps), -50) and (40, 0, -49) → (40, 0, -50 + A₁ + eps A₀)."""
    field = FlowField([Sphere((0.0, 0.0, -50.0), 6.0), Sphere((40.0, 0.0, -50.0), 3.0)],
                      np.array([100.0, 0.0, -50.0]), FlowParams(), margin=1.5)
    a0, a1 = field.radii
    assert a0 > a1 > 0
    eps = 1e-3
    moved = field.push_out(np.array([[0.0, 3.0, -50.0], [40.0, 0.0, -49.0]]), eps)
    np.testing.assert_allclose(moved, [[0.0, a0 + eps * a0, -50.0], [40.0, 0.0, -50.0 + a1 + eps * a0]],
                               rtol=0, atol=1e-12)
    assert (field.distances(moved, "true").min(axis=-1) > 0).all()


def test_streamline_segment_clear_is_the_sampled_flow_clearance():
    """``_segment_clear``: a chord through the inflated sphere (clearance −7.5 m at its middle) is not
    clear; one 10 m above the centre (closest clearance 10 − 7.5 = 2.5 m) and one ending on the surface
    (clearance 0 at the end: clear) are; each axis-aligned so a component of b − a is zero."""
    from auvplan.planners.flow.stream import _segment_clear

    field = FlowField([Sphere((0.0, 0.0, -50.0), 6.0)], np.array([100.0, 0.0, -50.0]), FlowParams(), margin=1.5)
    assert not _segment_clear(field, np.array([0.0, -20.0, -50.0]), np.array([0.0, 20.0, -50.0]))
    assert _segment_clear(field, np.array([0.0, -20.0, -40.0]), np.array([0.0, 20.0, -40.0]))
    assert _segment_clear(field, np.array([-30.0, 0.0, -50.0]), np.array([-7.5, 0.0, -50.0]))


EXIT_STARTS = int(os.environ.get("AUVPLAN_EXIT_STARTS", "20"))
"""Seeded starts of the exit-rule oracle: 20 in the suite (~0.4 s of CPU each, 17 of them through the direction
search), 60 in ``make oracles-full``."""


def test_exit_rule_leaves_a_line_distribution_body_just_outside_its_surface():
    """Starts inside the flow body of an ellipsoid (20 × 6 × 4 m, margin 1 m): the exit rule's last point
    lies outside every flow surface and within 1e-4 of the body's radius of it (the rule steps to
    1e-6 R beyond the surface, by the normal or by bisection along the gradient); :data:`EXIT_STARTS` seeded
    starts (the first of the same 60 draws)."""
    from auvplan.planners.flow.stream import _exit_body
    from auvplan.world import Ellipsoid

    field = FlowField([Ellipsoid((0.0, 0.0, -50.0), (20.0, 6.0, 4.0))], np.array([100.0, 0.0, -50.0]),
                      FlowParams(), margin=1.0)
    assert field.contained
    radius = float(field.radii[0])
    rng = np.random.default_rng(5)
    starts = rng.uniform(-1.0, 1.0, (400, 3)) * (20.0, 6.0, 4.0) + (0.0, 0.0, -50.0)
    inside = starts[field.distances(starts, "true").min(axis=-1) < 0][:60]
    assert len(inside) == 60
    inside = inside[:EXIT_STARTS]
    for p in inside:
        out = _exit_body(field, p.copy())
        assert out, p
        d = float(field.distances(out[-1][None], "true").min())
        assert 0.0 <= d <= 1e-4 * radius, (p, d)


@pytest.mark.parametrize("twist", [1e-5, 5e-5, 3e-4])
def test_shallow_interior_minimum_of_a_twisted_cell_is_found(twist):
    """One bilinear cell z = −200 + k·x·y (k small: the altitude along the anti-diagonal at −150 m is the
    shallow parabola 50 − 10⁴ k t(1 − t)): the exact segment test returns its interior minimum
    50 − 2 500 k, below both ends (50 m), however small the curvature."""
    x = y = np.array([0.0, 100.0])
    gx, gy = np.meshgrid(x, y)
    terrain = Terrain(x, y, -200.0 + twist * gx * gy)
    got = terrain.min_altitude_between(np.array([[0.0, 100.0, -150.0]]), np.array([[100.0, 0.0, -150.0]]))
    assert got[0] == pytest.approx(50.0 - 2500.0 * twist, abs=1e-9)


def test_segment_test_on_a_grid_with_more_rows_than_columns():
    """A grid of 2 columns × 11 rows (10 m), its seabed a zigzag in y with peaks at odd rows: a level
    segment along y crosses all ten rows of cells, and its exact minimum altitude is the dense-sampled
    bilinear one (scipy's interpolator at the row crossings and 2 001 points), at a peak — every row
    crossing must split."""
    x = np.array([0.0, 10.0])
    y = np.arange(11) * 10.0
    ridge = np.where(np.arange(11) % 2 == 1, -80.0, -100.0) - 0.5 * np.arange(11)
    z = np.repeat(ridge[:, None], 2, axis=1) + np.array([0.0, 3.0])
    terrain = Terrain(x, y, z)
    a, b = np.array([[4.0, 1.0, -60.0]]), np.array([[6.0, 99.0, -60.0]])
    # the seabed has no twist here (its x-slope is the same in every row), so along the segment it is
    # piecewise linear with kinks at the row crossings: samples there and in between give the exact minimum
    kinks = (y[1:-1] - a[0, 1]) / (b[0, 1] - a[0, 1])
    s = np.sort(np.r_[np.linspace(0.0, 1.0, 2001), kinks])[:, None]
    pts = a + s * (b - a)
    zb = RegularGridInterpolator((y, x), z)(np.c_[pts[:, 1], pts[:, 0]])
    expected = float((pts[:, 2] - zb).min())
    assert terrain.min_altitude_between(a, b)[0] == pytest.approx(expected, abs=1e-9)
