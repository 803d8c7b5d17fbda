"""Read gridded ocean currents from CF NetCDF (CMEMS, HYCOM, ROMS, …) into a :class:`GriddedCurrent`.

* Variables by CF ``standard_name`` (``eastward_sea_water_velocity``,
  ``northward_sea_water_velocity``, optional ``upward_sea_water_velocity``; or the
  grid-relative ``sea_water_x_velocity``/``sea_water_y_velocity``), common names
  (``u``/``v``/``w``, ``uo``/``vo``/``wo``, ``water_u``/``water_v``) or named explicitly.
* Horizontal grids: every layout of :mod:`auvplan.io.data.grids` (lat/lon, Ferret
  coordinate-less, 2-D lat/lon, CF ``grid_mapping`` projections, local metres),
  resampled linearly onto the scenario's bounds in the local frame; the vectors
  are turned from east/north (or the source grid's axes) into the local x/y axes.
* ``units`` converted to m/s with pint (cf_xarray's CF unit registry: ``m s-1``,
  ``cm s-1``, ``knots`` …); a variable without units is taken as m/s with a warning.
* Land masks: missing values (NaN or ``_FillValue``) below the deepest valid
  level of a column take that level's value; columns with no valid value (land)
  get zero current.  Land itself is no-go through the bathymetry (and ``[land]``).
* Depth axis positive down (``positive``, ``standard_name``) or elevation up;
  time axis decoded from CF units (xarray/cftime, any calendar) and measured in
  seconds from the scenario's ``[mission] start_time`` (ISO 8601), which must lie
  inside the file's time span; without a start time, from the file's first time.
"""

from __future__ import annotations

import functools
import logging
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ....errors import DataError
from ....world.currents.fields import GriddedCurrent
from ...files.limits import check_declared
from ..geo import LocalFrame
from ..grids import HorizontalGrid, axis_kind, horizontal_grid
from ..ncfile import open_dataset
from ..regrid import to_local
from .roms import is_s_coordinate, read_s_levels
from .vectors import grid_angle, to_east_north, vector_frame

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["CurrentsFileSpec", "read_currents", "velocity_factor", "parse_time", "open_water_gaps"]

log = logging.getLogger(__name__)

_NAMES = {
    "u": (("eastward_sea_water_velocity", "sea_water_x_velocity", "x_sea_water_velocity",
           "eastward_sea_water_velocity_assuming_no_tide",
           "surface_eastward_sea_water_velocity"), ("u", "uo", "water_u", "east_vel", "ucur", "uvel")),
    "v": (("northward_sea_water_velocity", "sea_water_y_velocity", "y_sea_water_velocity",
           "northward_sea_water_velocity_assuming_no_tide",
           "surface_northward_sea_water_velocity"), ("v", "vo", "water_v", "north_vel", "vcur", "vvel")),
    "w": (("upward_sea_water_velocity",), ("w", "wo", "water_w", "up_vel", "wcur")),
}


@dataclass(frozen=True)
class CurrentsFileSpec:
    """A NetCDF current file and, optionally, the names of its variables.

    Attributes
    ----------
    path : str
        The file (relative paths resolve against the scenario's folder).
    u, v, w : str
        Names of the eastward (or grid-x), northward (or grid-y) and upward velocity variables;
        detected from CF standard names when empty (``w`` optional).
    """

    path: str
    u: str = ""
    v: str = ""
    w: str = ""

    def __post_init__(self) -> None:
        if not self.path:
            raise ValueError("path = '': the current file name is empty")


