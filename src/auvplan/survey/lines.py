"""Depth-adaptive survey lines: each next line placed so its swath overlaps the previous one by at least
the minimum fraction at every station along it, over the seabed actually under both swaths.

Frame: the lines run along the compass heading ``ψ`` (unit ``d = (sin ψ, cos ψ)``); ``n = (cos ψ, -sin ψ)``
points across, to the right.  A point is ``s d + c n``.  Stations ``s_k`` cut the area every
``station_m``; at each station the area spans ``[lo_k, hi_k]`` across (its cross-section) and a line is
its across offset ``c_k``.  The swath of a line at a station reaches ``r⁻_k`` to the left and ``r⁺_k``
to the right (:func:`auvplan.survey.swath.swath_reach`, fans across ``n``): edges ``E⁻ = c - r⁻`` and
``E⁺ = c + r⁺``.  The overlap of two adjacent swaths at a station is ``(E⁺_a - E⁻_b) / min(W_a, W_b)``
(``W = r⁻ + r⁺``), the narrower swath's share — on a plane the same ratio as along the slope.

Placement (greedy, edge to edge):

1. the first line's largest offset with ``E⁻_k <= lo_k`` at every station (the area's edge covered);
2. each next line's largest offset ``c_k^max`` with an overlap ``>= overlap_min`` against the swath in
   front at that station (bisection over ``c``, the seabed re-read under the new swath at each trial);
3. the line is the largest function under ``c^max`` whose slope stays within ``tan(max_bend_deg)``
   (the upper Lipschitz envelope ``min_j c_j^max + L |s - s_j|``): it bends to follow the seabed, the
   overlap never drops below the minimum, and exceeds the maximum only where the bend limit binds;
4. until the swaths reach ``hi_k`` everywhere.

On a plane ``c^max`` is constant along the line, the lines are straight and the spacing follows the
closed-form recursion of the 2023 CUMCM problem B (tests/test_survey_lines.py derives it by hand).
With the AUV mounting the line's depth is the seabed plus the altitude, raised where needed so the pitch
stays within ``pitch_max_deg`` (the upper Lipschitz envelope again), and the swath is computed from that depth.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
import shapely.affinity
from numpy.typing import NDArray

from .swath import Seabed, Sensor, swath_reach

__all__ = ["LineParams", "SurveyLine", "SurveyLines", "place_lines", "upper_envelope", "lower_envelope",
           "to_sn", "from_sn"]


@dataclass(frozen=True)
class LineParams:
    """How the lines are placed.

    Attributes
    ----------
    overlap_min, overlap_max : float
        Bounds of the overlap between adjacent swaths (fractions of the narrower swath).
    station_m : float
        Distance between stations along the lines (m).
    max_bend_deg : float
        Largest angle between a line and its nominal heading (deg); 0 keeps the lines straight.
    pitch_max_deg : float
        Steepest climb or dive along a line with the AUV mounting (deg).
    surface_z : float
        Elevation of the sensor with the surface mounting (m, 0 at the sea surface).
    step_m : float
        Sampling step of the seabed profiles under the swath (m).
    max_lines : int
        Give up after this many lines.
    """

    overlap_min: float = 0.10
    overlap_max: float = 0.20
    station_m: float = 50.0
    max_bend_deg: float = 15.0
    pitch_max_deg: float = 15.0
    surface_z: float = 0.0
    step_m: float = 5.0
    max_lines: int = 500

    def __post_init__(self) -> None:
        if not 0.0 <= self.overlap_min < self.overlap_max < 1.0:
            raise ValueError(f"overlap = [{self.overlap_min}, {self.overlap_max}]: need 0 <= min < max < 1")
        if not self.station_m > 0 or not self.step_m > 0:
            raise ValueError("station_m and step_m must be positive")
        if not 0.0 <= self.max_bend_deg < 60.0:
            raise ValueError(f"max_bend_deg = {self.max_bend_deg}: must be in [0, 60)")
        if not 0.0 < self.pitch_max_deg < 60.0:
            raise ValueError(f"pitch_max_deg = {self.pitch_max_deg}: must be in (0, 60)")
        if self.max_lines < 1:
            raise ValueError(f"max_lines = {self.max_lines}: must be >= 1")


@dataclass(frozen=True)
class SurveyLine:
    """One line: its offset, depth and swath at every station, and the stations it is flown over.

    Attributes
    ----------
    c, z : numpy.ndarray
        ``(K,)`` across offset and sensor elevation (m) at every station.
    left, right : numpy.ndarray
        ``(K,)`` swath reach to the left (``-n``) and to the right (``+n``) (m); NaN off the line.
    first, last : int
        The stations ``first..last`` (inclusive) the line is flown over.
    """

    c: NDArray[np.float64]
    z: NDArray[np.float64]
    left: NDArray[np.float64]
    right: NDArray[np.float64]
    first: int
    last: int

    @property
    def active(self) -> slice:
        """The stations of the line."""
        return slice(self.first, self.last + 1)


@dataclass(frozen=True)
class SurveyLines:
    """The planned lines of one survey.

    Attributes
    ----------
    heading : float
        Nominal compass heading of the lines (rad).
    stations : numpy.ndarray
        ``(K,)`` along-line coordinates of the stations (m).
    area_lo, area_hi : numpy.ndarray
        ``(K,)`` the area's cross-section at every station (m across; NaN where the area is absent).
    lines : tuple of SurveyLine
        The lines, in placement order (left to right).
    complete : bool
        Whether the swaths reach the area's far edge everywhere (False: ``max_lines`` reached).
    """

    heading: float
    stations: NDArray[np.float64]
    area_lo: NDArray[np.float64]
    area_hi: NDArray[np.float64]
    lines: tuple[SurveyLine, ...]
    complete: bool

    def waypoints(self, i: int) -> NDArray[np.float64]:
        """Waypoints of one line in the world frame, in increasing station order.

        Parameters
        ----------
        i : int
            The line (placement order).

        Returns
        -------
        numpy.ndarray
            ``(M, 3)`` waypoints (m).
        """
        ln = self.lines[i]
        a = ln.active
        x, y = from_sn(self.stations[a], ln.c[a], self.heading)
        return np.column_stack([x, y, ln.z[a]])

    def overlaps(self) -> list[NDArray[np.float64]]:
        """Overlap fraction of each adjacent pair at the stations they share where their seam is in the area.

        Returns
        -------
        list of numpy.ndarray
            One array of fractions per pair.
        """
        out = []
        for a, b in zip(self.lines[:-1], self.lines[1:], strict=True):
            k = np.zeros(self.stations.size, dtype=bool)
            k[max(a.first, b.first):min(a.last, b.last) + 1] = True
            ea, eb = a.c + a.right, b.c - b.left
            k &= np.isfinite(self.area_hi) & (eb < self.area_hi) & (ea > self.area_lo)
            wa, wb = a.left + a.right, b.left + b.right
            out.append(((ea - eb) / np.minimum(wa, wb))[k])
        return out


def to_sn(x: NDArray[np.float64], y: NDArray[np.float64], heading: float) -> tuple[NDArray[np.float64],
                                                                                   NDArray[np.float64]]:
    """World ``(x, y)`` to line coordinates ``(s, n)``.

    Parameters
    ----------
    x, y : numpy.ndarray
        World coordinates (m).
    heading : float
        Compass heading of the lines (rad).

    Returns
    -------
    tuple of numpy.ndarray
        ``s`` along and ``n`` across (to the right) (m).
    """
    sh, ch = math.sin(heading), math.cos(heading)
    return x * sh + y * ch, x * ch - y * sh


def from_sn(s: NDArray[np.float64], n: NDArray[np.float64], heading: float) -> tuple[NDArray[np.float64],
                                                                                     NDArray[np.float64]]:
    """Line coordinates ``(s, n)`` back to world ``(x, y)`` (the inverse of :func:`to_sn`).

    Parameters
    ----------
    s, n : numpy.ndarray
        Along and across coordinates (m).
    heading : float
        Compass heading of the lines (rad).

    Returns
    -------
    tuple of numpy.ndarray
        ``x`` and ``y`` (m).
    """
    sh, ch = math.sin(heading), math.cos(heading)
    return s * sh + n * ch, s * ch - n * sh


def upper_envelope(s: NDArray[np.float64], cap: NDArray[np.float64], slope: float) -> NDArray[np.float64]:
    """The largest function under ``cap`` with ``|dc/ds| <= slope``: ``min_j cap_j + slope |s - s_j|``.

    Parameters
    ----------
    s : numpy.ndarray
        ``(K,)`` station coordinates (m).
    cap : numpy.ndarray
        ``(K,)`` upper bounds; ``inf`` where unconstrained.
    slope : float
        Largest slope.

    Returns
    -------
    numpy.ndarray
        ``(K,)`` the envelope (``inf`` everywhere when nothing is constrained).
    """
    finite = np.isfinite(cap)
    if not finite.any():
        return np.full(s.size, np.inf)
    return np.asarray(np.min(cap[finite][None, :] + slope * np.abs(s[:, None] - s[finite][None, :]), axis=1))


def lower_envelope(s: NDArray[np.float64], floor: NDArray[np.float64], slope: float) -> NDArray[np.float64]:
    """The smallest function over ``floor`` with ``|dz/ds| <= slope``: ``max_j floor_j - slope |s - s_j|``.

    Parameters
    ----------
    s : numpy.ndarray
        ``(K,)`` coordinates along (m).
    floor : numpy.ndarray
        ``(K,)`` lower bounds.
    slope : float
        Largest slope.

    Returns
    -------
    numpy.ndarray
        ``(K,)`` the envelope.
    """
    return -upper_envelope(s, -floor, slope)


def _bisect_max(g: Callable[[NDArray[np.float64]], NDArray[np.float64]], lo: NDArray[np.float64],
                hi: NDArray[np.float64], iters: int = 40) -> NDArray[np.float64]:
    """Largest ``c`` in ``[lo, hi]`` with ``g(c) >= 0`` for ``g`` decreasing (vectorised; ``hi`` if ``g(hi) >= 0``)."""
    ok_hi = g(hi) >= 0
    a, b = lo.copy(), hi.copy()
    for _ in range(iters):
        m = 0.5 * (a + b)
        ok = g(m) >= 0
        a = np.where(ok, m, a)
        b = np.where(ok, b, m)
    return np.where(ok_hi, hi, a)


class _Placer:
    """The swath of a trial line at chosen stations (the seabed read under it at each trial)."""

    def __init__(self, seabed: Seabed, sensor: Sensor, params: LineParams, stations: NDArray[np.float64],
                 heading: float) -> None:
        self.seabed, self.sensor, self.p, self.s, self.heading = seabed, sensor, params, stations, heading
        sh, ch = math.sin(heading), math.cos(heading)
        self.right_dir = np.array([ch, -sh])

    def nominal_z(self, s: NDArray[np.float64], c: NDArray[np.float64]) -> NDArray[np.float64]:
        if self.sensor.mounting == "auv":
            x, y = from_sn(s, c, self.heading)
            return np.asarray(self.seabed(x, y) + self.sensor.altitude_m)
        return np.full(s.size, self.p.surface_z)

    def reach(self, s: NDArray[np.float64], c: NDArray[np.float64],
              z: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        x, y = from_sn(s, c, self.heading)
        xy = np.column_stack([x, y])
        u = np.broadcast_to(self.right_dir, xy.shape)
        right = swath_reach(self.seabed, self.sensor, xy, z, u, self.p.step_m)
        left = swath_reach(self.seabed, self.sensor, xy, z, -u, self.p.step_m)
        return left, right

    def trial(self, s: NDArray[np.float64], c: NDArray[np.float64]) -> tuple[NDArray[np.float64],
                                                                           NDArray[np.float64]]:
        return self.reach(s, c, self.nominal_z(s, c))

    def first_bound(self, st: NDArray[np.float64],
                    lo: NDArray[np.float64]) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
        """``g(c) >= 0`` while the swath's left edge reaches the area's edge ``lo``."""

        def g(c: NDArray[np.float64]) -> NDArray[np.float64]:
            left, _ = self.trial(st, c)
            return np.asarray(lo - (c - left))

        return g

    def next_bound(self, st: NDArray[np.float64], front: NDArray[np.float64],
                   width: NDArray[np.float64]) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
        """``g(c) >= 0`` while the overlap with the swath in front (edge ``front``) is at least the minimum."""
        eta = self.p.overlap_min

        def g(c: NDArray[np.float64]) -> NDArray[np.float64]:
            left, right = self.trial(st, c)
            return np.asarray(front - (c - left) - eta * np.minimum(width, left + right))

        return g

    def depth_profile(self, c: NDArray[np.float64], first: int, last: int) -> NDArray[np.float64]:
        """Sensor elevation along a line: surface, or seabed + altitude within the pitch limit."""
        z = np.full(self.s.size, np.nan)
        a = slice(first, last + 1)
        if self.sensor.mounting != "auv":
            z[a] = self.p.surface_z
            return z
        x, y = from_sn(self.s[a], c[a], self.heading)
        arc = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))])
        target = self.seabed(x, y) + self.sensor.altitude_m
        z[a] = np.minimum(lower_envelope(arc, target, math.tan(math.radians(self.p.pitch_max_deg))),
                          self.p.surface_z)
        return z


def _cross_sections(area: shapely.Polygon, s: NDArray[np.float64],
                    heading: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The area's extent across over the strip of every station (half-way to its neighbours either side).

    The strip, not the cut at the station alone, so a corner or a slanted edge between two stations is
    inside the extent the swaths must reach.  NaN where a strip misses the area.
    """
    sh, ch = math.sin(heading), math.cos(heading)
    rot = shapely.affinity.affine_transform(area, [sh, ch, ch, -sh, 0.0, 0.0])  # (x, y) -> (s, n)
    _, n0, _, n1 = rot.bounds
    half = 0.5 * (s[1] - s[0]) if s.size > 1 else 0.5
    strips = shapely.box(s - half, n0 - 1.0, s + half, n1 + 1.0)
    parts = shapely.intersection(strips, rot)
    b = shapely.bounds(parts)
    empty = shapely.is_empty(parts) | ~(shapely.area(parts) > 0)
    lo, hi = b[:, 1].copy(), b[:, 3].copy()
    lo[empty], hi[empty] = np.nan, np.nan
    return lo, hi


