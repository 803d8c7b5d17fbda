"""Coverage measured on a track: the swath footprints on the seabed (shapely polygons), the coverage of
the area, the overlap of every adjacent line pair (min / median / max), the gaps as polygons, and the
comparison with a fixed-lane lawnmower sized for the shallowest depth.

A footprint is the union of the quadrilaterals between the swath edges of consecutive track samples; the
fan of each sample is across its fan direction (the vehicle's heading for a flown track, so a crab angle
in a cross-current turns the fan; the line's nominal heading for a planned route).  The overlap of two
adjacent footprints is measured at the planner's stations on cuts across the nominal heading: the shared
width over the narrower footprint's width, where the two swaths meet inside the area.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from .lines.frame import Frame, StraightFrame
from .lines.placement import SurveyLines
from .lines.swath import Seabed, Sensor, swath_reach

__all__ = ["Coverage", "footprints", "measure", "lawnmower", "Lawnmower", "fan_right", "cut_spans"]


def fan_right(heading: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit vectors to the right of compass headings.

    Parameters
    ----------
    heading : numpy.ndarray
        ``(N,)`` compass headings (rad).

    Returns
    -------
    numpy.ndarray
        ``(N, 2)`` unit vectors.
    """
    h = np.asarray(heading, dtype=float)
    return np.column_stack([np.cos(h), -np.sin(h)])


def footprints(seabed: Seabed, sensor: Sensor, points: NDArray[np.float64], right: NDArray[np.float64],
               labels: NDArray[np.int64], n_lines: int, step: float) -> list[shapely.Geometry]:
    """The swath footprint of every line.

    Parameters
    ----------
    seabed : callable
        ``zb(x, y)`` (m).
    sensor : Sensor
        Swath sensor (its mounting decides nothing here: ``points`` carry the sensor's elevation).
    points : numpy.ndarray
        ``(N, 3)`` sensor positions along the track (m).
    right : numpy.ndarray
        ``(N, 2)`` unit fan directions (to the right).
    labels : numpy.ndarray
        ``(N,)`` line of each sample (negative: not on a line).
    n_lines : int
        Number of lines.
    step : float
        Sampling step of the seabed profiles (m).

    Returns
    -------
    list of shapely geometry
        One footprint per line (empty where a line has fewer than two samples).
    """
    out = []
    for k in range(n_lines):
        idx = np.flatnonzero(labels == k)
        if idx.size < 2:
            out.append(shapely.Polygon())
            continue
        p, u = points[idx], right[idx]
        rr = swath_reach(seabed, sensor, p[:, :2], p[:, 2], u, step)
        ll = swath_reach(seabed, sensor, p[:, :2], p[:, 2], -u, step)
        left, rgt = p[:, :2] - ll[:, None] * u, p[:, :2] + rr[:, None] * u
        gap = sensor.gap
        if gap is None:
            bands = [(left, rgt)]
        else:  # a side-scan: two bands either side of the nadir gap
            gr = np.minimum(swath_reach(seabed, gap, p[:, :2], p[:, 2], u, step), rr)
            gl = np.minimum(swath_reach(seabed, gap, p[:, :2], p[:, 2], -u, step), ll)
            bands = [(left, p[:, :2] - gl[:, None] * u), (p[:, :2] + gr[:, None] * u, rgt)]
        polys = [shapely.make_valid(shapely.polygons(np.stack([a[:-1], a[1:], b[1:], b[:-1], a[:-1]], axis=1)))
                 for a, b in bands]
        out.append(shapely.union_all(np.concatenate(polys), grid_size=None).buffer(0))
    return out


