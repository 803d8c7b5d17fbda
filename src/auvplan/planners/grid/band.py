"""The elastic band that refines a lattice path under the planner's own cost (the grid planner's step 4).

:func:`edge_cost` prices straight segments with the planner's cost (length, or length + energy in the
current, each segment in its own direction); :func:`densify` and :func:`resample_free` put points on a
path, the latter keeping vertices where a resampled segment would collide (exact test);
:func:`_relax` moves each interior vertex towards its neighbours' midpoint or along the path's two
normals when that lowers the cost of its two segments and keeps both free; :func:`_refine` runs the
band coarse to fine, and :func:`_converge` until halving the spacing no longer lowers the exact cost
(:func:`~auvplan.planners.core.common.path_cost`).  Used by :mod:`auvplan.planners.grid` (and
:func:`~auvplan.planners.grid.planner.refine_plan` for any planner's path).
"""

from __future__ import annotations

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...cost import CostModel, segment_energy
from ...guidance.avoidance.local import key_waypoints
from ...path import arc_length, polyline_length, resample_polyline
from ...world import World
from ..core.base import PlannerSpec, PlanningProblem
from ..core.common import path_cost
from .band_kernels import band_choose, band_gains, band_moves, band_segments, chord_lengths

__all__ = ["edge_cost", "gives_up", "level_count", "resample_free"]


def edge_cost(world: World, a: FloatArray, b: FloatArray, model: CostModel, objective: str,
              current: ArrayLike | None = None) -> FloatArray:
    """Cost of travelling straight segments.

    Parameters
    ----------
    world : World
        Source of the current field.
    a, b : numpy.ndarray
        Segment starts and ends ``(..., 3)`` (m).
    model : CostModel
        Weights and vehicle figures.
    objective : str
        ``"length"`` (the length in m) or ``"cost"`` (the cost function's ``w_L`` length + ``w_E`` energy).
    current : array_like, optional
        The current at the midpoints ``(..., 3)`` (m/s) when the caller has it.

    Returns
    -------
    numpy.ndarray
        ``(...)``; ``inf`` where the current beats the vehicle.
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape == b.shape and a.ndim >= 2:  # the band's and the lattice's case: one compiled pass, the same bits
        length: FloatArray = np.empty(a.shape[:-1])
        chord_lengths(np.ascontiguousarray(a).reshape(-1, 3), np.ascontiguousarray(b).reshape(-1, 3),
                      length.reshape(-1))
    else:
        length = np.linalg.norm(b - a, axis=-1)
    if objective == "length":
        return length
    units, _, _, blocked = segment_energy(world, a, b, model, current)
    cost = model.w_length * length + model.w_energy * model.scale * units
    return np.where(blocked, np.inf, cost)


def resample_free(world: World, path: np.ndarray, spacing: float) -> np.ndarray:
    """Points every ``spacing`` metres along the free polyline ``path (N, 3)``, except where a
    resampled segment would cut a corner into the seabed or an obstacle: there the original
    vertices between its two ends are kept, so that stretch follows ``path`` and stays free.

    Parameters
    ----------
    world : World
        Static constraints.
    path : ndarray, shape (N, 3)
        A polyline that passes the exact segment test.
    spacing : float
        Arc-length spacing (m).

    Returns
    -------
    ndarray, shape (M, 3)
        A free polyline through the same end points.
    """
    p = np.asarray(path, dtype=float)
    s = arc_length(p)
    r = resample_polyline(p, spacing)
    q = np.linspace(0.0, s[-1], r.shape[0])
    bad = np.flatnonzero(~world.segments_free(np.stack([r[:-1], r[1:]], axis=1), moving=False))
    if bad.size == 0:
        return r
    pieces, last = [], 0
    for i in bad:
        pieces += [r[last:i + 1], p[(s > q[i]) & (s < q[i + 1])]]
        last = int(i) + 1
    return np.vstack([*pieces, r[last:]])


def _normals(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors perpendicular to the chords ``t (m, 3)`` (normalised in place) and to each other."""
    norm = np.sqrt(np.einsum("ij,ij->i", t, t))
    t /= np.maximum(norm, 1e-12)[:, None]
    t[norm <= 1e-12] = (1.0, 0.0, 0.0)  # a point revisited (zero chord): every direction is normal to it;
    # take those of an x chord, never NaN
    tx, ty, tz = t[:, 0], t[:, 1], t[:, 2]
    steep = np.abs(tz) >= 0.9  # t x (0, 0, 1), or t x (1, 0, 0) for a steep chord
    n1 = np.empty_like(t)
    n1[:, 0] = np.where(steep, 0.0, ty)
    n1[:, 1] = np.where(steep, tz, -tx)
    n1[:, 2] = np.where(steep, -ty, 0.0)
    n1 /= np.sqrt(np.einsum("ij,ij->i", n1, n1))[:, None]
    n2 = np.empty_like(t)
    n2[:, 0] = ty * n1[:, 2] - tz * n1[:, 1]
    n2[:, 1] = tz * n1[:, 0] - tx * n1[:, 2]
    n2[:, 2] = tx * n1[:, 1] - ty * n1[:, 0]
    return n1, n2


