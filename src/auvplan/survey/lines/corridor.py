"""Corridor surveys: lines parallel to a pipeline's or cable's centre line, following its bends.

The centre line's corners are rounded (:func:`~auvplan.survey.lines.frame.round_corners`, shapely's
``offset_curve`` out and back) to a radius larger than half the corridor plus the vehicle's turn radius,
so the line frame along it (:class:`~auvplan.survey.lines.frame.CurveFrame`) is one to one over the corridor,
no line parallel to the centre line crosses itself at a bend and each turns with at least the vehicle's
radius.  The corridor is the band ``|n| <= w(s) / 2`` about the rounded centre line: shapely's flat-capped
buffer for a constant width, the band between the two offset curves for widths given per vertex
(interpolated along the line).  The lines are then placed in that frame as over any area
(:func:`~auvplan.survey.lines.placement.place_lines`): depth-adaptive, the overlap held at every station.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from .frame import CurveFrame, round_corners

__all__ = ["Corridor", "build_corridor", "default_bend_radius", "given_band"]


@dataclass(frozen=True)
class Corridor:
    """A corridor: its area, its line frame and the rounded centre line.

    Attributes
    ----------
    area : shapely.Polygon
        The band to cover (m).
    frame : CurveFrame
        The line frame along the rounded centre line.
    centerline : numpy.ndarray
        ``(K, 2)`` the rounded centre line (m).
    bend_radius_m : float
        The radius its corners were rounded to (m).
    """

    area: shapely.Polygon
    frame: CurveFrame
    centerline: NDArray[np.float64]
    bend_radius_m: float


def default_bend_radius(widths: NDArray[np.float64], turn_radius: float) -> float:
    """The default rounding radius: the vehicle's turn radius plus the widest corridor.

    Half the width keeps the outermost lines (at most half the width off the centre line) turning with the
    vehicle's radius; the other half keeps the swaths beyond them inside the one-to-one frame.

    Parameters
    ----------
    widths : numpy.ndarray
        Corridor widths (m).
    turn_radius : float
        The vehicle's least turn radius (m).

    Returns
    -------
    float
        Radius (m).
    """
    return float(turn_radius + np.max(widths))


def build_corridor(points: NDArray[np.float64], widths: NDArray[np.float64], bend_radius: float) -> Corridor:
    """The corridor about a centre line.

    Parameters
    ----------
    points : numpy.ndarray
        ``(M, 2)`` the centre line's vertices (m).
    widths : numpy.ndarray
        ``(M,)`` the full width at every vertex, or ``(1,)`` one width (m).
    bend_radius : float
        Radius the corners are rounded to (m); larger than half the widest corridor.

    Returns
    -------
    Corridor
        Area, frame and rounded centre line.
    """
    p = np.asarray(points, dtype=float)
    w = np.asarray(widths, dtype=float).reshape(-1)
    if not bend_radius > 0.5 * float(w.max()):
        raise ValueError(f"bend_radius_m = {bend_radius:g}: must exceed half the widest corridor ({w.max() / 2:g} m)")
    rounded = round_corners(p, bend_radius)
    frame = CurveFrame(rounded, n_limit=0.98 * bend_radius)
    if w.size == 1:
        area = shapely.LineString(rounded).buffer(0.5 * float(w[0]), cap_style="flat", join_style="round",
                                                  quad_segs=45)
    else:
        sv, _ = frame.to_sn(p[:, 0], p[:, 1])
        s = np.unique(np.r_[frame.s, sv])
        half = 0.5 * np.interp(s, sv, w)
        lx, ly = frame.from_sn(s, -half)
        rx, ry = frame.from_sn(s, half)
        area = shapely.make_valid(shapely.Polygon(np.r_[np.column_stack([lx, ly]), np.column_stack([rx, ry])[::-1]]))
    if not isinstance(area, shapely.Polygon) or area.is_empty:
        raise ValueError("the corridor about the centre line is not a simple band (does the line cross itself?)")
    # the band about the rounded line misses the outside of every bend of the given line (R (sec(θ/2) - 1)
    # deep: 335 m at a 90° corner rounded to 810 m): the corridor to cover is the band about the line as given
    # too, so the union is surveyed; its outer edge must stay where the frame is one to one
    area = shapely.make_valid(shapely.union(area, given_band(p, w)))
    if not isinstance(area, shapely.Polygon):
        raise ValueError("the corridor about the centre line is not a simple band (does the line cross itself?)")
    ring = np.asarray(shapely.segmentize(area, 10.0).exterior.coords)
    off = float(np.max(shapely.distance(shapely.points(ring), frame.line)))
    if off > frame.n_limit:
        raise ValueError(f"a corner is too sharp for the corridor: its outer edge lies {off:.0f} m off the centre "
                         f"line rounded to {bend_radius:.0f} m, beyond the {frame.n_limit:.0f} m where the lines' "
                         "frame is one to one (soften the corner with more vertices, or narrow the corridor)")
    return Corridor(area, frame, rounded, float(bend_radius))


def given_band(points: NDArray[np.float64], widths: NDArray[np.float64]) -> shapely.Polygon:
    """The corridor about the centre line as given (its corners not rounded), flat at its two ends.

    Every point within half the width of the polyline: shapely's flat-capped buffer with round joins for one
    width; for widths per vertex, each leg's band (the width interpolated along it) and, at every inner vertex,
    the round join on the outside of its bend: the sector of the vertex's half width between the two legs' normals
    (a whole disc there poked out past the flat end of a leg shorter than half the width: 240 m past a 60 m last
    leg of a 600 m corridor, a 'gap' where no line goes).  Repeated vertices count once.

    Parameters
    ----------
    points : numpy.ndarray
        ``(M, 2)`` the centre line's vertices (m).
    widths : numpy.ndarray
        ``(M,)`` the full width at every vertex, or ``(1,)`` one width (m).

    Returns
    -------
    shapely.Polygon
        The band (m).
    """
    p = np.asarray(points, dtype=float)
    w = np.asarray(widths, dtype=float).reshape(-1)
    if w.size == 1:
        return shapely.LineString(p).buffer(0.5 * float(w[0]), cap_style="flat", join_style="round", quad_segs=45)
    keep = np.r_[True, np.hypot(*np.diff(p, axis=0).T) > 1e-9]  # a zero-length leg has no direction
    p, w = p[keep], w[keep]
    d = np.diff(p, axis=0)
    d /= np.hypot(d[:, 0], d[:, 1])[:, None]
    right = np.column_stack([d[:, 1], -d[:, 0]])
    parts = []
    for i in range(p.shape[0] - 1):
        a, b = 0.5 * w[i] * right[i], 0.5 * w[i + 1] * right[i]
        parts.append(shapely.Polygon([p[i] - a, p[i + 1] - b, p[i + 1] + b, p[i] + a]))
    for i in range(1, p.shape[0] - 1):
        cross = float(d[i - 1, 0] * d[i, 1] - d[i - 1, 1] * d[i, 0])
        turn = math.atan2(cross, float(np.dot(d[i - 1], d[i])))  # > 0: a left turn
        if abs(turn) < 1e-9:
            continue
        out = right if turn > 0 else -right  # the outside of the bend
        a0 = math.atan2(out[i - 1, 1], out[i - 1, 0])
        phi = a0 + np.linspace(0.0, turn, max(2, int(math.ceil(abs(turn) / (math.pi / 90.0))) + 1))
        arc = p[i] + 0.5 * w[i] * np.column_stack([np.cos(phi), np.sin(phi)])
        parts.append(shapely.Polygon(np.vstack([p[i], arc])))
    return shapely.make_valid(shapely.union_all(parts))
