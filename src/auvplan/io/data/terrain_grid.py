"""A grid of elevation made a :class:`~auvplan.world.terrain.Terrain` in the local frame: missing values filled
or refused, a crop to a lat/lon box, the projection and the resampling onto a regular metric grid.

Used by :mod:`.bathymetry` (files and built-in terrains) and by anyone holding the grid already
(:func:`terrain_from_lonlat`, :func:`terrain_from_xy`).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...errors import DataError
from ...world.seabed import SeabedFit
from ...world.terrain import Terrain
from .geo import LocalFrame, normalise_lon
from .grids import HorizontalGrid, horizontal_grid
from .regrid import data_span
from .seabed_model import model_seabed

__all__ = ["MAX_ELEVATION_M", "terrain_from_grid", "terrain_from_lonlat", "terrain_from_xy"]

_F64 = NDArray[np.float64]
"""Array of float64."""

log = logging.getLogger("auvplan.io.data.bathymetry")
"""The reader's logger (:mod:`.bathymetry`): a clipped crop is its warning, under the name it always had."""


MAX_ELEVATION_M = 12_000.0
"""Largest elevation or depth a grid may hold, after its units (m): the Challenger Deep is 10 935 m deep, Everest
8 849 m high (hostile round 22: a land cell filled with -1e30 that the file did not declare as its fill value was
read as a seabed 10³⁰ m deep, and flown through)."""


def _check_range(z: _F64, src: str, where: Callable[[int, int], str]) -> None:
    """Refuse values no seabed or land on Earth has (an undeclared fill value, wrong units or scale_factor)."""
    big = np.abs(np.where(np.isfinite(z), z, 0.0)) > MAX_ELEVATION_M
    if big.any():
        j, i = np.argwhere(big)[0]
        n = int(big.sum())
        raise DataError(f"{src}: elevation holds {float(z[j, i]):.6g} m (at {where(j, i)}; {n:,} such "
                        f"value{'s' if n != 1 else ''}): beyond the {MAX_ELEVATION_M:,.0f} m of any seabed or land on "
                        "Earth; declare it as the file's fill value (_FillValue, a GeoTIFF's nodata), or check the "
                        "units and scale_factor")


def _fill_nan(z: _F64, policy: str, src: str, where: Callable[[int, int], str]) -> _F64:
    bad = ~np.isfinite(z)
    if not bad.any():
        return z
    if policy == "error":
        j, i = np.argwhere(bad)[0]
        raise DataError(
            f"{src}: elevation has {int(bad.sum())} missing (fill/NaN) values, first at {where(j, i)}; "
            "set nan_policy = 'land' (treat as no-go) or 'nearest'"
        )
    if policy == "land":
        return np.where(bad, 1.0, z)
    if bad.all():
        raise DataError(f"{src}: every elevation value is missing")
    from scipy import ndimage  # imported when used (#56)

    idx = ndimage.distance_transform_edt(bad, return_distances=False, return_indices=True)
    filled: _F64 = z[tuple(idx)]
    return filled


def _crop_axis(axis: _F64, lo: float, hi: float, side_lo: str, side_hi: str, name: str,
               clipped: list[str]) -> tuple[int, int]:
    """Index range of ``axis`` covering ``[lo, hi]`` plus one node of margin; a request beyond the data
    is clipped to the data's edge (noted in ``clipped``)."""
    if lo < axis[0]:
        clipped.append(f"{side_lo} edge {lo:.5f} → {axis[0]:.5f}")
    if hi > axis[-1]:
        clipped.append(f"{side_hi} edge {hi:.5f} → {axis[-1]:.5f}")
    i0 = max(int(np.searchsorted(axis, lo, side="right")) - 2, 0)
    i1 = min(int(np.searchsorted(axis, hi, side="left")) + 2, axis.size)
    return i0, i1


