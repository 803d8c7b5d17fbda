"""A seabed model that is never deeper than its data (the conservative resampling).

The data (soundings on a rectilinear grid) describe a surface: their bilinear interpolant
``zd``.  A :class:`~auvplan.world.terrain.Terrain` is the bilinear interpolant ``zm`` of its
own regular grid, usually at another cell size and rotated/stretched against the data's grid
by the projection.  :func:`conservative_nodes` chooses the model's node values so that
``zm >= zd`` everywhere on the model's extent, and as little above it as this rule allows:

* each model node starts at the data surface (``z0 = zd(node)``: the linear, non-overshooting
  interpolant);
* per model cell, the exact extremes of ``D = zd - bilinear(z0)`` and of ``zd`` are found
  (:func:`cell_extremes`); the cell is made safe either by raising its four corners by
  ``max D`` (a uniform lift of its bilinear surface: the rule of a cell finer than the data)
  or by setting them to ``max zd`` (the upper envelope of the data over the cell's footprint:
  the rule of a cell coarser than the data), whichever raises the corners less;
* a node takes the largest value any of its (up to four) cells asks of it.  Raising a corner
  never lowers a bilinear surface, so every cell stays safe.

**Why the extremes are exact.**  The cell is mapped into the data's fractional index space
(affinely: the projection is smooth over one cell; the twist is below a millimetre for
kilometre cells).  The data lines split it into pieces; on each piece ``zd`` and the model are
both bilinear in axes that are rotations and scalings of each other, so ``D`` is a quadratic
whose Hessian has zero trace: no strict interior maximum or minimum.  The extremes lie on the
pieces' edges — the cell's edges and the data lines — where ``D`` is a quadratic of the
segment parameter, fitted exactly from three values.  Every sounding inside the cell is an
end of such a segment (where two data lines cross), so the model is at or above every
sounding.

The same kernel, run on the final nodes, gives the largest height of the model above the data
(:attr:`SeabedFit.excess_max_m`), which is what the conservative rule costs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._types import FloatArray
from ..runtime.jit import kernel

__all__ = ["SeabedFit", "affine_margin", "cell_extremes", "conservative_nodes", "data_at", "fit_report",
           "window_max"]


@dataclass(frozen=True)
class SeabedFit:
    """How the model seabed sits against its data (m; positive: the model is shallower).

    Attributes
    ----------
    method : str
        The resampling method that made the model.
    excess_max_m : float
        Largest height of the model above the data's bilinear surface, anywhere on its extent.
    excess_mean_m : float
        Mean height of the model above the data at the model's nodes.
    deficit_max_m : float
        Largest depth of the model *below* the data anywhere (0 for ``conservative``, up to
        rounding; positive for methods that overshoot, e.g. ``cubic``).
    """

    method: str
    excess_max_m: float
    excess_mean_m: float
    deficit_max_m: float

    def describe(self) -> str:
        """One line for ``validate``, ``data inspect`` and the report.

        Returns
        -------
        str
            The figures, with what they mean.
        """
        below = ("never deeper than the data" if self.deficit_max_m <= 1e-6
                 else f"DEEPER than the data by up to {self.deficit_max_m:.1f} m")
        return (f"seabed model ({self.method}) {below}; shallower by up to {self.excess_max_m:.1f} m "
                f"(mean {self.excess_mean_m:.2f} m at its nodes)")


@kernel(inline="always")
def _data(z: FloatArray, r: float, c: float) -> float:
    """Bilinear value of the data at fractional index ``(r, c)`` (clamped to the grid)."""
    nr, nc = z.shape
    r = min(max(r, 0.0), nr - 1.0)
    c = min(max(c, 0.0), nc - 1.0)
    i = min(int(math.floor(r)), nr - 2)
    k = min(int(math.floor(c)), nc - 2)
    u, v = r - i, c - k
    val: float = ((1.0 - u) * ((1.0 - v) * z[i, k] + v * z[i, k + 1])
            + u * ((1.0 - v) * z[i + 1, k] + v * z[i + 1, k + 1]))
    return val


@kernel
def data_at(z: FloatArray, fr: FloatArray, fc: FloatArray) -> FloatArray:
    """The data's bilinear surface at fractional indices (any shape, flattened in C order).

    Parameters
    ----------
    z : numpy.ndarray
        Data ``(nrow, ncol)``.
    fr, fc : numpy.ndarray
        Fractional row and column indices, same shape.

    Returns
    -------
    numpy.ndarray
        The values, the shape of ``fr``.
    """
    out = np.empty(fr.shape)
    a, b, o = fr.ravel(), fc.ravel(), out.reshape(-1)
    for n in range(a.size):
        o[n] = _data(z, a[n], b[n])
    return out


@kernel(inline="always")
def _quad_extremes(d0: float, dm: float, d1: float) -> tuple[float, float]:
    """Max and min on ``[0, 1]`` of the quadratic through ``(0, d0), (1/2, dm), (1, d1)``."""
    hi, lo = max(d0, d1), min(d0, d1)
    a = 2.0 * d0 - 4.0 * dm + 2.0 * d1
    b = -3.0 * d0 + 4.0 * dm - d1
    if a != 0.0:
        u = -b / (2.0 * a)
        if 0.0 < u < 1.0:
            val = d0 + b * u + a * u * u
            hi, lo = max(hi, val), min(lo, val)
    return hi, lo


@kernel(inline="always")
def _sorted_into(us: FloatArray, n: int) -> None:
    """Insertion sort of ``us[:n]`` in place (a handful of values per segment)."""
    for a in range(1, n):
        key = us[a]
        b = a - 1
        while b >= 0 and us[b] > key:
            us[b + 1] = us[b]
            b -= 1
        us[b + 1] = key


@kernel
def _segment(z: FloatArray, o: FloatArray, ea: FloatArray, eb: FloatArray, zc: FloatArray,
             s0: float, t0: float, s1: float, t1: float, acc: FloatArray, us: FloatArray) -> None:
    """Extremes of ``zd`` and ``D`` on the cell-parameter segment ``(s0, t0) → (s1, t1)``, folded into
    ``acc = [max zd, max D, min D]``; ``us`` is scratch space for the segment's breakpoints."""
    r0 = o[0] + s0 * ea[0] + t0 * eb[0]
    c0 = o[1] + s0 * ea[1] + t0 * eb[1]
    r1 = o[0] + s1 * ea[0] + t1 * eb[0]
    c1 = o[1] + s1 * ea[1] + t1 * eb[1]
    us[0], us[1] = 0.0, 1.0
    n = 2
    if r1 != r0:
        for k in range(int(math.ceil(min(r0, r1))), int(math.floor(max(r0, r1))) + 1):
            us[n] = min(max((k - r0) / (r1 - r0), 0.0), 1.0)
            n += 1
    if c1 != c0:
        for k in range(int(math.ceil(min(c0, c1))), int(math.floor(max(c0, c1))) + 1):
            us[n] = min(max((k - c0) / (c1 - c0), 0.0), 1.0)
            n += 1
    _sorted_into(us, n)
    for p in range(n - 1):
        ua, ub = us[p], us[p + 1]
        if ub - ua <= 1e-12:
            continue
        z_0 = z_m = z_1 = d_0 = d_m = d_1 = 0.0
        for q in range(3):
            u = ua + 0.5 * q * (ub - ua)
            s, t = s0 + u * (s1 - s0), t0 + u * (t1 - t0)
            zd = _data(z, o[0] + s * ea[0] + t * eb[0], o[1] + s * ea[1] + t * eb[1])
            zm = ((1.0 - t) * ((1.0 - s) * zc[0] + s * zc[1]) + t * ((1.0 - s) * zc[2] + s * zc[3]))
            if q == 0:
                z_0, d_0 = zd, zd - zm
            elif q == 1:
                z_m, d_m = zd, zd - zm
            else:
                z_1, d_1 = zd, zd - zm
        hz, _ = _quad_extremes(z_0, z_m, z_1)
        hd, ld = _quad_extremes(d_0, d_m, d_1)
        acc[0] = max(acc[0], hz)
        acc[1] = max(acc[1], hd)
        acc[2] = min(acc[2], ld)


