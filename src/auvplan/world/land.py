"""Land as polygons in the local frame: an exact no-go area for points and segments.

:class:`Land` holds shoreline polygons (GSHHG, a user's shapefile/GeoPackage, …)
already projected into the local metric frame.  It answers, vectorised:

* :meth:`Land.contains` — whether points lie on land (their x, y inside a polygon);
* :meth:`Land.signed_distance` — horizontal distance to the shoreline, negative on land;
* :meth:`Land.segments_hit` — the **exact** segment test: whether a straight segment's
  horizontal trace meets a land polygon anywhere (shapely/GEOS ``intersects`` on the
  segment as a line string; no sampling);
* :meth:`Land.burn` — a seabed :class:`Terrain` raised above the sea surface on every
  grid node of every cell that touches land.  The bilinear seabed of such a cell is then
  above the surface everywhere in it (all four corners are), so any path that keeps its
  altitude ≥ 0 below the surface — what the cost, the planners and the simulator already
  enforce through the terrain — can never enter a cell that touches land, hence never
  crosses a polygon.  Conservative by at most one cell.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely

from .._types import ArrayLike, BoolArray, FloatArray
from ..errors import DataError
from .terrain import Terrain

__all__ = ["Land"]


@dataclass(frozen=True, eq=False)
class Land:
    """Land polygons in the local frame (m).

    Parameters
    ----------
    geometry : shapely Polygon or MultiPolygon
        Land areas (x east, y north, metres); holes are water (lakes are land here only
        if the source says so).
    name : str
        Source, for messages.

    Raises
    ------
    DataError
        If ``geometry`` is not polygonal.
    """

    geometry: shapely.Geometry
    name: str = ""
    _prepared: shapely.Geometry = field(init=False, repr=False)
    _boundary: shapely.Geometry = field(init=False, repr=False)

    def __post_init__(self) -> None:
        g = self.geometry
        if not isinstance(g, shapely.Geometry) or shapely.get_type_id(g) not in (3, 6, 7):
            raise DataError(f"land {self.name!r}: expected polygons, got {type(g).__name__}")
        if not shapely.is_valid(g):  # by the rings' structure: a part drawn inside another stays land (the default
            g = shapely.make_valid(g, method="structure", keep_collapsed=False)  # even-odd rebuild made it a hole)
        g = shapely.union_all(shapely.get_parts(g)) if not g.is_empty else g
        object.__setattr__(self, "geometry", g)
        shapely.prepare(g)
        object.__setattr__(self, "_prepared", g)
        object.__setattr__(self, "_boundary", g.boundary)

    @property
    def is_empty(self) -> bool:
        """Whether no land lies in the area.

        Returns
        -------
        bool
            True without any polygon.
        """
        return bool(self.geometry.is_empty)

    def contains(self, points: ArrayLike) -> BoolArray:
        """Where the horizontal position of points is on land (boundary included).

        Parameters
        ----------
        points : array_like
            Points ``(..., 2)`` or ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True on land.
        """
        p = np.asarray(points, dtype=float)
        if self.is_empty:
            return np.zeros(p.shape[:-1], dtype=bool)
        on_land: BoolArray = shapely.intersects_xy(self._prepared, p[..., 0], p[..., 1])
        return on_land

    def signed_distance(self, points: ArrayLike) -> FloatArray:
        """Horizontal distance from points to the shoreline.

        Parameters
        ----------
        points : array_like
            Points ``(..., 2)`` or ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            Distance ``(...)`` (m), negative on land, ``+inf`` without land.
        """
        p = np.asarray(points, dtype=float)
        if self.is_empty:
            return np.full(p.shape[:-1], np.inf)
        pts = shapely.points(p[..., 0], p[..., 1])
        d = shapely.distance(self._boundary, pts)
        signed: FloatArray = np.where(self.contains(p), -d, d)
        return signed

    def segments_hit(self, segments: ArrayLike) -> BoolArray:
        """Exact test: where the horizontal trace of a segment meets land.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True for segments that touch land.
        """
        s = np.asarray(segments, dtype=float)
        lead = s.shape[:-2]
        if self.is_empty or s.size == 0:
            return np.zeros(lead, dtype=bool)
        flat = s.reshape(-1, 2, s.shape[-1])[..., :2]
        lines = shapely.linestrings(flat)
        # a zero-length segment is a point
        zero = np.all(flat[:, 0] == flat[:, 1], axis=-1)
        hit = np.empty(flat.shape[0], dtype=bool)
        hit[~zero] = shapely.intersects(self._prepared, lines[~zero])
        hit[zero] = shapely.intersects_xy(self._prepared, flat[zero, 0, 0], flat[zero, 0, 1])
        return hit.reshape(lead)

    def burn(self, terrain: Terrain, height: float = 1.0) -> Terrain:
        """The terrain with every node of every cell that touches land raised.

        Parameters
        ----------
        terrain : Terrain
            Seabed to raise.
        height : float, default 1.0
            Least elevation of the raised nodes (m, above the sea surface).

        Returns
        -------
        Terrain
            A new terrain (``terrain`` itself when no cell touches land).
        """
        if self.is_empty:
            return terrain
        x, y = np.asarray(terrain.x), np.asarray(terrain.y)
        x0, y0, x1, y1 = shapely.bounds(self.geometry)
        # every cell whose closed box can meet the bounding box (cells touching it on an edge included)
        i0 = max(int(np.searchsorted(x, x0, side="left")) - 1, 0)
        i1 = min(int(np.searchsorted(x, x1, side="right")), x.size - 1)
        j0 = max(int(np.searchsorted(y, y0, side="left")) - 1, 0)
        j1 = min(int(np.searchsorted(y, y1, side="right")), y.size - 1)
        z = np.array(terrain.z, dtype=float)
        if i1 <= i0 or j1 <= j0:
            return terrain
        jj, ii = np.meshgrid(np.arange(j0, j1), np.arange(i0, i1), indexing="ij")
        cells = shapely.box(x[ii], y[jj], x[ii + 1], y[jj + 1])
        touch = shapely.intersects(self._prepared, cells)
        for dj in (0, 1):
            for di in (0, 1):
                jn, in_ = jj[touch] + dj, ii[touch] + di
                z[jn, in_] = np.maximum(z[jn, in_], height)
        # beyond the grid the seabed is continued with the edge values: land there is covered by the edge cells
        return Terrain(x, y, z, name=f"{terrain.name} + land {self.name}".strip(), fit=terrain.fit)
