"""The frame of a file's velocity components, and their rotation to east/north.

Ocean models on projected or rotated grids (ROMS, NEMO, the Norwegian and many coastal forecasts)
give velocity *along the grid's axes*.  :func:`vector_frame` decides which frame the components are
in, from, in order:

1. CF ``standard_name``: ``eastward_…``/``northward_…`` → east/north;
   ``sea_water_x_velocity``, ``x_sea_water_velocity`` (MET Norway), ``grid_eastward_…`` → grid axes;
2. a ROMS/CROCO ``angle`` (or ``angle_rho``) variable — the angle between the grid's XI axis and
   east — → grid axes, turned by that angle;
3. a CF ``grid_mapping`` whose axes are not east/north (a rotated pole, or any projection) → grid axes;
4. otherwise (plain latitude/longitude axes) → east/north.

:func:`grid_angle` gives, per source node, the angle ``alpha`` of the grid's x axis counter-clockwise
from east: the file's own ``angle``; for a projection or a rotated pole, the geodesic azimuth of a
small step along the grid's x axis (pyproj, on the projection's own ellipsoid; a sphere for a rotated
pole); for 2-D latitude/longitude without an angle, the spherical azimuth between neighbouring nodes
(as ROMS computes its ``angle``).  :func:`to_east_north` then turns ``(u, v)`` into
``(u cos a - v sin a, u sin a + v cos a)``; the east/north components go on to the local frame like
any others.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ....errors import DataError
from ..grids import HorizontalGrid

if TYPE_CHECKING:
    import xarray as xr
    from pyproj import Geod

__all__ = ["VectorFrame", "vector_frame", "grid_angle", "to_east_north", "GRID_X_NAMES"]

_F64 = NDArray[np.float64]

#: CF (and MET Norway) standard names of grid-relative x components.
GRID_X_NAMES = ("sea_water_x_velocity", "x_sea_water_velocity", "grid_eastward_sea_water_velocity",
                "sea_water_x_velocity_at_u_location")
_EAST_NAMES = ("eastward_sea_water_velocity", "eastward_sea_water_velocity_assuming_no_tide",
               "surface_eastward_sea_water_velocity", "baroclinic_eastward_sea_water_velocity",
               "barotropic_eastward_sea_water_velocity")


@dataclass(frozen=True)
class VectorFrame:
    """Which frame a file's horizontal components are in.

    Attributes
    ----------
    grid_relative : bool
        True when the components are along the grid's axes.
    reason : str
        How it was decided (for ``data inspect``).
    angle_variable : str
        The file's angle variable (ROMS ``angle``), or empty.
    """

    grid_relative: bool
    reason: str
    angle_variable: str = ""


def _angle_variable(ds: xr.Dataset) -> str:
    for name in ("angle", "angle_rho"):
        if name in ds.variables and ds[name].ndim == 2:
            return name
    return ""


def vector_frame(ds: xr.Dataset, u_name: str, grid: HorizontalGrid) -> VectorFrame:
    """Decide the frame of the components (see the module's rules).

    Parameters
    ----------
    ds : xarray.Dataset
        The open file.
    u_name : str
        The x/eastward component's variable.
    grid : HorizontalGrid
        Its horizontal grid.

    Returns
    -------
    VectorFrame
        The frame and the reason.
    """
    std = str(ds[u_name].attrs.get("standard_name", "")).strip().lower()
    angle = _angle_variable(ds)
    if std in _EAST_NAMES or std.startswith("eastward_"):
        return VectorFrame(False, f"east/north (standard_name {std!r})")
    if std in GRID_X_NAMES:
        return VectorFrame(True, f"grid axes (standard_name {std!r})", angle)
    if angle:
        return VectorFrame(True, f"grid axes (ROMS/CROCO variable {angle!r}: angle of the XI axis from east)", angle)
    if grid.kind == "projected" and grid.crs is not None:
        what = "rotated pole" if grid.crs.is_geographic else "projection"
        return VectorFrame(True, f"grid axes (grid_mapping: {what} {grid.crs.name!r})")
    return VectorFrame(False, "east/north (latitude/longitude axes, no grid-relative name)")


def _azimuth_alpha(lon0: _F64, lat0: _F64, lon1: _F64, lat1: _F64, geod: Geod | None = None) -> _F64:
    """Angle counter-clockwise from east (rad) of the geodesic from point 0 to point 1 (on a sphere unless
    ``geod`` is given)."""
    from pyproj import Geod  # where a file is projected (issue 56)

    geod = Geod(ellps="sphere") if geod is None else geod
    az, _, _ = geod.inv(lon0, lat0, lon1, lat1)
    return np.deg2rad(90.0 - np.asarray(az, dtype=float))


def grid_angle(ds: xr.Dataset, grid: HorizontalGrid, frame: VectorFrame, dims: tuple[str, str],
               flips: tuple[bool, bool], src: str) -> _F64:
    """Angle of the grid's x axis counter-clockwise from east at every source node (rad).

    Parameters
    ----------
    ds : xarray.Dataset
        The open file.
    grid : HorizontalGrid
        The components' grid (ascending 1-D axes, or 2-D latitude/longitude).
    frame : VectorFrame
        The decided frame (its angle variable, if any).
    dims : tuple of 2 str
        The row and column dimensions of the components.
    flips : tuple of 2 bool
        Whether the components were reversed along rows / columns.
    src : str
        The file, for messages.

    Returns
    -------
    numpy.ndarray
        ``(nrow, ncol)`` angles (rad).
    """
    if frame.angle_variable:
        da = ds[frame.angle_variable]
        a = np.asarray(da.values, dtype=float)
        if set(map(str, da.dims)) == set(dims):
            a = np.asarray(da.transpose(*dims).values, dtype=float)
        units = str(da.attrs.get("units", "radians")).strip().lower()
        if units.startswith("deg"):
            a = np.deg2rad(a)
        a = a[::-1] if flips[0] else a
        a = a[:, ::-1] if flips[1] else a
        nr, nc = np.asarray(grid.rows).shape[0], np.asarray(grid.cols).shape[-1]
        if a.shape != (nr, nc):
            raise DataError(f"{src}: angle variable {frame.angle_variable!r} has shape {a.shape}, "
                            f"the velocity grid {(nr, nc)}")
        return a
    if grid.kind == "projected" and grid.crs is not None:
        cx, cy = np.meshgrid(grid.cols, grid.rows)
        h = 1e-3 * float(min(np.min(np.diff(grid.cols)), np.min(np.diff(grid.rows))))
        from pyproj import Geod, Transformer

        tr = Transformer.from_crs(grid.crs, "EPSG:4326", always_xy=True)
        lon0, lat0 = tr.transform(cx - 0.5 * h, cy)
        lon1, lat1 = tr.transform(cx + 0.5 * h, cy)
        # the projection's own ellipsoid (a rotated pole turns a sphere)
        geod = None if grid.crs.is_geographic else (grid.crs.get_geod() or Geod(ellps="WGS84"))
        return _azimuth_alpha(lon0, lat0, lon1, lat1, geod)
    if grid.kind == "curvilinear":
        lat, lon = np.asarray(grid.rows, dtype=float), np.asarray(grid.cols, dtype=float)
        i0 = np.r_[0, np.arange(lon.shape[1] - 1)]
        i1 = np.r_[np.arange(1, lon.shape[1]), lon.shape[1] - 1]
        return _azimuth_alpha(lon[:, i0], lat[:, i0], lon[:, i1], lat[:, i1])
    return np.zeros((np.asarray(grid.rows).size, np.asarray(grid.cols).size))


def to_east_north(u: _F64, v: _F64, alpha: _F64) -> tuple[_F64, _F64]:
    """Turn grid-axis components into east/north.

    Parameters
    ----------
    u, v : numpy.ndarray
        Components along the grid's x and y axes (``(..., nrow, ncol)``).
    alpha : numpy.ndarray
        ``(nrow, ncol)`` angle of the x axis counter-clockwise from east (rad).

    Returns
    -------
    east, north : numpy.ndarray
        The components towards east and north.
    """
    c, s = np.cos(alpha), np.sin(alpha)
    return u * c - v * s, u * s + v * c