@dataclass(frozen=True)
class Coverage:
    """Coverage of an area by the footprints of one survey.

    Attributes
    ----------
    coverage_pct : float
        Share of the area inside a footprint (%).
    overlap : list of numpy.ndarray
        Overlap fractions of each adjacent pair at the stations where they meet inside the area.
    gaps : list of shapely.Polygon
        The uncovered parts of the area of at least ``min_gap_m2``.
    footprints : list of shapely geometry
        Footprint of every line.
    area_m2 : float
        Area measured (m²): the survey polygon's, less ``no_go_m2``.
    no_go_m2 : float
        Area of the polygon inside charted no-go zones (m²): not surveyed, so neither covered nor a gap.
    """

    coverage_pct: float
    overlap: list[NDArray[np.float64]]
    gaps: list[shapely.Polygon]
    footprints: list[shapely.Geometry]
    area_m2: float
    no_go_m2: float = 0.0

    def pair_stats(self) -> list[dict[str, float]]:
        """Min, median and max overlap of every adjacent pair.

        Returns
        -------
        list of dict
            ``pair``, ``min_pct``, ``median_pct``, ``max_pct`` (NaN for a pair that never meets in the area).
        """
        return [{"pair": i, "min_pct": 100.0 * float(o.min()), "median_pct": 100.0 * float(np.median(o)),
                 "max_pct": 100.0 * float(o.max())} if o.size else
                {"pair": i, "min_pct": math.nan, "median_pct": math.nan, "max_pct": math.nan}
                for i, o in enumerate(self.overlap)]

    @property
    def overlap_min_pct(self) -> float:
        """Least overlap of any adjacent pair anywhere (%)."""
        vals = [o.min() for o in self.overlap if o.size]
        return 100.0 * float(min(vals)) if vals else math.nan

    @property
    def overlap_max_pct(self) -> float:
        """Largest overlap of any adjacent pair anywhere (%)."""
        vals = [o.max() for o in self.overlap if o.size]
        return 100.0 * float(max(vals)) if vals else math.nan

    @property
    def gap_area_m2(self) -> float:
        """Total uncovered area (m²)."""
        return self.area_m2 * (1.0 - self.coverage_pct / 100.0)


def cut_spans(fp: shapely.Geometry, s: NDArray[np.float64], frame: Frame,
              n_range: tuple[float, float]) -> NDArray[np.float64]:
    """``(K, 4)`` a footprint's extent on the cut across the nominal direction at every station.

    Columns: the left edge, the gap's left and right edges (a side-scan's nadir gap: the widest hole
    between the footprint's pieces on the cut; NaN when there is none), the right edge (m across).  NaN
    where the cut misses the footprint.

    Parameters
    ----------
    fp : shapely geometry
        The footprint.
    s : numpy.ndarray
        ``(K,)`` the stations (m along).
    frame : Frame
        The line frame.
    n_range : tuple of float
        The cut's extent across (m).

    Returns
    -------
    numpy.ndarray
        ``(K, 4)`` offsets across (m).
    """
    out = np.full((s.size, 4), np.nan)
    if fp.is_empty:
        return out
    xa, ya = frame.from_sn(s, np.full(s.size, n_range[0]))
    xb, yb = frame.from_sn(s, np.full(s.size, n_range[1]))
    cuts = shapely.linestrings(np.stack([np.column_stack([xa, ya]), np.column_stack([xb, yb])], axis=1))
    parts, which = shapely.get_parts(shapely.intersection(cuts, fp), return_index=True)
    keep = shapely.get_type_id(parts) == 1  # the LineString pieces of the cut inside the footprint
    parts, which = parts[keep], which[keep]
    if not parts.size:
        return out
    xy, pi = shapely.get_coordinates(parts, return_index=True)
    k = which[pi]
    p0x, p0y = frame.from_sn(s[k], np.zeros(k.size))
    r = frame.right(s[k])
    n = (xy[:, 0] - p0x) * r[:, 0] + (xy[:, 1] - p0y) * r[:, 1]
    lo, hi = np.full(parts.size, np.inf), np.full(parts.size, -np.inf)
    np.minimum.at(lo, pi, n)
    np.maximum.at(hi, pi, n)
    order = np.lexsort((lo, which))
    w, lo, hi = which[order], lo[order], hi[order]
    starts = np.flatnonzero(np.r_[True, w[1:] != w[:-1]])
    for a, b in zip(starts, np.r_[starts[1:], w.size], strict=True):
        reach = np.maximum.accumulate(hi[a:b])
        out[w[a], 0], out[w[a], 3] = lo[a], reach[-1]
        if b - a > 1:
            hole = lo[a + 1:b] - reach[:-1]
            j = int(np.argmax(hole))
            if hole[j] > 0:
                out[w[a], 1], out[w[a], 2] = reach[j], lo[a + 1 + j]
    return out


