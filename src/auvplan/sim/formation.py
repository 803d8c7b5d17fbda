"""Several vehicles in one closed loop: a formation along the route (``[[vehicles]]``, ``[formation]``).

:func:`run_formation` is the formation's pipeline: the global plan of the leader's route (or the
fixed survey line) → the executable mission (:func:`auvplan.sim.mission_route`) → every slot's
swept track checked against the seabed and reshaped to column where it fails
(:func:`auvplan.guidance.formation.plan.plan_formation`) → :func:`simulate_formation`.

:func:`simulate_formation` steps every vehicle together at ``dt``: each is the single-vehicle model
of :mod:`auvplan.vehicles` (under-actuated, one rudder, PD heading autopilot, Nomoto yaw, surge lag,
pitch-driven depth, drift in the current, wave disturbance), driven by its own formation guidance
(:func:`auvplan.guidance.formation.keeping.formation_command`); obstacle distances, collisions and the
moving obstacles' tracks are :mod:`auvplan.sim`'s own.  The run stops at the first contact (seabed,
obstacle, or two hulls closer than ``contact_m``); a vehicle's run ends when it reaches its final
slot (within the arrival radius, once the leader has arrived).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._types import ArrayLike, RngLike, Status, as_rng
from ..guidance.formation.error import error_figures
from ..guidance.formation.keeping import FormationParams
from ..guidance.formation.plan import FormationPlan, plan_formation
from ..guidance.formation.steer import FormationCommand, formation_command
from ..planners.core.base import PlanResult, Progress
from ..vehicles import Vehicle, VehicleState
from ..world import World
from .events import FAR, _deadlocked, _distance, _obstacle_shapes, _progressed
from .mission import Mission
from .pipeline import planned_route
from .result import SimResult

__all__ = ["FormationResult", "FormationRecord", "simulate_formation", "run_formation"]


@dataclass(frozen=True, eq=False)
class FormationResult:
    """The closed loop of a formation: one :class:`SimResult` per vehicle and the formation's figures.

    In each vehicle's SimResult ``cross_track`` is the signed cross error to the line through its
    slot along the slot's course (the error its route attraction nulls) and ``route_error`` its size.

    Attributes
    ----------
    status : Status
        ``EXACT`` when every vehicle reached its final slot, else the first failure.
    names : tuple of str
        Vehicle names, leader first.
    runs : tuple of SimResult
        Each vehicle's time series (its own length: a vehicle stops recording when it arrives).
    slots : tuple of ndarray (N_i, 3)
        Each vehicle's slot position at its recorded steps.
    error : tuple of ndarray (N_i,)
        Formation error: distance from the vehicle to its slot (m).
    t : ndarray (N,)
        Times of the fleet's recorded steps.
    vehicle_distance : ndarray (N,)
        Least centre distance between two running vehicles at each of them (inf with one left).
    shapes : tuple of str
        The shape being flown at each recorded step.
    events : tuple of (float, str, str)
        ``(time, kind, message)``: arrivals, collision, deadlock, timeout.
    wall_time_s : float
        Wall-clock time of the run.
    """

    status: Status
    names: tuple[str, ...]
    runs: tuple[SimResult, ...]
    slots: tuple[np.ndarray, ...]
    error: tuple[np.ndarray, ...]
    t: np.ndarray
    vehicle_distance: np.ndarray
    shapes: tuple[str, ...]
    events: tuple[tuple[float, str, str], ...]
    wall_time_s: float

    @property
    def metrics(self) -> dict[str, Any]:
        """Fleet figures and one entry per vehicle (formation error RMS/max, arrivals, clearances)."""
        per: dict[str, dict[str, Any]] = {}
        for name, run, err in zip(self.names, self.runs, self.error):
            m = run.metrics
            per[name] = {
                "status": m["status"], "arrived": m["arrived"], "duration_s": m["duration_s"],
                "distance_m": m["distance_m"],
                **error_figures(run.t[:err.size], err),
                "min_altitude_m": m["min_altitude_m"], "min_obstacle_distance_m": m["min_obstacle_distance_m"],
            }
        collisions = sum(1 for e in self.events if e[1] in ("collision", "unavoidable"))
        return {
            "status": self.status.value,
            "vehicles": len(self.names),
            "arrivals": sum(1 for v in per.values() if v["arrived"]),
            "collisions": collisions,
            "vehicle_contacts": sum(1 for e in self.events if e[1] == "collision" and "vehicle" in e[2]),
            "min_vehicle_distance_m": float(self.vehicle_distance.min()) if self.vehicle_distance.size else math.inf,
            "formation_error_rms_m": max(v["formation_error_rms_m"] for v in per.values()),
            "formation_error_max_m": max(v["formation_error_max_m"] for v in per.values()),
            # after the launch transient (NaN when a vehicle never came within the settling radius)
            "settled_error_max_m": float(np.max([v["settled_error_max_m"] for v in per.values()])),
            "min_altitude_m": min(v["min_altitude_m"] for v in per.values()),
            "min_obstacle_distance_m": min(v["min_obstacle_distance_m"] for v in per.values()),
            "duration_s": float(self.t[-1]) if self.t.size else 0.0,
            "wall_time_s": self.wall_time_s,
            "per_vehicle": per,
        }


@dataclass(frozen=True, eq=False)
class FormationRecord:
    """Everything a formation mission produced: the leader's plan, the checked formation plan and the run.

    Attributes
    ----------
    scenario : str
        Scenario name.
    seed : int
        Seed of the run (-1 for a generator).
    plan : PlanResult or None
        The global plan (None for a fixed route).
    formation : FormationPlan or None
        Shapes and checked slot tracks (None when the plan failed).
    result : FormationResult or None
        The closed loop (None when a plan failed).
    """

    scenario: str
    seed: int
    plan: PlanResult | None
    formation: FormationPlan | None
    result: FormationResult | None

    @property
    def status(self) -> Status:
        """The global plan's failure, the formation plan's, or the flight's outcome."""
        if self.plan is not None and not self.plan.status.ok:
            return self.plan.status
        if self.formation is None or not self.formation.status.ok:
            return Status.INFEASIBLE
        return self.result.status if self.result is not None else Status.INFEASIBLE


