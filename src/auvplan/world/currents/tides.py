"""Tidal currents predicted from harmonic constants at current stations, interpolated in space and depth.

Prediction (XTide's method, on the tables of the harmonics file it ships with): the signed speed
along a station's flood/ebb axis at UTC time t is ::

    s(t) = s0 + Σ_i f_i(y) A_i cos(ω_i h + (V0+u)_i(y) - G_i),     G_i = κ_i - ω_i z

with ``y`` the UTC year of t, ``h`` the hours since 1 January of that year 00:00 UTC, ``(V0+u)(y)``
the equilibrium argument at the start of the year and ``f(y)`` the node factor of its middle (both
tabulated per year in the data file), ``κ`` the station's phase (local epoch, referred to the time
meridian ``z`` hours east of Greenwich; ``-ω z`` refers it to Greenwich) and ``s0`` the mean current.
Positive speeds flow towards the flood direction, negative ones towards the ebb direction (NOAA's
convention).  The prediction is checked against pyTMD's astronomical arguments in the tests.

Space and depth: each site holds one or more depth bins; a point takes each site's velocity
interpolated linearly in depth (clamped at the shallowest and deepest bins), then the sites'
inverse-distance-squared mean ``w_k = 1 / (d_k² + r0²)`` over the horizontal distances.  Both steps are
linear in the station velocities, so a field is one matrix ``W (N, S)`` applied to the stations'
velocities ``(S, 2)``: :meth:`TidalCurrent.sample` predicts the stations once per time and applies
``W`` with one product (the planners sample whole lattices over many times this way).
"""

from __future__ import annotations

import datetime as _dt
import math
from dataclasses import dataclass, field

import numpy as np

from ..._types import ArrayLike, FloatArray, IntArray
from ...errors import DataError
from ...geometry import as_points
from ...runtime.jit import kernel
from .fields import CurrentField

__all__ = ["HarmonicTables", "TidalCurrent", "predict_speed", "unix_time"]

_EPOCH = _dt.datetime(1970, 1, 1, tzinfo=_dt.UTC)


def unix_time(when: _dt.datetime) -> float:
    """Seconds since 1970-01-01 00:00 UTC of an aware datetime.

    Parameters
    ----------
    when : datetime.datetime
        A time with a time zone.

    Returns
    -------
    float
        Unix time (s).

    Raises
    ------
    ValueError
        If ``when`` has no time zone.
    """
    if when.tzinfo is None:
        raise ValueError(f"{when.isoformat()}: a time zone is required (e.g. 'Z' for UTC)")
    return (when - _EPOCH).total_seconds()


