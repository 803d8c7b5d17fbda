"""The planning problem as a box-bounded optimisation problem over B-spline control points.

The decision vector is the ``K`` free interior control points of a clamped cubic B-spline from
the start to the goal (``D = 3K``), bounded by the world's box (and the depth band); every
candidate is sampled at ``S`` points in one matrix product and costed with
:func:`auvplan.cost.evaluate_paths` (document 002 eq. 9, the seabed tested exactly per segment).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .._types import Status
from ..cost import CostModel, CostTerms, evaluate_paths
from ..optim import Problem
from ..path import sample_population
from .base import PlannerSpec, PlanningProblem

__all__ = ["cost_model_for", "search_box", "make_objective", "spline_problem", "control_polygon", "check_endpoints",
           "plan_terms"]


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


def control_polygon(problem: PlanningProblem, X: np.ndarray) -> np.ndarray:
    """Control points ``(P, K + 2, 3)`` of decision vectors ``X (P, 3K)`` (start and goal added)."""
    X = np.atleast_2d(X)
    k = X.shape[1] // 3
    ctrl = np.empty((X.shape[0], k + 2, 3))
    ctrl[:, 0] = problem.start
    ctrl[:, -1] = problem.goal
    ctrl[:, 1:-1] = X.reshape(-1, k, 3)
    return ctrl


def path_terms(problem: PlanningProblem, spec: PlannerSpec, X: np.ndarray, exact: bool = False) -> CostTerms:
    """Cost terms of decision vectors ``X (P, 3K)``."""
    return evaluate_paths(problem.world, sample_population(control_polygon(problem, X), spec.samples),
                          cost_model_for(problem, spec), exact=exact)


def make_objective(problem: PlanningProblem, spec: PlannerSpec,
                   strict: bool = False) -> Callable[[np.ndarray], np.ndarray]:
    """Vectorised objective ``(P, 3K) -> (P,)`` of the planning problem; ``strict`` scores a
    path that fails a constraint (the exact segment test included) ``+inf``."""
    model = cost_model_for(problem, spec)

    def objective(X: np.ndarray) -> np.ndarray:
        terms = evaluate_paths(problem.world, sample_population(control_polygon(problem, X), spec.samples), model)
        return np.where(terms.violations > 0, np.inf, terms.total) if strict else terms.total

    return objective


def spline_problem(problem: PlanningProblem, spec: PlannerSpec, budget: int | None, x0=None,
                   strict: bool = False) -> Problem:
    """The optimisation :class:`~auvplan.optim.Problem` (objective, box, seeds, budget) of a plan."""
    lo3, hi3 = search_box(problem)
    k = spec.control_points
    return Problem(make_objective(problem, spec, strict), np.tile(lo3, k), np.tile(hi3, k), x0=x0, budget=budget)


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
