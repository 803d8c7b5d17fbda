"""Refining a backtracked flight by Zermelo's heading equation (shooting from its first heading).

In a current ``c(x, y, t) = (u, v)`` the heading θ (mathematical angle) of a time-optimal flight at
through-water speed V obeys Zermelo's navigation equation (Zermelo 1931; Bryson and Ho 1975, §2.7)

    ẋ = V cos θ + u,   ẏ = V sin θ + v,
    θ̇ = sin²θ ∂v/∂x + sin θ cos θ (∂u/∂x − ∂v/∂y) − cos²θ ∂u/∂y,

in a current that changes with time too.  An extremal is fixed by its first heading θ₀: the
shooting integrates it (RK4 through the grid's current table, :func:`.front_kernels.shoot`) from
headings about the backtracked one (:func:`.front.backtrack`), takes the closest approach to the goal
within a little more than the front's arrival time, and minimises that miss over θ₀ (Brent's
bounded method to 10⁻⁹ rad).  The extremal through the goal is the refined flight; in a current
uniform in space θ̇ = 0 and it is the exact constant heading of the least time.  The caller keeps it
only when, flown through the World's current, it beats the backtracked flight and passes the exact
segment test.
"""

from __future__ import annotations

import math

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...optim.bounded_min import bounded_min
from .front import FrontGrid
from .front_kernels import shoot

__all__ = ["closest_approach", "refine_shot"]


def closest_approach(track: FloatArray, goal: FloatArray) -> tuple[float, int, float]:
    """Closest approach of a sampled track to a point.

    Parameters
    ----------
    track : numpy.ndarray
        ``(n, 2+)`` positions at equal time steps (m).
    goal : numpy.ndarray
        ``(2,)`` the point (m).

    Returns
    -------
    distance : float
        Least distance from the point to the polyline (m).
    index : int
        The segment it lies on.
    fraction : float
        Where on the segment, in ``[0, 1]``.
    """
    a, b = track[:-1, :2], track[1:, :2]
    d = b - a
    L2 = np.maximum((d * d).sum(axis=1), 1e-300)
    f = np.clip(((goal - a) * d).sum(axis=1) / L2, 0.0, 1.0)
    dist = np.hypot(*(a + f[:, None] * d - goal).T)
    i = int(np.argmin(dist))
    return float(dist[i]), i, float(f[i])


def refine_shot(grid: FrontGrid, start: ArrayLike, goal: ArrayLike, depart: float, speed: float, theta: float,
                t_window: float, step: float, spread: float = math.radians(30.0),
                tol: float | None = None) -> tuple[FloatArray, FloatArray, FloatArray] | None:
    """The extremal through the goal nearest the backtracked first heading (module notes).

    Parameters
    ----------
    grid : FrontGrid
        Grid and current table.
    start, goal : array_like
        End points (m; x and y used).
    depart : float
        Departure time (s).
    speed : float
        Through-water speed V (m/s).
    theta : float
        Backtracked first heading (mathematical angle, rad).
    t_window : float
        Latest time the extremal may pass the goal (s).
    step : float
        RK4 step (s).
    spread : float, default 30°
        Headings tried on either side of ``theta`` (rad).
    tol : float, optional
        Largest miss accepted (m; default a twentieth of a cell).

    Returns
    -------
    tuple or None
        ``(points (M, 2), times (M,), headings (M,))`` from the start to the goal, or None when no
        extremal passes within ``tol``.
    """
    s, q = np.asarray(start, dtype=float)[:2], np.asarray(goal, dtype=float)[:2]
    n = max(int(math.ceil((t_window - depart) / step)), 2) + 1
    out = np.empty((n, 3))
    args = grid.table_args()
    tol = 0.05 * grid.h if tol is None else tol

    def miss(th0: float) -> float:
        shoot(*args, s[0], s[1], th0, depart, step, speed, out)
        return closest_approach(out, q)[0]

    cands = theta + np.linspace(-spread, spread, 61)
    vals = np.array([miss(c) for c in cands])
    i = int(np.argmin(vals))
    d = cands[1] - cands[0]
    best, _, _ = bounded_min(miss, cands[i] - d, cands[i] + d, xatol=1e-9)  # SciPy's bounded Brent, bit for bit
    if miss(best) > tol:
        return None
    shoot(*args, s[0], s[1], best, depart, step, speed, out)
    _, k, f = closest_approach(out, q)
    pts = np.vstack([out[:k + 1, :2], q])
    times = np.append(depart + step * np.arange(k + 1), depart + step * (k + f))
    heads = np.append(out[:k + 1, 2], out[k, 2])
    return pts, times, heads
