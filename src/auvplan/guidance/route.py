"""A polyline route with an active leg: along-track and cross-track errors and progress.

Cross-track error ``e`` is positive to the right (starboard) of the leg direction; the leg's
course is a compass angle.  The active leg advances when the vehicle is within the switch radius
of its end, or past it.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry import as_points

__all__ = ["RouteTracker", "RoutePoint", "crab_heading"]


def crab_heading(course: float, current, speed: float) -> float:
    """Heading that makes good ``course`` over ground through a horizontal ``current``.

    The crab angle β = asin(c⊥ / u) turns the bow into the current component c⊥ across the
    course (positive to starboard) so that the through-water velocity at ``speed`` u cancels it;
    |c⊥| ≥ u is clipped to a 90° crab (the course cannot be made good).

    Parameters
    ----------
    course : float
        Desired course over ground (compass, rad).
    current : sequence of float
        Current (east, north, ...) at the vehicle (m/s); only the horizontal part is used.
    speed : float
        Through-water speed (m/s).

    Returns
    -------
    float
        Commanded heading (compass, rad), ``course − β``.
    """
    c_right = current[0] * math.cos(course) - current[1] * math.sin(course)
    return course - math.asin(max(-1.0, min(1.0, c_right / max(speed, 1e-6))))


class RoutePoint:
    """Where the vehicle stands relative to its route (plain attributes, no logic)."""

    __slots__ = ("leg", "along", "cross", "course", "progress", "z_ref", "gamma", "last")

    def __init__(self, leg, along, cross, course, progress, z_ref, gamma, last):
        self.leg, self.along, self.cross, self.course = leg, along, cross, course
        self.progress, self.z_ref, self.gamma, self.last = progress, z_ref, gamma, last


class RouteTracker:
    """Tracks progress along waypoints ``(N, 3)`` (``reset()`` to start again)."""

    def __init__(self, waypoints, switch_radius: float) -> None:
        w = as_points(waypoints, "waypoints").reshape(-1, 3)
        if w.shape[0] < 2:
            raise ValueError("a route needs at least two waypoints")
        keep = np.r_[True, np.linalg.norm(np.diff(w, axis=0), axis=1) > 1e-9]
        self.w = w[keep]
        d = np.diff(self.w, axis=0)
        self.length = np.hypot(d[:, 0], d[:, 1])
        self.course = np.arctan2(d[:, 0], d[:, 1])
        self.gamma = np.arctan2(d[:, 2], np.maximum(self.length, 1e-9))
        self.cum = np.r_[0.0, np.cumsum(self.length)]
        self.switch_radius = float(switch_radius)
        self.k = 0

    @property
    def total_length(self) -> float:
        """Horizontal length of the route (m)."""
        return float(self.cum[-1])

    def reset(self) -> None:
        """Back to the first leg."""
        self.k = 0

    def _locate(self, x: float, y: float, k: int):
        a = self.w[k]
        c, s = math.cos(self.course[k]), math.sin(self.course[k])
        dx, dy = x - a[0], y - a[1]
        along = dx * s + dy * c
        cross = dx * c - dy * s
        return along, cross

    def update(self, x: float, y: float) -> RoutePoint:
        """Advance the active leg if due and return the vehicle's route coordinates."""
        last = self.length.size - 1
        while self.k < last:
            along, _ = self._locate(x, y, self.k)
            if along >= self.length[self.k] - self.switch_radius:
                self.k += 1
            else:
                break
        k = self.k
        along, cross = self._locate(x, y, k)
        frac = min(max(along / self.length[k], 0.0), 1.0) if self.length[k] > 0 else 1.0
        z_ref = float(self.w[k, 2] + frac * (self.w[k + 1, 2] - self.w[k, 2]))
        progress = float(self.cum[k] + min(max(along, 0.0), self.length[k]))
        return RoutePoint(k, along, cross, float(self.course[k]), progress, z_ref, float(self.gamma[k]), k == last)

    def cross_track(self, points) -> np.ndarray:
        """Distance of ``points (N, 3)`` to the whole polyline, horizontally (m)."""
        pts = as_points(points)[..., :2].reshape(-1, 2)
        a, b = self.w[None, :-1, :2], self.w[None, 1:, :2]
        d = b - a
        dd = np.maximum((d * d).sum(-1), 1e-12)
        out = np.empty(pts.shape[0])
        chunk = max(1, 2_000_000 // a.shape[1])  # bounded memory for long routes
        for k in range(0, pts.shape[0], chunk):
            p = pts[k:k + chunk, None, :]
            t = np.clip(((p - a) * d).sum(-1) / dd, 0.0, 1.0)
            out[k:k + chunk] = np.linalg.norm(p - (a + t[..., None] * d), axis=-1).min(axis=1)
        return out
