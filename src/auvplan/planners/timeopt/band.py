"""Refinement of a timed path by the time-aware elastic band (step 4 of :mod:`.search`'s notes): the path resampled
coarse to fine, each vertex pulled towards its neighbours' midpoint or moved across the path, kept where the vehicle
reaches the next vertex earlier and both segments pass the World's exact test.
"""

from __future__ import annotations

import numpy as np

from ..._types import FloatArray, IntArray
from ...path import densify, polyline_length, resample_polyline
from ...world import World
from .kernels import two_legs
from .timed import CurrentTable, TimedPath, timed_traverse

__all__ = ["refine"]


def _normals(p: FloatArray, i: IntArray) -> tuple[FloatArray, FloatArray]:
    """Unit horizontal normal of the chord ``p[i+1] - p[i-1]`` and the vertical."""
    t = p[i + 1] - p[i - 1]
    n1 = np.column_stack([-t[:, 1], t[:, 0], np.zeros(len(i))])
    n1 /= np.maximum(np.linalg.norm(n1, axis=1, keepdims=True), 1e-12)
    return n1, np.broadcast_to(np.array([0.0, 0.0, 1.0]), n1.shape)


def refine(world: World, table: CurrentTable, path: TimedPath, cell: float, vstep: float, ds: float,
           iterations: int) -> TimedPath:
    """The time-aware elastic band of the module notes, coarse to fine.

    The path is resampled every 16, 8, 4, 2, 1 and 1/2 cells (levels longer than a quarter of the
    path skipped) and relaxed at each level with steps of that spacing, so that whole stretches
    move before the detail settles.

    Parameters
    ----------
    world : World
        The world of the exact segment tests.
    table : CurrentTable
        The time-varying current.
    path : TimedPath
        The path to improve.
    cell : float
        Lattice spacing (m).
    vstep : float
        Largest vertical move (m).
    ds : float
        Largest integration sub-step (m).
    iterations : int
        Sweeps per level (0 returns ``path``).

    Returns
    -------
    TimedPath
        A free path never arriving later than ``path``.
    """
    best = path
    total = float(polyline_length(path.points))
    if iterations == 0 or not np.isfinite(path.duration) or path.tail is not None:
        return path  # (the band times legs forward: a path with tail-first legs is kept as the lattice made it)
    for level in (16.0, 8.0, 4.0, 2.0, 1.0, 0.5):
        spacing = level * cell
        if spacing > 0.25 * total and level > 0.5:
            continue
        p = resample_polyline(best.points, spacing)
        if not world.path_free(p):
            p = densify(best.points, spacing)
        trial = _relax(world, table, timed_traverse(table, p, path.times[0], path.speed, ds), spacing,
                       min(vstep, spacing), ds, iterations)
        if trial.duration <= best.duration:
            best = trial
    return best


def _relax(world: World, table: CurrentTable, best: TimedPath, step: float, vstep: float, ds: float,
           iterations: int) -> TimedPath:
    """One level of the elastic band with moves of ``step`` across and ``vstep`` up/down."""
    p = best.points
    n = p.shape[0]
    if n < 3 or not np.isfinite(best.duration):
        return best
    alpha = np.full(n, 0.5)
    delta = np.full(n, 0.5 * step)
    dz = np.full(n, 0.5 * vstep)
    args = table.args()
    for _ in range(iterations):
        for parity in (1, 2):
            i = np.arange(parity, n - 1, 2)
            i = i[(alpha[i] > 1e-3) | (delta[i] > 1e-3 * step)]
            if i.size == 0:
                continue
            a, b, c = p[i - 1], p[i], p[i + 1]
            n1, n2 = _normals(p, i)
            d, e = delta[i, None], dz[i, None]
            cand = np.stack([b, b + alpha[i, None] * (0.5 * (a + c) - b), b + d * n1, b - d * n1, b + e * n2,
                             b - e * n2], axis=1)
            arr = np.empty(cand.shape[:2])
            two_legs(*args, np.ascontiguousarray(a), np.ascontiguousarray(cand), np.ascontiguousarray(c),
                     best.times[i - 1], best.speed, ds, arr)
            arr[:, 1:][arr[:, 1:] >= arr[:, :1] - 1e-9] = np.inf
            first = np.stack([np.broadcast_to(a[:, None], cand.shape), cand], axis=2)
            second = np.stack([cand, np.broadcast_to(c[:, None], cand.shape)], axis=2)
            free = world.segments_free(first, moving=False) & world.segments_free(second, moving=False)
            arr[:, 1:][~free[:, 1:]] = np.inf
            k = np.argmin(arr, axis=1)
            win = k > 0
            trial = p.copy()
            trial[i[win]] = cand[win, k[win]]
            timed = timed_traverse(table, trial, best.times[0], best.speed, ds)
            if win.any() and timed.times[-1] < best.times[-1]:
                p, best = trial, timed
            else:
                win[:] = False
            lose = i[~win]
            alpha[lose] *= 0.5
            delta[lose] *= 0.5
            dz[lose] *= 0.5
        if np.all(delta[1:-1] <= 1e-3 * step) and np.all(alpha[1:-1] <= 1e-3):
            break
    return best
