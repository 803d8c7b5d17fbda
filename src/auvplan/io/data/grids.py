"""Horizontal grids of gridded data files and their projection into the local frame.

Every layout that GEBCO, ETOPO 2022, EMODnet, GMT, Ferret, CMEMS, HYCOM, ROMS
and GDAL write is reduced to one :class:`HorizontalGrid`:

* ``lonlat`` — 1-D longitude and latitude axes, from dimension coordinates or,
  in the Ferret/GMT layout, from 1-D data variables on coordinate-less
  dimensions (``lat(y)``, ``lon(x)``), or from 2-D ``lat(y, x)``/``lon(y, x)``
  variables that turn out to be rectilinear;
* ``curvilinear`` — truly 2-D longitude/latitude (ROMS, tripolar grids);
* ``projected`` — 1-D x/y axes in a coordinate reference system (a CF
  ``grid_mapping`` variable, or a GeoTIFF's CRS), e.g. UTM;
* ``local`` — 1-D metric x/y axes without a CRS, taken as the scenario's own frame.

:func:`to_local` resamples values on any of them onto a rectilinear grid in the
local frame (pyproj for every transformation).  Coverage is checked exactly on
the target nodes with a tolerance of 1e-6 of a source cell, and an uncovered
extent is reported with the side (north, south, east, west) that is missing.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS, Transformer
from scipy.interpolate import LinearNDInterpolator, RegularGridInterpolator
from scipy.optimize import minimize_scalar

from ...errors import DataError
from ..limits import BYTES_PER_TERRAIN_NODE, BudgetError, check, check_declared, current, grid_nodes
from .geo import LocalFrame, normalise_lon

__all__ = ["HorizontalGrid", "crs_line", "axis_kind", "data_span", "horizontal_grid", "to_local", "inscribed_extent"]

_F64 = NDArray[np.float64]
"""Array of float64."""

_LON_UNITS = {"degrees_east", "degree_east", "degree_e", "degrees_e", "degreee", "degreese"}
_LAT_UNITS = {"degrees_north", "degree_north", "degree_n", "degrees_n", "degreen", "degreesn"}
_METRES = {"m": 1.0, "metre": 1.0, "meter": 1.0, "metres": 1.0, "meters": 1.0, "km": 1000.0, "": 1.0}


def _attr(obj: xr.Dataset | xr.DataArray | xr.Variable | None, name: str) -> str:
    return str(obj.attrs.get(name, "")).strip().lower() if obj is not None else ""


def axis_kind(var: xr.DataArray | None, name: str) -> str:
    """Classify a coordinate variable from its CF attributes, then its name.

    Parameters
    ----------
    var : xarray.DataArray or None
        The coordinate variable; None for a bare dimension.
    name : str
        The variable's or dimension's name.

    Returns
    -------
    str
        ``'lon'``, ``'lat'``, ``'x'``, ``'y'``, ``'t'``, ``'z'`` or ``''`` (unknown).
    """
    std = _attr(var, "standard_name")
    units = _attr(var, "units").replace(" ", "")
    long_name = _attr(var, "long_name")
    axis = _attr(var, "axis")
    n = name.lower()
    if var is not None and np.issubdtype(var.dtype, np.datetime64):
        return "t"
    if std == "time" or axis == "t" or n in ("time", "t") or " since " in _attr(var, "units"):
        return "t"
    if std == "grid_longitude":  # a rotated pole's axes: coordinates of its grid_mapping, not longitude
        return "x"
    if std == "grid_latitude":
        return "y"
    if std == "longitude" or units in _LON_UNITS or n in ("lon", "longitude", "long", "nav_lon") \
            or long_name == "longitude":
        return "lon"
    if std == "latitude" or units in _LAT_UNITS or n in ("lat", "latitude", "nav_lat") or long_name == "latitude":
        return "lat"
    if std == "projection_x_coordinate" or axis == "x" or n in ("x", "easting", "east", "xc"):
        return "x" if units in _METRES else ("lon" if units.startswith("deg") else "")
    if std == "projection_y_coordinate" or axis == "y" or n in ("y", "northing", "north", "yc"):
        return "y" if units in _METRES else ("lat" if units.startswith("deg") else "")
    if std in ("depth", "height", "altitude") or axis == "z" or n in ("depth", "z", "lev", "level", "deptht",
                                                                       "height", "elevation", "s_rho"):
        return "z"
    return ""


@dataclass(frozen=True, eq=False)
class HorizontalGrid:
    """Where the nodes of a 2-D field lie (rows first, ascending 1-D axes except ``curvilinear``).

    Attributes
    ----------
    kind : str
        ``"lonlat"``, ``"curvilinear"``, ``"projected"`` or ``"local"``.
    rows, cols : ndarray
        Latitude/y and longitude/x of the nodes: 1-D ascending axes, or 2-D ``(nrow, ncol)``
        arrays for ``curvilinear``.  Longitudes of ``lonlat`` are unwrapped to be monotonic.
    crs : pyproj.CRS or None
        The projection of a ``projected`` grid.
    layout : str
        Human-readable description of how the axes were found (for ``data inspect``).
    """

    kind: str
    rows: np.ndarray
    cols: np.ndarray
    crs: CRS | None = None
    layout: str = ""

    def describe(self) -> str:
        """Describe the grid in one line: kind, axes ranges and sizes.

        Returns
        -------
        str
            The description.
        """
        r, c = np.asarray(self.rows), np.asarray(self.cols)
        if self.kind in ("lonlat", "curvilinear"):
            span = (f"lat {np.nanmin(r):.5f}..{np.nanmax(r):.5f}, lon {normalise_lon(np.nanmin(c)):.5f}.."
                    f"{normalise_lon(np.nanmax(c)):.5f}")
        else:
            span = f"y {np.nanmin(r):.1f}..{np.nanmax(r):.1f}, x {np.nanmin(c):.1f}..{np.nanmax(c):.1f} m"
        crs = f", CRS {crs_line(self.crs)}" if self.crs is not None else ""
        return f"{self.kind} grid {r.shape[0]} x {c.shape[-1]} ({self.layout}); {span}{crs}"


def crs_line(crs: CRS) -> str:
    """A CRS in one short line: its name and authority code, else its PROJ string.

    Parameters
    ----------
    crs : pyproj.CRS
        The CRS.

    Returns
    -------
    str
        E.g. ``WGS 84 / UTM zone 33N (EPSG:32633)`` or ``polar_stereographic (+proj=stere +lat_0=90 …)``.
    """
    name = crs.name
    if name.lower() in ("", "undefined", "unknown", "unnamed") and crs.coordinate_operation is not None:
        name = crs.coordinate_operation.method_name
    auth = crs.to_authority(min_confidence=90)
    if auth is not None:
        return f"{name} ({auth[0]}:{auth[1]})"
    import warnings

    with warnings.catch_warnings():  # "you will likely lose important projection information": not for a label
        warnings.simplefilter("ignore", UserWarning)
        text = crs.to_proj4()
    return f"{name} ({' '.join(p for p in text.split() if p not in ('+no_defs', '+type=crs'))})"


def _candidates(ds: xr.Dataset, dim: str) -> list[tuple[str, xr.DataArray]]:
    """Variables that could hold the coordinate values of ``dim``: the dimension coordinate,
    then 1-D coordinates or data variables on ``dim`` alone (the Ferret/GMT layout)."""
    out = [(dim, ds[dim])] if dim in ds.variables else []
    for name, var in ds.variables.items():
        if str(name) != dim and var.dims == (dim,):
            out.append((str(name), var))  # type: ignore[arg-type]  # a Variable: values, attrs and dims
    return out


def _axis_of(ds: xr.Dataset, dim: str) -> tuple[str, np.ndarray | None, str]:
    """``(kind, values, how)`` of a dimension: its own coordinate, else a 1-D lat/lon/x/y variable."""
    cands = _candidates(ds, dim)
    for name, var in cands:
        kind = axis_kind(var, name)
        if kind:
            how = "coordinate" if name == dim else f"1-D variable {name!r} on coordinate-less dimension {dim!r}"
            return kind, np.asarray(var.values), how
    return axis_kind(None, dim), None, "no coordinate values"


def _crs_of(ds: xr.Dataset, da: xr.DataArray, src: str) -> CRS | None:
    gm = str(da.attrs.get("grid_mapping", da.encoding.get("grid_mapping", ""))).strip()
    if not gm:
        return None
    gm = gm.split(":")[0].strip()
    if gm not in ds.variables:
        raise DataError(f"{src}: variable {da.name!r}: grid_mapping variable {gm!r} not found")
    try:
        return CRS.from_cf(dict(ds[gm].attrs))
    except Exception as exc:  # pyproj raises CRSError and others for incomplete mappings
        raise DataError(f"{src}: grid_mapping {gm!r} is not a usable CRS ({exc})") from exc


def _two_d_lonlat(ds: xr.Dataset, dims: tuple[str, str], src: str = "") -> tuple[_F64, _F64] | None:
    """2-D latitude and longitude variables on ``dims`` (any order), or None."""
    found = {}
    for name, var in ds.variables.items():
        if var.ndim == 2 and set(var.dims) == set(dims):
            kind = axis_kind(var, str(name))  # type: ignore[arg-type]  # a Variable quacks like a DataArray here
            if kind in ("lat", "lon") and kind not in found:
                check_declared(f"{src}: coordinate {str(name)!r}", "declares", var.shape)
                found[kind] = np.asarray(var.transpose(*dims).values, dtype=float)
    return (found["lat"], found["lon"]) if len(found) == 2 else None


def horizontal_grid(ds: xr.Dataset, da: xr.DataArray, src: str) -> tuple[str, str, HorizontalGrid, bool, bool]:
    """Find the horizontal axes of ``da`` in ``ds``.

    Parameters
    ----------
    ds : xarray.Dataset
        The open file.
    da : xarray.DataArray
        The data variable.
    src : str
        The file, for messages.

    Returns
    -------
    row_dim, col_dim : str
        The dimensions of latitude/y and longitude/x.
    grid : HorizontalGrid
        Node positions with ascending 1-D axes.
    flip_rows, flip_cols : bool
        Whether the data must be reversed along the row / column dimension to match the axes.
    """
    name = da.name
    kinds = {str(d): _axis_of(ds, str(d)) for d in da.dims}
    horiz = {d: k for d, k in kinds.items() if k[0] in ("lon", "lat", "x", "y")}
    by_kind = {k[0]: d for d, k in horiz.items()}
    if {"lat", "lon"} <= set(by_kind) or {"x", "y"} <= set(by_kind):
        geo = {"lat", "lon"} <= set(by_kind)
        rdim, cdim = (by_kind["lat"], by_kind["lon"]) if geo else (by_kind["y"], by_kind["x"])
        _, rows, how_r = horiz[rdim]
        _, cols, how_c = horiz[cdim]
        if rows is None or cols is None:
            two = _two_d_lonlat(ds, (rdim, cdim), src)
            if two is None:
                raise DataError(f"{src}: variable {name!r} has dimensions {tuple(da.dims)} without coordinate "
                                "values and no latitude/longitude variables on them")
            return _from_two_d(two, rdim, cdim, src, name)
        layout = how_r if how_r == how_c else f"{how_r}; {how_c}"
        if geo:
            kind, crs = "lonlat", None
        else:
            crs = _crs_of(ds, da, src)
            kind = "projected" if crs is not None else "local"
            if crs is not None and crs.is_geographic and not crs.is_derived:  # a rotated pole stays "projected"
                kind, crs = "lonlat", None
            scale = _METRES.get(_attr(ds[cdim], "units") if cdim in ds.variables else "", 1.0)
            rows, cols = rows * scale, cols * scale
        return _ascending(kind, rows, cols, crs, layout, rdim, cdim, src, name)
    # dims without any recognisable 1-D axis: 2-D lat/lon over the last two dimensions
    if da.ndim >= 2:
        rdim, cdim = str(da.dims[-2]), str(da.dims[-1])
        two = _two_d_lonlat(ds, (rdim, cdim), src)
        if two is not None:
            return _from_two_d(two, rdim, cdim, src, name)
    shown = {d: (k[0] or "?") for d, k in kinds.items()}
    raise DataError(f"{src}: variable {name!r}: cannot find latitude/longitude or x/y axes among its "
                    f"dimensions {shown}; give them CF standard_name/units attributes")


def _ascending(kind: str, rows: _F64, cols: _F64, crs: CRS | None, layout: str, rdim: str, cdim: str, src: str,
               name: Hashable) -> tuple[str, str, HorizontalGrid, bool, bool]:
    rows = np.asarray(rows, dtype=float).reshape(-1)
    cols = np.asarray(cols, dtype=float).reshape(-1)
    if rows.size == 0 or cols.size == 0:
        raise DataError(f"{src}: variable {name!r}: empty grid ({rows.size} x {cols.size} nodes)")
    if rows.size < 2 or cols.size < 2:
        raise DataError(f"{src}: variable {name!r}: the grid needs at least 2 x 2 nodes, got {rows.size} x {cols.size}")
    flip_r, flip_c = bool(rows[0] > rows[-1]), bool(cols[0] > cols[-1])
    rows, cols = (rows[::-1] if flip_r else rows), (cols[::-1] if flip_c else cols)
    if kind == "lonlat":
        cols = cols[0] + np.mod(cols - cols[0], 360.0)
        if cols[-1] - cols[0] < 1e-9 and cols.size > 1:
            raise DataError(f"{src}: variable {name!r}: longitude axis spans nothing")
    for axis, dim, values in (("row", rdim, rows), ("column", cdim, cols)):
        fault = _axis_fault(values)
        if fault:
            role = {"lonlat": ("latitude", "longitude"), "projected": ("y (northing)", "x (easting)")}.get(
                kind, ("y", "x"))[axis == "column"]
            raise DataError(f"{src}: variable {name!r}: the {role} axis {dim!r} {fault}; it must be finite and "
                            "strictly monotonic")
    return rdim, cdim, HorizontalGrid(kind, rows, cols, crs, layout), flip_r, flip_c


def _axis_fault(v: _F64) -> str:
    """What makes an (ascending-ordered) axis unusable: a non-finite value, a repeat, a reversal; '' if none."""
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        return f"has {bad.size} non-finite value(s) ({v[bad[0]]})"
    d = np.diff(v)
    rep = np.flatnonzero(d == 0)
    if rep.size:
        return f"repeats the value {v[rep[0]]:.10g}"
    rev = np.flatnonzero(d < 0)
    if rev.size:
        return f"is not monotonic ({v[rev[0]]:.10g} then {v[rev[0] + 1]:.10g})"
    return ""


def _from_two_d(two: tuple[_F64, _F64], rdim: str, cdim: str, src: str,
                name: Hashable) -> tuple[str, str, HorizontalGrid, bool, bool]:
    lat2, lon2 = two
    # rectilinear after all: latitude constant along rows, longitude constant along columns
    if np.allclose(lat2, lat2[:, :1], atol=1e-9) and np.allclose(lon2, lon2[:1, :], atol=1e-9):
        return _ascending("lonlat", lat2[:, 0], lon2[0, :], None,
                          "2-D latitude/longitude variables (rectilinear)", rdim, cdim, src, name)
    if not (np.all(np.isfinite(lat2)) and np.all(np.isfinite(lon2))):
        raise DataError(f"{src}: variable {name!r}: the 2-D latitude/longitude contain missing values")
    lon2 = lon2[0, 0] + np.mod(lon2 - lon2[0, 0] + 180.0, 360.0) - 180.0
    return rdim, cdim, HorizontalGrid("curvilinear", lat2, lon2, None, "2-D latitude/longitude variables"), False, False


# ---------------------------------------------------------------------- local frame
def _to_source(grid: HorizontalGrid, frame: LocalFrame, x: ArrayLike, y: ArrayLike) -> tuple[_F64, _F64]:
    """Local x, y → (row, col) coordinates of the source grid (lat/lon or projected y/x)."""
    lon, lat = frame.inverse(x, y)
    if grid.kind == "projected":
        tr = Transformer.from_crs("EPSG:4326", grid.crs, always_xy=True)
        cx, cy = tr.transform(lon, lat)
        return np.asarray(cy), np.asarray(cx)
    # longitudes within 180 degrees of the data's middle: a point just west of the data stays west of it
    c0 = 0.5 * float(grid.cols[0] + grid.cols[-1]) - 180.0
    return np.asarray(lat), c0 + np.mod(np.asarray(lon) - c0, 360.0)


def _from_source(grid: HorizontalGrid, frame: LocalFrame, r: ArrayLike, c: ArrayLike) -> tuple[_F64, _F64]:
    if grid.kind == "projected":
        tr = Transformer.from_crs(grid.crs, "EPSG:4326", always_xy=True)
        lon, lat = tr.transform(np.asarray(c, dtype=float), np.asarray(r, dtype=float))
        return frame.forward(lon, lat)
    if grid.kind == "local":
        return np.asarray(c, dtype=float), np.asarray(r, dtype=float)
    return frame.forward(c, r)


def inscribed_extent(grid: HorizontalGrid, frame: LocalFrame) -> tuple[float, float, float, float]:
    """Largest axis-aligned local rectangle inside the data's footprint.

    Each side is the extreme of the projected edge found by sampling and then refined by a
    bounded scalar minimisation, and moved 1 mm inwards; curvilinear grids use their outer node rows.

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
        res = minimize_scalar(lambda q, f=f: float(f(q)), bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-12})
        best = min(float(vals[k]), float(res.fun))
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
    out: _F64 = LinearNDInterpolator(pts, flat.reshape(flat.shape[0], -1).T)(q).T
    if np.isnan(out).any():
        raise DataError(f"{what}: the curvilinear data ({data_span(grid)}) do not cover the requested extent "
                        f"{_extent_text(gx, gy)}")
    return out


def _from_rectilinear(grid: HorizontalGrid, frame: LocalFrame, flat: _F64, gx: _F64, gy: _F64, method: str,
                      what: str) -> _F64:
    """Layers ``flat (L, nrow, ncol)`` at the local nodes: one ``RegularGridInterpolator`` per layer."""
    if grid.kind == "local":
        qr, qc = gy.ravel(), gx.ravel()
    else:
        qr, qc = (a.ravel() for a in _to_source(grid, frame, gx, gy))
    tol_r = 1e-6 * float(np.min(np.diff(grid.rows)))
    tol_c = 1e-6 * float(np.min(np.diff(grid.cols)))
    sides = _uncovered(grid, qr, qc, tol_r, tol_c)
    if sides:
        raise DataError(
            f"{what}: the data ({data_span(grid)}) do not cover the requested extent {_extent_text(gx, gy)}: "
            f"uncovered on the {' and '.join(sides)} side{'s' if len(sides) > 1 else ''}"
        )
    if method in ("cubic", "quintic", "pchip") and min(grid.rows.size, grid.cols.size) < 4:
        method = "linear"
    q = np.column_stack([np.clip(qr, grid.rows[0], grid.rows[-1]), np.clip(qc, grid.cols[0], grid.cols[-1])])
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

