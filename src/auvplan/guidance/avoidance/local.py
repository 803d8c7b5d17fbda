"""Local avoidance of moving obstacles with key waypoints and an APF (document 004).

Patent 004 (docs/methods.md §4):

* **Key waypoints** (step 2): walk the global path with i = first point, j = next; when the
  straight segment (i, j) collides with the terrain, store point i and set i = j − 1; at the goal
  store i and the goal.  The stored points alone rebuild a collision-free path.  The collision
  test is the exact segment test (:meth:`World.segments_free`) or the document's stepping test.
  Vectorised per stored point: all segments (i, j > i) are tested at once and the first failure
  taken.
* **Switching** (step 3): outside every moving obstacle's repulsion field the vehicle follows
  the global path; inside one it runs the APF toward the first unvisited key waypoint until it is
  within ε₁, then resumes the global path.
* **APF**: |F_att| = k₁ d(p, g)^w₁ toward g; for d(p, o) ≤ r,
  |F_rep| = k₂ (1/d(p, o) − 1/r) d(p, g)^w₃ / d(p, o)^w₂ away from the obstacle
  (d(p, o) from the obstacle surface); the next point is p + l F/|F| (point model), or F is the
  commanded direction (heading and pitch) of the vehicle.
* **Local minimum**: the count of the vehicle's own past points within r₁ of the current point
  reaching ε₂ means trapped; escape toward a random free sub-goal (seeded), then back to the key
  waypoint.  ``escape = "patent"`` is the document's rule as written (steps 3.3.2.5-3.3.2.7): a
  random obstacle-free point anywhere in the world is the sub-goal, drawn anew at every path point
  while the count says trapped, dropped as soon as it does not; ``escape = "sampled"`` (issue #36)
  draws within ``escape_radius`` at about the vehicle's depth and keeps the sub-goal until reached.

Failure modes are statuses: a key waypoint occupied by an obstacle is skipped (the next one
becomes the goal); a collision with an obstacle faster than the vehicle that was closing in is
``UNAVOIDABLE`` (reported with time and place), any other collision is ``COLLISION``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._types import RngLike, as_rng
from ...geometry import as_points
from ...world import World
from ..following.route import PathFollower, RoutePoint
from .params import AVOIDANCE, AvoidanceParams

__all__ = [
    "AVOIDANCE",
    "AvoidanceParams",
    "key_waypoints",
    "apf_force",
    "MinimumDetector",
    "LocalAvoidance",
]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""


# ---------------------------------------------------------------------- key waypoints
def key_waypoints(points: ArrayLike, world: World, method: str = "exact", step: float | None = None) -> _F64:
    """Select the waypoints of a path that hold it up (document 004 step 2).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` global path (m).
    world : World
        Seabed and static obstacles.
    method : {'exact', 'stepping'}, optional
        ``"exact"``: the World's exact segment test, static obstacles included; ``"stepping"``: the
        document's probe every ``step`` metres against the seabed only.
    step : float, optional
        Probe spacing of ``"stepping"`` (m).

    Returns
    -------
    numpy.ndarray
        ``(K, 3)`` stored points (first and last included) such that every straight segment between
        consecutive stored points is free.
    """
    p = as_points(points).reshape(-1, 3)
    if p.shape[0] < 2:
        return p.copy()
    n = p.shape[0]
    margin = world.margins.min_altitude

    def free_from(i: int) -> NDArray[np.bool_]:
        seg = np.stack([np.broadcast_to(p[i], (n - i - 1, 3)), p[i + 1:]], axis=1)
        if method == "stepping":
            if world.terrain is None:
                return np.ones(n - i - 1, dtype=bool)
            return ~world.terrain.segments_below_stepping(seg, margin, step)
        return world.segments_free(seg, moving=False)

    keys = [0]
    i = 0
    while True:
        ok = free_from(i)
        bad = np.flatnonzero(~ok)
        if bad.size == 0:
            break
        j = i + 1 + int(bad[0])  # first j whose segment (i, j) collides
        nxt = j - 1
        if nxt == i:  # even the next point is not reachable in a straight line: keep it anyway
            nxt = j
        keys.append(nxt)
        i = nxt
        if i >= n - 1:
            break
    if keys[-1] != n - 1:
        keys.append(n - 1)
    return p[keys].copy()


# ---------------------------------------------------------------------- APF kernel
def apf_force(p: ArrayLike, goal: ArrayLike, centers: ArrayLike, distances: ArrayLike,
              params: AvoidanceParams) -> _F64:
    """Return the resultant APF force at ``p`` toward ``goal`` among obstacles.

    Parameters
    ----------
    p : array_like
        ``(3,)`` position (m).
    goal : array_like
        ``(3,)`` goal (m).
    centers : array_like
        ``(M, 3)`` obstacle centres (m).
    distances : array_like
        ``(M,)`` distances from ``p`` to each obstacle surface (m); only those ≤ r repel.
    params : AvoidanceParams
        Gains and exponents.

    Returns
    -------
    numpy.ndarray
        ``(3,)`` force (the field's units; its direction is commanded).
    """
    p = np.asarray(p, dtype=float)
    to_goal = np.asarray(goal, dtype=float) - p
    dg = float(np.linalg.norm(to_goal))
    f = params.k_att * dg**params.w_att * to_goal / dg if dg > 0 else np.zeros(3)
    c = np.asarray(centers, dtype=float).reshape(-1, 3)
    d = np.asarray(distances, dtype=float).reshape(-1)
    near = d <= params.radius
    if near.any():
        dn = np.maximum(d[near], 1e-3)
        away = p - c[near]
        away /= np.maximum(np.linalg.norm(away, axis=1, keepdims=True), 1e-12)
        mag = params.k_rep * (1.0 / dn - 1.0 / params.radius) * dg**params.w_goal / dn**params.w_obs
        f = f + (mag[:, None] * away).sum(axis=0)
    return f


class MinimumDetector:
    """Counts own past points within r₁ of the current one (document 004's local-minimum test).

    Past points live in a preallocated ring buffer of ``4 ε₂`` entries (at least 50).

    Parameters
    ----------
    radius : float
        r₁ (m).
    count : int
        ε₂: that many past points within r₁ means trapped.
    every : float
        Time between remembered points (s).
    """

    def __init__(self, radius: float, count: int, every: float) -> None:
        self.radius, self.count, self.every = radius, count, every
        self.buf = np.empty((max(4 * count, 50), 3))
        self.reset()

    def reset(self) -> None:
        """Forget the history (after an escape)."""
        self.n = 0
        self.head = 0
        self._last = -math.inf
        self._trapped = False
        self.fresh = False

    def update(self, p: _F64, t: float) -> bool:
        """Remember ``p`` (every ``every`` s) and say whether the vehicle is trapped.

        Parameters
        ----------
        p : numpy.ndarray
            Current position (m); its first three entries are used.
        t : float
            Time (s).

        Returns
        -------
        bool
            True when at least ε₂ remembered points lie within r₁ of ``p``.
        """
        self.fresh = t - self._last >= self.every  # a new path point is remembered (and tested)
        if self.fresh:
            self.buf[self.head] = p[:3]
            self.head = (self.head + 1) % self.buf.shape[0]
            self.n = min(self.n + 1, self.buf.shape[0])
            self._last = t
            if self.n < self.count:
                return False
            d = self.buf[: self.n] - p[:3]
            self._trapped = int(np.count_nonzero(np.einsum("ij,ij->i", d, d) <= self.radius**2)) >= self.count
            return self._trapped
        return self.n >= self.count and self._trapped


def _random_free_point(world: World, p: ArrayLike, radius: float, t: float, rng: np.random.Generator,
                       tries: int = 64, goal: ArrayLike | None = None) -> _F64 | None:
    """A random free point within ``radius`` of ``p`` (horizontal disc at the same depth first).

    With ``goal``, the escape is planned (issue #36): of the free draws, those reached from ``p`` by a
    free straight segment (obstacles frozen at ``t``) are kept and the one with the shortest way
    ``|p − q| + |q − goal|`` taken; the first free draw when none is in sight.
    """
    ang = rng.uniform(0, 2 * np.pi, tries)
    rad = radius * np.sqrt(rng.uniform(0.25, 1.0, tries))
    dz = rng.uniform(-0.2, 0.2, tries) * radius
    cand = np.asarray(p) + np.c_[rad * np.cos(ang), rad * np.sin(ang), dz]
    ok = world.is_free(cand, t)
    if not ok.any():
        return None
    free = np.flatnonzero(ok)
    if goal is not None:
        seg = np.stack([np.broadcast_to(np.asarray(p, dtype=float), (free.size, 3)), cand[free]], axis=1)
        seen = free[world.segments_free(seg, t)]
        if seen.size:
            way = np.linalg.norm(cand[seen] - np.asarray(p), axis=1) + np.linalg.norm(cand[seen] - np.asarray(goal),
                                                                                        axis=1)
            best: _F64 = cand[int(seen[np.argmin(way)])]
            return best
    point: _F64 = cand[int(free[0])]
    return point


def _free_point_anywhere(world: World, t: float, rng: np.random.Generator, tries: int = 64,
                         rounds: int = 8) -> _F64 | None:
    """A random obstacle-free point anywhere in the world (document 004 step 3.3.2.5).

    Uniform in the world's bounds; the first of ``tries`` draws that is free (seabed, surface and
    depth margins, static obstacles, moving obstacles placed at ``t``), over at most ``rounds``
    batches; None when every draw is occupied.
    """
    b = world.bounds
    lo = np.array([b.xmin, b.ymin, b.zmin])
    hi = np.array([b.xmax, b.ymax, b.zmax])
    for _ in range(rounds):
        cand = lo + (hi - lo) * rng.uniform(0.0, 1.0, (tries, 3))
        ok = np.flatnonzero(world.is_free(cand, t))
        if ok.size:
            point: _F64 = cand[int(ok[0])]
            return point
    return None


# ---------------------------------------------------------------------- vehicle guidance
class LocalAvoidance:
    """Document 004's switching guidance wrapped around a path follower.

    ``command`` returns (heading, pitch or None, route point); pitch is None while the base
    follower drives (it then controls depth itself).

    Parameters
    ----------
    base : PathFollower
        The path follower (LOS, ILOS, hybrid) driving outside the obstacles' fields.
    keys : array_like
        ``(K, 3)`` key waypoints (:func:`key_waypoints`, m).
    world : World
        Seabed, obstacles and margins.
    params : AvoidanceParams
        The APF's parameters.
    vehicle_speed : float
        Cruise speed through the water (m/s).
    rng : RngLike, optional
        Seed or generator of the escapes' random sub-goals.
    """

    def __init__(self, base: PathFollower, keys: ArrayLike, world: World, params: AvoidanceParams,
                 vehicle_speed: float, rng: RngLike = None) -> None:
        self.base = base
        self.keys = np.asarray(keys, dtype=float)
        self.world = world
        self.params = params
        self.speed = vehicle_speed
        self.rng = as_rng(rng)
        self.detector = MinimumDetector(params.minimum_radius, params.minimum_count, params.history_dt)
        self.route = base.route
        self.name = base.name
        self.reset()

    def reset(self) -> None:
        """Back to route following from the first key waypoint."""
        self.base.reset()
        self.detector.reset()
        self.mode = "route"
        self.goal_index = 1
        self.subgoal: np.ndarray | None = None
        self.escapes = 0
        self.minimum_escapes = 0
        self.skipped = 0
        self.decisions = 0
        self.decision_time = 0.0
        self.speed_command = self.speed
        self._stall = (math.nan, math.nan, 0)
        self._trap_goal = False  # the sub-goal is the patent's escape point (dropped once not trapped)

    def _escape(self, p: _F64, t: float, scale: float = 1.0, minimum: bool = False) -> bool:
        """Document 004's escape: head for a random free sub-goal within ``scale × escape_radius``.

        With ``predictive`` avoidance the sub-goal is planned among the random draws (in sight, shortest
        way to the first unvisited key waypoint; :func:`_random_free_point`); document 004's APF keeps
        its random free point.  ``minimum``: fired by the local-minimum count
        (counted in ``minimum_escapes``) under ``escape = "sampled"``, else by the stalled route progress
        (under either rule: document 004 has no stall watch; :meth:`_patent_escape` is its own rule).
        """
        goal = self.keys[min(self.goal_index, len(self.keys) - 1)] if self.params.name == "predictive" else None
        sub = _random_free_point(self.world, p, scale * self.params.escape_radius, t, self.rng, goal=goal)
        if sub is None:
            return False
        self.detector.reset()
        self._trap_goal = False
        self.subgoal = sub
        self.escapes += 1
        self.minimum_escapes += int(minimum)
        if self.mode == "route":
            self.mode = "apf"
            self._advance_goal(p, t)
        return True

    def stalled(self, pos: ArrayLike, t: float, since: float) -> bool:
        """The route progress has not advanced since ``since`` (s): escape before any deadlock.

        Runs document 004's escape (a random free sub-goal) whenever no sub-goal is being
        followed, the k-th of one stall within k × ``escape_radius`` (a trap deeper than the
        radius is left in a few tries); returns True while the escapes still have time
        (``escape_time`` s from the first escape of this stall), False once a deadlock should be
        declared.

        Parameters
        ----------
        pos : array_like
            ``(3,)`` vehicle position (m).
        t : float
            Time (s).
        since : float
            Time the route progress last advanced (s).

        Returns
        -------
        bool
            True while escapes still have time, False when a deadlock should be declared.
        """
        if self._stall[0] != since:
            self._stall = (since, t, self.escapes)
        if t - self._stall[1] >= self.params.escape_time:
            return False
        if self.subgoal is None:
            self._escape(np.asarray(pos, dtype=float), t, 1.0 + self.escapes - self._stall[2])
        return True

    def _advance_goal(self, p: _F64, t: float) -> None:
        """First unvisited key waypoint: ahead of the vehicle, and not occupied by an obstacle."""
        k = self.goal_index
        while k < len(self.keys) - 1:
            here = self.keys[k]
            occupied = self.world.clearances(here, t)["moving"] < 0.0
            behind = np.dot(self.keys[k] - p, self.keys[min(k + 1, len(self.keys) - 1)] - self.keys[k]) < 0
            if occupied:
                self.skipped += 1
            if not (occupied or behind or np.linalg.norm(here - p) <= self.params.arrive):
                break
            k += 1
        self.goal_index = k

    def command(self, pos: _F64, t: float, current: _F64, obstacles: Sequence[tuple[Any, ...]],
                dt: float) -> tuple[float, float | None, RoutePoint]:
        """Compute the commanded heading, pitch (or None) and the base follower's route point.

        Parameters
        ----------
        pos : numpy.ndarray
            ``(3,)`` vehicle position (m).
        t : float
            Time (s).
        current : numpy.ndarray
            ``(3,)`` current at the vehicle (m/s).
        obstacles : sequence of tuple
            Obstacles near the vehicle: ``(cx, cy, surface distance, moving, centre)`` for a static one,
            ``(cx, cy, surface distance, True, centre, index, velocity, radius)`` for a moving one
            (m, m/s).
        dt : float
            Time step (s).

        Returns
        -------
        heading : float
            Commanded compass heading (rad).
        pitch : float or None
            Commanded pitch (rad, up positive); None while the base follower drives (it controls depth).
        point : RoutePoint
            The base follower's route point.
        """
        x, y, z = float(pos[0]), float(pos[1]), float(pos[2])
        near = [o for o in obstacles if o[3] and o[2] <= self.params.radius]
        psi, _, rp = self.base.command(x, y, z, current, self.speed, [o[:3] for o in obstacles if not o[3]], dt)
        if self.params.name == "none":
            return psi, None, rp
        if self.mode == "route" and near:
            self.mode = "apf"
            self._advance_goal(np.asarray(pos), t)
            self.detector.reset()
        if self.mode == "route":
            return psi, None, rp
        # APF mode
        t0 = time.perf_counter()
        self.decisions += 1
        try:
            return self._apf_command(pos, t, near, psi, rp)
        finally:
            self.decision_time += time.perf_counter() - t0

    def _patent_escape(self, p: _F64, t: float, goal: _F64) -> _F64:
        """Document 004 steps 3.3.2.5-3.3.2.7: while trapped, a new random free point anywhere at every
        path point; once not trapped, back to the first unvisited key waypoint.  Returns the goal to steer to."""
        if not self.detector.update(p, t):
            if self._trap_goal:
                self.subgoal, self._trap_goal = None, False
                key: _F64 = self.keys[self.goal_index]
                return key
            return goal
        if self.subgoal is not None and not (self._trap_goal and self.detector.fresh):
            return goal  # the same path point, or a stall escape's sub-goal (kept until reached)
        sub = _free_point_anywhere(self.world, t, self.rng)
        if sub is None:
            return goal
        if not self._trap_goal:  # a new escape; later draws while trapped re-draw the same one
            self.escapes += 1
            self.minimum_escapes += 1
        self.subgoal, self._trap_goal = sub, True
        return sub

    def _apf_command(self, pos: _F64, t: float, near: Sequence[tuple[Any, ...]], psi: float,
                     rp: RoutePoint) -> tuple[float, float | None, RoutePoint]:
        p = np.asarray(pos, dtype=float)
        goal = self.subgoal if self.subgoal is not None else self.keys[self.goal_index]
        if np.linalg.norm(goal - p) <= self.params.arrive:
            if self.subgoal is not None:
                self.subgoal = None
                self.detector.reset()
                goal = self.keys[self.goal_index]
            elif not near:
                self.mode = "route"
                return psi, None, rp
            else:
                self.goal_index = min(self.goal_index + 1, len(self.keys) - 1)
                goal = self.keys[self.goal_index]
        if self.params.escape_rule == "patent":
            goal = self._patent_escape(p, t, goal)
        elif self.subgoal is None and self.detector.update(p, t) and self._escape(p, t, minimum=True):
            goal = self.subgoal
        centers = np.array([o[4] for o in near]).reshape(-1, 3)
        dists = np.array([o[2] for o in near])
        if self.world.zones:  # the charted zones repel as static obstacles (from their nearest points)
            zc, zd = self.world.zones.exact.nearest(p, self.params.radius)
            centers, dists = np.concatenate([centers, zc]), np.concatenate([dists, np.maximum(zd, 0.0)])
        f = apf_force(p, goal, centers, dists, self.params)
        course = math.atan2(f[0], f[1])
        pitch = math.atan2(f[2], math.hypot(f[0], f[1]))
        # the seabed is respected while avoiding: never command a dive below the minimum altitude
        if self.world.terrain is not None:
            alt = float(p[2]) - self.world.terrain.elevation_at(float(p[0]), float(p[1])) \
                - self.world.margins.min_altitude
            if alt < 2.0 * self.params.arrive:
                pitch = max(pitch, math.radians(10.0) * (1.0 - alt / (2.0 * self.params.arrive)))
        return course, pitch, rp
