"""Lines and polygons cut at the antimeridian for the GeoJSON and KML exports, and joined again when read back.

A line from 179.9° to -179.9° written as it is is drawn the long way round the Earth by a viewer that joins
longitudes on a plane (QGIS, Leaflet, OpenLayers, ``geojson.io``).  RFC 7946 §3.1.9: "any geometry that crosses the
antimeridian SHOULD be represented by cutting it in two such that neither part's representation crosses the
antimeridian": a ``MultiLineString`` (``MultiPolygon``).  KML's longitudes are ``kml:angle180Type`` (``-180 ≤ λ ≤
180`` in the OGC KML 2.2 schema; a parser that validates refuses 180.1, e.g. GeoToolkit's ``Angle180``), so the safe
form there is the same cut, a ``MultiGeometry`` of ``LineString`` (``Polygon``) pieces, rather than longitudes beyond
180° which Google Earth alone draws.

:func:`cut_line` ends each piece at the crossing (its latitude and altitude interpolated linearly in degrees) on
±180° and starts the next at ∓180°; :func:`join_line` reads the pieces back, dropping each such pair (a point on the
antimeridian ending one piece and the same point starting the next: the cut, not a waypoint), so that the mission
read back has the waypoints written.  :func:`cut_ring` / :func:`join_rings` do the same for an envelope's polygon.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import shapely
from numpy.typing import ArrayLike

from ..._types import FloatArray

__all__ = ["cut_line", "join_line", "cut_ring", "join_rings", "crosses"]

_ON_EDGE_DEG = 1e-9
"""A longitude within this of ±180° is on the antimeridian (the exports write 9 decimals)."""


def crosses(lon: ArrayLike) -> bool:
    """Whether a line through these longitudes (degrees in [-180, 180]) crosses the antimeridian.

    Parameters
    ----------
    lon : array_like
        ``(N,)`` longitudes (degrees).

    Returns
    -------
    bool
        Some step between consecutive points is longer than 180° (the short way round is across ±180°).
    """
    d = np.abs(np.diff(np.asarray(lon, dtype=float)))
    return bool(np.any(d > 180.0))


def cut_line(coords: ArrayLike) -> list[FloatArray]:
    """A line cut at the antimeridian into pieces none of whose steps crosses it (module notes).

    Parameters
    ----------
    coords : array_like
        ``(N, k)`` points ``[lon, lat, ...]`` (degrees in [-180, 180]; the other columns, e.g. the altitude,
        interpolated at a cut too).

    Returns
    -------
    list of numpy.ndarray
        The pieces, in order: one (the line) when it does not cross; else each ends on ±180° at the crossing and the
        next starts at the same point on ∓180°.
    """
    p = np.asarray(coords, dtype=float)
    if p.shape[0] < 2 or not crosses(p[:, 0]):
        return [p.copy()]
    pieces: list[list[FloatArray]] = [[p[0]]]
    for a, b in zip(p[:-1], p[1:], strict=True):
        step = b[0] - a[0]
        if abs(step) > 180.0:
            edge = math.copysign(180.0, a[0])  # a's side; b unwrapped beside it, past the edge
            b_un = b.copy()
            b_un[0] = b[0] + (360.0 if step < 0.0 else -360.0)
            span = b_un[0] - a[0]
            t = (edge - a[0]) / span if span != 0.0 else 0.0  # 180 to -180: one meridian, cut at a
            c = a + t * (b_un - a)
            c[0] = edge
            pieces[-1].append(c)
            d = c.copy()
            d[0] = -edge
            pieces.append([d])
        pieces[-1].append(b)
    return [np.array(q) for q in pieces]


def join_line(pieces: Sequence[ArrayLike], z_tol: float = 1e-3) -> FloatArray:
    """The line a cut wrote as pieces (:func:`cut_line`), its cut points dropped.

    Parameters
    ----------
    pieces : sequence of array_like
        ``(k_i, m)`` points ``[lon, lat, ...]`` each.
    z_tol : float, optional
        How far the other columns (the altitude, m) of the two points of a cut may differ (the file's rounding).

    Returns
    -------
    numpy.ndarray
        ``(N, m)`` the pieces in order; where one ends on ±180° and the next starts at the same latitude (and
        altitude) on ±180°, both points are dropped (the cut, not a waypoint); other pieces are joined end to end.
    """
    arrs = [np.asarray(q, dtype=float) for q in pieces]
    arrs = [a.reshape(-1, a.shape[-1]) if a.ndim else a.reshape(0, 1) for a in arrs]
    out = [arrs[0]]
    for b in arrs[1:]:
        a = out[-1]
        if a.shape[0] and b.shape[0] and _same_cut(a[-1], b[0], z_tol):
            out[-1] = a[:-1]
            b = b[1:]
        out.append(b)
    return np.vstack(out) if out else np.empty((0, 3))


def _same_cut(a: FloatArray, b: FloatArray, z_tol: float) -> bool:
    on_edge = abs(abs(a[0]) - 180.0) <= _ON_EDGE_DEG and abs(abs(b[0]) - 180.0) <= _ON_EDGE_DEG
    return bool(on_edge and a.size == b.size and abs(a[1] - b[1]) <= _ON_EDGE_DEG
                and np.all(np.abs(a[2:] - b[2:]) <= z_tol))


def cut_ring(lon: ArrayLike, lat: ArrayLike) -> list[FloatArray]:
    """A polygon (its ring, not closed) cut at the antimeridian into polygons that do not cross it.

    The ring is the small one: its longitudes are unwrapped along it (each edge the short way round, as the
    check reads an envelope), then the pieces on either side of ±180° are cut out and moved back by 360°.

    Parameters
    ----------
    lon, lat : array_like
        ``(N,)`` the ring's vertices (degrees).

    Returns
    -------
    list of numpy.ndarray
        ``(k_i, 2)`` ``[lon, lat]`` rings (not closed): the ring itself when it does not cross.
    """
    lo = np.asarray(lon, dtype=float)
    la = np.asarray(lat, dtype=float)
    ring = np.column_stack([lo, la])
    if not crosses(np.r_[lo, lo[:1]]):
        return [ring]
    un = lo[0] + np.r_[0.0, np.cumsum((np.diff(lo) + 180.0) % 360.0 - 180.0)]
    poly = shapely.Polygon(np.column_stack([un, la]))
    out = []
    for k in (-360.0, 0.0, 360.0):
        part = shapely.intersection(poly, shapely.box(-180.0 + k, -90.0, 180.0 + k, 90.0))
        for g in shapely.get_parts(part):
            if isinstance(g, shapely.Polygon) and g.area > 0.0:
                xy = np.asarray(g.exterior.coords)[:-1]
                out.append(np.column_stack([xy[:, 0] - k, xy[:, 1]]))
    return out


def join_rings(rings: Sequence[ArrayLike]) -> FloatArray:
    """The polygon a cut wrote as pieces (:func:`cut_ring`): ``[lon, lat]`` rings (closed or not) joined.

    Parameters
    ----------
    rings : sequence of array_like
        ``(k_i, 2)`` each (degrees).

    Returns
    -------
    numpy.ndarray
        ``(N, 2)`` the ring (not closed), longitudes in [-180, 180); the vertices the cut added on ±180° (on a
        straight edge in degrees) removed.  One ring is returned as it is (not closed).
    """
    arrs = [np.asarray(r, dtype=float)[:, :2] for r in rings]
    arrs = [a[:-1] if a.shape[0] > 1 and np.array_equal(a[0], a[-1]) else a for a in arrs]
    if len(arrs) == 1:
        return arrs[0]
    ref = float(arrs[0][0, 0])
    polys = []
    for a in arrs:  # each piece moved beside the first (by whole turns)
        shift = 360.0 * round((float(np.mean(a[:, 0])) - ref) / 360.0)
        polys.append(shapely.Polygon(np.column_stack([a[:, 0] - shift, a[:, 1]])))
    union = shapely.union_all(polys)
    if not isinstance(union, shapely.Polygon):  # pieces that do not meet: the largest
        union = max(shapely.get_parts(union), key=lambda g: g.area)
    xy = np.asarray(shapely.simplify(union, 1e-8).exterior.coords)[:-1]
    return np.column_stack([(xy[:, 0] + 180.0) % 360.0 - 180.0, xy[:, 1]])
