"""Charted hazards and no-go zones in 3D: a footprint in the local frame times a depth band.

A :class:`Zone` is a closed prism: a polygonal footprint (a charted area, a cable or pipeline
corridor buffered about its line, a circle round a wreck) in the local metric frame (x east,
y north, m) times a vertical band, either

* between two depths (``top`` and ``bottom``, positive down; ``bottom = inf`` reaches the
  seabed), i.e. ``-bottom <= z <= -top``; or
* from the seabed up to ``above_seabed`` metres above it (a hazard lying on the seabed), i.e.
  ``z <= zb(x, y) + above_seabed``.

:class:`Zones` holds many of them behind a shapely ``STRtree`` over the footprints, so a
thousand zones cost a bulk index query, not a thousand tests.  Its queries, vectorised:

* :meth:`Zones.entries` — the **exact** segment-vs-prism test.  A flat band cuts the segment
  parameter to one interval (z is linear along the segment); the segment's horizontal trace over
  that interval is tested against the footprint with GEOS ``intersects``.  A seabed band clips
  the trace to the footprint (GEOS ``intersection``; every piece of a straight trace is a
  straight sub-segment) and tests each piece's least altitude with the terrain's exact walk
  (:meth:`Terrain.segment_min_altitude`).  No sampling anywhere; the prism is closed (touching
  a face is an entry).
* :meth:`Zones.signed_distance` — distance from points to the nearest prism, negative inside.
  For a flat band it is the Euclidean distance ``hypot(d_h, d_v)`` (exact: the prism is a
  product set); for a seabed band the vertical term is ``(z - zb - h) / sqrt(1 + G^2)`` with
  ``G`` the steepest seabed slope, a lower bound of the true distance, so the value is never
  above the true clearance (what the planners' Lipschitz shortcuts need).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely

from .._types import ArrayLike, BoolArray, FloatArray, IntArray
from ..errors import DataError
from .terrain import Terrain
from .zone_kernels import (
    any_hits_kernel,
    candidates_kernel,
    clear_kernel,
    flat_hits_kernel,
    near_distance_kernel,
    path_hits_kernel,
    slack_kernel,
)
from .zone_parts import band_tops, clip_pieces, distance_field, expand_groups, inner_centres, rasterise
from .zone_parts import rings as polygon_rings
from .zone_parts import samples as leg_samples
from .zone_parts import traces as trace_geoms

__all__ = ["Zone", "Zones", "ZoneApproach"]


@dataclass(frozen=True, eq=False)
class Zone:
    """One no-go prism.

    Parameters
    ----------
    name : str
        Name used in messages and drawings (a chart's object name, a cable's name …).
    footprint : shapely Polygon or MultiPolygon
        Horizontal extent in the local frame (m).
    top : float, default 0.0
        Depth of the top face (m, positive down); 0 is the sea surface.
    bottom : float, default inf
        Depth of the bottom face (m, positive down); ``inf`` reaches the seabed.
    above_seabed : float or None
        When given, the band is from the seabed up to this height (m) and ``top``/``bottom`` are
        not used.

    Raises
    ------
    DataError
        If the footprint is not polygonal or is empty, or the band is empty or negative.
    """

    name: str
    footprint: shapely.Geometry
    top: float = 0.0
    bottom: float = math.inf
    above_seabed: float | None = None

    def __post_init__(self) -> None:
        g = self.footprint
        if not isinstance(g, shapely.Geometry) or shapely.get_type_id(g) not in (3, 6) or g.is_empty:
            raise DataError(f"zone {self.name!r}: expected a non-empty polygon footprint, got "
                            f"{getattr(g, 'geom_type', type(g).__name__)}")
        if not shapely.is_valid(g):
            object.__setattr__(self, "footprint", shapely.make_valid(g))
        if self.above_seabed is not None:
            if not (math.isfinite(self.above_seabed) and self.above_seabed > 0):
                raise DataError(f"zone {self.name!r}: above_seabed_m must be positive, got {self.above_seabed}")
        elif not (self.top >= 0 and self.bottom > self.top):
            raise DataError(f"zone {self.name!r}: need 0 <= top_m < bottom_m, got top_m = {self.top}, "
                            f"bottom_m = {self.bottom}")

    @property
    def band(self) -> str:
        """The vertical band in words (for messages and drawings).

        Returns
        -------
        str
            E.g. ``"surface to seabed"``, ``"20-80 m deep"``, ``"seabed + 15 m"``.
        """
        if self.above_seabed is not None:
            return f"seabed + {self.above_seabed:g} m"
        top = "surface" if self.top == 0 else f"{self.top:g} m"
        bottom = "seabed" if math.isinf(self.bottom) else f"{self.bottom:g} m deep"
        return f"{top} to {bottom}"


@dataclass(frozen=True, eq=False)
class Zones:
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

    zones: tuple[Zone, ...]
    terrain: Terrain | None = None
    pad: float = 0.0
    _tree: shapely.STRtree = field(init=False, repr=False)
    _geoms: np.ndarray = field(init=False, repr=False)
    _zlo: FloatArray = field(init=False, repr=False)
    _zhi: FloatArray = field(init=False, repr=False)
    _h: FloatArray = field(init=False, repr=False)
    _seabed: BoolArray = field(init=False, repr=False)
    _bounds: FloatArray = field(init=False, repr=False)
    _grid: tuple[Any, ...] | None = field(init=False, repr=False)
    _field: tuple[Any, ...] = field(init=False, repr=False)
    _rings: tuple[FloatArray, IntArray, IntArray, FloatArray] = field(init=False, repr=False)
    _centres: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        zs = tuple(self.zones)
        object.__setattr__(self, "zones", zs)
        h = np.array([np.nan if z.above_seabed is None else z.above_seabed for z in zs], dtype=float)
        if np.isfinite(h).any() and self.terrain is None:
            bad = next(z.name for z in zs if z.above_seabed is not None)
            raise DataError(f"zone {bad!r}: above_seabed_m needs a seabed (a [terrain])")
        if not (math.isfinite(self.pad) and self.pad >= 0):
            raise DataError(f"zones: pad must be a non-negative number, got {self.pad}")
        footprints = np.array([z.footprint for z in zs], dtype=object)
        object.__setattr__(self, "_centres", inner_centres(footprints))
        geoms = shapely.buffer(footprints, self.pad, join_style="mitre") if self.pad > 0 and zs else footprints
        self._set_prisms(geoms, h)
        self._rasterise()

    def _set_prisms(self, geoms: np.ndarray, h: FloatArray) -> None:
        """The footprints (grown by the pad), their R-tree, rings and discs, and the bands grown by the pad."""
        zs = self.zones
        geoms = np.array(geoms, dtype=object)
        shapely.prepare(geoms)
        object.__setattr__(self, "_geoms", geoms)
        object.__setattr__(self, "_tree", shapely.STRtree(geoms))
        object.__setattr__(self, "_zlo", np.array([-z.bottom for z in zs], dtype=float) - self.pad)
        object.__setattr__(self, "_zhi", np.minimum(np.array([-z.top for z in zs], dtype=float) + self.pad, 0.0)
                           if self.pad else np.array([-z.top for z in zs], dtype=float))
        object.__setattr__(self, "_h", h + self.pad)
        object.__setattr__(self, "_seabed", np.isfinite(h))
        object.__setattr__(self, "_bounds", shapely.bounds(geoms).reshape(-1, 4))
        object.__setattr__(self, "_rings", polygon_rings(geoms, self._centres))

    def _rasterise(self) -> None:
        """The broad phase's grid (:func:`.zone_parts.rasterise`)."""
        grid = rasterise(self._bounds, self._tree, self._zlo, self._zhi, self._h, self.terrain) if self.zones else None
        object.__setattr__(self, "_grid", grid)
        if grid is not None:  # the fine lower-bound field (float32, about 1.5 million cells)
            object.__setattr__(self, "_field", distance_field(grid, self._rings, self._bounds))

    def candidates(self, segments: ArrayLike) -> tuple[IntArray, IntArray]:
        """The broad phase: the (segment, zone) pairs the exact test must look at (:mod:`.zone_kernels`);
        every other pair provably does not meet.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(N, 2, 3)`` (m).

        Returns
        -------
        seg, zone : numpy.ndarray of int
            The candidate pairs, sorted by segment.
        """
        if self._grid is None:
            return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
        return self._candidates(segments, self._grid[8], self._grid[9])

    def _candidates(self, segments: ArrayLike, zlo: Any, zhi: Any) -> tuple[IntArray, IntArray]:
        """:meth:`candidates` with the bands ``zlo``/``zhi`` ``(Z,)`` (z up, m) in place of the grid's."""
        s = np.ascontiguousarray(np.asarray(segments, dtype=float).reshape(-1, 2, 3))
        if self._grid is None or s.shape[0] == 0:
            return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
        x0, y0, cell, nx, ny, start, ids, box = self._grid[:8]
        args = (s, x0, y0, cell, nx, ny, start, ids, box, zlo, zhi)
        mark = np.full(len(self.zones), -1, dtype=np.intp)
        pairs = np.empty((2, 2 * s.shape[0] + 64), dtype=np.intp)
        m = candidates_kernel(*args, mark, pairs, pairs.shape[1])
        if m > pairs.shape[1]:  # more than the buffer held: again into one of the right size
            pairs = np.empty((2, m), dtype=np.intp)
            mark[:] = -1
            candidates_kernel(*args, mark, pairs, m)
        return pairs[0, :m], pairs[1, :m]

    def _lower_bound(self, p: FloatArray) -> FloatArray:
        """A lower bound of the horizontal distance from points ``(N, 3)`` to every footprint (m)."""
        assert self._grid is not None
        x0, y0, cell, nx, ny, *_, reach = self._grid
        fx, fy = (p[:, 0] - x0) / cell, (p[:, 1] - y0) / cell
        outside = np.hypot(np.maximum(np.maximum(-fx, fx - nx), 0.0), np.maximum(np.maximum(-fy, fy - ny), 0.0))
        i = np.clip(np.floor(fx).astype(int), 0, nx - 1)
        j = np.clip(np.floor(fy).astype(int), 0, ny - 1)
        inside: FloatArray = np.maximum(reach[j, i] - math.sqrt(2.0), 0.0)
        bound: FloatArray = np.where(outside > 0, outside, inside) * cell
        return bound

    def __len__(self) -> int:
        return len(self.zones)

    def with_pad(self, pad: float) -> Zones:
        """The same zones grown by another pad.

        Parameters
        ----------
        pad : float
            Growth (m).

        Returns
        -------
        Zones
            ``self`` when ``pad`` is the current one.
        """
        return self if pad == self.pad else Zones(self.zones, self.terrain, pad)

    @property
    def exact(self) -> Zones:
        """The same zones without :attr:`pad`.

        Returns
        -------
        Zones
            ``self`` when unpadded.
        """
        if self.pad == 0:
            return self
        cached: Zones | None = self.__dict__.get("_exact")
        if cached is None:
            cached = self._unpadded()
            object.__setattr__(self, "_exact", cached)
        return cached

    def _unpadded(self) -> Zones:
        """:attr:`exact` built from this padded set: its own footprints, bands, rings and R-tree (the exact
        tests and distances), the discs' centres shared, and the broad phase's cell lists and the fine field
        shared (a padded prism holds the unpadded one: its cells are a superset and its distances lower
        bounds); only the grid's bands, which the compiled flat-band test uses exactly, are its own."""
        out = object.__new__(Zones)
        for name, value in (("zones", self.zones), ("terrain", self.terrain), ("pad", 0.0),
                            ("_centres", self._centres)):
            object.__setattr__(out, name, value)
        # the zones' own heights, not (h + pad) - pad: that is an ulp off (0.2 -> 0.19999999999999996), and the
        # exact set must answer at a band's face as a set built alone
        h = np.array([np.nan if z.above_seabed is None else z.above_seabed for z in self.zones], dtype=float)
        out._set_prisms(np.array([z.footprint for z in self.zones], dtype=object), h)
        if self._grid is None:
            object.__setattr__(out, "_grid", None)
            return out
        sea = self._seabed
        # the highest seabed under its own box plus the height, as a set built alone has it (the padded top less
        # the pad is an ulp off, either way: a leg on the face was no candidate, or one an ulp above it was)
        top = band_tops(out._bounds, out._zhi, h, self.terrain)
        bottom = np.where(sea, -np.inf, out._zlo)
        object.__setattr__(out, "_grid", (*self._grid[:8], bottom, top, self._grid[10]))
        object.__setattr__(out, "_field", self._field)
        return out

    @property
    def names(self) -> list[str]:
        """The zones' names in order.

        Returns
        -------
        list of str
            One name per zone.
        """
        return [z.name for z in self.zones]

    # ------------------------------------------------------------------ segments
    def entries(self, segments: ArrayLike) -> tuple[IntArray, IntArray]:
        """Exact test: every (segment, zone) pair where the segment enters the zone's prism.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(N, 2, 3)`` (m).

        Returns
        -------
        seg, zone : numpy.ndarray of int
            Indices of the entering pairs (each pair once), sorted by segment, then zone.
        """
        s = np.asarray(segments, dtype=float).reshape(-1, 2, 3)
        empty = np.zeros(0, dtype=np.intp)
        if not self.zones or s.shape[0] == 0:
            return empty, empty
        cs, zi = self.candidates(s)
        if cs.size == 0:
            return empty, empty
        seabed = np.isfinite(self._h[zi])
        hit = np.zeros(cs.size, dtype=bool)
        flat = ~seabed
        if flat.any():
            out = np.empty(int(flat.sum()), dtype=bool)
            flat_hits_kernel(s, cs[flat], zi[flat], self._zlo, self._zhi, *self._rings, out)
            hit[flat] = out
        if seabed.any():
            sub = np.flatnonzero(seabed)
            hit[sub] = self._seabed_pairs(s, cs[sub], zi[sub])
        order = np.lexsort((zi[hit], cs[hit]))  # the broad phase lists a segment's zones in cell order
        return cs[hit][order], zi[hit][order]

    def _seabed_pairs(self, s: FloatArray, cs: IntArray, zi: IntArray) -> BoolArray:
        """Exact test of the (segment, seabed-band zone) pairs: the footprint met by the trace (GEOS), then
        :meth:`_seabed_hits`."""
        hit = np.zeros(cs.size, dtype=bool)
        idx, si = np.unique(cs, return_inverse=True)
        traces = trace_geoms(s[idx])
        meet = shapely.intersects(self._geoms[zi], traces[si])
        sub = np.flatnonzero(meet)
        hit[sub] = self._seabed_hits(s[cs[sub]], traces[si[sub]], zi[sub])
        return hit

    def _any_hits(self, s: FloatArray) -> BoolArray:
        """Which segments ``(N, 2, 3)`` enter any zone (exact): the compiled pass settles the flat bands and
        lists the seabed-band candidates of the rest (:func:`.zone_kernels.any_hits_kernel`)."""
        s = np.ascontiguousarray(s)
        return self._compiled_hits(any_hits_kernel, s, s.shape[0], lambda n: s[n])

    def _path_hits(self, p: FloatArray) -> BoolArray:
        """Which legs of polylines ``(P, S, 3)`` enter any zone (exact), ``(P * (S - 1),)``
        (:func:`.zone_kernels.path_hits_kernel`)."""
        p = np.ascontiguousarray(p)
        legs = p.shape[1] - 1

        def segments(n: IntArray) -> FloatArray:
            i, k = np.divmod(n, legs)
            return np.stack([p[i, k], p[i, k + 1]], axis=1)

        return self._compiled_hits(path_hits_kernel, p, p.shape[0] * legs, segments)

    def _compiled_hits(self, kernel: Any, data: FloatArray, count: int, segments: Any) -> BoolArray:
        """Run a compiled any-hit pass, then test its seabed-band candidates exactly (GEOS and the terrain)."""
        if self._grid is None or count == 0:
            return np.zeros(count, dtype=bool)
        hit = np.empty(count, dtype=bool)  # the kernel writes every entry
        x0, y0, cell, nx, ny, start, ids, box, zlo, zhi, _ = self._grid
        args = (data, x0, y0, cell, nx, ny, start, ids, box, zlo, zhi, self._seabed, *self._rings, *self._field)
        mark = np.full(len(self.zones), -1, dtype=np.intp)
        pairs = np.empty((2, count + 64), dtype=np.intp)
        m = kernel(*args, mark, hit, pairs, pairs.shape[1])
        if m > pairs.shape[1]:
            pairs = np.empty((2, m), dtype=np.intp)
            mark[:] = -1
            kernel(*args, mark, hit, pairs, m)
        if m:
            cs, zi = pairs[0, :m], pairs[1, :m]
            idx, local = np.unique(cs, return_inverse=True)
            hit[cs[self._seabed_pairs(segments(idx), local, zi)]] = True
        return hit

    def polyline_slack(self, points: ArrayLike) -> FloatArray:
        """The swarm planners' zone slack of the legs of polylines: minus the length of each leg that enters
        a zone (at least 1 m: a violation as deep as the leg), ``+inf`` for the others.

        Parameters
        ----------
        points : array_like
            Vertices ``(P, S, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(P, S - 1)`` (m).
        """
        p = np.ascontiguousarray(np.asarray(points, dtype=float))
        if not self.zones or p.shape[1] < 2 or p.shape[0] == 0:
            return np.full((p.shape[0], max(p.shape[1] - 1, 0)), np.inf)
        out = np.empty((p.shape[0], p.shape[1] - 1))  # the kernel writes every entry
        slack_kernel(p, self._path_hits(p), out)
        return out

    def polyline_inside_lengths(self, points: ArrayLike) -> FloatArray:
        """:meth:`inside_lengths` of the legs of polylines.

        Parameters
        ----------
        points : array_like
            Vertices ``(P, S, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(P, S - 1)`` (m): the length of each leg that enters a zone (at least 1), else 0.
        """
        out: FloatArray = np.maximum(-self.polyline_slack(points), 0.0)
        return out

    def _seabed_hits(self, seg: FloatArray, traces: np.ndarray, zi: IntArray) -> BoolArray:
        """Exact test against seabed bands: the trace clipped to the footprint, each piece's least
        altitude from the terrain's exact walk, compared with the band's height."""
        assert self.terrain is not None
        pieces, owner = clip_pieces(seg, traces, self._geoms[zi])
        hit = np.zeros(zi.size, dtype=bool)
        if owner.size:
            alt = self.terrain.segment_min_altitude(pieces)
            np.logical_or.at(hit, owner, alt <= self._h[zi][owner])
        return hit

    def segments_enter(self, segments: ArrayLike) -> BoolArray:
        """Where segments enter any zone (exact).

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True for segments that enter (or touch) a prism.
        """
        s = np.asarray(segments, dtype=float)
        lead = s.shape[:-2]
        if not self.zones:
            return np.zeros(lead, dtype=bool)
        return self._any_hits(s.reshape(-1, 2, 3)).reshape(lead)

    def traces_enter(self, traces: ArrayLike, trace_of: ArrayLike, za: ArrayLike, zb: ArrayLike) -> BoolArray:
        """:meth:`segments_enter` of segments that share horizontal traces (a lattice's edges along one
        direction from the nodes of one column).

        Each trace is marched over the fine field and, unless proven clear, tested once in 2D against the
        footprints its cells list (the compiled test with the bands set aside).  A segment over a trace
        that meets footprint ``k`` enters prism ``k`` when its z-range lies within the band (z is linear
        along it and the trace meets the footprint somewhere), not when the ranges are apart; only the
        others take the exact test.

        Parameters
        ----------
        traces : array_like
            Horizontal traces ``(T, 2, 2)`` (m).
        trace_of : array_like of int
            ``(N,)`` the trace of each segment.
        za, zb : array_like
            ``(N,)`` each segment's z at the trace's start and end (m, up).

        Returns
        -------
        numpy.ndarray of bool
            ``(N,)``, True where the segment enters (or touches) a prism.
        """
        t = np.ascontiguousarray(np.asarray(traces, dtype=float).reshape(-1, 2, 2))
        of = np.asarray(trace_of, dtype=np.intp).reshape(-1)
        za, zb = np.asarray(za, dtype=float).reshape(-1), np.asarray(zb, dtype=float).reshape(-1)
        out = np.zeros(of.size, dtype=bool)
        if not self.zones or of.size == 0:
            return out
        clear = np.zeros(t.shape[0], dtype=bool)
        fx0, fy0, f, fnx, fny, bound = self._field
        clear_kernel(t, fx0, fy0, f, fnx, fny, bound, clear)
        near = np.flatnonzero(~clear)
        flat = np.zeros((near.size, 2, 3))
        flat[:, :, :2] = t[near]
        every = np.full(len(self.zones), np.inf)
        cs, zi = self._candidates(flat, -every, every)
        met = np.empty(cs.size, dtype=bool)
        flat_hits_kernel(flat, cs, zi, -every, every, *self._rings, met)
        which, n = expand_groups(of, near[cs[met]])
        k = zi[met][which]
        lo, hi = np.minimum(za[n], zb[n]), np.maximum(za[n], zb[n])
        assert self._grid is not None
        sea = self._seabed[k]
        apart = (hi < self._zlo[k]) | (lo > self._grid[9][k])
        within = ~sea & (lo >= self._zlo[k]) & (hi <= self._zhi[k])
        out[n[within]] = True
        rest = np.flatnonzero(~apart & ~within & ~out[n])
        if rest.size:
            seg = np.empty((rest.size, 2, 3))
            seg[:, :, :2] = t[of[n[rest]]]
            seg[:, 0, 2], seg[:, 1, 2] = za[n[rest]], zb[n[rest]]
            idx = np.arange(rest.size)
            hit = np.zeros(rest.size, dtype=bool)
            f = ~sea[rest]
            if f.any():
                got = np.empty(int(f.sum()), dtype=bool)
                flat_hits_kernel(seg, idx[f], k[rest][f], self._zlo, self._zhi, *self._rings, got)
                hit[f] = got
            if (~f).any():
                hit[~f] = self._seabed_pairs(seg, idx[~f], k[rest][~f])
            out[n[rest][hit]] = True
        return out

    def envelopes_enter(self, a: ArrayLike, b: ArrayLike) -> BoolArray:
        """Where the vertical envelope of a leg (its horizontal trace times the depths between its
        ends: every way of flying it with depth held or ramped) meets a zone (exact).

        Parameters
        ----------
        a, b : array_like
            Leg starts and ends ``(K, 3)`` (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(K,)``, True where the envelope enters or touches a prism.
        """
        a = np.asarray(a, dtype=float).reshape(-1, 3)
        out = np.zeros(a.shape[0], dtype=bool)
        out[self.envelope_entries(a, b)[0]] = True
        return out

    def envelope_entries(self, a: ArrayLike, b: ArrayLike) -> tuple[IntArray, IntArray]:
        """Every (leg, zone) pair where the leg's vertical envelope (:meth:`envelopes_enter`) meets the zone.

        Parameters
        ----------
        a, b : array_like
            Leg starts and ends ``(K, 3)`` (m).

        Returns
        -------
        leg, zone : numpy.ndarray of int
            The pairs (each once), sorted by leg, then zone.
        """
        a, b = np.asarray(a, dtype=float).reshape(-1, 3), np.asarray(b, dtype=float).reshape(-1, 3)
        empty = np.zeros(0, dtype=np.intp)
        if not self.zones or a.shape[0] == 0:
            return empty, empty
        low = np.minimum(a[:, 2], b[:, 2])
        seg = np.stack([a, b], axis=1)
        traces = trace_geoms(seg)
        si, zi = self._tree.query(traces, predicate="intersects")
        hit = np.zeros(si.size, dtype=bool)
        seabed = np.isfinite(self._h[zi])
        flat = ~seabed
        hit[flat] = (low[si[flat]] <= self._zhi[zi[flat]]) & (np.maximum(a[si[flat], 2], b[si[flat], 2])
                                                              >= self._zlo[zi[flat]])
        if seabed.any():  # the envelope's lowest edge: the leg flown flat at its deeper end
            level = seg[si[seabed]].copy()
            level[:, :, 2] = low[si[seabed], None]
            hit[seabed] = self._seabed_hits(level, traces[si[seabed]], zi[seabed])
        order = np.lexsort((zi[hit], si[hit]))
        return si[hit][order].astype(np.intp), zi[hit][order].astype(np.intp)

    def inside_lengths(self, segments: ArrayLike) -> FloatArray:
        """A violation depth for the cost: the length of each segment that enters a zone (m, at
        least 1; 0 for a segment that enters none).

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m).
        """
        s = np.asarray(segments, dtype=float)
        lead = s.shape[:-2]
        flat = s.reshape(-1, 2, 3)
        out = np.zeros(flat.shape[0])
        if not self.zones:
            return out.reshape(lead)
        seg = np.flatnonzero(self._any_hits(flat))
        if seg.size:
            out[seg] = np.maximum(np.linalg.norm(flat[seg, 1] - flat[seg, 0], axis=-1), 1.0)
        return out.reshape(lead)

    # ------------------------------------------------------------------ points
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


@dataclass(frozen=True)
class ZoneApproach:
    """How a polyline passes one zone (:meth:`Zones.approach`).

    Attributes
    ----------
    name : str
        The zone.
    closest_m : float
        Least distance of the polyline to the prism (m); ≤ 0 when a leg enters it.
    entered_legs : tuple of int
        The legs (from 1) that enter it (exact test); empty when none does.
    """

    name: str
    closest_m: float
    entered_legs: tuple[int, ...]

    def as_dict(self) -> dict[str, object]:
        """The approach as JSON-ready values.

        Returns
        -------
        dict
            ``name``, ``closest_m``, ``entered_legs``.
        """
        return {"name": self.name, "closest_m": self.closest_m, "entered_legs": list(self.entered_legs)}
