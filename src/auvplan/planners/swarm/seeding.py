"""What the lattice knows, handed to the population optimisers: seeds from a coarse lattice path.

A coarse :class:`~auvplan.planners.grid.planner.GridReference` (``spec.seed_nodes`` nodes, the planner's
own cost on its edges) tells which side of each seamount or bank the cheap path takes.  Its
path gives candidate ``K`` interior control points of the clamped cubic B-spline from the start
to the goal: the least-squares fit of the path (samples at uniform arc length matched to uniform
spline parameters), the fit of its taut polygon (document 004's key waypoints), and every
arrangement of the ``K`` control points as repeats of the taut polygon's corners, which puts the
spline's bends where the path bends (the even spread of a least-squares fit is one local optimum
of the spline's parametrisation among many; on chagos-banks not the best one).  The planner
screens the candidates by its objective and seeds part of the first population with the best.
The same lattice path is the fallback plan when the optimiser ends with no feasible path.
"""

from __future__ import annotations

import functools
from dataclasses import replace

import numpy as np

from ..._types import ArrayLike, FloatArray, IntArray
from ...guidance.avoidance.local import key_waypoints
from ...path import basis_matrix, polyline_length, resample_polyline
from ...world import World
from ..core.base import PlannerSpec, PlanningProblem
from ..core.common import cost_model_for, search_box
from ..grid.planner import GridReference

__all__ = ["SEED_DETOUR", "SEED_LADDER", "SEED_LADDER_MAX", "STRAIGHT", "coarse_reference", "compositions",
           "corner_control_points", "fit_control_points", "lattice_seeds", "seed_candidates"]

SEED_LADDER = 8
"""Factor of nodes between the rungs of the seeding ladder (:func:`coarse_reference`): 8 000, 64 000,
512 000 with the default ``seed_nodes``."""

SEED_LADDER_MAX = 600_000
"""Most nodes of the seeding ladder's finest lattice: about the reference's 1 km lattice on the Chagos
box, the first that sees the narrow channel of ``chagos-channel``."""

SEED_DETOUR = 2.0
"""Lattice paths longer than this many times the straight start-goal distance send the seeding ladder on
to a finer lattice: the six hard built-ins' 8 000-node paths are 1.00–1.44 times it (a genuine detour
round a ridge), chagos-channel's 32 000- and 64 000-node paths round the bank 2.5 times."""

STRAIGHT = 1e-3
"""Whole turning (rad) below which the bend-weighted fit treats a polyline as straight (0.06°)."""


def coarse_reference(problem: PlanningProblem, spec: PlannerSpec) -> tuple[GridReference | None, FloatArray]:
    """The coarse lattice and its path from the start, finer lattices tried when it finds none.

    The lattice of ``spec.seed_nodes`` nodes first; when it finds no path (a channel narrower than its
    cells, or a layer under the depth ceiling thinner than its levels) or a path more than
    :data:`SEED_DETOUR` times the straight start-goal distance (a detour round a closed-looking
    passage), lattices :data:`SEED_LADDER` times finer in nodes each, up to :data:`SEED_LADDER_MAX`
    nodes, until one finds a path within that detour; the shortest path of the rungs is kept.  The finer
    rungs search A* towards the start alone (the same path cost, less of the lattice settled).  On the
    narrow Chagos channels (``chagos-channel``) the 8 000-node lattice sees no passage and the 64 000-node
    one only the way round the south of the Great Chagos Bank (2.5 times the distance, +135 % in cost):
    before the ladder the swarm ran unseeded (INFEASIBLE in 2 seeds of 6, with no lattice path to fall
    back on) and, with a ladder stopping at the first path, seeded with the detour, every seed but one
    followed it.  The finer lattices are built only where the coarse one failed or detoured (no hard
    built-in: their 8 000-node paths are at most 1.44 times the distance, ninetyeast-ridge round its
    ridge); on chagos-channel they are about half of the plan's CPU (docs/convergence.md).

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        ``spec.seed_nodes`` and the cost function.

    Returns
    -------
    reference : GridReference or None
        The lattice that found the path, else the last one tried (None when none can be built).
    path : numpy.ndarray
        Its path ``(N, 3)`` (m) from the start (empty when no lattice of the ladder finds one).
    """
    lower, upper = search_box(problem)
    model = cost_model_for(problem, spec)
    nodes, last = spec.seed_nodes, None
    best: tuple[GridReference, FloatArray] | None = None
    while True:
        params = replace(spec.grid, cell=0.0, cell_z=0.0, target_nodes=nodes,
                         max_nodes=max(spec.grid.max_nodes, nodes), objective="cost")
        try:
            ref = GridReference(problem.world, problem.goal, model, lower, upper, params,
                                start=None if nodes == spec.seed_nodes else problem.start)
        except ValueError:
            return best if best is not None else (last, np.empty((0, 3)))
        path = ref.query(problem.start)
        if path.shape[0] >= 2 and (best is None or _detour(path, problem) < _detour(best[1], problem)):
            best = (ref, path)
        if (best is not None and _detour(best[1], problem) <= SEED_DETOUR) or nodes * SEED_LADDER > SEED_LADDER_MAX:
            return best if best is not None else (ref, path)
        nodes, last = nodes * SEED_LADDER, ref  # the finer rungs search A* towards the start alone


