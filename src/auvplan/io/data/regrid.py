"""Gridded data resampled into the local frame: :func:`to_local` onto a rectilinear grid in the scenario's
frame (pyproj for every transformation), the largest local rectangle inside a grid's footprint
(:func:`inscribed_extent`) and the span of the data (:func:`data_span`).

Coverage is checked exactly on the target nodes with a tolerance of 1e-6 of a source cell, and an uncovered
extent is reported with the side (north, south, east, west) that is missing.  The grids themselves are read
by :mod:`auvplan.io.data.grids`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ...errors import DataError
from ...optim.bounded_min import bounded_min
from ..files.limits import BYTES_PER_TERRAIN_NODE, BudgetError, check, current, grid_nodes
from .geo import LocalFrame, normalise_lon
from .grids import _F64, HorizontalGrid

if TYPE_CHECKING:  # where a file is projected (issue 56)
    from pyproj import Transformer

__all__ = ["covered_source", "data_span", "to_local", "inscribed_extent"]


@functools.lru_cache(maxsize=16)
def _transformer(src: Any, dst: Any) -> Transformer:
    """pyproj's transformation ``src`` → ``dst`` (lon/lat order), built once per pair: building one costs ~30 ms
    and :func:`inscribed_extent`'s edge search transforms some 300 times per grid (Transformer objects are
    thread-safe since pyproj 3.1)."""
    from pyproj import Transformer

    return Transformer.from_crs(src, dst, always_xy=True)


def _to_source(grid: HorizontalGrid, frame: LocalFrame, x: ArrayLike, y: ArrayLike) -> tuple[_F64, _F64]:
    """Local x, y → (row, col) coordinates of the source grid (lat/lon or projected y/x)."""
    lon, lat = frame.inverse(x, y)
    if grid.kind == "projected":
        cx, cy = _transformer("EPSG:4326", grid.crs).transform(lon, lat)
        return np.asarray(cy), np.asarray(cx)
    # longitudes within 180 degrees of the data's middle: a point just west of the data stays west of it
    c0 = 0.5 * float(grid.cols[0] + grid.cols[-1]) - 180.0
    return np.asarray(lat), c0 + np.mod(np.asarray(lon) - c0, 360.0)


def _from_source(grid: HorizontalGrid, frame: LocalFrame, r: ArrayLike, c: ArrayLike) -> tuple[_F64, _F64]:
    if grid.kind == "projected":
        lon, lat = _transformer(grid.crs, "EPSG:4326").transform(np.asarray(c, dtype=float), np.asarray(r, dtype=float))
        return frame.forward(lon, lat)
    if grid.kind == "local":
        return np.asarray(c, dtype=float), np.asarray(r, dtype=float)
    return frame.forward(c, r)


def inscribed_extent(grid: HorizontalGrid, frame: LocalFrame) -> tuple[float, float, float, float]:
    """Largest axis-aligned local rectangle inside the data's footprint.

    Each side is the extreme of the projected edge found by sampling and then refined by Brent's
    bounded minimisation (:func:`~auvplan.optim.bounded_min.bounded_min`), and moved 1 mm inwards;
    curvilinear grids use their outer node rows.

    Parameters
    ----------
    grid : HorizontalGrid
        The data's nodes.
    frame : LocalFrame
        The local frame.

    Returns
    -------
    tuple of 4 float
        ``(xmin, xmax, ymin, ymax)`` in the local frame (m).
    """
    if grid.kind == "local":
        return float(grid.cols[0]), float(grid.cols[-1]), float(grid.rows[0]), float(grid.rows[-1])
    if grid.kind == "curvilinear":
        x, y = frame.forward(grid.cols, grid.rows)
        rect = float(x[:, 0].max()), float(x[:, -1].min()), float(y[0, :].max()), float(y[-1, :].min())
        ring_x = np.r_[x[0, :], x[1:, -1], x[-1, -2::-1], x[-2:0:-1, 0]]
        ring_y = np.r_[y[0, :], y[1:, -1], y[-1, -2::-1], y[-2:0:-1, 0]]
        return _inside_ring(ring_x, ring_y, rect)
    r0, r1, c0, c1 = grid.rows[0], grid.rows[-1], grid.cols[0], grid.cols[-1]
    edges = {  # (fixed coordinate, which local component, sign of the extreme: +1 max, -1 min)
        "west": (lambda s: (r0 + s * (r1 - r0), c0), 0, 1.0),
        "east": (lambda s: (r0 + s * (r1 - r0), c1), 0, -1.0),
        "south": (lambda s: (r0, c0 + s * (c1 - c0)), 1, 1.0),
        "north": (lambda s: (r1, c0 + s * (c1 - c0)), 1, -1.0),
    }
    out = {}
    for side, (edge, comp, sign) in edges.items():
        def f(s: ArrayLike, edge: Callable[[_F64], tuple[Any, Any]] = edge, comp: int = comp,
              sign: float = sign) -> _F64:
            r, c = np.broadcast_arrays(*edge(np.asarray(s, dtype=float)))
            return -sign * _from_source(grid, frame, r, c)[comp]
        s = np.linspace(0.0, 1.0, 201)
        vals = f(s)
        k = int(np.argmin(vals))
        lo, hi = s[max(k - 1, 0)], s[min(k + 1, s.size - 1)]
        # scipy.optimize's bounded Brent, step for step, without importing scipy.optimize (issue 56)
        _, fun, _ = bounded_min(lambda q: float(f(q)), lo, hi, xatol=1e-12)
        best = min(float(vals[k]), fun)
        out[side] = -sign * best + sign * 1e-3
    return _inside_footprint(grid, frame, (out["west"], out["east"], out["south"], out["north"]))


def _inside_footprint(grid: HorizontalGrid, frame: LocalFrame,
                      rect: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """``rect`` when it lies inside the data's projected footprint; otherwise (a grid turned far from the local
    axes, e.g. a polar-stereographic forecast far from its central meridian) the largest rectangle of the
    footprint's bounding-box proportions about its centroid that does (bisection on the scale)."""
    s = np.linspace(0.0, 1.0, 201)
    r0, r1, c0, c1 = grid.rows[0], grid.rows[-1], grid.cols[0], grid.cols[-1]
    ring_r = np.r_[np.full_like(s, r0), r0 + s * (r1 - r0), np.full_like(s, r1), r1 - s * (r1 - r0)]
    ring_c = np.r_[c0 + s * (c1 - c0), np.full_like(s, c1), c1 - s * (c1 - c0), np.full_like(s, c0)]
    px, py = _from_source(grid, frame, ring_r, ring_c)
    return _inside_ring(px, py, rect)


