"""A polyline route with an active leg: along-track and cross-track errors and progress.

Cross-track error ``e`` is positive to the right (starboard) of the leg direction; the leg's
course is a compass angle.  The active leg advances when the vehicle is within the switch radius
of its end, or past it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...geometry import as_points

__all__ = ["RouteTracker", "RoutePoint", "PathFollower", "crab_heading"]


def crab_heading(course: float, current: Sequence[float] | NDArray[np.float64], speed: float,
                 tail: bool = False) -> float:
    """Heading that makes good ``course`` over ground through a horizontal ``current``.

    The crab angle β = asin(c⊥ / u) turns the bow into the current component c⊥ across the
    course (positive to starboard) so that the through-water velocity at ``speed`` u cancels it;
    |c⊥| ≥ u is clipped to a 90° crab (the course cannot be made good).  ``tail``: the other heading
    that cancels c⊥, pointing *against* the course (``course + π + β``, the far root of the crab
    equation): the vehicle is carried along the course by a current stronger than itself
    (a tail-first leg of the time-optimal planner, :mod:`auvplan.planners.timeopt.tail`).

    Parameters
    ----------
    course : float
        Desired course over ground (compass, rad).
    current : sequence of float
        Current (east, north, ...) at the vehicle (m/s); only the horizontal part is used.
    speed : float
        Through-water speed (m/s).
    tail : bool, default False
        Head against the course (the far root).

    Returns
    -------
    float
        Commanded heading (compass, rad), ``course − β`` (``course + π + β`` tail-first).
    """
    c_right = current[0] * math.cos(course) - current[1] * math.sin(course)
    beta = math.asin(max(-1.0, min(1.0, c_right / max(speed, 1e-6))))
    return course + math.pi + beta if tail else course - beta


class RoutePoint:
    """Where the vehicle stands relative to its route (plain attributes, no logic).

    Parameters
    ----------
    leg : int
        Index of the active leg (waypoint ``leg`` to ``leg + 1``).
    along : float
        Along-track distance from the leg's start (m).
    cross : float
        Cross-track error, positive to starboard of the leg direction (m).
    course : float
        Compass course of the leg (rad).
    progress : float
        Horizontal distance made good along the whole route (m).
    z_ref : float
        Route elevation at the along-track position (m, up positive).
    gamma : float
        Flight-path angle of the leg (rad, up positive).
    last : bool
        Whether the active leg is the last one.
    """

    __slots__ = ("leg", "along", "cross", "course", "progress", "z_ref", "gamma", "last")

    def __init__(self, leg: int, along: float, cross: float, course: float, progress: float, z_ref: float,
                 gamma: float, last: bool) -> None:
        self.leg, self.along, self.cross, self.course = leg, along, cross, course
        self.progress, self.z_ref, self.gamma, self.last = progress, z_ref, gamma, last


class RouteTracker:
    """Track progress along a polyline of waypoints (``reset()`` to start again).

    Parameters
    ----------
    waypoints : array_like
        ``(N, 3)`` waypoints in the local frame (m), N ≥ 2; repeated points are dropped.
    switch_radius : float
        The active leg advances when the vehicle is this close to its end along the track (m).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs to fly tail-first (none by default).
    """

    def __init__(self, waypoints: ArrayLike, switch_radius: float, tail: ArrayLike | None = None) -> None:
        w = as_points(waypoints, "waypoints").reshape(-1, 3)
        if w.shape[0] < 2:
            raise ValueError("a route needs at least two waypoints")
        keep = np.r_[True, np.linalg.norm(np.diff(w, axis=0), axis=1) > 1e-9]
        self.w = w[keep]
        legs = np.zeros(w.shape[0] - 1, dtype=bool) if tail is None else np.asarray(tail, dtype=bool).reshape(-1)
        if legs.size != w.shape[0] - 1:
            raise ValueError(f"tail has {legs.size} flags for {w.shape[0] - 1} legs")
        #: Legs flown tail-first (heading against the leg, :func:`crab_heading`).
        self.tail: list[bool] = legs[keep[1:]].tolist()
        d = np.diff(self.w, axis=0)
        self.length = np.hypot(d[:, 0], d[:, 1])
        self.course = np.arctan2(d[:, 0], d[:, 1])
        self.gamma = np.arctan2(d[:, 2], np.maximum(self.length, 1e-9))
        self.cum = np.r_[0.0, np.cumsum(self.length)]
        self.switch_radius = float(switch_radius)
        self.k = 0
        self.kd = 0
        # the per-step look-ups on Python floats (numpy scalars cost several times more per operation)
        self._w, self._len, self._cum = self.w.tolist(), self.length.tolist(), self.cum.tolist()
        self._course, self._gamma = self.course.tolist(), self.gamma.tolist()
        self._cs = [(math.cos(c), math.sin(c)) for c in self._course]

    @property
    def total_length(self) -> float:
        """Horizontal length of the route (m)."""
        return float(self.cum[-1])

    def reset(self) -> None:
        """Back to the first leg."""
        self.k = 0
        self.kd = 0

    def _locate(self, x: float, y: float, k: int) -> tuple[float, float]:
        a = self._w[k]
        c, s = self._cs[k]
        dx, dy = x - a[0], y - a[1]
        along = dx * s + dy * c
        cross = dx * c - dy * s
        return along, cross

    def update(self, x: float, y: float) -> RoutePoint:
        """Advance the active leg if due and return the vehicle's route coordinates.

        Parameters
        ----------
        x, y : float
            Vehicle position east and north (m).

        Returns
        -------
        RoutePoint
            Active leg, along- and cross-track position, progress and reference depth.
        """
        lengths, w = self._len, self._w
        last = len(lengths) - 1
        while self.k < last:
            along, _ = self._locate(x, y, self.k)
            if along >= lengths[self.k] - (0.0 if self.tail[self.k] else self.switch_radius):  # (a tail-first
                # leg is slow: it is held to its end, where the next heading needs no turn ahead of time)
                self.k += 1
            else:
                break
        k = self.k
        along, cross = self._locate(x, y, k)
        if k >= self.kd + 2:
            self.kd = self._nearest_leg(x, y, self.kd, k)
        if k >= self.kd + 2:
            # switched past legs shorter than the switch radius: the vehicle still lies over leg kd, so
            # its depth stays between that leg's ends (the envelope every mission is checked under)
            j = self.kd + 1
            z_ref, gamma = w[j][2], self._gamma[j]
        else:
            frac = min(max(along / lengths[k], 0.0), 1.0) if lengths[k] > 0 else 1.0
            z_ref, gamma = w[k][2] + frac * (w[k + 1][2] - w[k][2]), self._gamma[k]
        progress = self._cum[k] + min(max(along, 0.0), lengths[k])
        return RoutePoint(k, along, cross, self._course[k], progress, z_ref, gamma, k == last)

    def _nearest_leg(self, x: float, y: float, first: int, last: int) -> int:
        """The leg among ``first`` … ``last`` horizontally nearest the vehicle (the later one on ties)."""
        best, best_d = first, math.inf
        for j in range(first, last + 1):
            along, cross = self._locate(x, y, j)
            off = along - min(max(along, 0.0), self._len[j])
            d = math.hypot(off, cross)
            if d <= best_d:
                best, best_d = j, d
        return best

    def cross_track(self, points: ArrayLike) -> NDArray[np.float64]:
        """Horizontal distance of points to the whole polyline.

        Parameters
        ----------
        points : array_like
            ``(N, 3)`` points (m).

        Returns
        -------
        numpy.ndarray
            ``(N,)`` distances (m), whatever the active leg.
        """
        import shapely

        pts = as_points(points)[..., :2].reshape(-1, 2)
        out = np.where(np.isnan(pts).any(axis=1), np.nan, np.inf)  # a point not at a finite place: no distance
        ok = np.flatnonzero(np.isfinite(pts).all(axis=1))
        if not ok.size:
            return out
        # the nearest leg of each point from an R-tree of the legs (GEOS's exact point-segment distance): every
        # point against every leg took 45 s after marcus-terrain-follow's flight (343 400 samples x 1 593 legs)
        legs = shapely.linestrings(np.stack([self.w[:-1, :2], self.w[1:, :2]], axis=1))
        near, dist = shapely.STRtree(legs).query_nearest(shapely.points(pts[ok]), return_distance=True,
                                                         all_matches=False)
        out[ok[near[0]]] = dist
        return out


class PathFollower(Protocol):
    """What the simulator and the local avoidance need of a path follower (LOS, ILOS, hybrid).

    Attributes
    ----------
    name : str
        Short name (``los``, ``ilos``, ``hybrid``).
    route : RouteTracker
        The route followed.
    """

    name: str
    route: RouteTracker

    def reset(self) -> None:
        """Restart the route and forget any internal state."""

    def command(self, x: float, y: float, z: float, current: Sequence[float] | NDArray[np.float64], speed: float,
                obstacles: Sequence[Sequence[float]], dt: float) -> tuple[float, bool, RoutePoint]:
        """Compute the command for one time step.

        Parameters
        ----------
        x, y, z : float
            Vehicle position (m).
        current : sequence of float
            Current velocity at the vehicle, east, north, up (m/s).
        speed : float
            Speed through the water (m/s).
        obstacles : sequence of (float, float, float)
            Nearby obstacles as ``(cx, cy, surface distance)`` (m).
        dt : float
            Time step (s).

        Returns
        -------
        command : float
            Commanded compass heading (rad).
        is_heading : bool
            True: the command is a heading (any crab angle already applied).
        point : RoutePoint
            The vehicle's position relative to the route.
        """
        ...
