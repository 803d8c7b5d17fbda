"""Survey areas and centre lines from vector files (GeoJSON, KML, shapefile, GeoPackage: any format GDAL
reads, through pyogrio), in any CRS, returned as longitude/latitude (WGS 84) for the scenario's local frame.

A polygon layer gives the survey area (its largest polygon); a line layer gives a corridor's centre line
(its longest line; a multi-line is joined end to end when its parts touch).  An area or a line crossing the
antimeridian, cut in two at ±180° as GeoJSON writers do (RFC 7946 §3.1.9), is joined again first.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import NDArray

from ....errors import ScenarioError
from .reader import read_vector

if TYPE_CHECKING:
    from pyproj import CRS

__all__ = ["read_layer", "read_area", "read_area_lonlat", "read_line_lonlat"]

log = logging.getLogger(__name__)


def read_layer(path: Path, layer: str, where: str, key: str = "file") -> tuple[list[shapely.Geometry], CRS]:
    """The geometries of a vector file's layer and the file's CRS (WGS 84 when it has none).

    Parameters
    ----------
    path : pathlib.Path
        GeoJSON, KML, shapefile, GeoPackage or any vector format GDAL reads.
    layer : str
        Layer name ('' for the first).
    where : str
        ``file: [survey]`` for messages.
    key : str
        The key that named the file, for messages.

    Returns
    -------
    tuple
        The non-empty geometries (in the file's coordinates) and its ``pyproj.CRS``.
    """
    src = f"{where} {key} = {str(path)!r}"
    found = read_vector(path, src, ScenarioError, layer=layer)
    return found.present(), found.crs


def _to_lonlat(xy: NDArray[np.float64], crs: CRS) -> NDArray[np.float64]:
    from pyproj import Transformer  # where a file is projected (issue 56)

    lon, lat = Transformer.from_crs(crs, "EPSG:4326", always_xy=True).transform(xy[:, 0], xy[:, 1])
    return np.column_stack([lon, lat])


def _antimeridian(parts: list[shapely.Geometry], crs: CRS) -> tuple[list[shapely.Geometry], bool]:
    """Parts of a lon/lat layer cut at the antimeridian (RFC 7946 §3.1.9), those from -180° moved east by 360°
    so that both halves meet at +180° again (the local frame normalises the longitudes); and whether any was."""
    if not crs.is_geographic or not any(p.bounds[2] >= 180.0 - 1e-9 for p in parts):
        return parts, False
    west = [p.bounds[0] <= -180.0 + 1e-9 for p in parts]
    moved = [shapely.transform(p, lambda xy: xy + [360.0, 0.0]) if w else p for p, w in zip(parts, west, strict=True)]
    return moved, any(west)


def read_area(path: Path, layer: str, where: str, key: str = "file") -> tuple[shapely.Polygon, CRS]:
    """The largest polygon of a vector file's layer and the file's CRS (WGS 84 when it has none).

    Parameters
    ----------
    path : pathlib.Path
        The vector file.
    layer : str
        Layer name ('' for the first).
    where : str
        ``file: [survey]`` for messages.
    key : str
        The key that named the file.

    Returns
    -------
    tuple
        The polygon (in the file's coordinates) and its ``pyproj.CRS``.
    """
    geoms, crs = read_layer(path, layer, where, key)
    polys = [p for g in geoms for p in shapely.get_parts(g) if isinstance(p, shapely.Polygon)]
    polys, moved = _antimeridian(polys, crs)
    if moved:  # the halves of an area cut at ±180°: one polygon again
        polys = [p for p in shapely.get_parts(shapely.union_all(polys)) if isinstance(p, shapely.Polygon)]
    if not polys:
        raise ScenarioError(f"{where} {key} = {str(path)!r}: no polygon in "
                            f"{f'layer {layer!r}' if layer else 'its first layer'}")
    if len(polys) > 1:  # documented (the largest polygon), and said: the others are not surveyed
        log.warning("%s %s = %r: %d polygons in the layer; the largest is the survey area, the other %d are left out",
                    where, key, str(path), len(polys), len(polys) - 1)
    return max(polys, key=lambda p: p.area), crs


def read_area_lonlat(path: Path, layer: str, where: str, key: str = "file") -> NDArray[np.float64]:
    """The exterior ring of the largest polygon of a layer, as ``(M, 2)`` longitude/latitude (deg).

    Parameters
    ----------
    path : pathlib.Path
        The vector file.
    layer : str
        Layer name ('' for the first).
    where : str
        ``file: [survey]`` for messages.
    key : str
        The key that named the file.

    Returns
    -------
    numpy.ndarray
        ``(M, 2)`` lon/lat of the ring (closed).

    Raises
    ------
    ScenarioError
        When the polygon has holes (a survey area is one ring: what must not be surveyed goes in ``[[zones]]``).
    """
    poly, crs = read_area(path, layer, where, key)
    if len(poly.interiors):  # its exterior alone would survey the holes too, silently (wave 18)
        raise ScenarioError(f"{where} {key} = {str(path)!r}: the area has {len(poly.interiors)} hole(s) (interior "
                            "rings), which a survey area cannot have; put what must not be surveyed in [[zones]] (the "
                            "lines are clipped to them), or remove the holes from the file")
    return _to_lonlat(np.asarray(poly.exterior.coords)[:, :2], crs)


def read_line_lonlat(path: Path, layer: str, where: str, key: str = "centerline_file") -> NDArray[np.float64]:
    """The longest line of a layer (a multi-line merged where its parts touch), as ``(M, 2)`` lon/lat (deg).

    Parameters
    ----------
    path : pathlib.Path
        The vector file.
    layer : str
        Layer name ('' for the first).
    where : str
        ``file: [survey]`` for messages.
    key : str
        The key that named the file.

    Returns
    -------
    numpy.ndarray
        ``(M, 2)`` lon/lat of the line's vertices.
    """
    geoms, crs = read_layer(path, layer, where, key)
    lines = []
    for g in geoms:
        if isinstance(g, shapely.MultiLineString):
            g = shapely.line_merge(shapely.MultiLineString(_antimeridian(list(shapely.get_parts(g)), crs)[0]))
        lines += [p for p in shapely.get_parts(g) if isinstance(p, shapely.LineString)]
    if not lines:
        raise ScenarioError(f"{where} {key} = {str(path)!r}: no line in "
                            f"{f'layer {layer!r}' if layer else 'its first layer'}")
    return _to_lonlat(np.asarray(max(lines, key=lambda p: p.length).coords)[:, :2], crs)
