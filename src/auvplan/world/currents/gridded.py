"""A current on a rectilinear (x, y, z[, t]) grid, :class:`GriddedCurrent`: u, v (and optionally w) interpolated
linearly in space and time by a compiled loop (checked against ``scipy.interpolate.RegularGridInterpolator`` in
the tests).  Points outside the grid take the value at the nearest grid face (clamping); a world checks at build
time that the grid covers its horizontal bounds.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...errors import DataError
from ...geometry import as_points
from ...runtime.jit import kernel
from .base import CurrentField

__all__ = ["GriddedCurrent"]


@dataclass(frozen=True, eq=False)
class GriddedCurrent(CurrentField):
    """Current on a rectilinear grid, interpolated linearly in x, y, z and t.

    Points and times outside the grid take the value at the nearest grid face (clamping); a
    world checks at build time that the grid covers its horizontal bounds.  The interpolation
    is one compiled loop over the points (bisection on each axis, 16-corner weights).

    Parameters
    ----------
    x, y, z : ndarray
        Ascending axes (m, local frame; ``z`` is elevation, negative below the surface);
        they need not be uniform.  ``z`` may have a single level (depth-independent current).
    u, v : ndarray
        Eastward and northward velocity (m/s), shape ``(nt, nz, ny, nx)`` (or ``(nz, ny, nx)``).
    w : ndarray or None
        Upward velocity, same shape; zero when ``None``.
    t : ndarray or None
        Ascending time axis (s); ``None`` for a steady field.
    name : str
        Source of the data, for messages.

    Raises
    ------
    DataError
        If a component is mis-shaped or not finite, or an axis is not strictly ascending.
    """

    x: FloatArray
    y: FloatArray
    z: FloatArray
    u: FloatArray
    v: FloatArray
    w: FloatArray | None = None
    t: FloatArray | None = None
    name: str = ""
    _axes: tuple[FloatArray, FloatArray, FloatArray, FloatArray] = field(init=False, repr=False)
    _data: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        axes = [np.ascontiguousarray(a, dtype=float).reshape(-1) for a in (self.x, self.y, self.z)]  # C: one kernel
        tax = np.zeros(1) if self.t is None else np.ascontiguousarray(self.t, dtype=float).reshape(-1)
        comps = [np.asarray(c, dtype=float) for c in (self.u, self.v)]
        comps.append(np.zeros_like(comps[0]) if self.w is None else np.asarray(self.w, dtype=float))
        shape = (tax.size, axes[2].size, axes[1].size, axes[0].size)
        for name, c in zip("uvw", comps):
            if c.size != int(np.prod(shape)):
                raise DataError(f"current {self.name!r}: component {name} has shape {c.shape}, expected {shape}")
        data = np.ascontiguousarray(np.stack([c.reshape(shape) for c in comps], axis=-1))
        if not np.all(np.isfinite(data)):
            raise DataError(f"current {self.name!r}: velocity components contain NaN or infinite values")
        for name, a in zip(("x", "y", "z", "time"), (*axes, tax)):
            if not np.all(np.isfinite(a)) or (a.size > 1 and not np.all(np.diff(a) > 0)):
                raise DataError(f"current {self.name!r}: axis {name} must be finite and strictly ascending")
        if axes[0].size < 2 or axes[1].size < 2:
            raise DataError(f"current {self.name!r}: the grid needs at least two x and two y nodes")
        data.setflags(write=False)
        object.__setattr__(self, "_axes", (tax, axes[2], axes[1], axes[0]))
        object.__setattr__(self, "_data", data)

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
        out = np.empty_like(flat)
        _interpolate(self._data, *self._axes, flat, float(t), out)
        return out.reshape(p.shape)

    def velocity_at(self, points: ArrayLike, times: ArrayLike) -> FloatArray:
        """The field at points, each at its own time, in one compiled loop (:meth:`CurrentField.velocity_at`).

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
        flat = np.ascontiguousarray(as_points(points).reshape(-1, 3))
        tt = np.ascontiguousarray(np.broadcast_to(np.asarray(times, dtype=float).reshape(-1), (flat.shape[0],)))
        out = np.empty_like(flat)
        _interpolate_at(self._data, *self._axes, flat, tt, out)
        return out

    @property
    def steady(self) -> bool:
        """Whether the field has at most one time (it then does not change with time)."""
        return self.t is None or np.size(self.t) <= 1

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
        x = np.asarray(self.x, dtype=float)
        y = np.asarray(self.y, dtype=float)
        tol = 1e-6 * max(1.0, float(np.ptp(x)), float(np.ptp(y)))
        return bool(x.min() - tol <= xmin and x.max() + tol >= xmax and y.min() - tol <= ymin and y.max() + tol >= ymax)

    @property
    def max_speed(self) -> float:
        """An upper bound of the horizontal current speed.

        Returns
        -------
        float
            Speed bound (m/s).
        """
        return float(np.sqrt(np.asarray(self.u) ** 2 + np.asarray(self.v) ** 2).max())


