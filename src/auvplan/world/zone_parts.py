"""Geometry helpers of :mod:`auvplan.world.zones`: the broad phase's grid, polygons as flat arrays for the
compiled tests, horizontal traces, clipped pieces and samples along legs."""

from __future__ import annotations

from typing import Any

import numpy as np
import shapely

from .._types import FloatArray, IntArray
from .terrain import Terrain

__all__ = ["rasterise", "rings", "samples", "traces", "clip_pieces"]


def rasterise(b: FloatArray, tree: shapely.STRtree, zlo: FloatArray, zhi: FloatArray, h: FloatArray,
              terrain: Terrain | None) -> tuple[Any, ...]:
    """The broad phase's grid (:mod:`.zone_kernels`): the zones listed per cell, each zone's bounding
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
    from scipy.ndimage import distance_transform_edt

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
    top = zhi.copy()
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
    bottom = np.where(np.isfinite(h), -np.inf, zlo)
    flagged = np.diff(start) > 0
    reach = distance_transform_edt(~flagged.reshape(ny, nx))
    return (float(lo[0]), float(lo[1]), cell, nx, ny, start, zi.astype(np.intp), np.ascontiguousarray(b), bottom,
            top, np.asarray(reach, dtype=float))


def rings(geoms: np.ndarray) -> tuple[FloatArray, IntArray, IntArray]:
    """Every polygon's rings as flat arrays for the compiled test.

    Parameters
    ----------
    geoms : numpy.ndarray of shapely geometries
        Polygons or multipolygons ``(Z,)``.

    Returns
    -------
    xy : numpy.ndarray
        Vertices ``(V, 2)``, each ring closed.
    ring : numpy.ndarray of int
        Ring offsets ``(R + 1,)`` into ``xy``.
    rings : numpy.ndarray of int
        Per polygon ring offsets ``(Z + 1,)`` into ``ring``.
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
    return xy, np.asarray(ring, dtype=np.intp), np.asarray(rings, dtype=np.intp)


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
    t = np.concatenate([np.linspace(0.0, 1.0, k) for k in n])
    leg = np.repeat(np.arange(len(legs)), n)
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


def clip_pieces(seg: FloatArray, traces: np.ndarray, geoms: np.ndarray) -> tuple[FloatArray, IntArray]:
    """The 3D pieces of segments over their paired footprints.

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
    cut = shapely.intersection(traces, geoms)
    parts, owner = shapely.get_parts(cut, return_index=True)
    keep = ~shapely.is_empty(parts)
    parts, owner = parts[keep], owner[keep]
    if owner.size == 0:
        return np.zeros((0, 2, 3)), owner.astype(np.intp)
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
    sa, sb = seg[owner, 0], seg[owner, 1]
    vertical = np.all(sa[:, :2] == sb[:, :2], axis=-1)
    tmin[vertical], tmax[vertical] = 0.0, 1.0  # a vertical segment over the footprint: all of it
    pieces = np.stack([sa + tmin[:, None] * (sb - sa), sa + tmax[:, None] * (sb - sa)], axis=1)
    return pieces, owner.astype(np.intp)
