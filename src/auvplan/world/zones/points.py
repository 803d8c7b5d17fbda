"""The zones' point queries and the class the rest of auvplan uses, :class:`Zones`: signed distances
(exact for flat bands, a lower bound for seabed bands: the notes of :mod:`auvplan.world.zones`), the
nearest points of the prisms, the closest approach of a polyline to every zone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from ..._types import ArrayLike, FloatArray, IntArray
from .exact import near_distance_kernel
from .parts import samples as leg_samples
from .segments import SegmentQueries
from .spec import ZoneApproach

__all__ = ["Zones"]


@dataclass(frozen=True, eq=False)
class Zones(SegmentQueries):
    """Many no-go prisms behind an R-tree (shapely ``STRtree``) of their footprints.

    Parameters
    ----------
    zones : tuple of Zone
        The prisms (may be empty).
    terrain : Terrain or None
        Seabed for the zones given ``above_seabed``; required when any is.
    pad : float, default 0.0
        Every prism grown by this much (m: footprints buffered, bands widened) in every query: the
        planners keep this far off, so a plan that skirts a zone stays outside it once densified,
        simplified into a mission and rounded in a file.  :attr:`exact` is the same zones unpadded
        (what checks of flown or exported missions test against).

    Raises
    ------
    DataError
        If a seabed zone comes without a terrain.
    """

    def _vertical(self, p: FloatArray, zi: IntArray) -> tuple[FloatArray, FloatArray]:
        """Per (point, zone) pair: distance above (> 0) / below the band, and the depth inside it."""
        z = p[:, 2]
        h = self._h[zi]
        out_v = np.maximum(self._zlo[zi] - z, z - self._zhi[zi])
        in_v = np.minimum(z - self._zlo[zi], self._zhi[zi] - z)
        sea = np.isfinite(h)
        if sea.any():
            assert self.terrain is not None
            g = z[sea] - self.terrain.elevation(p[sea, 0], p[sea, 1]) - h[sea]
            slope = math.sqrt(1.0 + self.terrain.max_slope ** 2)
            out_v[sea] = g / slope
            in_v[sea] = -g / slope
        return out_v, in_v

    def signed_distance(self, points: ArrayLike, exact: bool = False) -> FloatArray:
        """Distance from points to the nearest prism (m), negative inside.

        Exact Euclidean for flat bands; for seabed bands a lower bound (module docstring).  Unless
        ``exact``, points more than two broad-phase cells from every footprint get the grid's lower
        bound of their horizontal distance instead (positive, never above the truth).

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        exact : bool, default False
            Measure every point.

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m); ``+inf`` without zones.
        """
        p = np.asarray(points, dtype=float)
        lead = p.shape[:-1]
        flat = p.reshape(-1, 3)
        out = np.full(flat.shape[0], np.inf)
        if not self.zones or flat.shape[0] == 0:
            return out.reshape(lead)
        if not exact and self._grid is not None:
            bound = self._lower_bound(flat)
            near = bound < 2.0 * self._grid[2]
            out[~near] = bound[~near]
            if near.any():
                out[near] = self._near_distance(flat[near])
            return out.reshape(lead)
        pts = shapely.points(flat[:, 0], flat[:, 1])
        # an upper bound per point: its 3D distance to the horizontally nearest zone
        pi, zi = self._tree.query_nearest(pts, all_matches=False)
        out[pi] = self._pair_distance(flat[pi], pts[pi], zi)
        # every zone horizontally closer than that bound, checked exactly
        reach = np.where(np.isfinite(out), np.maximum(out, 0.0), 0.0)
        pi, zi = self._tree.query(pts, predicate="dwithin", distance=reach)
        if pi.size:
            np.minimum.at(out, pi, self._pair_distance(flat[pi], pts[pi], zi))
        return out.reshape(lead)

    def _near_distance(self, p: FloatArray) -> FloatArray:
        """Signed distance of points ``(N, 3)`` to the zones listed within two cells of them, capped at
        two cells (every other zone is at least that far): exact below the cap."""
        assert self._grid is not None
        x0, y0, cell, nx, ny, start, ids, *_ = self._grid
        p = np.ascontiguousarray(p)
        floor = np.zeros(p.shape[0])
        slope = 1.0
        if self._seabed.any():
            assert self.terrain is not None
            floor = np.ascontiguousarray(self.terrain.elevation(p[:, 0], p[:, 1]), dtype=float)
            slope = math.sqrt(1.0 + self.terrain.max_slope ** 2)
        mark = np.full(len(self.zones), -1, dtype=np.intp)
        out = np.full(p.shape[0], 2.0 * cell)
        near_distance_kernel(p, floor, x0, y0, cell, nx, ny, start, ids, 2, self._zlo, self._zhi, self._h, slope,
                             *self._rings, mark, out)
        return out

    def _pair_distance(self, p: FloatArray, pts: np.ndarray, zi: IntArray) -> FloatArray:
        """Signed distance of each point to its paired zone."""
        geoms = self._geoms[zi]
        dh = shapely.distance(geoms, pts)
        inside_h = dh == 0.0
        out_v, in_v = self._vertical(p, zi)
        d: FloatArray = np.hypot(dh, np.maximum(out_v, 0.0))
        inside = inside_h & (out_v <= 0.0)
        if inside.any():
            edge = shapely.distance(shapely.boundary(geoms[inside]), pts[inside])
            d[inside] = -np.minimum(edge, in_v[inside])
        return d

    def nearest(self, point: ArrayLike, reach: float) -> tuple[FloatArray, FloatArray]:
        """The nearest point of every prism within ``reach`` of a point, and its signed distance (for a
        repulsive field: the zones as static obstacles).

        Parameters
        ----------
        point : array_like
            ``(3,)`` (m).
        reach : float
            Farthest prism looked at (m).

        Returns
        -------
        points : numpy.ndarray
            ``(M, 3)`` nearest points of the prisms (on the boundary when ``point`` is inside): on the
            footprint's boundary or straight above/below the point, the depth clamped to the band (m).
        distances : numpy.ndarray
            ``(M,)`` :meth:`signed_distance` to each of them (m, negative inside).
        """
        p = np.asarray(point, dtype=float).reshape(3)
        empty = (np.zeros((0, 3)), np.zeros(0))
        if not self.zones:
            return empty
        pt = shapely.points(p[0], p[1])
        zi = self._tree.query(pt, predicate="dwithin", distance=reach)
        if zi.size == 0:
            return empty
        d = self._pair_distance(np.broadcast_to(p, (zi.size, 3)), np.full(zi.size, pt, dtype=object), zi)
        keep = d <= reach
        zi, d = zi[keep], d[keep]
        geoms = self._geoms[zi]
        over = shapely.contains_xy(geoms, p[0], p[1])
        out_v, _ = self._vertical(np.broadcast_to(p, (zi.size, 3)), zi)
        ends = shapely.get_coordinates(shapely.shortest_line(pt, shapely.boundary(geoms))).reshape(-1, 2, 2)[:, 1]
        q = np.column_stack([ends, np.full(zi.size, p[2])])
        above = over & (out_v > 0)  # over the footprint, outside the band: straight above or below
        q[above, :2] = p[:2]
        lo = np.where(np.isfinite(self._h[zi]), -np.inf, self._zlo[zi])
        hi = self._zhi[zi].copy()
        sea = np.isfinite(self._h[zi])
        if sea.any():
            assert self.terrain is not None
            hi[sea] = self.terrain.elevation(q[sea, 0], q[sea, 1]) + self._h[zi][sea]
        q[:, 2] = np.clip(p[2], lo, hi)
        return q, d

    def traces_near(self, segments: ArrayLike, reach: ArrayLike) -> tuple[IntArray, IntArray]:
        """The (segment, zone) pairs whose horizontal trace comes within ``reach`` of the zone's footprint (the
        R-tree's ``dwithin``; the bands are not looked at): the broad phase of a test under a horizontal error.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(N, 2, 3)`` (m).
        reach : float or array_like
            Horizontal distance (m): one for all, or ``(N,)`` one per segment.

        Returns
        -------
        seg, zone : numpy.ndarray of int
            The pairs (the R-tree's order).
        """
        s = np.asarray(segments, dtype=float).reshape(-1, 2, 3)
        if not self.zones or s.shape[0] == 0:
            return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
        k, j = self._tree.query(shapely.linestrings(s[:, :, :2]), predicate="dwithin", distance=reach)
        return k.astype(np.intp), j.astype(np.intp)

    def distances(self, points: ArrayLike) -> FloatArray:
        """Signed distance of every point to every zone (for reports: closest approach per zone).

        Parameters
        ----------
        points : array_like
            Points ``(N, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(N, Z)`` (m), negative inside.
        """
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        out = np.empty((p.shape[0], len(self.zones)))
        pts = shapely.points(p[:, 0], p[:, 1])
        for j in range(len(self.zones)):
            out[:, j] = self._pair_distance(p, pts, np.full(p.shape[0], j, dtype=np.intp))
        return out


    def clearance(self, polyline: ArrayLike, step: float = 25.0, max_samples: int = 4000) -> float:
        """Least distance of a polyline to any zone (m): ``min`` of :meth:`approach` over the zones,
        through the R-tree (no loop over the zones).

        Parameters
        ----------
        polyline : array_like
            Vertices ``(N, 3)`` (m).
        step : float, default 25.0
            Sample spacing along each leg (m).
        max_samples : int, default 4000
            Most samples per leg.

        Returns
        -------
        float
            ≤ 0 when a leg enters a zone (exact test); ``inf`` without zones.
        """
        p = np.asarray(polyline, dtype=float).reshape(-1, 3)
        if not self.zones or p.shape[0] == 0:
            return math.inf
        legs = np.stack([p[:-1], p[1:]], axis=1) if p.shape[0] > 1 else np.stack([p, p], axis=1)
        samples = leg_samples(legs, step, max_samples)
        d = float(self.signed_distance(samples).min())
        if self._grid is not None and d >= 2.0 * self._grid[2]:  # far from every zone: measured exactly
            d = float(self.signed_distance(samples, exact=True).min())
        return min(d, 0.0) if self.entries(legs)[0].size else d

    def approach(self, polyline: ArrayLike, step: float = 25.0, max_samples: int = 4000) -> list[ZoneApproach]:
        """Closest approach of a polyline to every zone, and the legs that enter each (exact).

        Parameters
        ----------
        polyline : array_like
            Vertices ``(N, 3)`` (m); leg ``k`` (from 1) joins vertices ``k - 1`` and ``k``.
        step : float, default 25.0
            Spacing of the samples along each leg the distance is measured at (m); the reported
            distance is within ``step / 2`` of the true least distance (above it at worst).
        max_samples : int, default 4000
            Most samples per leg (longer legs are sampled more coarsely).

        Returns
        -------
        list of ZoneApproach
            One per zone, in order: name, closest approach (m; ≤ 0 when entered) and the legs entering it.
        """
        p = np.asarray(polyline, dtype=float).reshape(-1, 3)
        if not self.zones:
            return []
        legs = np.stack([p[:-1], p[1:]], axis=1) if p.shape[0] > 1 else np.stack([p, p], axis=1)
        seg, zi = self.entries(legs)
        closest = self.distances(leg_samples(legs, step, max_samples)).min(axis=0)
        out = []
        for j, z in enumerate(self.zones):
            entered = tuple(sorted({int(s) + 1 for s in seg[zi == j]}))
            d = float(min(closest[j], 0.0)) if entered else float(closest[j])
            out.append(ZoneApproach(z.name, d, entered))
        return out
