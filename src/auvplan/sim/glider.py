"""The closed loop of a buoyancy glider: sawtooth flight through the current at every depth.

The glider (:mod:`auvplan.vehicles.glider`) flies steady dives and climbs between
``climb_depth_m`` and ``dive_depth_m`` (at least ``min_altitude`` above the seabed, from its
altimeter), at the flight model's vertical and horizontal speeds through the water, while the
World's current at its own depth and time carries it.  It surfaces after the yos of a planned cycle
(:func:`auvplan.vehicles.glider.yos_per_cycle`: ``yos``, or with ``surface_every_s`` up to the first top at or
after that long, the first dive included), counted as the Slocum's ``yoNN.ma`` counts them
(``num_half_cycles_to_do``) whatever their time (the altimeter shortens a yo, not the count), stays
``surface_time_s`` at the surface drifting with the surface current, takes a fix, and then:

* estimates the depth-averaged current the way a Slocum does (``m_water_vx/vy``): the fix less
  its dead-reckoned position, over the time since the previous fix;
* advances its waypoint list past every waypoint within ``capture_radius_m`` of the fix;
* holds the course from the fix to the active waypoint for the cycle, the heading corrected for the
  estimated current at the cycle's mean through-water speed (so the drift at the surface is allowed
  for: the per-cycle heading a pilot sends); it dead-reckons underwater (last fix + through-water
  displacement + the estimated current) and takes the course to the next waypoint from there when
  the dead-reckoned position captures an intermediate one (Slocum's ``goto_list`` with current
  correction).  ``correct_current=False`` points the nose at the waypoint from the fix and ignores
  the current: the naive pilot's steady heading.

The mission ends at the first fix within ``capture_radius_m`` of the last waypoint.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._types import ArrayLike, FloatArray, IntArray
from ..planners.timeopt.glider import cycle
from ..vehicles.glider import GliderParams, crab_heading, yo_timing, yos_per_cycle
from ..world import World

__all__ = ["GliderTrack", "fly_glider"]

_DIVE, _CLIMB, _SURFACE = -1, 1, 0


@dataclass(frozen=True, eq=False)
class GliderTrack:
    """What the closed loop flew.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Times (s).
    xyz : ndarray, shape (N, 3)
        Positions (m).
    phase : ndarray of int, shape (N,)
        −1 diving, +1 climbing, 0 at the surface.
    fixes : ndarray, shape (M, 3)
        Time (s) and position (x, y) of every surfacing's fix.
    dac : ndarray, shape (M, 2)
        The glider's depth-averaged current estimate at each fix (m/s).
    arrived : bool
        A fix fell within the capture radius of the last waypoint.
    arrive_s : float
        Time of that fix (s; ``inf`` when not arrived).
    energy_j : float
        Hotel, surface and pump energy (J).
    pump_j : float
        Of which the pump's (J).
    inflections : int
        Bottom inflections (pump strokes).
    reach_s : float
        Time the glider first came within the capture radius of the last waypoint, between fixes too
        (s; ``inf`` when never): the time to compare with a plan's arrival.
    reason : str
        ``"arrived"``, ``"grounded"`` (over land or a seabed with no room for a yo: shallower than
        ``climb_depth_m`` + ``min_altitude``; or a climb into a seabed rising more steeply than it, whose
        altimeter turns dives only) or ``"timeout"``.
    """

    t: FloatArray
    xyz: FloatArray
    phase: IntArray
    fixes: FloatArray
    dac: FloatArray
    arrived: bool
    arrive_s: float
    energy_j: float
    pump_j: float
    inflections: int
    reach_s: float = math.inf
    reason: str = "arrived"


def _bearing(a: FloatArray, b: FloatArray) -> float:
    return math.atan2(b[0] - a[0], b[1] - a[1])


class _Flight:
    """The loop's state and its three rules: the fix, the steering, the vertical phases (mutable, internal)."""

    def __init__(self, g: GliderParams, wps: FloatArray, start: ArrayLike, t0: float, dac0: ArrayLike,
                 correct: bool, min_altitude: float, density: float) -> None:
        self.g, self.wps, self.correct, self.alt, self.rho = g, wps, correct, min_altitude, density
        self.yo = yo_timing(g, g.climb_depth_m, g.dive_depth_m, density)
        self.n = yos_per_cycle(g, self.yo)  # the planned cycle's yos, as yoNN.ma counts them (was timed since the fix)
        self.v_eff = cycle(g, density=density).speed  # the crab holds the course over the cycle, surface drift too
        self.pos = np.array([*np.asarray(start, dtype=float)[:2], 0.0])
        self.t, self.phase, self.k, self.yos = t0, _SURFACE, 0, 0
        self.surface_left = 0.0  # starts at the surface: dives at once after the first fix
        self.dac = np.asarray(dac0, dtype=float).copy()
        self.dr = self.pos[:2].copy()
        self.last_fix_t, self.course, self.heading = t0, 0.0, 0.0
        self.fixes: list[tuple[float, float, float]] = []
        self.dacs: list[FloatArray] = []
        self.pump = self.energy = 0.0
        self.inflections = 0

    def fix(self) -> bool:
        """At the surface after its time there: estimate the current, advance the waypoints, dive; True at the goal."""
        if self.fixes and self.t > self.last_fix_t:  # dr carried the old estimate
            self.dac = (self.pos[:2] - self.dr) / (self.t - self.last_fix_t) + self.dac
        self.fixes.append((self.t, self.pos[0], self.pos[1]))
        self.dacs.append(self.dac.copy())
        while self.k < len(self.wps) and math.hypot(*(self.wps[self.k] - self.pos[:2])) < self.g.capture_radius_m:
            self.k += 1
        if self.k == len(self.wps):
            return True
        self.last_fix_t, self.dr = self.t, self.pos[:2].copy()
        self.phase, self.yos = _DIVE, 0
        self.course = self.heading = _bearing(self.pos[:2], self.wps[self.k])  # (the naive pilot's heading)
        return False

    def velocity(self) -> FloatArray:
        """Through-water velocity of this step (the heading corrected for the estimated current)."""
        if self.phase == _SURFACE:
            return np.zeros(3)
        if self.correct:
            self.heading = crab_heading(self.course, self.v_eff, self.dac)
        yo = self.yo
        w, u = (yo.w_dive, yo.u_dive) if self.phase == _DIVE else (yo.w_climb, yo.u_climb)
        target = self.wps[min(self.k, len(self.wps) - 1)]
        if self.correct and self.k < len(self.wps) - 1 and math.hypot(*(target - self.dr)) < self.g.capture_radius_m:
            self.k += 1  # dead-reckoned capture of an intermediate waypoint: the course to the next from here
            self.course = _bearing(self.dr, self.wps[self.k])
        return np.array([u * math.sin(self.heading), u * math.cos(self.heading), w])

    def vertical(self, world: World, dt: float) -> bool:
        """Inflections, surfacing and the pump after a step; True when aground."""
        g, depth = self.g, -self.pos[2]
        if self.phase == _SURFACE:
            self.surface_left -= dt
            self.pos[2] = 0.0
            return False
        seabed = -float(world.seabed(np.array([self.pos[0]]), np.array([self.pos[1]]))[0])
        if self.phase == _CLIMB and depth > seabed:  # a climb into a seabed rising faster: it hits the bottom
            return True
        if self.phase == _DIVE:
            bottom = min(g.dive_depth_m, seabed - self.alt)
            if bottom < g.climb_depth_m:  # aground: land, or no room for a yo
                return True
            if depth >= bottom:
                self.pos[2] = -bottom  # the inflection (the step's overshoot of at most |w| dt is not flown)
                shallow = bottom < g.climb_depth_m + 5.0  # hardly room for a yo: climb out and surface
                self.phase, self.inflections = _CLIMB, self.inflections + 1
                self.yos = self.n if shallow else self.yos + 1
                e = self.rho * 9.81 * bottom * 2e-6 * g.ballast_cc / g.pump_efficiency
                self.pump, self.energy = self.pump + e, self.energy + e
        else:
            due = self.yos >= self.n
            if depth <= (0.0 if due else g.climb_depth_m):
                self.pos[2] = 0.0 if due else -g.climb_depth_m
                if due:
                    self.phase, self.surface_left = _SURFACE, g.surface_time_s
                else:
                    self.phase = _DIVE
        return False


