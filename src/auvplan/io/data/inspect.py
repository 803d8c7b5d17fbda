"""``auvplan data inspect FILE``: what the readers detect in a data file, before a scenario uses it.

For every file: the format and its variables.  Then, as bathymetry: the elevation
variable, the layout of its horizontal axes (coordinates, coordinate-less dimensions with
1-D lat/lon variables, 2-D lat/lon, CRS), whether values are depths (and why), missing
values and the elevation range.  As currents: the u/v/w variables, their units and the
factor to m/s, time and depth axes, and the cells without a value (land).  A part that
does not apply says why in one line.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import xarray as xr
from xarray.backends import BackendEntrypoint, NetCDF4BackendEntrypoint

from ...errors import DataError
from ..files.limits import BudgetError, check_declared
from .bathymetry import _centre_lonlat
from .elevation import ElevationGrid, is_geotiff, read_elevation
from .geo import LocalFrame
from .grids import HorizontalGrid, axis_kind, horizontal_grid
from .inspect_frames import frame_lines, gap_line, roms_lines
from .ncfile import no_index
from .ocean.currents import _find, _z_axis, velocity_factor
from .ocean.roms import is_s_coordinate
from .regrid import _native_cell
from .seabed_model import model_seabed
from .terrain_grid import _fill_nan

__all__ = ["inspect_file"]


def _engine() -> type[BackendEntrypoint]:
    """xarray's NetCDF engine, named: no scan of every installed backend (rioxarray …, ~1 s; issue 56)."""
    return NetCDF4BackendEntrypoint


def _variables(path: Path) -> tuple[list[str], bool]:
    """The variables' lines, and whether an eastward/x velocity is among them (the file opened once)."""
    try:
        with xr.open_dataset(path, decode_times=False, engine=_engine(), **no_index()) as ds:
            out = [f"  {k}{tuple(map(str, v.dims))} {v.dtype}" + (f" [{v.attrs['units']}]" if "units" in v.attrs
                                                                   else "") for k, v in ds.variables.items()]
            has_current = _find(ds, "u", "", str(path), False) is not None
    except DataError:
        raise
    except Exception as exc:  # any unreadable file: say so, do not crash
        raise DataError(f"{path}: cannot read as NetCDF or GeoTIFF ({exc})") from exc
    return ["variables:", *out], has_current


def _bathymetry(path: Path) -> list[str]:
    try:
        eg = read_elevation(path)
    except BudgetError:
        raise  # a file too large to read is exit 2, not a layout that does not fit
    except DataError as exc:
        return [f"as bathymetry: not usable — {exc}"]
    z = eg.z[np.isfinite(eg.z)]
    rng = f"{z.min():.1f} .. {z.max():.1f} m" if z.size else "no value"
    return [
        f"as bathymetry: variable {eg.variable!r} ({eg.format})",
        f"  {eg.grid.describe()}",
        f"  values positive {eg.positive}; elevation (up) {rng}; {eg.missing} missing value(s)",
        *_seabed_costs(eg),
    ]


def _window(eg: ElevationGrid, z: np.ndarray, factor: float,
            max_nodes: float) -> tuple[HorizontalGrid, np.ndarray, str]:
    """The grid and data, or their centre part whose model at ``factor`` times the data's cell has at most
    ``max_nodes`` nodes (issue 56: a 1 MB file's finest model had 2 million nodes, ~10 s; at most 130 000
    nodes a model, the five models still cost ~2 s of CPU, at 40 000 ~0.6 s), and the note."""
    grid = eg.grid
    nr, nc = grid.rows.size, grid.cols.size
    shrink = math.sqrt(max_nodes * factor**2 / (nr * nc))
    if shrink >= 1.0:
        return grid, z, ""
    wr, wc = max(4, int(nr * shrink)), max(4, int(nc * shrink))
    r0, c0 = (nr - wr) // 2, (nc - wc) // 2
    part = replace(grid, rows=grid.rows[r0:r0 + wr], cols=grid.cols[c0:c0 + wc])
    return part, z[r0:r0 + wr, c0:c0 + wc], f" (the centre {wr} x {wc} data nodes)"