def _crop(grid: HorizontalGrid, z: _F64, box: tuple[float, ...], name: str) -> tuple[HorizontalGrid, _F64]:
    """Crop a lon/lat or projected grid to a lat/lon ``box``; parts of the box beyond the data are clipped
    with a warning (the projection step then reports any side the scenario bounds still miss)."""
    la0, la1, lo0, lo1 = box
    if grid.kind == "lonlat":
        lon = grid.cols
        lo0 = lon[0] + np.mod(lo0 - lon[0], 360.0)
        lo1 = lo0 + np.mod(lo1 - lo0, 360.0)
        if lo0 > lon[-1] and lo0 - 360.0 < lon[0] <= lo1 - 360.0:  # box starts west of a data edge at 0/360
            lo0, lo1 = lo0 - 360.0, lo1 - 360.0
        r_lo, r_hi, c_lo, c_hi = la0, la1, lo0, lo1
    else:
        from pyproj import Transformer

        tr = Transformer.from_crs("EPSG:4326", grid.crs, always_xy=True)
        c_lo, r_lo, c_hi, r_hi = tr.transform_bounds(lo0, la0, lo1, la1, densify_pts=101)
    if r_hi < grid.rows[0] or r_lo > grid.rows[-1] or c_hi < grid.cols[0] or c_lo > grid.cols[-1]:
        raise DataError(f"{name}: the box {list(box)} does not overlap the data ({data_span(grid)})")
    clipped: list[str] = []
    j0, j1 = _crop_axis(grid.rows, r_lo, r_hi, "south", "north", name, clipped)
    i0, i1 = _crop_axis(grid.cols, c_lo, c_hi, "west", "east", name, clipped)
    if clipped:
        log.warning("%s: the box %s reaches beyond the data; clipped (%s)", name, list(box), "; ".join(clipped))
    if i1 - i0 < 2 or j1 - j0 < 2:
        raise DataError(f"{name}: the box {list(box)} leaves fewer than 2 x 2 grid nodes")
    cropped = HorizontalGrid(grid.kind, grid.rows[j0:j1], grid.cols[i0:i1], grid.crs, grid.layout)
    return cropped, z[j0:j1, i0:i1]


def terrain_from_grid(
    grid: HorizontalGrid,
    elevation: ArrayLike,
    *,
    frame: LocalFrame,
    box: tuple[float, ...] = (),
    extent_m: tuple[float, float, float, float] | None = None,
    resample_m: float = 0.0,
    method: str = "conservative",
    nan_policy: str = "error",
    name: str = "",
) -> Terrain:
    """Project elevation (positive up) on any :class:`HorizontalGrid` into ``frame`` as a Terrain.

    ``box`` crops (keeping one node of margin; a box beyond the data is clipped with a warning),
    then the grid is projected and resampled onto a regular metric grid covering ``extent_m``
    (default: the largest rectangle inside the data); an extent the data miss is an error naming
    the uncovered side.

    Parameters
    ----------
    grid : HorizontalGrid
        The data's nodes.
    elevation : array_like
        ``(nrow, ncol)`` elevation, positive up (m).
    frame : LocalFrame
        The local frame.
    box : tuple of 4 float, optional
        ``(lat_min, lat_max, lon_min, lon_max)`` crop (degrees); empty: no crop.
    extent_m : tuple of 4 float, optional
        ``(xmin, xmax, ymin, ymax)`` to cover (m).
    resample_m : float, optional
        Cell of the regular metric grid (m); 0: the data's own spacing.
    nan_policy : {'error', 'land', 'nearest'}, optional
        Missing values: an error, no-go land, or the nearest valid value.
    method : str, optional
        Resampling method (``"conservative"``, default; ``"linear"``, ``"cubic"`` …).
    name : str, optional
        Name of the terrain (file:variable), for messages.

    Returns
    -------
    Terrain
        The seabed on a regular metric grid (m, up positive).
    """
    z = np.asarray(elevation, dtype=float)
    if z.size == 0:
        raise DataError(f"{name}: empty grid")
    if box and grid.kind in ("lonlat", "projected"):
        grid, z = _crop(grid, z, box, name)
    if grid.kind == "lonlat":
        where = lambda j, i: f"lat {grid.rows[j]:.4f}, lon {normalise_lon(grid.cols[i]):.4f}"  # noqa: E731
    elif grid.kind == "curvilinear":
        where = lambda j, i: f"lat {grid.rows[j, i]:.4f}, lon {normalise_lon(grid.cols[j, i]):.4f}"  # noqa: E731
    else:
        where = lambda j, i: f"x {grid.cols[i]:.1f}, y {grid.rows[j]:.1f}"  # noqa: E731
    if grid.kind == "local":
        return terrain_from_xy(grid.cols, grid.rows, z, resample_m=resample_m, nan_policy=nan_policy, name=name,
                               method=method)
    _check_range(z, name, where)
    z = _fill_nan(z, nan_policy, name, where)
    x, y, zz, fit = model_seabed(grid, z, frame, extent_m=extent_m, cell_m=resample_m or None, method=method,
                                 what=name)
    return Terrain(x, y, zz, name=name, fit=fit)


