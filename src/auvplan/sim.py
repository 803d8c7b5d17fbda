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
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from functools import partial
from typing import Any, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._types import RngLike, Status, as_rng
from .guidance.formation import Formation
from .guidance.hybrid import HybridGuidance, HybridParams
from .guidance.local import AvoidanceParams, LocalAvoidance, key_waypoints
from .guidance.los import LosGuidance, LosParams
from .guidance.mission import build_waypoints
from .guidance.predictive import PredictiveAvoidance
from .guidance.route import PathFollower, RouteTracker
from .path import resample_polyline
from .planners import plan as global_plan
from .planners.base import PlannerSpec, PlanningProblem, PlanResult, Progress
from .vehicles import Vehicle, VehicleParams, VehicleState
from .world import World
from .world.obstacles import Shape

__all__ = [
    "SimSettings",
    "Mission",
    "SimResult",
    "SimMetrics",
    "RunRecord",
    "planning_problem",
    "make_guidance",
    "simulate",
    "run_mission",
    "route_from_path",
    "mission_route",
    "planned_route",
    "decimate",
]


@dataclass(frozen=True)
class SimSettings:
    """Closed-loop settings: time step, time limit, arrival, deadlock and recording.

    Attributes
    ----------
    dt : float
        Time step (s).
    max_time : float
        Time limit (s); 0 = 3 × the nominal duration + 120 s.
    arrival_radius : float
        Distance from the last waypoint that counts as arrival (m).
    deadlock_time : float
        Deadlock window: time without 1 m of progress along the route (s).
    record_every : int
        Record every this many steps.
    """

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
    """What to do in a World: end points, an optional fixed route, and every component's settings.

    Attributes
    ----------
    name : str
        Mission (scenario) name.
    start, goal : tuple of float
        End points ``(x, y, z)`` (m).
    route : tuple of (x, y, z)
        A fixed route to follow instead of planning one (empty: plan).
    seed : int
        Default seed of the planner and of the simulation's disturbances.
    vehicle, planner, hybrid, los, avoidance, sim
        Settings of the vehicle, the global planner, the two path followers, the local
        avoidance and the closed loop.
    guidance : str
        ``"hybrid"``, ``"los"`` or ``"ilos"``.
    formation : Formation or None
        Several vehicles flying the route in formation (``[[vehicles]]``, ``[formation]``):
        :mod:`auvplan.sim_formation` flies them.
    """

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
    formation: Formation | None = None


class SimMetrics(TypedDict):
    """Summary figures of a run (:attr:`SimResult.metrics`; DESIGN.md §4 simulate JSON fields).

    Attributes
    ----------
    status : str
        The run's :class:`~auvplan._types.Status` value.
    arrived : bool
        Whether the vehicle reached the last waypoint.
    duration_s : float
        Time flown (s).
    distance_m : float
        Distance flown (m).
    min_altitude_m : float
        Least height above the seabed (m).
    min_clearance_m : float
        Smaller of ``min_altitude_m`` and ``min_obstacle_distance_m`` (m; margins not subtracted).
    min_obstacle_distance_m : float
        Least distance to an obstacle surface, static or moving (m).
    obstacle_min_distances_m : list of float
        Least distance to each obstacle, static then moving (m).
    collisions : int
        Contacts (``collision`` and ``unavoidable`` events).
    unavoidable : int
        Contacts with an obstacle faster than the vehicle that was closing in.
    cross_track_rms_m, cross_track_max_m : float
        RMS and largest distance to the route (m).
    escapes : int
        Local-minimum escapes.
    wall_time_s : float
        Wall-clock time of the run (s).
    """

    status: str
    arrived: bool
    duration_s: float
    distance_m: float
    min_altitude_m: float
    min_clearance_m: float
    min_obstacle_distance_m: float
    obstacle_min_distances_m: list[float]
    collisions: int
    unavoidable: int
    cross_track_rms_m: float
    cross_track_max_m: float
    escapes: int
    wall_time_s: float


