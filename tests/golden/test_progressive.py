"""Issue #14: the progressive pipeline (the optimiser alone, coarse to fine) and its bend-weighted refit."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.io.scenario import loader as scenario
from auvplan.optim import OptimizeResult
from auvplan.path import sample_population
from auvplan.planners import PlannerSpec, PlanningProblem, plan
from auvplan.planners.swarm import planner as swarm_planner
from auvplan.planners.swarm import problem as swarm_problem
from auvplan.planners.swarm.progressive import COARSE_ELITE, Elite, coarse_count, coarse_stage, refit
from auvplan.planners.swarm.seeding import fit_control_points
from auvplan.sim import planning_problem
from helpers import flat_world

MARCUS_FIELD_BEST = 537_040.0
"""The best cost known on marcus-wake-field (``--reference``, docs/convergence.md)."""
CHAGOS_REFERENCE = 489_326.0  # reference() on the conservative seabed (issue 30; was 491 967 on the cubic one)
"""The best cost any method found on chagos-banks (docs/bench_hard.md: the refined lattice plan)."""

L_PATH = np.array([[0.0, 0.0, -100.0], [10_000.0, 0.0, -100.0], [10_000.0, 10_000.0, -100.0]])


def _curve(ctrl: np.ndarray, ends: np.ndarray = L_PATH) -> np.ndarray:
    return sample_population(np.vstack([ends[0], ctrl, ends[-1]]), 2000)


# ---------------------------------------------------------------------- bend-weighted fit
def test_bend_weighted_fit_puts_the_spline_through_the_corner():
    """An L of two 10 km legs: the plain fit (arc length) cuts the corner by 656 m and keeps 2 of
    6 control points within 2.5 km of it; with bend = 1 half of the spline's parameter goes to the
    corner, 4 control points sit within 2.5 km and the spline passes within 2 m of it."""
    plain, bent = fit_control_points(L_PATH, 6, 200), fit_control_points(L_PATH, 6, 200, bend=1.0)
    cut = [np.linalg.norm(_curve(c) - L_PATH[1], axis=1).min() for c in (plain, bent)]
    near = [int((np.linalg.norm(c - L_PATH[1], axis=1) < 2500.0).sum()) for c in (plain, bent)]
    assert cut[0] == pytest.approx(655.7, abs=1.0) and cut[1] < 2.0
    assert near == [2, 4]


def test_bend_weighted_fit_keeps_the_mirror_symmetry_and_straight_lines():
    """Invariants: the L is its own mirror image under (x, y) -> (10 km - y, 10 km - x) with the
    ends swapped, so the fitted control points are too (reversed); a straight path has no bend, so
    the bend-weighted fit is the plain one and its control points lie on the line."""
    ctrl = fit_control_points(L_PATH, 6, 200, bend=1.0)
    mirrored = np.column_stack([10_000.0 - ctrl[::-1, 1], 10_000.0 - ctrl[::-1, 0], ctrl[::-1, 2]])
    assert np.allclose(mirrored, ctrl, atol=1e-6)
    line = np.linspace([0.0, 0.0, -50.0], [900.0, 300.0, -80.0], 7)
    assert np.allclose(fit_control_points(line, 4, 200, bend=1.0), fit_control_points(line, 4, 200), atol=1e-6)


# ---------------------------------------------------------------------- the coarse stage's pieces
def test_elite_keeps_the_best_distinct_vectors_seen():
    """Oracle by hand: every row seen, duplicates and non-finite values dropped, sorted by value."""
    e = Elite(3, 2)
    e.add([[0, 0], [1, 1], [2, 2]], [5.0, np.inf, 3.0])
    e.add([[2, 2], [3, 3], [4, 4], [5, 5]], [3.0, 4.0, 1.0, np.nan])
    assert e.X.tolist() == [[4, 4], [2, 2], [3, 3]] and e.f.tolist() == [1.0, 3.0, 4.0]
    seen = []
    wrapped = e.wrap(lambda X: seen.append(X) or X.sum(axis=1))
    assert wrapped(np.array([[-1.0, 0.0]])).tolist() == [-1.0] and len(seen) == 1
    assert e.f.tolist() == [-1.0, 1.0, 3.0]
    with pytest.raises(ValueError):
        Elite(0, 2)


def test_coarse_count_and_refit_of_a_straight_path():
    """⌈K/2⌉ but at least 2; a path whose control points lie on the start-goal line is refitted on the line."""
    assert [coarse_count(k) for k in (2, 3, 4, 5, 6, 7)] == [2, 2, 2, 3, 3, 4]
    world = flat_world()
    prob = PlanningProblem(world, np.array([100.0, 100.0, -50.0]), np.array([900.0, 800.0, -60.0]), speed=1.5)
    t = np.array([0.2, 0.5, 0.8])[:, None]
    X = (prob.start + t * (prob.goal - prob.start)).reshape(1, -1)
    Y = refit(prob, X, 6, 200, 1.0).reshape(6, 3)
    d = prob.goal - prob.start
    off = (Y - prob.start) - np.outer((Y - prob.start) @ d / (d @ d), d)
    assert np.abs(off).max() < 1e-6


def test_coarse_stage_seeds_are_bend_weighted_refits_of_its_best_paths():
    """The stage's wiring against an independent computation: a stub optimiser evaluates six
    coarse vectors (one twice) on the stage's problem; the seeds are the best ``population``
    distinct ones, best first, each path refitted by hand with ``fit_control_points(..., bend)``."""
    world = flat_world(depth=200.0)
    prob = PlanningProblem(world, np.array([100.0, 100.0, -50.0]), np.array([900.0, 800.0, -60.0]), speed=1.5)
    spec = PlannerSpec(name="iabc", pipeline="progressive", control_points=5, population=4, bend=0.7, samples=60)
    rng = np.random.default_rng(0)
    V = rng.uniform(np.tile([150.0, 150.0, -150.0], 3), np.tile([850.0, 850.0, -40.0], 3), size=(6, 9))
    V = np.vstack([V, V[:1]])
    seen = {}

    def stub(s, task, g):
        seen["dim"], seen["budget"] = task.dim, task.budget
        f = task.evaluate(V)
        return OptimizeResult(V[int(np.argmin(f))], float(f.min()), task.evaluations, 1, f[:1], 0.0, "stub")

    seeds, result = coarse_stage(prob, spec, 40, stub, rng)
    assert seen == {"dim": 9, "budget": 40} and result.evaluations == 7
    f = swarm_problem.spline_problem(prob, replace(spec, control_points=3), None).evaluate(V[:6])
    best = V[:6][np.argsort(f)[:4]]
    by_hand = [fit_control_points(sample_population(np.vstack([prob.start, v.reshape(3, 3), prob.goal]), 60), 5, 60,
                                  bend=0.7).ravel() for v in best]
    assert seeds.shape == (4, 15) and np.allclose(seeds, by_hand, atol=1e-9)


@pytest.mark.parametrize("k", [2, 3])
def test_progressive_at_the_fewest_control_points_spends_the_budget(k):
    """K = 2 has no coarser stage (one run), K = 3 a coarse stage at 2; both exactly N evaluations."""
    world = flat_world(depth=200.0)
    prob = PlanningProblem(world, np.array([100.0, 100.0, -50.0]), np.array([900.0, 800.0, -60.0]), speed=1.5)
    for budget in (2, 3, 57):
        r = plan(prob, PlannerSpec(pipeline="progressive", control_points=k, population=8, budget=budget), rng=0)
        assert r.evaluations == budget and r.status is Status.EXACT


def test_progressive_spec_is_validated():
    with pytest.raises(ValueError, match="coarse_fraction"):
        PlannerSpec(pipeline="progressive", coarse_fraction=1.0)
    with pytest.raises(ValueError, match=r"control_points = 1: must lie in \[2, 50\]"):
        PlannerSpec(control_points=1)
    with pytest.raises(ValueError, match="bend"):
        PlannerSpec(pipeline="progressive", bend=-0.1)


# ---------------------------------------------------------------------- on the hard case
@pytest.fixture(scope="module")
def chagos():
    world, mission = scenario.build(scenario.load("chagos-banks"))
    return world, planning_problem(world, mission), replace(mission.planner, pipeline="progressive")


def test_progressive_iabc_alone_finds_the_route_on_chagos(chagos):
    """IABC alone, 10 000 evaluations: in the document pipeline seeds 1–3 end 0.9–2.4 % above the
    best cost known; coarse to fine each ends EXACT within 1 % (measured +0.33, +0.47, +0.51 % against
    ``reference()``, 489 326, with the coarse stage aiming at an elite share, issue 59; seed 3 ended at
    +3.05 % with the stage aiming at the best source). The coarse stage spends exactly 20 % of the
    budget (a trace entry at 2 000 evaluations)."""
    world, prob, spec = chagos
    gaps = []
    for seed in (1, 2, 3):
        r = plan(prob, spec, rng=seed)
        assert r.status is Status.EXACT and world.path_free(r.path), r.message
        gaps.append(r.cost / CHAGOS_REFERENCE - 1)
        assert r.cost <= 1.01 * CHAGOS_REFERENCE, (seed, gaps[-1])
        assert r.evaluations == 10_000 and 2000 in r.trace[:, 0]
        assert np.all(np.diff(r.trace[:, 1]) <= 0) and r.trace[-1, 1] == pytest.approx(r.cost)
    assert sorted(gaps)[1] <= 0.006, gaps


def test_coarse_stage_colony_aims_at_an_elite_share_and_the_full_stage_at_the_best(monkeypatch):
    """The two stages' IABC settings, read from the specs the pipeline hands its optimiser: the coarse
    stage (3 control points) at ``elite = COARSE_ELITE`` (or the user's share when larger), the full
    stage (6) at the user's own ``elite``; the default (seeded) pipeline is not touched."""
    world = flat_world(depth=200.0)
    prob = PlanningProblem(world, np.array([100.0, 100.0, -50.0]), np.array([900.0, 800.0, -60.0]), speed=1.5)
    seen = []
    real = swarm_planner.run_optimizer

    def spy(s, task, g, progress=None, on_stall=None):
        seen.append((s.control_points, s.iabc.elite))
        return real(s, task, g, progress, on_stall)

    monkeypatch.setattr(swarm_planner, "run_optimizer", spy)
    spec = PlannerSpec(pipeline="progressive", control_points=6, population=8, budget=200, samples=40)
    for elite in (0.0, 0.5):
        plan(prob, replace(spec, iabc=replace(spec.iabc, elite=elite)), rng=0)
    plan(prob, replace(spec, pipeline="seeded", seed_nodes=1000), rng=0)
    assert seen == [(3, COARSE_ELITE), (6, 0.0), (3, 0.5), (6, 0.5), (6, 0.0)]


def test_progressive_iabc_alone_threads_the_gap_on_marcus_wake_field():
    """The corridor choice on the seamount field (issue 59): seeds 1 and 3 ended in the open detour
    north of the chain, +13.7 %, when the coarse stage's colony aimed its pull and its mutants at its
    best source (it collapsed onto the first feasible corridor within ~1 000 evaluations); aiming at
    the best 30 % they thread the gap (measured +0.13 and +0.12 %).  Independent check of the corridor:
    the path crosses the diagonal x + y = 210 km between the two seamounts (x - y near +19 km), not at
    x - y ~ -107 km."""
    world, mission = scenario.build(scenario.load("marcus-wake-field"))
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, pipeline="progressive")
    for seed in (1, 3):
        r = plan(prob, spec, rng=seed)
        assert r.status is Status.EXACT and world.path_free(r.path), r.message
        assert r.cost <= 1.01 * MARCUS_FIELD_BEST, (seed, r.cost / MARCUS_FIELD_BEST - 1)
        cross = r.path[np.argmin(np.abs(r.path[:, 0] + r.path[:, 1] - 210e3))]
        assert 0.0 < cross[0] - cross[1] < 40e3, cross


def test_progressive_is_reproducible(chagos):
    _, prob, spec = chagos
    small = replace(spec, budget=1500)
    a, b = plan(prob, small, rng=7), plan(prob, small, rng=7)
    assert a.cost == b.cost and np.array_equal(a.path, b.path)
