"""Depth-adaptive survey lines: each next line placed so its swath overlaps the previous one by at least
the minimum fraction at every station along it, over the seabed actually under both swaths.

Frame: the lines run along the compass heading ``ψ`` (unit ``d = (sin ψ, cos ψ)``); ``n = (cos ψ, -sin ψ)``
points across, to the right.  A point is ``s d + c n``.  Stations ``s_k`` cut the area every
``station_m``; at each station the area spans ``[lo_k, hi_k]`` across (its cross-section) and a line is
its across offset ``c_k``.  The swath of a line at a station reaches ``r⁻_k`` to the left and ``r⁺_k``
to the right (:func:`auvplan.survey.lines.swath.swath_reach`, fans across ``n``): edges ``E⁻ = c - r⁻`` and
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
closed-form recursion of the 2023 CUMCM problem B (tests/oracles/test_survey_lines.py derives it by hand).
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

from .envelope import lower_envelope, upper_envelope
from .frame import Frame, StraightFrame
from .navspacing import nav_margin
from .swath import Seabed, Sensor, swath_reach

__all__ = ["LineParams", "SurveyLine", "SurveyLines", "place_lines", "upper_envelope", "lower_envelope",
           "to_sn", "from_sn", "nav_margin"]


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
    overlap_margin : float
        Added to ``overlap_min`` where the lines are placed, so the flown overlap keeps the minimum when
        the vehicle crabs in a cross-current (:func:`auvplan.survey.ties.crab_margin`); the outermost
        swaths reach the area's edges with their reach shortened by the same fraction.
    nav_rel_per_m : float
        Relative navigation error of two adjacent lines per metre flown between their passes at a
        station (confidence × the dead-reckoning drift rate, issue 52; 0: exact navigation).  Each next
        line is brought closer by that error at every station (:func:`nav_margin`).
    nav_turn_m : float
        Longest path flown between the end of one line and the start of the next beyond the lines (m;
        the run-ins and the turn): part of the distance between the passes.
    """

    overlap_min: float = 0.10
    overlap_max: float = 0.20
    station_m: float = 50.0
    max_bend_deg: float = 15.0
    pitch_max_deg: float = 15.0
    surface_z: float = 0.0
    step_m: float = 5.0
    max_lines: int = 500
    overlap_margin: float = 0.0
    nav_rel_per_m: float = 0.0
    nav_turn_m: float = 0.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.overlap_min < self.overlap_max < 1.0:
            raise ValueError(f"overlap = [{self.overlap_min}, {self.overlap_max}]: need 0 <= min < max < 1")
        if not self.station_m > 0 or not self.step_m > 0:
            raise ValueError("station_m and step_m must be positive")
        if not 0.0 <= self.max_bend_deg < 60.0:
            raise ValueError(f"max_bend_deg = {self.max_bend_deg}: must be in [0, 60)")
        if not 0.0 < self.pitch_max_deg < 60.0:
            raise ValueError(f"pitch_max_deg = {self.pitch_max_deg}: must be in (0, 60)")
        if not 0.0 <= self.overlap_margin < 1.0 - self.overlap_min:
            raise ValueError(f"overlap_margin = {self.overlap_margin}: must be in [0, 1 - overlap_min)")
        if self.max_lines < 1:
            raise ValueError(f"max_lines = {self.max_lines}: must be >= 1")
        if not (0.0 <= self.nav_rel_per_m < 1.0 and 0.0 <= self.nav_turn_m < math.inf):
            raise ValueError(f"nav_rel_per_m = {self.nav_rel_per_m}, nav_turn_m = {self.nav_turn_m}: must be >= 0")


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
    gap_left, gap_right : numpy.ndarray or None
        ``(K,)`` a side-scan's nadir gap either side (m); None for a multibeam.
    nav_margin : numpy.ndarray or None
        ``(K,)`` how much closer the line was brought to the one before for their relative navigation
        error at each station (m; :func:`nav_margin`); None without one.
    """

    c: NDArray[np.float64]
    z: NDArray[np.float64]
    left: NDArray[np.float64]
    right: NDArray[np.float64]
    first: int
    last: int
    gap_left: NDArray[np.float64] | None = None
    gap_right: NDArray[np.float64] | None = None
    nav_margin: NDArray[np.float64] | None = None

    @property
    def nadir(self) -> NDArray[np.float64]:
        """``(K,)`` across offset of the middle of the nadir gap (the line itself for a multibeam) (m)."""
        if self.gap_left is None or self.gap_right is None:
            return self.c
        return np.asarray(self.c + 0.5 * (self.gap_right - self.gap_left))

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
    frame : Frame or None
        The line frame (None: straight along ``heading``); a corridor's follows its centre line.
    """

    heading: float
    stations: NDArray[np.float64]
    area_lo: NDArray[np.float64]
    area_hi: NDArray[np.float64]
    lines: tuple[SurveyLine, ...]
    complete: bool
    frame: Frame | None = None

    @property
    def geom(self) -> Frame:
        """The line frame."""
        return self.frame if self.frame is not None else StraightFrame(self.heading)

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
        x, y = self.geom.from_sn(self.stations[a], ln.c[a])
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
            out.append(pair_overlap(ea, eb, a.left + a.right, b.left + b.right, a, b)[k])
        return out


