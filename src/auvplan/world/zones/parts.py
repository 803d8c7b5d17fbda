"""Geometry helpers of :mod:`auvplan.world.zones`: the broad phase's grid, polygons as flat arrays for the
compiled tests, horizontal traces, clipped pieces and samples along legs."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import shapely

from ..._types import FloatArray, IntArray
from ..kernels.edt import distance_transform
from ..terrain import Terrain

__all__ = ["rasterise", "band_tops", "distance_field", "inner_centres", "rings", "samples", "traces", "clip_params",
           "clip_pieces", "expand_groups"]


def rasterise(b: FloatArray, tree: shapely.STRtree, zlo: FloatArray, zhi: FloatArray, h: FloatArray,
              terrain: Terrain | None) -> tuple[Any, ...]:
    """The broad phase's grid (:mod:`.broad`): the zones listed per cell, each zone's bounding
    box and band (a seabed band up to the highest seabed under its box), and each cell's distance
    (in cells) to the nearest cell that lists a zone.

    Parameters
    ----------
    b : numpy.ndarray
        The zones' bounding boxes ``(Z, 4)`` (m).
    tree : shapely.STRtree
        The footprints.
    zlo, zhi, h : numpy.ndarray
        Bands ``(Z,)``: bottom and top (z up, m) of flat bands; height of seabed bands (``nan`` else).
    terrain : Terrain or None
        The seabed of the seabed bands.

    Returns
    -------
    tuple
        ``(x0, y0, cell, nx, ny, start, ids, boxes, bottom, top, reach)``.
    """
    lo, hi = b[:, :2].min(axis=0), b[:, 2:].max(axis=0)
    span = float((hi - lo).max())
    size = float(np.median(np.maximum(b[:, 2] - b[:, 0], b[:, 3] - b[:, 1])))
    cell = max(min(max(2.0 * size, span / 512), span / 32), 1e-3)  # about twice a typical zone
    lo = lo - cell
    n = np.ceil((hi + cell - lo) / cell).astype(int)
    nx, ny = int(n[0]), int(n[1])
    jj, ii = np.divmod(np.arange(nx * ny), nx)
    boxes = shapely.box(lo[0] + ii * cell, lo[1] + jj * cell, lo[0] + (ii + 1) * cell, lo[1] + (jj + 1) * cell)
    ci, zi = tree.query(boxes, predicate="intersects")
    order = np.lexsort((zi, ci))
    ci, zi = ci[order], zi[order]
    start = np.zeros(nx * ny + 1, dtype=np.intp)
    np.add.at(start, ci + 1, 1)
    start = np.cumsum(start)
    top = band_tops(b, zhi, h, terrain)
    bottom = np.where(np.isfinite(h), -np.inf, zlo)
    flagged = np.diff(start) > 0
    reach = distance_transform(~flagged.reshape(ny, nx))
    return (float(lo[0]), float(lo[1]), cell, nx, ny, start, zi.astype(np.intp), np.ascontiguousarray(b), bottom,
            top, np.asarray(reach, dtype=float))


def band_tops(b: FloatArray, zhi: FloatArray, h: FloatArray, terrain: Terrain | None) -> FloatArray:
    """The broad phase's band tops: a flat band's own (``zhi``), a seabed band's the highest seabed under
    its box plus its height.

    Parameters
    ----------
    b : numpy.ndarray
        The zones' bounding boxes ``(Z, 4)`` (m).
    zhi, h : numpy.ndarray
        Tops of flat bands (z up, m) and heights of seabed bands (``nan`` else), ``(Z,)``.
    terrain : Terrain or None
        The seabed of the seabed bands.

    Returns
    -------
    numpy.ndarray
        ``(Z,)`` (z up, m).
    """
    top = np.array(zhi, dtype=float)
    sea = np.flatnonzero(np.isfinite(h))
    if sea.size:  # a seabed band reaches the highest seabed under the zone's box plus its height
        assert terrain is not None
        t = terrain
        x, y, z = np.asarray(t.x), np.asarray(t.y), np.asarray(t.z)
        for k in sea:
            x0, y0, x1, y1 = b[k]
            i0, i1 = max(np.searchsorted(x, x0, "right") - 1, 0), min(np.searchsorted(x, x1, "left"), x.size - 1)
            j0, j1 = max(np.searchsorted(y, y0, "right") - 1, 0), min(np.searchsorted(y, y1, "left"), y.size - 1)
            top[k] = z[j0:j1 + 1, i0:i1 + 1].max() + h[k]
    return top


def distance_field(grid: tuple[Any, ...], polygons: tuple[FloatArray, IntArray, IntArray, FloatArray],
                   boxes: FloatArray, cells: float = 4e5, slabs: int | None = None) -> tuple[Any, ...]:
    """A lower bound of the horizontal distance to the footprints on a grid finer than the broad phase's, per
    depth slab (:mod:`.bound`) and for every zone.

    The fine cells split each broad-phase cell ``sub`` times along each axis (``sub`` up to 16, about
    ``cells`` fine cells in all).  Within ``R`` (six fine cells) of a footprint's box each fine cell
    holds its centre's exact distance to the nearest footprint (:func:`.bound.field_kernel`; in a slab's
    plane, of the zones whose band meets the slab) less half the cell's diagonal; everywhere it holds at
    least the distance from its centre to the centre of the nearest cell whose centre lies within half a
    diagonal of any footprint (every cell a footprint touches is one), less a diagonal (scipy's Euclidean
    distance transform, once for every plane: a slab's footprints are some of them).  A point ``p`` of cell
    ``c`` and a footprint point ``q`` of such a cell ``c'`` are at least ``|c - c'| - sqrt 2`` cells
    apart, so no value is above the true distance from any point of its cell.  Values are stored in
    units of ``f / 64`` (:data:`.bound.FIELD_UNITS`), rounded down, with a millionth of the grid's extent off.

    Parameters
    ----------
    grid : tuple
        :func:`rasterise`'s grid (its bands ``bottom``, ``top`` place the zones in the slabs).
    polygons : tuple
        :func:`rings` of the footprints.
    boxes : numpy.ndarray
        The footprints' bounding boxes ``(Z, 4)`` (m).
    cells : float, default 4e5
        About how many fine cells (at least one per broad-phase cell, at most 16 x 16 of them).  The
        answers do not depend on it, only the time: for 1 000 zones over 100 km (23 000 broad-phase
        cells) 4e5 builds in 0.07 s against 0.2 s at 1.5e6, and the swarm's pass over the same
        populations costs the same (``benchmarks/zones.py passes``).
    slabs : int, optional
        Depth slabs (:data:`.bound.SLABS` when absent; one when the bands' finite ends are all equal).  The
        answers do not depend on it either.

    Returns
    -------
    tuple
        ``(x0, y0, f, nx, ny, bound, z0, zinv, top)``: corner, fine cell size and counts, the bound
        ``(slabs + 1, ny, nx)`` in units of ``f / FIELD_UNITS`` (uint16; plane ``s`` for slab ``s``, the last
        for every zone), and the slabs (:func:`.bound._slab`: slab ``s`` holds ``z`` with
        ``s <= (z - z0) * zinv < s + 1``, the first and the last open, ``top`` the last).
    """
    from .bound import FIELD_UNITS, field_kernel

    x0, y0, cell, nx, ny, _, _, _, bottom, top = grid[:10]
    z0, zinv, count, lo, hi = _depth_slabs(bottom, top, slabs)
    sub = int(min(max(math.sqrt(cells / (nx * ny)), 1.0), 16.0))
    f = cell / sub
    near = 6.0 * f
    d = np.full((count + 1, ny * sub, nx * sub), near)
    xy, ring, rings_, _ = polygons
    field_kernel(xy, ring, rings_, np.ascontiguousarray(boxes, dtype=float), lo, hi, x0, y0, f, near, d)
    half = f * math.sqrt(0.5)
    far = (np.asarray(distance_transform(d[-1] > half), dtype=float) - math.sqrt(2.0)) * f
    slack = 1e-6 * max(abs(x0), abs(y0), abs(x0 + nx * cell), abs(y0 + ny * cell), cell)
    units = np.empty(d.shape, dtype=np.uint16)
    for s in range(count + 1):
        bound = np.maximum(np.minimum(d[s], near) - half, far) - slack
        units[s] = np.floor(np.clip(bound * (FIELD_UNITS / f), 0.0, 65535.0))
    return x0, y0, f, nx * sub, ny * sub, units, z0, zinv, count - 1


def _depth_slabs(bottom: FloatArray, top: FloatArray, slabs: int | None) -> tuple[float, float, int, IntArray,
                                                                                   IntArray]:
    """The depth slabs over the bands' finite ends (one when they are all equal): ``z0``, ``zinv``, their count,
    and each zone's first and last slab (:func:`.bound.slabs_kernel`)."""
    from .bound import SLABS, slabs_kernel

    ends = np.concatenate([bottom, top])
    ends = ends[np.isfinite(ends)]
    z0, z1 = (float(ends.min()), float(ends.max())) if ends.size else (0.0, 0.0)
    count = (SLABS if slabs is None else slabs) if z1 > z0 else 1
    zinv = count / (z1 - z0) if z1 > z0 else 0.0
    lo, hi = np.empty(bottom.size, dtype=np.intp), np.empty(bottom.size, dtype=np.intp)
    slabs_kernel(np.asarray(bottom, dtype=float), z0, zinv, count - 1, lo)
    slabs_kernel(np.asarray(top, dtype=float), z0, zinv, count - 1, hi)
    return z0, zinv, count, lo, hi


def inner_centres(geoms: np.ndarray) -> np.ndarray:
    """A point deep inside each polygon: the centre of its largest part's maximum inscribed circle (to 5 %
    of the part's size: 1 % costs 0.35 s for 1 000 zones, 5 % 0.06 s, the radius 3 % smaller at worst on
    Natural Earth's reefs), in one vectorised GEOS call.

    Parameters
    ----------
    geoms : numpy.ndarray of shapely geometries
        Polygons or multipolygons ``(Z,)``.

    Returns
    -------
    numpy.ndarray of shapely Points
        ``(Z,)``.
    """
    if geoms.size == 0:
        return np.zeros(0, dtype=object)
    parts, owner = shapely.get_parts(geoms, return_index=True)
    area = shapely.area(parts)
    order = np.lexsort((-area, owner))  # per polygon, its largest part first
    first = order[np.r_[True, owner[order][1:] != owner[order][:-1]]]
    big = parts[first]
    size = np.sqrt(np.maximum(area[first], 1e-12))
    return np.asarray(shapely.get_point(shapely.maximum_inscribed_circle(big, tolerance=0.05 * size), 0), dtype=object)


def rings(geoms: np.ndarray, centres: np.ndarray | None = None) -> tuple[FloatArray, IntArray, IntArray, FloatArray]:
    """Every polygon's rings as flat arrays for the compiled test, and two discs per polygon.

    Parameters
    ----------
    geoms : numpy.ndarray of shapely geometries
        Polygons or multipolygons ``(Z,)``.
    centres : numpy.ndarray of shapely Points, optional
        The discs' centres (:func:`inner_centres` of ``geoms`` or of polygons inside them: a padded
        zone reuses its footprint's); computed when absent.

    Returns
    -------
    xy : numpy.ndarray
        Vertices ``(V, 2)``, each ring closed.
    ring : numpy.ndarray of int
        Ring offsets ``(R + 1,)`` into ``xy``.
    rings : numpy.ndarray of int
        Per polygon ring offsets ``(Z + 1,)`` into ``ring``.
    disc : numpy.ndarray
        ``(Z, 10)``: a centre ``(x, y)`` (``centres``), a radius ``r_in`` within which every point is
        inside (the centre's distance to the boundary less a millionth, 0 for a centre outside) and a
        radius ``r_out`` holding every vertex (plus a millionth); then the same about a segment
        (:func:`capsules`): its ends ``(ax, ay, bx, by)``, ``c_in`` and ``c_out``.
    """
    xy_parts: list[FloatArray] = []
    ring = [0]
    rings = [0]
    for g in geoms:
        for poly in shapely.get_parts(g):
            for r in (poly.exterior, *poly.interiors):
                c = np.asarray(r.coords, dtype=float)[:, :2]
                xy_parts.append(c)
                ring.append(ring[-1] + c.shape[0])
        rings.append(len(ring) - 1)
    xy = np.ascontiguousarray(np.concatenate(xy_parts)) if xy_parts else np.zeros((0, 2))
    disc = np.zeros((len(geoms), 4))
    if len(geoms):
        geoms = np.asarray(geoms, dtype=object)
        centres = inner_centres(geoms) if centres is None else centres
        c = shapely.get_coordinates(centres)
        r_in = np.where(shapely.contains(geoms, centres), shapely.distance(centres, shapely.boundary(geoms)), 0.0)
        counts = shapely.get_num_coordinates(geoms)
        v = shapely.get_coordinates(geoms)
        owner = np.repeat(np.arange(len(geoms)), counts)
        r_out = np.zeros(len(geoms))
        np.maximum.at(r_out, owner, np.hypot(v[:, 0] - c[owner, 0], v[:, 1] - c[owner, 1]))
        scale = np.maximum.reduce([np.abs(c[:, 0]), np.abs(c[:, 1]), r_out, np.ones(len(geoms))])
        disc[:] = np.column_stack([c, np.maximum(r_in - 1e-6 * scale, 0.0), r_out + 1e-6 * scale])
    disc = np.ascontiguousarray(np.column_stack([disc, capsules(np.asarray(geoms, dtype=object))]))
    return xy, np.asarray(ring, dtype=np.intp), np.asarray(rings, dtype=np.intp), disc


def capsules(geoms: np.ndarray) -> FloatArray:
    """Two capsules about one segment per polygon, along the principal axis of its vertices and
    shortened by half the polygon's width across it at each end (a cable corridor's own line).

    Every point within ``c_in`` of the segment is inside the polygon (the segment's distance to the
    boundary less a millionth, when the polygon contains it and is at least twice as long as wide;
    else 0), and every vertex lies within ``c_out`` (plus a millionth).  A trace passing nearer than
    ``c_in`` enters the footprint, one passing further than ``c_out`` misses it: long thin
    footprints, where a disc settles nothing, are settled without their edges.

    Parameters
    ----------
    geoms : numpy.ndarray of shapely geometries
        Polygons or multipolygons ``(Z,)``.

    Returns
    -------
    numpy.ndarray
        ``(Z, 6)``: ``(ax, ay, bx, by, c_in, c_out)``.
    """
    out = np.zeros((len(geoms), 6))
    if not len(geoms):
        return out
    counts = shapely.get_num_coordinates(geoms)
    v, owner = shapely.get_coordinates(geoms), np.repeat(np.arange(len(geoms)), counts)
    z = len(geoms)
    n = np.maximum(counts, 1)[:, None]
    mean = np.column_stack([np.bincount(owner, v[:, 0], z), np.bincount(owner, v[:, 1], z)]) / n
    d = v - mean[owner]
    sxx, syy = np.bincount(owner, d[:, 0] ** 2, len(geoms)), np.bincount(owner, d[:, 1] ** 2, len(geoms))
    angle = 0.5 * np.arctan2(2.0 * np.bincount(owner, d[:, 0] * d[:, 1], len(geoms)), sxx - syy)
    u = np.column_stack([np.cos(angle), np.sin(angle)])
    along, across = np.einsum("ij,ij->i", d, u[owner]), d[:, 1] * u[owner, 0] - d[:, 0] * u[owner, 1]
    lo, hi, left, right = (np.full(len(geoms), x) for x in (np.inf, -np.inf, np.inf, -np.inf))
    np.minimum.at(lo, owner, along)
    np.maximum.at(hi, owner, along)
    np.minimum.at(left, owner, across)
    np.maximum.at(right, owner, across)
    width, mid = right - left, 0.5 * (left + right)
    s0, s1 = lo + 0.5 * width, hi - 0.5 * width
    s0, s1 = np.where(s1 > s0, s0, 0.5 * (lo + hi)), np.where(s1 > s0, s1, 0.5 * (lo + hi))
    normal = np.column_stack([-u[:, 1], u[:, 0]])
    a = mean + s0[:, None] * u + mid[:, None] * normal
    b = mean + s1[:, None] * u + mid[:, None] * normal
    # every vertex's distance to the segment
    e = b - a
    ee = np.maximum((e**2).sum(axis=1), 1e-300)
    t = np.clip(((v - a[owner]) * e[owner]).sum(axis=1) / ee[owner], 0.0, 1.0)
    c_out = np.zeros(len(geoms))
    np.maximum.at(c_out, owner, np.hypot(*(a[owner] + t[:, None] * e[owner] - v).T))
    c_in = np.zeros(len(geoms))
    thin = np.flatnonzero(hi - lo >= 2.0 * width)
    if thin.size:
        axis = shapely.linestrings(np.stack([a[thin], b[thin]], axis=1))
        g = geoms[thin]
        c_in[thin] = np.where(shapely.contains(g, axis), shapely.distance(axis, shapely.boundary(g)), 0.0)
    scale = np.maximum.reduce([np.abs(a).max(axis=1), np.abs(b).max(axis=1), c_out, np.ones(len(geoms))])
    out[:] = np.column_stack([a, b, np.maximum(c_in - 1e-6 * scale, 0.0), c_out + 1e-6 * scale])
    return out

def samples(legs: FloatArray, step: float, max_samples: int) -> FloatArray:
    """Points along legs, ends included.

    Parameters
    ----------
    legs : numpy.ndarray
        ``(K, 2, 3)`` (m).
    step : float
        Spacing (m).
    max_samples : int
        Most points per leg.

    Returns
    -------
    numpy.ndarray
        ``(M, 3)`` (m).
    """
    length = np.linalg.norm(legs[:, 1] - legs[:, 0], axis=-1)
    n = np.clip(np.ceil(length / step).astype(int) + 1, 2, max_samples)
    leg = np.repeat(np.arange(len(legs)), n)
    ends = np.cumsum(n)
    # np.linspace(0, 1, k) of every leg at once, to the bit: i * (1 / (k - 1)), the last exactly 1
    t = (np.arange(leg.size) - (ends - n)[leg]) * (1.0 / (n - 1))[leg]
    t[ends - 1] = 1.0
    out: FloatArray = legs[leg, 0] + t[:, None] * (legs[leg, 1] - legs[leg, 0])
    return out


def traces(seg: FloatArray) -> np.ndarray:
    """The horizontal traces of segments as shapely geometries.

    Parameters
    ----------
    seg : numpy.ndarray
        Segments ``(K, 2, >=2)`` (m).

    Returns
    -------
    numpy.ndarray of shapely geometries
        ``(K,)`` line strings (a point for a vertical segment).
    """
    xy = np.ascontiguousarray(seg[:, :, :2])
    out = np.empty(xy.shape[0], dtype=object)
    zero = np.all(xy[:, 0] == xy[:, 1], axis=-1)
    if (~zero).any():
        out[~zero] = shapely.linestrings(xy[~zero])
    if zero.any():
        out[zero] = shapely.points(xy[zero, 0])
    return out


def clip_params(seg: FloatArray, traces: np.ndarray, geoms: np.ndarray) -> tuple[FloatArray, FloatArray, IntArray]:
    """The parameter intervals of segments over their paired footprints (GEOS ``intersection``).

    Parameters
    ----------
    seg : numpy.ndarray
        Segments ``(K, 2, >=2)`` (m).
    traces : numpy.ndarray of shapely geometries
        Their horizontal traces ``(K,)`` (:func:`traces`).
    geoms : numpy.ndarray of shapely geometries
        The footprint paired with each ``(K,)``.

    Returns
    -------
    t0, t1 : numpy.ndarray
        ``(M,)`` each piece of a trace over its footprint is the segment over ``[t0, t1]`` (a vertical
        segment over its footprint: ``[0, 1]``).
    owner : numpy.ndarray of int
        ``(M,)`` the pair each piece belongs to.
    """
    cut = shapely.intersection(traces, geoms)
    parts, owner = shapely.get_parts(cut, return_index=True)
    keep = ~shapely.is_empty(parts)
    parts, owner = parts[keep], owner[keep].astype(np.intp)
    if owner.size == 0:
        return np.zeros(0), np.zeros(0), owner
    xy, part = shapely.get_coordinates(parts, return_index=True)
    o = owner[part]
    a, d = seg[o, 0, :2], seg[o, 1, :2] - seg[o, 0, :2]
    dd = np.einsum("ij,ij->i", d, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(dd > 0, np.einsum("ij,ij->i", xy - a, d) / dd, 0.0)
    t = np.clip(t, 0.0, 1.0)
    n = parts.size
    tmin = np.full(n, np.inf)
    tmax = np.full(n, -np.inf)
    np.minimum.at(tmin, part, t)
    np.maximum.at(tmax, part, t)
    vertical = np.all(seg[owner, 0, :2] == seg[owner, 1, :2], axis=-1)
    tmin[vertical], tmax[vertical] = 0.0, 1.0  # a vertical segment over the footprint: all of it
    return tmin, tmax, owner


def clip_pieces(seg: FloatArray, traces: np.ndarray, geoms: np.ndarray) -> tuple[FloatArray, IntArray]:
    """The 3D pieces of segments over their paired footprints (:func:`clip_params`).

    Parameters
    ----------
    seg : numpy.ndarray
        Segments ``(K, 2, 3)`` (m).
    traces : numpy.ndarray of shapely geometries
        Their horizontal traces ``(K,)`` (:func:`traces`).
    geoms : numpy.ndarray of shapely geometries
        The footprint paired with each ``(K,)``.

    Returns
    -------
    pieces : numpy.ndarray
        ``(M, 2, 3)`` straight sub-segments over the footprints (m).
    owner : numpy.ndarray of int
        ``(M,)`` the pair each piece belongs to.
    """
    tmin, tmax, owner = clip_params(seg, traces, geoms)
    if owner.size == 0:
        return np.zeros((0, 2, 3)), owner
    sa, sb = seg[owner, 0], seg[owner, 1]
    pieces = np.stack([sa + tmin[:, None] * (sb - sa), sa + tmax[:, None] * (sb - sa)], axis=1)
    return pieces, owner


def expand_groups(group: IntArray, wanted: IntArray) -> tuple[IntArray, IntArray]:
    """Every (entry of ``wanted``, member of its group) pair.

    Parameters
    ----------
    group : numpy.ndarray of int
        ``(N,)`` the group of each member.
    wanted : numpy.ndarray of int
        ``(M,)`` groups asked for (repeats allowed).

    Returns
    -------
    which, member : numpy.ndarray of int
        The index into ``wanted`` and the member, one row per pair.
    """
    order = np.argsort(group, kind="stable")
    counts = np.bincount(group, minlength=int(wanted.max(initial=-1)) + 1)
    first = np.cumsum(counts) - counts
    size = counts[wanted]
    which = np.repeat(np.arange(wanted.size), size)
    offset = np.arange(which.size) - np.repeat(np.cumsum(size) - size, size)
    return which, order[first[wanted][which] + offset]
