"""Elevation grids from files, in every layout the common producers write.

* NetCDF (CF/COARDS): GEBCO (``elevation(lat, lon)``), ETOPO 2022 (``z(lat, lon)``),
  EMODnet (``elevation`` beside statistics variables), GMT ≥ 4 (``z(y, x)`` or
  ``z(lat, lon)``), Ferret/GMT with coordinate-less dimensions and 1-D
  ``lat``/``lon`` variables, 2-D latitude/longitude, CF ``grid_mapping``
  projections, descending axes, 0–360 longitudes, depths positive down;
* the GMT 3 native NetCDF layout: 1-D ``z(xysize)`` with ``x_range``,
  ``y_range``, ``spacing``/``dimension`` and ``node_offset`` (rows north to south);
* GeoTIFF / Cloud-Optimised GeoTIFF through rioxarray: the CRS is read and the
  nodata value honoured (masked to NaN).

:func:`read_elevation` returns an :class:`ElevationGrid` (positive up, NaN where
missing, ascending axes) that :mod:`auvplan.io.data.bathymetry` projects into the
scenario frame, and that ``auvplan data inspect`` prints.
"""

from __future__ import annotations

import logging
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ...errors import DataError
from ..files.limits import check_declared
from .grids import HorizontalGrid, axis_kind, horizontal_grid
from .ncfile import check_dims, open_dataset, variable_values

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["ElevationGrid", "read_elevation", "is_geotiff", "length_factor"]

log = logging.getLogger(__name__)

_UP_STANDARD = {
    "height_above_mean_sea_level",
    "height_above_reference_ellipsoid",
    "height_above_geoid",
    "altitude",
    "surface_altitude",
    "height",
    "sea_floor_elevation",
}
_DOWN_STANDARD = {"sea_floor_depth_below_sea_surface", "sea_floor_depth_below_geoid", "sea_floor_depth", "depth"}
_UP_NAMES = ("elevation", "elev", "z", "topo", "topography", "height", "bathymetry", "band1", "altitude")
_DOWN_NAMES = ("depth", "deptho", "bathy_depth", "sea_floor_depth", "h")  # h: ROMS


@dataclass(frozen=True, eq=False)
class ElevationGrid:
    """An elevation grid as read from a file (not yet projected).

    Attributes
    ----------
    grid : HorizontalGrid
        Node positions (ascending axes).
    z : ndarray, shape ``(nrow, ncol)``
        Elevation, positive up (m); NaN where the file has no value.
    name : str
        ``file:variable``, used in messages.
    variable : str
        The variable read.
    format : str
        ``"NetCDF"``, ``"GMT 3 native NetCDF"`` or ``"GeoTIFF"``.
    positive : str
        ``"up"`` or ``"down"`` as stored, with the reason (for ``data inspect``).
    missing : int
        Number of nodes without a value.
    """

    grid: HorizontalGrid
    z: np.ndarray
    name: str
    variable: str
    format: str
    positive: str
    missing: int


def _attr(obj: xr.Dataset | xr.DataArray, name: str) -> str:
    return str(obj.attrs.get(name, "")).strip().lower()


def is_geotiff(path: Path) -> bool:
    """Tell a TIFF file by its magic number, whatever its suffix.

    Parameters
    ----------
    path : pathlib.Path
        The file.

    Returns
    -------
    bool
        True for a (Geo)TIFF file.
    """
    if not path.is_file():  # a FIFO: opening it to read the magic number blocked for ever
        return False
    try:
        with open(path, "rb") as fh:
            head = fh.read(4)
    except OSError:
        return False
    return head[:4] in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+")


def _find_elevation(ds: xr.Dataset, variable: str, src: str) -> str:
    if variable:
        if variable not in ds.data_vars:
            raise DataError(f"{src}: variable {variable!r} not found; it has {sorted(map(str, ds.data_vars))}")
        return variable
    two_d = [str(k) for k, v in ds.data_vars.items() if v.ndim >= 2 and axis_kind(v, str(k)) not in ("lat", "lon")]
    for k in two_d:
        if _attr(ds[k], "standard_name") in _UP_STANDARD | _DOWN_STANDARD:
            return k
    for names in (_UP_NAMES, _DOWN_NAMES):
        for k in two_d:
            if k.lower() in names:
                return k
    if len(two_d) == 1:
        return two_d[0]
    if not two_d:  # an elevation variable with the wrong dimensionality: say so, naming it
        for key, var in ds.data_vars.items():
            named = str(key).lower() in _UP_NAMES + _DOWN_NAMES
            if named or _attr(var, "standard_name") in _UP_STANDARD | _DOWN_STANDARD:
                check_dims(var, 2, src, "elevation")
    raise DataError(
        f"{src}: cannot tell which variable is the elevation among {two_d or sorted(map(str, ds.data_vars))}; "
        "name it with 'variable'"
    )