def parse_time(text: str) -> np.datetime64:
    """Parse an ISO 8601 date-time as UTC ``datetime64[ns]``.

    Parameters
    ----------
    text : str
        ``2024-03-01T06:00:00Z``; offsets allowed, no offset means UTC.

    Returns
    -------
    numpy.datetime64
        The time in UTC, nanosecond resolution.
    """
    try:
        t = datetime.fromisoformat(text.strip())
    except ValueError as exc:
        raise ValueError(f"{text!r} is not an ISO 8601 date-time (e.g. 2024-03-01T06:00:00Z)") from exc
    if t.tzinfo is not None:
        t = t.astimezone(UTC).replace(tzinfo=None)
    if not 1678 <= t.year <= 2261:  # datetime64[ns] would wrap silently (year 1 became 1754)
        raise ValueError(f"{text!r}: year {t.year} is outside 1678..2261, the span of nanosecond times")
    return np.datetime64(t, "ns")


@functools.cache
def _unit_registry() -> Any:
    """cf_xarray's pint registry (CF/UDUNITS syntax), configured once: its import redefines a dozen units
    (``percent``, ``degrees`` …), which pint announces as warnings on its ``pint.util`` logger — silenced."""
    pint_log = logging.getLogger("pint.util")
    level = pint_log.level
    pint_log.setLevel(logging.ERROR)
    try:
        from cf_xarray.units import units as ureg
    finally:
        pint_log.setLevel(level)
    return ureg


def velocity_factor(units: str, where: str) -> float:
    """Return the factor from ``units`` to m/s, through pint's CF registry.

    Parameters
    ----------
    units : str
        CF/UDUNITS units text (``"m s-1"``, ``"cm/s"``, ``"knots"`` …).
    where : str
        File and variable, for messages.

    Returns
    -------
    float
        Multiply values in ``units`` by this to get m/s.
    """
    ureg = _unit_registry()
    try:
        q = ureg.Quantity(1.0, units)
    except Exception as exc:  # pint raises several types for unparsable units
        raise DataError(f"{where}: units {units!r} cannot be parsed ({exc})") from exc
    if not q.check("[length] / [time]"):
        raise DataError(f"{where}: units {units!r} are not a velocity (dimension {q.dimensionality})")
    return float(q.to("m/s").magnitude)


def _find(ds: xr.Dataset, comp: str, explicit: str, src: str, required: bool) -> str | None:
    if explicit:
        if explicit not in ds.data_vars:
            raise DataError(f"{src}: variable {explicit!r} not found; it has {sorted(map(str, ds.data_vars))}")
        return explicit
    stds, names = _NAMES[comp]
    for std in stds:
        for k, v in ds.data_vars.items():
            if str(v.attrs.get("standard_name", "")).lower() == std:
                return str(k)
    for k in ds.data_vars:
        if str(k).lower() in names:
            return str(k)
    if required:
        raise DataError(f"{src}: no {stds[0]} variable (standard_name or a common name such as {names[1]!r})")
    return None


def _open(path: Path, src: str) -> xr.Dataset:
    import xarray as xr  # imported when used (issue 56)

    open_dataset(path, "current").close()  # missing, not NetCDF, truncated: diagnosed and named
    try:
        return xr.open_dataset(path, decode_times=xr.coders.CFDatetimeCoder(use_cftime=None))
    except Exception as exc:  # xarray raises many types for unreadable files or undecodable times
        raise DataError(f"{src}: cannot read as CF NetCDF ({exc})") from exc


def _component(ds: xr.Dataset, name: str, dims: Sequence[str], flips: Sequence[bool], src: str) -> NDArray[np.float64]:
    da = ds[name]
    if set(map(str, da.dims)) != set(dims):
        raise DataError(f"{src}: variable {name!r} has dims {da.dims}, expected {tuple(dims)}")
    check_declared(f"{src}: variable {name!r}", "declares", da.shape)  # before a byte is read
    arr = np.array(da.transpose(*dims).values, dtype=float)
    for axis, flip in enumerate(flips):
        if flip:
            arr = np.flip(arr, axis=axis)
    if np.isinf(arr).any():
        raise DataError(f"{src}: variable {name!r} holds an infinite value ({int(np.isinf(arr).sum()):,} of them); "
                        "declare a fill value as _FillValue")
    units = str(da.attrs.get("units", "")).strip()
    if units:
        arr = arr * velocity_factor(units, f"{src}: variable {name!r}")
    else:
        log.warning("%s: variable %r has no units; taken as m/s", src, name)
    return arr