def _inside_ring(px: _F64, py: _F64, rect: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """``rect`` if inside the ring's polygon, else the largest one of the polygon's proportions about its centroid."""
    import shapely

    poly = shapely.Polygon(np.column_stack([px, py])).buffer(-1e-3)
    if poly.is_empty:  # a footprint under a millimetre wide (axes 1e-12° apart): its centroid was a GEOS traceback
        return rect  # the caller refuses it (an empty extent, or a cell far under the memory budget), naming it
    if rect[0] < rect[1] and rect[2] < rect[3] and poly.contains(shapely.box(rect[0], rect[2], rect[1], rect[3])):
        return rect
    cx, cy = poly.centroid.x, poly.centroid.y
    bx0, by0, bx1, by1 = poly.bounds
    w, h = bx1 - bx0, by1 - by0
    lo, hi = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if poly.contains(shapely.box(cx - mid * w / 2, cy - mid * h / 2, cx + mid * w / 2, cy + mid * h / 2)):
            lo = mid
        else:
            hi = mid
    return cx - lo * w / 2, cx + lo * w / 2, cy - lo * h / 2, cy + lo * h / 2


def _uncovered(grid: HorizontalGrid, qr: _F64, qc: _F64, tol_r: float, tol_c: float) -> list[str]:
    sides = []
    names = ("south", "north", "west", "east")
    tests = (qr < grid.rows[0] - tol_r, qr > grid.rows[-1] + tol_r, qc < grid.cols[0] - tol_c,
             qc > grid.cols[-1] + tol_c)
    for side, bad in zip(names, tests):
        if np.any(bad):
            sides.append(side)
    return sides


def data_span(grid: HorizontalGrid) -> str:
    """Describe the grid's extent for messages.

    Parameters
    ----------
    grid : HorizontalGrid
        The data's nodes.

    Returns
    -------
    str
        Latitude/longitude ranges (degrees), or x/y ranges (m).
    """
    if grid.kind in ("lonlat", "curvilinear"):
        r, c = np.asarray(grid.rows), np.asarray(grid.cols)
        return (f"lat {np.min(r):.4f}..{np.max(r):.4f}, lon {normalise_lon(np.min(c)):.4f}.."
                f"{normalise_lon(np.max(c)):.4f}")
    return f"y {grid.rows[0]:.0f}..{grid.rows[-1]:.0f}, x {grid.cols[0]:.0f}..{grid.cols[-1]:.0f} m"


def to_local(
    grid: HorizontalGrid,
    values: ArrayLike,
    frame: LocalFrame,
    *,
    extent_m: tuple[float, float, float, float] | None = None,
    cell_m: float | None = None,
    method: str = "linear",
    what: str = "grid",
) -> tuple[_F64, _F64, _F64]:
    """Resample ``values (..., nrow, ncol)`` on ``grid`` onto a rectilinear grid in ``frame``.

    Parameters
    ----------
    grid : HorizontalGrid
        Source node positions.
    values : ndarray
        Data; leading axes (time, depth, component) are carried along.
    frame : LocalFrame
        Target frame.
    extent_m : (xmin, xmax, ymin, ymax) or None
        Target extent; by default the largest rectangle inside the data.
    cell_m : float or None
        Target cell size; by default the data's own spacing at its centre.
    method : str
        ``RegularGridInterpolator`` method (``"linear"``, ``"cubic"`` …); curvilinear grids are
        always interpolated linearly on a Delaunay triangulation of their nodes.
    what : str
        Name used in error messages.

    Returns
    -------
    x, y, out : ndarray
        Metric axes and resampled values ``(..., ny, nx)``.
    """
    vals = np.asarray(values, dtype=float)
    x, y = _target_axes(grid, frame, extent_m, cell_m, what, math.prod(vals.shape[:-2]))
    gx, gy = np.meshgrid(x, y)
    lead = vals.shape[:-2]
    flat = vals.reshape(-1, *vals.shape[-2:])
    if grid.kind == "curvilinear":
        out = _from_curvilinear(grid, frame, flat, gx, gy, what)
    else:
        out = _from_rectilinear(grid, frame, flat, gx, gy, method, what)
    return x, y, out.reshape(*lead, y.size, x.size)


def _target_axes(grid: HorizontalGrid, frame: LocalFrame, extent_m: tuple[float, float, float, float] | None,
                 cell_m: float | None, what: str, layers: int = 1) -> tuple[_F64, _F64]:
    """The local grid's axes: the extent (default: the largest rectangle inside the data) at the cell size,
    refused before they are made when the local grid is over the memory budget (``layers`` values a node)."""
    if extent_m is None:
        extent_m = inscribed_extent(grid, frame)
    x0, x1, y0, y1 = extent_m
    if not (x0 < x1 and y0 < y1):
        raise DataError(f"{what}: empty extent {extent_m} after projection")
    native = cell_m is None
    if cell_m is None:
        cell_m = _native_cell(grid)
    if not cell_m > 0:
        raise DataError(f"{what}: cell size must be positive, got {cell_m}")
    nodes = grid_nodes(x1 - x0, y1 - y0, cell_m)
    check(current(), f"{what}:", f"resampling {_extent_m_text(extent_m)} at a cell of {cell_m:.3g} m "
          f"({'the data’s own spacing' if native else 'as asked'}; {nodes:.3g} nodes × {layers} layer(s)), which",
          nodes * (BYTES_PER_TERRAIN_NODE + 16.0 * layers), error=BudgetError,
          hint=("do the coordinates hold the units of the CRS the file declares (degrees labelled as metres, a "
                "geocentric CRS)? Or set a coarser [terrain] resample_m" if native else
                "set a coarser resample_m, or raise [limits] memory_mb"))
    nx = max(int(round((x1 - x0) / cell_m)) + 1, 2)
    ny = max(int(round((y1 - y0) / cell_m)) + 1, 2)
    return np.linspace(x0, x1, nx), np.linspace(y0, y1, ny)


def _extent_m_text(e: tuple[float, float, float, float]) -> str:
    return f"x [{e[0]:.6g}, {e[1]:.6g}] y [{e[2]:.6g}, {e[3]:.6g}] m"


def _extent_text(gx: _F64, gy: _F64) -> str:
    return f"x [{gx[0, 0]:.0f}, {gx[0, -1]:.0f}] y [{gy[0, 0]:.0f}, {gy[-1, 0]:.0f}] m"


def _from_curvilinear(grid: HorizontalGrid, frame: LocalFrame, flat: _F64, gx: _F64, gy: _F64, what: str) -> _F64:
    """Layers ``flat (L, nrow, ncol)`` at the local nodes: linear on one Delaunay triangulation of the nodes."""
    sx, sy = frame.forward(grid.cols, grid.rows)
    pts = np.column_stack([np.ravel(sx), np.ravel(sy)])
    q = np.column_stack([gx.ravel(), gy.ravel()])
    # one triangulation for every layer: values (npoints, layers)
    from scipy.interpolate import LinearNDInterpolator  # imported when used (#56)

    out: _F64 = LinearNDInterpolator(pts, flat.reshape(flat.shape[0], -1).T)(q).T
    if np.isnan(out).any():
        raise DataError(f"{what}: the curvilinear data ({data_span(grid)}) do not cover the requested extent "
                        f"{_extent_text(gx, gy)}")
    return out


def covered_source(grid: HorizontalGrid, frame: LocalFrame, gx: _F64, gy: _F64, what: str) -> tuple[_F64, _F64]:
    """Source (row, column) coordinates of the local nodes ``(gx, gy)`` of a rectilinear grid, checked to lie
    within the data (1e-6 of a cell); an uncovered side is a :class:`~auvplan.errors.DataError` naming it.

    Parameters
    ----------
    grid : HorizontalGrid
        A rectilinear grid (``lonlat``, ``projected`` or ``local``).
    frame : LocalFrame
        The local frame.
    gx, gy : numpy.ndarray
        Local node coordinates (m), same shape.
    what : str
        Name used in error messages.

    Returns
    -------
    qr, qc : numpy.ndarray
        Row and column coordinates in the data's own units, the shape of ``gx``.
    """
    if grid.kind == "local":
        qr, qc = gy, gx
    else:
        qr, qc = _to_source(grid, frame, gx, gy)
    tol_r = 1e-6 * float(np.min(np.diff(grid.rows)))
    tol_c = 1e-6 * float(np.min(np.diff(grid.cols)))
    sides = _uncovered(grid, qr, qc, tol_r, tol_c)
    if sides:
        raise DataError(
            f"{what}: the data ({data_span(grid)}) do not cover the requested extent {_extent_text(gx, gy)}: "
            f"uncovered on the {' and '.join(sides)} side{'s' if len(sides) > 1 else ''}"
        )
    return qr, qc


def _from_rectilinear(grid: HorizontalGrid, frame: LocalFrame, flat: _F64, gx: _F64, gy: _F64, method: str,
                      what: str) -> _F64:
    """Layers ``flat (L, nrow, ncol)`` at the local nodes: one ``RegularGridInterpolator`` per layer."""
    qr, qc = (a.ravel() for a in covered_source(grid, frame, gx, gy, what))
    if method in ("cubic", "quintic", "pchip") and min(grid.rows.size, grid.cols.size) < 4:
        method = "linear"
    q = np.column_stack([np.clip(qr, grid.rows[0], grid.rows[-1]), np.clip(qc, grid.cols[0], grid.cols[-1])])
    from scipy.interpolate import RegularGridInterpolator  # imported when used (#56)

    out = np.empty((flat.shape[0], q.shape[0]))
    for k in range(flat.shape[0]):  # one interpolator per 2-D layer (time/depth/component)
        out[k] = RegularGridInterpolator((grid.rows, grid.cols), flat[k], method=method)(q)
    return out


def _native_cell(grid: HorizontalGrid) -> float:
    """The data's own node spacing (m) at its centre."""
    if grid.kind in ("projected", "local"):
        deg = 111_320.0 if grid.crs is not None and grid.crs.is_geographic else 1.0  # rotated pole: degrees
        return deg * float(min(np.median(np.diff(grid.rows)), np.median(np.diff(grid.cols))))
    lat, lon = np.asarray(grid.rows), np.asarray(grid.cols)
    if grid.kind == "curvilinear":
        dlat = float(np.median(np.abs(np.diff(lat, axis=0)))) * 111_320.0
        dlon = float(np.median(np.abs(np.diff(lon, axis=1)))) * 111_320.0 * np.cos(np.deg2rad(np.mean(lat)))
        return min(d for d in (dlat, dlon) if d > 0)
    mid_lat = np.deg2rad(0.5 * (lat[0] + lat[-1]))
    dlat = float(np.median(np.diff(lat))) * 111_320.0
    dlon = float(np.median(np.diff(lon))) * 111_320.0 * np.cos(mid_lat)
    return float(min(dlat, dlon))