def _positive(da: xr.DataArray, positive: str) -> tuple[bool, str]:
    """``(down, reason)``: whether values are depths (positive down) and why we think so."""
    if positive:
        return positive == "down", f"{positive} (given in the scenario)"
    pos = _attr(da, "positive")
    if pos in ("up", "down"):
        return pos == "down", f"{pos} (attribute positive)"
    std = _attr(da, "standard_name")
    if std in _DOWN_STANDARD:
        return True, f"down (standard_name {std})"
    if std in _UP_STANDARD:
        return False, f"up (standard_name {std})"
    if str(da.name).lower() in _DOWN_NAMES:
        return True, f"down (variable name {da.name!r})"
    return False, "up (default: elevation)"


_METRES = re.compile(r"^(m|metres?|meters?)$")
"""Units that say metres (lower case)."""
_METRES_AND = re.compile(r"^(m|metres?|meters?)[.\s(,;]")
"""Metres followed by words (``m above mean sea level``, ``m (MSL)``, ``m.a.s.l.``)."""


def length_factor(units: str, where: str) -> float:
    """The factor from an elevation variable's (or a current file's depth axis's) ``units`` to metres.

    Metres however written, and no units, are 1; a length pint's CF registry reads (``ft``, ``fathoms``, ``km``,
    or such a unit followed by words) is converted (hostile round 22: a depth grid in feet was read as metres,
    the seabed 3.28 times too deep); units of another quantity (``m s-1``, ``degC``, ``degrees``) are refused.
    Text no registry reads is taken as metres, with a warning.

    Parameters
    ----------
    units : str
        The ``units`` attribute.
    where : str
        File and variable, for messages.

    Returns
    -------
    float
        Multiply the values by this to get metres.
    """
    text = units.strip()
    low = text.lower()
    if not text or text == "1" or _METRES.match(low) or (_METRES_AND.match(low) and not low.startswith("m ")):
        return 1.0
    from .ocean.currents import _unit_registry

    ureg = _unit_registry()
    for k, candidate in enumerate((text, low, re.split(r"[\s(]", low)[0])):
        if k == 2 and _METRES.match(candidate):
            return 1.0  # 'm above mean sea level': the words are not units
        try:
            q = ureg.Quantity(1.0, candidate)
        except Exception:  # pint raises several types for text it cannot read
            continue
        if q.check("[length]"):
            return float(q.to("m").magnitude)
        if k < 2:
            raise DataError(f"{where}: units {units!r} are not a length (dimension {q.dimensionality or 'angle'}); "
                            "an elevation or depth is in metres, feet, fathoms …")
    log.warning("%s: units %r are not units auvplan reads; taken as metres", where, units)
    return 1.0


def _open(path: Path, src: str) -> xr.Dataset:
    return open_dataset(path, "bathymetry", mask_and_scale=True, decode_times=False)  # faults diagnosed


def read_elevation(path: str | Path, *, variable: str = "", positive: str = "") -> ElevationGrid:
    """Read an elevation grid (NetCDF in any supported layout, or GeoTIFF).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    variable : str, optional
        Variable to read; detected when empty.
    positive : {'', 'up', 'down'}, optional
        Sign convention of the stored values; detected from the attributes when empty.

    Returns
    -------
    ElevationGrid
        The grid, elevation positive up (m).

    Raises
    ------
    DataError
        Naming the file, the variable and the fault.
    """
    path = Path(path)
    src = str(path)
    if path.is_file() and is_geotiff(path):
        return _read_geotiff(path, positive)
    with _open(path, src) as ds:
        if "x_range" in ds.variables and "dimension" in ds.variables and "z" in ds.variables \
                and ds["z"].ndim == 1:
            return _read_gmt3(ds, path, positive)
        var = _find_elevation(ds, variable, src)
        da = ds[var]
        check_declared(f"{src}: variable {var!r}", "declares", da.shape)  # before a byte is read
        rdim, cdim, grid, flip_r, flip_c = horizontal_grid(ds, da, src)
        extra = [d for d in da.dims if d not in (rdim, cdim)]
        for d in extra:
            if da.sizes[d] != 1:
                raise DataError(f"{src}: variable {var!r} must be 2-D; dimension {d!r} has {da.sizes[d]} values")
        da = da.isel({d: 0 for d in extra}).transpose(rdim, cdim)
        z = variable_values(da, src)
        down, why = _positive(da, positive)
        units = str(da.attrs.get("units", ""))
    return _finish(grid, z, flip_r, flip_c, down, why, f"{path.name}:{var}", var, "NetCDF", units,
                   f"{src}: variable {var!r}")


def _finish(grid: HorizontalGrid, z: NDArray[np.float64], flip_r: bool, flip_c: bool, down: bool, why: str, name: str,
            var: str, fmt: str, units: str = "", where: str = "") -> ElevationGrid:
    factor = length_factor(units, where or name)
    if factor != 1.0:
        z = z * factor
        why = f"{why}; units {units.strip()!r}, × {factor:g} to metres"
    if flip_r:
        z = z[::-1]
    if flip_c:
        z = z[:, ::-1]
    if down:
        z = -z
    z = np.ascontiguousarray(z)
    return ElevationGrid(grid, z, name, var, fmt, why, int(np.count_nonzero(~np.isfinite(z))))


