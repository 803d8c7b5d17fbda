"""Current fields built from other fields, for ensembles of forecasts (issue 39).

* :class:`PerturbedCurrent` — a base field plus a random, smooth, horizontal perturbation with a
  stated spread (standard deviation of each component, m/s) and correlation length L (m): a
  random-Fourier-feature Gaussian field whose covariance is ``σ² exp(-r² / (2 L²))``
  (Rahimi & Recht 2007): ``δ(x) = σ √(2/M) Σ_m a_m cos(k_m · x + φ_m)`` with ``k_m ~ N(0, I/L²)``,
  ``φ_m ~ U(0, 2π)`` and ``a_m`` ±1 independent per component.  Steady in time and depth.
* :class:`MeanCurrent` — the member-wise mean of several fields.
* :class:`ShiftedCurrent` — a field seen from a later clock: ``velocity(p, t) = base(p, t0 + t)``
  (re-planning from a vehicle's state mid-mission).
* :class:`DerivedCurrent` — what a field made from one base field (the perturbed and shifted fields, the glider's
  depth average) takes from it: its domain and its speed bound.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...geometry import as_points
from .fields import CurrentField

__all__ = ["DerivedCurrent", "PerturbedCurrent", "MeanCurrent", "ShiftedCurrent"]


class DerivedCurrent(CurrentField):
    """A current field made from one other field, :attr:`base`: defined where the base is, as fast at the most.

    A kind sets ``base`` (a dataclass field, or in its constructor) and its own :meth:`velocity`; a kind that can be
    faster than its base (:class:`PerturbedCurrent`) gives its own :attr:`max_speed`.

    Attributes
    ----------
    base : CurrentField
        The field it is made from.
    """

    base: CurrentField

    def covers(self, xmin: float, xmax: float, ymin: float, ymax: float) -> bool:
        """Whether the field is defined over the whole horizontal box (the base's).

        Parameters
        ----------
        xmin, xmax, ymin, ymax : float
            The box (m).

        Returns
        -------
        bool
            The base field's :meth:`CurrentField.covers`.
        """
        return self.base.covers(xmin, xmax, ymin, ymax)

    @property
    def max_speed(self) -> float:
        """The base field's bound (m/s)."""
        return self.base.max_speed


@dataclass(frozen=True, eq=False)
class PerturbedCurrent(DerivedCurrent):
    """A base current plus a smooth random horizontal perturbation (module notes).

    Parameters
    ----------
    base : CurrentField
        The nominal field.
    spread : float
        Standard deviation of each horizontal component of the perturbation (m/s), >= 0.
    correlation_m : float
        Correlation length L of the Gaussian covariance (m), > 0.
    seed : int
        Seed of the random field (same seed, same field).
    modes : int
        Number of random Fourier modes M.
    """

    base: CurrentField
    spread: float
    correlation_m: float
    seed: int = 0
    modes: int = 64
    _k: FloatArray = field(init=False, repr=False)
    _phase: FloatArray = field(init=False, repr=False)
    _amp: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not (self.spread >= 0 and self.correlation_m > 0 and self.modes >= 1):
            raise ValueError("spread must be >= 0, correlation_m > 0 and modes >= 1")
        rng = np.random.default_rng(self.seed)
        object.__setattr__(self, "_k", rng.normal(0.0, 1.0 / self.correlation_m, size=(2, self.modes, 2)))
        object.__setattr__(self, "_phase", rng.uniform(0.0, 2.0 * math.pi, size=(2, self.modes)))
        object.__setattr__(self, "_amp", rng.choice([-1.0, 1.0], size=(2, self.modes)))

    def perturbation(self, points: ArrayLike) -> FloatArray:
        """The perturbation alone at points.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(..., 3)`` (m/s; the vertical component is 0).
        """
        p = as_points(points)
        xy = p.reshape(-1, 3)[:, :2]
        out = np.zeros((xy.shape[0], 3))
        scale = self.spread * math.sqrt(2.0 / self.modes)
        for c in range(2):
            arg = xy @ self._k[c].T + self._phase[c]
            out[:, c] = scale * (np.cos(arg) @ self._amp[c])
        return out.reshape(p.shape)

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
        out: FloatArray = self.base.velocity(points, t) + self.perturbation(points)
        return out

    @property
    def max_speed(self) -> float:
        """An upper bound of the horizontal speed: the base's plus √2 σ √(2M) (each component bounded)."""
        return self.base.max_speed + math.sqrt(2.0) * self.spread * math.sqrt(2.0 * self.modes)


@dataclass(frozen=True, eq=False)
class MeanCurrent(CurrentField):
    """The mean of several current fields (equal weights).

    Parameters
    ----------
    members : sequence of CurrentField
        At least one field.
    """

    members: Sequence[CurrentField]

    def __post_init__(self) -> None:
        if not self.members:
            raise ValueError("a mean of no current field")
        object.__setattr__(self, "members", tuple(self.members))

    def velocity(self, points: ArrayLike, t: float = 0.0) -> FloatArray:
        """Current velocity at points and a time (the members' mean).

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        t : float, default 0.0
            Time (s).

        Returns
        -------
        numpy.ndarray
            Velocities ``(..., 3)`` (m/s).
        """
        total: FloatArray = sum((m.velocity(points, t) for m in self.members[1:]), self.members[0].velocity(points, t))
        return total / len(self.members)

    def velocity_at(self, points: ArrayLike, times: ArrayLike) -> FloatArray:
        """The field at points, each at its own time (the members' mean) (:meth:`CurrentField.velocity_at`).

        Parameters
        ----------
        points : array_like
            Points ``(N, 3)`` (m).
        times : array_like
            Times ``(N,)`` (s), one per point.

        Returns
        -------
        numpy.ndarray
            Velocities ``(N, 3)`` (m/s).
        """
        total: FloatArray = sum((m.velocity_at(points, times) for m in self.members[1:]),
                                self.members[0].velocity_at(points, times))
        return total / len(self.members)

    def covers(self, xmin: float, xmax: float, ymin: float, ymax: float) -> bool:
        """Whether the field is defined over the whole horizontal box (every member's).

        Parameters
        ----------
        xmin, xmax, ymin, ymax : float
            The box (m).

        Returns
        -------
        bool
            True when every point of the box is inside the field's domain.
        """
        return all(m.covers(xmin, xmax, ymin, ymax) for m in self.members)

    @property
    def max_speed(self) -> float:
        """The largest member bound (a mean is no faster than its fastest member)."""
        return max(m.max_speed for m in self.members)


@dataclass(frozen=True, eq=False)
class ShiftedCurrent(DerivedCurrent):
    """A field read from a later clock: ``velocity(p, t) = base.velocity(p, t0 + t)``.

    Parameters
    ----------
    base : CurrentField
        The field.
    t0 : float
        Offset (s).
    """

    base: CurrentField
    t0: float

    def velocity(self, points: ArrayLike, t: float = 0.0) -> FloatArray:
        """Current velocity at points and time ``t0 + t``.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        t : float, default 0.0
            Time (s) on the shifted clock.

        Returns
        -------
        numpy.ndarray
            Velocities ``(..., 3)`` (m/s).
        """
        return self.base.velocity(points, self.t0 + t)

    def velocity_at(self, points: ArrayLike, times: ArrayLike) -> FloatArray:
        """The field at points, each at its own time on the shifted clock (:meth:`CurrentField.velocity_at`).

        Parameters
        ----------
        points : array_like
            Points ``(N, 3)`` (m).
        times : array_like
            Times ``(N,)`` (s), one per point.

        Returns
        -------
        numpy.ndarray
            Velocities ``(N, 3)`` (m/s).
        """
        return self.base.velocity_at(points, self.t0 + np.asarray(times, dtype=float))
