"""The compiled broad phase of :class:`~auvplan.world.zones.Zones`: which segments can meet a zone at all.

The zones' footprints are rasterised once onto a grid of square cells, each cell listing the zones
whose footprint touches it (compressed rows: ``start``/``ids``).  A segment is a *candidate* when, in
some cell its horizontal trace crosses (the cells of its bounding box that the line does not pass by
on one side), a listed zone's depth band (``zlo``/``zhi``; a seabed band up to the highest seabed
under the zone plus its height) overlaps the segment's z-range and the segment meets the zone's
bounding box (slab clipping).  Everything else provably meets no zone; candidates go to the exact
shapely test.
"""

from __future__ import annotations

import math

from ..._types import BoolArray, FloatArray, IntArray
from ...runtime.jit import kernel

__all__ = ["FIELD_UNITS", "candidates_kernel"]  # the others are the internals of auvplan.world.zones

#: The fine distance field's values are whole units of a fine cell / FIELD_UNITS (uint16).
FIELD_UNITS = 64

#: Legs of a polyline passed at once by one disc of the fine field (:func:`path_hits_kernel`).
RUN = 4

# Only the field's look-up and march (:func:`_far`, :func:`_clear`), run for every leg, are inlined by numba
# (``inline="always"``): the swarm's pass is as fast as with every helper inlined (0.0512 vs 0.0510 s a plan
# replayed; 5.6 % slower with none) and the two any-hit passes compile in half the time.


@kernel
def _meets_box(ax: float, ay: float, dx: float, dy: float, x0: float, y0: float, x1: float, y1: float) -> bool:
    """Whether the segment ``a + t d, t in [0, 1]`` meets the closed box (slab clipping)."""
    t0, t1 = 0.0, 1.0
    if dx == 0.0:
        if ax < x0 or ax > x1:
            return False
    else:
        u, v = (x0 - ax) / dx, (x1 - ax) / dx
        t0, t1 = max(t0, min(u, v)), min(t1, max(u, v))
    if dy == 0.0:
        if ay < y0 or ay > y1:
            return False
    else:
        u, v = (y0 - ay) / dy, (y1 - ay) / dy
        t0, t1 = max(t0, min(u, v)), min(t1, max(u, v))
    return t0 <= t1


@kernel
def _row_cells(j: int, ax: float, ay: float, dx: float, dy: float, x0: float, y0: float, cell: float, i0: int,
               i1: int) -> tuple[int, int]:
    """The columns of row ``j`` (within ``i0..i1``) the segment ``a + t d`` can cross: the x-range of its
    part within the row's strip, widened by a millionth of a cell against rounding (a superset; the
    caller's corner test is exact)."""
    if dy == 0.0:
        return i0, i1
    lo = max(y0 + j * cell, min(ay, ay + dy))
    hi = min(y0 + (j + 1) * cell, max(ay, ay + dy))
    xa = ax + (lo - ay) * dx / dy
    xb = ax + (hi - ay) * dx / dy
    eps = 1e-6 * cell
    c0 = int(math.floor((min(xa, xb) - eps - x0) / cell))
    c1 = int(math.floor((max(xa, xb) + eps - x0) / cell))
    return max(c0, i0), min(c1, i1)


@kernel
def _passes_by(ax: float, ay: float, dx: float, dy: float, cx0: float, cy0: float, cell: float) -> bool:
    """Whether the line through ``a`` along ``d`` passes the cell ``[cx0, cx0 + cell] x [cy0, cy0 + cell]``
    by: all four corners strictly on one side of it."""
    s0 = dx * (cy0 - ay) - dy * (cx0 - ax)
    s1 = dx * (cy0 - ay) - dy * (cx0 + cell - ax)
    s2 = dx * (cy0 + cell - ay) - dy * (cx0 - ax)
    s3 = dx * (cy0 + cell - ay) - dy * (cx0 + cell - ax)
    return (s0 > 0 and s1 > 0 and s2 > 0 and s3 > 0) or (s0 < 0 and s1 < 0 and s2 < 0 and s3 < 0)


