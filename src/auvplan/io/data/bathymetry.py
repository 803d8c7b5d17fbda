"""Read seabed elevation grids (GEBCO, ETOPO, EMODnet, GMT, Ferret NetCDF, GeoTIFF) into a :class:`Terrain`.

What the reader handles, each covered by a round-trip test (file layouts: :mod:`auvplan.io.data.elevation`):

* the elevation variable found by CF ``standard_name``, common names
  (``elevation``, ``z``, ``topo``, ``depth``, ``Band1`` …) or given explicitly;
* elevation positive up or depth positive down (``positive`` attribute,
  ``standard_name``, the variable's name, or the ``positive`` option);
* geographic axes (1-D or 2-D lat/lon, coordinate-less dimensions with 1-D lat/lon
  variables, 0–360 longitudes, descending axes), CF ``grid_mapping`` and GeoTIFF
  projections (e.g. UTM), all projected about the scenario origin with pyproj;
  metric x/y axes without a CRS are used as they are;
* fill values / NaN: ``nan_policy="error"`` (default, a clear error naming the
  count and the first location), ``"land"`` (no-go: elevation +1 m) or
  ``"nearest"`` (nearest valid value);
* a crop to a lat/lon box and a resampling to a target cell size, by default
  ``conservative``: the model is never deeper than the data, and how much shallower
  it is gets measured (:mod:`auvplan.io.data.seabed_model`; ``linear``, ``cubic`` … on request).

Built-in real terrains: ``etopo1-marcus-wake``, ``etopo1-ninetyeast``, ``etopo1-new-england``,
``etopo1-chagos`` and ``etopo1-mariana`` (ETOPO1 cut-outs shipped in ``auvplan/data``) and
``matplotlib-topobathy`` (``topobathy.npz`` read through
``matplotlib.cbook.get_sample_data``; its value −1 marks shore water with no
depth and is treated as no-go).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...errors import DataError
from ...world.seabed import SeabedFit
from ...world.terrain import Terrain
from .elevation import is_geotiff, read_elevation
from .geo import LocalFrame, normalise_lon
from .grids import HorizontalGrid, horizontal_grid
from .regrid import data_span
from .seabed_model import METHODS, model_seabed

__all__ = [
    "TerrainSpec",
    "read_bathymetry",
    "terrain_from_lonlat",
    "terrain_from_xy",
    "terrain_from_grid",
    "load_terrain",
    "BUILTIN_TERRAINS",
    "builtin_terrain_path",
    "MAX_ELEVATION_M",
]

_F64 = NDArray[np.float64]
"""Array of float64."""

log = logging.getLogger(__name__)

BUILTIN_TERRAINS = {
    "etopo1-marcus-wake": "ETOPO1 1' relief (NOAA NGDC), 0.1° cut-out 14.2-16.3 N, 157.9-160.0 E (seamounts)",
    "matplotlib-topobathy": "matplotlib sample topobathy.npz, 48-50 N, 126-122 W, ~2.4 km (Juan de Fuca, Georgia)",
    "etopo1-ninetyeast": "ETOPO1 1' relief (NOAA NGDC), 0.1° cut-out 12.0-9.2 S, 87.6-90.8 E (Ninetyeast Ridge)",
    "etopo1-new-england": "ETOPO1 1' relief (NOAA NGDC), 0.1° cut-out 37.4-39.5 N, 63.3-60.4 W (New England Seamounts)",
    "etopo1-chagos": "ETOPO1 1' relief (NOAA NGDC), 0.1° cut-out 7.4-4.6 S, 70.4-73.3 E (Chagos banks and atolls)",
    "etopo1-mariana": "ETOPO1 1' relief (NOAA NGDC), 0.1° cut-out 15.8-19.0 N, 144.2-147.4 E (Mariana arc)",
}
_BUILTIN_FILES = {
    "etopo1-marcus-wake": "etopo1_seed_marcus_wake.nc",
    "etopo1-ninetyeast": "etopo1_ninetyeast.nc",
    "etopo1-new-england": "etopo1_new_england.nc",
    "etopo1-chagos": "etopo1_chagos.nc",
    "etopo1-mariana": "etopo1_mariana.nc",
}

@dataclass(frozen=True)
class TerrainSpec:
    """How to obtain the terrain of a scenario (the ``[terrain]`` table).

    Attributes
    ----------
    file : str
        NetCDF file (relative paths are resolved against the scenario's folder).
    builtin : str
        Name of a built-in terrain (see ``BUILTIN_TERRAINS``); exclusive with ``file``.
    variable : str
        Elevation variable; found automatically when empty.
    positive : str
        ``"up"`` (elevation), ``"down"`` (depth) or ``""`` to detect.
    box : tuple
        ``(lat_min, lat_max, lon_min, lon_max)`` crop in degrees; empty for no crop.
    resample_m : float
        Target cell size (m); 0 keeps the data's own spacing.
    method : str
        Resampling: ``"conservative"`` (default: never deeper than the data), or ``"linear"``,
        ``"cubic"``, ``"quintic"``, ``"pchip"`` (which can lie below it).
    nan_policy : str
        ``"error"``, ``"land"`` or ``"nearest"``.
    uncertainty : str
        Vertical uncertainty of the seabed (issue 39, :mod:`auvplan.world.uncertainty`): the name of the
        file's one-sigma uncertainty variable (m), ``"slope"`` for the slope rule, or ``""`` (then
        ``uncertainty_m`` alone, a constant).  Used with ``[mission] confidence``.
    uncertainty_m : float
        A constant one-sigma uncertainty (m), or the slope rule's floor σ₀.
    """

    file: str = ""
    builtin: str = ""
    variable: str = ""
    positive: str = ""
    box: tuple[float, ...] = ()
    resample_m: float = 0.0
    method: str = "conservative"
    nan_policy: str = "error"
    uncertainty: str = ""
    uncertainty_m: float = 0.0

    def __post_init__(self) -> None:
        if bool(self.file) == bool(self.builtin):
            raise ValueError("give exactly one of 'file' and 'builtin'")
        if self.builtin and self.builtin not in BUILTIN_TERRAINS:
            raise ValueError(f"unknown builtin terrain {self.builtin!r}; choose from {sorted(BUILTIN_TERRAINS)}")
        if self.positive not in ("", "up", "down"):
            raise ValueError(f"positive must be 'up' or 'down', got {self.positive!r}")
        if self.box and len(self.box) != 4:
            raise ValueError(f"box must be [lat_min, lat_max, lon_min, lon_max], got {list(self.box)}")
        if self.box and not (self.box[0] < self.box[1]):
            raise ValueError(f"box latitudes must satisfy lat_min < lat_max, got {list(self.box)}")
        if self.resample_m < 0:
            raise ValueError(f"resample_m must be >= 0, got {self.resample_m}")
        if self.method not in METHODS:
            raise ValueError(f"method must be one of {', '.join(METHODS)}; got {self.method!r}")
        if self.nan_policy not in ("error", "land", "nearest"):
            raise ValueError(f"nan_policy must be error, land or nearest; got {self.nan_policy!r}")
        if self.uncertainty_m < 0:
            raise ValueError(f"uncertainty_m = {self.uncertainty_m}: must be >= 0")
        if self.uncertainty and self.uncertainty != "slope" and not self.file:
            raise ValueError(f"uncertainty = {self.uncertainty!r}: a variable needs a [terrain] file (or use 'slope')")


def builtin_terrain_path(name: str) -> Path:
    """Return the path of a built-in NetCDF terrain shipped with the package.

    Parameters
    ----------
    name : str
        Built-in terrain name.

    Returns
    -------
    pathlib.Path
        The NetCDF file.
    """
    if name not in _BUILTIN_FILES:
        raise DataError(f"built-in terrain {name!r} is not a NetCDF file")
    return Path(str(resources.files("auvplan") / "data" / _BUILTIN_FILES[name]))


MAX_ELEVATION_M = 12_000.0
"""Largest elevation or depth a grid may hold, after its units (m): the Challenger Deep is 10 935 m deep, Everest
8 849 m high (hostile round 22: a land cell filled with -1e30 that the file did not declare as its fill value was
read as a seabed 10³⁰ m deep, and flown through)."""


# ---------------------------------------------------------------------- grid → Terrain
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


def read_bathymetry(
    path: str | Path,
    *,
    frame: LocalFrame | None = None,
    variable: str = "",
    positive: str = "",
    box: tuple[float, ...] = (),
    extent_m: tuple[float, float, float, float] | None = None,
    resample_m: float = 0.0,
    method: str = "conservative",
    nan_policy: str = "error",
) -> Terrain:
    """Read a bathymetry/topography grid (NetCDF in any supported layout, or GeoTIFF) into a Terrain.

    Geographic and projected grids need ``frame`` (the local frame about the scenario origin);
    without one, the frame is centred on the box or on the data.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    frame : LocalFrame, optional
        The local frame.
    variable : str, optional
        Elevation variable; detected when empty.
    positive : {'', 'up', 'down'}, optional
        Sign convention of the stored values; detected when empty.
    box : tuple of 4 float, optional
        ``(lat_min, lat_max, lon_min, lon_max)`` crop (degrees).
    extent_m : tuple of 4 float, optional
        ``(xmin, xmax, ymin, ymax)`` to cover (m).
    resample_m : float, optional
        Cell of the regular metric grid (m); 0: the data's own spacing.
    method : str, optional
        Resampling method.
    nan_policy : {'error', 'land', 'nearest'}, optional
        Missing values: an error, no-go land, or the nearest valid value.

    Returns
    -------
    Terrain
        The seabed in the local frame (m, up positive).
    """
    eg = read_elevation(path, variable=variable, positive=positive)
    grid = eg.grid
    if frame is None and grid.kind != "local":
        if box:
            frame = LocalFrame(0.5 * (box[0] + box[1]), 0.5 * (box[2] + box[3]))
        else:
            lon, lat = _centre_lonlat(grid)
            frame = LocalFrame(lat, lon)
    return terrain_from_grid(grid, eg.z, frame=frame, box=box, extent_m=extent_m, resample_m=resample_m,  # type: ignore[arg-type]
                             method=method, nan_policy=nan_policy, name=eg.name)


def _centre_lonlat(grid: HorizontalGrid) -> tuple[float, float]:
    if grid.kind == "projected":
        from pyproj import Transformer

        tr = Transformer.from_crs(grid.crs, "EPSG:4326", always_xy=True)
        lon, lat = tr.transform(float(np.mean(grid.cols)), float(np.mean(grid.rows)))
        return float(lon), float(lat)
    return float(np.mean(grid.cols)), float(np.mean(grid.rows))


def _topobathy() -> tuple[_F64, _F64, _F64]:
    from matplotlib import cbook

    data: Any = cbook.get_sample_data("topobathy.npz")  # an NpzFile (typed as ndarray | IO by matplotlib)
    lon = np.asarray(data["longitude"], dtype=float)
    lat = np.asarray(data["latitude"], dtype=float)
    topo = np.asarray(data["topo"], dtype=float)
    # -1 marks shore water with no depth: no-go (like land)
    topo = np.where(topo == -1.0, 1.0, topo)
    return lon, lat, topo


def load_terrain(
    spec: TerrainSpec,
    frame: LocalFrame | None,
    *,
    base_dir: Path | None = None,
    extent_m: tuple[float, float, float, float] | None = None,
) -> Terrain:
    """Obtain the terrain described by ``spec`` (file or built-in) in ``frame``.

    The result is kept on disk under a key of the file's bytes (a GeoTIFF's with those of the sidecar files
    GDAL reads with it: ``.aux.xml``, a world file …), the request and the code
    (:mod:`auvplan.io.data.cache`): the same scenario's seabed is modelled once.

    Parameters
    ----------
    spec : TerrainSpec
        The ``[terrain]`` table.
    frame : LocalFrame or None
        The scenario's local frame.
    base_dir : pathlib.Path, optional
        Folder that relative file names resolve against.
    extent_m : tuple of 4 float, optional
        ``(xmin, xmax, ymin, ymax)`` to cover (m).

    Returns
    -------
    Terrain
        The seabed in the local frame (m, up positive).
    """
    from .cache import cached, dataset_files

    path = _topobathy_path() if spec.builtin == "matplotlib-topobathy" else (
        builtin_terrain_path(spec.builtin) if spec.builtin else Path(spec.file))
    if not path.is_absolute() and base_dir is not None:
        path = base_dir / path
    request = (spec, None if frame is None else (frame.lat0, frame.lon0), extent_m)
    files = dataset_files(path) if is_geotiff(path) else [path]  # a GeoTIFF with the sidecars GDAL reads
    return cached("terrain", request, files, lambda: _load_terrain(spec, frame, path, extent_m), _pack, _unpack)


def _topobathy_path() -> Path:
    """Where matplotlib keeps ``topobathy.npz`` (found without importing matplotlib)."""
    from importlib.util import find_spec

    found = find_spec("matplotlib")
    where = list(found.submodule_search_locations or []) if found is not None else []
    return Path(where[0] if where else ".") / "mpl-data" / "sample_data" / "topobathy.npz"


def _load_terrain(spec: TerrainSpec, frame: LocalFrame | None, path: Path,
                  extent_m: tuple[float, float, float, float] | None) -> Terrain:
    common: dict[str, Any] = dict(box=spec.box, extent_m=extent_m, resample_m=spec.resample_m, method=spec.method,
                                  nan_policy=spec.nan_policy)
    if spec.builtin == "matplotlib-topobathy":
        lon, lat, topo = _topobathy()
        if frame is None:
            frame = LocalFrame(float(lat.mean()), float(lon.mean()))
        return terrain_from_lonlat(lon, lat, topo, frame=frame, name="matplotlib:topobathy.npz", **common)
    return read_bathymetry(path, frame=frame, variable=spec.variable, positive=spec.positive, **common)


def _pack(t: Terrain) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    fit = None if t.fit is None else [t.fit.method, t.fit.excess_max_m, t.fit.excess_mean_m, t.fit.deficit_max_m]
    return {"x": t.x, "y": t.y, "z": t.z}, {"name": t.name, "fit": fit}


def _unpack(arrays: dict[str, np.ndarray], meta: dict[str, Any]) -> Terrain:
    fit = meta["fit"]
    return Terrain(arrays["x"], arrays["y"], arrays["z"], name=meta["name"],
                   fit=None if fit is None else SeabedFit(str(fit[0]), *map(float, fit[1:])))
