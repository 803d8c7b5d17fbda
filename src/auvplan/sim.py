"""Mission definition and the closed-loop simulator.

:func:`simulate` runs a fixed-step loop (``dt``) of guidance → autopilot → vehicle → world,
with preallocated arrays and events: arrival (within ``arrival_radius`` of the last waypoint),
collision (seabed or an obstacle surface), deadlock (no progress along the route for
``deadlock_time``), timeout.  The loop is scalar Python on purpose (one vehicle, thousands of
small steps); the world is queried through its vectorised kernels once per step.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ._types import RngLike, Status, as_rng
from .guidance.hybrid import HybridGuidance, HybridParams
from .guidance.local import AvoidanceParams
from .guidance.los import LosGuidance, LosParams
from .guidance.route import RouteTracker
from .planners.base import PlannerSpec, PlanningProblem
from .vehicles import Vehicle, VehicleParams, VehicleState
from .world import World

__all__ = ["SimSettings", "Mission", "SimResult", "planning_problem", "make_guidance", "simulate"]


@dataclass(frozen=True)
class SimSettings:
    """Closed-loop settings: step ``dt`` (s), time limit (s; 0 = 3 × nominal + 120 s), arrival
    radius (m), deadlock window (s without 1 m of progress along the route), and the recording
    decimation ``record_every`` (steps)."""

    dt: float = 0.1
    max_time: float = 0.0
    arrival_radius: float = 10.0
    deadlock_time: float = 120.0
    record_every: int = 1

    def __post_init__(self) -> None:
        if not self.dt > 0 or self.max_time < 0 or not self.arrival_radius > 0 or not self.deadlock_time > 0:
            raise ValueError("dt, arrival_radius and deadlock_time must be positive and max_time >= 0")
        if self.record_every < 1:
            raise ValueError(f"record_every = {self.record_every}: must be >= 1")


@dataclass(frozen=True)
class Mission:
    """What to do in a World: end points, an optional fixed route, and every component's settings."""

    name: str
    start: tuple[float, float, float]
    goal: tuple[float, float, float]
    route: tuple[tuple[float, float, float], ...] = ()
    seed: int = 0
    vehicle: VehicleParams = field(default_factory=VehicleParams)
    planner: PlannerSpec = field(default_factory=PlannerSpec)
    guidance: str = "hybrid"
    hybrid: HybridParams = field(default_factory=HybridParams)
    los: LosParams = field(default_factory=LosParams)
    avoidance: AvoidanceParams = field(default_factory=AvoidanceParams)
    sim: SimSettings = field(default_factory=SimSettings)


@dataclass(frozen=True, eq=False)
class SimResult:
    """Time series and outcome of one closed-loop run.

    Arrays have one row per recorded step: ``t (N,)``, ``position (N, 3)``, ``heading (N,)``
    (compass, rad), ``speed (N,)`` (over ground), ``rudder (N,)`` (rad), ``cross_track (N,)``
    (signed, to the active leg, m), ``route_error (N,)`` (distance to the whole route, m),
    ``progress (N,)`` (m along the route), ``altitude (N,)`` (m above the seabed; inf without
    terrain), ``obstacle_distance (N, M)`` (m to each static then moving obstacle surface).
    """

    status: Status
    arrived: bool
    t: np.ndarray
    position: np.ndarray
    heading: np.ndarray
    speed: np.ndarray
    rudder: np.ndarray
    cross_track: np.ndarray
    route_error: np.ndarray
    progress: np.ndarray
    altitude: np.ndarray
    obstacle_distance: np.ndarray
    events: tuple[tuple[float, str, str], ...]
    guidance: str
    wall_time_s: float
    escapes: int = 0

    @property
    def metrics(self) -> dict:
        """Summary figures of the run (DESIGN.md §4 simulate JSON fields)."""
        d = np.linalg.norm(np.diff(self.position, axis=0), axis=1).sum() if self.t.size > 1 else 0.0
        per_obs = self.obstacle_distance.min(axis=0) if self.obstacle_distance.size else np.empty(0)
        return {
            "status": self.status.value,
            "arrived": self.arrived,
            "duration_s": float(self.t[-1]) if self.t.size else 0.0,
            "distance_m": float(d),
            "min_clearance_m": float(self.altitude.min()) if self.t.size else float("inf"),
            "min_obstacle_distance_m": float(per_obs.min()) if per_obs.size else float("inf"),
            "obstacle_min_distances_m": per_obs.tolist(),
            "collisions": sum(1 for e in self.events if e[1] == "collision"),
            "cross_track_rms_m": float(np.sqrt(np.mean(self.route_error**2))) if self.t.size else 0.0,
            "cross_track_max_m": float(self.route_error.max()) if self.t.size else 0.0,
            "escapes": self.escapes,
            "wall_time_s": self.wall_time_s,
        }


def planning_problem(world: World, mission: Mission) -> PlanningProblem:
    """The global planning problem of a mission in a world."""
    v = mission.vehicle
    return PlanningProblem(world, mission.start, mission.goal, v.speed, v.hotel_power, v.drag_k)


def make_guidance(name: str, route, mission: Mission):
    """A path follower by name (``hybrid``, ``los`` or ``ilos``) over ``route (N, 3)``."""
    if name == "hybrid":
        return HybridGuidance(RouteTracker(route, mission.hybrid.switch_radius), mission.hybrid)
    if name in ("los", "ilos"):
        return LosGuidance(RouteTracker(route, mission.los.switch_radius), mission.los, integral=name == "ilos")
    raise ValueError(f"unknown guidance {name!r}; choose hybrid, los or ilos")


def _obstacle_shapes(world: World, t: float):
    shapes = list(world.obstacles)
    shapes += [o.at(t) if o.active(t) else None for o in world.moving]
    return shapes