@kernel
def candidates_kernel(seg: FloatArray, x0: float, y0: float, cell: float, nx: int, ny: int, start: IntArray,
                      ids: IntArray, box: FloatArray, zlo: FloatArray, zhi: FloatArray, mark: IntArray,
                      pairs: IntArray, capacity: int) -> int:
    """The (segment, zone) candidate pairs of segments (see the module notes), each pair once.

    Parameters
    ----------
    seg : numpy.ndarray
        Segments ``(N, 2, 3)`` (m).
    x0, y0, cell : float
        The grid's corner and cell size (m).
    nx, ny : int
        Cells along x and y.
    start, ids : numpy.ndarray of int
        Compressed rows: the zones of cell ``c`` (``j * nx + i``) are ``ids[start[c]:start[c + 1]]``.
    box : numpy.ndarray
        The zones' bounding boxes ``(Z, 4)`` (m).
    zlo, zhi : numpy.ndarray
        The zones' bands ``(Z,)`` (z up, m).
    mark : numpy.ndarray of int
        Scratch ``(Z,)``, filled with -1 by the caller.
    pairs : numpy.ndarray of int
        Output ``(2, capacity)``: segment and zone of each pair, while they fit.
    capacity : int
        Columns of ``pairs``.

    Returns
    -------
    int
        The number of pairs (more than ``capacity``: call again with room for them).
    """
    m = 0
    for n in range(seg.shape[0]):
        ax, ay, az = seg[n, 0, 0], seg[n, 0, 1], seg[n, 0, 2]
        bx, by, bz = seg[n, 1, 0], seg[n, 1, 1], seg[n, 1, 2]
        i0 = max(int(math.floor((min(ax, bx) - x0) / cell)), 0)
        i1 = min(int(math.floor((max(ax, bx) - x0) / cell)), nx - 1)
        j0 = max(int(math.floor((min(ay, by) - y0) / cell)), 0)
        j1 = min(int(math.floor((max(ay, by) - y0) / cell)), ny - 1)
        zmin, zmax = min(az, bz), max(az, bz)
        dx, dy = bx - ax, by - ay
        for j in range(j0, j1 + 1):
            cy0 = y0 + j * cell
            r0, r1 = _row_cells(j, ax, ay, dx, dy, x0, y0, cell, i0, i1)
            for i in range(r0, r1 + 1):
                c = j * nx + i
                if start[c] == start[c + 1]:
                    continue
                if _passes_by(ax, ay, dx, dy, x0 + i * cell, cy0, cell):
                    continue
                for q in range(start[c], start[c + 1]):
                    k = ids[q]
                    if mark[k] == n:
                        continue
                    mark[k] = n
                    if zlo[k] <= zmax and zhi[k] >= zmin and _meets_box(ax, ay, dx, dy, box[k, 0], box[k, 1],
                                                                        box[k, 2], box[k, 3]):
                        if m < capacity:
                            pairs[0, m] = n
                            pairs[1, m] = k
                        m += 1
    return m


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


@kernel(inline="always")
def _far(px: float, py: float, fx0: float, fy0: float, f: float, fnx: int, fny: int, bound: FloatArray) -> float:
    """A lower bound of the horizontal distance from ``p`` to every footprint (m): the fine field's value in
    ``p``'s cell, or the distance to the field's rectangle (which holds every footprint) outside it."""
    u, v = (px - fx0) / f, (py - fy0) / f
    if u >= 0.0 and v >= 0.0 and u < fnx and v < fny:
        return float(bound[int(v), int(u)]) * (f / FIELD_UNITS)
    return math.hypot(max(-u, u - fnx, 0.0), max(-v, v - fny, 0.0)) * f