class _Recorder:
    """Preallocated time series of one vehicle."""

    def __init__(self, n: int, n_obs: int) -> None:
        self.k = 0
        self.t = np.empty(n)
        self.p = np.empty((n, 3))
        self.h, self.v, self.d, self.e, self.pr, self.alt, self.err = (np.empty(n) for _ in range(7))
        self.slot = np.empty((n, 3))
        self.obs = np.empty((n, n_obs))

    def add(self, t: float, s: VehicleState, speed: float, cross: float, progress: float, alt: float, err: float,
            slot: ArrayLike, dists: ArrayLike) -> None:
        k = self.k
        self.t[k], self.p[k], self.h[k], self.v[k], self.d[k] = t, (s.x, s.y, s.z), s.psi, speed, s.delta
        self.e[k], self.pr[k], self.alt[k], self.err[k], self.slot[k], self.obs[k] = \
            cross, progress, alt, err, slot, dists
        self.k += 1

    def result(self, status: Status, events: Sequence[tuple[float, str, str]], wall: float) -> SimResult:
        n = self.k
        p = self.p[:n].copy()
        return SimResult(status=status, arrived=status is Status.EXACT, t=self.t[:n].copy(), position=p,
                         heading=self.h[:n].copy(), speed=self.v[:n].copy(), rudder=self.d[:n].copy(),
                         cross_track=self.e[:n].copy(), route_error=np.abs(self.e[:n]),
                         progress=self.pr[:n].copy(), altitude=self.alt[:n].copy(),
                         obstacle_distance=self.obs[:n].copy(), events=tuple(events), guidance="formation",
                         wall_time_s=wall)


def _initial_states(mission: Mission, fplan: FormationPlan) -> list[VehicleState]:
    slots, courses = fplan.structure.slots(np.array(0.0))
    out = []
    for i, spec in enumerate(mission.formation.vehicles):  # type: ignore[union-attr]
        p = spec.start if spec.start else tuple(slots[i])
        out.append(VehicleState(float(p[0]), float(p[1]), float(p[2]), float(courses[i]) % (2 * math.pi),
                                mission.vehicle.speed))
    return out


def _scatter(states: Sequence[VehicleState], fp: FormationParams, rng: np.random.Generator) -> None:
    """Launch scatter (issue #36): each vehicle's initial horizontal position and heading off by
    N(0, ``start_sigma_m``²) per axis and N(0, ``start_heading_sigma_deg``²), drawn from ``rng``."""
    if fp.start_sigma_m <= 0.0 and fp.start_heading_sigma_deg <= 0.0:
        return
    draws = rng.standard_normal((len(states), 3))
    for s, (dx, dy, dpsi) in zip(states, draws):
        s.x += fp.start_sigma_m * float(dx)
        s.y += fp.start_sigma_m * float(dy)
        s.psi = (s.psi + math.radians(fp.start_heading_sigma_deg) * float(dpsi)) % (2 * math.pi)