def open_water_gaps(arr: np.ndarray) -> tuple[int, tuple[int, ...] | None]:
    """Missing values that are neither land nor below the seabed: a hole above a valid value of the same
    column, or a place and level without a value at one time that has one at another.

    Parameters
    ----------
    arr : numpy.ndarray
        ``(nt, nz, ny, nx)`` values, depth ascending (deepest level first).

    Returns
    -------
    count : int
        Number of such values.
    first : tuple of 4 int or None
        ``(t, z, row, col)`` index of the first.
    """
    bad = ~np.isfinite(arr)
    below = np.logical_or.accumulate(~bad, axis=1)  # a value at or below this level in the column
    gaps = bad & (below | (~bad).any(axis=0, keepdims=True))
    n = int(np.count_nonzero(gaps))
    return n, (tuple(int(i) for i in np.argwhere(gaps)[0]) if n else None)


def _where(grid: HorizontalGrid, j: int, i: int) -> str:
    """A source node in words (lat/lon, or x/y of the grid)."""
    r, c = np.asarray(grid.rows), np.asarray(grid.cols)
    if grid.kind == "curvilinear":
        return f"lat {r[j, i]:.4f}, lon {c[j, i]:.4f}"
    if grid.kind == "lonlat":
        return f"lat {r[j]:.4f}, lon {c[i]:.4f}"
    return f"grid y {r[j]:.1f}, x {c[i]:.1f}"


def _fill_land(arr: np.ndarray, has_z: bool, src: str, name: str) -> tuple[np.ndarray, int]:
    """Missing values → the deepest valid value above them in the column, else zero (land).
    ``arr`` is ``(nt, nz, ny, nx)`` with z ascending (deepest first)."""
    bad = ~np.isfinite(arr)
    if bad.all():
        raise DataError(f"{src}: variable {name!r}: every value is missing (fill/NaN)")
    if has_z:
        for k in range(arr.shape[1] - 2, -1, -1):  # from just below the surface downwards
            arr[:, k] = np.where(np.isfinite(arr[:, k]), arr[:, k], arr[:, k + 1])
    land = int(np.count_nonzero(~np.isfinite(arr[:, -1]).any(axis=0)))
    return np.where(np.isfinite(arr), arr, 0.0), land


def _time_axis(ds: xr.Dataset, tdim: str, start_time: str, src: str) -> NDArray[np.float64]:
    """Seconds of the time axis from ``start_time`` (or from the first time)."""
    var = ds[tdim] if tdim in ds.variables else None
    if var is None:
        raise DataError(f"{src}: time dimension {tdim!r} has no coordinate values")
    vals = np.asarray(var.values)
    if np.issubdtype(vals.dtype, np.datetime64):
        ref = parse_time(start_time) if start_time else vals.min()
        secs = (vals - ref).astype("timedelta64[ns]").astype(float) / 1e9
        shown = (str(vals.min())[:19], str(vals.max())[:19])
    elif vals.dtype == object:  # cftime dates of a non-standard calendar
        import cftime

        cal = vals[0].calendar
        ref = str(parse_time(start_time))[:19] if start_time else vals.min().isoformat()
        secs = np.asarray(cftime.date2num(list(vals), f"seconds since {ref}", calendar=cal), dtype=float)
        shown = (vals.min().isoformat(), vals.max().isoformat())
    else:
        units = str(var.attrs.get("units", "")).lower()
        if start_time:
            raise DataError(f"{src}: time variable {tdim!r} has units {units!r}, not a CF 'UNITS since DATE' "
                            "time; [mission] start_time cannot be matched to it")
        factor = {"s": 1.0, "sec": 1.0, "second": 1.0, "seconds": 1.0, "h": 3600.0, "hours": 3600.0,
                  "hour": 3600.0, "": 1.0}.get(units)
        if factor is None:
            raise DataError(f"{src}: time variable {tdim!r} has units {units!r}; use CF 'seconds since DATE'")
        secs = (vals.astype(float) - float(vals.min())) * factor
        return secs
    if start_time and vals.size > 1 and not (secs.min() <= 0.0 <= secs.max()):
        raise DataError(f"{src}: time variable {tdim!r} covers {shown[0]} .. {shown[1]}; "
                        f"[mission] start_time {start_time} is outside it")
    return secs


