"""The predicted error drawn along a mission: the band the vehicle may be in, and the error against time
(issue 52 item 6; ``docs/navigation.md``).

The band is the union, over the route, of the horizontal discs of radius confidence × σ round each
point.  Between two samples σ grows (a fix only lowers it, at a sample), and it is drawn as the convex
hull of the two end discs: the union of the discs whose centre and radius move linearly between them.
The samples kept are at most ``max_intervals`` evenly spread ones, and every fix with the sample before
it, so each reset shows.
"""

from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import ArrayLike

from .._types import FloatArray, IntArray
from .budget import ErrorProfile

__all__ = ["error_band", "profile_times", "band_samples"]


def band_samples(profile: ErrorProfile, max_intervals: int = 800) -> IntArray:
    """The samples the band is drawn through: evenly spread, with every fix and the sample before it.

    Parameters
    ----------
    profile : ErrorProfile
        The error along the mission.
    max_intervals : int, optional
        About how many intervals (fixes add theirs).

    Returns
    -------
    numpy.ndarray of int
        Increasing sample indices, first and last included.
    """
    m = profile.s_m.size
    every = max(1, int(np.ceil((m - 1) / max(max_intervals, 1))))
    fix = np.flatnonzero(profile.fix)
    keep = np.unique(np.r_[np.arange(0, m, every), m - 1, fix, np.maximum(fix - 1, 0)])
    out: IntArray = keep.astype(np.intp)
    return out


def error_band(profile: ErrorProfile, max_intervals: int = 800, quad_segs: int = 8) -> shapely.Geometry:
    """The horizontal band within the predicted error of a mission (a polygon in the local frame).

    Parameters
    ----------
    profile : ErrorProfile
        The error along the mission (:func:`~auvplan.nav.budget.error_profile`).
    max_intervals : int, optional
        About how many intervals the band is built from.
    quad_segs : int, optional
        Segments per quarter circle of each disc (shapely's ``buffer``).

    Returns
    -------
    shapely.Geometry
        A Polygon (or MultiPolygon): the union over the route of the discs of radius confidence × σ.
    """
    k = band_samples(profile, max_intervals)
    xy = profile.xyz[k, :2]
    if k.size < 2:
        return shapely.buffer(shapely.points(xy[0]), float(profile.after_m[k[0]]), quad_segs=quad_segs)
    pts = shapely.points(xy)
    start = shapely.buffer(pts[:-1], profile.after_m[k[:-1]], quad_segs=quad_segs)
    end = shapely.buffer(pts[1:], profile.before_m[k[1:]], quad_segs=quad_segs)
    hulls = shapely.convex_hull(shapely.union(start, end))
    return shapely.union_all(hulls)


def profile_times(profile: ErrorProfile, speed: float, dwell_s: ArrayLike | float = 0.0,
                  points: ArrayLike | None = None, vertex_times_s: ArrayLike | None = None) -> FloatArray:
    """Planned time at each sample: the distance travelled at the cruise speed and the dwells at the fixes
    passed before it (the dwell at a fix follows its sample); or, given the waypoints' planned arrivals (through
    the current at the legs' speeds), those at the waypoints and linear in the distance along each leg.

    Parameters
    ----------
    profile : ErrorProfile
        The error along the mission.
    speed : float
        Cruise speed (m/s).
    dwell_s : array_like or float, optional
        Time held at each fix, in order (or one value for all; s).
    points : array_like, optional
        ``(N, 3)`` the mission's waypoints (the profile's), with ``vertex_times_s``.
    vertex_times_s : array_like, optional
        ``(N,)`` planned arrival at each waypoint (s; :attr:`auvplan.nav.NavPlan.vertex_times_s`).

    Returns
    -------
    numpy.ndarray
        ``(M,)`` seconds from the start.
    """
    fix = np.flatnonzero(profile.fix)
    held = np.broadcast_to(np.asarray(dwell_s, dtype=float), fix.shape)
    if points is not None and vertex_times_s is not None:
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        arrive = np.asarray(vertex_times_s, dtype=float).reshape(-1)
        sv = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))]
        depart = arrive.copy()  # leaving each waypoint: after the dwell of a fix there
        at_fix = np.searchsorted(sv, profile.s_m[fix] - 1e-6)  # the profile's fixes are waypoints
        np.add.at(depart, np.minimum(at_fix, depart.size - 1), held)
        # a sample at a waypoint (up to rounding) is timed on the leg that arrives there
        leg = np.clip(np.searchsorted(sv, profile.s_m - 1e-6, side="left") - 1, 0, max(sv.size - 2, 0))
        span = np.maximum(sv[leg + 1] - sv[leg], 1e-12)
        timed: FloatArray = depart[leg] + (profile.s_m - sv[leg]) / span * (arrive[leg + 1] - depart[leg])
        return timed
    extra = np.zeros(profile.s_m.size)
    np.add.at(extra, np.minimum(fix + 1, extra.size - 1), held)
    out: FloatArray = profile.s_m / speed + np.cumsum(extra)
    return out