def _contact(i: int, dists: Sequence[float], alt: float, vdist: dict[int, float], names: Sequence[str],
             fp: FormationParams) -> str:
    """What vehicle ``i`` touches ('' when nothing)."""
    if alt < 0.0:
        return "the seabed"
    if dists and min(dists) < 0.0:
        return f"obstacle {int(np.argmin(dists))}"
    for j, d in vdist.items():
        if d < fp.contact_m:
            return f"vehicle {names[j]} (centres {d:.2f} m apart)"
    return ""


class _Fleet:
    """The vehicles, their recorders and the shared run state of one formation flight."""

    def __init__(self, world: World, mission: Mission, fplan: FormationPlan, rng: RngLike) -> None:
        form = mission.formation
        if form is None:
            raise ValueError("the mission has no [formation]")
        self.world, self.fp, self.hp, self.vp, self.st = world, form.params, mission.hybrid, mission.vehicle, \
            mission.sim
        vp, st, dt = self.vp, self.st, self.st.dt
        rng = as_rng(mission.seed if rng is None else rng)
        self.n, self.fr, self.names = form.n, fplan.structure, form.names
        n = self.n
        self.states = _initial_states(mission, fplan)
        self.models = [Vehicle(vp, dt) for _ in range(n)]
        self.tail = (n - 1) * self.fp.spacing_m
        self.max_time = st.max_time or 3.0 * (self.fr.length + self.tail) / vp.speed + 120.0
        self.n_steps = int(math.ceil(self.max_time / dt))
        n_rec = self.n_steps // st.record_every + 2
        self.n_static = len(world.obstacles)
        self.rec = [_Recorder(n_rec, self.n_static + len(world.moving)) for _ in range(n)]
        self.fleet_t, self.fleet_d = np.empty(n_rec), np.empty(n_rec)
        self.fleet_shape: list[str] = []
        waves = vp.wave_sigma_r > 0 or vp.wave_sigma_v > 0
        shape = (self.n_steps + 1, n, 2)
        self.noise = rng.standard_normal(shape) if waves else np.zeros(shape)
        _scatter(self.states, self.fp, rng)  # after the wave draws: runs without scatter keep their noise
        steps_t = np.arange(self.n_steps + 1) * dt
        self.tracks = np.stack([np.asarray(o.motion.position(steps_t)) for o in world.moving], axis=1) \
            if world.moving else np.empty((self.n_steps + 1, 0, 3))
        self.far = max(FAR, self.hp.influence + 10.0)
        self.velocities = np.asarray(np.gradient(self.tracks, dt, axis=0)) if self.n_steps > 0 \
            else np.zeros_like(self.tracks)
        self.radii = [o.shape.bounding_radius for o in world.moving]
        self.final, _ = self.fr.slots_at(self.fr.length)
        self.active, self.arrived = [True] * n, [False] * n
        self.events: list[tuple[float, str, str]] = []
        self.ends: list[Status] = [Status.TIMEOUT] * n
        self.status = Status.TIMEOUT
        self.s_ref, self.best, self.best_t = 0.0, np.full(n, -np.inf), np.zeros(n)
        # a leader launched behind the route's start (the launch scatter) starts the slots abreast of it
        self.s_ref = self.fr.project(self.states[0].x, self.states[0].y, 0.0, behind=math.inf, ahead=0.0)
        self.u_lead = vp.speed
        self.vel = [(s.u * math.sin(s.psi), s.u * math.cos(s.psi), 0.0) for s in self.states]

    def guide(self, k: int, t: float, pos: np.ndarray, cur: np.ndarray) -> tuple[list[FormationCommand | None],
                                                                                  float, bool]:
        """Every running vehicle's command at step ``k``, and its events; the largest follower lag; stop?"""
        world, fr, n = self.world, self.fr, self.n
        alt = pos[:, 2] - world.terrain.elevation(pos[:, 0], pos[:, 1]) if world.terrain is not None \
            else np.full(n, np.inf)
        shapes = _obstacle_shapes(world, t, self.tracks[k].tolist())
        if self.active[0]:
            self.s_ref = fr.project(pos[0, 0], pos[0, 1], self.s_ref)
        sl, courses = fr.slots_at(self.s_ref)
        ahead_, _ = fr.slots_at(self.s_ref + 1.0)  # the slots' own motion per metre of reference progress
        stretch = [math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(sl, ahead_)]
        gamma = [math.atan2(b[2] - a[2], max(h, 1e-9)) for a, b, h in zip(sl, ahead_, stretch)]
        cmds: list[FormationCommand | None] = [None] * n
        lag, stop = 0.0, False
        for i in range(n):
            if not self.active[i]:
                continue
            c, stopped = self._vehicle(i, k, t, pos, cur, float(alt[i]), shapes, sl, courses[i], gamma[i], stretch[i])
            cmds[i] = c
            stop |= stopped
            if i:
                lag = max(lag, c.along)
        return cmds, lag, stop

    def _vehicle(self, i: int, k: int, t: float, pos: np.ndarray, cur: np.ndarray, alt: float,
                 shapes: Sequence[Any], sl: Sequence[Sequence[float]], course: float, gamma: float,
                 stretch: float) -> tuple[FormationCommand, bool]:
        """Vehicle ``i``'s command, record and events (contact, arrival, deadlock); True: stop the run."""
        fp, st, vp, n, n_static = self.fp, self.st, self.vp, self.n, self.n_static
        dists = [_distance(sh, pos[i], self.far) for sh in shapes]
        others = {j: math.dist(pos[i], pos[j]) for j in range(n) if j != i and self.active[j]}
        near = [(it[1][0], it[1][1], d) for it, d in zip(shapes[:n_static], dists) if it is not None]
        peers = [(pos[j, 0], pos[j, 1], self.vel[j][0], self.vel[j][1], fp.separation_m) for j in others]
        peers += [(it[1][0], it[1][1], v[0], v[1], r + 0.5 * fp.separation_m)
                  for it, d, v, r in zip(shapes[n_static:], dists[n_static:], self.velocities[k], self.radii)
                  if it is not None and d < self.far]
        u_ff = (self.u_lead if i else vp.speed) * stretch
        c = formation_command(sl[i], course, gamma, pos[i], self.vel[i], cur[i], self.states[i].u, self.hp, fp, near,
                              peers, math.dist(pos[i], self.final[i]), u_ff, vp.speed, vp.max_speed,
                              [(pos[j, 0], pos[j, 1]) for j in others if j < i])
        prog = self.s_ref - c.along
        if k % st.record_every == 0:
            self.rec[i].add(t, self.states[i], math.hypot(self.vel[i][0], self.vel[i][1]), c.cross, prog, alt,
                            c.error, sl[i], dists)
        name = self.names[i]
        what = _contact(i, dists, alt, others, self.names, fp)
        if what:
            self.events.append((t, "collision", f"{name} hit {what} at t = {t:.1f} s, "
                                                f"position {pos[i].round(2).tolist()}"))
            self.ends[i] = self.status = Status.COLLISION
            return c, True
        if (self.arrived[0] or i == 0) and self.s_ref >= self.fr.length - st.arrival_radius and \
                c.error <= st.arrival_radius and (i or math.dist(pos[0], self.fr.w[-1]) <= st.arrival_radius):
            self.events.append((t, "arrival", f"{name} within {st.arrival_radius:g} m of its final slot"))
            self.arrived[i], self.active[i], self.ends[i] = True, False, Status.EXACT
            return c, False
        if _progressed(prog, self.best[i]):
            self.best[i], self.best_t[i] = prog, t
        elif _deadlocked(t, self.best_t[i], st.deadlock_time, None):
            self.events.append((t, "deadlock", f"{name}: no progress for {t - self.best_t[i]:.0f} s"))
            self.ends[i] = self.status = Status.DEADLOCK
            return c, True
        return c, False

    def record(self, t: float, pos: np.ndarray) -> None:
        """The fleet's figures at a recorded step: least vehicle distance and the shape being flown."""
        rec = self.rec
        run = [i for i in range(self.n) if self.active[i] or self.arrived[i] and rec[i].t[rec[i].k - 1] == t]
        dmin = min((math.dist(pos[a], pos[b]) for a in run for b in run if a < b), default=math.inf)
        j = len(self.fleet_shape)
        self.fleet_t[j], self.fleet_d[j] = t, dmin
        self.fleet_shape.append(self.fr.schedule.shape_at(self.s_ref))

    def steer(self, k: int, cmds: Sequence[FormationCommand | None], lag: float, cur: np.ndarray) -> None:
        """Step every running vehicle's model one ``dt`` on its command (the leader waits for laggards)."""
        vp, fp = self.vp, self.fp
        self.u_lead = max(vp.speed - fp.k_wait * max(lag, 0.0), fp.min_speed_ratio * vp.speed)
        for i in range(self.n):
            c = cmds[i]
            if not self.active[i] or c is None:
                continue
            u_c = self.u_lead if i == 0 else c.speed
            theta_c = c.gamma + math.atan(vp.depth_gain * (c.z_ref - self.states[i].z))
            self.vel[i] = self.models[i].step(self.states[i], c.psi, theta_c, u_c, cur[i], self.noise[k, i])

    def result(self, wall: float) -> FormationResult:
        """The run as a :class:`FormationResult`."""
        runs = tuple(r.result(self.ends[i], [e for e in self.events if self.names[i] in e[2]], wall)
                     for i, r in enumerate(self.rec))
        m = len(self.fleet_shape)
        return FormationResult(self.status, self.names, runs, tuple(r.slot[:r.k].copy() for r in self.rec),
                               tuple(r.err[:r.k].copy() for r in self.rec), self.fleet_t[:m].copy(),
                               self.fleet_d[:m].copy(), tuple(self.fleet_shape), tuple(self.events), wall)


