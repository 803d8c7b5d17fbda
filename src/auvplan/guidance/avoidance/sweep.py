"""Predicted sweep of a recurrent mover: the image of a shuttle beyond its turning point (issue #36).

Predictive avoidance (:mod:`.predictive`) extrapolates every obstacle straight on its present
velocity.  A mover that sweeps the same lane back and forth (a shuttle, a survey vessel's
lawn-mower legs, a patrol) breaks that prediction at its turning point: a vehicle trailing it down
the lane, or waiting beside the end of its lane, is safe on the straight prediction until the mover
turns round and comes back at their summed speeds — too late to get out of the lane (fast movers:
1.8–3 m/s against the vehicle's 1.5 m/s).

The sweep memory keeps every sensed obstacle's centres over ``window`` s.  A mover whose whole
remembered track lies within its radius of its present line of motion, and which has been *ahead*
of where it is now (it came back along the lane), is a shuttle: its turning point E is the farthest
remembered centre ahead along its velocity, a = (E − c)·v̂.  After turning at E (time a/|v|) its
centre is E − v (t − a/|v|) = (c + 2a v̂) − v t: a straight mover from the mirror point c + 2a v̂
with velocity −v — the method of images.  That image is added to the obstacles the velocity
obstacles and the predicted repulsion see, so the vehicle leaves the lane *before* the turn.
Before the turn the image lies beyond the lane's end, where it only keeps the vehicle off the
lane's extension (conservative).  A track seen only once (no return yet) gets the image of a turn
*now* (at its centre, velocity −v) while the vehicle trails the mover in its lane: a faster mover
pulling away down the vehicle's route may turn at any time, and the vehicle then keeps out of its lane.
"""

from __future__ import annotations

from collections import deque

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["SweepMemory"]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""


class SweepMemory:
    """Sensed centres of each obstacle over a window, and the images of shuttles at their turning points.

    Parameters
    ----------
    window : float
        Length of the remembered track (s).
    every : float
        Interval between remembered centres (s).
    """

    def __init__(self, window: float, every: float = 1.0) -> None:
        self.window, self.every = window, every
        self.tracks: dict[int, deque[tuple[float, _F64]]] = {}

    def update(self, i: int, t: float, centre: ArrayLike) -> None:
        """Remember obstacle ``i`` at ``centre`` at time ``t`` (every ``every`` s) and forget older centres.

        Parameters
        ----------
        i : int
            Obstacle identifier.
        t : float
            Time (s).
        centre : array_like
            ``(3,)`` sensed centre (m).
        """
        track = self.tracks.setdefault(i, deque())
        if track and t - track[-1][0] < self.every:
            return
        track.append((t, np.asarray(centre, dtype=float).copy()))
        while t - track[0][0] > self.window:
            track.popleft()

    def turning_distance(self, i: int, centre: ArrayLike, velocity: ArrayLike, radius: float) -> float:
        """Distance ahead (m) to the turning point of shuttle ``i``, or 0 when it is not a shuttle.

        Parameters
        ----------
        i : int
            Obstacle identifier.
        centre : array_like
            ``(3,)`` its centre now (m).
        velocity : array_like
            ``(3,)`` its velocity now (m/s).
        radius : float
            Its radius (m): the lane's half-width.

        Returns
        -------
        float
            a = (E − c)·v̂ > 0 for a shuttle whose remembered track lies within ``radius`` of its line
            of motion and reaches ahead of it; 0 otherwise.
        """
        track = self.tracks.get(i)
        v = np.asarray(velocity, dtype=float)
        speed = float(np.linalg.norm(v))
        if not track or len(track) < 3 or speed < 1e-6:
            return 0.0
        rel = np.array([c for _, c in track]) - np.asarray(centre, dtype=float)
        u = v / speed
        along = rel @ u
        lateral = np.linalg.norm(rel - along[:, None] * u, axis=1)
        if lateral.max() > radius:
            return 0.0  # not a lane: an orbit, a wander or a turn
        a = float(along.max())
        return a if a > 0.5 * radius else 0.0

    def images(self, ids: ArrayLike, C: ArrayLike, V: ArrayLike, R: ArrayLike,
               p: ArrayLike | None = None) -> tuple[_F64, _F64, _F64]:
        """The obstacles ``(C, V, R)`` followed by the images of the shuttles among them.

        Parameters
        ----------
        p : array_like, optional
            ``(3,)`` vehicle position (m): a mover whose turning point is not known yet gets the image
            of a turn *now* (at its centre, velocity −v) while the vehicle trails it in its lane
            (behind it, within twice its radius of its line of motion).
        ids : array_like
            ``(M,)`` obstacle identifiers.
        C, V : array_like
            ``(M, 3)`` centres (m) and velocities (m/s).
        R : array_like
            ``(M,)`` radii (m).

        Returns
        -------
        C, V, R : numpy.ndarray
            The obstacles and, appended, one image per shuttle: centre c + 2a v̂, velocity −v, same radius.
        """
        C = np.asarray(C, dtype=float).reshape(-1, 3)
        V = np.asarray(V, dtype=float).reshape(-1, 3)
        R = np.asarray(R, dtype=float).reshape(-1)
        extra_c, extra_v, extra_r = [], [], []
        for k, i in enumerate(np.asarray(ids).reshape(-1)):
            a = self.turning_distance(int(i), C[k], V[k], float(R[k]))
            if a == 0.0 and p is not None and np.linalg.norm(V[k]) > 0.05:
                u = V[k] / np.linalg.norm(V[k])
                rel = np.asarray(p, dtype=float) - C[k]
                behind = float(rel @ u)
                if behind < 0.0 and np.linalg.norm(rel - behind * u) < 2.0 * R[k]:
                    a = 1e-9  # trailing in its lane: image of a turn now
            if a > 0.0:
                extra_c.append(C[k] + 2.0 * a * V[k] / np.linalg.norm(V[k]))
                extra_v.append(-V[k])
                extra_r.append(R[k])
        if not extra_c:
            return C, V, R
        return np.vstack([C, extra_c]), np.vstack([V, extra_v]), np.r_[R, extra_r]