@kernel(inline="always")
def _clear(ax: float, ay: float, bx: float, by: float, fa: float, fb: float, fx0: float, fy0: float, f: float,
           fnx: int, fny: int, bound: FloatArray) -> bool:
    """Whether the fine field proves the segment's trace meets no footprint (False: not proven).

    ``fa``/``fb`` are the ends' bounds (:func:`_far`).  Every point within ``r = _far(p)`` of a point
    ``p`` (open disc) is off every footprint, so the trace is marched from ``a`` by those discs until
    they reach ``b``'s; a point with ``r = 0`` (near a footprint) or more than 256 steps stop the march.
    """
    dx, dy = bx - ax, by - ay
    length = math.hypot(dx, dy)
    if length < fa + fb:
        return True
    if fa == 0.0 or fb == 0.0:
        return False
    t, tb = fa / length, 1.0 - fb / length
    for _ in range(256):
        r = _far(ax + t * dx, ay + t * dy, fx0, fy0, f, fnx, fny, bound)
        if r == 0.0:
            return False
        t += r / length
        if t > tb:
            return True
    return False


@kernel
def _scan(n: int, ax: float, ay: float, az: float, bx: float, by: float, bz: float, x0: float, y0: float,
          cell: float, nx: int, ny: int, start: IntArray, ids: IntArray, box: FloatArray, zlo: FloatArray,
          zhi: FloatArray, seabed: BoolArray, xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray,
          mark: IntArray, pairs: IntArray, m: int, capacity: int) -> tuple[bool, int, int]:
    """The cells segment ``n``'s trace crosses: True at its first flat-band entry (pairs written for it
    dropped), else its seabed-band candidates appended to ``pairs`` from ``m``; returns (entered, m, the
    zone entered or -1)."""
    i0 = max(int(math.floor((min(ax, bx) - x0) / cell)), 0)
    i1 = min(int(math.floor((max(ax, bx) - x0) / cell)), nx - 1)
    j0 = max(int(math.floor((min(ay, by) - y0) / cell)), 0)
    j1 = min(int(math.floor((max(ay, by) - y0) / cell)), ny - 1)
    zmin, zmax = min(az, bz), max(az, bz)
    dx, dy = bx - ax, by - ay
    first = m
    for j in range(j0, j1 + 1):
        cy0 = y0 + j * cell
        r0, r1 = _row_cells(j, ax, ay, dx, dy, x0, y0, cell, i0, i1)
        for i in range(r0, r1 + 1):
            c = j * nx + i
            if start[c] == start[c + 1]:
                continue
            if _passes_by(ax, ay, dx, dy, x0 + i * cell, cy0, cell):
                continue
            for q in range(start[c], start[c + 1]):
                k = ids[q]
                if mark[k] == n:
                    continue
                mark[k] = n
                if not (zlo[k] <= zmax and zhi[k] >= zmin
                        and _meets_box(ax, ay, dx, dy, box[k, 0], box[k, 1], box[k, 2], box[k, 3])):
                    continue
                if seabed[k]:
                    if m < capacity:
                        pairs[0, m] = n
                        pairs[1, m] = k
                    m += 1
                elif _flat_hit(ax, ay, az, bx, by, bz, zlo[k], zhi[k], k, xy, ring, rings, disc):
                    return True, first, k
    return False, m, -1


@kernel
def any_hits_kernel(seg: FloatArray, x0: float, y0: float, cell: float, nx: int, ny: int, start: IntArray,
                    ids: IntArray, box: FloatArray, zlo: FloatArray, zhi: FloatArray, seabed: BoolArray,
                    xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray, fx0: float, fy0: float,
                    f: float, fnx: int, fny: int, bound: FloatArray, mark: IntArray, hit: BoolArray, pairs: IntArray,
                    capacity: int) -> int:
    """Broad phase and exact flat-band test in one pass: ``hit[n]`` is True where segment ``n`` enters a
    flat-band zone (the search stops at the first); the seabed-band candidates of every other segment
    are written to ``pairs (2, capacity)`` while they fit (the caller tests them exactly).

    A segment the fine field ``bound`` (:func:`.parts.distance_field`) proves clear of every
    footprint (:func:`_clear`) is passed at once.  Otherwise the same grid and scratch as
    :func:`candidates_kernel`; ``zlo``/``zhi`` are the grid's bands (a flat band exactly), ``seabed``
    flags the seabed bands.  Returns the number of seabed pairs (more than ``capacity``: call again
    with room for them).
    """
    m = 0
    for n in range(seg.shape[0]):
        ax, ay, az = seg[n, 0, 0], seg[n, 0, 1], seg[n, 0, 2]
        bx, by, bz = seg[n, 1, 0], seg[n, 1, 1], seg[n, 1, 2]
        fa = _far(ax, ay, fx0, fy0, f, fnx, fny, bound)
        fb = _far(bx, by, fx0, fy0, f, fnx, fny, bound)
        if _clear(ax, ay, bx, by, fa, fb, fx0, fy0, f, fnx, fny, bound):
            hit[n] = False
            continue
        hit[n], m, _ = _scan(n, ax, ay, az, bx, by, bz, x0, y0, cell, nx, ny, start, ids, box, zlo, zhi, seabed,
                             xy, ring, rings, disc, mark, pairs, m, capacity)
    return m


