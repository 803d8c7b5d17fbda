"""Lattice reference planner: analytic distances, the sphere geodesic, exactness, plan once / query many."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.planners import GridParams, GridReference, PlannerSpec, PlanningProblem, plan, plan_grid, with_reference
from auvplan.planners.core.common import cost_model_for, path_cost, search_box
from auvplan.planners.grid.band import edge_cost
from auvplan.sim import planning_problem
from auvplan.world import Bounds, Margins, Sphere, Terrain, World
from helpers import flat_world


def grid_spec(**kw) -> PlannerSpec:
    return PlannerSpec(name="grid", grid=GridParams(**kw))


@pytest.mark.parametrize("objective", ["length", "cost"])
def test_empty_world_gives_the_straight_line(objective):
    world = flat_world(depth=200.0, size=1000.0)
    start, goal = np.array([37.0, 81.0, -150.0]), np.array([913.0, 777.0, -40.0])
    r = plan(PlanningProblem(world, start, goal, 1.5), grid_spec(objective=objective, cell=40.0))
    assert r.status is Status.EXACT
    np.testing.assert_allclose(r.path, np.stack([start, goal]))
    assert r.cost_terms["length_m"] == pytest.approx(np.linalg.norm(goal - start), rel=1e-12)


def test_cost_to_go_is_the_26_connected_lattice_distance():
    """Oracle: with no obstacle, the cost-to-go of a node is the best, over the nodes k within
    two cells of the goal (which the goal links to directly), of |k - goal| plus the 3D octile
    distance ``(a - b) + √2 (b - c) + √3 c`` (cell counts sorted a ≥ b ≥ c) from the node to k."""
    world = World(Bounds(0, 200, 0, 200, -200, 0), margins=Margins(min_altitude=0.0, min_depth=-np.inf))
    prob = PlanningProblem(world, [10.0, 10.0, -190.0], [100.0, 100.0, -100.0], 1.5)
    spec = grid_spec(objective="length", cell=20.0, cell_z=20.0, any_angle=0)
    lo, hi = search_box(prob)
    ref = GridReference(world, prob.goal, cost_model_for(prob, spec), lo, hi, spec.grid)
    assert ref.shape == (11, 11, 11) and np.allclose([ax[5] for ax in ref.axes], prob.goal)
    idx = np.stack(np.meshgrid(*(np.arange(11),) * 3, indexing="ij"), axis=-1)
    best = np.full((11, 11, 11), np.inf)
    for k in np.ndindex(5, 5, 5):
        k = np.array(k) + 3
        d = np.sort(np.abs(idx - k), axis=-1)[..., ::-1].astype(float)
        octile = (d[..., 0] - d[..., 1]) + np.sqrt(2) * (d[..., 1] - d[..., 2]) + np.sqrt(3) * d[..., 2]
        best = np.minimum(best, 20.0 * (octile + np.linalg.norm(k - 5)))
    np.testing.assert_allclose(ref.cost_to_go, best, atol=1e-9)
    assert ref.edges == 2 * (3 * 11 * 11 * 10 + 6 * 11 * 10 * 10 + 4 * 10 * 10 * 10) + 5**3  # lattice + goal links


def test_any_angle_cost_to_go_is_the_euclidean_distance_in_open_water():
    """Oracle: with no obstacle the cost-to-go of every node is its straight-line distance to the
    goal.  The any-angle field (links of up to 16 cells) is within 0.8 % of it everywhere and
    0.1 % on average; the 26-neighbour field is metricated, up to 11 % and 7 % on average long."""
    world = World(Bounds(0, 2000, 0, 2000, -400, 0), margins=Margins(min_altitude=0.0, min_depth=-np.inf))
    goal = np.array([1000.0, 1000.0, -200.0])
    prob = PlanningProblem(world, [10.0, 10.0, -390.0], goal, 1.5)
    lo, hi = search_box(prob)
    err = {}
    for links in (16, 0):
        spec = grid_spec(objective="length", cell=40.0, cell_z=40.0, any_angle=links)
        ref = GridReference(world, goal, cost_model_for(prob, spec), lo, hi, spec.grid)
        d = np.linalg.norm(np.stack(np.meshgrid(*ref.axes, indexing="ij"), axis=-1) - goal, axis=-1)
        err[links] = ref.cost_to_go[d > 0] / d[d > 0] - 1.0
        assert err[links].min() > -1e-12  # never below the straight line: every link is a real segment
    assert err[16].max() < 0.008 and err[16].mean() < 0.0015
    assert err[0].max() > 0.10 and err[0].mean() > 0.06


def sphere_geodesic(s, g, c, r):
    """Shortest path from s to g around a ball (centre c, radius r): tangent, arc, tangent."""
    ds, dg = np.linalg.norm(s - c), np.linalg.norm(g - c)
    theta = np.arccos(np.dot(s - c, g - c) / (ds * dg))
    a_s, a_g = np.arccos(r / ds), np.arccos(r / dg)
    assert theta > a_s + a_g  # the straight line is blocked
    return np.sqrt(ds**2 - r**2) + np.sqrt(dg**2 - r**2) + r * (theta - a_s - a_g)


@pytest.mark.parametrize("objective", ["length", "cost"])
def test_path_around_a_sphere_is_within_one_percent_of_the_geodesic(objective):
    """The lattice-bound reference (no convergence) stays within 1 % of the geodesic."""
    c = np.array([500.0, 500.0, -150.0])
    world = flat_world(depth=300.0, size=1000.0, obstacles=(Sphere(c, 100.0),), obstacle=10.0, min_depth=20.0)
    s, g = np.array([100.0, 440.0, -150.0]), np.array([900.0, 500.0, -150.0])
    r = plan(PlanningProblem(world, s, g, 1.5), grid_spec(objective=objective, cell=25.0, converge=False))
    assert r.status is Status.EXACT and world.path_free(r.path)
    exact = sphere_geodesic(s, g, c, 110.0)
    assert exact <= r.cost_terms["length_m"] <= 1.01 * exact
    assert "lattice-bound" in r.message


def _sphere_scene():
    c = np.array([500.0, 500.0, -150.0])
    world = flat_world(depth=300.0, size=1000.0, obstacles=(Sphere(c, 100.0),), obstacle=10.0, min_depth=20.0)
    s, g = np.array([100.0, 440.0, -150.0]), np.array([900.0, 500.0, -150.0])
    return world, s, g, sphere_geodesic(s, g, c, 110.0)


def _ridge_scene():
    """A horizontal cylinder of radius 120 m lying on a flat seabed at -300 m along y (x0 = 500 m),
    on a 2 m grid; start and goal on the seabed floor on both sides, 10 m altitude required.
    The constraint surface is the cylinder raised by 10 m, so the geodesic in the x–z plane is
    tangent, arc over a circle of radius 120 m centred at (500, -290), tangent."""
    x = np.arange(0.0, 1000.0 + 1e-9, 2.0)
    r, zc = 120.0, -300.0
    X, _ = np.meshgrid(x, x)
    z = zc + np.sqrt(np.maximum(r**2 - (X - 500.0) ** 2, 0.0))
    world = World(Bounds(0, 1000, 0, 1000, -400, 0), Terrain(x, x, z),
                  margins=Margins(min_altitude=10.0, min_depth=20.0))
    s, g = np.array([150.0, 500.0, -290.0]), np.array([850.0, 500.0, -290.0])
    c2 = np.array([500.0, -290.0])
    d = np.linalg.norm(np.array([150.0, -290.0]) - c2)  # start at the circle centre's height
    tangent = np.sqrt(d**2 - r**2)
    arc = r * (np.pi - 2 * np.arccos(r / d))
    return world, s, g, 2 * tangent + arc


@pytest.mark.parametrize("scene", [_sphere_scene, _ridge_scene])
def test_converged_reference_is_within_five_hundredths_of_a_percent_of_the_geodesic(scene):
    world, s, g, exact = scene()
    r = plan(PlanningProblem(world, s, g, 1.5), grid_spec(objective="length", cell=25.0))
    assert r.status is Status.EXACT and world.path_free(r.path)
    assert "refined to convergence" in r.message
    # the bilinear seabed sags below the cylinder by up to dx² / 8r = 0.004 m between grid nodes
    assert exact * (1 - 2e-5) <= r.cost_terms["length_m"] <= 1.0005 * exact


@pytest.mark.parametrize("scene", [_sphere_scene, _ridge_scene])
def test_a_finer_cell_never_gives_a_worse_converged_reference(scene):
    """Halving the cell never raises the converged reference's cost (the finer reference's
    candidates include the coarser one's lattice), on either scene, and says so."""
    world, s, g, _ = scene()
    got = [plan(PlanningProblem(world, s, g, 1.5), grid_spec(objective="length", cell=c)) for c in (50.0, 25.0)]
    assert got[1].cost <= got[0].cost
    assert "best of the lattices at 25, 50 m" in got[1].message