@kernel
def _line_in_square(o: float, a: float, b: float, k: float) -> tuple[bool, float, float, float, float]:
    """The segment of ``{(s, t) in [0,1]^2 : o + a s + b t = k}``: ``(found, s0, t0, s1, t1)``."""
    pts = np.empty((4, 2))
    n = 0
    eps = 1e-12
    if b != 0.0:
        for s in (0.0, 1.0):
            t = (k - o - a * s) / b
            if -eps <= t <= 1.0 + eps:
                pts[n, 0], pts[n, 1] = s, min(max(t, 0.0), 1.0)
                n += 1
    if a != 0.0:
        for t in (0.0, 1.0):
            s = (k - o - b * t) / a
            if -eps <= s <= 1.0 + eps:
                pts[n, 0], pts[n, 1] = min(max(s, 0.0), 1.0), t
                n += 1
    if n < 2:
        return False, 0.0, 0.0, 0.0, 0.0
    best, i0, i1 = -1.0, 0, 1
    for i in range(n):
        for j in range(i + 1, n):
            d = (pts[i, 0] - pts[j, 0]) ** 2 + (pts[i, 1] - pts[j, 1]) ** 2
            if d > best:
                best, i0, i1 = d, i, j
    return True, pts[i0, 0], pts[i0, 1], pts[i1, 0], pts[i1, 1]


