"""Issue #35.1: the seeded pipeline's corridor choice, its last polyline polish, and the work it does
outside the evaluation budget (the lattice seeding and the polish), counted exactly."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from auvplan.planners import PlannerSpec, PlanningProblem, plan
from auvplan.planners.swarm import problem as swarm_problem
from auvplan.planners.swarm.seeding import coarse_reference
from auvplan.world import Bounds, Margins, Sphere, Terrain, World
from helpers import flat_world

GAP_A = (480.0, 520.0)
"""The gap on the straight line (the greedy corridor): behind it a second wall forces a detour."""
GAP_B = (740.0, 800.0)
"""The gap off the line (the better corridor)."""


def _two_corridors() -> PlanningProblem:
    """A 1 km square, seabed 100 m deep, walls to 2 m below the surface (impassable with 5 m altitude):
    wall 1 at x 400-450 m open only at gap A (on the straight start-goal line y = 500 m) and gap B;
    wall 2 at x 550-600 m for y 100-700 m, and a divider between the walls at y 600-700 m, so that
    through A the vehicle must go round wall 2's south end (about 1 285 m in all) while through B it
    passes north of wall 2 (about 960 m)."""
    x = np.arange(0.0, 1001.0, 10.0)
    X, Y = np.meshgrid(x, x)
    z = np.full(X.shape, -100.0)
    wall1 = (X >= 400) & (X <= 450) & ~((Y >= GAP_A[0]) & (Y <= GAP_A[1])) & ~((Y >= GAP_B[0]) & (Y <= GAP_B[1]))
    wall2 = (X >= 550) & (X <= 600) & (Y >= 100) & (Y <= 700)
    divider = (X >= 450) & (X <= 550) & (Y >= 600) & (Y <= 700)
    z[wall1 | wall2 | divider] = -2.0
    world = World(Bounds(0.0, 1000.0, 0.0, 1000.0, -100.0, 0.0), Terrain(x, x, z, name="two corridors"),
                  margins=Margins(min_altitude=5.0))
    return PlanningProblem(world, [100.0, 500.0, -60.0], [900.0, 500.0, -60.0], 1.5)


def _gap_crossed(path: np.ndarray) -> float:
    """The path's y where it crosses x = 425 m (wall 1's middle)."""
    i = int(np.argmax(path[:, 0] >= 425.0))
    a, b = path[i - 1], path[i]
    return float(a[1] + (425.0 - a[0]) / (b[0] - a[0]) * (b[1] - a[1]))


@pytest.fixture(scope="module")
def corridors():
    return _two_corridors()


def test_the_pipeline_takes_the_better_corridor_not_the_greedy_one(corridors):
    """Over five seeds the default pipeline crosses wall 1 through gap B (within 40 m of its edges in the
    grid: the terrain interpolates between the 10 m nodes; gap A is 220 m away), and its length is below the
    shortest path through gap A (1 285 m, the straight legs round wall 2's south end)."""
    spec = PlannerSpec(population=20, budget=1500)
    for seed in range(5):
        r = plan(corridors, spec, rng=seed)
        assert r.status.ok, r.message
        assert GAP_B[0] - 40.0 <= _gap_crossed(r.path) <= GAP_B[1] + 40.0, seed  # the interpolated walls' edges
        assert r.cost_terms["length_m"] < 1200.0
        assert corridors.world.path_free(r.path)


def test_polish_is_never_worse_and_outside_the_budget(corridors):
    """Same seed with and without the polyline polish: the same evaluations (exactly the budget: the
    polish is not an objective evaluation), a plan no worse and free; the polished plan is a polyline."""
    seen: list[int] = []
    real = swarm_problem.evaluate_paths

    def counting(world, points, model, exact=False):
        seen.append(points.shape[0])
        return real(world, points, model, exact)

    for seed in range(3):
        base = plan(corridors, PlannerSpec(population=20, budget=900, polish=0), rng=seed)
        swarm_problem.evaluate_paths = counting
        try:
            seen.clear()
            new = plan(corridors, PlannerSpec(population=20, budget=900, polish=2), rng=seed)
        finally:
            swarm_problem.evaluate_paths = real
        assert sum(seen) == 900 == new.evaluations == base.evaluations
        assert new.cost <= base.cost and new.status.ok and corridors.world.path_free(new.path)
        assert "polish_cpu_s" in new.work and "polish_cpu_s" not in base.work
        if new.cost < base.cost:
            assert new.control_points is None and "polished as a polyline" in new.message


def test_seeding_work_is_reported_exactly():
    """The lattice nodes of the seeding equal the seeding lattice's own shape product, and the CPU of
    the seeding and of the polish are reported, also in the plan's JSON record."""
    from auvplan.io.results.records import plan_record

    prob = PlanningProblem(flat_world(obstacles=(Sphere((500.0, 500.0, -50.0), 100.0),)),
                           [50.0, 50.0, -50.0], [950.0, 950.0, -50.0], 1.5)
    spec = PlannerSpec(population=20, budget=600, seed_nodes=5000)
    r = plan(prob, spec, rng=1)
    ref, _ = coarse_reference(prob, spec)
    assert ref is not None and r.work["seeding_lattice_nodes"] == int(np.prod(ref.shape)) <= 5000
    assert r.work["seeding_cpu_s"] > 0 and r.work["polish_cpu_s"] >= 0
    rec = plan_record(r, "flat", 1)
    assert rec["work"] == r.work and rec["evaluations"] == 600
    # the algorithm alone does no seeding and no polish: nothing reported
    alone = plan(prob, replace(spec, pipeline="document"), rng=1)
    assert alone.work == {}


def test_a_loop_is_not_polished_to_a_point():
    """Start = goal (a survey's loop): the plan keeps its spline, not the zero-length path."""
    prob = PlanningProblem(flat_world(obstacles=(Sphere((500.0, 500.0, -50.0), 100.0),)),
                           [50.0, 50.0, -50.0], [50.0, 50.0, -50.0], 1.5)
    r = plan(prob, PlannerSpec(population=20, budget=400), rng=0)
    assert r.path.shape[0] > 2 and r.control_points is not None


def test_polish_setting_is_validated():
    with pytest.raises(ValueError, match="polish"):
        PlannerSpec(polish=-1)