def pair_overlap(ea: NDArray[np.float64], eb: NDArray[np.float64], wa: NDArray[np.float64], wb: NDArray[np.float64],
                 a: SurveyLine | None = None, b: SurveyLine | None = None) -> NDArray[np.float64]:
    """Overlap of two adjacent swaths across the track, a share of the narrower swath.

    A multibeam: ``(E+_a - E-_b) / min(W_a, W_b)``, the shared width over the narrower swath.  A side-scan
    (both lines with a nadir gap): each line's gap is covered by its neighbours, so the overlap is how far
    each swath reaches past the other line's nadir, ``min(E+_a - m_b, m_a - E-_b)``, over the narrower of
    the two facing one-side swaths (``E+_a - m_a - g+_a`` and ``m_b - E-_b - g-_b``).

    Parameters
    ----------
    ea, eb : numpy.ndarray
        Right edge of swath ``a``, left edge of swath ``b`` (m across).
    wa, wb : numpy.ndarray
        Widths of the two swaths (multibeam) (m).
    a, b : SurveyLine, optional
        The lines, for a side-scan's gaps.

    Returns
    -------
    numpy.ndarray
        The overlap fractions.
    """
    if a is None or b is None or a.gap_right is None or b.gap_left is None:
        return np.asarray((ea - eb) / np.minimum(wa, wb))
    assert a.gap_left is not None and b.gap_right is not None
    return sidescan_overlap(ea, a.nadir, a.gap_right, eb, b.nadir, b.gap_left, a.c, b.c)


