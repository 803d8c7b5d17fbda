"""The zones' compiled broad phase (:mod:`auvplan.world.zones`): which zones a segment can meet at all.

The zones' footprints are rasterised once onto a grid of square cells, each cell listing the zones
whose footprint touches it (compressed rows: ``start``/``ids``).  A segment is a *candidate* when, in
some cell its horizontal trace crosses (the cells of its bounding box that the line does not pass by
on one side), a listed zone's depth band (``zlo``/``zhi``; a seabed band up to the highest seabed
under the zone plus its height) overlaps the segment's z-range and the segment meets the zone's
bounding box (slab clipping).  Everything else provably meets no zone; candidates go to the exact
test.  One walk over the cells (:func:`_scan`) serves both the candidate lists (:func:`candidates_kernel`)
and the any-hit passes (:mod:`.kernels`), which test the flat bands as they go.
"""

from __future__ import annotations

import math

from ..._types import BoolArray, FloatArray, IntArray
from ...runtime.jit import kernel
from .exact import _flat_hit

__all__ = ["candidates_kernel"]  # the others are the internals of auvplan.world.zones


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
def _scan(n: int, ax: float, ay: float, az: float, bx: float, by: float, bz: float, x0: float, y0: float,
          cell: float, nx: int, ny: int, start: IntArray, ids: IntArray, box: FloatArray, zlo: FloatArray,
          zhi: FloatArray, seabed: BoolArray, xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray,
          mark: IntArray, pairs: IntArray, m: int, capacity: int, collect: bool) -> tuple[bool, int, int]:
    """The cells segment ``n``'s trace crosses: True at its first flat-band entry (pairs written for it
    dropped), else its seabed-band candidates appended to ``pairs`` from ``m``; returns (entered, m, the
    zone entered or -1).  With ``collect`` every candidate (flat bands too) is appended and none tested."""
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
                if collect or seabed[k]:
                    if m < capacity:
                        pairs[0, m] = n
                        pairs[1, m] = k
                    m += 1
                elif _flat_hit(ax, ay, az, bx, by, bz, zlo[k], zhi[k], k, xy, ring, rings, disc):
                    return True, first, k
    return False, m, -1


@kernel
def candidates_kernel(seg: FloatArray, x0: float, y0: float, cell: float, nx: int, ny: int, start: IntArray,
                      ids: IntArray, box: FloatArray, zlo: FloatArray, zhi: FloatArray, seabed: BoolArray,
                      xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray, mark: IntArray,
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
    seabed : numpy.ndarray of bool
        The seabed bands ``(Z,)``.
    xy, ring, rings, disc : numpy.ndarray
        The polygons (:func:`.parts.rings`), not read here: :func:`_scan`'s arguments.
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
        _, m, _ = _scan(n, seg[n, 0, 0], seg[n, 0, 1], seg[n, 0, 2], seg[n, 1, 0], seg[n, 1, 1], seg[n, 1, 2], x0,
                        y0, cell, nx, ny, start, ids, box, zlo, zhi, seabed, xy, ring, rings, disc, mark, pairs, m,
                        capacity, True)
    return m
