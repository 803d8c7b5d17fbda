"""Paths: clamped cubic B-splines over control points, and polylines.

Document 002 smooths its control points with the cubic *uniform* B-spline
(eq. 6, whose printed cubes are a typo; corrected in METHODS.md §2)::

    B0 = (1-u)³/6,  B1 = (3u³ - 6u² + 4)/6,  B2 = (-3u³ + 3u² + 3u + 1)/6,  B3 = u³/6

That curve does not pass through its end control points, so auvplan uses
clamped (open-uniform) knots: the interior spans are the uniform segments above
and the curve starts at the start and ends at the goal.  Because the knots are
fixed for a given number of control points, sampling a whole population is one
matrix product with the basis matrix ``(S, K)`` (``scipy.interpolate.BSpline``
builds it): ``(P, K, 3) -> (P, S, 3)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy.interpolate import BSpline

from .geometry import as_points

__all__ = [
    "uniform_cubic_basis",
    "clamped_knots",
    "basis_matrix",
    "BSplinePath",
    "sample_population",
    "polyline_length",
    "resample_polyline",
]


def uniform_cubic_basis(u) -> np.ndarray:
    """Document 002 eq. 6 (corrected): the four uniform cubic basis functions, shape ``(..., 4)``."""
    u = np.asarray(u, dtype=float)
    return np.stack(
        [(1 - u) ** 3 / 6, (3 * u**3 - 6 * u**2 + 4) / 6, (-3 * u**3 + 3 * u**2 + 3 * u + 1) / 6, u**3 / 6], axis=-1
    )


def clamped_knots(n_control: int, degree: int = 3) -> np.ndarray:
    """Open-uniform knot vector on [0, 1] for ``n_control`` control points."""
    if n_control < degree + 1:
        raise ValueError(f"need at least {degree + 1} control points for degree {degree}, got {n_control}")
    inner = np.linspace(0.0, 1.0, n_control - degree + 1)
    return np.r_[np.zeros(degree), inner, np.ones(degree)]


@lru_cache(maxsize=64)
def _basis(n_control: int, n_samples: int, order: int) -> np.ndarray:
    knots = clamped_knots(n_control)
    u = np.linspace(0.0, 1.0, n_samples)
    spline = BSpline(knots, np.eye(n_control), 3)
    if order:
        spline = spline.derivative(order)
    m = np.ascontiguousarray(spline(u))
    m.setflags(write=False)
    return m


def basis_matrix(n_control: int, n_samples: int, order: int = 0) -> np.ndarray:
    """Basis matrix ``(S, K)`` (or of its ``order``-th derivative) at ``S`` uniform parameters in [0, 1]."""
    return _basis(int(n_control), int(n_samples), int(order))


def sample_population(control: np.ndarray, n_samples: int, order: int = 0) -> np.ndarray:
    """Sample clamped cubic B-splines of many paths at once: ``(P, K, 3) -> (P, S, 3)``."""
    c = np.asarray(control, dtype=float)
    lead, k = c.shape[:-2], c.shape[-2]
    basis = basis_matrix(k, n_samples, order)
    # one matrix product for the whole population: (S, K) @ (K, P·3)
    flat = np.moveaxis(c.reshape((-1, k, 3)), 1, 0).reshape(k, -1)
    out = (basis @ flat).reshape(n_samples, -1, 3)
    return np.ascontiguousarray(np.moveaxis(out, 0, 1)).reshape(lead + (n_samples, 3))


def polyline_length(points) -> np.ndarray:
    """Length of polylines ``(..., N, 3)``."""
    p = as_points(points)
    return np.linalg.norm(np.diff(p, axis=-2), axis=-1).sum(axis=-1)


def resample_polyline(points, spacing: float) -> np.ndarray:
    """Points every ``spacing`` metres of arc length along a polyline ``(N, 3)`` (ends kept)."""
    p = as_points(points)
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))]
    n = max(int(np.ceil(s[-1] / spacing)), 1) + 1
    q = np.linspace(0.0, s[-1], n)
    return np.column_stack([np.interp(q, s, p[:, k]) for k in range(3)])


@dataclass(frozen=True, eq=False)
class BSplinePath:
    """Clamped cubic B-spline through its first and last control points.

    ``path(u, order)`` returns positions (order 0) or derivatives with respect
    to the parameter ``u ∈ [0, 1]`` with shape ``(N, 3)`` (after toppra's
    interpolator interface).
    """

    control: np.ndarray
    _spline: BSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        c = as_points(self.control, "control").reshape(-1, 3)
        object.__setattr__(self, "control", c)
        object.__setattr__(self, "_spline", BSpline(clamped_knots(c.shape[0]), c, 3))

    def __call__(self, u, order: int = 0) -> np.ndarray:
        u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
        s = self._spline if order == 0 else self._spline.derivative(order)
        return s(u)

    def sample(self, n: int) -> np.ndarray:
        """``n`` points at uniform parameter values ``(n, 3)``."""
        return self(np.linspace(0.0, 1.0, n))

    def length(self, n: int = 2000) -> float:
        """Arc length by dense polyline (converges as n²)."""
        return float(polyline_length(self.sample(n)))

    def tangent(self, u) -> np.ndarray:
        """Unit tangents ``(N, 3)``."""
        d = self(u, 1)
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def curvature(self, u) -> np.ndarray:
        """Curvature |r' × r''| / |r'|³ (1/m)."""
        d1, d2 = self(u, 1), self(u, 2)
        return np.linalg.norm(np.cross(d1, d2), axis=-1) / np.linalg.norm(d1, axis=-1) ** 3

    def pitch(self, u) -> np.ndarray:
        """Path angle above the horizontal (rad, positive climbing)."""
        d = self(u, 1)
        return np.arctan2(d[..., 2], np.hypot(d[..., 0], d[..., 1]))
