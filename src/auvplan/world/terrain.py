"""Seabed heightfield on a regular grid in the local metric frame.

The seabed elevation ``zb(x, y)`` (metres, z up, negative under water) is the
bilinear interpolant of the grid.  Beyond the grid's extent the surface is
continued with the edge values (coordinates are clamped).

Two segment-versus-terrain tests are provided:

* :meth:`Terrain.segment_min_altitude` / :meth:`Terrain.segments_below` — **exact**:
  every grid line a segment crosses splits it into pieces that each lie in one
  cell; along a piece the bilinear surface is a quadratic in the segment
  parameter, so the altitude ``z(t) - zb(t)`` is a quadratic whose minimum is at
  a piece end or at its vertex (docs/methods.md §4, the exact collision model).  All
  pieces are walked in one compiled loop per segment (numba, :mod:`auvplan.world.kernels.terrain`), after a
  provable lower bound has cleared the segments that are far above the seabed.
* :meth:`Terrain.segments_below_stepping` — document 004's test: probes every
  ``step`` metres along the dominant axis.  It can miss features thinner than
  the step; it is kept so the two can be compared.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TypeAlias

import numpy as np

from .._types import ArrayLike, BoolArray, FloatArray, IntArray
from ..errors import DataError
from .kernels.terrain import (
    _elevations,
    _min_altitudes,
    box_floor_kernel,
    elevation_kernel,
    lipschitz_bound_kernel,
    min_altitude_kernel,
    walk_min_kernel,
)
from .seabed import SeabedFit

__all__ = ["Terrain", "TerrainKernelData", "elevation_kernel", "min_altitude_kernel", "lipschitz_bound_kernel",
           "box_floor_kernel", "walk_min_kernel"]

#: ``(coef, x0, y0, dx, dy, max_slope)``: bilinear coefficients ``(ny - 1, nx - 1, 4)`` (m), grid origin (m),
#: cell sizes (m) and the surface's steepest slope; the leading arguments of the compiled kernels.
TerrainKernelData: TypeAlias = tuple[FloatArray, float, float, float, float, float]


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
    fit : SeabedFit, optional
        How this model sits against the data it was made from (its excess height, and any depth
        below the data); None when unknown (synthetic terrains, older results folders).

    Raises
    ------
    DataError
        If the grid is smaller than 2 x 2, not uniform and ascending, mis-shaped or not finite.
    """

    x: FloatArray
    y: FloatArray
    z: FloatArray
    name: str = ""
    fit: SeabedFit | None = None
    _coef: FloatArray = field(init=False, repr=False)
    _lipschitz: float = field(init=False, repr=False)
    _kernel: TerrainKernelData = field(init=False, repr=False, compare=False)
    _cell_max: FloatArray = field(init=False, repr=False, compare=False)

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
        # C order whatever z's (np.stack follows a transposed z's layout): the kernels are compiled for C arrays
        coef = np.ascontiguousarray(np.stack([z00, z10 - z00, z01 - z00, z00 - z10 - z01 + z11], axis=-1))
        coef.setflags(write=False)
        object.__setattr__(self, "_coef", coef)
        # steepest slope of the bilinear surface (its Lipschitz constant): per cell the
        # gradient components are extreme on the cell edges
        gx = np.maximum(np.abs(coef[..., 1]), np.abs(coef[..., 1] + coef[..., 3])) / (x[1] - x[0])
        gy = np.maximum(np.abs(coef[..., 2]), np.abs(coef[..., 2] + coef[..., 3])) / (y[1] - y[0])
        object.__setattr__(self, "_lipschitz", float(np.sqrt(gx**2 + gy**2).max()))
        kernel_data: TerrainKernelData = (coef, float(x[0]), float(y[0]), float(x[1] - x[0]), float(y[1] - y[0]),
                                          self._lipschitz)
        object.__setattr__(self, "_kernel", kernel_data)
        # the bilinear surface of a cell is a convex combination of its corners: its top is the highest corner
        cell_max = np.maximum(np.maximum(z00, z10), np.maximum(z01, z11))
        cell_max.setflags(write=False)
        object.__setattr__(self, "_cell_max", cell_max)

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
    def kernel_data(self) -> TerrainKernelData:
        """``(coef, x0, y0, dx, dy, max_slope)``: the leading arguments of the compiled
        :func:`elevation_kernel` (first five) and :func:`min_altitude_kernel` (all six)."""
        return self._kernel

    @property
    def cell_max(self) -> FloatArray:
        """Highest seabed elevation of each cell ``(ny - 1, nx - 1)`` (m): the argument of
        :func:`~auvplan.world.kernels.terrain.box_floor_kernel`."""
        return self._cell_max

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` of the grid (m)."""
        return float(self.x[0]), float(self.x[-1]), float(self.y[0]), float(self.y[-1])

    # ------------------------------------------------------------------ evaluation
    def _locate(self, x: ArrayLike, y: ArrayLike) -> tuple[IntArray, IntArray, FloatArray, FloatArray]:
        fx = (np.asarray(x, dtype=float) - self.x[0]) / self.dx
        fy = (np.asarray(y, dtype=float) - self.y[0]) / self.dy
        i = np.clip(np.floor(fx), 0, self.x.size - 2).astype(np.intp)
        j = np.clip(np.floor(fy), 0, self.y.size - 2).astype(np.intp)
        u = np.clip(fx - i, 0.0, 1.0)
        v = np.clip(fy - j, 0.0, 1.0)
        return i, j, u, v

    def elevation(self, x: ArrayLike, y: ArrayLike) -> FloatArray:
        """Bilinear seabed elevation.

        Parameters
        ----------
        x, y : array_like
            Easting and northing (m); broadcast together.  Outside the grid the edge values hold.

        Returns
        -------
        numpy.ndarray
            Seabed elevation ``zb`` (m, positive up), the broadcast shape (0-d for scalars).
        """
        bx, by = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        out = np.empty(bx.shape)
        _elevations(*self.kernel_data[:5], bx.ravel(), by.ravel(), out.reshape(-1))
        zb: FloatArray = out[()]
        return zb

    def elevation_at(self, x: float, y: float) -> float:
        """:meth:`elevation` of one point with plain floats (the simulator's per-step query).

        Parameters
        ----------
        x, y : float
            Easting and northing (m).

        Returns
        -------
        float
            Seabed elevation (m, positive up).
        """
        return elevation_kernel(*self._kernel[:5], x, y)

    def elevation_bounds(self, x: ArrayLike, y: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """:meth:`elevation` in numpy, without the compiled kernel, and how far from it it can be.

        The kernel may fuse multiplications and additions and multiply by a reciprocal (its fast-math
        flags), so its bits differ from numpy's by a few roundings of the terms
        ``a + b u + c v + e u v``; the bound is 64 roundings of their magnitudes (the largest of this cell's and
        its neighbours': on a grid line the kernel may take the next cell), times the grid coordinates' size (which
        the cell fractions ``u``, ``v`` inherit).  ``validate`` decides a point
        well above the seabed with this alone and never loads a compiled kernel (issue 56).

        Parameters
        ----------
        x, y : array_like
            Easting and northing (m), finite; broadcast together.

        Returns
        -------
        zb : numpy.ndarray
            Seabed elevation (m), within ``err`` of :meth:`elevation`.
        err : numpy.ndarray
            The bound (m).
        """
        fx = np.abs((np.asarray(x, dtype=float) - self.x[0]) / self.dx)
        fy = np.abs((np.asarray(y, dtype=float) - self.y[0]) / self.dy)
        i, j, u, v = self._locate(x, y)
        a, b, c, e = np.moveaxis(self._coef[j, i], -1, 0)
        zb: FloatArray = a + b * u + c * v + e * u * v
        # on a grid line the kernel's cell fraction (a reciprocal's rounding off numpy's) may fall in the
        # neighbouring cell: its coefficients (a cliff beside a flat cell) count as well as this cell's
        ny, nx = self._coef.shape[:2]
        size = np.zeros(np.shape(zb))
        for dj in (-1, 0, 1):
            for di in (-1, 0, 1):
                near = self._coef[np.clip(j + dj, 0, ny - 1), np.clip(i + di, 0, nx - 1)]
                size = np.maximum(size, np.abs(near).sum(axis=-1))
        err: FloatArray = 64.0 * np.finfo(float).eps * size * (2.0 + fx + fy)
        return zb, err

    def gradient(self, x: ArrayLike, y: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Slope of the bilinear surface (zero across a clamped edge).

        Parameters
        ----------
        x, y : array_like
            Easting and northing (m); broadcast together.

        Returns
        -------
        gx, gy : numpy.ndarray
            ``dzb/dx`` and ``dzb/dy`` (m/m).
        """
        fx = (np.asarray(x, dtype=float) - self.x[0]) / self.dx
        fy = (np.asarray(y, dtype=float) - self.y[0]) / self.dy
        i, j, u, v = self._locate(x, y)
        _, b, c, e = np.moveaxis(self._coef[j, i], -1, 0)
        inside_x = (fx >= 0) & (fx <= self.x.size - 1)
        inside_y = (fy >= 0) & (fy <= self.y.size - 1)
        gx = np.where(inside_x, (b + e * v) / self.dx, 0.0)
        gy = np.where(inside_y, (c + e * u) / self.dy, 0.0)
        return gx, gy

    def altitude(self, points: ArrayLike) -> FloatArray:
        """Height of points above the seabed.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            Altitude ``z - zb`` ``(...)`` (m, negative below the seabed).
        """
        p = np.asarray(points, dtype=float)
        altitude: FloatArray = p[..., 2] - self.elevation(p[..., 0], p[..., 1])
        return altitude

    # ------------------------------------------------------------------ exact segment test
    @property
    def max_slope(self) -> float:
        """Largest slope |∇zb| of the bilinear surface (its Lipschitz constant)."""
        return self._lipschitz

    def altitude_lower_bound(self, ga: FloatArray, gb: FloatArray, dz: FloatArray, lh: FloatArray) -> FloatArray:
        """Provable lower bound of the minimum altitude along segments.

        ``min(g_a, g_b, (g_a + g_b - |Δz| - G L_h) / 2)``, G the steepest slope: the seabed
        cannot rise faster.

        Parameters
        ----------
        ga, gb : numpy.ndarray
            Altitudes of the segments' end points (m).
        dz : numpy.ndarray
            Rise of each segment (m).
        lh : numpy.ndarray
            Horizontal length of each segment (m).

        Returns
        -------
        numpy.ndarray
            Lower bound of the minimum altitude (m), broadcast shape of the inputs.
        """
        bound = 0.5 * (ga + gb - np.abs(dz) - self._lipschitz * lh)
        lower: FloatArray = np.minimum(bound, np.minimum(ga, gb))
        return lower

    def segment_min_altitude(self, segments: ArrayLike, threshold: float = np.inf,
                             end_altitudes: tuple[ArrayLike, ArrayLike] | None = None) -> FloatArray:
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
            Start and end points (m).
        threshold : float
            Altitude below which the result must be exact (m).
        end_altitudes : tuple of array_like, optional
            The altitudes ``(g_a, g_b)`` of the end points (m) when the caller already has them.

        Returns
        -------
        ndarray, shape ``(...)``
            Minimum altitude above the bilinear seabed over the whole segment (m).

        Raises
        ------
        ValueError
            If ``segments`` is not of shape ``(..., 2, 3)``.
        """
        seg = np.asarray(segments, dtype=float)
        if seg.shape[-2:] != (2, 3):
            raise ValueError(f"segments must have shape (..., 2, 3), got {seg.shape}")
        return self.min_altitude_between(seg[..., 0, :], seg[..., 1, :], threshold, end_altitudes)

    def min_altitude_between(self, a: ArrayLike, b: ArrayLike, threshold: float = np.inf,
                             end_altitudes: tuple[ArrayLike, ArrayLike] | None = None) -> FloatArray:
        """:meth:`segment_min_altitude` of the segments ``a -> b`` given as two arrays.

        Parameters
        ----------
        a, b : array_like
            Segment starts and ends ``(..., 3)`` (m); broadcast together.
        threshold : float
            Altitude below which the result must be exact (m).
        end_altitudes : tuple of array_like, optional
            The altitudes ``(g_a, g_b)`` of the end points (m) when the caller already has them.

        Returns
        -------
        numpy.ndarray
            Minimum altitude over each segment ``(...)`` (m).
        """
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        if a.shape != b.shape:
            a, b = np.broadcast_arrays(a, b)
        lead = a.shape[:-1]
        a = np.ascontiguousarray(a.reshape(-1, 3))
        b = np.ascontiguousarray(b.reshape(-1, 3))
        out = np.empty(a.shape[0])
        if end_altitudes is None:
            ga = gb = out  # not read: the kernel computes the end altitudes itself
            known = False
        else:
            # writable C arrays, as ``out`` above: one compiled kernel
            ga, gb = (np.require(np.broadcast_to(np.asarray(g, dtype=float), lead).reshape(-1), requirements=("C", "W"))
                      for g in end_altitudes)
            known = True
        _min_altitudes(*self.kernel_data, a, b, ga, gb, known, float(threshold), out)
        return out.reshape(lead)

    def segments_below(self, segments: ArrayLike, altitude: float = 0.0) -> BoolArray:
        """Where a segment passes below ``zb + altitude`` anywhere (exact).

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).
        altitude : float, default 0.0
            Required height above the seabed (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True for segments that dip below.
        """
        below: BoolArray = self.segment_min_altitude(segments, threshold=altitude) < altitude
        return below

    # ------------------------------------------------------------------ document 004 variant
    def segments_below_stepping(self, segments: ArrayLike, altitude: float = 0.0,
                                step: float | None = None) -> BoolArray:
        """Document 004's collision test: probe every ``step`` metres along the dominant axis.

        The probe count of a segment is ``ceil(span / step)`` where ``span`` is its
        largest coordinate extent; each probe is compared with the bilinear seabed.
        Features thinner than ``step`` can be missed.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).
        altitude : float, default 0.0
            Required height above the seabed (m).
        step : float, optional
            Probe spacing (m); defaults to the smaller cell size.

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True where a probe is below ``zb + altitude``.

        Raises
        ------
        ValueError
            If ``step`` is not positive.
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
        hits: BoolArray = np.logical_or.reduceat(below, starts).reshape(lead)
        return hits