def sidescan_overlap(ea: NDArray[np.float64], ma: NDArray[np.float64], gra: NDArray[np.float64],
                     eb: NDArray[np.float64], mb: NDArray[np.float64], glb: NDArray[np.float64],
                     ca: NDArray[np.float64], cb: NDArray[np.float64]) -> NDArray[np.float64]:
    """A side-scan pair's overlap: how far each swath reaches past the other's nadir, over the narrower band.

    Parameters
    ----------
    ea, ma, gra : numpy.ndarray
        Line ``a``'s right swath edge, nadir (gap middle) and right gap reach (m).
    eb, mb, glb : numpy.ndarray
        Line ``b``'s left swath edge, nadir and left gap reach (m).
    ca, cb : numpy.ndarray
        The two lines' offsets (m).

    Returns
    -------
    numpy.ndarray
        The overlap fractions.
    """
    band = np.minimum(ea - (ca + gra), (cb - glb) - eb)
    return np.asarray(np.minimum(ea - mb, ma - eb) / band)


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
                 frame: Frame) -> None:
        self.seabed, self.sensor, self.p, self.s, self.frame = seabed, sensor, params, stations, frame
        self.eta = params.overlap_min + params.overlap_margin
        self.hold = 1.0 - params.overlap_margin  # a crabbing fan reaches r cos ψ = r (1 - margin) across

    def nominal_z(self, s: NDArray[np.float64], c: NDArray[np.float64]) -> NDArray[np.float64]:
        if self.sensor.mounting == "auv":
            x, y = self.frame.from_sn(s, c)
            return np.asarray(self.seabed(x, y) + self.sensor.altitude_m)
        return np.full(s.size, self.p.surface_z)

    def reach(self, s: NDArray[np.float64], c: NDArray[np.float64],
              z: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        """Left and right reach, and the left and right nadir gap (zeros for a multibeam)."""
        x, y = self.frame.from_sn(s, c)
        xy = np.column_stack([x, y])
        u = self.frame.right(s)
        right = swath_reach(self.seabed, self.sensor, xy, z, u, self.p.step_m)
        left = swath_reach(self.seabed, self.sensor, xy, z, -u, self.p.step_m)
        gap = self.sensor.gap
        if gap is None:
            return left, right, np.zeros(s.size), np.zeros(s.size)
        gr = np.minimum(swath_reach(self.seabed, gap, xy, z, u, self.p.step_m), right)
        gl = np.minimum(swath_reach(self.seabed, gap, xy, z, -u, self.p.step_m), left)
        return left, right, gl, gr

    def trial(self, s: NDArray[np.float64], c: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        return self.reach(s, c, self.nominal_z(s, c))

    def first_bound(self, st: NDArray[np.float64],
                    lo: NDArray[np.float64]) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
        """``g(c) >= 0`` while the swath's left edge reaches the area's edge ``lo`` (a side-scan: its nadir)."""

        def g(c: NDArray[np.float64]) -> NDArray[np.float64]:
            left, _, gl, gr = self.trial(st, c)
            if self.sensor.gap is not None:
                return np.asarray(lo - (c + 0.5 * (gr - gl)))
            return np.asarray(lo - (c - self.hold * left))

        return g

    def next_bound(self, st: NDArray[np.float64], prev: dict[str, NDArray[np.float64]],
                   margin: NDArray[np.float64] | float = 0.0) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
        """``g(c) >= 0`` while the overlap with the line in front (``prev`` at the stations) is at least
        the minimum with both fans shortened by the crab margin (a side-scan: the minimum plus the margin),
        the new line displaced towards the far side by the relative navigation error ``margin`` (m)."""
        eta, k = self.eta, self.hold
        front, width = prev["c"] + prev["right"], prev["left"] + prev["right"]

        def g(c: NDArray[np.float64]) -> NDArray[np.float64]:
            left, right, gl, gr = self.trial(st, c)
            if self.sensor.gap is None:  # both fans crabbing: every reach r cos ψ = k r, the overlap of those
                edge = prev["c"] + k * prev["right"] - margin
                return np.asarray(edge - (c - k * left) - self.p.overlap_min * k * np.minimum(width, left + right))
            ma = prev["c"] + 0.5 * (prev["gr"] - prev["gl"])
            mb = c + 0.5 * (gr - gl)
            band = np.minimum(front - (prev["c"] + prev["gr"]), (c - gl) - (c - left))
            return np.asarray(np.minimum(front - mb, ma - (c - left)) - margin - eta * band)

        return g

    def depth_profile(self, c: NDArray[np.float64], first: int, last: int) -> NDArray[np.float64]:
        """Sensor elevation along a line: surface, or seabed + altitude within the pitch limit."""
        z = np.full(self.s.size, np.nan)
        a = slice(first, last + 1)
        if self.sensor.mounting != "auv":
            z[a] = self.p.surface_z
            return z
        x, y = self.frame.from_sn(self.s[a], c[a])
        arc = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))])
        target = self.seabed(x, y) + self.sensor.altitude_m
        z[a] = np.minimum(lower_envelope(arc, target, math.tan(math.radians(self.p.pitch_max_deg))),
                          self.p.surface_z)
        return z


