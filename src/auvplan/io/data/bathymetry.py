"""Read seabed elevation grids (GEBCO, ETOPO, EMODnet, GMT, Ferret NetCDF, GeoTIFF) into a :class:`Terrain`.

What the reader handles, each covered by a round-trip test (file layouts: :mod:`auvplan.io.data.elevation`;
the grid made a Terrain, its gaps, crop and resampling: :mod:`auvplan.io.data.terrain_grid`):

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

from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...errors import DataError
from ...world.seabed import SeabedFit
from ...world.terrain import Terrain
from .elevation import is_geotiff, read_elevation
from .geo import LocalFrame
from .grids import HorizontalGrid
from .seabed_model import METHODS
from .terrain_grid import MAX_ELEVATION_M, terrain_from_grid, terrain_from_lonlat, terrain_from_xy

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