@kernel
def cell_extremes(z: FloatArray, fr: FloatArray, fc: FloatArray, zn: FloatArray) -> FloatArray:
    """Exact extremes, per model cell, of the data and of the data minus the model.

    Parameters
    ----------
    z : numpy.ndarray
        Data ``(nrow, ncol)``.
    fr, fc : numpy.ndarray
        Fractional data indices (row, column) of the model's nodes ``(ny, nx)``.
    zn : numpy.ndarray
        Model node values ``(ny, nx)``.

    Returns
    -------
    numpy.ndarray
        ``(ny - 1, nx - 1, 3)``: max of the data, max and min of ``data - model`` over each cell.
    """
    ny, nx = fr.shape
    out = np.empty((ny - 1, nx - 1, 3))
    o = np.empty(2)
    ea = np.empty(2)
    eb = np.empty(2)
    zc = np.empty(4)
    acc = np.empty(3)
    span = 0.0  # the most data lines a segment of a cell can cross, for the scratch space
    for f in (fr, fc):
        span += max(np.abs(f[1:, :] - f[:-1, :]).max(), np.abs(f[:, 1:] - f[:, :-1]).max()) * 2.0
    us = np.empty(int(span) + 8)
    for j in range(ny - 1):
        for i in range(nx - 1):
            for d, f in enumerate((fr, fc)):
                p00, p10, p01, p11 = f[j, i], f[j, i + 1], f[j + 1, i], f[j + 1, i + 1]
                ea[d] = 0.5 * (p10 - p00 + p11 - p01)
                eb[d] = 0.5 * (p01 - p00 + p11 - p10)
                o[d] = 0.25 * (p00 + p10 + p01 + p11) - 0.5 * ea[d] - 0.5 * eb[d]
            zc[0], zc[1], zc[2], zc[3] = zn[j, i], zn[j, i + 1], zn[j + 1, i], zn[j + 1, i + 1]
            acc[0], acc[1], acc[2] = -np.inf, -np.inf, np.inf
            _segment(z, o, ea, eb, zc, 0.0, 0.0, 1.0, 0.0, acc, us)
            _segment(z, o, ea, eb, zc, 1.0, 0.0, 1.0, 1.0, acc, us)
            _segment(z, o, ea, eb, zc, 1.0, 1.0, 0.0, 1.0, acc, us)
            _segment(z, o, ea, eb, zc, 0.0, 1.0, 0.0, 0.0, acc, us)
            for d in range(2):  # the data lines of rows (d = 0) and of columns (d = 1) across the cell
                c0 = o[d] + min(0.0, ea[d]) + min(0.0, eb[d])
                c1 = o[d] + max(0.0, ea[d]) + max(0.0, eb[d])
                for k in range(int(math.ceil(c0)), int(math.floor(c1)) + 1):
                    found, s0, t0, s1, t1 = _line_in_square(o[d], ea[d], eb[d], float(k))
                    if found:
                        _segment(z, o, ea, eb, zc, s0, t0, s1, t1, acc, us)
            out[j, i, 0], out[j, i, 1], out[j, i, 2] = acc[0], acc[1], acc[2]
    return out


