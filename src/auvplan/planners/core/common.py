"""What every planner shares: the cost function a plan is scored on, the search box, the end-point
check, a plan's cost terms and a polyline's cost (used by the swarm, lattice, time-optimal and flow planners
alike, and by the vehicle's limits)."""

from __future__ import annotations

import numpy as np

from ..._types import ArrayLike, FloatArray, Status
from ...cost import CostModel, CostRow, evaluate_paths
from ...path import densify, polyline_length
from .base import PlannerSpec, PlanningProblem

__all__ = ["cost_model_for", "search_box", "check_endpoints", "plan_terms", "path_cost"]


def cost_model_for(problem: PlanningProblem, spec: PlannerSpec) -> CostModel:
    """The cost model of a planning problem under planner settings.

    Parameters
    ----------
    problem : PlanningProblem
        Vehicle speed and power figures.
    spec : PlannerSpec
        Energy model, weights, penalty and energy scale.

    Returns
    -------
    CostModel
        The cost function every planner is scored on.
    """
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


def search_box(problem: PlanningProblem) -> tuple[FloatArray, FloatArray]:
    """Per-coordinate bounds of the interior control points.

    Parameters
    ----------
    problem : PlanningProblem
        The world's bounds, depth band and seabed.

    Returns
    -------
    lower, upper : numpy.ndarray
        ``(3,)`` (m): the bounds, with z between the deepest of (bounds, max depth, lowest seabed)
        and the shallowest of (bounds, min depth).
    """
    b = problem.world.bounds
    m = problem.world.margins
    ztop = min(b.zmax, -m.min_depth)
    zlow = max(b.zmin, -m.max_depth) if np.isfinite(m.max_depth) else b.zmin
    if problem.world.terrain is not None:
        zlow = max(zlow, float(problem.world.terrain.z.min()))
    return np.array([b.xmin, b.ymin, zlow]), np.array([b.xmax, b.ymax, ztop])


def check_endpoints(problem: PlanningProblem) -> tuple[Status, str] | None:
    """Whether the start and the goal are free points.

    Parameters
    ----------
    problem : PlanningProblem
        World, start and goal.

    Returns
    -------
    tuple of (Status, str) or None
        ``(INVALID_START or INVALID_GOAL, message)`` for the first end point that is not free,
        else None.
    """
    w = problem.world
    ends = ((Status.INVALID_START, "start", problem.start), (Status.INVALID_GOAL, "goal", problem.goal))
    for status, name, p in ends:
        why = w.explain(p) if w.bounds.contains(p) else "outside the bounds"
        if why:
            return status, f"{name} {p.tolist()} is not free: {why}"
    return None


def plan_terms(row: CostRow, spec: PlannerSpec) -> dict[str, float]:
    """:attr:`PlanResult.cost_terms` from one :meth:`CostTerms.row`.

    Parameters
    ----------
    row : CostRow
        One path's cost terms.
    spec : PlannerSpec
        The weights.

    Returns
    -------
    dict of str to float
        The weighted terms (``length``, ``terrain``, ``energy``) and the physical figures
        (``length_m``, ``energy_j``, ``duration_s``, ``min_clearance_m``, ``violations`` and its
        deprecated alias ``collisions``).
    """
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


def path_cost(problem: PlanningProblem, spec: PlannerSpec, path: ArrayLike) -> dict[str, float]:
    """Cost terms of a polyline under the planner's cost function, as in :class:`PlanResult.cost_terms`.

    Segments no longer than 1/``spec.samples`` of the path, vertices kept.

    Parameters
    ----------
    problem : PlanningProblem
        World and vehicle figures.
    spec : PlannerSpec
        Cost settings and samples per path.
    path : array_like
        Vertices ``(N, 3)`` (m).

    Returns
    -------
    dict of str to float
        ``total`` and the terms of :func:`~auvplan.planners.core.common.plan_terms`.
    """
    path = np.asarray(path, dtype=float)
    spacing = max(float(polyline_length(path)) / spec.samples, 1e-9)
    terms = evaluate_paths(problem.world, densify(path, spacing)[None], cost_model_for(problem, spec), exact=True)
    row = terms.row(0)
    return {"total": row["total"], **plan_terms(row, spec)}
