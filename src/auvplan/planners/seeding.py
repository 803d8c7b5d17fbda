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

from ..guidance.local import key_waypoints
from ..path import basis_matrix, polyline_length, resample_polyline
from ..world import World
from .base import PlannerSpec, PlanningProblem
from .grid import GridReference
from .swarm_problem import cost_model_for, search_box

__all__ = ["coarse_reference", "corner_control_points", "fit_control_points", "lattice_seeds", "seed_candidates"]


def coarse_reference(problem: PlanningProblem, spec: PlannerSpec) -> tuple[GridReference | None, np.ndarray]:
    """The coarse lattice (None when it cannot be built) and its path ``(N, 3)`` from the start
    (empty when the lattice finds none)."""
    lower, upper = search_box(problem)
    params = replace(spec.grid, cell=0.0, cell_z=0.0, target_nodes=spec.seed_nodes,
                     max_nodes=max(spec.grid.max_nodes, spec.seed_nodes), objective="cost")
    try:
        ref = GridReference(problem.world, problem.goal, cost_model_for(problem, spec), lower, upper, params)
    except ValueError:
        return None, np.empty((0, 3))
    return ref, ref.query(problem.start)


def fit_control_points(path: np.ndarray, k: int, samples: int = 200) -> np.ndarray:
    """Interior control points ``(k, 3)`` of the clamped cubic B-spline through ``path[0]`` and
    ``path[-1]`` closest (least squares) to the polyline ``path`` sampled at uniform arc length."""
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
    return ctrl


def seed_candidates(ctrl, count: int, lower: np.ndarray, upper: np.ndarray,
                    rng: np.random.Generator, jitter: float = 0.02) -> np.ndarray:
    """``count`` decision vectors from the seed control points ``ctrl`` (one ``(k, 3)`` array or a
    list of them): each seed once, then copies of the seeds in turn jittered by
    ``N(0, (jitter · range)²)`` per coordinate, all clipped to the box ``(lower, upper)`` of the
    decision vector."""
    base = [np.asarray(c, dtype=float).reshape(-1) for c in (ctrl if isinstance(ctrl, list) else [ctrl])]
    count = max(count, 1)
    out = np.array([base[i % len(base)] for i in range(count)])
    if count > len(base):
        out[len(base):] += rng.normal(0.0, 1.0, size=out[len(base):].shape) * jitter * (upper - lower)
    return np.clip(out, lower, upper)


def corner_control_points(corners: np.ndarray, k: int, variants: int = 3) -> list[np.ndarray]:
    """Control points ``(k, 3)`` that place the spline's bends at ``corners (m, 3)`` (``1 <= m <= k``):
    each corner repeated, so that the clamped cubic B-spline turns close to it (through it when
    repeated three times).  The ``k - m`` spare repeats go first to the sharpest turns, then, for
    the other ``variants - 1`` arrangements, to the next corners in turn, so that the seeds also
    differ in how the control points are spread along the path (each arrangement is a different
    local optimum of the spline's parametrisation)."""
    corners = np.asarray(corners, dtype=float).reshape(-1, 3)
    m = corners.shape[0]
    if not 1 <= m <= k:
        raise ValueError(f"need 1 <= corners <= k, got {m} corners for k = {k}")
    out: list[np.ndarray] = []
    for v in range(max(variants, 1)):
        mult = np.full(m, k // m)
        spare = k - mult.sum()
        mult[(np.arange(spare) + v) % m] += 1
        arr = np.repeat(corners, mult, axis=0)
        if not any(np.array_equal(arr, o) for o in out):
            out.append(arr)
    return out


def lattice_seeds(path: np.ndarray, world: World, k: int, samples: int = 200) -> list[np.ndarray]:
    """Seed control points ``(k, 3)`` from a lattice path ``(N, 3)``: the least-squares fit of the
    path, the least-squares fit of its taut polygon (document 004's key waypoints: the waypoints
    that hold the path up, exact segment test) and, when the taut polygon has at most ``k``
    corners, control points repeated at its corners (:func:`corner_control_points`), which put
    the spline's bends where the path bends instead of spreading them evenly."""
    path = np.asarray(path, dtype=float)
    seeds = [fit_control_points(path, k, samples)]
    taut = key_waypoints(path, world)
    if taut.shape[0] > 2:
        seeds.append(fit_control_points(taut, k, samples))
        if taut.shape[0] - 2 <= k:
            seeds += corner_control_points(taut[1:-1], k)
    return seeds
