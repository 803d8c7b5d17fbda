"""Predictive local avoidance of moving obstacles (issue #21; document 004 and beyond).

Document 004's APF (:mod:`.local`) reacts to where the obstacles *are*; an obstacle closing
head-on at 2 m/s is then dodged by a few metres and hit.  This variant acts on where they *will
be*:

1. **Prediction**: each sensed obstacle (within ``sensor_range`` of its surface) gets a
   velocity — the scenario's (``velocity = "known"``) or the least-squares slope of its centres
   sensed over the last ``track_window`` s (``"track"``, as a sonar tracker would) — and its
   time and distance of closest approach to the vehicle on its present velocity
   (:func:`.vo.closest_approach`).
2. **Predicted APF**: document 004's repulsion law |F_rep| = k₂ (1/d − 1/r) / d^w₂ acts from
   the obstacle's predicted position at closest approach with d the predicted surface distance
   (the attraction is the unit direction of the path follower's command, or toward an escape
   sub-goal, so d(p, g)^w₃ = 1): the preferred direction.
3. **Velocity obstacles** (:func:`.vo.vo_choose`): heading (every 10°), pitch (within ±80 % of
   the vehicle's pitch limit, where the depth band and the altitude margin allow) and speed
   (cruise, ``max_speed``, 60 % of cruise) commands, each flown with the vehicle's real turn
   rate; the one closest to the preferred direction among those that keep ``margin`` from
   every obstacle over ``horizon`` s is commanded.  While the path follower's own command
   keeps twice the margin over twice the horizon, it keeps control (depth included).
4. **Escapes**: document 004's local-minimum count and random free sub-goal, plus the
   simulation's stall hook (:meth:`.local.LocalAvoidance.stalled`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._types import RngLike
from ...vehicles import VehicleParams
from ...world import World
from ..following.route import PathFollower, RoutePoint
from .local import AvoidanceParams, LocalAvoidance
from .sweep import SweepMemory
from .turning import arc_chords, turn_rate
from .vo import CFG, predicted_preference_windows, vo_choose_windows

__all__ = ["TrackEstimator", "PredictiveAvoidance"]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""

# the seabed coefficients of a world without one: read-only like a Terrain's, so that vo_choose_windows is
# compiled once (numba types a writable array apart from a read-only one: a second ~5 s compile)
_NO_SEABED = np.zeros((1, 1, 4))
_NO_SEABED.setflags(write=False)

WEIGHTS = np.array([0.5, 0.3, 0.15, 0.3, 0.6])
"""Costs of a safe candidate beyond its angle to the preferred direction (rad per unit):
relative speed change, pitch change (rad), change from the previous choice (rad), clearance
shortfall below twice the margin (fraction), crossing ahead of a moving obstacle (once; the
give-way rule of the road, COLREG rule 15: pass astern)."""

VERTICAL_BUFFER = 5.0
"""Extra metres kept inside the depth band and above the altitude margin by vertical manoeuvres."""


class TrackEstimator:
    """Velocities of sensed obstacles from their recent centres (least-squares slope).

    ``update(i, t, centre)`` records a sighting of obstacle ``i``; ``velocity(i)`` fits a
    straight line to the sightings of the last ``window`` seconds (zero with fewer than two).

    Parameters
    ----------
    window : float
        Length of the sighting history used (s).
    """

    def __init__(self, window: float) -> None:
        self.window = window
        self.tracks: dict[int, list[tuple[float, _F64]]] = {}

    def update(self, i: int, t: float, centre: ArrayLike) -> None:
        """Record obstacle ``i`` at ``centre`` at time ``t`` and forget sightings older than the window.

        Parameters
        ----------
        i : int
            Obstacle identifier.
        t : float
            Time of the sighting (s).
        centre : array_like
            ``(3,)`` sensed centre (m).
        """
        track = self.tracks.setdefault(i, [])
        if track and t - track[-1][0] > self.window:  # lost and found again: start a new track
            track.clear()
        track.append((t, np.asarray(centre, dtype=float)))
        while t - track[0][0] > self.window:
            track.pop(0)

    def velocity(self, i: int) -> _F64:
        """Estimate the velocity of obstacle ``i`` by least squares over its recent sightings.

        Parameters
        ----------
        i : int
            Obstacle identifier.

        Returns
        -------
        numpy.ndarray
            ``(3,)`` velocity (m/s); zero with fewer than two sightings.
        """
        track = self.tracks.get(i, ())
        if len(track) < 2:
            return np.zeros(3)
        ts = np.array([s[0] for s in track])
        cs = np.array([s[1] for s in track])
        tm = ts - ts.mean()
        v: _F64 = tm @ (cs - cs.mean(axis=0)) / (tm @ tm)
        return v


class PredictiveAvoidance(LocalAvoidance):
    """Prediction + predicted APF + velocity obstacles around a path follower (see the module notes).

    ``command`` returns (heading, pitch or None, route point) like :class:`.LocalAvoidance`;
    ``speed_command`` holds the commanded speed through the water.

    Parameters
    ----------
    base : PathFollower
        The path follower (LOS, ILOS, hybrid) driving while its own command stays clear.
    keys : array_like
        ``(K, 3)`` key waypoints (m).
    world : World
        Seabed, obstacles, bounds and margins.
    params : AvoidanceParams
        Avoidance parameters (horizon, margin, sensor range …).
    vehicle : VehicleParams
        The vehicle: its turn-rate, pitch and speed limits bound the candidates.
    rng : RngLike, optional
        Seed or generator of the escapes' random sub-goals.
    """

    def __init__(self, base: PathFollower, keys: ArrayLike, world: World, params: AvoidanceParams,
                 vehicle: VehicleParams, rng: RngLike = None) -> None:
        self.vehicle = vehicle
        self.r_max = vehicle.nomoto_K * math.radians(vehicle.rudder_max_deg)
        self.lag = vehicle.nomoto_T + 1.0 / vehicle.heading_wn
        self.theta_max = 0.8 * math.radians(vehicle.pitch_max_deg)
        self.speeds = np.array([vehicle.speed, vehicle.max_speed, 0.6 * vehicle.speed]) if params.speed_change \
            else np.array([vehicle.speed])
        self.offsets = np.radians(np.arange(-180.0, 180.0, 10.0))
        self.pitch_offsets = np.array([0.0, -0.5, 0.5, -1.0, 1.0]) * self.theta_max
        m, b = world.margins, world.bounds
        self.z_hi = min(b.zmax, -m.min_depth) - VERTICAL_BUFFER
        self.z_lo = max(b.zmin, -m.max_depth) + VERTICAL_BUFFER
        self.altitude = m.min_altitude + VERTICAL_BUFFER
        self.terrain = world.terrain is not None
        tk = world.terrain.kernel_data[:5] if world.terrain is not None else (_NO_SEABED, 0.0, 0.0, 1.0, 1.0)
        self.coef = tk[0]
        self.cfg = np.zeros(len(CFG))
        self.cfg[5:] = (self.r_max, self.lag, params.horizon, params.margin, self.z_lo, self.z_hi, float(self.terrain),
                        *tk[1:], self.altitude)
        super().__init__(base, keys, world, params, vehicle.speed, rng)

    def reset(self) -> None:
        """Back to route following; forget the tracks and the last choice."""
        super().reset()
        self.estimator = TrackEstimator(self.params.track_window)
        self.sweep = SweepMemory(self.params.sweep_window)
        self._last_p: np.ndarray | None = None
        self._psi_last = math.nan
        self.solves = 0
        self.solve_time = 0.0

    def command(self, pos: _F64, t: float, current: _F64, obstacles: Sequence[tuple[Any, ...]],
                dt: float) -> tuple[float, float | None, RoutePoint]:
        """Compute the commanded heading, pitch (or None) and the base route point; set ``speed_command``.

        Parameters
        ----------
        pos : numpy.ndarray
            ``(3,)`` vehicle position (m).
        t : float
            Time (s).
        current : numpy.ndarray
            ``(3,)`` current at the vehicle (m/s).
        obstacles : sequence of tuple
            Obstacles near the vehicle, as for :meth:`LocalAvoidance.command`.
        dt : float
            Time step (s).

        Returns
        -------
        heading : float
            Commanded compass heading (rad).
        pitch : float or None
            Commanded pitch (rad); None while the base follower drives.
        point : RoutePoint
            The base follower's route point.
        """
        p = np.asarray(pos, dtype=float)
        statics = [o[:3] for o in obstacles if not o[3]]
        psi_b, _, rp = self.base.command(float(p[0]), float(p[1]), float(p[2]), current, self.speed, statics, dt)
        last, self._last_p = self._last_p, p
        self.speed_command = self.speed
        sensed = [o for o in obstacles if o[3] and o[2] <= self.params.sensor_range]
        if not sensed and self.subgoal is None:
            self.mode = "route"
            return psi_b, None, rp
        cur = np.asarray(current, dtype=float)  # the velocity over ground only when a decision needs it
        v_now = (p - last) / dt if last is not None \
            else self.speed * np.array([math.sin(psi_b), math.cos(psi_b), 0.0]) + cur
        t0 = time.perf_counter()
        self.decisions += 1
        try:
            return self._decide(p, t, v_now, cur, sensed, psi_b, rp)
        finally:
            self.decision_time += time.perf_counter() - t0

    def _sensed(self, t: float, sensed: Sequence[tuple[Any, ...]], p: _F64) -> tuple[_F64, _F64, _F64, _F64]:
        """Centres, velocities, radii (+ the obstacle margin) and time windows of the predicted obstacles: the
        sensed ones (a turning one as the chords of its CTRV arc, :mod:`.turning`) and the shuttles' images
        (:mod:`.sweep`)."""
        C, V, R = self._straight(t, sensed, p)
        W = np.zeros((len(R), 2))
        W[:, 1] = math.inf
        if not self.params.turn_model:
            return C, V, R, W
        keep, parts = np.ones(len(R), dtype=bool), []
        for k, o in enumerate(sensed):
            omega = turn_rate(self.sweep.tracks.get(o[5], ()), t)
            if omega != 0.0:
                keep[k] = False
                parts.append(arc_chords(C[k], V[k], float(R[k]), omega, 2.0 * self.params.horizon,
                                        growth=self.params.turn_growth))
        if not parts:
            return C, V, R, W
        return (np.vstack([C[keep]] + [q[0] for q in parts]), np.vstack([V[keep]] + [q[1] for q in parts]),
                np.concatenate([R[keep]] + [q[2] for q in parts]), np.vstack([W[keep]] + [q[3] for q in parts]))

    def _straight(self, t: float, sensed: Sequence[tuple[Any, ...]], p: _F64) -> tuple[_F64, _F64, _F64]:
        """Centres, velocities (known or estimated) and radii (+ the obstacle margin) of the sensed obstacles,
        and of the shuttles' images (:mod:`.sweep`)."""
        C = np.array([o[4] for o in sensed], dtype=float).reshape(-1, 3)
        R = np.array([o[7] for o in sensed], dtype=float) + self.world.margins.obstacle
        if self.params.velocity == "known":
            V = np.array([o[6] for o in sensed], dtype=float).reshape(-1, 3)
        else:
            for o, c in zip(sensed, C):
                self.estimator.update(o[5], t, c)
            V = np.array([self.estimator.velocity(o[5]) for o in sensed]).reshape(-1, 3)
        ids = [o[5] for o in sensed]
        for i, c in zip(ids, C):
            self.sweep.update(i, t, c)
        if self.params.sweep:  # shuttles' images beyond their turning points (issue #36)
            return self.sweep.images(ids, C, V, R, p)
        return C, V, R

    def _preferred(self, p: _F64, t: float, psi_b: float, rp: RoutePoint) -> tuple[_F64, float]:
        """Unit attraction (follower's command or escape sub-goal) and the undisturbed pitch."""
        if self.subgoal is not None and np.linalg.norm(self.subgoal - p) <= self.params.arrive:
            self.subgoal = None
            self.detector.reset()
        if self.mode != "route" and self.params.escape_rule == "patent":
            self._patent_escape(p, t, p)
        elif self.subgoal is None and self.mode != "route" and self.detector.update(p, t):
            self._escape(p, t, minimum=True)
        if self.subgoal is not None:
            a = self.subgoal - p
            a /= max(float(np.linalg.norm(a)), 1e-9)
            return a, min(max(math.asin(a[2]), -self.theta_max), self.theta_max)
        th = rp.gamma + math.atan(self.vehicle.depth_gain * (rp.z_ref - float(p[2])))
        th = min(max(th, -self.theta_max), self.theta_max)
        return np.array([math.cos(th) * math.sin(psi_b), math.cos(th) * math.cos(psi_b), math.sin(th)]), th

    def _solve(self, p: _F64, v_now: _F64, cur: _F64, C: _F64, V: _F64, R: _F64, W: _F64, headings: _F64,
               pitches: _F64, speeds: _F64, pref: _F64, theta_pref: float,
               horizon: float) -> tuple[int, int, int, float, bool]:
        water = v_now - cur
        cfg = self.cfg
        cfg[7] = horizon
        cfg[0] = math.atan2(water[0], water[1])
        cfg[1] = max(math.hypot(water[0], water[1]), 0.1)
        cfg[2], cfg[3] = theta_pref, self.speed
        cfg[4] = self._psi_last if math.isfinite(self._psi_last) else cfg[0]
        choice: tuple[int, int, int, float, bool] = vo_choose_windows(p, v_now, cur, C, V, R, W, headings, pitches,
                                                                      speeds, pref, self.coef, cfg, WEIGHTS)
        return choice

    def _decide(self, p: _F64, t: float, v_now: _F64, cur: _F64, sensed: Sequence[tuple[Any, ...]], psi_b: float,
                rp: RoutePoint) -> tuple[float, float | None, RoutePoint]:
        C, V, R, W = self._sensed(t, sensed, p)
        a, theta_pref = self._preferred(p, t, psi_b, rp)
        psi_a = math.atan2(a[0], a[1])
        if self.subgoal is None:  # the follower keeps control while its own command stays clear
            _, _, _, clear, safe = self._solve(p, v_now, cur, C, V, R, W, np.array([psi_b]), np.array([theta_pref]),
                                               self.speeds[:1], a, theta_pref, 2.0 * self.params.horizon)
            if safe and clear >= 2.0 * self.params.margin:
                self.mode = "route"
                self._psi_last = psi_b
                return psi_b, None, rp
        if self.mode == "route":
            self.mode = "vo"
            self.detector.reset()
        t0 = time.perf_counter()
        # document 004's repulsion from the predicted geometry at closest approach
        pr = self.params
        pref = predicted_preference_windows(p, v_now, C, V, R, W, a, pr.horizon, pr.k_rep, pr.w_obs, pr.radius)
        headings = math.atan2(pref[0], pref[1]) + self.offsets
        if math.isfinite(self._psi_last):
            headings = np.concatenate((headings, (self._psi_last, psi_a)))
        pitches = np.clip(theta_pref + self.pitch_offsets, -self.theta_max, self.theta_max) if self.params.vertical \
            else np.array([theta_pref])
        i, j, k, _, _ = self._solve(p, v_now, cur, C, V, R, W, headings, pitches, self.speeds, pref, theta_pref,
                                    self.params.horizon)
        self.solves += 1
        self.solve_time += time.perf_counter() - t0
        self._psi_last = float(headings[i])
        self.speed_command = float(self.speeds[k])
        return self._psi_last, float(pitches[j]), rp
