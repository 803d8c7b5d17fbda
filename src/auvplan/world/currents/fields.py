"""Ocean current fields with one vectorised interface ``velocity(points, t) -> (N, 3)`` (:class:`CurrentField`,
:mod:`.base`).

* :class:`UniformCurrent` — constant vector.
* :class:`LambOseenVortices` — a sum of viscous Lamb–Oseen vortices, document 002
  eqs. 1–2 (docs/methods.md §2).  The document's eq. 3, ``Γ/(πδ²) exp(-r²/δ²)``, is the
  vertical **vorticity** of the vortex (1/s), not a vertical velocity: it is
  offered as :meth:`LambOseenVortices.vorticity` and the vertical velocity is 0.
* :class:`GriddedCurrent` (:mod:`.gridded`) — u, v (and optionally w) on an (x, y, z[, t]) grid,
  interpolated linearly in space and time (a compiled loop; checked against
  ``scipy.interpolate.RegularGridInterpolator`` in the tests).
  Points outside the grid take the value at the nearest grid face (clamping); a
  world checks at build time that the grid covers its horizontal bounds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...geometry import as_points
from ...runtime.jit import kernel
from .base import CurrentField
from .gridded import GriddedCurrent

__all__ = ["CurrentField", "UniformCurrent", "LambOseenVortices", "GriddedCurrent"]


@dataclass(frozen=True)
class UniformCurrent(CurrentField):
    """Spatially uniform, steady current.

    Parameters
    ----------
    vector : tuple of float, default (0, 0, 0)
        ``(u, v, w)`` (m/s; east, north, up).
    """

    vector: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def velocity(self, points: ArrayLike, t: float = 0.0) -> FloatArray:
        """Current velocity at points and a time.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        t : float, default 0.0
            Time (s).

        Returns
        -------
        numpy.ndarray
            Velocities ``(..., 3)`` (m/s; east, north, up).
        """
        p = as_points(points)
        out = np.empty(p.shape)
        out[...] = self.vector  # broadcast into a fresh array (cheaper than broadcast_to + copy per step)
        return out

    @property
    def steady(self) -> bool:
        """True: the field does not change with time (:meth:`CurrentField.velocity_at` asks it once)."""
        return True

    @property
    def max_speed(self) -> float:
        """An upper bound of the horizontal current speed.

        Returns
        -------
        float
            Speed bound (m/s).
        """
        return float(np.hypot(self.vector[0], self.vector[1]))


@dataclass(frozen=True, eq=False)
class LambOseenVortices(CurrentField):
    """Sum of Lamb–Oseen vortices (document 002 eqs. 1–2).

    For one vortex at ``(x0, y0)`` with circulation ``Γ`` (m²/s, positive
    counter-clockwise) and core radius ``δ`` (m)::

        Vx = -Γ (y - y0) / (2π r²) (1 - exp(-r²/δ²))
        Vy = +Γ (x - x0) / (2π r²) (1 - exp(-r²/δ²))

    Near the centre the bracket over r² tends to 1/δ² (solid-body rotation,
    ``|V| ≈ Γ r / (2π δ²)``); that limit is evaluated without cancellation.

    Parameters
    ----------
    centers : array_like, shape (K, 2)
        Vortex centres (m).
    gamma : array_like, shape (K,)
        Circulations Γ (m²/s).
    delta : array_like, shape (K,)
        Core radii δ (m), positive.

    Raises
    ------
    ValueError
        If the three arrays disagree in length, a core radius is not positive or a value is not finite.
    """

    centers: FloatArray
    gamma: FloatArray
    delta: FloatArray
    _k: int = field(init=False, repr=False)

    def __post_init__(self) -> None:
        c = np.asarray(self.centers, dtype=float).reshape(-1, 2)
        g = np.asarray(self.gamma, dtype=float).reshape(-1)
        d = np.asarray(self.delta, dtype=float).reshape(-1)
        if not (c.shape[0] == g.size == d.size):
            raise ValueError("centers, gamma and delta must describe the same number of vortices")
        if np.any(d <= 0) or not np.all(np.isfinite(c)) or not np.all(np.isfinite(g)):
            raise ValueError("vortex core radii must be positive and all values finite")
        object.__setattr__(self, "centers", c)
        object.__setattr__(self, "gamma", g)
        object.__setattr__(self, "delta", d)
        object.__setattr__(self, "_k", g.size)

    def velocity(self, points: ArrayLike, t: float = 0.0) -> FloatArray:
        """Current velocity at points and a time.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        t : float, default 0.0
            Time (s).

        Returns
        -------
        numpy.ndarray
            Velocities ``(..., 3)`` (m/s; east, north, up).
        """
        p = as_points(points)
        flat = np.ascontiguousarray(p.reshape(-1, 3))
        out = np.zeros_like(flat)
        if self._k:
            q = np.empty((flat.shape[0], self._k))
            _vortex_q(flat, self.centers, self.delta, q)
            # numpy's exp is vectorised (in place: one temporary); the compiled loops do the rest
            e = np.negative(q)
            _vortex_sum(flat, self.centers, self.gamma, self.delta, q, np.exp(e, out=e), out)
        return out.reshape(p.shape)

    @property
    def steady(self) -> bool:
        """True: the field does not change with time (:meth:`CurrentField.velocity_at` asks it once)."""
        return True

    def vorticity(self, points: ArrayLike) -> FloatArray:
        """Vertical vorticity ω_z — the quantity of document 002's eq. 3.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ω_z ``(N,)`` (1/s) at the flattened points.
        """
        p = as_points(points).reshape(-1, 3)
        rx = p[:, None, 0] - self.centers[None, :, 0]
        ry = p[:, None, 1] - self.centers[None, :, 1]
        d2 = self.delta**2
        omega: FloatArray = (self.gamma / (np.pi * d2) * np.exp(-(rx * rx + ry * ry) / d2)).sum(axis=1)
        return omega

    @property
    def max_speed(self) -> float:
        """An upper bound of the horizontal current speed.

        Returns
        -------
        float
            Speed bound (m/s).
        """
        # one vortex peaks at r = 1.1209 δ with |V| = 0.63817 Γ / (2π δ); the sum is bounded by the sum
        return float(np.sum(0.63817 * np.abs(self.gamma) / (2.0 * np.pi * self.delta)))


@kernel
def _vortex_q(points: FloatArray, centers: FloatArray, delta: FloatArray, q: FloatArray) -> None:
    """q[k, m] = r²/δ² of point k from vortex m."""
    for k in range(points.shape[0]):
        for m in range(delta.size):
            rx = points[k, 0] - centers[m, 0]
            ry = points[k, 1] - centers[m, 1]
            q[k, m] = (rx * rx + ry * ry) / (delta[m] * delta[m])


@kernel
def _vortex_sum(points: FloatArray, centers: FloatArray, gamma: FloatArray, delta: FloatArray, q: FloatArray,
                e: FloatArray, out: FloatArray) -> None:
    """Sum of the vortex velocities into ``out (N, 3)`` from q = r²/δ² and e = exp(-q).

    The factor (1 - e) / r² is evaluated by its series (1 - q/2 + q²/6) / δ² for q < 1e-4
    (truncation below 1e-17 relative), so the centre has no cancellation.
    """
    for k in range(points.shape[0]):
        vx = 0.0
        vy = 0.0
        for m in range(gamma.size):
            rx = points[k, 0] - centers[m, 0]
            ry = points[k, 1] - centers[m, 1]
            d2 = delta[m] * delta[m]
            qk = q[k, m]
            f = (1.0 - qk * (0.5 - qk / 6.0)) / d2 if qk < 1e-4 else (1.0 - e[k, m]) / (qk * d2)
            f *= gamma[m] / (2.0 * math.pi)
            vx -= f * ry
            vy += f * rx
        out[k, 0] = vx
        out[k, 1] = vy
