"""``data inspect`` for current files: the frame of the components, the angle they are turned by, missing
values in open water, and ROMS/CROCO s-level files."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ...errors import DataError
from .grids import HorizontalGrid, axis_kind
from .ocean.currents import _z_axis, open_water_gaps
from .ocean.roms import LEVELS_M
from .ocean.vectors import grid_angle, vector_frame

__all__ = ["frame_lines", "gap_line", "roms_lines"]


def frame_lines(ds: xr.Dataset, u_name: str, grid: HorizontalGrid, dims: tuple[str, str], src: str) -> list[str]:
    """The frame the components are in and, when grid-relative, the range of the angle that turns them.

    Parameters
    ----------
    ds : xarray.Dataset
        The open file.
    u_name : str
        The x/eastward component.
    grid : HorizontalGrid
        Its grid (as read, before any flip: only the angle's range is shown).
    dims : tuple of 2 str
        Row and column dimensions.
    src : str
        The file, for messages.

    Returns
    -------
    list of str
        One or two lines.
    """
    vf = vector_frame(ds, u_name, grid)
    if not vf.grid_relative:
        return [f"  vectors: {vf.reason}"]
    try:
        alpha = np.rad2deg(grid_angle(ds, grid, vf, dims, (False, False), src))
    except DataError as exc:
        return [f"  vectors: {vf.reason}; angle not usable — {exc}"]
    return [f"  vectors: {vf.reason}; turned to east/north by the grid's angle "
            f"{np.nanmin(alpha):.2f} .. {np.nanmax(alpha):.2f} deg (x axis, counter-clockwise from east)"]


def gap_line(ds: xr.Dataset, name: str, dims: tuple[str, str], src: str) -> str | None:
    """A warning line for missing values in open water (see :func:`auvplan.io.data.ocean.currents.open_water_gaps`).

    Parameters
    ----------
    ds : xarray.Dataset
        The open file.
    name : str
        The variable.
    dims : tuple of 2 str
        Row and column dimensions.
    src : str
        The file, for messages.

    Returns
    -------
    str or None
        The warning, or None without such values.
    """
    da = ds[name]
    lead = {axis_kind(ds[d] if d in ds.variables else None, d): d for d in map(str, da.dims) if d not in dims}
    order = [lead[k] for k in ("t", "z") if k in lead]
    if len(order) != da.ndim - 2:
        return None
    arr = np.asarray(da.transpose(*order, *dims).values, dtype=float)
    if "t" not in lead:
        arr = arr[None]
    if "z" not in lead:
        arr = arr[:, None]
    elif arr.shape[1] > 1:
        z = _z_axis(ds, lead["z"], src)
        if z[0] > z[-1]:
            arr = arr[:, ::-1]
    count, first = open_water_gaps(arr)
    if first is None:
        return None
    return (f"  WARNING {name}: {count} missing value(s) in open water (the column has values below them, or the "
            f"place has values at other times), first at row {first[2]}, column {first[3]}, time index {first[0]}")


def roms_lines(ds: xr.Dataset, u_name: str, v_name: str) -> list[str]:
    """Describe a ROMS/CROCO s-level file.

    Parameters
    ----------
    ds : xarray.Dataset
        The open file.
    u_name, v_name : str
        The XI and ETA components.

    Returns
    -------
    list of str
        The lines.
    """
    h = np.asarray(ds["h"].values, dtype=float)
    vt = int(np.asarray(ds["Vtransform"].values).reshape(-1)[0]) if "Vtransform" in ds.variables else 1
    hc = float(np.asarray(ds["hc"].values).reshape(-1)[0])
    lines = [f"as currents: ROMS/CROCO s-levels: u {u_name!r} {tuple(map(str, ds[u_name].dims))}, "
             f"v {v_name!r} {tuple(map(str, ds[v_name].dims))} (Arakawa C: averaged onto the interior rho points)",
             f"  {ds['s_rho'].size} s-levels, Vtransform {vt}" + ("" if "Vtransform" in ds.variables else
                                                                   " (absent: ROMS's default)")
             + f", hc {hc:g} m; seabed h {np.nanmin(h):.1f} .. {np.nanmax(h):.1f} m; interpolated to "
             f"{sum(d <= np.nanmax(h) for d in LEVELS_M)} depths 0 .. "
             f"{max(d for d in LEVELS_M if d <= np.nanmax(h)):g} m"]
    if "lat_rho" in ds.variables:
        lat, lon = ds["lat_rho"].values, ds["lon_rho"].values
        lines.append(f"  rho grid {lat.shape[0]} x {lat.shape[1]}; lat {np.nanmin(lat):.4f}..{np.nanmax(lat):.4f}, "
                     f"lon {np.nanmin(lon):.4f}..{np.nanmax(lon):.4f}")
    if "angle" in ds.variables:
        a = np.rad2deg(np.asarray(ds["angle"].values, dtype=float))
        lines.append(f"  vectors: grid axes (ROMS/CROCO variable 'angle'); turned to east/north by "
                     f"{np.nanmin(a):.2f} .. {np.nanmax(a):.2f} deg (XI axis, counter-clockwise from east)")
    else:
        lines.append("  vectors: grid axes (ROMS); no 'angle' variable: XI taken as east")
    return lines
