"""Coarse-to-fine search over B-spline control points: the ``"progressive"`` pipeline's first stage.

A population optimiser alone, started at random over ``K`` control points, spends its budget
sorting out *which* control points do what before it can shape the path: on chagos-banks IABC's
colony settles with three or four of six control points crowded near the start and one wide arc around
the bank (+2–4 % against the reference), and no setting of the algorithm moves the idle control
points to the corner the path must turn.  Searched first with ``⌈K/2⌉`` control points, the
route (which side of each bank, where the path turns) is found in a space half as large; the
best paths of that stage, refitted to ``K`` control points with the fit weighted towards the
bends (:func:`~auvplan.planners.swarm.seeding.fit_control_points`, ``bend``), then seed the full
search (at most half of its first population, the rest drawn as usual), which starts with its
control points where the path turns.

No lattice and no local polish are involved: this is still the optimiser alone, run twice at two
resolutions of the same representation, and every evaluation of both stages counts against the
one budget.  The stage is optimiser-agnostic: it keeps the best distinct vectors the objective
saw (:class:`Elite`), not any optimiser's population.

The stage chooses the corridor, so its colony must keep several alive until their paths are shaped
(issue 59).  IABC's improved rules aim the pull of every move and the mutants of the worst fifth at
the best source; started at random, on marcus-wake-field (a 272 km route through a seamount chain)
the colony's best path of the first 500 evaluations is the open detour north of the chain, feasible
at +17 %, while every path through the gap still grazes a wall (+40 % and more with the terrain
penalty), and within ~1 000 evaluations every source is in the detour: 4 of 5 seeds ended +13.7 %.
The coarse stage therefore draws the colony's attraction centres among its best :data:`COARSE_ELITE`
share (IABC's ``elite``; the user's share when larger): the gap's lineages survive until one is
free (8 of 10 seeds thread it, +0.1–0.3 %).  The full stage, seeded with the chosen corridor,
refines with the user's settings (aimed at the best source by default).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...optim import OptimizeResult, Problem
from ...optim.base import Objective
from ...path import sample_population
from ..core.base import PlannerSpec, PlanningProblem
from .problem import control_polygon, spline_problem
from .seeding import fit_control_points

__all__ = ["COARSE_ELITE", "Elite", "RunOptimizer", "coarse_count", "coarse_stage", "refit"]

COARSE_ELITE = 0.3
"""IABC's ``elite`` share in the coarse stage (at least): the stage's colony aims its pull and its mutants at a
source drawn among its best 30 %, not at its best source (see the module notes)."""

RunOptimizer = Callable[[PlannerSpec, Problem, np.random.Generator], OptimizeResult]
"""``run(spec, problem, rng) -> OptimizeResult``: an optimiser run until the problem's budget is spent."""


class Elite:
    """The best ``size`` distinct decision vectors an objective has been asked about.

    Wraps an objective (:meth:`wrap`) and keeps, after every batch, the ``size`` rows of lowest
    value among all rows seen so far (exact duplicates counted once; ties in the order seen).

    Parameters
    ----------
    size : int
        Number of vectors kept (>= 1).
    dim : int
        Dimension of the vectors.
    """

    def __init__(self, size: int, dim: int) -> None:
        if size < 1:
            raise ValueError(f"size = {size}: must be >= 1")
        self.size = size
        self.X = np.empty((0, dim))
        self.f = np.empty(0)

    def add(self, X: ArrayLike, f: ArrayLike) -> None:
        """Merge a batch into the kept vectors.

        Parameters
        ----------
        X : array_like
            Vectors ``(B, D)``.
        f : array_like
            Their values ``(B,)`` (non-finite values are never kept).
        """
        rows = np.vstack([self.X, np.asarray(X, dtype=float).reshape(-1, self.X.shape[1])])
        vals = np.r_[self.f, np.asarray(f, dtype=float).ravel()]
        ok = np.isfinite(vals)
        rows, vals = rows[ok], vals[ok]
        first = np.sort(np.unique(rows, axis=0, return_index=True)[1])  # each vector once, in the order seen
        rows, vals = rows[first], vals[first]
        keep = np.argsort(vals, kind="stable")[: self.size]
        self.X, self.f = rows[keep], vals[keep]

    def wrap(self, objective: Objective) -> Objective:
        """The objective, recording every batch it evaluates.

        Parameters
        ----------
        objective : callable
            ``objective(X (P, D)) -> (P,)``.

        Returns
        -------
        callable
            The same values, with each batch merged by :meth:`add`.
        """
        def recorded(X: FloatArray) -> FloatArray:
            f = objective(X)
            self.add(X, f)
            return f

        return recorded


def coarse_count(k: int) -> int:
    """Control points of the coarse stage: ``⌈k/2⌉``, at least 2 (the fewest a clamped cubic spline
    between the start and the goal can have).

    Parameters
    ----------
    k : int
        Control points of the plan.

    Returns
    -------
    int
        ``max((k + 1) // 2, 2)``; equal to ``k`` for ``k <= 2`` (no coarser stage).
    """
    return max((k + 1) // 2, 2)


def refit(problem: PlanningProblem, X: ArrayLike, k: int, samples: int, bend: float) -> FloatArray:
    """Decision vectors of one control-point count refitted to ``k`` control points.

    Each vector's path (sampled at ``samples`` points) is fitted by a clamped cubic B-spline with
    ``k`` interior control points (:func:`~auvplan.planners.swarm.seeding.fit_control_points`).

    Parameters
    ----------
    problem : PlanningProblem
        Start and goal.
    X : array_like
        Decision vectors ``(P, 3k')`` (m).
    k : int
        Interior control points wanted.
    samples : int
        Samples per path.
    bend : float
        Weight of the bends in the fit.

    Returns
    -------
    numpy.ndarray
        ``(P, 3k)`` (m).
    """
    paths = sample_population(control_polygon(problem, X), samples)
    return np.array([fit_control_points(p, k, samples, bend).ravel() for p in paths]).reshape(-1, 3 * k)


def coarse_stage(problem: PlanningProblem, spec: PlannerSpec, budget: int,
                 run: RunOptimizer, rng: np.random.Generator) -> tuple[FloatArray, OptimizeResult]:
    """Search with ``⌈K/2⌉`` control points and return seeds for the full search.

    Parameters
    ----------
    problem : PlanningProblem
        World, end points, vehicle figures.
    spec : PlannerSpec
        The plan's settings (``control_points`` K, ``population``, ``samples``, ``bend``).
    budget : int
        Evaluations of this stage (>= 1).
    run : callable
        ``run(spec, problem, rng) -> OptimizeResult``: the optimiser of ``spec`` run on an
        optimisation problem until its budget is spent.
    rng : numpy.random.Generator
        The run's generator.

    Returns
    -------
    seeds : numpy.ndarray
        ``(M, 3K)``, M <= ``population``: the stage's best distinct vectors, best first, refitted to
        K control points.
    result : OptimizeResult
        The stage's run (its evaluations, iterations, history and trace).
    """
    coarse = replace(spec, control_points=coarse_count(spec.control_points),
                     iabc=replace(spec.iabc, elite=max(spec.iabc.elite, COARSE_ELITE)))
    task = spline_problem(problem, coarse, budget)
    elite = Elite(spec.population, task.dim)
    task.objective = elite.wrap(task.objective)
    result = run(coarse, task, rng)
    return refit(problem, elite.X, spec.control_points, spec.samples, spec.bend), result
