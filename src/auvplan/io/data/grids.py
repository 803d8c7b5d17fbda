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

:func:`auvplan.io.data.regrid.to_local` resamples values on any of them onto a
rectilinear grid in the local frame.
"""

from __future__ import annotations

from collections.abc import Hashable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ...errors import DataError
from ..files.limits import check_declared
from .geo import normalise_lon

if TYPE_CHECKING:
    import xarray as xr
    from pyproj import CRS

__all__ = ["HorizontalGrid", "crs_line", "axis_kind", "horizontal_grid"]

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
    from pyproj import CRS  # a projected grid's files only (issue 56: a plan from the cache needs no pyproj)

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
