"""The closed-loop simulator of one vehicle.

:func:`simulate` runs a fixed-step loop (``dt``) of guidance → autopilot → vehicle → world,
with preallocated arrays and events: arrival (within ``arrival_radius`` of the last waypoint),
collision (seabed or an obstacle surface), deadlock (no progress along the route for
``deadlock_time``), timeout.  The loop is scalar Python on purpose (one vehicle, thousands of
small steps); the world is queried through its vectorised kernels once per step.  Its phases:
:func:`_setup` (the run's fixed inputs and state, :class:`_Run`), per step :func:`_sense` (what the
vehicle is near), :func:`_command` (guidance or local avoidance), :meth:`_Recorder.add`,
:func:`_step_events` (the rules of :mod:`auvplan.sim.events`) and :func:`_steer` (autopilot and
vehicle), then :func:`_result`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._types import RngLike, Status, as_rng
from ..errors import AuvplanError
from ..guidance.avoidance.local import LocalAvoidance, key_waypoints
from ..guidance.avoidance.predictive import PredictiveAvoidance
from ..guidance.following.hybrid import HybridGuidance
from ..guidance.following.los import LosGuidance
from ..guidance.following.route import PathFollower, RoutePoint, RouteTracker
from ..nav.budget import LAUNCH_DIVE_MPS
from ..vehicles import Vehicle, VehicleState
from ..world import World
from ..world.obstacles import Shape
from .drift import NavDrift
from .events import (
    FAR,
    _arrived,
    _contact_event,
    _deadlocked,
    _distance,
    _dive_step,
    _launch_depth,
    _obstacle_shapes,
    _progressed,
)
from .mission import Mission
from .result import SimResult, _Recorder

__all__ = ["make_guidance", "simulate"]

_Placed = tuple[Any, tuple[float, ...]] | None
"""An obstacle's (shape, centre) at one step, None when inactive (:func:`~auvplan.sim.events._obstacle_shapes`)."""


def make_guidance(name: str, route: ArrayLike, mission: Mission, tail: ArrayLike | None = None,
                  statics: Sequence[Any] = ()) -> PathFollower:
    """Make a path follower by name.

    Parameters
    ----------
    name : {'hybrid', 'los', 'ilos'}
        The path follower.
    route : array_like
        ``(N, 3)`` waypoints to follow (m).
    mission : Mission
        Its ``hybrid`` and ``los`` settings.
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first (:class:`~auvplan.guidance.following.route.RouteTracker`).
    statics : sequence of shapes, optional
        The world's static obstacles: the hybrid field repels from one only inside the route's own
        clearance from it (:class:`~auvplan.guidance.following.hybrid.HybridGuidance`).

    Returns
    -------
    PathFollower
        :class:`~auvplan.guidance.following.hybrid.HybridGuidance` or
        :class:`~auvplan.guidance.following.los.LosGuidance`.
    """
    if name == "hybrid":
        return HybridGuidance(RouteTracker(route, mission.hybrid.switch_radius, tail), mission.hybrid, statics)
    if name in ("los", "ilos"):
        return LosGuidance(RouteTracker(route, mission.los.switch_radius, tail), mission.los, integral=name == "ilos")
    raise ValueError(f"unknown guidance {name!r}; choose hybrid, los or ilos")


