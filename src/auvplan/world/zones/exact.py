"""The zones' exact compiled tests (:mod:`auvplan.world.zones`): a segment against one prism with a flat band
(:func:`flat_hits_kernel`: the band cuts the segment, its trace against the footprint by two discs, two
capsules and at last the edges), and points' signed distances to the zones listed near them
(:func:`near_distance_kernel`)."""

from __future__ import annotations

import math

import numpy as np

from ..._types import BoolArray, FloatArray, IntArray
from ...runtime.jit import kernel

__all__: list[str] = []  # the kernels are the internals of auvplan.world.zones


@kernel
def _orient(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> float:
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


@kernel
def _on(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> bool:
    """Whether ``c``, collinear with ``a b``, lies on the closed segment."""
    return min(ax, bx) <= cx <= max(ax, bx) and min(ay, by) <= cy <= max(ay, by)


@kernel
def _segments_meet(ax: float, ay: float, bx: float, by: float, cx: float, cy: float, dx: float, dy: float) -> bool:
    """Whether the closed segments ``a b`` and ``c d`` share a point (orientation tests)."""
    o1, o2 = _orient(ax, ay, bx, by, cx, cy), _orient(ax, ay, bx, by, dx, dy)
    o3, o4 = _orient(cx, cy, dx, dy, ax, ay), _orient(cx, cy, dx, dy, bx, by)
    if ((o1 > 0 and o2 < 0) or (o1 < 0 and o2 > 0)) and ((o3 > 0 and o4 < 0) or (o3 < 0 and o4 > 0)):
        return True
    return ((o1 == 0 and _on(ax, ay, bx, by, cx, cy)) or (o2 == 0 and _on(ax, ay, bx, by, dx, dy))
            or (o3 == 0 and _on(cx, cy, dx, dy, ax, ay)) or (o4 == 0 and _on(cx, cy, dx, dy, bx, by)))


@kernel
def _meets_polygon(ax: float, ay: float, bx: float, by: float, k: int, xy: FloatArray, ring: IntArray,
                   rings: IntArray) -> bool:
    """Whether the closed segment ``a b`` meets the closed polygon ``k`` (its rings ``rings[k]:rings[k+1]``,
    each ring's closed vertex list ``xy[ring[r]:ring[r+1]]``): an edge crossed or touched, or ``a`` inside
    (even-odd rule over every ring, so holes are outside)."""
    inside = False
    xlo, xhi, ylo, yhi = min(ax, bx), max(ax, bx), min(ay, by), max(ay, by)
    for r in range(rings[k], rings[k + 1]):
        for v in range(ring[r], ring[r + 1] - 1):
            px, py, qx, qy = xy[v, 0], xy[v, 1], xy[v + 1, 0], xy[v + 1, 1]
            # the orientation tests only where the edge's box meets the segment's (else they cannot meet)
            if (min(px, qx) <= xhi and max(px, qx) >= xlo and min(py, qy) <= yhi and max(py, qy) >= ylo
                    and _segments_meet(ax, ay, bx, by, px, py, qx, qy)):
                return True
            if (py > ay) != (qy > ay) and ax < px + (ay - py) * (qx - px) / (qy - py):
                inside = not inside
    return inside


@kernel
def _flat_hit(ax: float, ay: float, az: float, bx: float, by: float, bz: float, lo: float, hi: float, k: int,
              xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray) -> bool:
    """Whether the segment ``a b`` enters the prism of polygon ``k`` times the flat band ``[lo, hi]``: the
    segment parameter cut to the band (z is linear along it), the trace over that interval against the
    polygon.  ``disc[k, :4] = (x, y, r_in, r_out)``: the disc of radius ``r_in`` about ``(x, y)`` lies inside
    the polygon (a trace passing nearer is in), the one of radius ``r_out`` holds it (a trace passing
    further is out); then the same with the capsules about a segment ``disc[k, 4:]``
    (:func:`.parts.capsules`: a cable corridor's edges are seldom walked); between them the edges decide."""
    dz = bz - az
    if dz == 0.0:
        if az < lo or az > hi:
            return False
        t0, t1 = 0.0, 1.0
    else:
        u, v = (lo - az) / dz, (hi - az) / dz
        t0, t1 = max(0.0, min(u, v)), min(1.0, max(u, v))
        if t0 > t1:
            return False
    dx, dy = bx - ax, by - ay
    cx, cy = (ax, ay) if t0 == 0.0 else (ax + t0 * dx, ay + t0 * dy)
    ex, ey = (bx, by) if t1 == 1.0 else (ax + t1 * dx, ay + t1 * dy)
    # two discs about a point of the polygon settle most pairs: one inside it, one holding it
    gx, gy = ex - cx, ey - cy
    gg = gx * gx + gy * gy
    ox, oy = disc[k, 0] - cx, disc[k, 1] - cy
    t = 0.0 if gg == 0.0 else min(max((ox * gx + oy * gy) / gg, 0.0), 1.0)
    wx, wy = ox - t * gx, oy - t * gy
    d2 = wx * wx + wy * wy
    if d2 < disc[k, 2] * disc[k, 2]:
        return True
    if d2 > disc[k, 3] * disc[k, 3]:
        return False
    e2 = _segment_distance2(cx, cy, ex, ey, disc[k, 4], disc[k, 5], disc[k, 6], disc[k, 7])
    if e2 < disc[k, 8] * disc[k, 8]:
        return True
    if e2 > disc[k, 9] * disc[k, 9]:
        return False
    return _meets_polygon(cx, cy, ex, ey, k, xy, ring, rings)


@kernel
def _point_distance2(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> float:
    """The squared distance from ``p`` to the closed segment ``a b``."""
    ex, ey = bx - ax, by - ay
    ee = ex * ex + ey * ey
    t = 0.0 if ee == 0.0 else min(max(((px - ax) * ex + (py - ay) * ey) / ee, 0.0), 1.0)
    qx, qy = ax + t * ex - px, ay + t * ey - py
    return qx * qx + qy * qy


@kernel
def _segment_distance2(ax: float, ay: float, bx: float, by: float, cx: float, cy: float, dx: float,
                       dy: float) -> float:
    """The squared distance between the closed segments ``a b`` and ``c d`` (0 where they meet)."""
    if _segments_meet(ax, ay, bx, by, cx, cy, dx, dy):
        return 0.0
    return min(_point_distance2(ax, ay, cx, cy, dx, dy), _point_distance2(bx, by, cx, cy, dx, dy),
               _point_distance2(cx, cy, ax, ay, bx, by), _point_distance2(dx, dy, ax, ay, bx, by))


@kernel
def flat_hits_kernel(seg: FloatArray, si: IntArray, zi: IntArray, zlo: FloatArray, zhi: FloatArray,
                     xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray, out: BoolArray) -> None:
    """Exact test of the pairs ``(seg[si[m]], zone zi[m])`` against flat bands ``[zlo, zhi]``."""
    for m in range(si.shape[0]):
        n, k = si[m], zi[m]
        out[m] = _flat_hit(seg[n, 0, 0], seg[n, 0, 1], seg[n, 0, 2], seg[n, 1, 0], seg[n, 1, 1], seg[n, 1, 2],
                           zlo[k], zhi[k], k, xy, ring, rings, disc)


@kernel
def _ring_distance(px: float, py: float, k: int, xy: FloatArray, ring: IntArray, rings: IntArray) -> tuple[float, bool]:
    """Distance from ``p`` to the boundary of polygon ``k`` and whether ``p`` is inside (even-odd rule)."""
    best = math.inf
    inside = False
    for r in range(rings[k], rings[k + 1]):
        for v in range(ring[r], ring[r + 1] - 1):
            ux, uy, wx, wy = xy[v, 0], xy[v, 1], xy[v + 1, 0], xy[v + 1, 1]
            ex, ey = wx - ux, wy - uy
            ee = ex * ex + ey * ey
            t = 0.0 if ee == 0.0 else min(max(((px - ux) * ex + (py - uy) * ey) / ee, 0.0), 1.0)
            qx, qy = ux + t * ex - px, uy + t * ey - py
            best = min(best, qx * qx + qy * qy)
            if (uy > py) != (wy > py) and px < ux + (py - uy) * (wx - ux) / (wy - uy):
                inside = not inside
    return math.sqrt(best), inside


@kernel
def near_distance_kernel(p: FloatArray, floor: FloatArray, x0: float, y0: float, cell: float, nx: int, ny: int,
                         start: IntArray, ids: IntArray, reach: int, zlo: FloatArray, zhi: FloatArray,
                         h: FloatArray, slope: float, xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray,
                         mark: IntArray, out: FloatArray) -> None:
    """Signed distance of points ``p (N, 3)`` to the zones listed within ``reach`` cells of them (the
    least over those zones, at most ``out``'s initial value; negative inside).

    A flat band ``[zlo, zhi]``: ``hypot(d_h, max(d_v, 0))`` outside, ``-min(edge, depth inside)``
    inside.  A seabed band (``h`` finite): the vertical term ``(z - floor - h) / slope`` with ``floor``
    the seabed under each point.  ``mark (Z,)`` is scratch filled with -1 by the caller.

    A point with the same ``x, y`` as the one before it (a lattice column's nodes) reuses that point's zones
    and their horizontal distances, in the same order (the same answers: only the vertical terms differ).
    """
    near = np.empty(mark.size, dtype=np.intp)
    edges = np.empty(mark.size)
    insides = np.empty(mark.size, dtype=np.bool_)
    count = 0
    for n in range(p.shape[0]):
        px, py, pz = p[n, 0], p[n, 1], p[n, 2]
        if n == 0 or px != p[n - 1, 0] or py != p[n - 1, 1]:
            count = _near_zones(px, py, n, x0, y0, cell, nx, ny, start, ids, reach, xy, ring, rings, mark, near,
                                edges, insides)
        best = out[n]
        for q in range(count):
            k, edge, inside = near[q], edges[q], insides[q]
            dh = 0.0 if inside else edge
            if math.isnan(h[k]):
                out_v = max(zlo[k] - pz, pz - zhi[k])
                in_v = min(pz - zlo[k], zhi[k] - pz)
            else:
                out_v = (pz - floor[n] - h[k]) / slope
                in_v = -out_v
            if dh == 0.0 and out_v <= 0.0:
                d = -min(edge, in_v)
            else:
                d = math.hypot(dh, max(out_v, 0.0))
            best = min(best, d)
        out[n] = best


@kernel
def _near_zones(px: float, py: float, n: int, x0: float, y0: float, cell: float, nx: int, ny: int, start: IntArray,
                ids: IntArray, reach: int, xy: FloatArray, ring: IntArray, rings: IntArray, mark: IntArray,
                near: IntArray, edges: FloatArray, insides: BoolArray) -> int:
    """The zones listed within ``reach`` cells of point ``(px, py)`` (each once, marked ``n``, in the cells'
    order) and the point's horizontal distance to each footprint's edges and whether it is inside, into
    ``near``, ``edges``, ``insides``; returns their count."""
    i = int(math.floor((px - x0) / cell))
    j = int(math.floor((py - y0) / cell))
    count = 0
    for jj in range(max(j - reach, 0), min(j + reach, ny - 1) + 1):
        for ii in range(max(i - reach, 0), min(i + reach, nx - 1) + 1):
            c = jj * nx + ii
            for q in range(start[c], start[c + 1]):
                k = ids[q]
                if mark[k] == n:
                    continue
                mark[k] = n
                near[count] = k
                edges[count], insides[count] = _ring_distance(px, py, k, xy, ring, rings)
                count += 1
    return count