def measure(area: shapely.Polygon, lines: SurveyLines, fps: list[shapely.Geometry],
            min_gap_m2: float = 1.0, no_go: shapely.Geometry | None = None) -> Coverage:
    """Coverage, per-pair overlap and gaps of footprints over the area.

    The overlap of two adjacent footprints is measured on the cut across the nominal direction (the
    centre line's normal for a corridor) at every station both lines are placed over (not on a run-in)
    where their seam is inside the area: the share
    of the narrower swath across the track (:func:`auvplan.survey.lines.placement.pair_overlap`; a side-scan's:
    how far each swath reaches past the other's nadir gap, :func:`auvplan.survey.lines.placement.sidescan_overlap`).

    Parameters
    ----------
    area : shapely.Polygon
        The survey area (m).
    lines : SurveyLines
        The planned lines (their stations, frame and the area's cross-sections).
    fps : list of shapely geometry
        Footprint of every line, in placement order.
    min_gap_m2 : float
        Gaps smaller than this (numerical slivers along shared edges) are not listed; the coverage
        counts every uncovered square metre.
    no_go : shapely geometry, optional
        The charted no-go zones' footprints: their part of the area is left out of the coverage (of its
        denominator too) and of the gaps.

    Returns
    -------
    Coverage
        The measures.
    """
    whole = float(area.area)
    if no_go is not None and not no_go.is_empty:
        area = shapely.make_valid(area.difference(no_go))
    union = shapely.union_all([f for f in fps if not f.is_empty])
    missing = area.difference(union) if not union.is_empty else area
    cover = 100.0 * (1.0 - missing.area / area.area) if area.area > 0 else math.nan
    gaps = [g for g in shapely.get_parts(missing) if isinstance(g, shapely.Polygon) and g.area >= min_gap_m2]
    frame = lines.geom
    wmax = max([float(np.nanmax(ln.left + ln.right)) for ln in lines.lines] + [1.0])
    lim = 0.98 * frame.n_limit
    n_range = (max(float(np.nanmin(lines.area_lo)) - 3.0 * wmax - 100.0, -lim),
               min(float(np.nanmax(lines.area_hi)) + 3.0 * wmax + 100.0, lim))
    spans = [cut_spans(f, _inside_ends(lines.stations, ln.first, ln.last), frame, n_range)
             for f, ln in zip(fps, lines.lines, strict=False)]
    lo, hi = lines.area_lo, lines.area_hi
    side = lines.lines[0].gap_left is not None if lines.lines else False
    overlap = []
    for i, (a, b) in enumerate(zip(spans[:-1], spans[1:], strict=True)):
        la, lb = lines.lines[i], lines.lines[i + 1]
        both = np.zeros(lines.stations.size, dtype=bool)  # the stations both lines are placed over (no run-in)
        both[max(la.first, lb.first):min(la.last, lb.last) + 1] = True
        ea, eb = a[:, 3], b[:, 0]
        with np.errstate(invalid="ignore", divide="ignore"):
            inside = (np.minimum(ea, eb) < hi) & (np.maximum(ea, eb) > lo)
            if side:
                ma, mb = 0.5 * (a[:, 1] + a[:, 2]), 0.5 * (b[:, 1] + b[:, 2])
                band = np.minimum(ea - a[:, 2], b[:, 1] - eb)
                eta = np.minimum(ea - mb, ma - eb) / band
            else:
                eta = (ea - eb) / np.minimum(a[:, 3] - a[:, 0], b[:, 3] - b[:, 0])
        keep = inside & both & np.isfinite(eta)
        overlap.append(eta[keep])
    return Coverage(cover, overlap, gaps, fps, float(area.area), whole - float(area.area))


def _inside_ends(s: NDArray[np.float64], first: int, last: int) -> NDArray[np.float64]:
    """The stations, the line's first and last a thousandth of a station inside it.

    Without a run-in a line's footprint ends on the cut across the track at its end stations, and shapely's cut
    along that edge returns a part of it (``run_in_m = 0``: a least overlap of 13 % and a greatest of 193 % read
    for lines placed at 50 % and 10 %); a hair inside, the cut crosses the footprint.
    """
    out = np.array(s, dtype=float)
    if last > first:
        nudge = 1e-3 * (out[first + 1] - out[first])
        out[first] += nudge
        out[last] -= nudge
    return out