@dataclass(frozen=True, eq=False)
class SimResult:
    """Time series and outcome of one closed-loop run.

    Arrays have one row per recorded step: ``t (N,)``, ``position (N, 3)``, ``heading (N,)``
    (compass, rad), ``speed (N,)`` (over ground), ``rudder (N,)`` (rad), ``cross_track (N,)``
    (signed, to the active leg, m), ``route_error (N,)`` (distance to the whole route, m),
    ``progress (N,)`` (m along the route), ``altitude (N,)`` (m above the seabed; inf without
    terrain), ``obstacle_distance (N, M)`` (m to each static then moving obstacle surface).

    Attributes
    ----------
    status : Status
        ``EXACT`` on arrival, else ``COLLISION``, ``UNAVOIDABLE``, ``DEADLOCK`` or ``TIMEOUT``.
    arrived : bool
        Whether the vehicle reached the last waypoint.
    t, position, heading, speed, rudder, cross_track, route_error, progress, altitude, obstacle_distance : ndarray
        The recorded time series (see above).
    events : tuple of (float, str, str)
        ``(time, kind, message)`` of arrival, collision, unavoidable, deadlock or timeout.
    guidance, avoidance : str
        The path follower and the local avoidance used.
    wall_time_s : float
        Wall-clock time of the run.
    escapes, decision_steps, decision_time_s
        Local-minimum escapes, APF decision steps and their total time (s).
    """

    status: Status
    arrived: bool
    t: NDArray[np.float64]
    position: NDArray[np.float64]
    heading: NDArray[np.float64]
    speed: NDArray[np.float64]
    rudder: NDArray[np.float64]
    cross_track: NDArray[np.float64]
    route_error: NDArray[np.float64]
    progress: NDArray[np.float64]
    altitude: NDArray[np.float64]
    obstacle_distance: NDArray[np.float64]
    events: tuple[tuple[float, str, str], ...]
    guidance: str
    wall_time_s: float
    escapes: int = 0
    avoidance: str = "none"
    decision_steps: int = 0
    decision_time_s: float = 0.0

    @property
    def metrics(self) -> SimMetrics:
        """Summary figures of the run (DESIGN.md §4 simulate JSON fields).

        ``min_altitude_m`` is the least height above the seabed, ``min_obstacle_distance_m`` the
        least distance to an obstacle surface (static or moving), ``min_clearance_m`` the smaller
        of the two (the geometric clearance, as in a plan's cost terms; margins not subtracted),
        ``collisions`` the contacts (``collision`` and ``unavoidable`` events).
        """
        d = np.linalg.norm(np.diff(self.position, axis=0), axis=1).sum() if self.t.size > 1 else 0.0
        per_obs = self.obstacle_distance.min(axis=0) if self.obstacle_distance.size else np.empty(0)
        altitude = float(self.altitude.min()) if self.t.size else float("inf")
        obstacle = float(per_obs.min()) if per_obs.size else float("inf")
        return {
            "status": self.status.value,
            "arrived": self.arrived,
            "duration_s": float(self.t[-1]) if self.t.size else 0.0,
            "distance_m": float(d),
            "min_altitude_m": altitude,
            "min_clearance_m": min(altitude, obstacle),
            "min_obstacle_distance_m": obstacle,
            "obstacle_min_distances_m": per_obs.tolist(),
            "collisions": sum(1 for e in self.events if e[1] in ("collision", "unavoidable")),
            "unavoidable": sum(1 for e in self.events if e[1] == "unavoidable"),
            "cross_track_rms_m": float(np.sqrt(np.mean(self.route_error**2))) if self.t.size else 0.0,
            "cross_track_max_m": float(self.route_error.max()) if self.t.size else 0.0,
            "escapes": self.escapes,
            "wall_time_s": self.wall_time_s,
        }


def planning_problem(world: World, mission: Mission) -> PlanningProblem:
    """Build the global planning problem of a mission in a world.

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        End points and vehicle figures (speed, hotel power, drag).

    Returns
    -------
    PlanningProblem
        Start, goal (m), speed (m/s), hotel power (W) and drag factor (W s³/m³) in the world.
    """
    v = mission.vehicle
    return PlanningProblem(world, np.asarray(mission.start, dtype=float), np.asarray(mission.goal, dtype=float),
                           v.speed, v.hotel_power, v.drag_k)


