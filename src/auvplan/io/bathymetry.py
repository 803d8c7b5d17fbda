"""Read seabed elevation grids (GEBCO, ETOPO, GMT, generic CF NetCDF) into a :class:`Terrain`.

What the reader handles, each covered by a round-trip test:

* the elevation variable found by CF ``standard_name``, common names
  (``elevation``, ``z``, ``topo``, ``depth``, ``Band1`` …) or given explicitly;
* elevation positive up or depth positive down (``positive`` attribute,
  ``standard_name``, the variable's name, or the ``positive`` option);
* geographic axes (lat/lon, by ``standard_name``, ``units`` or name; 0–360
  longitudes; descending axes) projected about the scenario origin with
  pyproj, or metric x/y axes used as they are;
* fill values / NaN: ``nan_policy="error"`` (default, a clear error naming the
  count and the first location), ``"land"`` (no-go: elevation +1 m) or
  ``"nearest"`` (nearest valid value);
* a crop to a lat/lon box and a smooth resampling to a target cell size
  (cubic by default: the 0.1° ETOPO1 cut-out is ~11 km per cell).

Built-in real terrains: ``etopo1-marcus-wake`` (the ETOPO1 cut-out shipped in
``auvplan/data``) and ``matplotlib-topobathy`` (``topobathy.npz`` read through
``matplotlib.cbook.get_sample_data``; its value −1 marks shore water with no
depth and is treated as no-go).
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from scipy import ndimage

from ..errors import DataError
from ..world.terrain import Terrain
from .geo import LocalFrame, normalise_lon, regrid_lonlat

__all__ = [
    "TerrainSpec",
    "read_bathymetry",
    "terrain_from_lonlat",
    "terrain_from_xy",
    "load_terrain",
    "BUILTIN_TERRAINS",
    "builtin_terrain_path",
]

BUILTIN_TERRAINS = {
    "etopo1-marcus-wake": "ETOPO1 1' relief (NOAA NGDC), 0.1° cut-out 14.2-16.3 N, 157.9-160.0 E (seamounts)",
    "matplotlib-topobathy": "matplotlib sample topobathy.npz, 48-50 N, 126-122 W, ~2.4 km (Juan de Fuca, Georgia)",
}

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
_DOWN_NAMES = ("depth", "deptho", "bathy_depth", "sea_floor_depth")
_LON_UNITS = {"degrees_east", "degree_east", "degree_e", "degrees_e", "degreee", "degreese"}
_LAT_UNITS = {"degrees_north", "degree_north", "degree_n", "degrees_n", "degreen", "degreesn"}


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
        Resampling interpolation: ``"cubic"`` (smooth, default) or ``"linear"``.
    nan_policy : str
        ``"error"``, ``"land"`` or ``"nearest"``.
    """

    file: str = ""
    builtin: str = ""
    variable: str = ""
    positive: str = ""
    box: tuple[float, ...] = ()
    resample_m: float = 0.0
    method: str = "cubic"
    nan_policy: str = "error"

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
        if self.method not in ("cubic", "linear", "quintic", "pchip"):
            raise ValueError(f"method must be one of cubic, linear, quintic, pchip; got {self.method!r}")
        if self.nan_policy not in ("error", "land", "nearest"):
            raise ValueError(f"nan_policy must be error, land or nearest; got {self.nan_policy!r}")


def builtin_terrain_path(name: str) -> Path:
    """Path of a built-in NetCDF terrain shipped with the package."""
    if name != "etopo1-marcus-wake":
        raise DataError(f"built-in terrain {name!r} is not a NetCDF file")
    return Path(str(resources.files("auvplan") / "data" / "etopo1_seed_marcus_wake.nc"))


# ---------------------------------------------------------------------- variable detection
def _attr(obj, name: str) -> str:
    return str(obj.attrs.get(name, "")).strip().lower()


def _find_elevation(ds: xr.Dataset, variable: str, src: str) -> str:
    if variable:
        if variable not in ds.data_vars:
            raise DataError(f"{src}: variable {variable!r} not found; it has {sorted(map(str, ds.data_vars))}")
        return variable
    two_d = [str(k) for k, v in ds.data_vars.items() if v.ndim == 2]
    for k in two_d:
        if _attr(ds[k], "standard_name") in _UP_STANDARD | _DOWN_STANDARD:
            return k
    for names in (_UP_NAMES, _DOWN_NAMES):
        for k in two_d:
            if k.lower() in names:
                return k
    if len(two_d) == 1:
        return two_d[0]
    raise DataError(
        f"{src}: cannot tell which variable is the elevation among {two_d or sorted(map(str, ds.data_vars))}; "
        "name it with 'variable'"
    )


def _is_down(da: xr.DataArray, positive: str) -> bool:
    if positive:
        return positive == "down"
    pos = _attr(da, "positive")
    if pos in ("up", "down"):
        return pos == "down"
    if _attr(da, "standard_name") in _DOWN_STANDARD:
        return True
    return str(da.name).lower() in _DOWN_NAMES