def _z_axis(ds: xr.Dataset, zdim: str, src: str) -> NDArray[np.float64]:
    var = ds[zdim] if zdim in ds.variables else None
    if var is None:
        raise DataError(f"{src}: depth dimension {zdim!r} has no coordinate values")
    zv = np.asarray(var.values, dtype=float)
    units = str(var.attrs.get("units", ""))
    if not units.strip().lower().startswith(("dbar", "decibar")):  # a pressure axis: 1 dbar ~ 1 m of sea water
        from ..elevation import length_factor  # levels in km or feet were read as metres (hostile round 22)

        zv = zv * length_factor(units, f"{src}: depth axis {zdim!r}")
    attrs = {k: str(v).lower() for k, v in var.attrs.items()}
    pos = attrs.get("positive", "")
    std = attrs.get("standard_name", "")
    down = pos == "down" or (pos != "up" and (std == "depth" or zdim.lower().startswith("depth")
                                              or (std == "" and np.all(zv >= 0))))
    return -zv if down else zv


def _directions(grid: HorizontalGrid, frame: LocalFrame, x: NDArray[np.float64], y: NDArray[np.float64],
                grid_relative: bool) -> list[tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """Unit vectors (local x/y) of the components' directions at the local nodes ``(x, y)``:
    east/north, or the source projection's x/y axes for grid-relative components."""
    gx, gy = np.meshgrid(x, y)
    lon, lat = frame.inverse(gx, gy)
    if grid.kind == "projected" and grid_relative:
        from pyproj import Transformer

        to_src = Transformer.from_crs("EPSG:4326", grid.crs, always_xy=True)
        to_geo = Transformer.from_crs(grid.crs, "EPSG:4326", always_xy=True)
        cx, cy = to_src.transform(lon, lat)
        h = 1.0
        moves = [to_geo.transform(cx + h, cy), to_geo.transform(cx, cy + h)]
    else:
        d = 1e-5
        moves = [(lon + d, lat), (lon, lat + d)]
    out = []
    for mlon, mlat in moves:
        mx, my = frame.forward(mlon, mlat)
        vx, vy = mx - gx, my - gy
        n = np.hypot(vx, vy)
        out.append((vx / n, vy / n))
    return out


def read_currents(spec: CurrentsFileSpec, frame: LocalFrame | None, *, base_dir: Path | None = None,
                  extent_m: tuple[float, float, float, float] | None = None, start_time: str = "",
                  member: tuple[str, int] | None = None) -> GriddedCurrent:
    """Read the current file of ``spec`` into the local frame over ``extent_m`` (default: the data's own).

    The result is kept on disk under a key of the file's bytes, the request and the code
    (:mod:`auvplan.io.data.cache`): the same file is regridded once for the same scenario.

    Parameters
    ----------
    spec : CurrentsFileSpec
        The file and its variable names.
    frame : LocalFrame or None
        The scenario's local frame; None for a file already in local metres.
    base_dir : pathlib.Path, optional
        Folder that a relative file name resolves against.
    extent_m : tuple of 4 float, optional
        ``(xmin, xmax, ymin, ymax)`` to cover (m).
    start_time : str, optional
        ISO 8601 UTC time of simulation ``t = 0``; the file's first time when empty.
    member : (str, int), optional
        ``(dimension, index)``: read one member of an ensemble file (issue 39).

    Returns
    -------
    GriddedCurrent
        The current on a local grid (m/s), in time and depth when the file has them.

    Raises
    ------
    DataError
        Naming the file, the variable and the fault (missing variable, units, uncovered area or time).
    """
    from ..cache import cached

    path = Path(spec.path)
    if not path.is_absolute() and base_dir is not None:
        path = base_dir / path
    request = (spec, None if frame is None else (frame.lat0, frame.lon0), extent_m, start_time, member)
    return cached("currents", request, [path], lambda: _read(spec, frame, path, extent_m, start_time, member),
                  _pack, _unpack)


def _pack(c: GriddedCurrent) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    arrays = {k: np.asarray(getattr(c, k)) for k in ("x", "y", "z", "u", "v", "w", "t") if getattr(c, k) is not None}
    return arrays, {"name": c.name}


def _unpack(arrays: dict[str, np.ndarray], meta: dict[str, Any]) -> GriddedCurrent:
    return GriddedCurrent(arrays["x"], arrays["y"], arrays["z"], arrays["u"], arrays["v"], arrays.get("w"),
                          arrays.get("t"), name=str(meta["name"]))


def _read(spec: CurrentsFileSpec, frame: LocalFrame | None, path: Path,
          extent_m: tuple[float, float, float, float] | None, start_time: str,
          member: tuple[str, int] | None) -> GriddedCurrent:
    """:func:`read_currents` without the cache."""
    src = str(path)
    with _open(path, src) as ds:
        if member is not None:  # one realisation of an ensemble file
            ds = ds.isel({member[0]: member[1]})
        names = {c: _find(ds, c, getattr(spec, c), src, c != "w") for c in "uvw"}
        if is_s_coordinate(ds, str(names["u"])):  # ROMS/CROCO: s-levels, staggered u/v, turned by `angle`
            grid, t, z, comps = read_s_levels(ds, str(names["u"]), str(names["v"]), src,
                                              lambda d: _time_axis(ds, d, start_time, src), velocity_factor)
            return _finish(grid, t, z, comps, True, names, frame, extent_m, path)
        da_u = ds[names["u"]]
        rdim, cdim, grid, flip_r, flip_c = horizontal_grid(ds, da_u, src)
        lead = _lead_axes(ds, da_u, (rdim, cdim), src)
        t = _time_axis(ds, lead["t"], start_time, src) if "t" in lead else None
        z = _z_axis(ds, lead["z"], src) if "z" in lead else np.zeros(1)
        dims = [lead[k] for k in ("t", "z") if k in lead] + [rdim, cdim]
        flip_t = t is not None and t.size > 1 and bool(t[0] > t[-1])
        flip_z = z.size > 1 and bool(z[0] > z[-1])
        flips = ([flip_t] if t is not None else []) + ([flip_z] if "z" in lead else []) + [flip_r, flip_c]
        comps = {c: _component(ds, n, dims, flips, src) for c, n in names.items() if n is not None}
        vframe = vector_frame(ds, str(names["u"]), grid)
        if vframe.grid_relative:  # along the grid's axes: turned to east/north at the source nodes
            alpha = grid_angle(ds, grid, vframe, (rdim, cdim), (flip_r, flip_c), src)
            comps["u"], comps["v"] = to_east_north(comps["u"], comps["v"], alpha)
            log.info("%s: velocity along the grid's axes (%s), turned to east/north by %.1f..%.1f deg", src,
                     vframe.reason, np.rad2deg(alpha.min()), np.rad2deg(alpha.max()))
    t = t[::-1] if flip_t and t is not None else t
    z = z[::-1] if flip_z else z
    return _finish(grid, t, z, comps, "z" in lead, names, frame, extent_m, path)


MAX_CURRENT_MPS = 50.0
"""Largest current speed a file may hold, after its units (the fastest tidal races run at 8-11 m/s; hostile
round 20: a component of 1e30, ROMS's usual fill value left undeclared, passed ``validate``)."""


def _finish(grid: HorizontalGrid, t: NDArray[np.float64] | None, z: NDArray[np.float64],
            comps: dict[str, np.ndarray], has_z: bool, names: dict[str, str | None], frame: LocalFrame | None,
            extent_m: tuple[float, float, float, float] | None, path: Path) -> GriddedCurrent:
    """East/north components on the source grid → land filled, regridded into the local frame."""
    src = str(path)
    shape = (1 if t is None else t.size, z.size, *comps["u"].shape[-2:])
    for c, arr in comps.items():  # 1e30 m/s (an undeclared fill value, a wrong scale_factor) was read as a current
        big = np.abs(np.where(np.isfinite(arr), arr, 0.0)) > MAX_CURRENT_MPS
        if big.any():
            at = tuple(int(i) for i in np.unravel_index(int(np.argmax(big)), shape))
            raise DataError(f"{src}: variable {names[c]!r} holds {float(arr.reshape(shape)[at]):.3g} m/s (at "
                            f"{_where(grid, at[2], at[3])}, level {at[1]}, time {at[0]}; "
                            f"{int(big.sum()):,} such values): over the {MAX_CURRENT_MPS:g} m/s no ocean current "
                            "reaches; declare a fill value as _FillValue, or check the units and scale_factor")
    land = 0
    for c in comps:
        gaps, first = open_water_gaps(comps[c].reshape(shape))
        if first is not None:
            log.warning("%s: variable %r: %d missing value(s) in open water (below them the column has values, or "
                        "the place has values at other times), first at %s, level %d, time %d; filled from the "
                        "level above, else zero", src, names[c], gaps, _where(grid, first[2], first[3]), first[1],
                        first[0])
        comps[c], n = _fill_land(comps[c].reshape(shape), has_z, src, str(names[c]))
        land = max(land, n)
    if land:
        log.info("%s: %d horizontal cells without a value (land): zero current there", src, land)
    if grid.kind == "local":
        x, y = grid.cols, grid.rows
    else:
        x, y, comps = _regrid(grid, comps, frame, extent_m, False, {c: f"{src}: variable {names[c]!r}"
                                                                    for c in comps})
    return GriddedCurrent(x, y, z, comps["u"], comps["v"], comps.get("w"), t, name=path.name)


def _lead_axes(ds: Any, da: Any, horizontal: tuple[str, str], src: str) -> dict[str, str]:
    """The variable's dimensions before the horizontal two: ``{"t": name, "z": name}``, at most one each."""
    lead: dict[str, str] = {}
    for d in map(str, da.dims):
        if d in horizontal:
            continue
        kind = axis_kind(ds[d] if d in ds.variables else None, d)
        if kind not in ("t", "z") or kind in lead:
            raise DataError(f"{src}: variable {str(da.name)!r}: dimension {d!r} is neither one time nor one "
                            "depth axis")
        lead[kind] = d
    return lead


def _regrid(grid: Any, comps: dict[str, np.ndarray], frame: LocalFrame | None,
            extent_m: tuple[float, float, float, float] | None, grid_relative: bool,
            what: dict[str, str]) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """Geographic (or projected) components onto a local grid, the horizontal ones turned east/north."""
    if frame is None:
        lon, lat = np.mean(grid.cols), np.mean(grid.rows)
        frame = LocalFrame(float(lat), float(lon))
    regridded = {c: to_local(grid, a, frame, extent_m=extent_m, method="linear", what=what[c])
                 for c, a in comps.items()}
    x, y = regridded["u"][0], regridded["u"][1]
    out = {c: r[2] for c, r in regridded.items()}
    (ex, ey), (nx, ny) = _directions(grid, frame, x, y, grid_relative)
    u, v = out["u"], out["v"]
    out["u"], out["v"] = u * ex + v * nx, u * ey + v * ny
    return x, y, out