def test_plan_once_query_many_on_real_terrain(salish):
    """One cost-to-go field answers many starts; every answer passes the exact segment test,
    and the lattice path's edge costs add up to the field's value (the search's invariant)."""
    _, world, mission = salish
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, name="grid")
    model = cost_model_for(prob, spec)
    lo, hi = search_box(prob)
    ref = GridReference(world, prob.goal, model, lo, hi, spec.grid)
    rng = np.random.default_rng(3)
    pts = rng.uniform(lo, hi, size=(400, 3))
    starts = pts[world.is_free(pts, moving=False)][:8]
    assert len(starts) == 8
    for s in starts:
        raw = ref.query(s)
        if raw.shape[0] == 0:
            continue
        along = edge_cost(world, raw[:-1], raw[1:], model, "cost").sum()
        ids, w = ref._connect(s, towards=False)
        assert along == pytest.approx((w + ref._dist[ids]).min(), rel=1e-3)  # node-mean vs midpoint current
        r = plan_grid(replace(prob, start=s), spec, reference=ref)
        assert r.status is Status.EXACT and world.path_free(r.path) and r.cost_terms["collisions"] == 0
        assert r.cost <= path_cost(prob, spec, raw)["total"] + 1e-6  # refining never makes it worse


def test_goal_enclosed_by_terrain_is_infeasible_with_a_message():
    x = np.arange(0.0, 1001.0, 10.0)
    gx, gy = np.meshgrid(x, x)
    rr = np.hypot(gx - 500.0, gy - 500.0)
    z = np.where((rr > 150.0) & (rr < 220.0), -1.0, -100.0)
    world = World(Bounds(0, 1000, 0, 1000, -100, 0), Terrain(x, x, z), margins=Margins(min_altitude=5.0, min_depth=2.0))
    r = plan(PlanningProblem(world, [50.0, 50.0, -50.0], [500.0, 500.0, -50.0], 1.5), grid_spec(cell=20.0))
    assert r.status is Status.INFEASIBLE and "enclosed" in r.message and r.path.shape == (0, 3)
    assert not np.isfinite(r.cost)