@kernel
def _locate(axis: FloatArray, value: float) -> tuple[int, float]:
    """``(i, w)`` with ``value`` between ``axis[i]`` and ``axis[i + 1]`` at weight ``w`` in [0, 1],
    clamped to the ends; a single-node axis gives ``(0, 0)``.  The first guess assumes even
    spacing, then the index walks to the right cell (one step on an even axis)."""
    n = axis.size
    if n == 1 or value <= axis[0]:
        return 0, 0.0
    if value >= axis[n - 1]:
        return n - 2, 1.0
    i = int((value - axis[0]) / (axis[n - 1] - axis[0]) * (n - 1))
    i = min(max(i, 0), n - 2)
    while value < axis[i]:
        i -= 1
    while value > axis[i + 1]:
        i += 1
    return i, (value - axis[i]) / (axis[i + 1] - axis[i])


@kernel
def _interpolate(data: FloatArray, taxis: FloatArray, zaxis: FloatArray, yaxis: FloatArray, xaxis: FloatArray,
                 points: FloatArray, t: float, out: FloatArray) -> None:
    """Quadrilinear interpolation of ``data (nt, nz, ny, nx, 3)`` at ``points (N, 3)``, time ``t``
    (corners of zero weight, as on a single-node axis, are skipped)."""
    it, wt = _locate(taxis, t)
    for k in range(points.shape[0]):
        iz, wz = _locate(zaxis, points[k, 2])
        iy, wy = _locate(yaxis, points[k, 1])
        ix, wx = _locate(xaxis, points[k, 0])
        w00, w01, w10, w11 = (1.0 - wy) * (1.0 - wx), (1.0 - wy) * wx, wy * (1.0 - wx), wy * wx
        out[k, 0] = out[k, 1] = out[k, 2] = 0.0
        for dt in range(2):
            a = wt if dt else 1.0 - wt
            for dz in range(2):
                ab = a * (wz if dz else 1.0 - wz)
                if ab == 0.0:
                    continue
                ti, zi = it + dt, iz + dz
                for c in range(3):
                    out[k, c] += ab * (w00 * data[ti, zi, iy, ix, c] + w01 * data[ti, zi, iy, ix + 1, c]
                                       + w10 * data[ti, zi, iy + 1, ix, c] + w11 * data[ti, zi, iy + 1, ix + 1, c])


@kernel
def _interpolate_at(data: FloatArray, taxis: FloatArray, zaxis: FloatArray, yaxis: FloatArray, xaxis: FloatArray,
                    points: FloatArray, times: FloatArray, out: FloatArray) -> None:
    """:func:`_interpolate` with a time per point: ``points[k]`` at ``times[k]`` (the same arithmetic)."""
    for k in range(points.shape[0]):
        _interpolate(data, taxis, zaxis, yaxis, xaxis, points[k:k + 1], times[k], out[k:k + 1])