def _axis_kind(ds: xr.Dataset, dim: str) -> str:
    """'lon', 'lat', 'x' or 'y' for a dimension, from CF attributes or its name."""
    coord = ds[dim] if dim in ds.variables else None
    std = _attr(coord, "standard_name") if coord is not None else ""
    units = _attr(coord, "units").replace(" ", "") if coord is not None else ""
    long_name = _attr(coord, "long_name") if coord is not None else ""
    name = dim.lower()
    if std == "longitude" or units in _LON_UNITS or name in ("lon", "longitude", "long") or long_name == "longitude":
        return "lon"
    if std == "latitude" or units in _LAT_UNITS or name in ("lat", "latitude") or long_name == "latitude":
        return "lat"
    if std == "projection_x_coordinate" or name in ("x", "easting", "east"):
        return "x" if units in ("m", "metre", "meter", "metres", "meters", "km", "") else "lon"
    if std == "projection_y_coordinate" or name in ("y", "northing", "north"):
        return "y" if units in ("m", "metre", "meter", "metres", "meters", "km", "") else "lat"
    raise DataError(f"axis {dim!r}: cannot tell whether it is longitude, latitude, x or y (units {units!r})")


def _fill_nan(z: np.ndarray, policy: str, src: str, where) -> np.ndarray:
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
    idx = ndimage.distance_transform_edt(bad, return_distances=False, return_indices=True)
    return z[tuple(idx)]


# ---------------------------------------------------------------------- grid → Terrain
def terrain_from_lonlat(
    lon,
    lat,
    elevation,
    *,
    frame: LocalFrame,
    box: tuple[float, ...] = (),
    extent_m: tuple[float, float, float, float] | None = None,
    resample_m: float = 0.0,
    method: str = "cubic",
    nan_policy: str = "error",
    name: str = "",
) -> Terrain:
    """Build a Terrain from elevation (positive up) on a lat/lon grid ``(nlat, nlon)``.

    Axes may be descending and longitudes 0–360 or ±180; ``box`` crops
    (keeping one node of margin), then the grid is projected into ``frame`` and
    resampled onto a regular metric grid.
    """
    lon = np.asarray(lon, dtype=float).reshape(-1)
    lat = np.asarray(lat, dtype=float).reshape(-1)
    z = np.asarray(elevation, dtype=float)
    if lon.size == 0 or lat.size == 0 or z.size == 0:
        raise DataError(f"{name}: empty grid (lat {lat.size}, lon {lon.size})")
    if z.shape != (lat.size, lon.size):
        raise DataError(f"{name}: elevation shape {z.shape} does not match (lat, lon) = ({lat.size}, {lon.size})")
    # ascending axes; longitudes made monotonic on one branch
    if lat.size > 1 and lat[0] > lat[-1]:
        lat, z = lat[::-1], z[::-1]
    if lon.size > 1 and lon[0] > lon[-1]:
        lon, z = lon[::-1], z[:, ::-1]
    lon = lon[0] + np.mod(lon - lon[0], 360.0)
    if np.any(np.diff(lon) <= 0) or np.any(np.diff(lat) <= 0):
        raise DataError(f"{name}: latitude and longitude axes must be strictly monotonic")
    if box:
        la0, la1, lo0, lo1 = box
        lo0 = lon[0] + np.mod(lo0 - lon[0], 360.0)
        lo1 = lo0 + np.mod(lo1 - lo0, 360.0)
        if la1 < lat[0] or la0 > lat[-1] or lo0 > lon[-1]:
            raise DataError(
                f"{name}: the box {list(box)} does not overlap the data "
                f"(lat {lat[0]:.4f}..{lat[-1]:.4f}, lon {normalise_lon(lon[0]):.4f}..{normalise_lon(lon[-1]):.4f})"
            )
        i0 = max(int(np.searchsorted(lon, lo0, side="right")) - 2, 0)
        i1 = min(int(np.searchsorted(lon, lo1, side="left")) + 2, lon.size)
        j0 = max(int(np.searchsorted(lat, la0, side="right")) - 2, 0)
        j1 = min(int(np.searchsorted(lat, la1, side="left")) + 2, lat.size)
        lon, lat, z = lon[i0:i1], lat[j0:j1], z[j0:j1, i0:i1]
        if lon.size < 2 or lat.size < 2:
            raise DataError(f"{name}: the box {list(box)} leaves fewer than 2 x 2 grid nodes")
    if lon.size < 2 or lat.size < 2:
        raise DataError(f"{name}: the grid needs at least 2 x 2 nodes, got {lat.size} x {lon.size}")
    z = _fill_nan(z, nan_policy, name, lambda j, i: f"lat {lat[j]:.4f}, lon {normalise_lon(lon[i]):.4f}")
    x, y, zz = regrid_lonlat(
        lon, lat, z, frame, extent_m=extent_m, cell_m=resample_m or None, method=method, what=name
    )
    return Terrain(x, y, zz, name=name)


