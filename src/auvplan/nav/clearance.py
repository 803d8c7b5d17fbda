"""Clearance under navigation uncertainty: the seabed and the obstacles within the horizontal error of a leg.

The vehicle's true horizontal position lies within ``r = confidence × σ`` of where it believes it is
(its depth is measured, so the uncertainty is horizontal only).  On a leg ``p(t) = a + t (b − a)`` the
vehicle believed at ``p(t)`` may be anywhere over the disc of radius ``r`` round it, so the leg is clear when

    min over t, |q − p(t)| ≤ r of  z(t) − zb(q)  ≥ min_altitude.

For a seabed point ``q`` of the stadium (the segment buffered by ``r``) the binding depth is the deepest
``z(t)`` among the ``t`` whose disc holds ``q``: an interval of ``t`` (exact, from the projection of ``q``
on the leg), at one of whose ends the linear ``z`` is least.  The minimum over the stadium is taken on a
lattice of spacing ``h`` (default a fiftieth of a terrain cell) over the stadium grown by ``h/√2``, each
node's interval taken for the grown radius ``r + h/√2`` (a superset of its neighbours' intervals), less
the seabed's Lipschitz bound ``L h/√2`` (:attr:`Terrain.max_slope`): every point of the stadium lies
within ``h/√2`` of a node, so the result never exceeds the true least altitude, and it is below it by
at most ``2 L h`` plus what the grown radius adds.  ``tests/oracles/test_nav.py`` compares it with an
independent brute-force sampling.  :func:`safe_radius` is its inverse (bisection on ``r``: the least
altitude only falls as ``r`` grows).  Static obstacles are tested with their exact segment test at the
margin plus ``r`` (a ball of radius ``r`` contains the horizontal disc: this errs only on the safe side).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from .._types import BoolArray, FloatArray
from ..runtime.jit import kernel
from ..world import World
from ..world.terrain import Terrain, elevation_kernel

__all__ = ["lattice_step", "leg_slack", "safe_radius", "pieces", "leg_uncertain_altitude", "uncertain_clearance"]

_MAX_NODES = 50_000_000
"""Most lattice nodes one test may visit; beyond it the test refuses the leg (-inf)."""

_HALF_DIAG = 0.7071067811865476


@kernel
def _slack(coef: FloatArray, x0: float, y0: float, dx: float, dy: float, ax: float, ay: float, az: float, bx: float,
           by: float, bz: float, r: float, h: float, lip: float) -> float:
    """Least ``z(t) − zb(q)`` over the stadium of radius ``r`` (a lower bound, see the module docstring)."""
    ux, uy = bx - ax, by - ay
    ll = ux * ux + uy * uy
    reach = r + h * _HALF_DIAG
    i0, i1 = math.floor((min(ax, bx) - reach) / h), math.ceil((max(ax, bx) + reach) / h)
    j0, j1 = math.floor((min(ay, by) - reach) / h), math.ceil((max(ay, by) + reach) / h)
    if (i1 - i0 + 1) * (j1 - j0 + 1) > _MAX_NODES:
        return -math.inf
    best = math.inf
    for j in range(j0, j1 + 1):
        qy = j * h
        for i in range(i0, i1 + 1):
            qx = i * h
            tl = 0.0 if ll == 0.0 else ((qx - ax) * ux + (qy - ay) * uy) / ll
            tc = min(max(tl, 0.0), 1.0)
            if math.hypot(ax + tc * ux - qx, ay + tc * uy - qy) > reach:
                continue
            if ll == 0.0:
                t1 = t2 = 0.0
            else:
                perp = math.hypot(ax + tl * ux - qx, ay + tl * uy - qy)
                half = math.sqrt(max(reach * reach - perp * perp, 0.0) / ll)
                t1, t2 = max(tl - half, 0.0), min(tl + half, 1.0)
            z = min(az + t1 * (bz - az), az + t2 * (bz - az))
            best = min(best, z - elevation_kernel(coef, x0, y0, dx, dy, qx, qy))
    return best - lip * h * _HALF_DIAG


def lattice_step(terrain: Terrain) -> float:
    """Default lattice spacing of the stadium test: a fiftieth of the smaller cell side (m).

    Parameters
    ----------
    terrain : Terrain
        The seabed.

    Returns
    -------
    float
        ``h`` (m).
    """
    return min(terrain.dx, terrain.dy) / 50.0


def leg_slack(terrain: Terrain, a: ArrayLike, b: ArrayLike, r: ArrayLike, h: float | None = None) -> FloatArray:
    """Least altitude of each segment over the highest seabed within horizontal distance ``r`` (a lower bound).

    Parameters
    ----------
    terrain : Terrain
        The seabed.
    a, b : array_like
        ``(K, 3)`` the segments' ends (m).
    r : array_like
        ``(K,)`` or scalar radius (m, ≥ 0).
    h : float, optional
        Lattice spacing (m; :func:`lattice_step` by default).

    Returns
    -------
    numpy.ndarray
        ``(K,)`` (m): never above ``min z(t) − zb(q)`` over the stadium.
    """
    pa, pb = np.atleast_2d(np.asarray(a, dtype=float)), np.atleast_2d(np.asarray(b, dtype=float))
    rr = np.broadcast_to(np.asarray(r, dtype=float), (pa.shape[0],))
    step = lattice_step(terrain) if h is None else float(h)
    coef, x0, y0, dx, dy, _ = terrain.kernel_data
    lip = terrain.max_slope
    out = np.empty(pa.shape[0])
    for k in range(pa.shape[0]):
        (ax, ay, az), (bx, by, bz) = pa[k, :3], pb[k, :3]
        out[k] = _slack(coef, x0, y0, dx, dy, ax, ay, az, bx, by, bz, float(rr[k]), step, lip)
    return out


def safe_radius(terrain: Terrain, a: ArrayLike, b: ArrayLike, min_altitude: float, r_max: float,
                h: float | None = None, tol: float = 0.5) -> FloatArray:
    """The largest horizontal uncertainty each segment allows (the inverse of :func:`leg_slack`, by bisection).

    Parameters
    ----------
    terrain : Terrain
        The seabed.
    a, b : array_like
        ``(K, 3)`` the segments' ends (m).
    min_altitude : float
        The altitude to keep (m).
    r_max : float
        Largest radius looked at (m): a segment clear at ``r_max`` gets ``inf``.
    h : float, optional
        Lattice spacing (m).
    tol : float, optional
        Bisection tolerance (m); the radius returned is on the safe side.

    Returns
    -------
    numpy.ndarray
        ``(K,)`` (m): ``leg_slack(r) ≥ min_altitude`` for ``r ≤ safe_radius``; 0 when not even ``r = 0``.
    """
    pa, pb = np.atleast_2d(np.asarray(a, dtype=float)), np.atleast_2d(np.asarray(b, dtype=float))
    step = lattice_step(terrain) if h is None else float(h)
    coef, x0, y0, dx, dy, _ = terrain.kernel_data
    lip = terrain.max_slope
    out = np.empty(pa.shape[0])
    for k in range(pa.shape[0]):
        (ax, ay, az), (bx, by, bz) = pa[k, :3], pb[k, :3]

        def clear(r: float, ax: float = ax, ay: float = ay, az: float = az, bx: float = bx, by: float = by,
                  bz: float = bz) -> bool:
            return bool(_slack(coef, x0, y0, dx, dy, ax, ay, az, bx, by, bz, r, step, lip) >= min_altitude)
        if clear(r_max):
            out[k] = math.inf
            continue
        lo, hi = 0.0, r_max
        if not clear(0.0):
            out[k] = 0.0
            continue
        while hi - lo > tol:
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if clear(mid) else (lo, mid)
        out[k] = lo
    return out


def pieces(points: ArrayLike, step: float) -> tuple[FloatArray, FloatArray, np.ndarray]:
    """Cut a polyline's legs into pieces no longer than ``step`` horizontally.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` vertices (m).
    step : float
        Longest horizontal piece (m).

    Returns
    -------
    a, b : numpy.ndarray
        ``(K, 3)`` the pieces' ends.
    leg : numpy.ndarray of int
        ``(K,)`` the leg of each piece.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    h = np.hypot(*np.diff(p[:, :2], axis=0).T)
    n = np.maximum(np.ceil(h / step), 1).astype(int)
    leg = np.repeat(np.arange(len(n)), n)
    k = np.arange(leg.size) - np.repeat(np.cumsum(n) - n, n)
    f0, f1 = (k / n[leg])[:, None], ((k + 1) / n[leg])[:, None]
    d = p[1:] - p[:-1]
    return p[leg] + f0 * d[leg], p[leg] + f1 * d[leg], leg


