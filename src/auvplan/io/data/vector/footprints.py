"""Footprints of ``[[zones]]`` (:mod:`.zones`): a polygon made valid keeping its area, a sliver enclosing none
refused, a line buffered into a corridor and a point into a disc, each circumscribing the true shape.
"""

from __future__ import annotations

import logging
import math
from typing import Any

import shapely

from ....errors import DataError, ScenarioError
from .dense import lean

__all__: list[str] = []

log = logging.getLogger("auvplan.io.data.vector.zones")
"""The zones' logger (:mod:`.zones`): a polygon made valid is its warning, under the name it always had."""


_QUAD_SEGS = 16
_INSCRIBED = math.cos(math.pi / (4 * _QUAD_SEGS))
"""A buffer's arcs are polygons inscribed in them; buffering by ``r / _INSCRIBED`` circumscribes the
true arcs, so the footprint contains every point within ``r`` (never less, at most 0.12 % more)."""


_SLIVER_M = 1e-3
"""A footprint whose mean width (twice its area over its perimeter) is under this (m) encloses no area: points on a
line, a ring folded on itself, or such a line projected from degrees (a few micrometres of curvature)."""


def _mean_width(g: Any) -> float:
    """Twice the area over the perimeter (m): a strip's width, half a disc's radius; 0 for a sliver."""
    perimeter = float(shapely.length(shapely.boundary(g))) if not g.is_empty else 0.0
    return 2.0 * float(g.area) / perimeter if perimeter > 0.0 else 0.0


def _made_valid(geom: Any, where: str) -> Any:
    """A polygon feature's valid polygonal parts (empty when it has none): an invalid one (a self-crossing ring, a
    chart's self-touching part) made valid with ``shapely.make_valid`` and said so (a warning, when ``where``
    names it and an area is left: the callers refuse one with none, and a warning before that refusal said it
    was kept).  GEOS's other operations do not keep an invalid polygon's area: ``segmentize`` of a bow tie kept
    one of its two lobes."""
    if shapely.is_valid(geom):
        return geom
    parts = [g for g in shapely.get_parts(_repaired(geom)) if shapely.get_type_id(g) in (3, 6)]
    out = shapely.union_all(parts) if parts else shapely.Polygon()
    if where and not out.is_empty:  # one with no area left is refused by the caller, not warned of
        log.warning("%s: not a valid polygon (%s): made valid (shapely.make_valid), its %d polygonal parts kept",
                    where, shapely.is_valid_reason(geom), len(shapely.get_parts(out)))
    return out


def _repaired(geom: Any) -> Any:
    """``shapely.make_valid`` keeping a polygon's area: its rings' structure (shells unioned, holes subtracted),
    not the default rebuild from the linework with the even-odd rule, which made a part lying inside another
    part (GEOS's "Nested shells": a chart's area with a sub-area as a second part) a hole of the zone."""
    if shapely.get_type_id(geom) in (3, 6):
        return shapely.make_valid(geom, method="structure", keep_collapsed=False)
    return shapely.make_valid(geom)


def _polygonal(geom: Any, where: str) -> Any:
    """A polygon feature as a valid footprint (:func:`_made_valid`); one enclosing no area refused."""
    out = _made_valid(geom, where)
    if _mean_width(out) < _SLIVER_M:
        raise ScenarioError(f"{where}: the polygon encloses no area (mean width {_mean_width(out):.2g} m)")
    return out


def _footprint(geom: Any, buffer_m: float, radius_m: float, where: str) -> Any:
    """A polygon from a polygon, a line buffered by ``buffer_m`` or a point by ``radius_m`` (m)."""
    kind = shapely.get_type_id(geom)
    if kind in (3, 6):
        return lean(_polygonal(geom, where))  # a million vertices: simplified, grown to contain them (.dense)
    if kind in (1, 2, 5):
        if not buffer_m:
            raise ScenarioError(f"{where}: {geom.geom_type} features need buffer_m (a corridor's half-width)")
        return shapely.buffer(geom, buffer_m / _INSCRIBED, quad_segs=_QUAD_SEGS)
    if kind in (0, 4):
        if not radius_m:
            raise ScenarioError(f"{where}: {geom.geom_type} features need radius_m")
        return shapely.buffer(geom, radius_m / _INSCRIBED, quad_segs=_QUAD_SEGS)
    raise DataError(f"{where}: unsupported geometry {geom.geom_type} (a zone is a polygon, a line or a point; "
                    "split the collection into its parts)")
