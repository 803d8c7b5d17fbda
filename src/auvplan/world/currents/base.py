"""The interface of every ocean current field: ``velocity(points, t) -> (N, 3)``, the field over a series of times
(:meth:`CurrentField.sample`) or along a recorded track (:meth:`CurrentField.velocity_at`), whether it is steady,
the box it covers and a bound of its speed.  The fields themselves: :mod:`.fields`, :mod:`.gridded`, :mod:`.tides`,
:mod:`.ensemble`.
"""

from __future__ import annotations

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...geometry import as_points

__all__ = ["CurrentField"]


class CurrentField:
    """Base class: a current field returns velocities ``(N, 3)`` (m/s) at ``points (N, 3)``."""

    def velocity(self, points: ArrayLike, t: float = 0.0) -> FloatArray:  # pragma: no cover - interface
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
        raise NotImplementedError

    def sample(self, points: ArrayLike, times: ArrayLike) -> FloatArray:
        """The field at points for every time of a series.

        Parameters
        ----------
        points : array_like
            Points ``(N, 3)`` (m).
        times : array_like
            Times ``(T,)`` (s).

        Returns
        -------
        numpy.ndarray
            Velocities ``(T, N, 3)`` (m/s).
        """
        p = as_points(points).reshape(-1, 3)
        return np.stack([self.velocity(p, float(t)) for t in np.atleast_1d(times)])

    def velocity_at(self, points: ArrayLike, times: ArrayLike) -> FloatArray:
        """The field at points, each at its own time (a recorded track).

        A :attr:`steady` field is asked once for all the points; any other field once per point,
        unless it answers the whole array at once itself (the gridded field, the tides), with the same
        values (``tests/test_flown_tail.py``).

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
        p = as_points(points).reshape(-1, 3)
        if self.steady:
            return self.velocity(p)
        tt = np.broadcast_to(np.asarray(times, dtype=float).reshape(-1), (p.shape[0],))
        return np.array([self.velocity(q, float(s)) for q, s in zip(p, tt)]).reshape(-1, 3)

    @property
    def steady(self) -> bool:
        """Whether the field does not change with time (False unless a kind says so).

        Returns
        -------
        bool
            True for the uniform current, Lamb–Oseen vortices and a gridded field with at most one time.
        """
        return False

    def covers(self, xmin: float, xmax: float, ymin: float, ymax: float) -> bool:
        """Whether the field is defined over the whole horizontal box.

        Parameters
        ----------
        xmin, xmax, ymin, ymax : float
            The box (m).

        Returns
        -------
        bool
            True when every point of the box is inside the field's domain.
        """
        return True

    @property
    def max_speed(self) -> float:
        """An upper bound of the horizontal current speed.

        Returns
        -------
        float
            Speed bound (m/s).
        """
        raise NotImplementedError  # pragma: no cover - interface