def leg_uncertain_altitude(world: World, points: ArrayLike, radius: ArrayLike, step: float) -> FloatArray:
    """Least altitude of each leg above the highest seabed within its horizontal uncertainty.

    Parameters
    ----------
    world : World
        The seabed (``+inf`` without one).
    points : array_like
        ``(N, 3)`` the mission's waypoints (m).
    radius : array_like
        ``(N - 1,)`` the horizontal uncertainty of each leg (confidence × σ, its largest on the leg; m).
    step : float
        Longest piece (m).

    Returns
    -------
    numpy.ndarray
        ``(N - 1,)`` (m): :func:`leg_slack` least over each leg's pieces; compare with ``min_altitude``.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.full(max(p.shape[0] - 1, 0), np.inf)
    if world.terrain is None or out.size == 0:
        return out
    a, b, leg = pieces(p, step)
    np.minimum.at(out, leg, leg_slack(world.terrain, a, b, np.asarray(radius, dtype=float)[leg]))
    return out


def uncertain_clearance(world: World, points: ArrayLike, radius: ArrayLike, step: float) -> tuple[FloatArray,
                                                                                                   BoolArray]:
    """Each leg's least uncertain altitude and whether it is clear of the seabed and the static obstacles.

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    points : array_like
        ``(N, 3)`` waypoints (m).
    radius : array_like
        ``(N - 1,)`` horizontal uncertainty per leg (m).
    step : float
        Longest piece of the seabed test (m).

    Returns
    -------
    altitude : numpy.ndarray
        ``(N - 1,)`` :func:`leg_uncertain_altitude` (m).
    clear : numpy.ndarray of bool
        ``(N - 1,)`` altitude ≥ ``min_altitude`` and no static obstacle within its margin plus the radius.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    r = np.asarray(radius, dtype=float)
    alt = leg_uncertain_altitude(world, p, r, step)
    ok = alt >= world.margins.min_altitude
    seg = np.stack([p[:-1], p[1:]], axis=1)
    for shape in world.obstacles:
        for k in np.flatnonzero(ok):
            ok[k] = not bool(shape.segments_hit(seg[k:k + 1], world.margins.obstacle + float(r[k]))[0])
    return alt, ok
