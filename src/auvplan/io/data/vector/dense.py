"""Bounds on what a zone file may cost: a polygon of a million vertices, a file of a million features.

GEOS buffers a polygon in time and memory that grow with the crossings of its offset curve, and those grow
with the square of the vertices within the buffer distance of each other: a 300 m ring of 10⁶ vertices (two
millimetres apart, rounded to 10⁻⁷°) took 110 s and 7.8 GB before ``std::bad_alloc`` when the zones were
grown by their 1 m pad.  Such a polygon is made lean first: simplified within :data:`LEAN_TOL_M` and grown
by twice that, it contains the original (every point of the original lies within the tolerance of the
simplified outline) and has a few hundred vertices.  Features and vertices past :data:`MAX_ZONES` and
:data:`MAX_ZONE_VERTICES` are refused naming the file: 40 000 points buffered took 14 s and 800 MB, 200 000 ran
out of memory after a minute.
"""

from __future__ import annotations

from typing import Any

import shapely

__all__ = ["LEAN_FROM", "LEAN_TOL_M", "MAX_ZONES", "MAX_ZONE_VERTICES", "lean", "check_zone_count",
           "check_zone_vertices"]

LEAN_FROM = 10_000
"""A polygon footprint with more vertices than this is made lean (:func:`lean`); fewer are kept exactly."""
LEAN_TOL_M = 0.1
"""Simplification tolerance of :func:`lean` (m); the footprint grows by at most three times this (the simplified
outline lies within it of the original, then the buffer adds twice it: 0.29 m measured over a 0.09 m zigzag)."""
MAX_ZONES = 20_000
"""Most zones the features of the files may make in the area."""
MAX_ZONE_VERTICES = 2_000_000
"""Most vertices of all the footprints together (after :func:`lean`)."""


def lean(polygon: Any) -> Any:
    """A valid (multi)polygon with few vertices that contains ``polygon`` (or ``polygon`` when it has few).

    Parameters
    ----------
    polygon : shapely Polygon or MultiPolygon
        A valid footprint (m).

    Returns
    -------
    shapely geometry
        ``polygon`` itself when it has at most :data:`LEAN_FROM` vertices; else ``polygon`` simplified within
        :data:`LEAN_TOL_M` and buffered by twice that (the buffer's arcs are chords inscribed at cos 22.5° > 1/2
        of their radius, so it reaches past every point of the original).
    """
    if shapely.get_num_coordinates(polygon) <= LEAN_FROM:
        return polygon
    outline = shapely.simplify(polygon, LEAN_TOL_M, preserve_topology=True)
    return shapely.buffer(outline, 2.0 * LEAN_TOL_M, quad_segs=2)


def check_zone_count(count: int, src: str, error: type[Exception]) -> None:
    """Refuse a file whose features make more than :data:`MAX_ZONES` zones in the area.

    Parameters
    ----------
    count : int
        Zones made so far.
    src : str
        Message prefix naming the file and the key.
    error : type of Exception
        Raised with a message starting with ``src``.
    """
    if count > MAX_ZONES:
        raise error(f"{src}: more than {MAX_ZONES:,} features reach the operating area (each is a zone; 40,000 took "
                    "14 s and 800 MB to index): select the ones that matter with where = or a smaller file")


def check_zone_vertices(footprints: list[Any], src: str, error: type[Exception]) -> None:
    """Refuse footprints of more than :data:`MAX_ZONE_VERTICES` vertices in all.

    Parameters
    ----------
    footprints : list of shapely geometries
        The zones' footprints (m), lean.
    src : str
        Message prefix naming the scenario.
    error : type of Exception
        Raised with a message starting with ``src``.
    """
    total = int(shapely.get_num_coordinates(footprints).sum()) if footprints else 0
    if total > MAX_ZONE_VERTICES:
        raise error(f"{src}: [[zones]] footprints of {total:,} vertices in all, over the {MAX_ZONE_VERTICES:,} "
                    "allowed: simplify the zone files (ogr2ogr -simplify) or select fewer features (where =)")
