"""A turn-limited path along a flow's direction field: the path a vehicle flies that steers by the flow.

:func:`turn_limited_path` integrates a vehicle whose heading command is the flow direction at its
position, at constant step ``h``, turning by at most ``h / R`` per step (R the vehicle's turn radius),
so every turn between two steps is at most the vehicle's own turn over that step (local radius ≥ R).
Every leg is checked by the caller's exact test; where the vehicle cannot follow the flow within the
clearance (a start 0.5 m from a surface facing it), the path stops there and says so (``unflyable``),
instead of turning a corner the vehicle cannot fly.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..._types import ArrayLike, BoolArray, FloatArray

__all__ = ["TurnLimited", "turn_limited_path"]


@dataclass(frozen=True, eq=False)
class TurnLimited:
    """A turn-limited path and how it ended.

    Parameters
    ----------
    path : numpy.ndarray
        ``(N, 3)`` polyline (m), from the start; ends at the goal when ``status == "arrived"``.
    status : str
        ``"arrived"``, ``"unflyable"`` (the next leg failed the exact test) or ``"max_steps"``.
    max_turn_deg : float
        Largest turn between two consecutive steps before the arrival leg (deg).
    """

    path: FloatArray
    status: str
    max_turn_deg: float


def _turn_towards(d: FloatArray, u: FloatArray, limit: float) -> FloatArray:
    """Unit ``d`` turned towards unit ``u`` in their common plane by at most ``limit`` rad."""
    c = float(np.clip(d @ u, -1.0, 1.0))
    angle = float(np.arccos(c))
    if angle <= limit:
        return u
    side = u - c * d
    n = float(np.linalg.norm(side))
    if n < 1e-12:  # u opposite d: any perpendicular; take the one closest to the horizontal plane's
        side = np.cross(d, [0.0, 0.0, 1.0])
        if np.linalg.norm(side) < 1e-12:
            side = np.cross(d, [1.0, 0.0, 0.0])
        n = float(np.linalg.norm(side))
    out: FloatArray = np.cos(limit) * d + np.sin(limit) * side / n
    return out


def turn_limited_path(direction: Callable[[FloatArray], FloatArray], start: ArrayLike, goal: ArrayLike,
                      radius: float, step: float, arrive: float, free: Callable[[FloatArray, FloatArray], bool],
                      max_steps: int = 20000, heading: ArrayLike | None = None) -> TurnLimited:
    """Fly a vehicle that steers along ``direction`` with a turn radius of at least ``radius``.

    Parameters
    ----------
    direction : callable
        ``direction(x (3,)) -> (3,)`` the flow's direction at ``x`` (need not be unit).
    start, goal : array_like
        End points ``(3,)`` (m).
    radius : float
        Least turn radius R (m): the heading turns by at most ``step / radius`` per step.
    step : float
        Step length h (m).
    arrive : float
        Arrival radius about the goal (m); the last leg goes straight to the goal.
    free : callable
        ``free(a, b) -> bool``: whether the leg a-b passes the exact test (margins included).
    max_steps : int, optional
        Step limit.
    heading : array_like, optional
        Initial heading ``(3,)``; the flow's direction at the start by default.

    Returns
    -------
    TurnLimited
        The path, its status and the largest turn between steps.
    """
    x = np.asarray(start, dtype=float).copy()
    g = np.asarray(goal, dtype=float)
    d = np.asarray(direction(x) if heading is None else heading, dtype=float)
    d = d / np.linalg.norm(d)
    limit = step / radius
    pts = [x.copy()]
    worst = 0.0
    for _ in range(max_steps):
        if np.linalg.norm(g - x) <= max(arrive, step):
            if not free(x, g):
                return TurnLimited(np.array(pts), "unflyable", np.degrees(worst))
            pts.append(g.copy())
            return TurnLimited(np.array(pts), "arrived", np.degrees(worst))
        u = np.asarray(direction(x), dtype=float)
        nu = float(np.linalg.norm(u))
        new = _turn_towards(d, u / nu, limit) if nu > 0 else d
        if len(pts) > 1:
            worst = max(worst, float(np.arccos(np.clip(new @ d, -1.0, 1.0))))
        d = new
        y = x + step * d
        if not free(x, y):
            return TurnLimited(np.array(pts), "unflyable", np.degrees(worst))
        x = y
        pts.append(x.copy())
    return TurnLimited(np.array(pts), "max_steps", np.degrees(worst))


def flyable_path(velocity: Callable[[FloatArray], FloatArray], segments_free: Callable[[FloatArray], BoolArray],
                 start: ArrayLike, goal: ArrayLike, radius: float, arrive: float) -> TurnLimited:
    """The turn-limited path of a vehicle with turn radius ``radius`` steering by a flow field.

    Steps of ``radius / 20`` (a turn of at most 2.9° a step), every leg checked by ``segments_free``
    (the World's exact segment test), at most three times the straight distance in steps plus 2 000.

    Parameters
    ----------
    velocity : callable
        ``velocity(x (N, 3)) -> (N, 3)`` the flow (e.g. :meth:`FlowField.velocity`).
    segments_free : callable
        ``segments_free(seg (N, 2, 3)) -> (N,) bool`` (e.g. ``World.segments_free`` of static obstacles).
    start, goal : array_like
        End points ``(3,)`` (m).
    radius : float
        The vehicle's turn radius (m), > 0.
    arrive : float
        Arrival radius (m).

    Returns
    -------
    TurnLimited
        See :func:`turn_limited_path`.
    """
    a, b = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    step = radius / 20.0
    n = int(3.0 * np.linalg.norm(b - a) / step) + 2000
    return turn_limited_path(lambda x: velocity(x[None])[0], a, b, radius, step, arrive,
                             lambda p, q: bool(segments_free(np.stack([p, q])[None])[0]), n)