def _seabed_costs(eg: ElevationGrid, max_nodes: float = 4e4) -> list[str]:
    """What the conservative seabed model costs (its height above the data) at a few cell sizes (a model
    over ``max_nodes`` nodes is measured on the data's centre part)."""
    grid = eg.grid
    if grid.kind == "curvilinear":
        return ["  seabed model: 2-D lat/lon grid, triangulated linearly (no excess measured)"]
    if not np.isfinite(eg.z).any():
        return []
    native = _native_cell(grid)
    lon, lat = _centre_lonlat(grid) if grid.kind != "local" else (0.0, 0.0)
    frame = LocalFrame(lat, lon)
    z = _fill_nan(eg.z, "nearest", eg.name, lambda j, i: "")
    lines = ["  seabed model (conservative: never deeper than the data) — how much shallower, by cell:"]
    for factor in (0.1, 0.25, 0.5, 1.0, 2.0):
        cell = native * factor
        if grid.kind == "curvilinear" or min(grid.rows.size, grid.cols.size) / factor < 2:
            continue
        part, zpart, where = _window(eg, z, factor, max_nodes)
        try:
            *_, fit = model_seabed(part, zpart, frame, extent_m=None, cell_m=cell, method="conservative",
                                   what=eg.name)
        except DataError as exc:
            return [f"  seabed model: not measured ({exc})"]
        if fit is not None:
            lines.append(f"    cell {cell:.0f} m: up to {fit.excess_max_m:.1f} m, mean {fit.excess_mean_m:.2f} m "
                         f"at the nodes{where}")
    return lines


def _currents(path: Path) -> list[str]:
    src = str(path)
    try:
        with xr.open_dataset(path, decode_times=xr.coders.CFDatetimeCoder(use_cftime=None),
                             engine=_engine()) as ds:
            names = {c: _find(ds, c, "", src, c != "w") for c in "uvw"}
            if is_s_coordinate(ds, str(names["u"])):
                return roms_lines(ds, str(names["u"]), str(names["v"]))
            da = ds[names["u"]]
            rdim, cdim, grid, _, _ = horizontal_grid(ds, da, src)
            lines = [f"as currents: u {names['u']!r}, v {names['v']!r}, w {names['w']!r}",
                     f"  {grid.describe()}", *frame_lines(ds, str(names["u"]), grid, (rdim, cdim), src)]
            for n in names.values():
                if n is None:
                    continue
                units = str(ds[n].attrs.get("units", "")).strip()
                factor = velocity_factor(units, f"{src}: variable {n!r}") if units else 1.0
                check_declared(f"{src}: variable {n!r}", "declares", ds[n].shape)
                vals = np.asarray(ds[n].values, dtype=float)
                lines.append(f"  {n}: units {units or '(none: taken as m/s)'} → × {factor:g} to m/s; "
                             f"{int(np.count_nonzero(~np.isfinite(vals)))} missing value(s) (land → zero current)")
                gap = gap_line(ds, n, (rdim, cdim), src)
                lines += [gap] if gap else []
            for d in map(str, da.dims):
                if d in (rdim, cdim):
                    continue
                kind = axis_kind(ds[d] if d in ds.variables else None, d)
                if kind == "t" and d in ds.variables:
                    v = ds[d].values
                    cal = ds[d].encoding.get("calendar", "standard")
                    lines.append(f"  time {d!r}: {v.size} steps, {str(v.min())[:19]} .. {str(v.max())[:19]} "
                                 f"(calendar {cal})")
                elif kind == "z":
                    z = _z_axis(ds, d, src)
                    lines.append(f"  depth {d!r}: {z.size} levels, elevation {z.min():g} .. {z.max() + 0.0:g} m")
                else:
                    lines.append(f"  dimension {d!r}: not a time or depth axis")
    except BudgetError:
        raise
    except (DataError, ValueError, TypeError) as exc:
        return [f"as currents: not usable — {exc}"]
    return lines


def inspect_file(path: str | Path) -> str:
    """Report what auvplan detects in a data file (NetCDF or GeoTIFF).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    str
        A human-readable report: variables, and the file read as bathymetry and as currents.
    """
    path = Path(path)
    if not path.is_file():  # a folder, a FIFO or a device said 'file not found' (hostile round 20)
        raise DataError(f"{path}: file not found" if not path.exists() else
                        f"{path}: not a regular file (a FIFO, a device or a folder)")
    if is_geotiff(path):
        return "\n".join([f"{path}: GeoTIFF", *_bathymetry(path)])
    variables, has_current = _variables(path)
    lines = [f"{path}: NetCDF", *variables]
    bathy = _bathymetry(path)
    if not (has_current and "not usable" in bathy[0]):  # a current file is not expected to be a seabed
        lines += bathy
    lines += _currents(path) if has_current else ["as currents: no eastward/x velocity variable"]
    return "\n".join(lines)