def test_invalid_end_points_and_oversized_lattice_are_statuses():
    world = flat_world(depth=100.0)
    r = plan(PlanningProblem(world, [50.0, 50.0, -99.0], [900.0, 900.0, -50.0], 1.5), grid_spec())
    assert r.status is Status.INVALID_START
    r = plan(PlanningProblem(world, [50.0, 50.0, -50.0], [900.0, 900.0, -50.0], 1.5),
             grid_spec(cell=1.0, target_nodes=10, max_nodes=1000))
    assert r.status is Status.INFEASIBLE and "max_nodes" in r.message


def test_marcus_wake_reference_and_the_gap_of_a_swarm_plan(marcus):
    """The reference rides the vortices: cheaper than the straight line on the same cost, and
    the gap of a swarm plan is its cost minus the reference's on that same cost."""
    _, world, mission = marcus
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, grid=GridParams(cell=1000.0))
    ref = plan(prob, replace(spec, name="grid"))
    assert ref.status is Status.EXACT and world.path_free(ref.path)
    straight = plan_grid(prob, replace(spec, name="grid", grid=GridParams(cell=1000.0, relax_iterations=0)))
    line = path_cost(prob, spec, np.stack([prob.start, prob.goal]))["total"]
    assert ref.cost < line - 1000.0  # ≥ 0.4 % cheaper: the detour pays
    assert straight.cost >= ref.cost
    swarm = plan(prob, replace(spec, name="pso", population=20, iterations=20), rng=0)
    g = with_reference(swarm, prob, spec, ref)
    assert g.reference_cost == ref.cost and g.gap == pytest.approx(swarm.cost - ref.cost)
    assert g.gap_pct == pytest.approx(100 * (swarm.cost - ref.cost) / ref.cost)