def simulate_formation(world: World, mission: Mission, fplan: FormationPlan, rng: RngLike = None,
                       progress: Callable[[float, float], object] | None = None) -> FormationResult:
    """Fly every vehicle of ``mission.formation`` along the formation plan ``fplan`` in ``world``.

    Parameters
    ----------
    world : World
        Seabed, currents, static and moving obstacles.
    mission : Mission
        Vehicle class, hybrid-field gains, simulation settings and the formation.
    fplan : FormationPlan
        The shapes along the route and the slot tracks (:func:`plan_formation`).
    rng : Generator, int or None
        Seed of the wave disturbances (the mission's seed by default).
    progress : callable, optional
        ``progress(t, expected)`` every simulated minute.

    Returns
    -------
    FormationResult
        Every vehicle's time series, the formation errors and the events.
    """
    t_wall = time.perf_counter()
    fleet = _Fleet(world, mission, fplan, rng)
    dt = fleet.st.dt
    every, expected = max(1, int(round(60.0 / dt))), (fleet.fr.length + fleet.tail) / fleet.vp.speed
    for k in range(fleet.n_steps + 1):
        t = k * dt
        if progress is not None and k % every == 0:
            progress(t, expected)
        pos = np.array([[s.x, s.y, s.z] for s in fleet.states])
        cur = world.currents.velocity(pos, t)
        cmds, lag, stop = fleet.guide(k, t, pos, cur)
        if k % fleet.st.record_every == 0:
            fleet.record(t, pos)
        if stop:
            break
        if all(fleet.arrived):
            fleet.status = Status.EXACT
            break
        fleet.steer(k, cmds, lag, cur)
    else:
        fleet.events.append((fleet.n_steps * dt, "timeout",
                             f"not every vehicle arrived after {fleet.max_time:.0f} s"))
    return fleet.result(time.perf_counter() - t_wall)


def run_formation(world: World, mission: Mission, rng: RngLike = None, progress: Progress | None = None,
                  flight: Callable[[float, float], object] | None = None) -> FormationRecord:
    """A formation mission end to end: leader's plan → mission → formation plan → closed loop.

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        A mission with a ``formation``.
    rng : Generator, int or None
        Seed of the planner and of the flight (the mission's seed by default).
    progress, flight : callable, optional
        The planner's and the flight's progress callbacks.

    Returns
    -------
    FormationRecord
        The plans and the run; a failed plan has no run (its status says why).
    """
    if mission.formation is None:
        raise ValueError("the mission has no [formation]")
    seed = mission.seed if rng is None else rng
    recorded = int(seed) if isinstance(seed, int | np.integer) else -1
    planned, route = planned_route(world, mission, seed, progress)
    if route is None:
        return FormationRecord(mission.name, recorded, planned, None, None)
    fplan = plan_formation(world, route, mission.formation)
    if not fplan.status.ok:
        return FormationRecord(mission.name, recorded, planned, fplan, None)
    result = simulate_formation(world, mission, fplan, seed, flight)
    return FormationRecord(mission.name, recorded, planned, fplan, result)
