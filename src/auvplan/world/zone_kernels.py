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

from .._jit import kernel
from .._types import BoolArray, FloatArray, IntArray

__all__ = ["candidates_kernel"]


@kernel(inline="always")
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
            for i in range(i0, i1 + 1):
                c = j * nx + i
                if start[c] == start[c + 1]:
                    continue
                cx0 = x0 + i * cell
                # the line passes the cell by when all four corners lie strictly on one side of it
                s0 = dx * (cy0 - ay) - dy * (cx0 - ax)
                s1 = dx * (cy0 - ay) - dy * (cx0 + cell - ax)
                s2 = dx * (cy0 + cell - ay) - dy * (cx0 - ax)
                s3 = dx * (cy0 + cell - ay) - dy * (cx0 + cell - ax)
                if (s0 > 0 and s1 > 0 and s2 > 0 and s3 > 0) or (s0 < 0 and s1 < 0 and s2 < 0 and s3 < 0):
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
def near_pairs_kernel(px: FloatArray, py: FloatArray, x0: float, y0: float, cell: float, nx: int, ny: int,
                      start: IntArray, ids: IntArray, reach: int, mark: IntArray, pairs: IntArray,
                      capacity: int) -> int:
    """The (point, zone) pairs of the zones listed in the cells within ``reach`` cells of each point's
    cell (each pair once), written into ``pairs (2, capacity)`` while they fit; ``mark (Z,)`` is
    scratch (filled with -1 by the caller).  Returns the number of pairs.  A zone not paired with a
    point lies at least ``reach`` cells from it horizontally."""
    m = 0
    for n in range(px.shape[0]):
        i = int(math.floor((px[n] - x0) / cell))
        j = int(math.floor((py[n] - y0) / cell))
        for jj in range(max(j - reach, 0), min(j + reach, ny - 1) + 1):
            for ii in range(max(i - reach, 0), min(i + reach, nx - 1) + 1):
                c = jj * nx + ii
                for q in range(start[c], start[c + 1]):
                    k = ids[q]
                    if mark[k] == n:
                        continue
                    mark[k] = n
                    if m < capacity:
                        pairs[0, m] = n
                        pairs[1, m] = k
                    m += 1
    return m


@kernel(inline="always")
def _orient(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> float:
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


@kernel(inline="always")
def _on(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> bool:
    """Whether ``c``, collinear with ``a b``, lies on the closed segment."""
    return min(ax, bx) <= cx <= max(ax, bx) and min(ay, by) <= cy <= max(ay, by)


@kernel(inline="always")
def _segments_meet(ax: float, ay: float, bx: float, by: float, cx: float, cy: float, dx: float, dy: float) -> bool:
    """Whether the closed segments ``a b`` and ``c d`` share a point (orientation tests)."""
    o1, o2 = _orient(ax, ay, bx, by, cx, cy), _orient(ax, ay, bx, by, dx, dy)
    o3, o4 = _orient(cx, cy, dx, dy, ax, ay), _orient(cx, cy, dx, dy, bx, by)
    if ((o1 > 0 and o2 < 0) or (o1 < 0 and o2 > 0)) and ((o3 > 0 and o4 < 0) or (o3 < 0 and o4 > 0)):
        return True
    return ((o1 == 0 and _on(ax, ay, bx, by, cx, cy)) or (o2 == 0 and _on(ax, ay, bx, by, dx, dy))
            or (o3 == 0 and _on(cx, cy, dx, dy, ax, ay)) or (o4 == 0 and _on(cx, cy, dx, dy, bx, by)))


@kernel(inline="always")
def _meets_polygon(ax: float, ay: float, bx: float, by: float, k: int, xy: FloatArray, ring: IntArray,
                   rings: IntArray) -> bool:
    """Whether the closed segment ``a b`` meets the closed polygon ``k`` (its rings ``rings[k]:rings[k+1]``,
    each ring's closed vertex list ``xy[ring[r]:ring[r+1]]``): an edge crossed or touched, or ``a`` inside
    (even-odd rule over every ring, so holes are outside)."""
    inside = False
    for r in range(rings[k], rings[k + 1]):
        for v in range(ring[r], ring[r + 1] - 1):
            px, py, qx, qy = xy[v, 0], xy[v, 1], xy[v + 1, 0], xy[v + 1, 1]
            if _segments_meet(ax, ay, bx, by, px, py, qx, qy):
                return True
            if (py > ay) != (qy > ay) and ax < px + (ay - py) * (qx - px) / (qy - py):
                inside = not inside
    return inside


@kernel
def flat_hits_kernel(seg: FloatArray, si: IntArray, zi: IntArray, zlo: FloatArray, zhi: FloatArray,
                     xy: FloatArray, ring: IntArray, rings: IntArray, out: BoolArray) -> None:
    """Exact test of the pairs ``(seg[si[m]], zone zi[m])`` against flat bands ``[zlo, zhi]``: the
    segment parameter cut to the band (z is linear along it), the trace over that interval against
    the polygon."""
    for m in range(si.shape[0]):
        n, k = si[m], zi[m]
        ax, ay, az = seg[n, 0, 0], seg[n, 0, 1], seg[n, 0, 2]
        bx, by, bz = seg[n, 1, 0], seg[n, 1, 1], seg[n, 1, 2]
        dz = bz - az
        if dz == 0.0:
            if az < zlo[k] or az > zhi[k]:
                out[m] = False
                continue
            t0, t1 = 0.0, 1.0
        else:
            u, v = (zlo[k] - az) / dz, (zhi[k] - az) / dz
            t0, t1 = max(0.0, min(u, v)), min(1.0, max(u, v))
            if t0 > t1:
                out[m] = False
                continue
        dx, dy = bx - ax, by - ay
        cx, cy = (ax, ay) if t0 == 0.0 else (ax + t0 * dx, ay + t0 * dy)
        ex, ey = (bx, by) if t1 == 1.0 else (ax + t1 * dx, ay + t1 * dy)
        out[m] = _meets_polygon(cx, cy, ex, ey, k, xy, ring, rings)
