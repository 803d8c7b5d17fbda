"""Coastlines in: land polygons from GSHHG or a user's vector file, projected into the local frame.

``[land]`` in a scenario names either a built-in GSHHG cut-out (``builtin``) or a
vector file that GDAL reads (``file``: shapefile, GeoPackage, GeoJSON, FlatGeobuf …;
``layer`` picks one layer), read with pyogrio.  Polygons are densified in their own
CRS (so that long straight edges follow the source geometry), transformed with pyproj
to WGS 84 and then into the scenario's azimuthal-equidistant frame, and clipped to the
operating area with a margin.  The result is a :class:`auvplan.world.Land`.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from ....errors import DataError
from ....world.land import Land
from ..geo import LocalFrame
from .kept import kept_geometries
from .reader import read_vector

__all__ = ["LandSpec", "BUILTIN_LAND", "read_land", "builtin_land_path"]

log = logging.getLogger(__name__)

BUILTIN_LAND = {
    "gshhg-juan-de-fuca": ("gshhg_h_juan_de_fuca.geojson",
                           "GSHHG 2.3.7 high-resolution shorelines (land), 48.0-48.55 N, 123.8-122.55 W"),
}


@dataclass(frozen=True)
class LandSpec:
    """The ``[land]`` table: a built-in coastline cut-out or a vector file of land polygons.

    Attributes
    ----------
    builtin : str
        Name of a built-in cut-out (``BUILTIN_LAND``); exclusive with ``file``.
    file : str
        Vector file (relative paths are resolved against the scenario's folder).
    layer : str
        Layer of a multi-layer file (GeoPackage): needed when the file holds several (one layer: none).
    """

    builtin: str = ""
    file: str = ""
    layer: str = ""

    def __post_init__(self) -> None:
        if bool(self.file) == bool(self.builtin):
            raise ValueError("give exactly one of 'file' and 'builtin'")
        if self.builtin and self.builtin not in BUILTIN_LAND:
            raise ValueError(f"builtin = {self.builtin!r}: choose from {sorted(BUILTIN_LAND)}")


def builtin_land_path(name: str) -> Path:
    """Return the path of a built-in coastline file shipped with the package.

    Parameters
    ----------
    name : str
        A key of ``BUILTIN_LAND``.

    Returns
    -------
    pathlib.Path
        The GeoJSON file.
    """
    return Path(str(resources.files("auvplan") / "data" / BUILTIN_LAND[name][0]))


def _read_polygons(path: Path, layer: str, src: str) -> tuple[Any, Any]:
    """The union of a layer's polygons and its CRS (:func:`.vector.read_vector`)."""
    read = read_vector(path, src, DataError, layer=layer)
    geoms = np.asarray(read.present(), dtype=object)
    kinds = shapely.get_type_id(geoms) if geoms.size else np.empty(0, dtype=int)
    polys = geoms[np.isin(kinds, (3, 6))]
    if polys.size == 0:
        found = sorted({g.geom_type for g in geoms}) or ["nothing"]
        raise DataError(f"{src}: geometry: no polygons (found {', '.join(found)}); land must be given as "
                        "closed polygons, e.g. GSHHG level 1 or OpenStreetMap land polygons")
    if not read.crs_stated:
        log.warning("%s: no CRS; taken as WGS 84 longitude/latitude", src)
    return shapely.union_all(_valid(polys)), read.crs


def _valid(geoms: Any) -> Any:
    """Invalid polygons made valid by their rings' structure (shells unioned, holes subtracted): a part drawn
    inside another stays land (the default rebuild by the even-odd rule made it a hole); valid ones as they are."""
    out = np.where(shapely.is_valid(geoms), geoms, shapely.make_valid(geoms, method="structure", keep_collapsed=False))
    return out[()] if out.ndim == 0 else out  # one geometry in, one out


def read_land(spec: LandSpec, frame: LocalFrame, extent_m: tuple[float, float, float, float], *,
              base_dir: Path | None = None, margin_m: float = 2000.0) -> Land:
    """Read the land polygons of ``spec`` into ``frame``, clipped to ``extent_m`` widened by ``margin_m``.

    Parameters
    ----------
    spec : LandSpec
        The ``[land]`` table.
    frame : LocalFrame
        The scenario's local frame.
    extent_m : tuple of 4 float
        ``(xmin, xmax, ymin, ymax)`` of the scenario (m).
    base_dir : pathlib.Path, optional
        Folder that relative file paths resolve against.
    margin_m : float, optional
        Widening of the clip box (m).

    Returns
    -------
    Land
        The land polygons in local coordinates (m).
    """
    if spec.builtin:
        path = builtin_land_path(spec.builtin)
    else:
        path = Path(spec.file)
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
    src = str(path)
    request = (spec, src, frame.lat0, frame.lon0, tuple(float(v) for v in extent_m), float(margin_m))
    geometry = kept_geometries("land", request, path,
                               lambda: [("land", _land_geometry(path, spec, src, frame, extent_m, margin_m))])[0][1]
    name = spec.builtin or path.name
    return Land(geometry, name=name)


def _land_geometry(path: Path, spec: LandSpec, src: str, frame: LocalFrame,
                   extent_m: tuple[float, float, float, float], margin_m: float) -> Any:
    """The layer's land polygons densified, projected into ``frame`` and clipped to the widened extent."""
    geom, crs = _read_polygons(path, spec.layer, src)
    geom = shapely.segmentize(geom, 0.005 if crs.is_geographic else 500.0)
    from pyproj import Transformer  # where a file is projected (issue 56)

    to_geo = Transformer.from_crs(crs, "EPSG:4326", always_xy=True)

    def project(xy: np.ndarray) -> np.ndarray:
        lon, lat = to_geo.transform(xy[:, 0], xy[:, 1])
        x, y = frame.forward(lon, lat)
        return np.column_stack([x, y])

    local = shapely.transform(geom, project)
    x0, x1, y0, y1 = extent_m
    clipped = shapely.clip_by_rect(local, x0 - margin_m, y0 - margin_m, x1 + margin_m, y1 + margin_m)
    clipped = _valid(clipped)
    parts = [p for p in shapely.get_parts(clipped) if shapely.get_type_id(p) in (3, 6)]
    geometry = shapely.union_all(parts) if parts else shapely.MultiPolygon()
    if geometry.is_empty:
        log.info("%s: no land inside the operating area", src)
    return geometry