def place_lines(seabed: Seabed, area: shapely.Polygon, sensor: Sensor, heading: float,
                params: LineParams) -> SurveyLines:
    """Place the depth-adaptive lines of a survey of ``area`` along ``heading``.

    Parameters
    ----------
    seabed : callable
        ``zb(x, y)`` (m).
    area : shapely.Polygon
        The area to cover, in the local frame (m).
    sensor : Sensor
        Swath sensor and mounting.
    heading : float
        Nominal compass heading of the lines (rad).
    params : LineParams
        Overlap bounds, station spacing, bend and pitch limits.

    Returns
    -------
    SurveyLines
        The lines, left to right across the heading.
    """
    ring = np.asarray(area.exterior.coords)
    s_all, _ = to_sn(ring[:, 0], ring[:, 1], heading)
    s0, s1 = float(s_all.min()), float(s_all.max())
    k = max(2, int(math.ceil((s1 - s0) / params.station_m)) + 1)
    s = np.linspace(s0, s1, k)
    lo, hi = _cross_sections(area, s, heading)
    inside = np.isfinite(lo)
    pl = _Placer(seabed, sensor, params, s, heading)
    bend = math.tan(math.radians(params.max_bend_deg))
    front = np.full(k, -np.inf)  # right edge of the swath in front (latest line over each station)
    width, front_c = np.full(k, np.nan), np.full(k, np.nan)
    lines: list[SurveyLine] = []
    while len(lines) < params.max_lines:
        todo = np.flatnonzero(inside & (front < hi))
        if not todo.size:
            break
        first, last = (int(todo[0]), int(todo[-1])) if not lines else (max(int(todo[0]) - 1, 0),
                                                                       min(int(todo[-1]) + 1, k - 1))
        flown = np.zeros(k, dtype=bool)
        flown[first:last + 1] = True
        idx = np.flatnonzero(flown & inside & np.isfinite(front)) if lines else todo
        st = s[idx]
        if not lines:
            base, span = lo[idx], 0.0
            bound = pl.first_bound(st, base)
        else:
            base, span = front_c[idx], 3.0 * float(np.nanmax(width[idx])) + 10.0 * params.step_m
            bound = pl.next_bound(st, front[idx], width[idx])
        if not lines:
            span = 1.0 + 2.0 * float(np.max(pl.trial(st, base)[0])) + 10.0 * params.step_m
        cmax = np.full(k, np.inf)
        cmax[idx] = _bisect_max(bound, base, base + span)
        c = upper_envelope(s, cmax, bend) if bend > 0 else np.full(k, float(np.min(cmax[idx])))
        z = pl.depth_profile(c, first, last)
        left, right = np.full(k, np.nan), np.full(k, np.nan)
        a = slice(first, last + 1)
        left[a], right[a] = pl.reach(s[a], c[a], z[a])
        line = SurveyLine(c, z, left, right, first, last)
        lines.append(line)
        front[a], width[a], front_c[a] = c[a] + right[a], left[a] + right[a], c[a]
    complete = not (inside & (front < hi)).any()
    return SurveyLines(heading, s, lo, hi, tuple(lines), complete)
