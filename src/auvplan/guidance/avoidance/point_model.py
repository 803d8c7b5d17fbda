"""Document 004's point model: a point stepping along the APF force among static obstacles, escaping
local minima toward random sub-goals (:mod:`.local` holds the force, the minimum detector and the
vehicle's avoidance).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._types import RngLike, Status, as_rng
from ...world import World
from .local import AvoidanceParams, MinimumDetector, _random_free_point, apf_force

__all__ = ["PointModelResult", "run_point_model"]

_F64 = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class PointModelResult:
    """Track of document 004's point model: status, points, escapes and local minima found.

    Attributes
    ----------
    status : Status
        ``EXACT`` at the goal, ``DEADLOCK`` trapped without escapes, ``TIMEOUT`` out of steps.
    points : numpy.ndarray
        ``(N, 3)`` the points visited (m).
    escapes : int
        Escapes toward random sub-goals.
    minima : int
        Local minima detected.
    """

    status: Status
    points: _F64
    escapes: int
    minima: int


def run_point_model(world: World, start: ArrayLike, goal: ArrayLike, params: AvoidanceParams, step: float = 1.0,
                    max_steps: int = 5000, rng: RngLike = None, escape: bool = True) -> PointModelResult:
    """Run document 004's point model among the World's static obstacles: p₁ = p + l F/|F|.

    With ``escape=False`` it is plain APF, which stalls in a local minimum (status ``DEADLOCK``).

    Parameters
    ----------
    world : World
        Static obstacles (and seabed, for the step's collision test).
    start, goal : array_like
        ``(3,)`` start and goal (m).
    params : AvoidanceParams
        The APF's parameters.
    step : float, optional
        Step length l (m).
    max_steps : int, optional
        Steps before ``TIMEOUT``.
    rng : RngLike, optional
        Seed or generator of the escapes.
    escape : bool, optional
        Escape local minima toward random sub-goals (document 004); False: plain APF.

    Returns
    -------
    PointModelResult
        Status, visited points, escapes and minima.
    """
    rng = as_rng(rng)
    p = np.asarray(start, dtype=float)
    g = np.asarray(goal, dtype=float)
    det = MinimumDetector(params.minimum_radius, params.minimum_count, 1.0)
    pts = [p.copy()]
    sub = None
    escapes = minima = 0
    centers = np.array([s.center for s in world.obstacles]).reshape(-1, 3)
    for k in range(max_steps):
        target = sub if sub is not None else g
        if np.linalg.norm(g - p) <= params.arrive:
            return PointModelResult(Status.EXACT, np.asarray(pts), escapes, minima)
        if sub is not None and np.linalg.norm(sub - p) <= params.arrive:
            sub = None
            det.reset()
            continue
        if det.update(p, float(k)):
            minima += 1
            if not escape:
                return PointModelResult(Status.DEADLOCK, np.asarray(pts), escapes, minima)
            sub = _random_free_point(world, p, params.escape_radius, 0.0, rng)
            escapes += sub is not None
            det.reset()
            target = sub if sub is not None else g
        p = _apf_step(world, p, target, centers, params, step, rng)
        pts.append(p.copy())
    return PointModelResult(Status.TIMEOUT, np.asarray(pts), escapes, minima)


def _apf_step(world: World, p: np.ndarray, target: np.ndarray, centers: np.ndarray, params: AvoidanceParams,
              step: float, rng: np.random.Generator) -> np.ndarray:
    """One step ``l`` along the APF's force from ``p``; a random one where that meets an obstacle or the seabed,
    none where that does too (never a step through anything)."""
    d = np.array([s.distance(p).item() for s in world.obstacles])
    f = apf_force(p, target, centers, d, params)
    n = np.linalg.norm(f)
    nxt = p + step * f / n if n > 0 else p
    if not world.segments_free(np.stack([p, nxt])[None], moving=False)[0]:
        nxt = p + step * rng.normal(size=3) * np.array([1, 1, 0.2])  # never step through anything
        if not world.segments_free(np.stack([p, nxt])[None], moving=False)[0]:
            nxt = p
    return nxt