def fly_glider(world: World, glider: GliderParams, start: ArrayLike, waypoints: ArrayLike, t0: float = 0.0, *,
               min_altitude: float = 10.0, dac0: ArrayLike = (0.0, 0.0), correct_current: bool = True,
               dt: float = 10.0, max_s: float = 30 * 86400.0, density: float = 1025.0) -> GliderTrack:
    """Fly the glider from ``start`` (x, y at the surface) through ``waypoints`` (module notes).

    Parameters
    ----------
    world : World
        Seabed and current (sampled at the glider's depth and time every step).
    glider : GliderParams
        Flight model, yo and surfacing settings, power.
    start : array_like, shape (2,) or (3,)
        Start position (m; starts at the surface).
    waypoints : array_like, shape (K, 2+)
        Waypoints (m); the last one is the goal.
    t0 : float, default 0.0
        Start time (s).
    min_altitude : float, default 10.0
        Least altitude above the seabed of a dive's bottom (m).
    dac0 : array_like, default (0, 0)
        Current estimate before the first fix (m/s; e.g. the plan's depth-averaged current).
    correct_current : bool, default True
        Correct the heading for the estimated current (False: point at the waypoint).
    dt : float, default 10.0
        Time step (s).
    max_s : float, default 30 days
        Give up after this long (s).
    density : float, default 1025.0
        Water density for the flight model and the pump (kg/m³).

    Returns
    -------
    GliderTrack
        The track, fixes, estimates and energy.
    """
    g = glider
    wps = np.asarray(waypoints, dtype=float)[:, :2]
    f = _Flight(g, wps, start, t0, dac0, correct_current, min_altitude, density)
    n = int(max_s / dt) + 2
    t_out, xyz, phase_out = np.empty(n), np.empty((n, 3)), np.empty(n, dtype=np.int64)
    arrive, reach, reason = math.inf, math.inf, "timeout"
    for i in range(n):
        t_out[i], xyz[i], phase_out[i] = f.t, f.pos, f.phase
        if f.phase == _SURFACE and f.surface_left <= 0.0 and f.fix():
            arrive, reason = f.t, "arrived"
            break
        reach = _drift_step(f, world, wps[-1], dt, reach)
        if f.vertical(world, dt):
            reason = "grounded"
            break
    m = i + 1
    return GliderTrack(t_out[:m].copy(), xyz[:m].copy(), phase_out[:m].copy(), np.array(f.fixes).reshape(-1, 3),
                       np.array(f.dacs).reshape(-1, 2), math.isfinite(arrive), arrive, f.energy, f.pump,
                       f.inflections, min(reach, arrive), reason)


def _drift_step(f: _Flight, world: World, goal: FloatArray, dt: float, reach: float) -> float:
    """One step ``dt`` of the flight through the water and the current (sampled at least half a metre deep), its
    dead reckoning and energy; ``reach`` the time it first comes within the capture radius of ``goal``."""
    g = f.g
    vel = f.velocity()
    cur = world.currents.velocity(np.array([[f.pos[0], f.pos[1], min(f.pos[2], -0.5)]]), f.t)[0]
    f.pos = f.pos + dt * np.array([vel[0] + cur[0], vel[1] + cur[1], vel[2]])
    if reach == math.inf and math.hypot(f.pos[0] - goal[0], f.pos[1] - goal[1]) < g.capture_radius_m:
        reach = f.t + dt
    f.dr = f.dr + dt * (vel[:2] + f.dac)
    f.energy += dt * (g.hotel_w + (g.surface_power_w if f.phase == _SURFACE else 0.0))
    f.t += dt
    return reach