def make_guidance(name: str, route: ArrayLike, mission: Mission) -> PathFollower:
    """Make a path follower by name.

    Parameters
    ----------
    name : {'hybrid', 'los', 'ilos'}
        The path follower.
    route : array_like
        ``(N, 3)`` waypoints to follow (m).
    mission : Mission
        Its ``hybrid`` and ``los`` settings.

    Returns
    -------
    PathFollower
        :class:`~auvplan.guidance.hybrid.HybridGuidance` or :class:`~auvplan.guidance.los.LosGuidance`.
    """
    if name == "hybrid":
        return HybridGuidance(RouteTracker(route, mission.hybrid.switch_radius), mission.hybrid)
    if name in ("los", "ilos"):
        return LosGuidance(RouteTracker(route, mission.los.switch_radius), mission.los, integral=name == "ilos")
    raise ValueError(f"unknown guidance {name!r}; choose hybrid, los or ilos")


FAR = 60.0
"""Obstacle distances beyond this (m) are recorded as the lower bound |p - c| - bounding radius
(beyond the reach of every guidance law: APF radius 30 m, hybrid influence 25 m by default)."""


def _distance(item: tuple[Shape, tuple[float, ...]] | None, pos: NDArray[np.float64], far: float = FAR) -> float:
    """Distance to a placed shape's surface, exact within ``far`` (a cheap lower bound beyond)."""
    if item is None:
        return math.inf
    shape, c = item
    bound = math.dist((pos[0], pos[1], pos[2]), c) - shape.bounding_radius
    if bound > far:
        return bound
    # the shape is defined about its own centre: move the query point instead of the shape
    return shape.distance(pos - c + np.asarray(shape.center)).item()


def _obstacle_shapes(world: World, t: float, centres: Sequence[Sequence[float] | NDArray[np.float64]] | None = None
                     ) -> list[tuple[Any, tuple[float, ...]] | None]:
    """(shape, centre) of every static and active moving obstacle at ``t`` (None when inactive);
    ``centres`` are the moving obstacles' centres at ``t`` when the caller has them."""
    items: list[tuple[Any, tuple[float, ...]] | None] = [(o, o.center) for o in world.obstacles]
    if centres is None:
        centres = [o.center(t) for o in world.moving]
    items += [(o.shape, tuple(c)) if o.active(t) else None for o, c in zip(world.moving, centres)]
    return items


PROGRESS_STEP = 1.0
"""Route progress (m) that counts as progress for the deadlock watch: the best progress so far must
be exceeded by more than this."""


def _contact_event(alt: float, dists: Sequence[float], pos: NDArray[np.float64], t: float,
                   moving: Sequence[Any], speed: float) -> tuple[Status, str] | None:
    """The collision at one step: ``(status, what was hit)``, or None.

    Contact means penetration: an altitude below 0 (under the seabed) or a distance below 0 (inside an
    obstacle); touching at exactly 0 m is not a collision, as a point with zero clearance is free for
    :meth:`World.clearances`.  The seabed is named first; else the obstacle the vehicle is deepest in
    (``dists`` lists the static obstacles, then ``moving``).  Hitting a moving obstacle is UNAVOIDABLE
    when it is at least as fast as the vehicle (``speed``) and closing in, its velocity pointing towards
    the vehicle (``v_o · (p - c) > 0``: tangential motion does not close in), else a COLLISION.
    """
    if alt < 0.0:
        return Status.COLLISION, "the seabed"
    if not any(d < 0.0 for d in dists):
        return None
    i = int(np.argmin(dists))
    what = f"obstacle {i}"
    j = i - (len(dists) - len(moving))
    if j >= 0:
        v_o = moving[j].velocity(t)
        closing = float(np.dot(v_o, pos - moving[j].center(t))) > 0.0
        if np.linalg.norm(v_o) >= speed and closing:
            return Status.UNAVOIDABLE, what + f" (moving at {np.linalg.norm(v_o):.2f} m/s, faster than the vehicle, " \
                "closing in)"
    return Status.COLLISION, what


def _arrived(last: bool, pos: Sequence[float], goal: Sequence[float], radius: float) -> bool:
    """Arrival: on the last leg and within ``radius`` of the goal (at exactly ``radius``: arrived)."""
    return last and math.dist(pos, goal) <= radius


def _progressed(progress: float, best: float) -> bool:
    """Whether the route progress beats the best so far by more than :data:`PROGRESS_STEP`."""
    return progress > best + PROGRESS_STEP


