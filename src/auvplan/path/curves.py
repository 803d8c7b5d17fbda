"""Paths: clamped cubic B-splines over control points, and polylines.

Document 002 smooths its control points with the cubic *uniform* B-spline
(eq. 6, whose printed cubes are a typo; corrected in docs/methods.md §2)::

    B0 = (1-u)³/6,  B1 = (3u³ - 6u² + 4)/6,  B2 = (-3u³ + 3u² + 3u + 1)/6,  B3 = u³/6

That curve does not pass through its end control points, so auvplan uses
clamped (open-uniform) knots: the interior spans are the uniform segments above
and the curve starts at the start and ends at the goal.  Because the knots are
fixed for a given number of control points, sampling a whole population is one
matrix product with the basis matrix ``(S, K)`` (:mod:`.deboor` builds it: ``scipy.interpolate.BSpline``'s
values, bit for bit): ``(P, K, 3) -> (P, S, 3)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from .._types import ArrayLike, FloatArray, IntArray
from ..geometry import as_points
from ..runtime.jit import jit_enabled, kernel
from . import deboor

if TYPE_CHECKING:
    from scipy.interpolate import BSpline

__all__ = [
    "uniform_cubic_basis",
    "clamped_knots",
    "basis_matrix",
    "BSplinePath",
    "sample_population",
    "polyline_length",
    "arc_length",
    "resample_polyline",
    "densify",
]


def uniform_cubic_basis(u: ArrayLike) -> FloatArray:
    """Document 002 eq. 6 (corrected): the four uniform cubic basis functions.

    Parameters
    ----------
    u : array_like
        Local parameter within a span, in ``[0, 1]`` (any shape).

    Returns
    -------
    numpy.ndarray
        ``B0 … B3`` at ``u``, shape ``(..., 4)``; they sum to 1.
    """
    u = np.asarray(u, dtype=np.float64)
    return np.stack(
        [(1 - u) ** 3 / 6, (3 * u**3 - 6 * u**2 + 4) / 6, (-3 * u**3 + 3 * u**2 + 3 * u + 1) / 6, u**3 / 6], axis=-1
    )


def clamped_knots(n_control: int, degree: int = 3) -> FloatArray:
    """Open-uniform knot vector on [0, 1] for ``n_control`` control points.

    Parameters
    ----------
    n_control : int
        Number of control points (at least ``degree + 1``).
    degree : int, default 3
        Spline degree.

    Returns
    -------
    numpy.ndarray
        Knots ``(n_control + degree + 1,)``: ``degree + 1`` zeros, uniform interior knots, ``degree + 1`` ones.

    Raises
    ------
    ValueError
        If there are fewer than ``degree + 1`` control points.
    """
    if n_control < degree + 1:
        raise ValueError(f"need at least {degree + 1} control points for degree {degree}, got {n_control}")
    inner = np.linspace(0.0, 1.0, n_control - degree + 1)
    knots: FloatArray = np.r_[np.zeros(degree), inner, np.ones(degree)]
    return knots


@lru_cache(maxsize=64)
def _basis(n_control: int, n_samples: int, order: int) -> FloatArray:
    # scipy.interpolate.BSpline(knots, eye, 3).derivative(order)(u), bit for bit, without importing
    # scipy.interpolate (~0.2 s of a command's start, #56): see .deboor
    m: FloatArray = np.ascontiguousarray(deboor.basis(clamped_knots(n_control), n_control,
                                                      np.linspace(0.0, 1.0, n_samples), order))
    m.setflags(write=False)
    return m


def basis_matrix(n_control: int, n_samples: int, order: int = 0) -> FloatArray:
    """Basis matrix ``(S, K)`` (or of its ``order``-th derivative) at ``S`` uniform parameters in [0, 1].

    Parameters
    ----------
    n_control : int
        Number of control points ``K``.
    n_samples : int
        Number of uniform parameter values ``S`` (ends included).
    order : int, default 0
        Derivative order with respect to the parameter (0 = positions).

    Returns
    -------
    numpy.ndarray
        Read-only ``(S, K)`` matrix (cached): ``basis @ control`` samples the curve.
    """
    return _basis(int(n_control), int(n_samples), int(order))


def sample_population(control: ArrayLike, n_samples: int, order: int = 0) -> FloatArray:
    """Sample clamped cubic B-splines of many paths at once: ``(P, K, 3) -> (P, S, 3)``.

    Parameters
    ----------
    control : array_like
        Control points ``(..., K, 3)`` (m), any number of leading axes.
    n_samples : int
        Number of samples ``S`` per path, at uniform parameter values in [0, 1].
    order : int, default 0
        Derivative order with respect to the parameter (0 = positions in m).

    Returns
    -------
    numpy.ndarray
        Samples ``(..., S, 3)``.
    """
    c = np.asarray(control, dtype=float)
    lead, k = c.shape[:-2], c.shape[-2]
    basis = basis_matrix(k, n_samples, order)
    if jit_enabled():  # else one BLAS matrix product (a compiled loop run as Python would be slow)
        # one compiled pass over the population, no BLAS call (whose threads cost more CPU than the sums)
        flat3 = np.ascontiguousarray(c.reshape((-1, k, 3)))
        samples: FloatArray = np.empty((flat3.shape[0], n_samples, 3))
        lo, hi = _support(k, int(n_samples), int(order))
        _sample_kernel(flat3, basis, lo, hi, samples)
        return samples.reshape(lead + (n_samples, 3))
    # one matrix product for the whole population: (P·3, K) @ (K, S), the same sums as (S, K) @ (K, P·3)
    flat = c.reshape((-1, k, 3)).transpose(0, 2, 1).reshape(-1, k)
    out = (flat @ basis.T).reshape(-1, 3, n_samples)
    samples = np.ascontiguousarray(out.transpose(0, 2, 1)).reshape(lead + (n_samples, 3))
    return samples


@lru_cache(maxsize=64)
def _support(n_control: int, n_samples: int, order: int) -> tuple[IntArray, IntArray]:
    """First and one-past-last column of the non-zero entries of each row of :func:`basis_matrix`
    (a cubic B-spline has at most four non-zero basis functions at a parameter)."""
    nz = basis_matrix(n_control, n_samples, order) != 0.0
    any_nz = nz.any(axis=1)
    lo = np.where(any_nz, nz.argmax(axis=1), 0).astype(np.intp)
    hi = np.where(any_nz, n_control - nz[:, ::-1].argmax(axis=1), 0).astype(np.intp)
    lo.setflags(write=False)
    hi.setflags(write=False)
    return lo, hi


@kernel
def _sample_kernel(control: FloatArray, basis: FloatArray, lo: IntArray, hi: IntArray, out: FloatArray) -> None:
    """``out[i, s] = basis[s] @ control[i]`` for ``control (N, K, 3)``, summed over the non-zero columns
    ``lo[s] <= k < hi[s]`` of each row in increasing ``k`` (the zero terms add nothing to a finite sum)."""
    for i in range(control.shape[0]):
        for s in range(basis.shape[0]):
            x = y = z = 0.0
            for k in range(lo[s], hi[s]):
                b = basis[s, k]
                x += b * control[i, k, 0]
                y += b * control[i, k, 1]
                z += b * control[i, k, 2]
            out[i, s, 0] = x
            out[i, s, 1] = y
            out[i, s, 2] = z


def polyline_length(points: ArrayLike) -> FloatArray:
    """Length of polylines.

    Parameters
    ----------
    points : array_like
        Vertices ``(..., N, 3)`` (m).

    Returns
    -------
    numpy.ndarray
        Lengths ``(...)`` (m); a 0-d array for one polyline.
    """
    p = as_points(points)
    length: FloatArray = np.linalg.norm(np.diff(p, axis=-2), axis=-1).sum(axis=-1)
    return length


def arc_length(points: ArrayLike) -> FloatArray:
    """Arc length at each vertex of a polyline: 0 at the first, the polyline's length at the last.

    Parameters
    ----------
    points : array_like
        Vertices ``(N, D)`` (m).

    Returns
    -------
    numpy.ndarray
        ``(N,)`` distances along the polyline (m).
    """
    p = np.asarray(points, dtype=float)
    s: FloatArray = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))]
    return s


def resample_polyline(points: ArrayLike, spacing: float) -> FloatArray:
    """Points every ``spacing`` metres of arc length along a polyline (ends kept).

    Parameters
    ----------
    points : array_like
        Vertices ``(N, 3)`` (m).
    spacing : float
        Largest arc-length step between output points (m); the steps are equal.

    Returns
    -------
    numpy.ndarray
        Points ``(M, 3)`` (m), ``M >= 2``, the first and last vertex included.
    """
    p = as_points(points)
    s = arc_length(p)
    n = max(int(np.ceil(s[-1] / spacing)), 1) + 1
    q = np.linspace(0.0, s[-1], n)
    return np.column_stack([np.interp(q, s, p[:, k]) for k in range(3)])


@dataclass(frozen=True, eq=False)
class BSplinePath:
    """Clamped cubic B-spline through its first and last control points.

    ``path(u, order)`` returns positions (order 0) or derivatives with respect
    to the parameter ``u ∈ [0, 1]`` with shape ``(N, 3)`` (after toppra's
    interpolator interface).

    Parameters
    ----------
    control : array_like
        Control points ``(K, 3)`` (m), ``K >= 4``; stored as a float array.
    """

    control: FloatArray
    _spline: BSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        c = as_points(self.control, "control").reshape(-1, 3)
        object.__setattr__(self, "control", c)
        from scipy.interpolate import BSpline

        object.__setattr__(self, "_spline", BSpline(clamped_knots(c.shape[0]), c, 3))

    def __call__(self, u: ArrayLike, order: int = 0) -> FloatArray:
        """Positions or parameter derivatives at ``u``.

        Parameters
        ----------
        u : array_like
            Curve parameter, clipped to [0, 1] (any shape).
        order : int, default 0
            Derivative order with respect to ``u`` (0 = positions in m).

        Returns
        -------
        numpy.ndarray
            ``(..., 3)`` for ``u`` of shape ``(...)``.
        """
        u = np.clip(np.asarray(u, dtype=np.float64), 0.0, 1.0)
        s = self._spline if order == 0 else self._spline.derivative(order)
        out: FloatArray = s(u)
        return out

    def sample(self, n: int) -> FloatArray:
        """Points at uniform parameter values.

        Parameters
        ----------
        n : int
            Number of points (ends included).

        Returns
        -------
        numpy.ndarray
            Positions ``(n, 3)`` (m).
        """
        return self(np.linspace(0.0, 1.0, n))

    def length(self, n: int = 2000) -> float:
        """Arc length by dense polyline (converges as n²).

        Parameters
        ----------
        n : int, default 2000
            Number of polyline vertices.

        Returns
        -------
        float
            Length (m).
        """
        return float(polyline_length(self.sample(n)))

    def tangent(self, u: ArrayLike) -> FloatArray:
        """Unit tangents.

        Parameters
        ----------
        u : array_like
            Curve parameter in [0, 1], shape ``(N,)``.

        Returns
        -------
        numpy.ndarray
            Unit tangent vectors ``(N, 3)``.
        """
        d = self(u, 1)
        unit: FloatArray = d / np.linalg.norm(d, axis=-1, keepdims=True)
        return unit

    def curvature(self, u: ArrayLike) -> FloatArray:
        """Curvature ``|r' × r''| / |r'|³``.

        Parameters
        ----------
        u : array_like
            Curve parameter in [0, 1], shape ``(N,)``.

        Returns
        -------
        numpy.ndarray
            Curvature ``(N,)`` (1/m).
        """
        d1, d2 = self(u, 1), self(u, 2)
        kappa: FloatArray = np.linalg.norm(np.cross(d1, d2), axis=-1) / np.linalg.norm(d1, axis=-1) ** 3
        return kappa

    def pitch(self, u: ArrayLike) -> FloatArray:
        """Path angle above the horizontal.

        Parameters
        ----------
        u : array_like
            Curve parameter in [0, 1], shape ``(N,)``.

        Returns
        -------
        numpy.ndarray
            Path angle ``(N,)`` (rad, positive climbing).
        """
        d = self(u, 1)
        angle: FloatArray = np.arctan2(d[..., 2], np.hypot(d[..., 0], d[..., 1]))
        return angle


def densify(points: ArrayLike, spacing: float) -> FloatArray:
    """The polyline with extra points so that no segment exceeds ``spacing`` (every vertex kept).

    Parameters
    ----------
    points : array_like
        Vertices ``(N, 3)`` (m).
    spacing : float
        Longest segment allowed (m).

    Returns
    -------
    numpy.ndarray
        Vertices ``(M, 3)``, ``M >= N`` (m).
    """
    p = np.asarray(points, dtype=float)
    if p.shape[0] < 2:
        return p.copy()
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    n = np.maximum(np.ceil(seg / spacing).astype(int), 1)
    i = np.repeat(np.arange(len(n)), n)
    first = np.cumsum(n) - n  # index of each segment's first output point
    t = (np.arange(i.size) - first[i]) / n[i]  # j / k for j < k, as k-long aranges / k
    out = p[i] + t[:, None] * (p[i + 1] - p[i])
    return np.vstack([out, p[-1]])
