"""Read gridded ocean currents from CF NetCDF into a :class:`GriddedCurrent`.

Variables are found by CF ``standard_name`` (``eastward_sea_water_velocity``,
``northward_sea_water_velocity``, optional ``upward_sea_water_velocity``) or
common names (``u``/``v``/``w``, ``uo``/``vo``/``wo``, ``water_u``/``water_v``),
or named explicitly.  Axes: longitude/latitude (projected about the scenario
origin and resampled linearly onto a metric grid) or metric x/y; an optional
depth axis (positive down, or elevation positive up); an optional time axis
(seconds from its first value, or decoded datetimes measured from the first).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import DataError
from ..world.currents import GriddedCurrent
from .geo import LocalFrame, regrid_lonlat

__all__ = ["CurrentsFileSpec", "read_currents"]

_NAMES = {
    "u": ("eastward_sea_water_velocity", ("u", "uo", "water_u", "east_vel", "ucur")),
    "v": ("northward_sea_water_velocity", ("v", "vo", "water_v", "north_vel", "vcur")),
    "w": ("upward_sea_water_velocity", ("w", "wo", "water_w", "up_vel", "wcur")),
}


@dataclass(frozen=True)
class CurrentsFileSpec:
    """A NetCDF current file and, optionally, the names of its variables."""

    path: str
    u: str = ""
    v: str = ""
    w: str = ""

    def __post_init__(self) -> None:
        if not self.path:
            raise ValueError("path: the current file name is empty")


def _find(ds: xr.Dataset, comp: str, explicit: str, src: str, required: bool) -> str | None:
    if explicit:
        if explicit not in ds.data_vars:
            raise DataError(f"{src}: variable {explicit!r} not found; it has {sorted(map(str, ds.data_vars))}")
        return explicit
    std, names = _NAMES[comp]
    for k, v in ds.data_vars.items():
        if str(v.attrs.get("standard_name", "")).lower() == std:
            return str(k)
    for k in ds.data_vars:
        if str(k).lower() in names:
            return str(k)
    if required:
        raise DataError(f"{src}: no {std} variable (standard_name or a common name such as {names[0]!r})")
    return None


def _classify(ds: xr.Dataset, dim: str) -> str:
    c = ds[dim] if dim in ds.variables else None
    attrs = {} if c is None else {k: str(v).lower() for k, v in c.attrs.items()}
    std, units, name = attrs.get("standard_name", ""), attrs.get("units", ""), dim.lower()
    if c is not None and np.issubdtype(c.dtype, np.datetime64):
        return "t"
    if std == "time" or name in ("time", "t") or " since " in units:
        return "t"
    if std == "longitude" or units.startswith("degrees_e") or name in ("lon", "longitude"):
        return "lon"
    if std == "latitude" or units.startswith("degrees_n") or name in ("lat", "latitude"):
        return "lat"
    if std == "depth" or name in ("depth", "z", "lev", "level", "height", "elevation"):
        return "z"
    if name in ("x", "easting") or std == "projection_x_coordinate":
        return "x"
    if name in ("y", "northing") or std == "projection_y_coordinate":
        return "y"
    raise DataError(f"axis {dim!r}: cannot tell whether it is time, depth, latitude/longitude or x/y")


def read_currents(spec: CurrentsFileSpec, frame: LocalFrame | None, *, base_dir: Path | None = None) -> GriddedCurrent:
    """Read a current file described by ``spec`` into the local frame."""
    path = Path(spec.path)
    if not path.is_absolute() and base_dir is not None:
        path = base_dir / path
    src = str(path)
    if not path.is_file():
        raise DataError(f"{src}: current file not found")
    try:
        ds = xr.open_dataset(path)
    except Exception as exc:  # xarray raises many types for unreadable files
        raise DataError(f"{src}: cannot read as NetCDF ({exc})") from exc
    with ds:
        names = {c: _find(ds, c, getattr(spec, c), src, c != "w") for c in "uvw"}
        da_u = ds[names["u"]]
        kinds = {str(d): _classify(ds, str(d)) for d in da_u.dims}
        order = [k for k in ("t", "z") if k in kinds.values()]
        horiz = ["lat", "lon"] if "lat" in kinds.values() else ["y", "x"]
        if not set(horiz) <= set(kinds.values()):
            raise DataError(f"{src}: variable {names['u']!r} needs lat/lon or x/y axes, has {kinds}")
        dims = [next(d for d, k in kinds.items() if k == want) for want in order + horiz]
        comps: list[np.ndarray | None] = []
        for c in "uvw":
            if names[c] is None:
                comps.append(None)
                continue
            da = ds[names[c]]
            if set(map(str, da.dims)) != set(dims):
                raise DataError(f"{src}: variable {names[c]!r} has dims {da.dims}, expected {tuple(dims)}")
            arr = np.asarray(da.transpose(*dims).values, dtype=float)
            if not np.all(np.isfinite(arr)):
                raise DataError(f"{src}: variable {names[c]!r} has missing values; currents must be complete")
            comps.append(arr)
        axes = {k: np.asarray(ds[d].values) for d, k in kinds.items() if d in ds.variables}
        z_attrs = {}
        if "z" in kinds.values():
            zdim = next(d for d, k in kinds.items() if k == "z")
            z_attrs = {k: str(v).lower() for k, v in ds[zdim].attrs.items()} if zdim in ds.variables else {}
    # time axis in seconds from its first value
    t = None
    if "t" in axes:
        ta = axes["t"]
        t = (ta - ta[0]).astype("timedelta64[ns]").astype(float) / 1e9 if np.issubdtype(ta.dtype, np.datetime64) \
            else ta.astype(float) - float(ta[0])
    z = np.zeros(1)
    if "z" in axes:
        zv = axes["z"].astype(float)
        down = z_attrs.get("positive") == "down" or (z_attrs.get("positive") != "up" and np.all(zv >= 0)
                                                    and z_attrs.get("standard_name", "depth") == "depth")
        z = -zv if down else zv
    # sort every axis ascending
    arrays = [a for a in comps if a is not None]
    lead_axes = [("t", t)] if t is not None else []
    lead_axes += [("z", z)] if "z" in axes else []
    for i, (_, ax) in enumerate(lead_axes):
        if ax.size > 1 and ax[0] > ax[-1]:
            arrays = [np.flip(a, axis=i) for a in arrays]
            lead_axes[i] = (lead_axes[i][0], ax[::-1])
    lead = dict(lead_axes)
    t = lead.get("t", t)
    z = lead.get("z", z)
    h0 = axes[horiz[0]].astype(float)
    h1 = axes[horiz[1]].astype(float)
    nlead = len(lead_axes)
    if h0[0] > h0[-1]:
        arrays, h0 = [np.flip(a, axis=nlead) for a in arrays], h0[::-1]
    if h1[0] > h1[-1]:
        arrays, h1 = [np.flip(a, axis=nlead + 1) for a in arrays], h1[::-1]
    if horiz[0] == "lat":
        if frame is None:
            frame = LocalFrame(float(h0.mean()), float(h1.mean()))
        lon = h1[0] + np.mod(h1 - h1[0], 360.0)
        regridded = [regrid_lonlat(lon, h0, a, frame, method="linear", what=src) for a in arrays]
        x, y = regridded[0][0], regridded[0][1]
        arrays = [r[2] for r in regridded]
    else:
        x, y = h1, h0
    shape = (1 if t is None else t.size, z.size, y.size, x.size)
    arrays = [a.reshape(shape) for a in arrays]
    w = arrays[2] if len(arrays) == 3 else None
    return GriddedCurrent(x, y, z, arrays[0], arrays[1], w, t, name=path.name)