def _deadlocked(t: float, best_time: float, deadlock_time: float, stalled: Callable[[], bool] | None) -> bool:
    """Deadlock: no progress for more than ``deadlock_time`` since ``best_time`` and, with local avoidance,
    its escapes given up (``stalled()`` is False; it is asked only once the time is up, as it runs them)."""
    return t - best_time > deadlock_time and (stalled is None or not stalled())


def simulate(world: World, mission: Mission, route: ArrayLike | None = None, guidance: str | None = None,
             rng: RngLike = None, avoidance: str | None = None, keys: ArrayLike | None = None,
             progress: Callable[[float, float], object] | None = None) -> SimResult:
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
        Seed of the wave disturbance and of the escape sub-goals.
    avoidance : str, optional
        ``predictive`` (prediction + velocity obstacles), ``apf`` (document 004) or ``none``; the
        mission's choice by default.  With avoidance, a stalled route progress first runs
        document 004's escapes for ``escape_time`` s before ``DEADLOCK`` is declared.
    keys : array_like (K, 3), optional
        Key waypoints for the APF; derived from the route by document 004's rule by default.
    progress : callable, optional
        ``progress(t, expected)`` every simulated minute: the time flown and the time the route
        should take at the vehicle's speed (s), for a progress bar.

    Returns
    -------
    SimResult
        Status, recorded time series and events of the run.
    """
    t_wall = time.perf_counter()
    rng = as_rng(mission.seed if rng is None else rng)
    route = np.asarray(mission.route if route is None else route, dtype=float).reshape(-1, 3)
    st = mission.sim
    dt = st.dt
    vp = mission.vehicle
    guide = make_guidance(guidance or mission.guidance, route, mission)
    tracker = guide.route
    av_name = avoidance or mission.avoidance.name
    local = None
    if av_name in ("apf", "predictive"):
        keys = key_waypoints(route, world, mission.avoidance.collision_check) if keys is None else keys
        av = replace(mission.avoidance, name=av_name)
        local = LocalAvoidance(guide, keys, world, av, vp.speed, rng) if av_name == "apf" \
            else PredictiveAvoidance(guide, keys, world, av, vp, rng)
    vehicle = Vehicle(vp, dt)
    first = route[1] - route[0]
    s = VehicleState(float(route[0, 0]), float(route[0, 1]), float(route[0, 2]),
                     math.atan2(first[0], first[1]) % (2 * math.pi), vp.speed)
    max_time = st.max_time or 3.0 * tracker.total_length / vp.speed + 120.0
    n_steps = int(math.ceil(max_time / dt))
    n_rec = n_steps // st.record_every + 2
    n_static = len(world.obstacles)
    n_obs = n_static + len(world.moving)
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
    # the moving obstacles' centres at every step time, one vectorised call per obstacle
    steps_t = np.arange(n_steps + 1) * dt
    far = max(FAR, mission.avoidance.radius + 10.0, mission.hybrid.influence + 10.0)
    tracks = np.stack([np.asarray(o.motion.position(steps_t)) for o in world.moving], axis=1) \
        if world.moving else np.empty((n_steps + 1, 0, 3))
    # their velocities (what the scenario knows; predictive avoidance may estimate them instead)
    velocities = np.asarray(np.gradient(tracks, dt, axis=0)) if n_steps > 0 else np.zeros_like(tracks)
    radii = [o.shape.bounding_radius for o in world.moving]
    every = max(1, int(round(60.0 / dt)))
    expected = tracker.total_length / vp.speed
    for k in range(n_steps + 1):
        t = k * dt
        if progress is not None and k % every == 0:
            progress(t, expected)
        pos = np.array([s.x, s.y, s.z])
        shapes = _obstacle_shapes(world, t, tracks[k].tolist())
        dists = [_distance(sh, pos, far) for sh in shapes]
        alt = s.z - terrain.elevation_at(s.x, s.y) if terrain is not None else math.inf
        cur = currents.velocity(pos[None], t)[0]
        pitch_cmd = None
        if local is None:
            near = [(it[1][0], it[1][1], d) for it, d in zip(shapes, dists) if it is not None]
            psi_d, _, rp = guide.command(s.x, s.y, s.z, cur, s.u, near, dt)
        else:
            obstacles = [(it[1][0], it[1][1], d, False, it[1]) if i < n_static else
                         (it[1][0], it[1][1], d, True, it[1], i, velocities[k, i - n_static], radii[i - n_static])
                         for i, (it, d) in enumerate(zip(shapes, dists)) if it is not None]
            psi_d, pitch_cmd, rp = local.command(pos, t, cur, obstacles, dt)
        if k % st.record_every == 0:
            T[rec], P[rec], H[rec], D[rec] = t, pos, s.psi, s.delta
            V[rec] = math.hypot(vel[0], vel[1])
            E[rec], PR[rec], ALT[rec] = rp.cross, rp.progress, alt
            OBS[rec] = dists
            rec += 1
        # events
        hit = _contact_event(alt, dists, pos, t, world.moving, vp.speed)
        if hit is not None:
            status, what = hit
            kind = "unavoidable" if status is Status.UNAVOIDABLE else "collision"
            events.append((t, kind, f"hit {what} at t = {t:.1f} s, position {pos.round(2).tolist()}"))
            break
        if _arrived(rp.last, (s.x, s.y, s.z), goal, st.arrival_radius):
            events.append((t, "arrival", f"within {st.arrival_radius:g} m of the last waypoint"))
            status = Status.EXACT
            break
        if _progressed(rp.progress, best_progress):
            best_progress, best_time = rp.progress, t
        elif _deadlocked(t, best_time, st.deadlock_time,
                         None if local is None else partial(local.stalled, pos, t, best_time)):
            tried = f" ({local.escapes} escapes tried)" if local is not None else ""
            events.append((t, "deadlock", f"no progress along the route for {t - best_time:.0f} s{tried}"))
            status = Status.DEADLOCK
            break
        if pitch_cmd is None:
            theta_c = rp.gamma + math.atan(vp.depth_gain * (rp.z_ref - s.z))
        else:
            theta_c = pitch_cmd
        vel = vehicle.step(s, psi_d, theta_c, vp.speed if local is None else local.speed_command, cur, noise[k])
    else:
        events.append((n_steps * dt, "timeout", f"not arrived after {max_time:.0f} s"))
    if k % st.record_every != 0 or rec == 0:  # always keep the final state
        T[rec], P[rec], H[rec], D[rec] = k * dt, (s.x, s.y, s.z), s.psi, s.delta
        V[rec] = math.hypot(vel[0], vel[1])
        E[rec], PR[rec] = rp.cross, rp.progress
        ALT[rec] = float(terrain.altitude(P[rec])) if terrain is not None else math.inf
        OBS[rec] = [_distance(sh, P[rec]) for sh in _obstacle_shapes(world, k * dt)]
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
        escapes=local.escapes if local is not None else 0,
        avoidance=av_name,
        decision_steps=local.decisions if local is not None else 0,
        decision_time_s=local.decision_time if local is not None else 0.0,
    )


@dataclass(frozen=True, eq=False)
class RunRecord:
    """Everything one mission produced: the plan, the route flown, its key waypoints, the run.

    ``seed`` is the integer seed the run used (the mission's unless another was given; -1 when a
    ``numpy.random.Generator`` was passed instead of a seed).

    Attributes
    ----------
    scenario : str
        Scenario name.
    seed : int
        Seed of the run (-1 for a generator).
    plan : PlanResult or None
        The global plan (None for a mission with a fixed route).
    route, keys : ndarray, shape (N, 3) and (K, 3)
        Waypoints flown and their key waypoints (document 004).
    sim : SimResult or None
        The closed-loop run (None when the plan failed).
    """

    scenario: str
    seed: int
    plan: PlanResult | None
    route: NDArray[np.float64]
    keys: NDArray[np.float64]
    sim: SimResult | None

    @property
    def status(self) -> Status:
        """The mission's outcome: the plan's failure if it failed, else the simulation's."""
        if self.plan is not None and not self.plan.status.ok:
            return self.plan.status
        return self.sim.status if self.sim is not None else Status.INFEASIBLE


