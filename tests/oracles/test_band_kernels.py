"""Issue 59 (CPU): the elastic band's compiled pass and the polish's give-up.

The band's array work is compiled (:mod:`auvplan.planners.grid.band_kernels`); the oracle is the numpy
formulation it replaced, written out here (normals from ``band._normals``, the five moves, numpy's
``argmin`` and the step updates), which must move every point to the same bits on paths that exercise
each branch: a zero chord, steep chords, points blocked by a sphere, a current that varies in space.
The give-up (:func:`auvplan.planners.grid.band.gives_up`) is checked by hand and on a real plan: the
lattice candidate's refinement stops early and the plan is the same, to the bit, as with it run out.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from auvplan.cost import CostModel
from auvplan.planners.grid import band
from auvplan.world import Sphere
from auvplan.world.currents.fields import LambOseenVortices
from helpers import flat_world


def _einsum_sums_x_z_then_y() -> bool:
    """Whether this numpy's ``einsum`` adds three terms as ``(x + z) + y`` (its SIMD reduction on x86-64 and
    arm64 builds: the order the kernels copy to give the same bits).  Another build may add them in another
    order; the kernels are then equal to numpy to the last bits only, and the tests below say so."""
    v = np.array([[1.0, 1e-16, -1.0]])
    return float(np.einsum("ij,ij->i", v, np.ones_like(v))[0]) == (1.0 + -1.0) + 1e-16


SAME_ORDER = _einsum_sums_x_z_then_y()


def assert_same_bits(got: np.ndarray, want: np.ndarray) -> None:
    """Bit for bit where numpy sums as the kernels do; else to a few units in the last place."""
    if SAME_ORDER:
        assert got.tobytes() == want.tobytes()
    else:  # pragma: no cover - a numpy build with another einsum order
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-9)


def _relax_numpy(world, p, model, objective, iterations, step):
    """The band as it was before the kernels (numpy throughout): the oracle."""
    p = p.copy()
    n = p.shape[0]
    alpha, delta, tol = np.full(n, 0.5), np.full(n, 0.5 * step), 1e-3 * step
    for _ in range(iterations):
        for every in (np.arange(1, n - 1, 2), np.arange(2, n - 1, 2)):
            i = every[(alpha[every] > 1e-3) | (delta[every] > tol)]
            if i.size == 0:
                continue
            m = i.size
            a, b, c = p[i - 1], p[i], p[i + 1]
            n1, n2 = band._normals(c - a)
            d = delta[i, None]
            pts = np.stack([b, b + alpha[i, None] * (0.5 * (a + c) - b), b + d * n1, b - d * n1, b + d * n2,
                            b - d * n2])
            cost = band.edge_cost(world, np.concatenate([np.broadcast_to(a, (6, m, 3)), pts]),
                                  np.concatenate([pts, np.broadcast_to(c, (6, m, 3))]), model, objective)
            both = cost[:6] + cost[6:]
            better = both[1:] < both[0] - 1e-9 * np.abs(both[0])
            for kk, jj in zip(*np.nonzero(better), strict=True):
                seg = np.array([[a[jj], pts[kk + 1, jj]], [pts[kk + 1, jj], c[jj]]])
                better[kk, jj] = world.segments_free(seg, moving=False).all()
            new = np.where(better, both[1:], np.inf)
            k = np.argmin(new, axis=0)
            ok = np.isfinite(new[k, np.arange(m)])
            p[i[ok]] = pts[k[ok] + 1, np.flatnonzero(ok)]
            pulled, pushed = ok & (k == 0), ok & (k > 0)
            alpha[i[pulled]] = np.minimum(alpha[i[pulled]] * 1.5, 1.0)
            delta[i[pushed]] = np.minimum(delta[i[pushed]] * 1.5, step)
            alpha[i[~pulled]] *= 0.5
            delta[i[~pushed]] *= 0.5
    return p


@pytest.fixture(scope="module")
def scene():
    """A sphere in the way, a vortex current, and a zig-zag path with a zero chord and steep chords."""
    world = flat_world(depth=400.0, size=2000.0, obstacles=(Sphere(np.array([1000.0, 1000.0, -200.0]), 150.0),),
                       obstacle=10.0, min_depth=10.0)
    world = replace(world, currents=LambOseenVortices(np.array([[900.0, 1300.0], [1400.0, 600.0]]),
                                                      np.array([1500.0, -1000.0]), np.array([300.0, 200.0])))
    rng = np.random.default_rng(7)
    t = np.linspace(0.0, 1.0, 41)[:, None]
    p = np.array([100.0, 800.0, -200.0]) * (1 - t) + np.array([1900.0, 800.0, -200.0]) * t
    p[1:-1] += rng.normal(0.0, 25.0, (39, 3))
    p[10], p[12] = p[9] + [0.0, 0.0, 30.0], p[9] + [0.0, 0.0, 60.0]  # steep chords
    p[20] = p[18]  # p[19]'s neighbours coincide: a zero chord
    assert world.path_free(p)
    return world, p


@pytest.mark.parametrize("objective", ["cost", "length"])
@pytest.mark.parametrize("step", [40.0, 400.0])
def test_the_compiled_band_moves_every_point_to_the_same_bits_as_numpy(scene, objective, step):
    world, p = scene
    model = CostModel(speed=1.5)
    want = _relax_numpy(world, p, model, objective, 4, step)
    got = band._relax(world, p, model, objective, 4, step)
    assert np.abs(want - p).max() > 1.0  # the band did move points: the comparison has teeth
    assert_same_bits(got, want)
    # the rows handed to the exact test: (a -> move, move -> c) of each move, as numpy's fancy indexing
    from auvplan.planners.grid.band_kernels import band_moves, band_segments

    i = np.arange(1, p.shape[0] - 1, 2)
    ends, tips = np.empty((12, i.size, 3)), np.empty((12, i.size, 3))
    band_moves(p, i, np.full(p.shape[0], 0.5), np.full(p.shape[0], 0.5 * step), ends, tips)
    picked = np.random.default_rng(5).random((5, i.size)) < 0.5
    kk, jj = (np.ascontiguousarray(v) for v in np.nonzero(picked))  # C, as band.py passes them
    seg = np.empty((kk.size, 2, 2, 3))
    band_segments(ends, tips, kk, jj, seg)
    moves = tips[kk + 1, jj]
    want = np.stack([np.stack([p[i[jj] - 1], moves], 1), np.stack([moves, p[i[jj] + 1]], 1)], 1)
    np.testing.assert_array_equal(seg, want)


def test_level_count_and_give_up_by_hand():
    """1/8 … 1/512 of the length is 7 levels, … 1/2048 is 9, … 1/64 is 4; a refinement at 110 against a
    target of 100 gives up with 2 levels left gaining at most 4 each (110 - 8 >= 100), not at most 6."""
    assert [band.level_count(f) for f in (512.0, 2048.0, 64.0, 8.0, 4.0)] == [7, 9, 4, 1, 0]
    assert band.gives_up(110.0, 100.0, 4.0, 2) and not band.gives_up(110.0, 100.0, 6.0, 2)
    assert band.gives_up(100.0, 100.0, 50.0, 0) and not band.gives_up(99.9, 100.0, 0.0, 0)


def test_the_lattice_candidate_gives_up_and_the_plan_is_the_same(monkeypatch):
    """showcase: the seeding lattice's polygon (+0.08 % above the spline, within ``LATTICE_WITHIN``) gains
    nothing on its first level, so its refinement stops after one level instead of seven; the plan, its
    path and its convergence verdict are the same, to the bit, as with the refinement run out."""
    from auvplan.io.scenario import loader as sc
    from auvplan.planners import plan
    from auvplan.planners.grid import planner as gp
    from auvplan.sim import planning_problem

    world, mission = sc.build(sc.load("showcase"))
    prob, spec = planning_problem(world, mission), mission.planner
    levels: list[tuple[float | None, int]] = []
    real = band._converge

    def spy(*args, target=None, **kwargs):
        out = real(*args, target=target, **kwargs)
        levels.append((target, out[2]))
        return out

    monkeypatch.setattr(gp, "_converge", spy)
    quick = plan(prob, spec, rng=1)
    gave_up = list(levels)
    levels.clear()
    monkeypatch.setattr(gp, "_converge", lambda *a, target=None, **k: spy(*a, target=None, **k))
    full = plan(prob, spec, rng=1)
    assert [n for t, n in gave_up if t is not None] == [1] and [n for _, n in levels] == [7, 7]
    assert quick.cost == full.cost and quick.path.tobytes() == full.path.tobytes()
    assert quick.converged is full.converged is True
    assert quick.work["polish_lattice_cost"] >= quick.cost


def test_the_compiled_box_test_answers_as_the_numpy_comparisons():
    """``World.segments_free``'s convex part (:mod:`auvplan.world.kernels.box`) against numpy's comparisons
    on segments with ends exactly on each face, just outside it, NaN and infinite coordinates, in a
    world with a depth band (min 10 m, max 300 m) and no seabed, in shapes ``(2, 3)`` and ``(4, 5, 2, 3)``."""
    from auvplan.world import Bounds, Margins, World

    b = Bounds(-50.0, 950.0, 20.0, 1020.0, -400.0, 0.0)
    world = World(b, None, margins=Margins(min_altitude=0.0, min_depth=10.0, max_depth=300.0))
    rng = np.random.default_rng(3)
    faces = np.array([[-50.0, 950.0], [20.0, 1020.0], [-300.0, -10.0]])
    s = rng.uniform(-60.0, 1030.0, (4, 5, 2, 3))
    s[..., 2] = rng.uniform(-310.0, 0.0, (4, 5, 2))
    for k, (axis, side) in enumerate([(0, 0), (0, 1), (1, 0), (1, 1), (2, 0), (2, 1)]):
        s[0, k % 5, k % 2, axis] = faces[axis, side]  # on the face: inside
        s[1, k % 5, k % 2, axis] = np.nextafter(faces[axis, side], np.inf if side else -np.inf)  # just out
    s[2, 0, 0, 0], s[2, 1, 1, 2], s[2, 2, 0, 1], s[2, 3, 1, 2] = np.nan, np.nan, np.inf, -np.inf
    z = s[..., 2]
    with np.errstate(invalid="ignore"):
        want = np.all(-z >= 10.0, axis=-1) & np.all(-z <= 300.0, axis=-1) & b.contains(s).all(axis=-1)
    got = world.segments_free(s)
    assert got.shape == want.shape and (got == want).all() and 3 < want.sum() < want.size - 3
    assert bool(world.segments_free(s[0, 1])) == bool(want[0, 1])


def test_chord_lengths_are_numpys_norm_to_the_bit():
    """``edge_cost``'s lengths (compiled :func:`~auvplan.planners.grid.band_kernels.chord_lengths`) equal
    ``numpy.linalg.norm(b - a, axis=-1)`` bit for bit over magnitudes from 1e-3 to 1e6 m, and for a
    single segment (numpy's path) too."""
    rng = np.random.default_rng(11)
    a = rng.normal(size=(12, 40, 3)) * 10.0 ** rng.uniform(-3, 6, (12, 40, 1))
    b = a + rng.normal(size=(12, 40, 3)) * 10.0 ** rng.uniform(-3, 6, (12, 40, 1))
    got = band.edge_cost(None, a, b, CostModel(), "length")  # the length objective never asks the world
    assert got.tobytes() == np.linalg.norm(b - a, axis=-1).tobytes()
    assert band.edge_cost(None, a[0, 0], b[0, 0], CostModel(), "length") == np.linalg.norm(b[0, 0] - a[0, 0])


def test_the_fronts_depth_schedule_table_is_the_field_slice_by_slice():
    """``build_grid`` with a depth schedule asks the field once per depth for all that depth's times
    (:meth:`CurrentField.sample`) instead of once per time slice (juan-de-fuca-tides: 1.2 -> 0.3 s of a
    3-4 s plan, the same plan): every slice must still be the field at that slice's own depth and time.  A
    gridded current varying in x, y, z and t, a schedule diving 20 -> 180 m and back (10-min slices over
    6 h), against the field's ``velocity`` slice by slice: the same float32 table, to the bit."""
    from auvplan.planners.timeopt.front import build_grid
    from auvplan.world import GriddedCurrent

    ax, zax, tax = np.linspace(0.0, 2000.0, 5), np.array([-400.0, -200.0, -100.0, 0.0]), np.linspace(0, 7 * 3600, 8)
    T, Z, Y, X = np.meshgrid(tax, zax, ax, ax, indexing="ij")
    u = 0.3 * np.sin(X / 700.0 + T / 9000.0) + Z / 500.0
    v = 0.2 * np.cos(Y / 500.0 - T / 7000.0) * (1.0 + Z / 400.0)
    world = replace(flat_world(depth=400.0, size=2000.0), currents=GriddedCurrent(ax, ax, zax, u, v, t=tax))
    schedule = (np.array([0.0, 3 * 3600.0, 6 * 3600.0]), np.array([-20.0, -180.0, -20.0]))
    g = build_grid(world, (0.0, 0.0), (2000.0, 2000.0), 250.0, (-20.0, -20.0), 0.0, 6 * 3600.0, 600.0, schedule)
    zt = np.round(np.interp(g.dt * np.arange(g.cur.shape[0]), *schedule))
    xx, yy = np.meshgrid(*(250.0 * np.arange(n) for n in g.cur.shape[1:3]), indexing="ij")
    want = np.stack([world.currents.velocity(np.stack([xx.ravel(), yy.ravel(), np.full(xx.size, z)], axis=1),
                                             g.dt * k)[:, :2] for k, z in enumerate(zt)])
    assert 10 < np.unique(zt).size < zt.size  # many depths, and slices that share one
    assert g.cur.tobytes() == want.reshape(g.cur.shape).astype(np.float32).tobytes()


@pytest.mark.parametrize("margin", [0.0, 10.0])
def test_the_compiled_sphere_slack_is_the_numpy_loop_to_the_bit(margin):
    """``cost.paths._obstacle_slack`` folds every sphere in one compiled pass (track-multi: 9 spheres, 80 % of its
    swarm's CPU in the per-sphere numpy loop); the oracle is that loop (``Sphere.distance`` and
    ``Sphere.segments_hit``, numpy's ``einsum``/``norm``): the same slack and clearance to the bit on
    segments through, beside and inside three spheres and an ellipsoid (the loop's own path), zero-length
    segments included, with and without a margin."""
    from auvplan.cost.paths import _obstacle_slack
    from auvplan.world import Ellipsoid

    spheres = [Sphere(np.array([500.0, 500.0, -100.0]), 40.0), Sphere(np.array([560.0, 520.0, -90.0]), 25.0),
               Sphere(np.array([300.0, 700.0, -150.0]), 60.0)]
    ell = Ellipsoid(np.array([700.0, 300.0, -120.0]), np.array([50.0, 30.0, 20.0]))
    world = flat_world(depth=400.0, size=1000.0, obstacles=(*spheres, ell), obstacle=margin)
    rng = np.random.default_rng(17)
    a = rng.uniform([200.0, 200.0, -250.0], [800.0, 800.0, -20.0], (6, 40, 3))
    b = a + rng.normal(0.0, 80.0, a.shape)
    b[0, :5] = a[0, :5]  # zero-length segments
    slack, clear = np.full(a.shape[:-1], np.inf), np.full(a.shape[:-1], np.inf)
    ends = np.stack([a, b], axis=-2)
    for shape in world.obstacles:
        d = np.minimum(shape.distance(a), shape.distance(b))
        touch = shape.segments_hit(ends, 0.0)
        hit = shape.segments_hit(ends, margin) if margin > 0 else touch
        clear = np.minimum(clear, np.where(touch, np.minimum(d, 0.0), d))
        slack = np.minimum(slack, np.where(hit, np.minimum(d - margin, -1.0), d - margin))
    got_slack, got_clear = _obstacle_slack(world, a, b)
    assert (slack < 0).sum() > 10 and (clear > 0).sum() > 10
    assert_same_bits(got_slack, slack)
    assert_same_bits(got_clear, clear)