def _detour(path: FloatArray, problem: PlanningProblem) -> float:
    """A lattice path's length over the straight start-goal distance (1 for a loop: start = goal)."""
    distance = float(np.linalg.norm(problem.goal - problem.start))
    return float(polyline_length(path)) / distance if distance > 0 else 1.0


def fit_control_points(path: ArrayLike, k: int, samples: int = 200, bend: float = 0.0) -> FloatArray:
    """Least-squares fit of a clamped cubic B-spline to a polyline.

    The spline runs through ``path[0]`` and ``path[-1]``; its interior control points minimise the
    squared distance to the polyline sampled at uniform arc length (``bend = 0``) or at uniform
    *bend-weighted* length, in which every radian the polyline turns counts as much as
    ``bend / Θ`` of its length (Θ its whole turning), so that the uniform spline parameter, and
    with it the control points, crowd where the polyline bends instead of spreading evenly along
    its straight stretches (a polyline turning less than :data:`STRAIGHT` in all is fitted at
    uniform arc length).

    Parameters
    ----------
    path : array_like
        Vertices ``(N, 3)`` (m).
    k : int
        Number of interior control points.
    samples : int, default 200
        Samples of the polyline and the spline matched in the fit.
    bend : float, default 0.0
        Weight of the turning against the length (0: arc length alone; 1: half of the spline's
        parameter for the bends when the polyline turns at all).

    Returns
    -------
    numpy.ndarray
        Interior control points ``(k, 3)`` (m).
    """
    path = np.asarray(path, dtype=float)
    length = float(polyline_length(path))
    pts = resample_polyline(path, max(length / (samples - 1), 1e-9))
    steps = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    s = np.r_[0.0, np.cumsum(steps)]
    if bend > 0 and pts.shape[0] > 2:
        s = s / max(s[-1], 1e-12) + bend * _turning(pts, steps)
    if pts.shape[0] != samples or bend > 0:  # exactly `samples` points, uniform in s
        q = np.linspace(0.0, s[-1], samples)
        pts = np.column_stack([np.interp(q, s, pts[:, d]) for d in range(3)])
    B = basis_matrix(k + 2, samples)
    rhs = pts - np.outer(B[:, 0], path[0]) - np.outer(B[:, -1], path[-1])
    ctrl, *_ = np.linalg.lstsq(B[:, 1:-1], rhs, rcond=None)
    return np.asarray(ctrl, dtype=np.float64)  # numpy types lstsq as floating[Any]: float64 in, float64 out


def _turning(pts: FloatArray, steps: FloatArray) -> FloatArray:
    """Cumulative turning at the vertices of a polyline, as a share of its whole turning.

    Each vertex's turning angle (``atan2(|a × b|, a · b)``, accurate near 0) is split half to the
    segment before it and half to the one after, so that the measure grows across a corner, not at
    one sample.  A polyline that turns less than ``STRAIGHT`` radians in all is straight: zeros."""
    t = np.diff(pts, axis=0) / np.maximum(steps, 1e-12)[:, None]
    angle = np.arctan2(np.linalg.norm(np.cross(t[:-1], t[1:]), axis=1), np.einsum("ij,ij->i", t[1:], t[:-1]))
    per_segment = 0.5 * (np.r_[0.0, angle] + np.r_[angle, 0.0])
    total = per_segment.sum()
    out: FloatArray = np.r_[0.0, np.cumsum(per_segment)] / total if total > STRAIGHT else np.zeros(pts.shape[0])
    return out


