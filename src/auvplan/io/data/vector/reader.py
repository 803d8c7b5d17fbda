"""The one reader of vector feature files: GeoJSON, KML, Shapefile, GeoPackage, FileGDB, S-57 electronic
charts and any other format GDAL reads (through pyogrio), in any CRS.

Survey areas and centre lines (:mod:`.areas`), charted zones (:mod:`.zones`) and land polygons
(:mod:`.coast`) read their layers here; each keeps its own error type (a survey file is a scenario error,
a zone or land file a data error) and its own message prefix (``file: [survey] file = '...'``).
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import shapely

from .guard import check_source, offline
from .jsoncrs import check_geojson_crs

if TYPE_CHECKING:
    from pyproj import CRS

__all__ = ["VectorLayer", "read_vector"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class VectorLayer:
    """The features of one layer of a vector file.

    Attributes
    ----------
    geometries : numpy.ndarray of shapely geometries
        One per feature in file order (``None`` where a feature has none), in the file's coordinates.
    crs : pyproj.CRS
        The layer's CRS (WGS 84 longitude/latitude when the file states none).
    fields : dict of str to numpy.ndarray
        The attribute columns read (empty unless asked for), aligned with ``geometries``.
    crs_stated : bool
        Whether the file states its CRS (else ``crs`` is WGS 84 by assumption).
    """

    geometries: np.ndarray
    crs: CRS
    fields: dict[str, np.ndarray]
    crs_stated: bool = True

    def present(self) -> list[shapely.Geometry]:
        """The non-empty geometries, in file order.

        Returns
        -------
        list of shapely geometries
            Features without a geometry or with an empty one left out.
        """
        return [g for g in self.geometries if g is not None and not g.is_empty]


def _geometries(wkb: np.ndarray, src: str, error: type[Exception]) -> np.ndarray:
    """The features' geometries: one GEOS cannot build (an unclosed ring, GDAL only warns) refused naming the
    feature, and the empty parts of a multi-part geometry dropped (GEOS's ``segmentize`` of a MultiPolygon with an
    empty part crashed the process: hostile round 22)."""
    from shapely.errors import GEOSException

    with np.errstate(invalid="ignore"):  # a NaN coordinate is the caller's to refuse, by feature
        try:
            geoms = np.asarray(shapely.from_wkb(wkb), dtype=object)
        except GEOSException:  # the first feature GEOS refuses, by its number in the file
            for k, one in enumerate(wkb):
                try:
                    shapely.from_wkb(one)
                except GEOSException as exc:
                    raise error(f"{src}: feature #{k + 1}: not a geometry GEOS reads ({exc})") from None
            raise
    for k, g in enumerate(geoms):
        if g is not None and shapely.get_type_id(g) in (4, 5, 6, 7) and not g.is_empty:
            parts = shapely.get_parts(g)
            empty = shapely.is_empty(parts)
            if empty.any():
                geoms[k] = type(g)(list(parts[~empty]))
    return geoms


def read_vector(path: Path, src: str, error: type[Exception], *, layer: str = "", where: str = "",
                fields: bool = False) -> VectorLayer:
    """Read one layer of a vector file.

    Parameters
    ----------
    path : pathlib.Path
        The file (or a FileGDB folder).
    src : str
        Message prefix naming the file and the key that named it, e.g. ``"s.toml: [[zones]] file = 'a.gpkg'"``.
    error : type of Exception
        Raised (with a message starting with ``src``) when the file is missing, unreadable or its CRS unusable
        (a GeoJSON ``crs`` member GDAL could not build, :mod:`.jsoncrs`),
        is a FIFO or a device, or only describes other sources (an OGR VRT, a WFS; :mod:`.guard`).
    layer : str, default ''
        Layer name ('' for the first); for S-57 charts the object class (``CBLSUB``, ``WRECKS`` ...).
    where : str, default ''
        An OGR SQL attribute filter ('' for every feature); it selects the same features with or without
        ``fields``.
    fields : bool, default False
        Also read the attribute columns.

    Returns
    -------
    VectorLayer
        Geometries, CRS and (when asked) attributes.
    """
    import pyogrio

    if not path.exists():
        raise error(f"{src}: not found")
    check_source(path, src, error)  # no FIFO, device or description of other sources (.guard)
    try:
        # GDAL kept off the network; its warnings one line each, not Python's two
        with offline(), warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            layers = [] if layer else [(str(n), g) for n, g in pyogrio.list_layers(path)]
            if len(layers) <= 1:
                # with an attribute filter the columns are read: GDAL's shapefile, FlatGeobuf and FileGDB drivers
                # test the filter on the fields asked for, and no field asked for matched no feature
                meta, _, wkb, columns = pyogrio.raw.read(path, layer=layer or None, where=where or None,
                                                         read_geometry=True, columns=None if fields or where else [])
    except Exception as exc:  # GDAL raises several types for unreadable files, layers and filters
        raise error(f"{src}: cannot read as a vector file{f' (layer {layer!r})' if layer else ''}"
                    f"{f' where {where!r}' if where else ''} ({str(exc).splitlines()[0]})") from exc
    if len(layers) > 1:  # the first alone was read: an S-57 chart's DSID record, no feature (hostile round 22)
        listed = ", ".join(f"{n} ({g or 'no geometry'})" for n, g in layers[:12]) + (", …" if len(layers) > 12 else "")
        raise error(f"{src}: the file holds {len(layers)} layers ({listed}); name the one to read with layer = "
                    "'…' (for an S-57 chart the object class: CBLSUB, WRECKS, OBSTRN …)")
    for w in said:
        log.warning("%s: %s", src, " ".join(str(w.message).split()))
    from pyproj import CRS  # where a file is projected (issue 56)

    try:
        crs = CRS.from_user_input(meta.get("crs") or "EPSG:4326")
    except Exception as exc:  # pyproj's CRSError
        raise error(f"{src}: crs {meta.get('crs')!r} is not usable ({exc})") from exc
    check_geojson_crs(path, src, error, crs)  # a GeoJSON crs GDAL could not build is read as WGS 84, silently
    if not (crs.is_geographic or crs.is_projected):  # pyproj's traceback (engineering), or read as a map (geocentric)
        raise error(f"{src}: crs {crs.name!r} ({crs.type_name}) is not longitude/latitude or a map projection: its "
                    "features have no place on the Earth's surface")
    geoms = _geometries(wkb, src, error) if wkb is not None else np.empty(0, dtype=object)
    names = [str(n) for n in meta.get("fields", [])]
    return VectorLayer(np.asarray(geoms, dtype=object), crs, dict(zip(names, columns, strict=True)) if fields else {},
                       bool(meta.get("crs")))
