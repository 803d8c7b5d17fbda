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

1. the first line's largest offset with ``E⁻_k <= lo_k`` at every station (the area's edge covered); where that
   swath reaches past ``hi_k`` at every station (one swath wider than the whole area), midway between it and the
   smallest offset whose swath still reaches ``hi_k``;
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

The parameters, the lines placed and the overlap of two swaths are data of :mod:`.lineset`.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import shapely
import shapely.affinity
from numpy.typing import NDArray

from .envelope import lower_envelope, upper_envelope
from .frame import Frame, StraightFrame
from .lineset import LineParams, SurveyLine, SurveyLines, from_sn, to_sn
from .lineset import pair_overlap as pair_overlap
from .lineset import sidescan_overlap as sidescan_overlap
from .navspacing import nav_margin
from .swath import Seabed, Sensor, swath_reach

__all__ = ["LineParams", "SurveyLine", "SurveyLines", "place_lines", "upper_envelope", "lower_envelope",
           "to_sn", "from_sn", "nav_margin"]


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


def _first_line(pl: _Placer, st: NDArray[np.float64], lo: NDArray[np.float64], hi: NDArray[np.float64],
                step: float) -> NDArray[np.float64]:
    """Largest offsets of the first line at the stations ``st``; a multibeam's, where its swath reaches across the
    whole cross-section ``[lo, hi]``, centred between the offsets that reach the two edges."""
    left, _, gl, gr = pl.trial(st, lo)
    if pl.sensor.gap is not None:
        pad = 1.0 + float(np.max(np.abs(gr - gl))) + 10.0 * step
        return _bisect_max(pl.first_bound(st, lo), lo - pad, lo + pad)
    pad = 1.0 + 2.0 * float(np.max(left)) + 10.0 * step
    cmax = _bisect_max(pl.first_bound(st, lo), lo, lo + pad)
    # one swath wider than the area: its offset as far in as the left edge allows put the line up to a swath outside
    # the area (a 50 m corridor in 100 m of water: 148 m off the centre line, looping at its bends); then the middle
    # of that and the smallest offset whose right edge still reaches ``hi``.  Only where this one line is the survey
    # (its swath across every station): a tip of a wider area keeps the greedy line, the next lines' shortest

    def reaches(c: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(hi - (c + pl.hold * pl.trial(st, c)[1]))

    if not bool(np.all(reaches(cmax) < 0.0)):
        return cmax
    return 0.5 * (cmax + _bisect_max(reaches, np.minimum(hi, lo) - pad - (cmax - lo), cmax))


def _finishing(pl: _Placer, st: NDArray[np.float64], hi: NDArray[np.float64], floor: NDArray[np.float64],
               cmax: NDArray[np.float64], limit: float) -> NDArray[np.float64]:
    """``cmax`` with the offsets past ``limit`` brought in to the furthest offset any station needs to finish its
    cross-section at ``hi`` (a line brought in keeps every overlap: it only grows; one level for all, so the bend
    limit's envelope cannot pull a station that needs more, a bend's outer wedge, short of finishing)."""

    def done(c: NDArray[np.float64]) -> NDArray[np.bool_]:
        _, right, gl, gr = pl.trial(st, c)
        return np.asarray((c + 0.5 * (gr - gl) if pl.sensor.gap is not None else c + pl.hold * right) >= hi)

    a, b = np.minimum(floor, cmax), cmax.copy()
    ok = done(b)
    if not ok.any():
        return cmax
    for _ in range(40):  # the finishing side of the bracket: a line a hair short of hi would leave the station to do
        m = 0.5 * (a + b)
        fin = done(m)
        a, b = np.where(fin, a, m), np.where(fin, m, b)
    return np.where(cmax > limit, np.minimum(cmax, float(np.max(b[ok]))), cmax)


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
            cmax[idx] = _first_line(pl, st, lo[idx], hi[idx], params.step_m)
        else:
            at = {key: v[idx] for key, v in prev.items()}
            span = 3.0 * float(np.nanmax(at["left"] + at["right"])) + 10.0 * params.step_m
            margin = np.zeros(k)
            if params.nav_rel_per_m > 0.0:
                m = nav_margin(fr, s, lines[-1], len(lines) % 2 == 1, params, span)[idx]
                margin[idx] = np.where(np.isfinite(m), m, np.nanmax(m, initial=0.0))  # (an older line's stations)
            cmax[idx] = _bisect_max(pl.next_bound(st, at, margin[idx]), at["c"], at["c"] + span)
        if (cmax[idx] > fr.n_limit).any():  # past where a corridor's frame is one to one: its parallel folds at a bend
            cmax[idx] = _finishing(pl, s[idx], hi[idx], prev["c"][idx] if lines else lo[idx], cmax[idx], fr.n_limit)
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