def conservative_nodes(z: FloatArray, fr: FloatArray, fc: FloatArray, margin: FloatArray | float = 0.0) -> FloatArray:
    """Model node values whose bilinear surface is at or above the data's everywhere.

    Parameters
    ----------
    z : numpy.ndarray
        Data ``(nrow, ncol)`` (finite).
    fr, fc : numpy.ndarray
        Fractional data indices (row, column) of the model's nodes ``(ny, nx)``, at least 2 x 2.
    margin : float or numpy.ndarray, optional
        Extra lift per cell ``(ny - 1, nx - 1)`` (m) covering how far the true map of a cell into the
        data's index space departs from the affine one the extremes are exact for
        (:func:`affine_margin`); 0 for grids that are affine images of each other.

    Returns
    -------
    numpy.ndarray
        ``(ny, nx)`` node values.
    """
    z = np.ascontiguousarray(z, dtype=float)
    fr = np.ascontiguousarray(fr, dtype=float)
    fc = np.ascontiguousarray(fc, dtype=float)
    z0 = data_at(z, fr, fc)
    ext = cell_extremes(z, fr, fc, z0)
    pad = np.broadcast_to(np.asarray(margin, dtype=float), ext.shape[:2])
    lift = np.maximum(ext[..., 1], 0.0) + pad  # a finer cell: lift its surface uniformly
    top = ext[..., 0] + pad  # a coarser one: all corners at the data's maximum over it
    del ext
    corners = ((slice(None, -1), slice(None, -1)), (slice(None, -1), slice(1, None)),
               (slice(1, None), slice(None, -1)), (slice(1, None), slice(1, None)))
    envelope_raise = np.zeros_like(lift)
    for c in corners:
        envelope_raise += np.maximum(top - z0[c], 0.0)
    use_lift = 4.0 * lift <= envelope_raise
    del envelope_raise
    out: FloatArray = z0.copy()
    for c in corners:
        np.maximum(out[c], np.where(use_lift, z0[c] + lift, np.maximum(top, z0[c])), out=out[c])
    return out


