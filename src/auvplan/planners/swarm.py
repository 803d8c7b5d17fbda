"""Global planning with swarm optimisers over B-spline control points (document 002).

The decision vector is the ``K`` free interior control points of a clamped
cubic B-spline from the start to the goal (``D = 3K``), bounded by the world's
box (and the surface margin).  Every candidate is sampled at ``S`` points in
one matrix product and costed with :func:`auvplan.cost.evaluate_paths`; the
optimiser is IABC (document 002's improvement), ABC, GA or PSO, all with the
same evaluation budget when a budget is given.

Status: ``EXACT`` when the best path passes every exact constraint test,
``INFEASIBLE`` when even the best path violates one (the path is still
returned, with the number of violating segments in the message),
``INVALID_START`` / ``INVALID_GOAL`` when an end point is not free.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from .._types import RngLike, Status, as_rng
from ..cost import CostModel, evaluate_paths
from ..optim import ABC, GA, IABC, PSO, Termination, minimize
from ..path import sample_population
from .base import PlannerSpec, PlanningProblem, PlanResult

__all__ = ["plan_swarm", "cost_model_for", "make_objective", "make_optimizer", "check_endpoints", "plan_terms"]


def cost_model_for(problem: PlanningProblem, spec: PlannerSpec) -> CostModel:
    """The cost model of a planning problem under planner settings."""
    return CostModel(
        speed=problem.speed,
        hotel_power=problem.hotel_power,
        drag_k=problem.drag_k,
        energy=spec.energy,
        w_length=spec.w_length,
        w_terrain=spec.w_terrain,
        w_energy=spec.w_energy,
        terrain_penalty=spec.terrain_penalty,
        energy_scale=spec.energy_scale,
    )


def search_box(problem: PlanningProblem) -> tuple[np.ndarray, np.ndarray]:
    """Per-coordinate bounds ``(3,)`` of the interior control points."""
    b = problem.world.bounds
    m = problem.world.margins
    ztop = min(b.zmax, -m.min_depth)
    zlow = max(b.zmin, -m.max_depth) if np.isfinite(m.max_depth) else b.zmin
    if problem.world.terrain is not None:
        zlow = max(zlow, float(problem.world.terrain.z.min()))
    return np.array([b.xmin, b.ymin, zlow]), np.array([b.xmax, b.ymax, ztop])


def make_objective(problem: PlanningProblem, spec: PlannerSpec) -> Callable[[np.ndarray], np.ndarray]:
    """Vectorised objective ``(P, 3K) -> (P,)`` of the planning problem."""
    model = cost_model_for(problem, spec)
    start, goal = problem.start, problem.goal
    k = spec.control_points

    def objective(X: np.ndarray) -> np.ndarray:
        ctrl = np.empty((X.shape[0], k + 2, 3))
        ctrl[:, 0] = start
        ctrl[:, -1] = goal
        ctrl[:, 1:-1] = X.reshape(-1, k, 3)
        return evaluate_paths(problem.world, sample_population(ctrl, spec.samples), model).total

    return objective


def make_optimizer(spec: PlannerSpec, lower: np.ndarray, upper: np.ndarray, rng: np.random.Generator):
    """The optimiser named by ``spec.name`` over ``[lower, upper]``."""
    if spec.name == "iabc":
        params = replace(spec.iabc, max_iterations=spec.iterations)
        return IABC(lower, upper, spec.population, params, rng)
    if spec.name == "abc":
        return ABC(lower, upper, spec.population, spec.abc, rng)
    if spec.name == "ga":
        return GA(lower, upper, spec.population, spec.ga, rng)
    if spec.name == "pso":
        return PSO(lower, upper, spec.population, spec.pso, rng)
    raise ValueError(f"unknown swarm planner {spec.name!r}")


def plan_terms(row: dict, spec: PlannerSpec) -> dict:
    """:attr:`PlanResult.cost_terms` from one :meth:`CostTerms.row`: the weighted terms and the
    physical figures."""
    return {
        "length": row["length"] * spec.w_length,
        "terrain": row["terrain"] * spec.w_terrain,
        "energy": row["energy"] * spec.w_energy,
        "length_m": row["length"],
        "energy_j": row["energy_j"],
        "duration_s": row["duration_s"],
        "min_clearance_m": row["min_clearance_m"],
        "violations": row["violations"],
        "collisions": row["violations"],  # deprecated alias of "violations" (CHANGELOG 0.2.0)
    }


def check_endpoints(problem: PlanningProblem) -> tuple[Status, str] | None:
    """``(status, message)`` when the start or goal is not a free point, else None."""
    w = problem.world
    ends = ((Status.INVALID_START, "start", problem.start), (Status.INVALID_GOAL, "goal", problem.goal))
    for status, name, p in ends:
        why = w.explain(p) if w.bounds.contains(p) else "outside the bounds"
        if why:
            return status, f"{name} {p.tolist()} is not free: {why}"
    return None


def _failure(problem: PlanningProblem, status: Status, message: str, name: str) -> PlanResult:
    return PlanResult(status, np.empty((0, 3)), float("inf"), {}, 0, 0, 0.0, np.empty(0), name, None, message)


def plan_swarm(
    problem: PlanningProblem,
    spec: PlannerSpec,
    rng: RngLike = None,
    progress: Callable[[int, float], None] | None = None,
) -> PlanResult:
    """Plan with the swarm optimiser named by ``spec.name``.

    Parameters
    ----------
    problem : PlanningProblem
        World, end points, vehicle energy figures.
    spec : PlannerSpec
        Optimiser, population, iterations, evaluation budget, cost settings.
    rng : Generator, int or None
        Seed of the run (same seed → same result).
    progress : callable, optional
        ``progress(iteration, best_cost)`` after each iteration.
    """
    t0 = time.perf_counter()
    bad = check_endpoints(problem)
    if bad is not None:
        return _failure(problem, bad[0], bad[1], spec.name)
    lo3, hi3 = search_box(problem)
    k = spec.control_points
    lower, upper = np.tile(lo3, k), np.tile(hi3, k)
    optimizer = make_optimizer(spec, lower, upper, as_rng(rng))
    termination = Termination(max_iterations=spec.iterations, max_evaluations=spec.budget or None)
    result = minimize(make_objective(problem, spec), optimizer, termination, progress)
    ctrl = np.vstack([problem.start, result.x.reshape(k, 3), problem.goal])
    path = sample_population(ctrl, spec.samples)
    terms = evaluate_paths(problem.world, path[None], cost_model_for(problem, spec), exact=True)
    row = terms.row(0)
    free = problem.world.path_free(path, moving=False)
    status = Status.EXACT if (free and row["violations"] == 0) else Status.INFEASIBLE
    message = "" if status is Status.EXACT else (
        f"the best path found still violates {row['violations']} segment constraint(s) "
        f"(deepest violation {-row['min_clearance_m']:.1f} m); raise the budget or relax the margins"
    )
    cost_terms = plan_terms(row, spec)
    return PlanResult(
        status=status,
        path=path,
        cost=float(result.f),
        cost_terms=cost_terms,
        evaluations=result.evaluations,
        iterations=result.iterations,
        wall_time_s=time.perf_counter() - t0,
        history=result.history,
        planner=spec.name,
        control_points=ctrl,
        message=message,
    )
