"""Seabed heightfield on a regular grid in the local metric frame.

The seabed elevation ``zb(x, y)`` (metres, z up, negative under water) is the
bilinear interpolant of the grid.  Beyond the grid's extent the surface is
continued with the edge values (coordinates are clamped).

Two segment-versus-terrain tests are provided:

* :meth:`Terrain.segment_min_altitude` / :meth:`Terrain.segments_below` — **exact**:
  every grid line a segment crosses splits it into pieces that each lie in one
  cell; along a piece the bilinear surface is a quadratic in the segment
  parameter, so the altitude ``z(t) - zb(t)`` is a quadratic whose minimum is at
  a piece end or at its vertex (METHODS.md §4, the exact collision model).  All
  pieces of all segments are processed as flat arrays.
* :meth:`Terrain.segments_below_stepping` — document 004's test: probes every
  ``step`` metres along the dominant axis.  It can miss features thinner than
  the step; it is kept so the two can be compared.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import DataError

__all__ = ["Terrain"]


@dataclass(frozen=True, eq=False)
class Terrain:
    """Regular-grid seabed heightfield.

    Parameters
    ----------
    x, y : ndarray
        Ascending, uniformly spaced grid coordinates (m), shapes ``(nx,)`` and ``(ny,)``.
    z : ndarray
        Seabed elevation (m, positive up), shape ``(ny, nx)``; must be finite.
    name : str
        Free text (source of the data).
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    name: str = ""
    _coef: np.ndarray = field(init=False, repr=False)
    _lipschitz: float = field(init=False, repr=False)
    _coef_list: list = field(init=False, repr=False, compare=False)
    _x0: float = field(init=False, repr=False, compare=False)
    _y0: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        x = np.asarray(self.x, dtype=float)
        y = np.asarray(self.y, dtype=float)
        z = np.asarray(self.z, dtype=float)
        if x.ndim != 1 or y.ndim != 1 or x.size < 2 or y.size < 2:
            raise DataError(
                f"terrain {self.name!r}: the grid needs at least 2 x 2 nodes, got x {x.shape}, y {y.shape}"
            )
        if z.shape != (y.size, x.size):
            raise DataError(
                f"terrain {self.name!r}: elevation shape {z.shape} does not match (ny, nx) = ({y.size}, {x.size})"
            )
        for name, axis in (("x", x), ("y", y)):
            step = np.diff(axis)
            if not np.all(step > 0) or not np.allclose(step, step[0], rtol=1e-6, atol=1e-9):
                raise DataError(f"terrain {self.name!r}: axis {name} must be ascending and uniformly spaced")
        bad = ~np.isfinite(z)
        if bad.any():
            j, i = np.argwhere(bad)[0]
            raise DataError(
                f"terrain {self.name!r}: elevation has {int(bad.sum())} non-finite values "
                f"(first at x={x[i]:.1f}, y={y[j]:.1f})"
            )
        for name, value in (("x", x), ("y", y), ("z", z)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        # bilinear coefficients per cell: zb = a + b u + c v + e u v, u, v in [0, 1]
        z00, z10, z01, z11 = z[:-1, :-1], z[:-1, 1:], z[1:, :-1], z[1:, 1:]
        coef = np.stack([z00, z10 - z00, z01 - z00, z00 - z10 - z01 + z11], axis=-1)
        coef.setflags(write=False)
        object.__setattr__(self, "_coef", coef)
        # steepest slope of the bilinear surface (its Lipschitz constant): per cell the
        # gradient components are extreme on the cell edges
        gx = np.maximum(np.abs(coef[..., 1]), np.abs(coef[..., 1] + coef[..., 3])) / (x[1] - x[0])
        gy = np.maximum(np.abs(coef[..., 2]), np.abs(coef[..., 2] + coef[..., 3])) / (y[1] - y[0])
        object.__setattr__(self, "_lipschitz", float(np.sqrt(gx**2 + gy**2).max()))
        object.__setattr__(self, "_coef_list", self._coef.tolist())
        object.__setattr__(self, "_x0", float(x[0]))
        object.__setattr__(self, "_y0", float(y[0]))

    # ------------------------------------------------------------------ grid facts
    @property
    def dx(self) -> float:
        """Cell size along x (m)."""
        return float(self.x[1] - self.x[0])

    @property
    def dy(self) -> float:
        """Cell size along y (m)."""
        return float(self.y[1] - self.y[0])

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` of the grid (m)."""
        return float(self.x[0]), float(self.x[-1]), float(self.y[0]), float(self.y[-1])

    # ------------------------------------------------------------------ evaluation
    def _locate(self, x, y):
        fx = (np.asarray(x, dtype=float) - self.x[0]) / self.dx
        fy = (np.asarray(y, dtype=float) - self.y[0]) / self.dy
        i = np.clip(np.floor(fx), 0, self.x.size - 2).astype(np.intp)
        j = np.clip(np.floor(fy), 0, self.y.size - 2).astype(np.intp)
        u = np.clip(fx - i, 0.0, 1.0)
        v = np.clip(fy - j, 0.0, 1.0)
        return i, j, u, v

    def elevation(self, x, y) -> np.ndarray:
        """Bilinear seabed elevation at ``(x, y)`` (broadcasting arrays, m)."""
        i, j, u, v = self._locate(x, y)
        a, b, c, e = np.moveaxis(self._coef[j, i], -1, 0)
        return a + b * u + c * v + e * u * v

    def elevation_at(self, x: float, y: float) -> float:
        """:meth:`elevation` of one point with plain floats (the simulator's per-step query)."""
        fx = (x - self._x0) / self.dx
        fy = (y - self._y0) / self.dy
        i = min(max(math.floor(fx), 0), self.x.size - 2)
        j = min(max(math.floor(fy), 0), self.y.size - 2)
        u = min(max(fx - i, 0.0), 1.0)
        v = min(max(fy - j, 0.0), 1.0)
        a, b, c, e = self._coef_list[j][i]
        return a + b * u + c * v + e * u * v

    def gradient(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """``(dzb/dx, dzb/dy)`` of the bilinear surface (zero slope across a clamped edge)."""
        fx = (np.asarray(x, dtype=float) - self.x[0]) / self.dx
        fy = (np.asarray(y, dtype=float) - self.y[0]) / self.dy
        i, j, u, v = self._locate(x, y)
        _, b, c, e = np.moveaxis(self._coef[j, i], -1, 0)
        inside_x = (fx >= 0) & (fx <= self.x.size - 1)
        inside_y = (fy >= 0) & (fy <= self.y.size - 1)
        gx = np.where(inside_x, (b + e * v) / self.dx, 0.0)
        gy = np.where(inside_y, (c + e * u) / self.dy, 0.0)
        return gx, gy

    def altitude(self, points) -> np.ndarray:
        """Height of ``points (..., 3)`` above the seabed (negative below it)."""
        p = np.asarray(points, dtype=float)
        return p[..., 2] - self.elevation(p[..., 0], p[..., 1])

    # ------------------------------------------------------------------ exact segment test
    def _line_crossings(self, a, b, origin, step, n):
        """Parameters t in (0, 1) where coordinate ``a + t (b - a)`` crosses grid lines 0..n-1."""
        ka = (a - origin) / step
        kb = (b - origin) / step
        lo_f = np.minimum(ka, kb)
        hi_f = np.maximum(ka, kb)
        lo = np.maximum(np.floor(lo_f) + 1, 0)
        hi = np.minimum(np.ceil(hi_f) - 1, n - 1)
        count = np.maximum(hi - lo + 1, 0).astype(np.intp)
        seg = np.repeat(np.arange(a.size), count)
        first = np.repeat(lo, count)
        offs = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        k = first + offs
        t = (k - ka[seg]) / (kb[seg] - ka[seg])
        return seg, t

    @property
    def max_slope(self) -> float:
        """Largest slope |∇zb| of the bilinear surface (its Lipschitz constant)."""
        return self._lipschitz

    def altitude_lower_bound(self, ga, gb, dz, lh) -> np.ndarray:
        """Provable lower bound ``min(g_a, g_b, (g_a + g_b - |Δz| - G L_h) / 2)`` of the minimum
        altitude along segments with end altitudes ``g_a, g_b``, rise ``Δz`` and horizontal
        length ``L_h`` (G the steepest slope: the seabed cannot rise faster)."""
        bound = 0.5 * (ga + gb - np.abs(dz) - self._lipschitz * lh)
        return np.minimum(bound, np.minimum(ga, gb))

    def segment_min_altitude(self, segments, threshold: float = np.inf, end_altitudes=None) -> np.ndarray:
        """Minimum of ``z - zb`` along each segment, exact wherever it is below ``threshold``.

        With the default ``threshold = inf`` every value is exact.  With a finite
        threshold, segments whose provable lower bound
        ``(g_a + g_b - |Δz| - G L_h) / 2`` (g the end altitudes, G the steepest
        slope, L_h the horizontal length) is already ≥ ``threshold`` return that
        bound instead of the exact minimum: enough for a constraint test at
        ``threshold`` at a fraction of the cost.

        Parameters
        ----------
        segments : array_like, shape ``(..., 2, 3)``
            Start and end points.
        threshold : float
            Altitude below which the result must be exact.
        end_altitudes : tuple of ndarray, optional
            The altitudes ``(g_a, g_b)`` of the end points when the caller already has them.

        Returns
        -------
        ndarray, shape ``(...)``
            Minimum altitude above the bilinear seabed over the whole segment.
        """
        seg = np.asarray(segments, dtype=float)
        if seg.shape[-2:] != (2, 3):
            raise ValueError(f"segments must have shape (..., 2, 3), got {seg.shape}")
        lead = seg.shape[:-2]
        seg = seg.reshape(-1, 2, 3)
        if seg.shape[0] == 0:
            return np.zeros(lead)
        if np.isfinite(threshold):
            if end_altitudes is None:
                ga = seg[:, 0, 2] - self.elevation(seg[:, 0, 0], seg[:, 0, 1])
                gb = seg[:, 1, 2] - self.elevation(seg[:, 1, 0], seg[:, 1, 1])
            else:
                ga, gb = (np.asarray(g, dtype=float).reshape(-1) for g in end_altitudes)
            d = seg[:, 1] - seg[:, 0]
            bound = self.altitude_lower_bound(ga, gb, d[:, 2], np.hypot(d[:, 0], d[:, 1]))
            near = bound < threshold
            if near.any():
                bound[near] = self._exact_min_altitude(seg[near])
            return bound.reshape(lead)
        return self._exact_min_altitude(seg).reshape(lead)

    def _exact_min_altitude(self, seg: np.ndarray) -> np.ndarray:
        """Exact minimum altitude along segments ``(n, 2, 3)``."""
        n = seg.shape[0]
        p0, p1 = seg[:, 0], seg[:, 1]
        d = p1 - p0
        sx, tx = self._line_crossings(p0[:, 0], p1[:, 0], self.x[0], self.dx, self.x.size)
        sy, ty = self._line_crossings(p0[:, 1], p1[:, 1], self.y[0], self.dy, self.y.size)
        ids = np.concatenate([np.arange(n), np.arange(n), sx, sy])
        ts = np.concatenate([np.zeros(n), np.ones(n), tx, ty])
        order = np.lexsort((ts, ids))
        ids, ts = ids[order], ts[order]
        same = ids[:-1] == ids[1:]
        sid = ids[:-1][same]
        ta, tb = ts[:-1][same], ts[1:][same]
        tm = 0.5 * (ta + tb)
        # cell of each piece and the local coordinates u(t) = u0 + du t, v(t) = v0 + dv t
        xm = p0[sid, 0] + tm * d[sid, 0]
        ym = p0[sid, 1] + tm * d[sid, 1]
        fx = (xm - self.x[0]) / self.dx
        fy = (ym - self.y[0]) / self.dy
        i = np.clip(np.floor(fx), 0, self.x.size - 2).astype(np.intp)
        j = np.clip(np.floor(fy), 0, self.y.size - 2).astype(np.intp)
        u0 = (p0[sid, 0] - self.x[i]) / self.dx
        v0 = (p0[sid, 1] - self.y[j]) / self.dy
        du = d[sid, 0] / self.dx
        dv = d[sid, 1] / self.dy
        # outside the extent the surface is the clamped edge: u constant there
        out_lo_x, out_hi_x = fx < 0, fx > self.x.size - 1
        out_lo_y, out_hi_y = fy < 0, fy > self.y.size - 1
        u0 = np.where(out_lo_x, 0.0, np.where(out_hi_x, 1.0, u0))
        du = np.where(out_lo_x | out_hi_x, 0.0, du)
        v0 = np.where(out_lo_y, 0.0, np.where(out_hi_y, 1.0, v0))
        dv = np.where(out_lo_y | out_hi_y, 0.0, dv)
        a, b, c, e = np.moveaxis(self._coef[j, i], -1, 0)
        h0 = a + b * u0 + c * v0 + e * u0 * v0
        h1 = b * du + c * dv + e * (u0 * dv + v0 * du)
        h2 = e * du * dv
        # g(t) = z(t) - h(t) = g0 + g1 t + g2 t^2
        g0 = p0[sid, 2] - h0
        g1 = d[sid, 2] - h1
        g2 = -h2
        ga = g0 + g1 * ta + g2 * ta * ta
        gb = g0 + g1 * tb + g2 * tb * tb
        gmin = np.minimum(ga, gb)
        with np.errstate(divide="ignore", invalid="ignore"):
            tv = -g1 / (2.0 * g2)
        inner = (g2 > 0) & (tv > ta) & (tv < tb)
        gv = np.where(inner, g0 - g1 * g1 / (4.0 * np.where(inner, g2, 1.0)), np.inf)
        gmin = np.minimum(gmin, gv)
        starts = np.flatnonzero(np.r_[True, sid[1:] != sid[:-1]])
        return np.minimum.reduceat(gmin, starts)

    def segments_below(self, segments, altitude: float = 0.0) -> np.ndarray:
        """True where a segment passes below ``zb + altitude`` anywhere (exact)."""
        return self.segment_min_altitude(segments, threshold=altitude) < altitude

    # ------------------------------------------------------------------ document 004 variant
    def segments_below_stepping(self, segments, altitude: float = 0.0, step: float | None = None) -> np.ndarray:
        """Document 004's collision test: probe every ``step`` metres along the dominant axis.

        The probe count of a segment is ``ceil(span / step)`` where ``span`` is its
        largest coordinate extent; each probe is compared with the bilinear seabed.
        ``step`` defaults to the smaller cell size.  Features thinner than ``step``
        can be missed.
        """
        seg = np.asarray(segments, dtype=float)
        lead = seg.shape[:-2]
        seg = seg.reshape(-1, 2, 3)
        n = seg.shape[0]
        if n == 0:
            return np.zeros(lead, dtype=bool)
        step = min(self.dx, self.dy) if step is None else float(step)
        if step <= 0:
            raise ValueError(f"step must be positive, got {step}")
        d = seg[:, 1] - seg[:, 0]
        span = np.abs(d).max(axis=1)
        count = np.maximum(np.ceil(span / step).astype(np.intp), 1) + 1
        sid = np.repeat(np.arange(n), count)
        k = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        t = k / (count[sid] - 1)
        pts = seg[sid, 0] + t[:, None] * d[sid]
        below = self.altitude(pts) < altitude
        starts = np.cumsum(count) - count
        return np.logical_or.reduceat(below, starts).reshape(lead)