def simulate(world: World, mission: Mission, route: ArrayLike | None = None, guidance: str | None = None,
             rng: RngLike = None, avoidance: str | None = None, keys: ArrayLike | None = None,
             progress: Callable[[float, float], object] | None = None, tail: ArrayLike | None = None,
             fix_kinds: Sequence[str] | None = None) -> SimResult:
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
    tail : array_like of bool, optional
        ``(N - 1,)`` legs of ``route`` flown tail-first (a time-optimal plan's, :func:`.pipeline.mission_route`).
    fix_kinds : sequence of str, optional
        ``(N,)`` the position fix at each waypoint (``""``, ``"gps"``, ``"usbl"``) when the mission flies
        with a drifting estimate (``mission.nav_drift``); by default its surface waypoints are GPS fixes.
        With drift the vehicle steers by its estimate, which a fix resets once the route's leg after
        the fix waypoint becomes active (:mod:`auvplan.sim.drift`).

    Returns
    -------
    SimResult
        Status, recorded time series and events of the run.
    """
    t_wall = time.perf_counter()
    run = _setup(world, mission, route, guidance, rng, avoidance, keys, tail, fix_kinds)
    st, dt, s = mission.sim, mission.sim.dt, run.state
    every = max(1, int(round(60.0 / dt)))
    expected = run.tracker.total_length / mission.vehicle.speed + sum(run.dwell) + run.dive_s
    k, last = 0, None
    for k in range(run.n_steps + 1):
        t = k * dt
        if progress is not None and k % every == 0:
            progress(t, _eta(t, expected, run.tracker.total_length, last))
        ended, rp = _step(run, k, t)
        last = rp
        if ended:
            break
    else:
        run.events.append((run.n_steps * dt, "timeout", f"not arrived after {run.max_time:.0f} s"))
    if k % st.record_every != 0:  # always keep the final state, sensed as every recorded one
        pos, _, dists, alt, _ = _sense(run, k, k * dt)
        run.rec.add(k * dt, pos, s, run.vel, rp, alt, dists, run.nav_error())
    return _result(run, time.perf_counter() - t_wall)


def _step(run: _Run, k: int, t: float) -> tuple[bool, RoutePoint]:
    """Step ``k`` of the flight (at ``t``): sense, command, record, the run's events (True: it ends here), then
    the step to the next (none after the last); the step's route point."""
    st, dt, s = run.mission.sim, run.mission.sim.dt, run.state
    pos, shapes, dists, alt, cur = _sense(run, k, t)
    psi_d, pitch_cmd, rp = _command(run, k, t, pos, shapes, dists, cur)
    if k % st.record_every == 0:
        run.rec.add(t, pos, s, run.vel, rp, alt, dists, run.nav_error())
    if _step_events(run, t, pos, alt, dists, rp):
        return True, rp
    if k < run.n_steps:  # the last step's state is the run's final state: no step beyond it
        if run.dive_to == run.dive_to:  # the launch's dive from the surface (sim.events), before the first leg
            _dive(run, t, alt, cur)
        elif t < run.hold_until:  # the dwell at a surface fix: drifting with the current, GPS holds the estimate
            _hold(run, cur)
        else:
            _steer(run, k, psi_d, pitch_cmd, rp, cur)
            if run.drift is not None:
                _drift(run.drift, s, pos, alt, cur, dt)
        if run.fixes:
            _fixes_passed(run, (k + 1) * dt, rp)
    return False, rp


@dataclass(eq=False)
class _Run:
    """One run's fixed inputs (world, mission, follower, avoidance, vehicle, the moving obstacles' tracks,
    the wave noise) and the state the loop carries (vehicle state and velocity, best progress, events)."""

    world: World
    mission: Mission
    guide: PathFollower
    local: LocalAvoidance | PredictiveAvoidance | None
    avoidance: str
    vehicle: Vehicle
    state: VehicleState
    max_time: float
    n_steps: int
    noise: NDArray[np.float64]  # (n_steps + 1, 2) standard normal draws of the wave disturbance
    tracks: NDArray[np.float64]  # (n_steps + 1, M, 3) the moving obstacles' centres at every step time
    velocities: NDArray[np.float64]  # (n_steps + 1, M, 3) their velocities
    radii: list[float]
    far: float
    rec: _Recorder
    goal: NDArray[np.float64]
    bands: list[tuple[float, float]]  # the static obstacles' depth bands (:func:`_depth_band`)
    vel: tuple[float, float, float] = (0.0, 0.0, 0.0)
    status: Status = Status.TIMEOUT
    best_progress: float = -1.0
    best_time: float = 0.0
    events: list[tuple[float, str, str]] = field(default_factory=list)
    drift: NavDrift | None = None  # the drifting estimate (mission.nav_drift), None: perfect navigation
    fixes: tuple[str, ...] = ()  # the fix at each waypoint
    fixed: int = 0  # fixes up to this waypoint index are taken
    dwell: tuple[float, ...] = ()  # the time held at each waypoint (surface_s at a surface fix; s)
    hold_until: float = -math.inf  # the dwell under way ends at this time (s)
    regain: bool = False  # back from a dwell's drift behind the active leg's start: the way back counts as progress
    dive_to: float = math.nan  # the launch's dive under way ends at this height (the first waypoint's; nan: none)
    dive_s: float = 0.0  # its duration in still water (s; the progress bar's)

    def nav_error(self) -> float:
        """The estimate's horizontal error now (m; 0 with perfect navigation)."""
        return 0.0 if self.drift is None else math.hypot(*self.drift.error)

    def estimate(self) -> tuple[float, float]:
        """The horizontal offset of the estimate from the true position (m)."""
        return (0.0, 0.0) if self.drift is None else (float(self.drift.error[0]), float(self.drift.error[1]))

    @property
    def tracker(self) -> RouteTracker:
        """The path follower's route tracker."""
        return self.guide.route


def _local_avoidance(world: World, mission: Mission, name: str, route: NDArray[np.float64], guide: PathFollower,
                     keys: ArrayLike | None, rng: np.random.Generator) -> LocalAvoidance | PredictiveAvoidance | None:
    """The local avoidance ``name`` wraps around ``guide`` (None for ``none``)."""
    if name not in ("apf", "predictive"):
        return None
    keys = key_waypoints(route, world, mission.avoidance.collision_check) if keys is None else keys
    av = replace(mission.avoidance, name=name)
    return LocalAvoidance(guide, keys, world, av, mission.vehicle.speed, rng) if name == "apf" \
        else PredictiveAvoidance(guide, keys, world, av, mission.vehicle, rng)


def _moving_tracks(world: World, n_steps: int, dt: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The moving obstacles' centres at every step time (one vectorised call per obstacle) and their
    velocities (what the scenario knows; predictive avoidance may estimate them instead)."""
    steps_t = np.arange(n_steps + 1) * dt
    tracks = np.stack([np.asarray(o.motion.position(steps_t)) for o in world.moving], axis=1) \
        if world.moving else np.empty((n_steps + 1, 0, 3))
    velocities = np.asarray(np.gradient(tracks, dt, axis=0)) if n_steps > 0 else np.zeros_like(tracks)
    return tracks, velocities


MAX_SIM_STEPS = 20_000_000
"""Most time steps one closed-loop flight may take (its noise, tracks and record are allocated for them; at
~0.1 ms a step, half an hour of work).  A survey's lines at ``[vehicle] speed = 1e-300`` asked numpy for
10³⁰⁶ steps ('Maximum allowed dimension exceeded', naming no key; hostile round 20): the load-time estimate
sees the straight line from start to goal, which a survey (start = goal) makes 0 m long."""


def _check_steps(max_time: float, dt: float, length_m: float, speed: float, given: bool) -> None:
    """Refuse a flight of more than :data:`MAX_SIM_STEPS` time steps, naming the keys that make it."""
    steps = max_time / dt
    if not steps <= MAX_SIM_STEPS:  # nan and inf too
        why = "[sim] max_time" if given else f"3 × the {length_m:.4g} m route at [vehicle] speed = {speed:g} m/s"
        raise AuvplanError(f"[sim] dt = {dt:g} s over a time limit of {max_time:.4g} s ({why}): {steps:.3g} time "
                           f"steps, over the {MAX_SIM_STEPS:,} a flight may take; raise the speed or dt, or set a "
                           "shorter [sim] max_time")


def _setup(world: World, mission: Mission, route: ArrayLike | None, guidance: str | None, rng: RngLike,
           avoidance: str | None, keys: ArrayLike | None, tail: ArrayLike | None = None,
           fix_kinds: Sequence[str] | None = None) -> _Run:
    """The run's inputs and initial state: on the first waypoint, heading along the first leg, at cruise speed (with
    ``[navigation]``, at the surface above it, its dive first: :mod:`auvplan.sim.events`)."""
    gen = as_rng(mission.seed if rng is None else rng)
    waypoints = np.asarray(mission.route if route is None else route, dtype=float).reshape(-1, 3)
    st, vp = mission.sim, mission.vehicle
    guide = make_guidance(guidance or mission.guidance, waypoints, mission, tail, world.obstacles)
    av_name = avoidance or mission.avoidance.name
    local = _local_avoidance(world, mission, av_name, waypoints, guide, keys, gen)  # before the noise: same draws
    first = waypoints[1] - waypoints[0]
    s = VehicleState(float(waypoints[0, 0]), float(waypoints[0, 1]), float(waypoints[0, 2]),
                     (math.atan2(first[0], first[1]) + (math.pi if guide.route.tail[0] else 0.0)) % (2 * math.pi),
                     vp.speed)  # (heading against a first leg flown tail-first)
    max_time = st.max_time or 3.0 * guide.route.total_length / vp.speed + 120.0
    waves = vp.wave_sigma_r > 0 or vp.wave_sigma_v > 0
    fixes, dwell = _fix_waypoints(mission, waypoints, fix_kinds)
    if fixes and not st.max_time:  # the dwells are flown time too
        max_time += sum(dwell)
    depth = _launch_depth(world, mission.navigation, waypoints)
    if depth > 0.0:  # launched at the surface above the first waypoint: the dive is flown time too
        s.z = 0.0
        max_time += 0.0 if st.max_time else 3.0 * depth / LAUNCH_DIVE_MPS
    _check_steps(max_time, st.dt, guide.route.total_length, vp.speed, bool(st.max_time))
    n_steps = int(math.ceil(max_time / st.dt))
    noise = gen.standard_normal((n_steps + 1, 2)) if waves else np.zeros((n_steps + 1, 2))
    tracks, velocities = _moving_tracks(world, n_steps, st.dt)
    drift: NavDrift | None = None
    if mission.nav_drift and mission.navigation is not None:  # its own stream, drawn last: nothing else changes
        drift = NavDrift(mission.navigation, np.random.default_rng(int(gen.integers(2**63))))
    return _Run(world, mission, guide, local, av_name, Vehicle(vp, st.dt), s, max_time, n_steps, noise, tracks,
                velocities, [o.shape.bounding_radius for o in world.moving],
                max(FAR, mission.avoidance.radius + 10.0, mission.hybrid.influence + 10.0),
                _Recorder(n_steps // st.record_every + 2, len(world.obstacles) + len(world.moving)), waypoints[-1],
                [_depth_band(o) for o in world.obstacles], drift=drift, fixes=fixes, dwell=dwell,
                dive_to=float(waypoints[0, 2]) if depth > 0.0 else math.nan, dive_s=depth / LAUNCH_DIVE_MPS)


def _fix_waypoints(mission: Mission, waypoints: NDArray[np.float64],
                   fix_kinds: Sequence[str] | None) -> tuple[tuple[str, ...], tuple[float, ...]]:
    """The fix at each waypoint the tracker keeps and the time held there (``surface_s`` at a GPS fix);
    empty without ``[navigation]``."""
    nav = mission.navigation
    if nav is None:
        return (), ()
    kinds = list(fix_kinds) if fix_kinds is not None else \
        ["gps" if i > 0 and z >= -0.5 else "" for i, z in enumerate(waypoints[:, 2])]
    kept = np.r_[True, np.linalg.norm(np.diff(waypoints, axis=0), axis=1) > 1e-9]  # as the tracker keeps them
    for i in np.flatnonzero(~kept)[::-1]:  # a dropped duplicate's fix goes to the waypoint it repeats
        kinds[i - 1] = kinds[i - 1] or kinds[i]
    fixes = tuple(k for k, m in zip(kinds, kept, strict=True) if m)
    return fixes, tuple(nav.surface_s if k == "gps" else 0.0 for k in fixes)


def _fixes_passed(run: _Run, t: float, rp: RoutePoint) -> None:
    """The fixes of the waypoints passed: taken once the leg after a fix waypoint is active (the estimate
    reset, and at a surface fix the dwell started at ``t``)."""
    s = run.state
    while run.fixed < min(rp.leg, len(run.fixes) - 1):
        run.fixed += 1
        kind = run.fixes[run.fixed]
        if kind and run.drift is not None:
            run.drift.fix(kind, (s.x, s.y, s.z))
        if run.dwell[run.fixed] > 0.0:
            run.hold_until = t + run.dwell[run.fixed]


def _dive(run: _Run, t: float, alt: float, cur: NDArray[np.float64]) -> None:
    """One ``dt`` of the launch's dive (:mod:`auvplan.sim.events`): held over the first waypoint, sinking at the
    ground speed straight down; the estimate drifts over the water distance as the budget's launch does; the
    deadlock watch waits (no progress along the route is made or expected)."""
    s, dt = run.state, run.mission.sim.dt
    z, water = _dive_step(s.z, run.dive_to, cur, dt)
    run.vel = (0.0, 0.0, (z - s.z) / dt)
    s.z = z
    if run.drift is not None:
        run.drift.advance(0.0, alt, water)
    run.best_time, run.best_progress = t, -math.inf
    if z <= run.dive_to:
        run.dive_to = math.nan


def _hold(run: _Run, cur: NDArray[np.float64]) -> None:
    """One ``dt`` of the dwell at a surface fix: propulsion off (the hotel load only), the vehicle drifts
    with the current; GPS holds its estimate; the deadlock watch restarts after it, from where the drift left the
    vehicle (a head current carries it back along the route: regaining that is progress, not a stall)."""
    s, dt = run.state, run.mission.sim.dt
    s.x += float(cur[0]) * dt
    s.y += float(cur[1]) * dt
    run.vel = (float(cur[0]), float(cur[1]), 0.0)
    run.best_time = run.hold_until
    run.best_progress, run.regain = -math.inf, True


def _depth_band(shape: Shape) -> tuple[float, float]:
    """The depths ``(z_low, z_high)`` (m, up positive) at which a static obstacle has a horizontal
    cross-section: the shape's exact vertical extent (``z_range``)."""
    return shape.z_range


def _sense(run: _Run, k: int, t: float) -> tuple[NDArray[np.float64], list[_Placed], list[float], float,
                                                    NDArray[np.float64]]:
    """What the vehicle is in at step ``k``: its position, the obstacles (placed) and their distances, its
    altitude above the seabed and the current."""
    s, world = run.state, run.world
    pos = np.array([s.x, s.y, s.z])
    shapes = _obstacle_shapes(world, t, run.tracks[k].tolist())
    dists = [_distance(sh, pos, run.far) for sh in shapes]
    alt = s.z - world.terrain.elevation_at(s.x, s.y) if world.terrain is not None else math.inf
    cur = world.currents.velocity(pos[None], t)[0]
    return pos, shapes, dists, alt, cur


def _eta(t: float, expected: float, total: float, rp: Any) -> float:
    """The flight's expected duration for the progress bar: the route's length at the vehicle's speed, then
    (past 2 % of the route) the time so far scaled by the route still to go (issue 56: a flight slowed by
    the current ran on for hours behind a bar stuck at 100 %)."""
    done = 0.0 if rp is None else float(rp.progress)
    if t <= 0.0 or done < 0.02 * total:
        return expected
    return max(t, t * total / done)


def _command(run: _Run, k: int, t: float, pos: NDArray[np.float64], shapes: Sequence[_Placed],
             dists: Sequence[float], cur: NDArray[np.float64]) -> tuple[float, float | None, RoutePoint]:
    """The commanded heading, pitch (None: the autopilot's depth law) and route point of step ``k``."""
    s, dt = run.state, run.mission.sim.dt
    n_static, bands = len(run.world.obstacles), run.bands
    # the follower's field acts in the horizontal plane: a static obstacle the vehicle passes above or
    # below (its depth outside the obstacle's band) is not steered round
    level = [i >= n_static or bands[i][0] <= s.z <= bands[i][1] for i in range(len(shapes))]
    ex, ey = (0.0, 0.0) if run.drift is None else run.estimate()  # it steers by where it believes it is
    if run.local is None:
        near = [(it[1][0], it[1][1], d) for it, d, lv in zip(shapes, dists, level) if it is not None and lv]
        psi_d, _, rp = run.guide.command(s.x + ex, s.y + ey, s.z, cur, s.u, near, dt)
        return psi_d, None, rp
    if run.drift is not None:
        pos = pos + np.array([ex, ey, 0.0])
    obstacles = [(it[1][0], it[1][1], d, False, it[1]) if i < n_static else
                 (it[1][0], it[1][1], d, True, it[1], i, run.velocities[k, i - n_static], run.radii[i - n_static])
                 for i, (it, d) in enumerate(zip(shapes, dists)) if it is not None and level[i]]
    return run.local.command(pos, t, cur, obstacles, dt)


def _step_events(run: _Run, t: float, pos: NDArray[np.float64], alt: float, dists: Sequence[float],
                 rp: RoutePoint) -> bool:
    """The events of one step (contact, arrival, deadlock) into ``run.events`` and ``run.status``;
    True when the run ends.  Progress along the route resets the deadlock watch."""
    st, s, local = run.mission.sim, run.state, run.local
    hit = _contact_event(alt, dists, pos, t, run.world.moving, run.mission.vehicle.speed)
    if hit is not None:
        run.status, what = hit
        kind = "unavoidable" if run.status is Status.UNAVOIDABLE else "collision"
        run.events.append((t, kind, f"hit {what} at t = {t:.1f} s, position {pos.round(2).tolist()}"))
        return True
    ex, ey = (0.0, 0.0) if run.drift is None else run.estimate()  # arrival as the vehicle believes it
    if _arrived(rp.last, (s.x + ex, s.y + ey, s.z), run.goal, st.arrival_radius):
        run.events.append((t, "arrival", f"within {st.arrival_radius:g} m of the last waypoint"))
        run.status = Status.EXACT
        return True
    regain = min(rp.along, 0.0) if run.regain else 0.0  # behind the leg's start after a dwell (m, ≤ 0)
    run.regain = run.regain and rp.along < 0.0
    if _progressed(rp.progress + regain, run.best_progress):
        run.best_progress, run.best_time = rp.progress + regain, t
    elif _deadlocked(t, run.best_time, st.deadlock_time,
                     None if local is None else partial(local.stalled, pos, t, run.best_time)):
        tried = f" ({local.escapes} escapes tried)" if local is not None else ""
        run.events.append((t, "deadlock", f"no progress along the route for {t - run.best_time:.0f} s{tried}"))
        run.status = Status.DEADLOCK
        return True
    return False


def _drift(drift: NavDrift, s: VehicleState, pos: NDArray[np.float64], alt: float, cur: NDArray[np.float64],
           dt: float) -> None:
    """The estimate's drift over one step from ``pos``: over the ground and through the water (the step's current,
    which the vehicle model adds over ``dt``, taken out)."""
    dx, dy = s.x - float(pos[0]), s.y - float(pos[1])
    drift.advance(math.hypot(dx, dy), alt, math.hypot(dx - float(cur[0]) * dt, dy - float(cur[1]) * dt))


def _steer(run: _Run, k: int, psi_d: float, pitch_cmd: float | None, rp: RoutePoint, cur: NDArray[np.float64]) -> None:
    """Autopilot and vehicle: one ``dt`` on the commanded heading and pitch (the depth law without a pitch)."""
    s, vp = run.state, run.mission.vehicle
    if pitch_cmd is None:
        theta_c = rp.gamma + math.atan(vp.depth_gain * (rp.z_ref - s.z))
    else:
        theta_c = pitch_cmd
    cruise = run.mission.leg_speeds[min(rp.leg, len(run.mission.leg_speeds) - 1)] if run.mission.leg_speeds \
        else vp.speed  # the leg's speed (issue 38); avoidance's command scales with it
    run.vel = run.vehicle.step(s, psi_d, theta_c, cruise if run.local is None else
                               run.local.speed_command * cruise / vp.speed, cur, run.noise[k])


def _result(run: _Run, wall_time: float) -> SimResult:
    """The run as a :class:`~auvplan.sim.result.SimResult`."""
    rec, n, local = run.rec, run.rec.n, run.local
    position = rec.p[:n].copy()
    return SimResult(
        status=run.status,
        arrived=run.status is Status.EXACT,
        t=rec.t[:n].copy(),
        position=position,
        heading=rec.h[:n].copy(),
        speed=rec.v[:n].copy(),
        rudder=rec.d[:n].copy(),
        cross_track=rec.e[:n].copy(),
        route_error=run.tracker.cross_track(position),
        progress=rec.pr[:n].copy(),
        altitude=rec.alt[:n].copy(),
        obstacle_distance=rec.obs[:n].copy(),
        events=tuple(run.events),
        guidance=run.guide.name,
        wall_time_s=wall_time,
        escapes=local.escapes if local is not None else 0,
        avoidance=run.avoidance,
        decision_steps=local.decisions if local is not None else 0,
        decision_time_s=local.decision_time if local is not None else 0.0,
        minimum_escapes=local.minimum_escapes if local is not None else 0,
        nav_error=rec.ne[:n].copy() if run.drift is not None else None,
    )
