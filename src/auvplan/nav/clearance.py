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
Charted no-go zones (:mod:`auvplan.world.zones`, unpadded) by :func:`zone_within`: a leg is not clear when a point
of a prism lies within ``r`` horizontally of the leg at the leg's own depth — for a band between two depths exactly
(the sub-segment whose depth is in the band, its horizontal trace's distance to the footprint at most ``r``), for a
band from the seabed up to ``h`` on the safe side (the trace within ``r`` of the footprint and the leg's least
altitude within ``r``, :func:`leg_slack` over the whole stadium, at most ``h``).
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import ArrayLike

from .._types import BoolArray, FloatArray
from ..runtime.jit import kernel
from ..world import World
from ..world.terrain import Terrain, elevation_kernel

__all__ = ["lattice_step", "leg_slack", "safe_radius", "pieces", "leg_uncertain_altitude", "uncertain_clearance",
           "zone_within", "zone_safe_radius", "obstacle_within", "obstacle_safe_radius", "hazard_safe_radius"]

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


@kernel
def _slacks(coef: FloatArray, x0: float, y0: float, dx: float, dy: float, pa: FloatArray, pb: FloatArray,
            rr: FloatArray, h: float, lip: float) -> FloatArray:
    """:func:`_slack` of each segment ``pa[k] → pb[k]`` at radius ``rr[k]``."""
    out = np.empty(pa.shape[0])
    for k in range(pa.shape[0]):
        out[k] = _slack(coef, x0, y0, dx, dy, pa[k, 0], pa[k, 1], pa[k, 2], pb[k, 0], pb[k, 1], pb[k, 2], rr[k], h,
                        lip)
    return out


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
    pa = np.ascontiguousarray(np.atleast_2d(np.asarray(a, dtype=float))[:, :3])
    pb = np.ascontiguousarray(np.atleast_2d(np.asarray(b, dtype=float))[:, :3])
    rr = np.ascontiguousarray(np.broadcast_to(np.asarray(r, dtype=float), (pa.shape[0],)))
    step = lattice_step(terrain) if h is None else float(h)
    coef, x0, y0, dx, dy, _ = terrain.kernel_data
    out: FloatArray = _slacks(coef, x0, y0, dx, dy, pa, pb, rr, step, float(terrain.max_slope))
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


def leg_uncertain_altitude(world: World, points: ArrayLike, radius: ArrayLike, step: float,
                           piece_radius: ArrayLike | None = None) -> FloatArray:
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
    piece_radius : array_like, optional
        ``(K,)`` the uncertainty of each piece of :func:`pieces` (its largest, at its end: the budget's
        ``piece_error_m``); default: its leg's ``radius``.

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
    r = np.asarray(radius, dtype=float)[leg] if piece_radius is None else np.asarray(piece_radius, dtype=float)
    np.minimum.at(out, leg, leg_slack(world.terrain, a, b, r))
    return out


def uncertain_clearance(world: World, points: ArrayLike, radius: ArrayLike, step: float,
                        piece_radius: ArrayLike | None = None) -> tuple[FloatArray, BoolArray]:
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
    piece_radius : array_like, optional
        ``(K,)`` the uncertainty of each piece of :func:`pieces` (``step`` long at most), its largest: each piece is
        tested under its own (the seabed, the obstacles and the zones); default: every piece under its leg's ``radius``.

    Returns
    -------
    altitude : numpy.ndarray
        ``(N - 1,)`` :func:`leg_uncertain_altitude` (m).
    clear : numpy.ndarray of bool
        ``(N - 1,)`` altitude ≥ ``min_altitude`` and no static obstacle within its margin plus the radius.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    r = np.asarray(radius, dtype=float)
    alt = leg_uncertain_altitude(world, p, r, step, piece_radius)
    ok = alt >= world.margins.min_altitude
    if piece_radius is None:
        seg, rr, leg = np.stack([p[:-1], p[1:]], axis=1), r, np.arange(r.size)
    else:
        a, b, leg = pieces(p, step)
        seg, rr = np.stack([a, b], axis=1), np.asarray(piece_radius, dtype=float)
    for within in ((obstacle_within,) if world.obstacles else ()) + ((zone_within,) if world.zones else ()):
        near = np.flatnonzero(ok[leg])  # the pieces of the legs still clear
        if near.size:
            hit = within(world, seg[near], rr[near]) >= 0
            ok[leg[near[hit]]] = False
    return alt, ok


def _band_trace(a: FloatArray, b: FloatArray, lo: float, hi: float) -> shapely.Geometry | None:
    """The horizontal trace of the part of segment ``a → b`` whose depth lies in ``[lo, hi]`` (z linear along it)."""
    dz = b[2] - a[2]
    if dz == 0.0:
        t0, t1 = (0.0, 1.0) if lo <= a[2] <= hi else (1.0, 0.0)
    else:
        ta, tb = (lo - a[2]) / dz, (hi - a[2]) / dz
        t0, t1 = max(min(ta, tb), 0.0), min(max(ta, tb), 1.0)
    if t0 > t1:
        return None
    p0, p1 = a[:2] + t0 * (b[:2] - a[:2]), a[:2] + t1 * (b[:2] - a[:2])
    return shapely.linestrings([p0, p1]) if t1 > t0 else shapely.points(p0)


def zone_within(world: World, segments: ArrayLike, radius: ArrayLike) -> np.ndarray:
    """The first charted no-go zone within each segment's horizontal uncertainty (module notes), ``-1`` for none.

    Parameters
    ----------
    world : World
        Its zones (unpadded: :attr:`~auvplan.world.zones.Zones.exact`) and, for seabed bands, its terrain.
    segments : array_like
        ``(K, 2, 3)`` the legs (m).
    radius : array_like
        ``(K,)`` or scalar horizontal uncertainty of each (m).

    Returns
    -------
    numpy.ndarray of int
        ``(K,)`` the index of a zone (``world.zones.zones``) a point of whose prism lies within the radius of the
        segment at its depth; ``-1`` where none does.
    """
    seg = np.asarray(segments, dtype=float).reshape(-1, 2, 3)
    r = np.broadcast_to(np.asarray(radius, dtype=float), (seg.shape[0],))
    out = np.full(seg.shape[0], -1, dtype=np.intp)
    if not world.zones or seg.shape[0] == 0:
        return out
    specs = world.zones.exact.zones
    ks, js = world.zones.exact.traces_near(seg, r)  # the broad phase: the footprints within reach
    hit = np.zeros(ks.size, dtype=bool)
    seabed = np.array([specs[j].above_seabed is not None for j in js.tolist()], dtype=bool)
    if seabed.any() and world.terrain is not None:  # the band's top within reach: the highest seabed within r + height
        k = ks[seabed]
        height = np.array([specs[j].above_seabed for j in js[seabed].tolist()], dtype=float)
        hit[seabed] = leg_slack(world.terrain, seg[k, 0], seg[k, 1], r[k]) <= height
    flat = np.flatnonzero(~seabed)
    if flat.size:  # a band between two depths: the part of the leg in the band within reach of the footprint
        parts = [_band_trace(seg[ks[i], 0], seg[ks[i], 1], -specs[js[i]].bottom, -specs[js[i]].top) for i in flat]
        inside = np.array([p is not None for p in parts], dtype=bool)
        idx = flat[inside]
        if idx.size:
            feet = [specs[j].footprint for j in js[idx].tolist()]
            hit[idx] = shapely.distance(np.array([p for p in parts if p is not None], dtype=object),
                                        np.array(feet, dtype=object)) <= r[ks[idx]]
    first = np.flatnonzero(hit)  # each leg's first zone within reach, in the broad phase's order
    legs, at = np.unique(ks[first], return_index=True)
    out[legs] = js[first[at]]
    return out


def zone_safe_radius(world: World, a: ArrayLike, b: ArrayLike, r_max: float, tol: float = 0.5) -> FloatArray:
    """The largest horizontal uncertainty each segment allows near the charted zones (the inverse of
    :func:`zone_within`): for a band between two depths the distance from the part of the segment in the band to the
    footprint, less a micrometre; for a seabed band by bisection over the radii that reach the footprint from the
    segment's trace (within ``tol`` below the least radius at which both the footprint and the band are within reach).

    Parameters
    ----------
    world : World
        Its zones and terrain.
    a, b : array_like
        ``(K, 3)`` the segments' ends (m).
    r_max : float
        Largest radius looked at (m): a segment with no zone within it gets ``inf``.
    tol : float, optional
        Bisection tolerance (m; the radius returned is on the safe side).

    Returns
    -------
    numpy.ndarray
        ``(K,)`` (m): :func:`zone_within` finds no zone for any radius up to it.
    """
    seg = np.stack([np.atleast_2d(np.asarray(a, dtype=float)), np.atleast_2d(np.asarray(b, dtype=float))], axis=1)
    out = np.full(seg.shape[0], np.inf)
    if not world.zones or seg.shape[0] == 0:
        return out
    specs = world.zones.exact.zones
    ks, js = world.zones.exact.traces_near(seg, r_max)
    for k, j in zip(ks.tolist(), js.tolist(), strict=True):
        z, p, q = specs[j], seg[k, 0], seg[k, 1]
        if z.above_seabed is None:
            part = _band_trace(p, q, -z.bottom, -z.top)
            r = math.inf if part is None else float(shapely.distance(part, z.footprint)) * (1.0 - 1e-12) - 1e-6
        else:  # zone_within's test: the footprint within x of the trace and the leg's least altitude within x
            reach = float(shapely.distance(shapely.linestrings([p[:2], q[:2]]), z.footprint))

            def hit(x: float, p: FloatArray = p, q: FloatArray = q, h: float = z.above_seabed,
                    reach: float = reach) -> bool:
                return (x >= reach and world.terrain is not None
                        and float(leg_slack(world.terrain, p, q, x)[0]) <= h)
            if not hit(r_max):
                continue
            lo, hi = 0.0, r_max
            while hi - lo > tol and not hit(0.0):  # (in the band's reach on the line itself: no radius is safe)
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if hit(mid) else (mid, hi)
            r = lo
        out[k] = min(out[k], max(r, 0.0))
    return out


def obstacle_within(world: World, segments: ArrayLike, radius: ArrayLike) -> np.ndarray:
    """The first static obstacle within each segment's obstacle margin plus its horizontal uncertainty, ``-1`` for
    none (each shape's exact segment test at ``margin + r``: a ball of radius ``r`` contains the horizontal disc).

    Parameters
    ----------
    world : World
        Its static obstacles and margins.
    segments : array_like
        ``(K, 2, 3)`` the legs (m).
    radius : array_like
        ``(K,)`` or scalar horizontal uncertainty of each (m).

    Returns
    -------
    numpy.ndarray of int
        ``(K,)`` the index of an obstacle (``world.obstacles``) within the margin plus the radius; ``-1`` where none.
    """
    seg = np.asarray(segments, dtype=float).reshape(-1, 2, 3)
    r = np.broadcast_to(np.asarray(radius, dtype=float), (seg.shape[0],))
    out = np.full(seg.shape[0], -1, dtype=np.intp)
    for j, shape in enumerate(world.obstacles):
        k = np.flatnonzero(out < 0)
        out[k[shape.segments_hit(seg[k], world.margins.obstacle + r[k])]] = j
    return out


def obstacle_safe_radius(world: World, a: ArrayLike, b: ArrayLike, r_max: float) -> FloatArray:
    """The largest horizontal uncertainty each segment allows near the static obstacles (the inverse of
    :func:`obstacle_within`): the least distance of the segment to each obstacle's surface
    (:meth:`~auvplan.world.obstacles.Sphere.segment_distance`, the figure its exact segment test compares with the
    margin) less the margin, less a micrometre.

    Parameters
    ----------
    world : World
        Its static obstacles and margins.
    a, b : array_like
        ``(K, 3)`` the segments' ends (m).
    r_max : float
        Largest radius looked at (m): a segment with no obstacle within it gets ``inf``.

    Returns
    -------
    numpy.ndarray
        ``(K,)`` (m): :func:`obstacle_within` finds no obstacle for any radius up to it; 0 when not even ``r = 0``.
    """
    seg = np.stack([np.atleast_2d(np.asarray(a, dtype=float)), np.atleast_2d(np.asarray(b, dtype=float))], axis=1)
    out = np.full(seg.shape[0], np.inf)
    for shape in world.obstacles:
        near = shape.segments_hit(seg, world.margins.obstacle + float(r_max))  # the broad phase: within reach
        if near.any():
            gap = shape.segment_distance(seg[near]) - world.margins.obstacle
            out[near] = np.minimum(out[near], np.maximum(gap * (1.0 - 1e-12) - 1e-6, 0.0))
    return out


def hazard_safe_radius(world: World, a: ArrayLike, b: ArrayLike, r_max: float) -> FloatArray:
    """The largest horizontal uncertainty each segment allows: the least of the seabed's (:func:`safe_radius`),
    the charted zones' (:func:`zone_safe_radius`) and the static obstacles' (:func:`obstacle_safe_radius`) — every
    hazard :func:`uncertain_clearance` tests under the error (the fix planner's safe radius).

    Parameters
    ----------
    world : World
        Seabed, zones, static obstacles and margins.
    a, b : array_like
        ``(K, 3)`` the segments' ends (m).
    r_max : float
        Largest radius looked at (m): a segment clear of every hazard within it gets ``inf``.

    Returns
    -------
    numpy.ndarray
        ``(K,)`` (m).
    """
    pa, pb = np.atleast_2d(np.asarray(a, dtype=float)), np.atleast_2d(np.asarray(b, dtype=float))
    out = np.full(pa.shape[0], np.inf)
    if world.terrain is not None:
        out = safe_radius(world.terrain, pa, pb, world.margins.min_altitude, r_max)
    if world.zones:
        out = np.minimum(out, zone_safe_radius(world, pa, pb, r_max))
    if world.obstacles:
        out = np.minimum(out, obstacle_safe_radius(world, pa, pb, r_max))
    return out