def test_streamline_plans_are_recosted_on_the_planners_cost_function():
    """A flow plan reports its length only; on the cost function it gains the energy term, and
    a swarm plan is left as it is (bench and reference gaps compare like with like)."""
    from auvplan.io.scenario import loader as sc
    from auvplan.planners.grid.planner import on_cost_function

    world, mission = sc.build(sc.load("flow-spheres"))
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, name="flow")
    r = plan(prob, spec)
    assert r.status is Status.EXACT and r.cost_terms["energy"] == 0.0
    c = on_cost_function(r, prob, spec)
    assert c.cost == pytest.approx(path_cost(prob, spec, r.path)["total"], rel=1e-12)
    assert c.cost_terms["energy"] > 0 and c.cost > r.cost
    swarm = replace(r, planner="iabc")
    assert on_cost_function(swarm, prob, spec) is swarm


def test_reference_is_the_best_known_plan_on_salish_shelf(salish):
    """The lattice alone is 0.8 % dearer than the seeded swarm plans on salish-shelf; the reference
    (best of the refined lattice and the seeded swarms at twice the budget) is never beaten by more
    than 0.05 % by the planners users run, and says what it is."""
    from auvplan.planners import reference

    _, world, mission = salish
    prob = planning_problem(world, mission)
    spec = mission.planner
    ref = reference(prob, spec)
    runs = [plan(prob, replace(spec, name=name), seed).cost for name, seed in (("iabc", 0), ("iabc", 1), ("pso", 0))]
    assert ref.status is Status.EXACT and "best of 4" in ref.message
    assert ref.cost <= min(runs) * (1 + 5e-4)
    assert ref.cost < plan_grid(prob, replace(spec, name="grid")).cost


def test_halving_the_cell_on_marcus_wake_never_raises_the_reference(marcus):
    """On marcus-wake the 1 km lattice alone converges to a plan slightly dearer than the 2 km one
    (a different local optimum of the band); with the ladder of coarser lattices the 1 km
    reference is never dearer than the 2 km one, nor than its own lattice alone."""
    _, world, mission = marcus
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, name="grid")
    fine, coarse = (plan_grid(prob, replace(spec, grid=GridParams(cell=c))) for c in (1000.0, 2000.0))
    alone = plan_grid(prob, replace(spec, grid=GridParams(cell=1000.0, ladder=False)))
    assert alone.cost > coarse.cost  # the case the ladder is for
    assert fine.cost <= coarse.cost and fine.cost <= alone.cost
    assert fine.status is Status.EXACT and world.path_free(fine.path) and "1000, 2000, 4000 m" in fine.message


def test_reference_is_never_beaten_by_more_than_five_hundredths_on_a_hard_case():
    """new-england-seamounts (real ETOPO1, abyssal plain among seamounts) at a small budget: every
    planner's seeded run costs at least the reference minus 0.05 % (the gap study's property,
    benchmarks/gap.py, on one case), and the reference says which plan won."""
    from auvplan.io.scenario import loader as sc
    from auvplan.planners import reference

    world, mission = sc.build(sc.load("new-england-seamounts"))
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, budget=2000, population=20, grid=GridParams(cell=2000.0))
    ref = reference(prob, spec)
    runs = [plan(prob, replace(spec, name=n), seed) for n in ("iabc", "abc", "ga", "pso", "de") for seed in (0, 1)]
    best = min(r.cost for r in runs if r.status is Status.EXACT)
    assert ref.status is Status.EXACT and world.path_free(ref.path) and "best of 4" in ref.message
    assert ref.cost <= best * (1 + 5e-4)