def _relax(world: World, p: np.ndarray, model: CostModel, objective: str, iterations: int,
           step: float) -> np.ndarray:
    """Elastic band with pattern search: each interior point tries a pull towards its
    neighbours' midpoint and moves of ``±δ`` along two normals of the path, and takes the
    best move that lowers the cost of its two segments and keeps both free (odd and even
    points in turn, so that the moves are independent).  Failed points halve their steps.
    Only the moves that lower the cost go through the exact segment test.  (The arrays are
    filled in place rather than stacked: the same numbers, fewer temporaries.)"""
    p = p.copy()
    n = p.shape[0]
    if n < 3 or iterations == 0:
        return p
    alpha = np.full(n, 0.5)
    delta = np.full(n, 0.5 * step)
    tol = 1e-3 * step
    parities = (np.arange(1, n - 1, 2), np.arange(2, n - 1, 2))
    for _ in range(iterations):
        for every in parities:
            i = every[(alpha[every] > 1e-3) | (delta[every] > tol)]
            if i.size == 0:
                continue
            m = i.size
            ends, tips = np.empty((12, m, 3)), np.empty((12, m, 3))  # a -> each move, each move -> c
            band_moves(p, i, alpha, delta, ends, tips)
            new, better = np.empty((5, m)), np.empty((5, m), dtype=bool)
            band_gains(edge_cost(world, ends, tips, model, objective), new, better)
            kk, jj = (np.ascontiguousarray(k) for k in np.nonzero(better))  # C whatever their count: one kernel
            if kk.size:  # only the moves that lower the cost go through the exact segment test
                seg = np.empty((kk.size, 2, 2, 3))
                band_segments(ends, tips, kk, jj, seg)
                better[kk, jj] = world.segments_free(seg, moving=False).all(axis=-1)
            band_choose(p, i, tips, new, better, alpha, delta, float(step))
        if np.all(alpha[1:-1] <= 1e-3) and np.all(delta[1:-1] <= tol):
            break
    return p


def _refine(world: World, raw: np.ndarray, model: CostModel, objective: str, cell: float,
            iterations: int) -> np.ndarray:
    """Coarse-to-fine elastic band: the path is resampled at 1/8, 1/16, … of its length down to
    half a cell (a ladder of spacings fixed by the path, not by the cell, so that every lattice
    hands the band the same coarse levels; resamplings that would cut into an obstacle densify
    instead) and relaxed at each level with steps of that spacing, so that whole stretches move
    together before the detail is settled."""
    path = raw
    spacing = float(polyline_length(raw)) / 8.0
    while True:
        spacing = max(spacing, 0.5 * cell)
        path = _relax(world, resample_free(world, path, spacing), model, objective, iterations, spacing)
        if spacing <= 0.5 * cell:
            return path
        spacing *= 0.5


def _converge(problem: PlanningProblem, spec: PlannerSpec, path: np.ndarray, model: CostModel,
              iterations: int, tol: float, cycles: int = 6, finest: float = 2048.0,
              target: float | None = None) -> tuple[np.ndarray, float, int]:
    """Refine until the cost stops improving, the same way whatever the lattice: cycles of
    levels, each level resampling the best path so far every 1/8, 1/16, … 1/``finest`` of its length
    (:func:`resample_free`), relaxing it with steps of that spacing (and, for the length
    objective, dropping the vertices that hold nothing up) and keeping it only when cheaper and
    free; the cycles stop when one gains less than ``tol`` (relative), or after ``cycles``.

    With a ``target`` (a cost the caller needs the path to beat, else the refinement is of no use to it)
    the refinement gives up after a level when the remaining levels of the cycle, each gaining as much as
    the best level so far, could not bring the cost below it (:func:`gives_up`).

    Returns the path, its cost and the number of levels run.
    """
    world, objective = problem.world, spec.grid.objective
    best, best_cost = path, path_cost(problem, spec, path)["total"]
    length = float(polyline_length(path))
    levels, steps = 0, level_count(finest)
    for _ in range(cycles):
        before, gain = best_cost, 0.0
        spacing = length / 8.0
        for step in range(steps):
            levels += 1
            cand = _relax(world, resample_free(world, best, spacing), model, objective, iterations, spacing)
            if objective == "length":
                cand = key_waypoints(cand, world)
            cost = path_cost(problem, spec, cand)["total"]
            if cost < best_cost and world.path_free(cand):
                gain = max(gain, best_cost - cost)
                best, best_cost = cand, cost
            if target is not None and gives_up(best_cost, target, gain, steps - step - 1):
                return best, best_cost, levels
            spacing *= 0.5
        if before - best_cost < tol * max(abs(before), 1e-12):
            break
    return best, best_cost, levels


def level_count(finest: float) -> int:
    """Levels per cycle of :func:`_converge`: spacings 1/8, 1/16, … down to 1/``finest`` of the length
    (the finest kept when ``finest`` is not a power of two times 8).

    Parameters
    ----------
    finest : float
        The finest level's spacing as a fraction of the length (1/``finest``).

    Returns
    -------
    int
        The number of levels (0 when ``finest`` < 8).
    """
    n, spacing = 0, 1.0 / 8.0
    while spacing >= 1.0 / finest:
        n, spacing = n + 1, spacing * 0.5
    return n


def gives_up(cost: float, target: float, gain: float, remaining: int) -> bool:
    """Whether a refinement at ``cost`` cannot reach below ``target`` in ``remaining`` levels that each
    gain at most ``gain`` (the best single level's gain so far).

    Parameters
    ----------
    cost : float
        The refined path's cost after the level just run.
    target : float
        The cost to beat.
    gain : float
        The largest gain of one level so far (0: no level has gained).
    remaining : int
        Levels left in the cycle.

    Returns
    -------
    bool
        True when ``cost - remaining * gain >= target``.
    """
    return cost - remaining * gain >= target
