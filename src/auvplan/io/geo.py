"""Geodesy for inputs and exports: the local metric frame about a scenario origin.

The local frame is pyproj's azimuthal equidistant projection about
``(lat0, lon0)`` on WGS 84 (x east, y north, metres).  Geographic grids are
projected once, here, and resampled onto a rectilinear metric grid so that the
algorithms below never see latitudes or longitudes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from pyproj import Transformer
from scipy.interpolate import RegularGridInterpolator

from ..errors import DataError

__all__ = ["LocalFrame", "normalise_lon", "regrid_lonlat"]


def normalise_lon(lon) -> np.ndarray:
    """Longitudes mapped to ``[-180, 180)``."""
    return np.mod(np.asarray(lon, dtype=float) + 180.0, 360.0) - 180.0


@dataclass(frozen=True)
class LocalFrame:
    """Azimuthal equidistant frame about ``(lat0, lon0)`` (degrees)."""

    lat0: float
    lon0: float
    _fwd: Transformer = field(init=False, repr=False, compare=False)
    _inv: Transformer = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not (-90.0 <= self.lat0 <= 90.0) or not np.isfinite(self.lon0):
            raise ValueError(f"origin must be a valid latitude/longitude, got ({self.lat0}, {self.lon0})")
        lon0 = float(normalise_lon(self.lon0))
        proj = f"+proj=aeqd +lat_0={self.lat0} +lon_0={lon0} +datum=WGS84 +units=m +no_defs"
        object.__setattr__(self, "_fwd", Transformer.from_crs("EPSG:4326", proj, always_xy=True))
        object.__setattr__(self, "_inv", Transformer.from_crs(proj, "EPSG:4326", always_xy=True))

    def forward(self, lon, lat) -> tuple[np.ndarray, np.ndarray]:
        """Longitude/latitude (degrees) → local x, y (m)."""
        x, y = self._fwd.transform(normalise_lon(lon), np.asarray(lat, dtype=float))
        return np.asarray(x), np.asarray(y)

    def inverse(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Local x, y (m) → longitude in ``[-180, 180)`` and latitude (degrees)."""
        lon, lat = self._inv.transform(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        return normalise_lon(lon), np.asarray(lat)


def _inscribed_extent(frame: LocalFrame, lon: np.ndarray, lat: np.ndarray) -> tuple[float, float, float, float]:
    """Largest axis-aligned metric rectangle inside the projected lon/lat rectangle."""
    s = np.linspace(0.0, 1.0, 101)
    lo_lon, hi_lon, lo_lat, hi_lat = lon[0], lon[-1], lat[0], lat[-1]
    west = frame.forward(np.full_like(s, lo_lon), lo_lat + s * (hi_lat - lo_lat))
    east = frame.forward(np.full_like(s, hi_lon), lo_lat + s * (hi_lat - lo_lat))
    south = frame.forward(lo_lon + s * (hi_lon - lo_lon), np.full_like(s, lo_lat))
    north = frame.forward(lo_lon + s * (hi_lon - lo_lon), np.full_like(s, hi_lat))
    return float(west[0].max()), float(east[0].min()), float(south[1].max()), float(north[1].min())


def regrid_lonlat(
    lon: np.ndarray,
    lat: np.ndarray,
    values: np.ndarray,
    frame: LocalFrame,
    *,
    extent_m: tuple[float, float, float, float] | None = None,
    cell_m: float | None = None,
    method: str = "linear",
    what: str = "grid",
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Resample values on a (lat, lon) grid onto a rectilinear grid in the local frame.

    Parameters
    ----------
    lon, lat : ndarray
        Ascending axes (degrees); ``lon`` already unwrapped to be monotonic.
    values : ndarray, shape ``(..., nlat, nlon)``
        Data; leading axes (time, depth, component) are carried along.
    frame : LocalFrame
        Target frame.
    extent_m : (xmin, xmax, ymin, ymax) or None
        Target extent; by default the largest rectangle inside the data.
    cell_m : float or None
        Target cell size; by default the data's own spacing at its centre.
    method : str
        ``scipy.interpolate.RegularGridInterpolator`` method ("linear", "cubic", ...).
    what : str
        Name used in error messages.

    Returns
    -------
    x, y, out : ndarray
        Metric axes and resampled values ``(..., ny, nx)``.
    """
    if extent_m is None:
        extent_m = _inscribed_extent(frame, lon, lat)
    x0, x1, y0, y1 = extent_m
    if not (x0 < x1 and y0 < y1):
        raise DataError(f"{what}: empty extent {extent_m} after projection")
    if cell_m is None:
        mid_lat = np.deg2rad(0.5 * (lat[0] + lat[-1]))
        dlat = float(np.median(np.diff(lat))) * 111_320.0
        dlon = float(np.median(np.diff(lon))) * 111_320.0 * np.cos(mid_lat)
        cell_m = min(dlat, dlon)
    if not cell_m > 0:
        raise DataError(f"{what}: cell size must be positive, got {cell_m}")
    nx = max(int(round((x1 - x0) / cell_m)) + 1, 2)
    ny = max(int(round((y1 - y0) / cell_m)) + 1, 2)
    x = np.linspace(x0, x1, nx)
    y = np.linspace(y0, y1, ny)
    gx, gy = np.meshgrid(x, y)
    qlon, qlat = frame.inverse(gx, gy)
    # bring the query longitudes onto the data's (possibly 0-360) branch
    qlon = lon[0] + np.mod(qlon - lon[0], 360.0)
    tol = 1e-9
    outside = (qlon < lon[0] - tol) | (qlon > lon[-1] + tol) | (qlat < lat[0] - tol) | (qlat > lat[-1] + tol)
    if outside.any():
        raise DataError(
            f"{what}: the data (lat {lat[0]:.4f}..{lat[-1]:.4f}, lon {lon[0]:.4f}..{lon[-1]:.4f}) "
            f"do not cover the requested extent x [{x0:.0f}, {x1:.0f}] y [{y0:.0f}, {y1:.0f}] m"
        )
    if method in ("cubic", "quintic", "pchip") and min(lat.size, lon.size) < 4:
        method = "linear"
    vals = np.asarray(values, dtype=float)
    lead = vals.shape[:-2]
    flat = vals.reshape(-1, lat.size, lon.size)
    q = np.column_stack([np.clip(qlat.ravel(), lat[0], lat[-1]), np.clip(qlon.ravel(), lon[0], lon[-1])])
    out = np.empty((flat.shape[0], ny * nx))
    for k in range(flat.shape[0]):  # one interpolator per 2-D layer (time/depth/component)
        out[k] = RegularGridInterpolator((lat, lon), flat[k], method=method)(q)
    return x, y, out.reshape(*lead, ny, nx)