@dataclass(frozen=True, eq=False)
class HarmonicTables:
    """Constituent speeds and the yearly tables of equilibrium arguments and node factors.

    Attributes
    ----------
    names : tuple of str
        Constituent names.
    speed : ndarray, shape (C,)
        Angular speeds (degrees per hour).
    first_year : int
        Year of the first column of the tables.
    equilibrium : ndarray, shape (C, Y)
        ``V0 + u`` at 1 January 00:00 UTC of each year (degrees, Greenwich).
    node_factor : ndarray, shape (C, Y)
        Node factor ``f`` for the middle of each year.

    Raises
    ------
    DataError
        If the arrays disagree in shape.
    """

    names: tuple[str, ...]
    speed: FloatArray
    first_year: int
    equilibrium: FloatArray
    node_factor: FloatArray

    def __post_init__(self) -> None:
        c = len(self.names)
        for key in ("speed", "equilibrium", "node_factor"):
            object.__setattr__(self, key, np.asarray(getattr(self, key), dtype=float))
        shapes = (self.speed.shape, self.equilibrium.shape[0], self.node_factor.shape)
        if shapes != ((c,), c, self.equilibrium.shape):
            raise DataError("harmonic tables: speeds, equilibrium arguments and node factors disagree in shape")

    @property
    def years(self) -> tuple[int, int]:
        """First and last year the tables cover.

        Returns
        -------
        tuple of int
            ``(first, last)``, both included.
        """
        return self.first_year, self.first_year + self.equilibrium.shape[1] - 1

    def arguments(self, unix_seconds: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """The astronomical arguments at UTC times.

        Parameters
        ----------
        unix_seconds : array_like
            Times ``(N,)`` (s since 1970-01-01 00:00 UTC).

        Returns
        -------
        hours : numpy.ndarray
            Hours since the start of each time's UTC year ``(N,)``.
        v0u : numpy.ndarray
            ``V0 + u`` of that year ``(N, C)`` (degrees).
        f : numpy.ndarray
            Node factors of that year ``(N, C)``.

        Raises
        ------
        DataError
            If a time falls outside the years of the tables.
        """
        t = np.atleast_1d(np.asarray(unix_seconds, dtype=float))
        years = (t.astype("datetime64[s]").astype("datetime64[Y]").astype(int) + 1970).astype(int)
        y0, y1 = self.years
        if years.min() < y0 or years.max() > y1:
            raise DataError(f"tidal prediction: years {years.min()}-{years.max()} outside the tables ({y0}-{y1})")
        start = (np.asarray(years - 1970, dtype="datetime64[Y]").astype("datetime64[s]")).astype(float)
        col = years - y0
        return (t - start) / 3600.0, self.equilibrium[:, col].T, self.node_factor[:, col].T


def predict_speed(tables: HarmonicTables, amplitude: ArrayLike, greenwich_phase: ArrayLike, mean: ArrayLike,
                  unix_seconds: ArrayLike) -> FloatArray:
    """Signed speeds along the flood axis of ``S`` stations at ``N`` UTC times (module notes).

    Parameters
    ----------
    tables : HarmonicTables
        Constituents and their yearly tables.
    amplitude : array_like
        Amplitudes ``(S, C)`` (m/s).
    greenwich_phase : array_like
        Greenwich phases ``G = κ - ω z`` ``(S, C)`` (degrees).
    mean : array_like
        Mean current along the flood axis ``(S,)`` (m/s).
    unix_seconds : array_like
        Times ``(N,)`` (s since 1970-01-01 00:00 UTC).

    Returns
    -------
    numpy.ndarray
        Signed speeds ``(N, S)`` (m/s; positive towards the flood).
    """
    hours, v0u, f = tables.arguments(unix_seconds)
    arg = np.radians(hours[:, None] * tables.speed[None, :] + v0u)  # (N, C)
    g = np.radians(np.asarray(greenwich_phase, dtype=float))  # (S, C)
    a = np.asarray(amplitude, dtype=float)
    # cos(arg - g) = cos(arg) cos(g) + sin(arg) sin(g): two (N, C) @ (C, S) products
    speed: FloatArray = np.asarray(mean, dtype=float)[None, :] + (f * np.cos(arg)) @ (a * np.cos(g)).T + \
        (f * np.sin(arg)) @ (a * np.sin(g)).T
    return speed


@dataclass(frozen=True, eq=False)
class TidalCurrent(CurrentField):
    """Tidal current field from harmonic current stations (see the module notes).

    Parameters
    ----------
    tables : HarmonicTables
        Constituents and their yearly tables.
    site_xy : ndarray, shape (K, 2)
        Horizontal positions of the sites in the local frame (m).
    site : ndarray of int, shape (S,)
        Site index of each station (depth bin).
    depth : ndarray, shape (S,)
        Depth of each bin below the surface (m, positive).
    flood, ebb : ndarray, shape (S, 2)
        Unit vectors (east, north in the local frame) of the flood and ebb directions.
    amplitude, greenwich_phase : ndarray, shape (S, C)
        Amplitudes (m/s) and Greenwich phases (degrees).
    mean : ndarray, shape (S,)
        Mean current along the flood axis (m/s).
    epoch : float
        UTC time of ``t = 0`` (seconds since 1970-01-01): the mission's ``start_time``.
    r0 : float
        Smoothing distance of the inverse-distance weights (m).
    names : tuple of str
        Station names, for reports.

    Raises
    ------
    DataError
        If the station arrays disagree in shape, there is no station, a site has none, or r0 <= 0.
    """

    tables: HarmonicTables
    site_xy: FloatArray
    site: IntArray
    depth: FloatArray
    flood: FloatArray
    ebb: FloatArray
    amplitude: FloatArray
    greenwich_phase: FloatArray
    mean: FloatArray
    epoch: float
    r0: float = 1000.0
    names: tuple[str, ...] = ()
    _bins: tuple[IntArray, FloatArray] = field(init=False, repr=False)
    _cache: dict[int, FloatArray] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        for key in ("site_xy", "depth", "flood", "ebb", "amplitude", "greenwich_phase", "mean"):
            object.__setattr__(self, key, np.asarray(getattr(self, key), dtype=float))
        object.__setattr__(self, "site", np.asarray(self.site, dtype=int))
        s = self.depth.size
        if not (self.site.shape == self.mean.shape == (s,) and self.flood.shape == self.ebb.shape == (s, 2)
                and self.amplitude.shape == self.greenwich_phase.shape == (s, len(self.tables.names))):
            raise DataError("tidal current: station arrays disagree in shape")
        if s == 0 or self.site.min() < 0 or self.site.max() >= self.site_xy.shape[0] or self.r0 <= 0:
            raise DataError("tidal current: needs at least one station, valid site indices and r0 > 0")
        # each site's bins sorted by depth, padded to a common length by repeating the deepest
        bins = [np.flatnonzero(self.site == k) for k in range(self.site_xy.shape[0])]
        bins = [b[np.argsort(self.depth[b])] for b in bins]
        width = max(max(b.size for b in bins), 2)
        idx = np.array([np.r_[b, np.full(width - b.size, b[-1])] if b.size else np.zeros(width, int) for b in bins])
        if any(b.size == 0 for b in bins):
            raise DataError("tidal current: a site without stations")
        object.__setattr__(self, "_bins", (idx, self.depth[idx]))
        object.__setattr__(self, "_cache", {})

    # ------------------------------------------------------------------ stations
    def station_velocity(self, t: ArrayLike) -> FloatArray:
        """Velocities of every station at times.

        Parameters
        ----------
        t : array_like
            Times ``(T,)`` (s after ``epoch``).

        Returns
        -------
        numpy.ndarray
            ``(T, S, 2)`` (east, north; m/s).
        """
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        s = predict_speed(self.tables, self.amplitude, self.greenwich_phase, self.mean, self.epoch + tt)
        velocity: FloatArray = np.where(s[..., None] >= 0.0, s[..., None] * self.flood, -s[..., None] * self.ebb)
        return velocity

    def weights(self, points: ArrayLike) -> FloatArray:
        """The linear map from station velocities to the field at points.

        Parameters
        ----------
        points : array_like
            Points ``(N, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``W (N, S)``: each row sums to 1.
        """
        p = np.ascontiguousarray(as_points(points).reshape(-1, 3))
        out = np.zeros((p.shape[0], self.depth.size))
        idx, zs = self._bins
        _weights(p, self.site_xy, float(self.r0), idx, zs, out)
        return out

    def _station_at(self, t: float) -> FloatArray:
        """Station velocities ``(S, 2)`` at ``t``: linear between predictions every minute, made a day
        at a time (interpolation error below 1e-5 of the M2 amplitude, 6e-4 of M8's)."""
        day = math.floor(t / 86400.0)
        table = self._cache.get(day)
        if table is None:
            if len(self._cache) > 8:
                self._cache.clear()
            table = self._cache[day] = self.station_velocity(day * 86400.0 + 60.0 * np.arange(1442))
        f = (t - day * 86400.0) / 60.0
        i = min(int(f), 1440)
        a = f - i
        velocity: FloatArray = (1.0 - a) * table[i] + a * table[i + 1]
        return velocity

    # ------------------------------------------------------------------ CurrentField
    def velocity(self, points: ArrayLike, t: float = 0.0) -> FloatArray:
        """Current velocity at points and a time.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        t : float, default 0.0
            Time (s after ``epoch``).

        Returns
        -------
        numpy.ndarray
            Velocities ``(..., 3)`` (m/s; east, north, and 0 up).
        """
        p = as_points(points)
        uv = self.weights(p) @ self._station_at(float(t))
        out = np.zeros(p.reshape(-1, 3).shape)
        out[:, :2] = uv
        return out.reshape(p.shape)

    def velocity_at(self, points: ArrayLike, times: ArrayLike) -> FloatArray:
        """The field at points, each at its own time (:meth:`CurrentField.velocity_at`; the station tables a
        day at a time, as :meth:`velocity`).

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
        tt = np.broadcast_to(np.asarray(times, dtype=float).reshape(-1), (p.shape[0],))
        station = np.empty((tt.size, self.depth.size, 2))
        day = np.floor(tt / 86400.0)
        for d in np.unique(day):  # the minute tables of :meth:`_station_at`, blended per point
            k = np.flatnonzero(day == d)
            table = self._cache.get(int(d))
            if table is None:
                if len(self._cache) > 8:
                    self._cache.clear()
                table = self._cache[int(d)] = self.station_velocity(d * 86400.0 + 60.0 * np.arange(1442))
            f = (tt[k] - d * 86400.0) / 60.0
            i = np.minimum(f.astype(int), 1440)
            a = (f - i)[:, None, None]
            station[k] = (1.0 - a) * table[i] + a * table[i + 1]
        out = np.zeros(p.shape)
        out[:, :2] = np.matmul(self.weights(p)[:, None, :], station)[:, 0, :]
        return out

    def sample(self, points: ArrayLike, times: ArrayLike) -> FloatArray:
        """The field at points for every time of a series (one matrix product).

        Parameters
        ----------
        points : array_like
            Points ``(N, 3)`` (m).
        times : array_like
            Times ``(T,)`` (s after ``epoch``).

        Returns
        -------
        numpy.ndarray
            Velocities ``(T, N, 3)`` (m/s).
        """
        p = as_points(points).reshape(-1, 3)
        w = self.weights(p)
        vs = self.station_velocity(times)  # (T, S, 2)
        t, s, _ = vs.shape
        uv = w @ vs.transpose(1, 0, 2).reshape(s, 2 * t)  # (N, T * 2): one BLAS product
        out = np.zeros((t, p.shape[0], 3))
        out[..., :2] = uv.reshape(p.shape[0], t, 2).transpose(1, 0, 2)
        return out

    @property
    def max_speed(self) -> float:
        """An upper bound of the current speed.

        Returns
        -------
        float
            Speed bound (m/s).
        """
        # the field is a convex combination of stations, each bounded by |s0| + Σ A max_y f
        fmax = self.tables.node_factor.max(axis=1)
        return float((np.abs(self.mean) + self.amplitude @ fmax).max())


@kernel
def _weights(points: FloatArray, site_xy: FloatArray, r0: float, idx: IntArray, zs: FloatArray,
             out: FloatArray) -> None:
    """Rows of ``W``: inverse-distance-squared site weights times each site's linear depth weights
    (clamped at its shallowest and deepest bins); ``idx``/``zs (K, B)`` the sites' bins by depth."""
    nk, nb = zs.shape
    for n in range(points.shape[0]):
        total = 0.0
        for k in range(nk):
            dx = points[n, 0] - site_xy[k, 0]
            dy = points[n, 1] - site_xy[k, 1]
            total += 1.0 / (dx * dx + dy * dy + r0 * r0)
        depth = -points[n, 2]
        for k in range(nk):
            dx = points[n, 0] - site_xy[k, 0]
            dy = points[n, 1] - site_xy[k, 1]
            w = 1.0 / (dx * dx + dy * dy + r0 * r0) / total
            j = 1
            while j < nb - 1 and zs[k, j] < depth:
                j += 1
            lo, hi = zs[k, j - 1], zs[k, j]
            a = 0.0
            if hi > lo:
                a = min(max((depth - lo) / (hi - lo), 0.0), 1.0)
            out[n, idx[k, j - 1]] += w * (1.0 - a)
            out[n, idx[k, j]] += w * a
