"""The planning problem as a box-bounded optimisation problem over B-spline control points.

The decision vector is the ``K`` free interior control points of a clamped cubic B-spline from
the start to the goal (``D = 3K``), bounded by the world's box (and the depth band); every
candidate is sampled at ``S`` points in one matrix product and costed with
:func:`auvplan.cost.evaluate_paths` (document 002 eq. 9, the seabed tested exactly per segment).
"""

from __future__ import annotations

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...cost import CostTerms, evaluate_paths
from ...optim import Problem
from ...optim.base import Objective
from ...path import sample_population
from ..core.base import PlannerSpec, PlanningProblem
from ..core.common import cost_model_for, search_box

__all__ = ["make_objective", "spline_problem", "control_polygon", "along_track_order"]


def control_polygon(problem: PlanningProblem, X: ArrayLike) -> FloatArray:
    """Control points of decision vectors (start and goal added).

    Parameters
    ----------
    problem : PlanningProblem
        Start and goal.
    X : array_like
        Decision vectors ``(P, 3K)`` or one ``(3K,)`` (m).

    Returns
    -------
    numpy.ndarray
        ``(P, K + 2, 3)`` (m).
    """
    X = np.atleast_2d(X)
    k = X.shape[1] // 3
    ctrl = np.empty((X.shape[0], k + 2, 3))
    ctrl[:, 0] = problem.start
    ctrl[:, -1] = problem.goal
    ctrl[:, 1:-1] = X.reshape(-1, k, 3)
    return ctrl


def along_track_order(problem: PlanningProblem, X: ArrayLike) -> FloatArray:
    """Decision vectors with their control points sorted along the start-to-goal axis.

    The representation's repair (:class:`~auvplan.optim.Problem` ``repair``): the ``K`` interior
    control points of each vector are put in the order of their projections on the line from
    the start to the goal (a stable sort), so that the spline visits them in the order it meets
    them along the track instead of doubling back between two of them.  The box is per point,
    so a sorted vector stays in the box.

    Parameters
    ----------
    problem : PlanningProblem
        Start and goal.
    X : array_like
        Decision vectors ``(P, 3K)`` or one ``(3K,)`` (m).

    Returns
    -------
    numpy.ndarray
        ``(P, 3K)``: the same points, sorted per vector.
    """
    X = np.atleast_2d(np.asarray(X, dtype=float))
    pts = X.reshape(X.shape[0], -1, 3)
    axis = problem.goal - problem.start
    order = np.argsort((pts - problem.start) @ axis, axis=1, kind="stable")
    out: FloatArray = np.take_along_axis(pts, order[:, :, None], axis=1).reshape(X.shape)
    return out


def path_terms(problem: PlanningProblem, spec: PlannerSpec, X: FloatArray, exact: bool = False) -> CostTerms:
    """Cost terms of decision vectors ``X (P, 3K)``."""
    return evaluate_paths(problem.world, sample_population(control_polygon(problem, X), spec.samples),
                          cost_model_for(problem, spec), exact=exact)


def make_objective(problem: PlanningProblem, spec: PlannerSpec, strict: bool = False) -> Objective:
    """Vectorised objective ``(P, 3K) -> (P,)`` of the planning problem.

    Parameters
    ----------
    problem : PlanningProblem
        World, end points, vehicle figures.
    spec : PlannerSpec
        Cost settings, number of samples per path.
    strict : bool, default False
        Score a path that fails a constraint (the exact segment test included) ``+inf``.

    Returns
    -------
    callable
        ``objective(X (P, 3K)) -> (P,)`` (cost units).
    """
    model = cost_model_for(problem, spec)

    def objective(X: FloatArray) -> FloatArray:
        terms = evaluate_paths(problem.world, sample_population(control_polygon(problem, X), spec.samples), model)
        values: FloatArray = np.where(terms.violations > 0, np.inf, terms.total) if strict else terms.total
        return values

    return objective


def spline_problem(problem: PlanningProblem, spec: PlannerSpec, budget: int | None, x0: ArrayLike | None = None,
                   strict: bool = False) -> Problem:
    """The optimisation :class:`~auvplan.optim.Problem` (objective, box, seeds, budget) of a plan.

    Parameters
    ----------
    problem : PlanningProblem
        World, end points, vehicle figures.
    spec : PlannerSpec
        Number of control points and cost settings.
    budget : int or None
        Objective evaluations allowed (None: no budget).
    x0 : array_like, optional
        Seed decision vectors ``(M, 3K)``.
    strict : bool, default False
        Score infeasible paths ``+inf`` (:func:`make_objective`).

    Returns
    -------
    Problem
        Box-bounded problem over the ``3K`` control-point coordinates, its repair
        :func:`along_track_order`.
    """
    lo3, hi3 = search_box(problem)
    k = spec.control_points
    return Problem(make_objective(problem, spec, strict), np.tile(lo3, k), np.tile(hi3, k), x0=x0, budget=budget,
                   repair=lambda X: along_track_order(problem, X))