def _cross_sections(area: shapely.Polygon, s: NDArray[np.float64],
                    frame: Frame) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The area's extent across over the strip of every station (half-way to its neighbours either side).

    The strip, not the cut at the station alone, so a corner or a slanted edge between two stations is
    inside the extent the swaths must reach.  NaN where a strip misses the area.
    """
    rot = frame.area_sn(area)
    _, n0, _, n1 = rot.bounds
    half = 0.5 * (s[1] - s[0]) if s.size > 1 else 0.5
    strips = shapely.box(s - half, n0 - 1.0, s + half, n1 + 1.0)
    parts = shapely.intersection(strips, rot)
    b = shapely.bounds(parts)
    empty = shapely.is_empty(parts) | ~(shapely.area(parts) > 0)
    lo, hi = b[:, 1].copy(), b[:, 3].copy()
    lo[empty], hi[empty] = np.nan, np.nan
    return lo, hi


def _first_line(pl: _Placer, st: NDArray[np.float64], lo: NDArray[np.float64],
                step: float) -> NDArray[np.float64]:
    """Largest offsets of the first line at the stations ``st``."""
    left, _, gl, gr = pl.trial(st, lo)
    if pl.sensor.gap is not None:
        pad = 1.0 + float(np.max(np.abs(gr - gl))) + 10.0 * step
        return _bisect_max(pl.first_bound(st, lo), lo - pad, lo + pad)
    return _bisect_max(pl.first_bound(st, lo), lo, lo + 1.0 + 2.0 * float(np.max(left)) + 10.0 * step)


def place_lines(seabed: Seabed, area: shapely.Polygon, sensor: Sensor, heading: float,
                params: LineParams, frame: Frame | None = None) -> SurveyLines:
    """Place the depth-adaptive lines of a survey of ``area`` along ``heading`` (or along a frame).

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
    frame : Frame, optional
        The line frame (a corridor's :class:`~auvplan.survey.lines.frame.CurveFrame`); default straight along
        ``heading``.

    Returns
    -------
    SurveyLines
        The lines, left to right across the nominal direction.
    """
    fr = frame if frame is not None else StraightFrame(heading)
    s0, _, s1, _ = fr.area_sn(area).bounds
    k = max(2, int(math.ceil((s1 - s0) / params.station_m)) + 1)
    s = np.linspace(s0, s1, k)
    lo, hi = _cross_sections(area, s, fr)
    inside = np.isfinite(lo)
    pl = _Placer(seabed, sensor, params, s, fr)
    bend = math.tan(math.radians(params.max_bend_deg))
    front = np.full(k, -np.inf)  # how far the swaths in front cover (a side-scan: the latest nadir)
    prev = {key: np.full(k, np.nan) for key in ("c", "left", "right", "gl", "gr")}
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
        cmax = np.full(k, np.inf)
        if not lines:
            cmax[idx] = _first_line(pl, st, lo[idx], params.step_m)
        else:
            at = {key: v[idx] for key, v in prev.items()}
            span = 3.0 * float(np.nanmax(at["left"] + at["right"])) + 10.0 * params.step_m
            margin = np.zeros(k)
            if params.nav_rel_per_m > 0.0:
                m = nav_margin(fr, s, lines[-1], len(lines) % 2 == 1, params, span)[idx]
                margin[idx] = np.where(np.isfinite(m), m, np.nanmax(m, initial=0.0))  # (an older line's stations)
            cmax[idx] = _bisect_max(pl.next_bound(st, at, margin[idx]), at["c"], at["c"] + span)
        c = upper_envelope(s, cmax, bend) if bend > 0 else np.full(k, float(np.min(cmax[idx])))
        z = pl.depth_profile(c, first, last)
        left, right, gl, gr = (np.full(k, np.nan) for _ in range(4))
        a = slice(first, last + 1)
        left[a], right[a], gl[a], gr[a] = pl.reach(s[a], c[a], z[a])
        side = sensor.gap is not None
        lines.append(SurveyLine(c, z, left, right, first, last, gl if side else None, gr if side else None,
                                margin if lines and params.nav_rel_per_m > 0.0 else None))
        front[a] = c[a] + 0.5 * (gr[a] - gl[a]) if side else c[a] + pl.hold * right[a]
        for key, v in (("c", c), ("left", left), ("right", right), ("gl", gl), ("gr", gr)):
            prev[key][a] = v[a]
    complete = not (inside & (front < hi)).any()
    return SurveyLines(fr.heading, s, lo, hi, tuple(lines), complete, frame)