@kernel
def path_hits_kernel(p: FloatArray, x0: float, y0: float, cell: float, nx: int, ny: int, start: IntArray,
                     ids: IntArray, box: FloatArray, zlo: FloatArray, zhi: FloatArray, seabed: BoolArray,
                     xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray, fx0: float, fy0: float,
                     f: float, fnx: int, fny: int, bound: FloatArray, mark: IntArray, hit: BoolArray, pairs: IntArray,
                     capacity: int) -> int:
    """:func:`any_hits_kernel` over the legs of polylines ``p (P, S, 3)``: ``hit (P * (S - 1),)`` and the
    pairs' segment ``n = i (S - 1) + s``.

    The legs go in runs of :data:`RUN`: a run whose vertices all lie within the fine field's bound at the
    centre of their box (a disc off every footprint, holding the run's legs: it is convex) is passed with
    one look-up; otherwise leg by leg, each vertex's field value looked up once."""
    m = 0
    legs = p.shape[1] - 1
    for i in range(p.shape[0]):
        fa = -1.0  # not looked up yet
        last = -1  # the flat-band zone the last entering leg entered
        for s0 in range(0, legs, RUN):
            s1 = min(s0 + RUN, legs)
            lx, hx, ly, hy = p[i, s0, 0], p[i, s0, 0], p[i, s0, 1], p[i, s0, 1]
            for s in range(s0 + 1, s1 + 1):
                lx, hx = min(lx, p[i, s, 0]), max(hx, p[i, s, 0])
                ly, hy = min(ly, p[i, s, 1]), max(hy, p[i, s, 1])
            cx, cy = 0.5 * (lx + hx), 0.5 * (ly + hy)
            rr = 0.0
            for s in range(s0, s1 + 1):
                rr = max(rr, (p[i, s, 0] - cx) ** 2 + (p[i, s, 1] - cy) ** 2)
            r = _far(cx, cy, fx0, fy0, f, fnx, fny, bound)
            if r * r > rr:
                for s in range(s0, s1):
                    hit[i * legs + s] = False
                fa = -1.0
                continue
            ax, ay, az = p[i, s0, 0], p[i, s0, 1], p[i, s0, 2]
            if fa < 0.0:
                fa = _far(ax, ay, fx0, fy0, f, fnx, fny, bound)
            for s in range(s0, s1):
                n = i * legs + s
                bx, by, bz = p[i, s + 1, 0], p[i, s + 1, 1], p[i, s + 1, 2]
                fb = _far(bx, by, fx0, fy0, f, fnx, fny, bound)
                if _clear(ax, ay, bx, by, fa, fb, fx0, fy0, f, fnx, fny, bound):
                    hit[n] = False
                elif last >= 0 and _flat_hit(ax, ay, az, bx, by, bz, zlo[last], zhi[last], last, xy, ring, rings,
                                             disc):
                    hit[n] = True  # the zone the path's last entering leg entered: most often this one's too
                else:
                    hit[n], m, last = _scan(n, ax, ay, az, bx, by, bz, x0, y0, cell, nx, ny, start, ids, box, zlo,
                                            zhi, seabed, xy, ring, rings, disc, mark, pairs, m, capacity)
                ax, ay, az, fa = bx, by, bz, fb
    return m


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
    """
    for n in range(p.shape[0]):
        px, py, pz = p[n, 0], p[n, 1], p[n, 2]
        i = int(math.floor((px - x0) / cell))
        j = int(math.floor((py - y0) / cell))
        best = out[n]
        for jj in range(max(j - reach, 0), min(j + reach, ny - 1) + 1):
            for ii in range(max(i - reach, 0), min(i + reach, nx - 1) + 1):
                c = jj * nx + ii
                for q in range(start[c], start[c + 1]):
                    k = ids[q]
                    if mark[k] == n:
                        continue
                    mark[k] = n
                    edge, inside = _ring_distance(px, py, k, xy, ring, rings)
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
def field_kernel(xy: FloatArray, ring: IntArray, rings: IntArray, box: FloatArray, fx0: float, fy0: float, f: float,
                 reach: float, out: FloatArray) -> None:
    """The horizontal distance from each fine cell's centre to the nearest footprint, where it is below
    ``reach`` (m): ``out (fny, fnx)``, filled with ``reach`` by the caller, lowered to the distance to every
    polygon ``k`` (rings as in :func:`_meets_polygon`; 0 inside) over the cells of its box ``box[k]`` grown
    by ``reach``."""
    fny, fnx = out.shape
    for k in range(box.shape[0]):
        i0 = max(int(math.floor((box[k, 0] - reach - fx0) / f - 0.5)), 0)
        i1 = min(int(math.ceil((box[k, 2] + reach - fx0) / f - 0.5)), fnx - 1)
        j0 = max(int(math.floor((box[k, 1] - reach - fy0) / f - 0.5)), 0)
        j1 = min(int(math.ceil((box[k, 3] + reach - fy0) / f - 0.5)), fny - 1)
        for j in range(j0, j1 + 1):
            py = fy0 + (j + 0.5) * f
            for i in range(i0, i1 + 1):
                if out[j, i] == 0.0:
                    continue
                px = fx0 + (i + 0.5) * f
                edge, inside = _ring_distance(px, py, k, xy, ring, rings)
                out[j, i] = min(out[j, i], 0.0 if inside else edge)


@kernel
def clear_kernel(t: FloatArray, fx0: float, fy0: float, f: float, fnx: int, fny: int, bound: FloatArray,
                 out: BoolArray) -> None:
    """Which horizontal traces ``t (T, 2, 2)`` the fine field proves clear of every footprint: :func:`_clear`'s
    march, given up after 24 discs (a long trace skirting a footprint: the cells' test is cheaper)."""
    for n in range(t.shape[0]):
        ax, ay, bx, by = t[n, 0, 0], t[n, 0, 1], t[n, 1, 0], t[n, 1, 1]
        fa = _far(ax, ay, fx0, fy0, f, fnx, fny, bound)
        fb = _far(bx, by, fx0, fy0, f, fnx, fny, bound)
        dx, dy = bx - ax, by - ay
        length = math.hypot(dx, dy)
        out[n] = length < fa + fb
        if out[n] or fa == 0.0 or fb == 0.0:
            continue
        s, sb = fa / length, 1.0 - fb / length
        for _ in range(24):
            r = _far(ax + s * dx, ay + s * dy, fx0, fy0, f, fnx, fny, bound)
            if r == 0.0:
                break
            s += r / length
            if s > sb:
                out[n] = True
                break


@kernel
def slack_kernel(p: FloatArray, hit: BoolArray, out: FloatArray) -> None:
    """The swarm cost's zone slack of the legs of polylines ``p (P, S, 3)``: ``out (P, S - 1)`` is minus the
    length of each leg ``hit`` flags (``hit (P * (S - 1),)``; at least 1 m), ``+inf`` elsewhere."""
    legs = p.shape[1] - 1
    for i in range(p.shape[0]):
        for s in range(legs):
            if hit[i * legs + s]:
                dx, dy, dz = p[i, s + 1, 0] - p[i, s, 0], p[i, s + 1, 1] - p[i, s, 1], p[i, s + 1, 2] - p[i, s, 2]
                out[i, s] = -max(math.sqrt(dx * dx + dy * dy + dz * dz), 1.0)
            else:
                out[i, s] = math.inf
