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

from .lines import SurveyLines, from_sn, to_sn
from .swath import Seabed, Sensor, swath_reach

__all__ = ["Coverage", "footprints", "measure", "lawnmower", "Lawnmower", "fan_right"]


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
        quads = np.stack([left[:-1], left[1:], rgt[1:], rgt[:-1], left[:-1]], axis=1)
        polys = shapely.make_valid(shapely.polygons(quads))
        out.append(shapely.union_all(polys, grid_size=None).buffer(0))
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
        Area of the survey polygon (m²).
    """

    coverage_pct: float
    overlap: list[NDArray[np.float64]]
    gaps: list[shapely.Polygon]
    footprints: list[shapely.Geometry]
    area_m2: float

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


def _cut_spans(fp: shapely.Geometry, s: NDArray[np.float64], heading: float) -> NDArray[np.float64]:
    """``(K, 2)`` across extent of a footprint on the cut at every station (NaN where it misses)."""
    out = np.full((s.size, 2), np.nan)
    if fp.is_empty:
        return out
    sh, ch = math.sin(heading), math.cos(heading)
    rot = shapely.affinity.affine_transform(fp, [sh, ch, ch, -sh, 0.0, 0.0])  # (x, y) -> (s, n)
    b = rot.bounds
    cuts = shapely.linestrings(np.stack([np.column_stack([s, np.full(s.size, b[1] - 1.0)]),
                                         np.column_stack([s, np.full(s.size, b[3] + 1.0)])], axis=1))
    parts = shapely.intersection(cuts, rot)
    bounds = shapely.bounds(parts)
    ok = ~shapely.is_empty(parts)
    out[ok] = bounds[ok][:, [1, 3]]
    return out


def measure(area: shapely.Polygon, lines: SurveyLines, fps: list[shapely.Geometry],
            min_gap_m2: float = 1.0) -> Coverage:
    """Coverage, per-pair overlap and gaps of footprints over the area.

    Parameters
    ----------
    area : shapely.Polygon
        The survey area (m).
    lines : SurveyLines
        The planned lines (their stations, heading and the area's cross-sections).
    fps : list of shapely geometry
        Footprint of every line, in placement order.
    min_gap_m2 : float
        Gaps smaller than this (numerical slivers along shared edges) are not listed; the coverage
        counts every uncovered square metre.

    Returns
    -------
    Coverage
        The measures.
    """
    union = shapely.union_all([f for f in fps if not f.is_empty])
    missing = area.difference(union) if not union.is_empty else area
    cover = 100.0 * (1.0 - missing.area / area.area)
    gaps = [g for g in shapely.get_parts(missing) if isinstance(g, shapely.Polygon) and g.area >= min_gap_m2]
    spans = [_cut_spans(f, lines.stations, lines.heading) for f in fps]
    lo, hi = lines.area_lo, lines.area_hi
    overlap = []
    for a, b in zip(spans[:-1], spans[1:], strict=True):
        ea, eb = a[:, 1], b[:, 0]
        with np.errstate(invalid="ignore"):
            inside = (np.minimum(ea, eb) < hi) & (np.maximum(ea, eb) > lo)
            eta = (ea - eb) / np.minimum(a[:, 1] - a[:, 0], b[:, 1] - b[:, 0])
        keep = inside & np.isfinite(eta)
        overlap.append(eta[keep])
    return Coverage(cover, overlap, gaps, fps, float(area.area))


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
              surface_z: float, run_in_m: float, grid_m: float = 0.0) -> Lawnmower:
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
        Sampling of the seabed inside the area (m); default 1/100 of the area's size.

    Returns
    -------
    Lawnmower
        The lanes' count, spacing and length.
    """
    x0, y0, x1, y1 = area.bounds
    g = grid_m or max(x1 - x0, y1 - y0) / 100.0
    gx, gy = np.meshgrid(np.arange(x0, x1 + g, g), np.arange(y0, y1 + g, g))
    inside = shapely.contains_xy(area, gx, gy)
    zb = seabed(gx[inside], gy[inside])
    top = float(np.max(zb))
    height = sensor.altitude_m if sensor.mounting == "auv" else surface_z - top
    width = 2.0 * float(sensor.flat_reach(height))
    spacing = (1.0 - overlap_min) * width
    ring = np.asarray(area.exterior.coords)
    s, n = to_sn(ring[:, 0], ring[:, 1], heading)
    span = float(np.ptp(n))
    count = max(1, int(math.ceil(max(span - width, 0.0) / spacing)) + 1)
    offsets = float(n.min()) + width / 2.0 + spacing * np.arange(count)
    big = float(np.ptp(s)) + 2.0
    total = 0.0
    for c in offsets:
        xa, ya = from_sn(np.array([s.min() - 1.0, s.min() - 1.0 + big]), np.array([c, c]), heading)
        cut = shapely.intersection(shapely.LineString(np.column_stack([xa, ya])), area)
        if not cut.is_empty:
            total += cut.length + 2.0 * run_in_m
    return Lawnmower(count, spacing, total, -top)