def simulate(world: World, mission: Mission, route=None, guidance: str | None = None, rng: RngLike = None) -> SimResult:
    """Fly ``mission`` along ``route`` (default: the mission's route) in ``world``.

    Parameters
    ----------
    world : World
        Seabed, currents, static and moving obstacles.
    mission : Mission
        Vehicle, guidance and simulation settings.
    route : array_like (N, 3), optional
        Waypoints to follow; the mission's own route by default.
    guidance : str, optional
        ``hybrid``, ``los`` or ``ilos``; the mission's choice by default.
    rng : Generator, int or None
        Seed of the wave disturbance.
    """
    t_wall = time.perf_counter()
    rng = as_rng(mission.seed if rng is None else rng)
    route = np.asarray(mission.route if route is None else route, dtype=float).reshape(-1, 3)
    st = mission.sim
    dt = st.dt
    vp = mission.vehicle
    guide = make_guidance(guidance or mission.guidance, route, mission)
    tracker = guide.route
    vehicle = Vehicle(vp, dt)
    first = route[1] - route[0]
    s = VehicleState(float(route[0, 0]), float(route[0, 1]), float(route[0, 2]),
                     math.atan2(first[0], first[1]) % (2 * math.pi), vp.speed)
    max_time = st.max_time or 3.0 * tracker.total_length / vp.speed + 120.0
    n_steps = int(math.ceil(max_time / dt))
    n_rec = n_steps // st.record_every + 2
    n_obs = len(world.obstacles) + len(world.moving)
    T = np.empty(n_rec)
    P = np.empty((n_rec, 3))
    H = np.empty(n_rec)
    V = np.empty(n_rec)
    D = np.empty(n_rec)
    E = np.empty(n_rec)
    PR = np.empty(n_rec)
    ALT = np.empty(n_rec)
    OBS = np.empty((n_rec, n_obs))
    waves = vp.wave_sigma_r > 0 or vp.wave_sigma_v > 0
    noise = rng.standard_normal((n_steps + 1, 2)) if waves else np.zeros((n_steps + 1, 2))
    goal = route[-1]
    events: list[tuple[float, str, str]] = []
    status = Status.TIMEOUT
    best_progress, best_time = -1.0, 0.0
    terrain = world.terrain
    currents = world.currents
    rec = 0
    vel = (0.0, 0.0, 0.0)
    k = 0
    for k in range(n_steps + 1):
        t = k * dt
        pos = np.array([s.x, s.y, s.z])
        shapes = _obstacle_shapes(world, t)
        dists = [sh.distance(pos).item() if sh is not None else math.inf for sh in shapes]
        obstacles = [(sh.center[0], sh.center[1], d) for sh, d in zip(shapes, dists) if sh is not None]
        alt = float(terrain.altitude(pos)) if terrain is not None else math.inf
        cur = currents.velocity(pos[None], t)[0]
        psi_d, _, rp = guide.command(s.x, s.y, s.z, cur, s.u, obstacles, dt)
        if k % st.record_every == 0:
            T[rec], P[rec], H[rec], D[rec] = t, pos, s.psi, s.delta
            V[rec] = math.hypot(vel[0], vel[1])
            E[rec], PR[rec], ALT[rec] = rp.cross, rp.progress, alt
            OBS[rec] = dists
            rec += 1
        # events
        if alt < 0.0 or any(d < 0.0 for d in dists):
            what = "the seabed" if alt < 0.0 else f"obstacle {int(np.argmin(dists))}"
            events.append((t, "collision", f"hit {what} at {pos.round(2).tolist()}"))
            status = Status.COLLISION
            break
        if rp.last and math.dist((s.x, s.y, s.z), goal) <= st.arrival_radius:
            events.append((t, "arrival", f"within {st.arrival_radius:g} m of the last waypoint"))
            status = Status.EXACT
            break
        if rp.progress > best_progress + 1.0:
            best_progress, best_time = rp.progress, t
        elif t - best_time > st.deadlock_time:
            events.append((t, "deadlock", f"no progress along the route for {st.deadlock_time:g} s"))
            status = Status.DEADLOCK
            break
        dz = rp.z_ref - s.z
        theta_c = rp.gamma + math.atan(vp.depth_gain * dz)
        vel = vehicle.step(s, psi_d, theta_c, vp.speed, cur, noise[k])
    else:
        events.append((n_steps * dt, "timeout", f"not arrived after {max_time:.0f} s"))
    if k % st.record_every != 0 or rec == 0:  # always keep the final state
        T[rec], P[rec], H[rec], D[rec] = k * dt, (s.x, s.y, s.z), s.psi, s.delta
        V[rec] = math.hypot(vel[0], vel[1])
        E[rec], PR[rec] = rp.cross, rp.progress
        ALT[rec] = float(terrain.altitude(P[rec])) if terrain is not None else math.inf
        OBS[rec] = [sh.distance(P[rec]).item() if sh is not None else math.inf
                    for sh in _obstacle_shapes(world, k * dt)]
        rec += 1
    P_out = P[:rec].copy()
    return SimResult(
        status=status,
        arrived=status is Status.EXACT,
        t=T[:rec].copy(),
        position=P_out,
        heading=H[:rec].copy(),
        speed=V[:rec].copy(),
        rudder=D[:rec].copy(),
        cross_track=E[:rec].copy(),
        route_error=tracker.cross_track(P_out),
        progress=PR[:rec].copy(),
        altitude=ALT[:rec].copy(),
        obstacle_distance=OBS[:rec].copy(),
        events=tuple(events),
        guidance=guide.name,
        wall_time_s=time.perf_counter() - t_wall,
    )
