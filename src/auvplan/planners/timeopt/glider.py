"""Glider missions planned in dive cycles against the depth-averaged current (issue 58).

A glider crosses the water column on every yo, so what carries it over a dive cycle is the
current averaged over the depths it flies (Davis et al. 2002, *Autonomous buoyancy-driven
underwater gliders*; the basis of glider route planning, e.g. GENIoS, Merckelbach 2013):

1. :class:`DepthAveragedCurrent` is the World's current averaged over the yo's depth band at each
   place and time: from ``climb_depth_m`` to ``dive_depth_m``, or ``min_altitude`` above the
   seabed where that is shallower (a glider spends equal time at every depth of a steady yo), and
   the surface current weighted by the share of the cycle spent drifting at the surface.
2. The glider's speed over a dive cycle is its through-water distance per cycle (flight model,
   :func:`auvplan.vehicles.glider.yo_timing`) over the cycle's duration including the time at the
   surface (:func:`cycle`).
3. The time-optimal planner (:mod:`auvplan.planners.timeopt`) plans in that depth-averaged,
   time-varying current at that speed, at one depth level (a horizontal problem; the seabed and
   land are kept off by the World's tests at ``climb_depth_m``).
4. The timed plan is cut at every surfacing (:func:`surfacings`): the waypoints a pilot sends are
   the planned positions of the fixes, and each cycle's heading is the course to the next one
   corrected for the depth-averaged current there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...vehicles.glider import GliderParams, crab_heading, yo_timing, yos_per_cycle
from ...world import World
from ...world.currents.ensemble import DerivedCurrent
from ..core.base import PlannerSpec, PlanningProblem, PlanResult
from ..core.params import TimeoptParams
from .planner import plan_timeopt

__all__ = ["DepthAveragedCurrent", "Cycle", "cycle", "GliderPlan", "plan_glider", "surfacings", "endurance_days"]


class DepthAveragedCurrent(DerivedCurrent):
    """The current averaged over a glider's depth band (module notes, step 1).

    Parameters
    ----------
    world : World
        The World whose current and seabed are used.
    top_m, bottom_m : float
        Depths of the band (m): the yo's top and its deepest point.
    min_altitude : float
        Least altitude of the bottom above the seabed (m).
    levels : int, default 8
        Depths sampled, evenly over the band.
    surface_share : float, default 0.0
        Share of the time spent drifting at the surface (the surface current, 0.5 m down, weighs that much).
    """

    def __init__(self, world: World, top_m: float, bottom_m: float, min_altitude: float, levels: int = 8,
                 surface_share: float = 0.0) -> None:
        self.base = world.currents
        self.world = world
        self.top, self.bottom, self.min_altitude = top_m, bottom_m, min_altitude
        self.frac = (np.arange(levels) + 0.5) / levels
        self.surface_share = surface_share

    def velocity(self, points: ArrayLike, t: float = 0.0) -> FloatArray:
        """Depth-averaged velocity at points (their depth ignored) and a time.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).
        t : float, default 0.0
            Time (s).

        Returns
        -------
        numpy.ndarray
            ``(..., 3)`` (m/s); the vertical component is 0.
        """
        p = np.asarray(points, dtype=float)
        flat = p.reshape(-1, 3)
        zb = self.world.seabed(flat[:, 0], flat[:, 1]) if self.world.terrain is not None else \
            np.full(len(flat), -np.inf)
        low = np.minimum(self.bottom, np.maximum(-zb - self.min_altitude, self.top))
        depth = self.top + (low - self.top)[:, None] * self.frac[None, :]
        q = np.repeat(flat, len(self.frac), axis=0)
        q[:, 2] = -depth.reshape(-1)
        v = self.base.velocity(q, t).reshape(len(flat), len(self.frac), 3).mean(axis=1)
        if self.surface_share > 0:
            top = flat.copy()
            top[:, 2] = -0.5
            v = (1.0 - self.surface_share) * v + self.surface_share * self.base.velocity(top, t)
        v[:, 2] = 0.0
        return np.asarray(v.reshape(p.shape), dtype=float)


@dataclass(frozen=True)
class Cycle:
    """One dive cycle: ``yos`` yos, then the climb to the surface and the time there.

    Attributes
    ----------
    duration_s : float
        Surfacing to surfacing (s).
    underwater_s : float
        Of which underwater (s).
    distance_m : float
        Through-water horizontal distance (m).
    energy_j : float
        Hotel, surface and pump energy (J).
    yos : int
        Yos between two surfacings (:func:`auvplan.vehicles.glider.yos_per_cycle`: ``yos``, or with
        ``surface_every_s`` up to the first top at or after that long underwater, the first dive included) —
        what the Slocum ``yoNN.ma`` counts (``num_half_cycles_to_do``) and the flight flies.
    """

    duration_s: float
    underwater_s: float
    distance_m: float
    energy_j: float
    yos: int = 0

    @property
    def speed(self) -> float:
        """Mean through-water speed over the cycle, the time at the surface included (m/s)."""
        return self.distance_m / self.duration_s


def cycle(glider: GliderParams, bottom_m: float | None = None, density: float = 1025.0) -> Cycle:
    """The dive cycle to ``bottom_m`` (default ``dive_depth_m``): duration, distance and energy.

    Parameters
    ----------
    glider : GliderParams
        The glider.
    bottom_m : float, optional
        Deepest point of the yos (m).
    density : float, default 1025.0
        Water density (kg/m³).

    Returns
    -------
    Cycle
        The first dive from the surface, ``yos`` yos to ``climb_depth_m`` and the last climb to the
        surface (when ``surface_every_s`` is set, up to the first top at or after it: ``yos_per_cycle``).
    """
    g = glider
    bottom = g.dive_depth_m if bottom_m is None else bottom_m
    yo = yo_timing(g, g.climb_depth_m, bottom, density)
    yo_s = yo.dive_s + yo.climb_s
    n = yos_per_cycle(g, yo)  # the first top at or after surface_every_s, the first dive included (was ceil(S / yo_s))
    top = g.climb_depth_m
    extra_s = top / -yo.w_dive + top / yo.w_climb  # the first dive from and the last climb to the surface
    under = n * yo_s + extra_s
    dist = n * yo.distance_m + top / -yo.w_dive * yo.u_dive + top / yo.w_climb * yo.u_climb
    energy = (under + g.surface_time_s) * g.hotel_w + g.surface_time_s * g.surface_power_w + n * yo.pump_j
    return Cycle(under + g.surface_time_s, under, dist, energy, n)


def endurance_days(glider: GliderParams, bottom_m: float | None = None) -> float:
    """Days the battery lasts flying dive cycles to ``bottom_m`` (hotel, surface and pump energy).

    Parameters
    ----------
    glider : GliderParams
        The glider (``battery_wh``).
    bottom_m : float, optional
        Deepest point of the yos (m; default ``dive_depth_m``).

    Returns
    -------
    float
        Endurance (days).
    """
    c = cycle(glider, bottom_m)
    return glider.battery_wh * 3600.0 / (c.energy_j / c.duration_s) / 86400.0


@dataclass(frozen=True, eq=False)
class GliderPlan:
    """A glider mission in dive cycles.

    Attributes
    ----------
    result : PlanResult
        The time-optimal plan in the depth-averaged current (its ``times`` per vertex).
    waypoints : ndarray, shape (M, 2)
        Planned fix positions, one per surfacing, the goal last (m).
    times : ndarray, shape (M,)
        Their planned times (s).
    headings : ndarray, shape (M,)
        Compass heading of the cycle that ends at each waypoint, corrected for the depth-averaged
        current (rad).
    currents : ndarray, shape (M, 2)
        Depth-averaged current at each cycle's midpoint (m/s).
    cycle : Cycle
        The nominal dive cycle.
    arrive_s : float
        Planned time of entering the capture radius of the goal (s).
    energy_j : float
        Planned energy to the goal (J).
    endurance_days : float
        Battery endurance flying these cycles (days).
    """

    result: PlanResult
    waypoints: FloatArray
    times: FloatArray
    headings: FloatArray
    currents: FloatArray
    cycle: Cycle
    arrive_s: float
    energy_j: float
    endurance_days: float


def surfacings(points: ArrayLike, times: ArrayLike, period: float) -> tuple[FloatArray, FloatArray]:
    """Positions and times of the fixes along a timed path, one every ``period`` seconds, the end last.

    Parameters
    ----------
    points : array_like, shape (N, 2+)
        Path vertices (m).
    times : array_like, shape (N,)
        Their times (s, increasing).
    period : float
        Dive cycle duration (s).

    Returns
    -------
    (ndarray (M, 2), ndarray (M,))
        Fix positions and times, the path's start excluded and its end included.
    """
    p = np.asarray(points, dtype=float)[:, :2]
    t = np.asarray(times, dtype=float)
    ts = np.arange(t[0] + period, t[-1], period)
    ts = np.append(ts[ts < t[-1] - 1e-6], t[-1])
    xy = np.stack([np.interp(ts, t, p[:, 0]), np.interp(ts, t, p[:, 1])], axis=1)
    return xy, ts


def _arrival(points: FloatArray, times: FloatArray, goal: FloatArray, radius: float) -> float:
    """Time the timed path first comes within ``radius`` of ``goal`` (linear between vertices, 1 m steps)."""
    d = np.hypot(points[:, 0] - goal[0], points[:, 1] - goal[1])
    inside = np.flatnonzero(d < radius)
    if not len(inside) or inside[0] == 0:
        return float(times[0] if len(inside) else times[-1])
    i = inside[0]
    s = np.linspace(0.0, 1.0, 1001)
    seg = points[i - 1, :2] + s[:, None] * (points[i, :2] - points[i - 1, :2])
    j = int(np.argmax(np.hypot(seg[:, 0] - goal[0], seg[:, 1] - goal[1]) < radius))
    return float(times[i - 1] + s[j] * (times[i] - times[i - 1]))


def plan_glider(world: World, glider: GliderParams, start: ArrayLike, goal: ArrayLike, depart: float = 0.0,
                min_altitude: float = 10.0, timeopt: TimeoptParams | None = None) -> GliderPlan:
    """Plan a glider mission from ``start`` to ``goal`` (x, y) departing at ``depart`` (module notes).

    Parameters
    ----------
    world : World
        Seabed, land and the 3D current.
    glider : GliderParams
        The glider.
    start, goal : array_like
        End points (m; their depth is ignored: planned at ``climb_depth_m``).
    depart : float, default 0.0
        Departure (s after the World's time origin).
    min_altitude : float, default 10.0
        Least altitude of a yo's bottom above the seabed (m).
    timeopt : TimeoptParams, optional
        The time-optimal planner's settings (``depart_s`` is set to ``depart``).

    Returns
    -------
    GliderPlan
        The plan; ``result.status`` says whether one was found (the other fields are then empty).
    """
    c = cycle(glider)
    dac = DepthAveragedCurrent(world, glider.climb_depth_m, glider.dive_depth_m, min_altitude,
                               surface_share=glider.surface_time_s / c.duration_s)
    flat = replace(world, currents=dac)
    z = -glider.climb_depth_m
    a = np.array([*np.asarray(start, dtype=float)[:2], z])
    b = np.array([*np.asarray(goal, dtype=float)[:2], z])
    problem = PlanningProblem(flat, a, b, speed=c.speed, hotel_power=c.energy_j / c.duration_s, drag_k=0.0)
    params = replace(timeopt or TimeoptParams(levels=1), depart_s=depart, levels=1)
    res = plan_timeopt(problem, PlannerSpec(name="timeopt", timeopt=params))
    if res.times is None or not len(res.path):
        empty = np.empty((0, 2))
        return GliderPlan(res, empty, np.empty(0), np.empty(0), empty, c, math.inf, math.inf, endurance_days(glider))
    pts, ts = np.asarray(res.path), np.asarray(res.times)
    xy, tf = surfacings(pts, ts, c.duration_s)
    prev = np.vstack([a[:2], xy[:-1]])
    mid = 0.5 * (prev + xy)
    tm = np.append(depart, tf[:-1]) + 0.5 * np.diff(np.append(depart, tf))
    cur = np.array([dac.velocity(np.array([[m[0], m[1], z]]), float(tt))[0, :2] for m, tt in zip(mid, tm, strict=True)])
    heads = np.array([crab_heading(math.atan2(q[0] - p[0], q[1] - p[1]), c.speed, cc)
                      for p, q, cc in zip(prev, xy, cur, strict=True)])
    arrive = _arrival(pts, ts, b, glider.capture_radius_m)
    energy = (arrive - depart) * c.energy_j / c.duration_s
    return GliderPlan(res, xy, tf, heads, cur, c, arrive, energy, endurance_days(glider))