def _read_gmt3(ds: xr.Dataset, path: Path, positive: str) -> ElevationGrid:
    """GMT 3's native NetCDF grid: ``z(xysize)`` stored row by row from the north."""
    src = str(path)
    try:
        nx, ny = (int(v) for v in np.asarray(ds["dimension"].values).reshape(-1)[:2])
        xr_, yr_ = np.asarray(ds["x_range"].values, float), np.asarray(ds["y_range"].values, float)
    except (ValueError, TypeError) as exc:
        raise DataError(f"{src}: GMT 3 grid: unreadable 'dimension'/'x_range'/'y_range' ({exc})") from exc
    check_declared(f"{src}: variable 'z'", "declares", ds["z"].shape)
    z = np.asarray(ds["z"].values, dtype=float)
    if nx < 2 or ny < 2 or z.size != nx * ny:
        raise DataError(f"{src}: variable 'z' has {z.size} values, but dimension says {nx} x {ny}")
    offset = int(ds["z"].attrs.get("node_offset", ds.attrs.get("node_offset", 0)))
    dx, dy = (xr_[1] - xr_[0]) / (nx - 1 + offset), (yr_[1] - yr_[0]) / (ny - 1 + offset)
    half = 0.5 if offset else 0.0
    x = xr_[0] + (np.arange(nx) + half) * dx
    y = yr_[1] - (np.arange(ny) + half) * dy
    units = str(ds["x_range"].attrs.get("units", "")).lower()
    kind = "local" if units in ("m", "meter", "metre", "meters", "metres") else "lonlat"
    if kind == "lonlat":
        x = x[0] + np.mod(x - x[0], 360.0)
    grid = HorizontalGrid(kind, y[::-1].copy(), x, None, "GMT 3 native: z(xysize), x_range/y_range/dimension")
    down, why = _positive(ds["z"], positive)
    return _finish(grid, z.reshape(ny, nx), True, False, down, why, f"{path.name}:z", "z", "GMT 3 native NetCDF",
                   str(ds["z"].attrs.get("units", "")), f"{src}: variable 'z'")


def _read_geotiff(path: Path, positive: str) -> ElevationGrid:
    src = str(path)
    try:
        import rioxarray  # noqa: F401  (registers the .rio accessor)

        da: xr.DataArray = rioxarray.open_rasterio(path, masked=True)  # type: ignore[assignment]  # one raster
    except Exception as exc:  # rasterio raises many types for broken files
        raise DataError(f"{src}: cannot read as GeoTIFF ({exc})") from exc
    with da:
        check_declared(f"{src}: band 1", "declares", da.shape[-2:])  # rasterio reads the header only
        if da.sizes.get("band", 1) != 1:
            raise DataError(f"{src}: band: the GeoTIFF has {da.sizes['band']} bands; one elevation band is needed")
        crs = da.rio.crs
        if crs is None:
            raise DataError(f"{src}: crs: the GeoTIFF has no coordinate reference system")
        from pyproj import CRS

        pcrs = CRS.from_user_input(crs.to_wkt())
        if not (pcrs.is_geographic or pcrs.is_projected):  # a pyproj traceback (engineering) or read as a map
            raise DataError(f"{src}: crs {pcrs.name!r} ({pcrs.type_name}) is not longitude/latitude or a map "
                            "projection: the grid has no place on the Earth's surface")
        t = da.rio.transform()
        if t.b or t.d:  # rioxarray then numbers the pixels 0, 1, 2 … as the coordinates (hostile round 22)
            raise DataError(f"{src}: the GeoTIFF's grid is rotated or sheared (geotransform {tuple(t)[:6]}); auvplan "
                            "reads north-up grids: warp it first (gdalwarp)")
        x = np.asarray(da["x"].values, dtype=float)
        y = np.asarray(da["y"].values, dtype=float)
        z = np.asarray(da.isel(band=0).values, dtype=float) if "band" in da.dims else np.asarray(da.values, float)
        nodata = da.rio.encoded_nodata
        desc = str(da.attrs.get("long_name", "band 1"))
    kind = "lonlat" if pcrs.is_geographic else "projected"
    flip_r, flip_c = bool(y[0] > y[-1]), bool(x[0] > x[-1])
    rows, cols = (y[::-1] if flip_r else y), (x[::-1] if flip_c else x)
    if kind == "lonlat":
        cols = cols[0] + np.mod(cols - cols[0], 360.0)
    if rows.size < 2 or cols.size < 2:
        raise DataError(f"{src}: band 1: the grid needs at least 2 x 2 pixels, got {rows.size} x {cols.size}")
    layout = f"GeoTIFF pixel centres, nodata {nodata}" if nodata is not None else "GeoTIFF pixel centres, no nodata"
    grid = HorizontalGrid(kind, rows, cols, None if kind == "lonlat" else pcrs, layout)
    down = positive == "down"
    why = f"{positive} (given in the scenario)" if positive else "up (GeoTIFF default: elevation)"
    return _finish(grid, z, flip_r, flip_c, down, why, f"{path.name}:{desc}", desc, "GeoTIFF")
