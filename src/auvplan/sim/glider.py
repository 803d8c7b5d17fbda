"""The closed loop of a buoyancy glider: sawtooth flight through the current at every depth.

The glider (:mod:`auvplan.vehicles.glider`) flies steady dives and climbs between
``climb_depth_m`` and ``dive_depth_m`` (at least ``min_altitude`` above the seabed, from its
altimeter), at the flight model's vertical and horizontal speeds through the water, while the
World's current at its own depth and time carries it.  It surfaces after ``yos`` yos or once
``surface_every_s`` has passed, stays ``surface_time_s`` at the surface drifting with the surface
current, takes a fix, and then:

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
from ..planners.glider import cycle
from ..vehicles.glider import GliderParams, crab_heading, yo_timing
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
        ``climb_depth_m`` + ``min_altitude``) or ``"timeout"``.
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
    yo = yo_timing(g, g.climb_depth_m, g.dive_depth_m, density)
    v_eff = cycle(g, density=density).speed  # the crab holds the course over the whole cycle, surface drift too
    n = int(max_s / dt) + 2
    t_out, xyz, phase_out = np.empty(n), np.empty((n, 3)), np.empty(n, dtype=np.int64)
    fixes: list[tuple[float, float, float]] = []
    dacs: list[FloatArray] = []
    pos = np.array([*np.asarray(start, dtype=float)[:2], 0.0])
    t, phase, k = t0, _SURFACE, 0
    surface_left = 0.0  # starts at the surface: dives at once after the first fix
    dac = np.asarray(dac0, dtype=float).copy()
    dr = pos[:2].copy()
    last_fix_t = t0
    yos, bottom = 0, g.dive_depth_m
    heading = 0.0
    pump = energy = 0.0
    inflections, arrive, reach = 0, math.inf, math.inf
    reason = "timeout"
    for i in range(n):
        t_out[i], xyz[i], phase_out[i] = t, pos, phase
        if phase == _SURFACE and surface_left <= 0.0:  # the fix: estimate, advance, dive
            if fixes:
                under = t - last_fix_t
                dac = (pos[:2] - dr) / under + dac if under > 0 else dac  # dr carried the old estimate
            fixes.append((t, pos[0], pos[1]))
            dacs.append(dac.copy())
            while k < len(wps) and math.hypot(*(wps[k] - pos[:2])) < g.capture_radius_m:
                k += 1
            if k == len(wps):
                arrive, reason = t, "arrived"
                break
            last_fix_t, dr = t, pos[:2].copy()
            phase, yos = _DIVE, 0
            course = heading = _bearing(pos[:2], wps[k])  # the course of this cycle (the naive pilot's heading)
        if phase != _SURFACE:
            target = wps[min(k, len(wps) - 1)]
            if correct_current:
                heading = crab_heading(course, v_eff, dac)
            w, u = (yo.w_dive, yo.u_dive) if phase == _DIVE else (yo.w_climb, yo.u_climb)
            vel = np.array([u * math.sin(heading), u * math.cos(heading), w])
            if correct_current and k < len(wps) - 1 and math.hypot(*(target - dr)) < g.capture_radius_m:
                k += 1  # dead-reckoned capture of an intermediate waypoint: the course to the next from here
                course = _bearing(dr, wps[k])
        else:
            vel = np.zeros(3)
        cur = world.currents.velocity(np.array([[pos[0], pos[1], min(pos[2], -0.5)]]), t)[0]
        move = vel + np.array([cur[0], cur[1], 0.0])
        pos = pos + dt * move
        if reach == math.inf and math.hypot(pos[0] - wps[-1, 0], pos[1] - wps[-1, 1]) < g.capture_radius_m:
            reach = t + dt
        dr = dr + dt * (vel[:2] + dac)
        t += dt
        energy += dt * (g.hotel_w + (g.surface_power_w if phase == _SURFACE else 0.0))
        depth = -pos[2]
        if phase == _SURFACE:
            surface_left -= dt
            pos[2] = 0.0
        elif phase == _DIVE:
            seabed = -float(world.seabed(np.array([pos[0]]), np.array([pos[1]]))[0])
            bottom = min(g.dive_depth_m, seabed - min_altitude)
            if seabed - min_altitude < g.climb_depth_m:  # aground: land, or no room for a yo
                reason = "grounded"
                break
            if depth >= bottom:
                pos[2] = -bottom  # the inflection (the step's overshoot of at most |w| dt is not flown)
                shallow = bottom < g.climb_depth_m + 5.0  # no room for a yo: climb out and surface
                phase, yos, inflections = _CLIMB, g.yos if shallow else yos + 1, inflections + 1
                e = density * 9.81 * max(depth, 0.0) * 2e-6 * g.ballast_cc / g.pump_efficiency
                pump, energy = pump + e, energy + e
        else:
            due = yos >= g.yos or (g.surface_every_s > 0 and t - last_fix_t >= g.surface_every_s)
            if depth <= (0.0 if due else g.climb_depth_m):
                pos[2] = 0.0 if due else -g.climb_depth_m
                if due:
                    phase, surface_left, pos[2] = _SURFACE, g.surface_time_s, 0.0
                else:
                    phase = _DIVE
    m = i + 1
    return GliderTrack(t_out[:m].copy(), xyz[:m].copy(), phase_out[:m].copy(), np.array(fixes).reshape(-1, 3),
                       np.array(dacs).reshape(-1, 2), math.isfinite(arrive), arrive, energy, pump, inflections,
                       min(reach, arrive), reason)