@dataclass(frozen=True)
class Lawnmower:
    """A fixed-lane lawnmower over the same area, sized so the shallowest depth still overlaps.

    Attributes
    ----------
    lines : int
        Number of lanes.
    spacing_m : float
        Lane spacing (m).
    line_length_m : float
        Length of the lanes inside the area plus their run-ins (m).
    shallowest_m : float
        Least water depth in the area (m).
    """

    lines: int
    spacing_m: float
    line_length_m: float
    shallowest_m: float


def lawnmower(seabed: Seabed, area: shapely.Polygon, sensor: Sensor, heading: float, overlap_min: float,
              surface_z: float, run_in_m: float, grid_m: float = 0.0, frame: Frame | None = None) -> Lawnmower:
    """The fixed-lane lawnmower of the conventional planner: one spacing for the whole area, from the swath
    over a flat seabed at the shallowest depth (surface mounting) or at the altitude (AUV mounting).

    Parameters
    ----------
    seabed : callable
        ``zb(x, y)`` (m).
    area : shapely.Polygon
        The survey area (m).
    sensor : Sensor
        Swath sensor and mounting.
    heading : float
        Compass heading of the lanes (rad), the same as the adaptive survey's.
    overlap_min : float
        Least overlap between lanes.
    surface_z : float
        Sensor elevation with the surface mounting (m).
    run_in_m : float
        Run-in at both ends of every lane (m).
    grid_m : float
        Sampling of the seabed inside the area (m); default: 10 000 samples over the area.
    frame : Frame, optional
        The lanes' frame (a corridor's: lanes parallel to the centre line); default straight along ``heading``.

    Returns
    -------
    Lawnmower
        The lanes' count, spacing and length.
    """
    x0, y0, x1, y1 = area.bounds
    g = grid_m or (max(x1 - x0, y1 - y0) if frame is None else math.sqrt(area.area)) / 100.0
    gx, gy = np.meshgrid(np.arange(x0, x1 + g, g), np.arange(y0, y1 + g, g))
    inside = shapely.contains_xy(area, gx, gy)
    # the boundary too: a strip narrower than the grid holds no grid node (np.max of nothing: a ValueError out of
    # `auvplan survey` on a 1.6 km x 12 m strip), and the shallowest water is often on the edge
    ring = shapely.get_coordinates(shapely.segmentize(area.boundary, g))
    zb = seabed(np.r_[gx[inside], ring[:, 0]], np.r_[gy[inside], ring[:, 1]])
    top = float(np.max(zb))
    height = sensor.altitude_m if sensor.mounting == "auv" else surface_z - top
    reach = float(sensor.flat_reach(height))
    gap = sensor.gap
    if gap is None:
        width, spacing = 2.0 * reach, (1.0 - overlap_min) * 2.0 * reach
    else:  # each lane's nadir gap covered by its neighbours: lanes one reach apart less the overlap
        band = reach - float(gap.flat_reach(height))
        width, spacing = 0.0, reach - overlap_min * band
    fr = frame if frame is not None else StraightFrame(heading)
    s0, n0, s1, n1 = fr.area_sn(area).bounds
    count = max(1, int(math.ceil(max(n1 - n0 - width, 0.0) / spacing)) + 1)
    # the lanes spread evenly from one side's first to the other's last (at most ``spacing`` apart), as a fixed
    # planner lays them: stepping ``spacing`` from one side put the last lane up to a spacing beyond the area, a
    # lane counted but of no length (a corridor two lanes wide read one lane's length: -28.5 km "saved")
    offsets = np.linspace(n0 + width / 2.0, n1 - width / 2.0, count) if count > 1 else np.array([(n0 + n1) / 2.0])
    ss = np.linspace(s0 - 1.0, s1 + 1.0, 2 if frame is None else max(2, int((s1 - s0) / 10.0)))
    total = 0.0
    for c in offsets:
        xa, ya = fr.from_sn(ss, np.full(ss.size, c))
        cut = shapely.intersection(shapely.LineString(np.column_stack([xa, ya])), area)
        if not cut.is_empty:
            total += cut.length + 2.0 * run_in_m * len(shapely.get_parts(cut))
    return Lawnmower(count, spacing, total, -top)