def route_from_path(path: ArrayLike, spacing: float) -> NDArray[np.float64]:
    """Resample a dense planned path into waypoints every ``spacing`` metres.

    The ends are kept; the result is not checked: use :func:`mission_route` for the mission a
    vehicle flies.

    Parameters
    ----------
    path : array_like
        ``(M, 3)`` dense path (m).
    spacing : float
        Distance between waypoints along the path (m).

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m).
    """
    return resample_polyline(path, spacing)


def mission_route(world: World, mission: Mission, path: ArrayLike) -> NDArray[np.float64]:
    """Build the executable mission of a planned path: the waypoints the simulation flies and every export carries.

    :func:`auvplan.guidance.mission.build_waypoints`: floors under rising seabed, 3D
    Douglas–Peucker where the exact envelope test decides what may be dropped.

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    mission : Mission
        The mission (unused today; kept for mission-specific settings).
    path : array_like
        ``(M, 3)`` dense planned path (m).

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m), safe under held and ramped depth semantics.
    """
    return build_waypoints(path, world)


def decimate(result: SimResult, every_m: float = 20.0, every_s: float = 30.0) -> SimResult:
    """Thin a run's recorded samples for exports and reports.

    One sample every ``every_m`` metres or ``every_s`` seconds (whichever comes first), plus the
    first and last samples and those of least altitude and least obstacle distance (the
    full-resolution result stays in ``run.npz``).

    Parameters
    ----------
    result : SimResult
        The run.
    every_m : float, optional
        Distance between kept samples along the track (m).
    every_s : float, optional
        Time between kept samples (s).

    Returns
    -------
    SimResult
        The same run with fewer samples (``result`` itself when it has two or fewer).
    """
    n = result.t.size
    if n <= 2:
        return result
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(result.position, axis=0), axis=1))]
    keep = np.zeros(n, dtype=bool)
    keep[np.unique(np.searchsorted(s, np.arange(0.0, s[-1], every_m)))] = True
    keep[np.unique(np.searchsorted(result.t, np.arange(0.0, result.t[-1], every_s)))] = True
    keep[[0, n - 1, int(np.argmin(result.altitude))]] = True
    if result.obstacle_distance.size:
        keep[int(np.argmin(result.obstacle_distance.min(axis=1)))] = True
    arrays = ("t", "position", "heading", "speed", "rudder", "cross_track", "route_error", "progress", "altitude",
              "obstacle_distance")
    return replace(result, **{k: getattr(result, k)[keep] for k in arrays})