def seed_candidates(ctrl: ArrayLike | list[FloatArray], count: int, lower: FloatArray, upper: FloatArray,
                    rng: np.random.Generator, jitter: float = 0.02) -> FloatArray:
    """Decision vectors seeding a population: the seed control points and jittered copies.

    Parameters
    ----------
    ctrl : array_like or list of numpy.ndarray
        Seed interior control points ``(k, 3)`` (m), one array or a list of them, each flattened
        into a decision vector.
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
        ``(max(count, 1), 3k)``: each seed once, then copies of the seeds in turn jittered by
        ``N(0, (jitter · range)²)``, all clipped to the box.
    """
    base = [np.asarray(c, dtype=float).reshape(-1) for c in (ctrl if isinstance(ctrl, list) else [ctrl])]
    count = max(count, 1)
    out = np.array([base[i % len(base)] for i in range(count)])
    if count > len(base):
        out[len(base):] += rng.normal(0.0, 1.0, size=out[len(base):].shape) * jitter * (upper - lower)
    seeds: FloatArray = np.clip(out, lower, upper)
    return seeds


def compositions(k: int, m: int) -> IntArray:
    """Every way of writing ``k`` as an ordered sum of ``m`` non-negative integers.

    Parameters
    ----------
    k : int
        The total (>= 0).
    m : int
        Number of parts (>= 1).

    Returns
    -------
    numpy.ndarray
        ``(C(k + m - 1, m - 1), m)`` integer rows, the first part in decreasing order.
    """
    return np.array(_compositions(k, m), dtype=np.int_).reshape(-1, m)


@functools.lru_cache(maxsize=64)
def _compositions(k: int, m: int) -> tuple[tuple[int, ...], ...]:
    """:func:`compositions` as tuples, cached (each plan asks for the same few)."""
    if m == 1:
        return ((k,),)
    return tuple((first, *rest) for first in range(k, -1, -1) for rest in _compositions(k - first, m - 1))


def corner_control_points(polygon: ArrayLike, k: int) -> list[FloatArray]:
    """Control points that put the spline's bends at the corners of a polygon.

    Every arrangement of the ``k`` control points as repeats of the corners (a corner may get none:
    a coarse lattice path turns where the best path need not), so that the clamped cubic B-spline
    turns close to the repeated corners (through a corner repeated three times).  The
    arrangements are local optima of the spline's parametrisation that the smooth least-squares
    fit does not reach.

    Parameters
    ----------
    polygon : array_like
        Vertices ``(m + 2, 3)`` (m): the start, ``1 <= m <= k`` corners, the goal.
    k : int
        Number of interior control points.

    Returns
    -------
    list of numpy.ndarray
        One ``(k, 3)`` array per composition of ``k`` into ``m`` parts (:func:`compositions`).

    Raises
    ------
    ValueError
        If the polygon has no corner or more than ``k``.
    """
    corners = np.asarray(polygon, dtype=float).reshape(-1, 3)[1:-1]
    m = corners.shape[0]
    if not 1 <= m <= k:
        raise ValueError(f"need 1 <= corners <= k, got {m} corners for k = {k}")
    return [np.repeat(corners, mult, axis=0) for mult in compositions(k, m)]


def lattice_seeds(path: ArrayLike, world: World, k: int, samples: int = 200) -> list[FloatArray]:
    """Seed control points from a lattice path.

    The least-squares fit of the path, the least-squares fit of its taut polygon (document 004's
    key waypoints: the waypoints that hold the path up, exact segment test) and, when the taut
    polygon has at most ``k`` corners, the control points repeated at its corners
    (:func:`corner_control_points`), which put the spline's bends where the path bends instead of
    spreading them evenly.

    Parameters
    ----------
    path : array_like
        Lattice path ``(N, 3)`` (m) from the start to the goal.
    world : World
        The world (its exact segment test picks the taut polygon).
    k : int
        Number of interior control points.
    samples : int, default 200
        Samples matched in the least-squares fits.

    Returns
    -------
    list of numpy.ndarray
        Candidate interior control points, each ``(k, 3)`` (m); the path's fit first.
    """
    path = np.asarray(path, dtype=float)
    seeds = [fit_control_points(path, k, samples)]
    taut = key_waypoints(path, world)
    if taut.shape[0] > 2:
        seeds.append(fit_control_points(taut, k, samples))
        if taut.shape[0] - 2 <= k:
            seeds += corner_control_points(taut, k)
    return seeds