def test_the_ladder_runs_when_the_finest_lattice_finds_no_path():
    """A 10 m and a 20 m lattice over 1 km x 1 km x 200 m are over ``max_nodes`` (refused, no
    path); the ladder then tries the coarser cells and the 40 m lattice plans (the straight line
    of the empty world), naming every cell tried.  Without the ladder the refusal stands."""
    world = flat_world(depth=200.0, size=1000.0)
    prob = PlanningProblem(world, [37.0, 81.0, -150.0], [913.0, 777.0, -40.0], 1.5)
    params = GridParams(cell=10.0, target_nodes=1000, max_nodes=20_000)
    r = plan_grid(prob, PlannerSpec(name="grid", grid=params))
    assert r.status is Status.EXACT and "10, 20, 40 m: 40 m" in r.message
    np.testing.assert_allclose(r.path, np.stack([prob.start, prob.goal]))
    alone = plan_grid(prob, PlannerSpec(name="grid", grid=replace(params, ladder=False)))
    assert alone.status is Status.INFEASIBLE and "max_nodes" in alone.message


def test_the_ladder_reports_the_finest_failure_when_no_lattice_finds_a_path():
    """A ridge to the surface splits the world: every lattice of the ladder fails, the status is
    INFEASIBLE with the finest lattice's message and the coarser cells tried named."""
    x = np.linspace(0.0, 1000.0, 21)
    z = np.full((21, 21), -200.0)
    z[10, :] = 0.0  # x = 500 m: the seabed at the surface, no altitude left above it
    world = World(Bounds(0.0, 1000.0, 0.0, 1000.0, -200.0, 0.0), Terrain(x, x, z.T, name="ridge"),
                  margins=Margins(min_altitude=5.0))
    prob = PlanningProblem(world, [100.0, 500.0, -100.0], [900.0, 500.0, -100.0], 1.5)
    r = plan_grid(prob, PlannerSpec(name="grid", grid=GridParams(cell=20.0)))
    assert r.status is Status.INFEASIBLE and "cannot be reached" in r.message
    assert "no path on the coarser lattices either (40 m)" in r.message


def test_a_finer_any_angle_lattice_gives_a_shorter_lattice_path_round_a_sphere():
    """The lattice path alone (no refinement) round the sphere scene's ball, against its geodesic:
    with any-angle links halving the cell strictly shortens it (3.2 %, 1.9 %, 0.9 % long at 100,
    50, 25 m), where the 26-direction path is metricated and gets no better (2.2 %, 4.6 %, 6.4 %)."""
    from auvplan.path import polyline_length

    world, s, g, exact = _sphere_scene()
    prob = PlanningProblem(world, s, g, 1.5)
    lo, hi = search_box(prob)
    excess = {}
    for links in (16, 0):
        excess[links] = []
        for cell in (100.0, 50.0, 25.0):
            spec = grid_spec(objective="length", cell=cell, any_angle=links)
            ref = GridReference(world, g, cost_model_for(prob, spec), lo, hi, spec.grid, s)
            raw = ref.query(s)
            assert world.path_free(raw)  # every any-angle link is a free segment (the exact test)
            excess[links].append(polyline_length(raw) / exact - 1.0)
    assert excess[16][0] > excess[16][1] > excess[16][2] > 0.0 and excess[16][2] < 0.01
    assert min(excess[0]) > 0.02 and excess[0][2] > excess[0][0]


def test_band_normals_are_unit_and_orthogonal_also_on_a_zero_chord() -> None:
    """The elastic band's two move directions: unit, perpendicular to the chord and to each other; a
    point whose neighbours coincide (the path comes back on itself) gets finite normals, not NaN."""
    from auvplan.planners.grid.band import _normals

    p = np.array([[0.0, 0.0, -10.0], [5.0, 1.0, -12.0], [10.0, 3.0, -9.0], [5.0, 1.0, -12.0],
                  [5.0, 1.0, 30.0], [5.0, 1.0, -12.0]])
    i = np.arange(1, p.shape[0] - 1)
    n1, n2 = _normals(p[i + 1] - p[i - 1])
    assert np.all(np.isfinite(n1)) and np.all(np.isfinite(n2))
    np.testing.assert_allclose(np.linalg.norm(n1, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(n2, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.einsum("ij,ij->i", n1, n2), 0.0, atol=1e-12)
    t = p[i + 1] - p[i - 1]
    np.testing.assert_allclose(np.einsum("ij,ij->i", n1, t), 0.0, atol=1e-9)
    np.testing.assert_allclose(np.einsum("ij,ij->i", n2, t), 0.0, atol=1e-9)
