"""What the lattice knows, handed to the population optimisers: seeds from a coarse lattice path.

A coarse :class:`~auvplan.planners.grid.GridReference` (``spec.seed_nodes`` nodes, the planner's
own cost on its edges) tells which side of each seamount or bank the cheap path takes.  Its
path is fitted by least squares as the ``K`` interior control points of the clamped cubic
B-spline from the start to the goal (samples at uniform arc length matched to uniform spline
parameters), and the fit plus jittered copies seed part of the first population.  The same
lattice path is the fallback plan when the optimiser ends with no feasible path.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .._types import ArrayLike, FloatArray
from ..path import basis_matrix, polyline_length, resample_polyline
from .base import PlannerSpec, PlanningProblem
from .grid import GridReference
from .swarm_problem import cost_model_for, search_box

__all__ = ["coarse_reference", "fit_control_points", "seed_candidates"]


def coarse_reference(problem: PlanningProblem, spec: PlannerSpec) -> tuple[GridReference | None, FloatArray]:
    """The coarse lattice and its path from the start.

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        ``spec.seed_nodes`` and the cost function.

    Returns
    -------
    reference : GridReference or None
        The coarse lattice (None when it cannot be built).
    path : numpy.ndarray
        Its path ``(N, 3)`` (m) from the start (empty when the lattice finds none).
    """
    lower, upper = search_box(problem)
    params = replace(spec.grid, cell=0.0, cell_z=0.0, target_nodes=spec.seed_nodes,
                     max_nodes=max(spec.grid.max_nodes, spec.seed_nodes), objective="cost")
    try:
        ref = GridReference(problem.world, problem.goal, cost_model_for(problem, spec), lower, upper, params)
    except ValueError:
        return None, np.empty((0, 3))
    return ref, ref.query(problem.start)


def fit_control_points(path: ArrayLike, k: int, samples: int = 200) -> FloatArray:
    """Least-squares fit of a clamped cubic B-spline to a polyline.

    The spline runs through ``path[0]`` and ``path[-1]``; its interior control points minimise the
    squared distance to the polyline sampled at uniform arc length.

    Parameters
    ----------
    path : array_like
        Vertices ``(N, 3)`` (m).
    k : int
        Number of interior control points.
    samples : int, default 200
        Samples of the polyline and the spline matched in the fit.

    Returns
    -------
    numpy.ndarray
        Interior control points ``(k, 3)`` (m).
    """
    path = np.asarray(path, dtype=float)
    length = float(polyline_length(path))
    pts = resample_polyline(path, max(length / (samples - 1), 1e-9))
    if pts.shape[0] != samples:  # resample_polyline rounds the count: interpolate to exactly `samples`
        s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
        q = np.linspace(0.0, s[-1], samples)
        pts = np.column_stack([np.interp(q, s, pts[:, d]) for d in range(3)])
    B = basis_matrix(k + 2, samples)
    rhs = pts - np.outer(B[:, 0], path[0]) - np.outer(B[:, -1], path[-1])
    ctrl, *_ = np.linalg.lstsq(B[:, 1:-1], rhs, rcond=None)
    return np.asarray(ctrl, dtype=np.float64)  # numpy types lstsq as floating[Any]: float64 in, float64 out


def seed_candidates(ctrl: ArrayLike, count: int, lower: FloatArray, upper: FloatArray,
                    rng: np.random.Generator, jitter: float = 0.02) -> FloatArray:
    """Decision vectors seeding a population: the fitted control points and jittered copies.

    Parameters
    ----------
    ctrl : array_like
        Fitted interior control points ``(k, 3)`` (m), flattened into the decision vector.
    count : int
        Number of vectors (at least 1 is returned).
    lower, upper : numpy.ndarray
        Box of the decision vector ``(3k,)`` (m).
    rng : numpy.random.Generator
        Source of the jitter.
    jitter : float, default 0.02
        Standard deviation of the jitter as a fraction of the box width per coordinate.

    Returns
    -------
    numpy.ndarray
        ``(max(count, 1), 3k)``: the fit first, then copies jittered by ``N(0, (jitter · range)²)``,
        all clipped to the box.
    """
    x = np.clip(np.asarray(ctrl, dtype=float).reshape(-1), lower, upper)
    out = np.repeat(x[None], max(count, 1), axis=0)
    if count > 1:
        out[1:] += rng.normal(0.0, 1.0, size=out[1:].shape) * jitter * (upper - lower)
    seeds: FloatArray = np.clip(out, lower, upper)
    return seeds
