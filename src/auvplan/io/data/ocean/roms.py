"""ROMS/CROCO currents on terrain-following s-levels and staggered (Arakawa C) points.

A file is read this way when its ``u`` lies on an ``s_rho`` dimension and the file has the
vertical-grid variables ``Cs_r``, ``h`` and ``hc`` (``Vtransform`` 1 or 2, default 1 as in ROMS
before it was written; ``zeta`` optional, default 0).

* **Staggering** (Arakawa C): ``u[..., k]`` lies between rho points ``k`` and ``k + 1`` along XI and
  ``v[..., j, :]`` between rho points ``j`` and ``j + 1`` along ETA — in full grids (``xi_u = xi_rho - 1``)
  and in cut-outs that kept the same index ranges (``xi_u = xi_rho``).  Both are averaged onto the
  interior rho points (ROMS's ``u2rho``/``v2rho``); ``mask_u``/``mask_v`` mark land as missing.
* **Depths** of the rho levels (ROMS/CROCO's standard transforms; Shchepetkin & McWilliams 2005,
  myroms.org/wiki/Vertical_S-coordinate)::

      Vtransform 1:  z0 = hc s + (h - hc) C,          z = z0 + zeta (1 + z0 / h)
      Vtransform 2:  z0 = (hc s + h C) / (hc + h),    z = zeta + (zeta + h) z0

* **Levels**: every column is interpolated linearly in z to fixed depths (:data:`LEVELS_M`, those
  down to the deepest ``h``); above the top rho level the top value holds, below the bottom one the
  bottom value down to the seabed, and below the seabed values are missing (filled like any land mask).
* **Frame**: ``u``/``v`` are along the grid's XI/ETA axes and are turned to east/north with ``angle``
  (:mod:`auvplan.io.data.ocean.vectors`), at the rho points.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ....errors import DataError
from ..grids import HorizontalGrid
from .vectors import to_east_north

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["LEVELS_M", "is_s_coordinate", "s_depths", "read_s_levels", "to_levels"]

_F64 = NDArray[np.float64]

#: Depths (m, positive down) the s-levels are interpolated to (those down to the deepest seabed).
LEVELS_M = (0.0, 2.0, 5.0, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0, 75.0, 100.0, 125.0, 150.0, 200.0, 250.0, 300.0,
            400.0, 500.0, 600.0, 750.0, 1000.0, 1250.0, 1500.0, 2000.0, 2500.0, 3000.0, 3500.0, 4000.0, 5000.0,
            6000.0)


def is_s_coordinate(ds: xr.Dataset, u_name: str) -> bool:
    """Whether ``u_name`` is a ROMS/CROCO field on s-levels (``s_rho`` and ``Cs_r``, ``h``, ``hc``).

    Parameters
    ----------
    ds : xarray.Dataset
        The open file.
    u_name : str
        The x velocity variable.

    Returns
    -------
    bool
        True for s-levels.
    """
    return "s_rho" in ds[u_name].dims and all(v in ds.variables for v in ("Cs_r", "h", "hc"))


def s_depths(s: _F64, cs: _F64, h: _F64, hc: float, zeta: _F64, vtransform: int) -> _F64:
    """Elevation of the rho levels (m, up positive) by ROMS's standard transforms.

    Parameters
    ----------
    s, cs : numpy.ndarray
        ``(S,)`` s-coordinate and stretching curve of the levels (−1 at the bottom, 0 at the top).
    h : numpy.ndarray
        ``(ny, nx)`` depth of the seabed (m, positive).
    hc : float
        Critical depth (m).
    zeta : numpy.ndarray
        ``(T, ny, nx)`` free surface (m).
    vtransform : int
        1 or 2.

    Returns
    -------
    numpy.ndarray
        ``(T, S, ny, nx)`` elevations (m).
    """
    s4, c4 = s[None, :, None, None], cs[None, :, None, None]
    h4, z4 = h[None, None], zeta[:, None]
    if vtransform == 1:
        z0 = hc * s4 + (h4 - hc) * c4
        return z0 + z4 * (1.0 + z0 / h4)
    if vtransform == 2:
        z0 = (hc * s4 + h4 * c4) / (hc + h4)
        return z4 + (z4 + h4) * z0
    raise ValueError(f"Vtransform must be 1 or 2, got {vtransform}")


def to_levels(values: _F64, z: _F64, targets: _F64, h: _F64) -> _F64:
    """Interpolate columns on s-levels to fixed elevations.

    Parameters
    ----------
    values, z : numpy.ndarray
        ``(T, S, ny, nx)`` values and the elevations of their levels (ascending along S).
    targets : numpy.ndarray
        ``(K,)`` elevations (m, ascending).
    h : numpy.ndarray
        ``(ny, nx)`` seabed depth (m): targets below ``-h`` are missing.

    Returns
    -------
    numpy.ndarray
        ``(T, K, ny, nx)``.
    """
    n_s = z.shape[1]
    out = np.empty((values.shape[0], targets.size, *values.shape[2:]))
    for k, zt in enumerate(targets):
        above = np.count_nonzero(z < zt, axis=1)  # levels strictly below the target
        hi = np.clip(above, 1, n_s - 1)[:, None]
        lo = hi - 1
        z_lo, z_hi = np.take_along_axis(z, lo, 1)[:, 0], np.take_along_axis(z, hi, 1)[:, 0]
        v_lo, v_hi = np.take_along_axis(values, lo, 1)[:, 0], np.take_along_axis(values, hi, 1)[:, 0]
        w = np.clip((zt - z_lo) / (z_hi - z_lo), 0.0, 1.0)
        layer = v_lo + w * (v_hi - v_lo)
        out[:, k] = np.where(zt < -h[None] - 1e-9, np.nan, layer)
    return out


def _scalar(ds: xr.Dataset, name: str, default: float | None, src: str) -> float:
    if name not in ds.variables:
        if default is None:
            raise DataError(f"{src}: ROMS variable {name!r} not found")
        return default
    return float(np.asarray(ds[name].values).reshape(-1)[0])


def _destagger(ds: xr.Dataset, name: str, axis: int, n_rho: tuple[int, int], factor: float,
               src: str) -> _F64:
    """``(T, S, ny-2, nx-2)`` values at the interior rho points from the staggered ``name``."""
    da = ds[name]
    arr = np.array(da.values, dtype=float) * factor
    if np.isinf(arr).any():  # numpy's RuntimeWarnings in the interpolation, then 'every value is missing'
        raise DataError(f"{src}: variable {name!r} holds an infinite value ({int(np.isinf(arr).sum()):,} of them); "
                        "declare a fill value as _FillValue")
    if arr.ndim == 3:
        arr = arr[None]
    mask_name = f"mask_{name}"
    if mask_name in ds.variables and ds[mask_name].shape == arr.shape[-2:]:
        arr = np.where(np.asarray(ds[mask_name].values) == 0, np.nan, arr)
    ny, nx = n_rho
    ok_shape = ((ny, nx - 1), (ny, nx)) if axis == 3 else ((ny - 1, nx), (ny, nx))
    if arr.shape[-2:] not in ok_shape:
        raise DataError(f"{src}: variable {name!r} has horizontal shape {arr.shape[-2:]}; on rho points "
                        f"{(ny, nx)} the staggered shape is one of {list(ok_shape)}")
    if axis == 3:
        mid = 0.5 * (arr[..., :, : nx - 2] + arr[..., :, 1: nx - 1])
        return mid[..., 1: ny - 1, :]
    mid = 0.5 * (arr[..., : ny - 2, :] + arr[..., 1: ny - 1, :])
    return mid[..., :, 1: nx - 1]


def read_s_levels(ds: xr.Dataset, u_name: str, v_name: str, src: str,
                  time_axis: Callable[[str], _F64 | None],
                  factor: Callable[[str, str], float]) -> tuple[HorizontalGrid, _F64 | None, _F64, dict[str, _F64]]:
    """Read ROMS/CROCO s-level currents onto interior rho points and fixed depths, east/north.

    Parameters
    ----------
    ds : xarray.Dataset
        The open file.
    u_name, v_name : str
        The XI and ETA velocity variables.
    src : str
        The file, for messages.
    time_axis : callable
        Seconds of a time dimension (the reader's own time handling).
    factor : callable
        ``(units, where) → factor to m/s``.

    Returns
    -------
    grid : HorizontalGrid
        Curvilinear, the interior rho points.
    t : numpy.ndarray or None
        Seconds.
    z : numpy.ndarray
        ``(K,)`` elevations of the levels (m, ascending).
    comps : dict
        ``{"u", "v"}`` east and north ``(T, K, ny-2, nx-2)`` (m/s; NaN below the seabed and on land).
    """
    lat, lon = _rho_points(ds, src)
    ny, nx = lat.shape
    units = {n: str(ds[n].attrs.get("units", "m s-1")) for n in (u_name, v_name)}
    u = _destagger(ds, u_name, 3, (ny, nx), factor(units[u_name], f"{src}: variable {u_name!r}"), src)
    v = _destagger(ds, v_name, 2, (ny, nx), factor(units[v_name], f"{src}: variable {v_name!r}"), src)
    inner = (slice(1, ny - 1), slice(1, nx - 1))
    h = np.asarray(ds["h"].values, dtype=float)[inner]
    s, z_rho, vt = _rho_depths(ds, src, inner, h, u.shape[0])
    order = np.argsort(z_rho[0, :, 0, 0]) if s.size > 1 else np.arange(1)
    z_rho, u, v = z_rho[:, order], u[:, order], v[:, order]
    targets = 0.0 - np.asarray([d for d in LEVELS_M if d <= float(np.nanmax(h))] or [0.0])[::-1]
    if "angle" in ds.variables:
        angle = np.asarray(ds["angle"].values, dtype=float)[inner]
    else:
        angle = np.zeros(h.shape)
    u, v = to_east_north(u, v, angle)
    comps = {"u": to_levels(u, z_rho, targets, h), "v": to_levels(v, z_rho, targets, h)}
    tdim = str(ds[u_name].dims[0]) if ds[u_name].ndim == 4 else ""
    t = time_axis(tdim) if tdim else None
    grid = HorizontalGrid("curvilinear", lat[inner], lon[inner], None,
                          f"ROMS rho points (interior), s-levels Vtransform {vt} to {targets.size} depths")
    return grid, t, targets, comps


def _rho_points(ds: xr.Dataset, src: str) -> tuple[_F64, _F64]:
    """The rho points' latitudes and longitudes (continuous across the antimeridian), at least 4 x 4."""
    for name in ("lat_rho", "lon_rho"):
        if name not in ds.variables:
            raise DataError(f"{src}: ROMS s-level file without {name!r}")
    lat, lon = np.asarray(ds["lat_rho"].values, dtype=float), np.asarray(ds["lon_rho"].values, dtype=float)
    lon = lon[0, 0] + np.mod(lon - lon[0, 0] + 180.0, 360.0) - 180.0  # continuous across the antimeridian
    ny, nx = lat.shape
    if ny < 4 or nx < 4:
        raise DataError(f"{src}: ROMS grid of {ny} x {nx} rho points is too small (needs 4 x 4)")
    return lat, lon


def _rho_depths(ds: xr.Dataset, src: str, inner: tuple[slice, slice], h: _F64,
                n_t: int) -> tuple[_F64, _F64, int]:
    """The s-levels, the elevations of the interior rho points on them at every time (over the free surface
    ``zeta``, 0 without one) and the Vtransform."""
    s = np.asarray(ds["s_rho"].values, dtype=float)
    cs = np.asarray(ds["Cs_r"].values, dtype=float)
    hc = _scalar(ds, "hc", None, src)
    vt = int(_scalar(ds, "Vtransform", 1.0, src))
    if vt not in (1, 2):
        raise DataError(f"{src}: Vtransform = {vt}; ROMS defines 1 and 2")
    if "zeta" in ds.variables:
        zeta = np.asarray(ds["zeta"].values, dtype=float)
        zeta = (zeta[None] if zeta.ndim == 2 else zeta)[(slice(None), *inner)]
        zeta = np.where(np.isfinite(zeta), zeta, 0.0)
    else:
        zeta = np.zeros((n_t, *h.shape))
    return s, s_depths(s, cs, h, hc, zeta, vt), vt