def affine_margin(z: FloatArray, fr: FloatArray, fc: FloatArray, corners_r: FloatArray, corners_c: FloatArray,
                  true_r: FloatArray, true_c: FloatArray) -> FloatArray:
    """Per model cell, a bound on the data's change between the true and the affine map of the cell.

    Parameters
    ----------
    z : numpy.ndarray
        Data ``(nrow, ncol)``.
    fr, fc : numpy.ndarray
        ``(ny, nx)`` fractional data indices of the model's nodes.
    corners_r, corners_c : numpy.ndarray
        ``(K, 2, 2)`` fractional data indices of the corners of a sample of K cells (``[t, s]``).
    true_r, true_c : numpy.ndarray
        ``(K, 3, 3)`` the same at the sampled cells' nine points ``(s, t) in {0, 1/2, 1}^2``.

    Returns
    -------
    numpy.ndarray
        ``(ny - 1, nx - 1)`` margin (m): twice the largest departure (over the sample: it varies smoothly
        over the model's extent) of the true index position from the affine one, times the data's steepest
        change per index along each axis around the cell.
    """
    z = np.asarray(z, dtype=float)
    out = np.zeros((fr.shape[0] - 1, fr.shape[1] - 1))
    reach = int(np.ceil(max(np.abs(np.diff(fr, axis=0)).max(), np.abs(np.diff(fr, axis=1)).max(),
                            np.abs(np.diff(fc, axis=0)).max(), np.abs(np.diff(fc, axis=1)).max()))) + 2
    jr = np.clip(np.floor(fr[:-1, :-1]).astype(int), 0, z.shape[0] - 2)
    jc = np.clip(np.floor(fc[:-1, :-1]).astype(int), 0, z.shape[1] - 2)
    for axis, f, f2 in ((0, corners_r, true_r), (1, corners_c, true_c)):
        p00, p10, p01, p11 = f[:, 0, 0], f[:, 0, 1], f[:, 1, 0], f[:, 1, 1]
        ea = 0.5 * (p10 - p00 + p11 - p01)
        eb = 0.5 * (p01 - p00 + p11 - p10)
        o = 0.25 * (p00 + p10 + p01 + p11) - 0.5 * ea - 0.5 * eb
        dev = 0.0
        for b in range(3):
            for a in range(3):
                dev = max(dev, float(np.abs(f2[:, b, a] - (o + 0.5 * a * ea + 0.5 * b * eb)).max()))
        step = np.abs(np.diff(z, axis=axis))
        step = np.pad(step, ((0, 1), (0, 0)) if axis == 0 else ((0, 0), (0, 1)), mode="edge")
        local = window_max(step, reach)
        out += 2.0 * dev * local[jr, jc]
    return out


def _run_max(a: FloatArray, width: int, axis: int) -> FloatArray:
    """``out[i] = max(a[i : i + width])`` along ``axis`` (``a.shape[axis] - width + 1`` values): maxima over
    runs of doubling length (a sparse table), then two overlapping runs; O(n log width)."""
    a = np.moveaxis(a, axis, 0)
    run, span = a, 1
    while 2 * span <= width:
        run = np.maximum(run[:-span], run[span:])
        span *= 2
    n = a.shape[0] - width + 1
    out: FloatArray = np.moveaxis(np.maximum(run[:n], run[width - span:width - span + n]), 0, axis)
    return out


def window_max(a: FloatArray, reach: int) -> FloatArray:
    """Largest value of the square ``(2 reach + 1)²`` window about each element of a 2-D array, the edges
    continued with their own values: ``scipy.ndimage.maximum_filter(a, size=2 * reach + 1,
    mode="nearest")`` without importing ``scipy.ndimage`` (~0.1 s of a command's start, issue 56).  A
    maximum is exact, so the two agree bit for bit.

    Parameters
    ----------
    a : numpy.ndarray
        2-D array.
    reach : int
        Half-width of the window (≥ 0).

    Returns
    -------
    numpy.ndarray
        The window maxima, the shape of ``a``.
    """
    padded = np.pad(np.asarray(a), reach, mode="edge")
    return _run_max(_run_max(padded, 2 * reach + 1, 0), 2 * reach + 1, 1)


def fit_report(z: FloatArray, fr: FloatArray, fc: FloatArray, zn: FloatArray, method: str) -> SeabedFit:
    """Measure how the model ``zn`` sits against the data (exact extremes, node mean).

    Parameters
    ----------
    z : numpy.ndarray
        Data ``(nrow, ncol)``.
    fr, fc : numpy.ndarray
        Fractional data indices of the model's nodes ``(ny, nx)``.
    zn : numpy.ndarray
        Model node values ``(ny, nx)``.
    method : str
        The method that made ``zn``.

    Returns
    -------
    SeabedFit
        The figures.
    """
    z = np.ascontiguousarray(z, dtype=float)
    fr = np.ascontiguousarray(fr, dtype=float)
    fc = np.ascontiguousarray(fc, dtype=float)
    zn = np.ascontiguousarray(zn, dtype=float)
    ext = cell_extremes(z, fr, fc, zn)
    z0 = data_at(z, fr, fc)
    return SeabedFit(method, float(max(-ext[..., 2].min(), 0.0)), float(np.mean(zn - z0)),
                     float(max(ext[..., 1].max(), 0.0)))