def planned_route(world: World, mission: Mission, seed: RngLike,
                  progress: Progress | None = None) -> tuple[PlanResult | None, NDArray[np.float64] | None]:
    """The route a mission flies: its fixed route, or the global plan's (:func:`mission_route`).

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        What to do.
    seed : Generator, int or None
        Seed of the planner.
    progress : callable, optional
        ``progress(iteration, best)`` of a swarm planner.

    Returns
    -------
    tuple
        The plan (None for a fixed route) and the route ``(N, 3)`` (m), None when the plan failed.
    """
    if mission.route:
        return None, np.asarray(mission.route, dtype=float)
    planned = global_plan(planning_problem(world, mission), mission.planner, seed, progress)
    if not planned.status.ok:
        return planned, None
    return planned, mission_route(world, mission, planned.path)


def run_mission(world: World, mission: Mission, rng: RngLike = None,
                progress: Progress | None = None, guidance: str | None = None,
                avoidance: str | None = None, flight: Callable[[float, float], object] | None = None) -> RunRecord:
    """Scenario pipeline: global plan → key waypoints → closed-loop simulation (DESIGN.md §1).

    A mission with a fixed route skips the planner.  A failed plan is returned with no
    simulation (its status says why).

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        What to do.
    rng : Generator, int or None
        Seed of the planner and of the simulation (the mission's seed by default).
    progress : callable, optional
        ``progress(iteration, best)`` of a swarm planner.
    flight : callable, optional
        The simulation's progress callback (see :func:`simulate`).
    guidance, avoidance : str, optional
        Override the mission's path follower and local avoidance.

    Returns
    -------
    RunRecord
        Plan, route, key waypoints and simulation.
    """
    seed = mission.seed if rng is None else rng
    recorded = int(seed) if isinstance(seed, int | np.integer) else -1
    planned, route = planned_route(world, mission, seed, progress)
    if route is None:
        return RunRecord(mission.name, recorded, planned, np.empty((0, 3)), np.empty((0, 3)), None)
    keys = key_waypoints(route, world, mission.avoidance.collision_check)
    result = simulate(world, mission, route=route, guidance=guidance, rng=seed, avoidance=avoidance, keys=keys,
                      progress=flight)
    return RunRecord(mission.name, recorded, planned, route, keys, result)
