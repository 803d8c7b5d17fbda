"""The zones' segment queries: the exact segment-vs-prism test (:meth:`SegmentQueries.entries`), the compiled
any-hit passes of the swarm cost and the final check, shared traces of the lattice and vertical envelopes."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely

from ..._types import ArrayLike, BoolArray, FloatArray, IntArray
from .bound import clear_kernel
from .exact import flat_hits_kernel
from .index import ZoneIndex
from .kernels import any_hits_kernel, path_hits_kernel, slack_kernel
from .parts import clip_pieces, expand_groups
from .parts import traces as trace_geoms

__all__ = ["SegmentQueries"]


@dataclass(frozen=True, eq=False)
class SegmentQueries(ZoneIndex):
    """The segment queries over :class:`.index.ZoneIndex`.

    Parameters
    ----------
    zones : tuple of Zone
        The prisms (may be empty).
    terrain : Terrain or None
        Seabed for the zones given ``above_seabed``.
    pad : float, default 0.0
        Growth of every prism (m; :class:`.index.ZoneIndex`).
    """

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
        """Exact test of the (segment, seabed-band zone) pairs: a segment whose least altitude over its whole
        length (the terrain's exact walk) is above the band's height, by a millionth of the figures against
        rounding, is above it over every piece too; the others take the footprint met by the trace (GEOS),
        then :meth:`_seabed_hits`."""
        assert self.terrain is not None
        hit = np.zeros(cs.size, dtype=bool)
        idx, si = np.unique(cs, return_inverse=True)
        seg = s[idx]
        low, h = self.terrain.segment_min_altitude(seg)[si], self._h[zi]
        scale = 1.0 + np.abs(h) + np.abs(seg[si, :, 2]).max(axis=1)
        maybe = np.flatnonzero(~(low > h + 1e-6 * scale))
        if maybe.size == 0:
            return hit
        traces = trace_geoms(seg)
        meet = shapely.intersects(self._geoms[zi[maybe]], traces[si[maybe]])
        sub = maybe[meet]
        hit[sub] = self._seabed_hits(s[cs[sub]], traces[si[sub]], zi[sub])
        return hit

    def _any_hits(self, s: FloatArray) -> BoolArray:
        """Which segments ``(N, 2, 3)`` enter any zone (exact): the compiled pass settles the flat bands and
        lists the seabed-band candidates of the rest (:func:`.kernels.any_hits_kernel`)."""
        s = np.ascontiguousarray(s)
        return self._compiled_hits(any_hits_kernel, s, s.shape[0], lambda n: s[n])

    def _path_hits(self, p: FloatArray) -> BoolArray:
        """Which legs of polylines ``(P, S, 3)`` enter any zone (exact), ``(P * (S - 1),)``
        (:func:`.kernels.path_hits_kernel`)."""
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
        fx0, fy0, f, fnx, fny, bound = self._field[:6]
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
            out[n[rest][self._pairs_enter(t[of[n[rest]]], za[n[rest]], zb[n[rest]], k[rest], sea[rest])]] = True
        return out

    def _pairs_enter(self, trace: FloatArray, za: FloatArray, zb: FloatArray, k: IntArray,
                     sea: BoolArray) -> BoolArray:
        """The exact test of segments over ``trace`` (``(M, 2, 2)``, z from ``za`` to ``zb``) against prism ``k``
        each (``sea``: a band measured from the seabed)."""
        seg = np.empty((k.size, 2, 3))
        seg[:, :, :2] = trace
        seg[:, 0, 2], seg[:, 1, 2] = za, zb
        idx = np.arange(k.size)
        hit = np.zeros(k.size, dtype=bool)
        f = ~sea
        if f.any():
            got = np.empty(int(f.sum()), dtype=bool)
            flat_hits_kernel(seg, idx[f], k[f], self._zlo, self._zhi, *self._rings, got)
            hit[f] = got
        if (~f).any():
            hit[~f] = self._seabed_pairs(seg, idx[~f], k[~f])
        return hit

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