def terrain_from_lonlat(lon: ArrayLike, lat: ArrayLike, elevation: ArrayLike, *, frame: LocalFrame, name: str = "",
                        **kw: Any) -> Terrain:
    """Build a Terrain from elevation (positive up) on 1-D lat/lon axes.

    Parameters
    ----------
    lon, lat : array_like
        1-D axes (degrees; any order, 0–360 or ±180).
    elevation : array_like
        ``(nlat, nlon)`` elevation, positive up (m).
    frame : LocalFrame
        The local frame.
    name : str, optional
        Name of the terrain, for messages.
    **kw
        Further keywords of :func:`terrain_from_grid`.

    Returns
    -------
    Terrain
        The seabed on a regular metric grid (m).
    """
    import xarray as xr  # imported when used (issue 56)

    lon = np.asarray(lon, dtype=float).reshape(-1)
    lat = np.asarray(lat, dtype=float).reshape(-1)
    z = np.asarray(elevation, dtype=float)
    if lon.size == 0 or lat.size == 0 or z.size == 0:
        raise DataError(f"{name}: empty grid (lat {lat.size}, lon {lon.size})")
    if z.shape != (lat.size, lon.size):
        raise DataError(f"{name}: elevation shape {z.shape} does not match (lat, lon) = ({lat.size}, {lon.size})")
    ds = xr.Dataset({"z": (("lat", "lon"), z)}, coords={"lat": lat, "lon": lon})
    _, _, grid, flip_r, flip_c = horizontal_grid(ds, ds["z"], name)
    z = z[::-1] if flip_r else z
    z = z[:, ::-1] if flip_c else z
    return terrain_from_grid(grid, z, frame=frame, name=name, **kw)


def terrain_from_xy(x: ArrayLike, y: ArrayLike, elevation: ArrayLike, *, resample_m: float = 0.0,
                    nan_policy: str = "error", name: str = "", method: str = "conservative") -> Terrain:
    """Build a Terrain from elevation on metric axes (any order, possibly non-uniform).

    Parameters
    ----------
    x, y : array_like
        1-D axes in the local frame (m).
    elevation : array_like
        ``(ny, nx)`` elevation, positive up (m).
    resample_m : float, optional
        Cell of the regular metric grid (m); 0: the data's own spacing.
    nan_policy : {'error', 'land', 'nearest'}, optional
        Missing values: an error, no-go land, or the nearest valid value.
    name : str, optional
        Name of the terrain (file:variable), for messages.
    method : str, optional
        Resampling method when the grid is resampled (``"conservative"``, default; ``"linear"`` …).

    Returns
    -------
    Terrain
        The seabed on a regular metric grid (m).
    """
    x = np.asarray(x, dtype=float).reshape(-1)
    y = np.asarray(y, dtype=float).reshape(-1)
    z = np.asarray(elevation, dtype=float)
    if x.size == 0 or y.size == 0 or z.size == 0:
        raise DataError(f"{name}: empty grid (x {x.size}, y {y.size})")
    if z.shape != (y.size, x.size):
        raise DataError(f"{name}: elevation shape {z.shape} does not match (y, x) = ({y.size}, {x.size})")
    if y.size > 1 and y[0] > y[-1]:
        y, z = y[::-1], z[::-1]
    if x.size > 1 and x[0] > x[-1]:
        x, z = x[::-1], z[:, ::-1]
    xs, ys = x, y  # the axes as arrays, for the message
    _check_range(z, name, lambda j, i: f"x {xs[i]:.1f}, y {ys[j]:.1f}")
    z = _fill_nan(z, nan_policy, name, lambda j, i: f"x {xs[i]:.1f}, y {ys[j]:.1f}")
    step_x, step_y = np.diff(x), np.diff(y)
    uniform = x.size > 1 and y.size > 1 and np.allclose(step_x, step_x[0]) and np.allclose(step_y, step_y[0])
    if resample_m or not uniform:
        cell = resample_m or float(min(step_x.min(), step_y.min()))
        grid = HorizontalGrid("local", y, x, None, "metric axes")
        x, y, z, fit = model_seabed(grid, z, LocalFrame(0.0, 0.0), extent_m=(x[0], x[-1], y[0], y[-1]), cell_m=cell,
                                    method=method, what=name)
        return Terrain(x, y, z, name=name, fit=fit)
    return Terrain(x, y, z, name=name, fit=SeabedFit(method, 0.0, 0.0, 0.0))