def terrain_from_xy(x, y, elevation, *, resample_m: float = 0.0, nan_policy: str = "error", name: str = "") -> Terrain:
    """Build a Terrain from elevation on metric axes (any order, possibly non-uniform)."""
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
    z = _fill_nan(z, nan_policy, name, lambda j, i: f"x {x[i]:.1f}, y {y[j]:.1f}")
    step_x, step_y = np.diff(x), np.diff(y)
    uniform = x.size > 1 and y.size > 1 and np.allclose(step_x, step_x[0]) and np.allclose(step_y, step_y[0])
    if resample_m or not uniform:
        from scipy.interpolate import RegularGridInterpolator

        cell = resample_m or float(min(step_x.min(), step_y.min()))
        nx = max(int(round((x[-1] - x[0]) / cell)) + 1, 2)
        ny = max(int(round((y[-1] - y[0]) / cell)) + 1, 2)
        xi, yi = np.linspace(x[0], x[-1], nx), np.linspace(y[0], y[-1], ny)
        gy, gx = np.meshgrid(yi, xi, indexing="ij")
        z = RegularGridInterpolator((y, x), z)(np.column_stack([gy.ravel(), gx.ravel()])).reshape(ny, nx)
        x, y = xi, yi
    return Terrain(x, y, z, name=name)


def read_bathymetry(
    path,
    *,
    frame: LocalFrame | None = None,
    variable: str = "",
    positive: str = "",
    box: tuple[float, ...] = (),
    extent_m: tuple[float, float, float, float] | None = None,
    resample_m: float = 0.0,
    method: str = "cubic",
    nan_policy: str = "error",
) -> Terrain:
    """Read a NetCDF bathymetry/topography grid into a Terrain.

    Geographic grids need ``frame`` (the local frame about the scenario origin);
    without one, the frame is centred on the (cropped) grid.
    """
    path = Path(path)
    src = str(path)
    if not path.is_file():
        raise DataError(f"{src}: bathymetry file not found")
    try:
        ds = xr.open_dataset(path, mask_and_scale=True)
    except Exception as exc:  # xarray raises many types for unreadable files
        raise DataError(f"{src}: cannot read as NetCDF ({exc})") from exc
    with ds:
        var = _find_elevation(ds, variable, src)
        da = ds[var]
        if da.ndim != 2:
            raise DataError(f"{src}: variable {var!r} must be 2-D, has dims {da.dims}")
        kinds = [_axis_kind(ds, str(d)) for d in da.dims]
        if sorted(kinds) not in (["lat", "lon"], ["x", "y"]):
            raise DataError(f"{src}: variable {var!r} has axes {dict(zip(da.dims, kinds))}; need lat/lon or x/y")
        order = ["lat", "lon"] if "lat" in kinds else ["y", "x"]
        da = da.transpose(*[da.dims[kinds.index(k)] for k in order])
        z = np.asarray(da.values, dtype=float)
        if _is_down(da, positive):
            z = -z
        a0 = np.asarray(ds[da.dims[0]].values, dtype=float) if da.dims[0] in ds.variables else None
        a1 = np.asarray(ds[da.dims[1]].values, dtype=float) if da.dims[1] in ds.variables else None
        if a0 is None or a1 is None:
            raise DataError(f"{src}: variable {var!r} has a dimension without coordinate values")
        if order[1] == "x" and _attr(ds[da.dims[1]], "units") == "km":
            a0, a1 = a0 * 1000.0, a1 * 1000.0
    name = f"{path.name}:{var}"
    if order[0] == "lat":
        if frame is None:
            lat0 = float(np.mean(box[:2]) if box else a0.mean())
            frame = LocalFrame(lat0, float(np.mean(box[2:]) if box else a1.mean()))
        return terrain_from_lonlat(
            a1, a0, z, frame=frame, box=box, extent_m=extent_m, resample_m=resample_m,
            method=method, nan_policy=nan_policy, name=name,
        )
    return terrain_from_xy(a1, a0, z, resample_m=resample_m, nan_policy=nan_policy, name=name)


def _topobathy():
    from matplotlib import cbook

    data = cbook.get_sample_data("topobathy.npz")
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
    """Obtain the terrain described by ``spec`` (file or built-in) in ``frame``."""
    common: dict[str, Any] = dict(box=spec.box, extent_m=extent_m, resample_m=spec.resample_m, method=spec.method,
                                  nan_policy=spec.nan_policy)
    if spec.builtin == "matplotlib-topobathy":
        lon, lat, topo = _topobathy()
        if frame is None:
            frame = LocalFrame(float(lat.mean()), float(lon.mean()))
        return terrain_from_lonlat(lon, lat, topo, frame=frame, name="matplotlib:topobathy.npz", **common)
    path = builtin_terrain_path(spec.builtin) if spec.builtin else Path(spec.file)
    if not path.is_absolute() and base_dir is not None:
        path = base_dir / path
    return read_bathymetry(path, frame=frame, variable=spec.variable, positive=spec.positive, **common)
